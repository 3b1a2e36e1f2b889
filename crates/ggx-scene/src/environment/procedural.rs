//! Procedural equirectangular environments generated at load time, so that scenes need no
//! downloaded assets: a sun and sky, and a photo studio with soft boxes.

use glam::{Vec2, Vec3};

use super::uv_to_direction;

/// Evaluates `radiance` at every texel centre of a `width x height` equirect map.
fn generate(width: u32, height: u32, radiance: impl Fn(Vec3) -> Vec3) -> Vec<[f32; 4]> {
    (0..height)
        .flat_map(|row| (0..width).map(move |col| (col, row)))
        .map(|(col, row)| {
            let uv = Vec2::new((col as f32 + 0.5) / width as f32, (row as f32 + 0.5) / height as f32);
            radiance(uv_to_direction(uv)).extend(1.0).to_array()
        })
        .collect()
}

/// Hermite smoothstep from 0 at `e0` to 1 at `e1`: `3t^2 - 2t^3`.
fn smoothstep(e0: f32, e1: f32, x: f32) -> f32 {
    let t = ((x - e0) / (e1 - e0)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Direction with `elevation` above the horizon and azimuth `azimuth` (degrees, from +x
/// towards +z).
fn direction(elevation: f32, azimuth: f32) -> Vec3 {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    Vec3::new(e.cos() * a.cos(), e.sin(), e.cos() * a.sin())
}

/// A clear sky: a blue gradient from a bright horizon (`mix` by `sqrt(elevation)`), a sun of
/// 2 degrees angular radius at 35 degrees elevation (azimuth 60 degrees) with a soft glow, and
/// a dim brown ground below the horizon.
pub fn sky(width: u32, height: u32) -> Vec<[f32; 4]> {
    let sun = direction(35.0, 60.0);
    let (horizon, zenith) = (Vec3::new(1.0, 1.0, 1.05), Vec3::new(0.25, 0.45, 1.0));
    let ground = Vec3::new(0.25, 0.21, 0.17) * 0.4;
    let cos_sun_radius = 2f32.to_radians().cos();
    generate(width, height, |d| {
        if d.y < 0.0 {
            return ground * (1.0 + d.y * 0.5);
        }
        let sky = horizon.lerp(zenith, d.y.sqrt()) * 0.8;
        let cos = d.dot(sun);
        let angle = cos.clamp(-1.0, 1.0).acos();
        let glow = Vec3::new(1.0, 0.85, 0.6) * 2.0 * (-angle / 0.12).exp();
        let disk = Vec3::new(1.0, 0.92, 0.8) * 800.0 * smoothstep(cos_sun_radius - 1e-4, cos_sun_radius + 1e-4, cos);
        sky + glow + disk
    })
}

/// A soft box: centre direction, half extents (tangent of the angular half-size) and
/// radiance.
struct SoftBox {
    center: Vec3,
    half: Vec2,
    radiance: Vec3,
}

impl SoftBox {
    /// Radiance along `d`: the gnomonic projection of `d` onto the box's plane,
    /// `(d.t, d.b) / d.c`, tested against the half extents with 10% smooth edges.
    fn eval(&self, d: Vec3) -> Vec3 {
        let cos = d.dot(self.center);
        if cos <= 0.0 {
            return Vec3::ZERO;
        }
        let t = Vec3::Y.cross(self.center).normalize();
        let b = self.center.cross(t);
        let p = Vec2::new(d.dot(t), d.dot(b)) / cos;
        let edge = |x: f32, h: f32| smoothstep(h, 0.9 * h, x.abs());
        self.radiance * edge(p.x, self.half.x) * edge(p.y, self.half.y)
    }
}

/// A photo studio: a dark grey room (brighter towards the top) with a warm key soft box
/// front-right, a cool fill front-left, a tall rim strip behind and a square top light.
pub fn studio(width: u32, height: u32) -> Vec<[f32; 4]> {
    let boxes = [
        SoftBox { center: direction(35.0, 60.0), half: Vec2::new(0.45, 0.3), radiance: Vec3::new(8.0, 7.6, 7.0) },
        SoftBox { center: direction(20.0, 150.0), half: Vec2::new(0.55, 0.35), radiance: Vec3::new(2.0, 2.2, 2.5) },
        SoftBox { center: direction(30.0, -90.0), half: Vec2::new(0.15, 0.7), radiance: Vec3::splat(6.0) },
        SoftBox { center: direction(85.0, 0.0), half: Vec2::new(0.35, 0.35), radiance: Vec3::splat(3.0) },
    ];
    generate(width, height, |d| {
        let room = Vec3::splat(0.03 + 0.05 * (0.5 + 0.5 * d.y));
        boxes.iter().map(|b| b.eval(d)).sum::<Vec3>() + room
    })
}
