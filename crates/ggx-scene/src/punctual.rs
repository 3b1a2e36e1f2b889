//! Punctual lights (`KHR_lights_punctual`): points, spots and directional lights, delta
//! lights that only next-event estimation reaches.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;

/// [`PunctualLight::kind`] of a point light.
pub const PUNCTUAL_POINT: u32 = 0;
/// [`PunctualLight::kind`] of a spot light.
pub const PUNCTUAL_SPOT: u32 = 1;
/// [`PunctualLight::kind`] of a directional light.
pub const PUNCTUAL_DIRECTIONAL: u32 = 2;

/// One punctual light in world space, 64 bytes (WGSL `PunctualLight`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct PunctualLight {
    /// Position (point, spot).
    pub position: [f32; 3],
    /// [`PUNCTUAL_POINT`], [`PUNCTUAL_SPOT`] or [`PUNCTUAL_DIRECTIONAL`].
    pub kind: u32,
    /// Unit direction the light shines along (spot, directional: the node's -Z).
    pub direction: [f32; 3],
    /// Range beyond which a point or spot light gives nothing; 0 for none.
    pub range: f32,
    /// `color * intensity`: radiant intensity (point, spot; glTF's candela taken as W/sr) or
    /// irradiance (directional; glTF's lux taken as W/m^2), linear RGB.
    pub intensity: [f32; 3],
    /// `1 / max(1e-3, cos(inner) - cos(outer))` (spot).
    pub spot_scale: f32,
    /// `-cos(outer) * spot_scale` (spot).
    pub spot_offset: f32,
    /// Padding.
    pub pad: [u32; 3],
}

impl PunctualLight {
    /// Radiance-weighted contribution at distance `d` toward direction `-w` (`w` from the
    /// shading point to the light, unit) for a point or spot light: `I window(d) spot(w) / d^2`
    /// with the glTF recommended window `clamp(1 - (d / range)^4, 0, 1)` and spot falloff
    /// `clamp(cos * scale + offset, 0, 1)^2` (`KHR_lights_punctual` README); a directional
    /// light's irradiance as is.
    #[inline]
    pub fn incident(&self, w: Vec3, d: f32) -> Vec3 {
        let intensity = Vec3::from(self.intensity);
        if self.kind == PUNCTUAL_DIRECTIONAL {
            return intensity;
        }
        let mut atten = 1.0 / (d * d);
        if self.range > 0.0 {
            let r = d / self.range;
            let r2 = r * r;
            atten *= (1.0 - r2 * r2).max(0.0).min(1.0);
        }
        if self.kind == PUNCTUAL_SPOT {
            let cd = Vec3::from(self.direction).dot(-w);
            let a = (cd * self.spot_scale + self.spot_offset).max(0.0).min(1.0);
            atten *= a * a;
        }
        let out = intensity * atten;
        if out.is_finite() { out } else { Vec3::ZERO }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn light(kind: u32) -> PunctualLight {
        let cos_inner = 0.9f32;
        let cos_outer = 0.8f32;
        let spot_scale = 1.0 / (cos_inner - cos_outer).max(1e-3);
        PunctualLight {
            position: [0.0; 3],
            kind,
            direction: [0.0, -1.0, 0.0],
            range: 0.0,
            intensity: [4.0, 2.0, 1.0],
            spot_scale,
            spot_offset: -cos_outer * spot_scale,
            pad: [0; 3],
        }
    }

    #[test]
    fn inverse_square_window_and_spot_cone() {
        assert_eq!(size_of::<PunctualLight>(), 64);
        let down = Vec3::Y; // toward a light above the point
        assert_eq!(light(PUNCTUAL_POINT).incident(down, 2.0), Vec3::new(1.0, 0.5, 0.25));
        let ranged = PunctualLight { range: 2.0, ..light(PUNCTUAL_POINT) };
        assert_eq!(ranged.incident(down, 2.0), Vec3::ZERO);
        assert!((ranged.incident(down, 1.0).x - 4.0 * (1.0 - 1.0 / 16.0)).abs() < 1e-6);
        // Spot: full inside the inner cone, nothing outside the outer one.
        assert_eq!(light(PUNCTUAL_SPOT).incident(down, 1.0), Vec3::new(4.0, 2.0, 1.0));
        let outside = Vec3::new(1.0, 1.0, 0.0).normalize();
        assert_eq!(light(PUNCTUAL_SPOT).incident(outside, 1.0), Vec3::ZERO);
        assert_eq!(light(PUNCTUAL_DIRECTIONAL).incident(down, 1e30), Vec3::new(4.0, 2.0, 1.0));
        assert_eq!(light(PUNCTUAL_POINT).incident(down, 0.0), Vec3::ZERO, "no inf at the light");
    }
}
