//! ggx's equirect environment map as the image and transform Mitsuba's `envmap` needs to show
//! the same sky.
//!
//! The two conventions differ in three ways:
//!
//! * **Axes.** ggx: `u = atan2(d.z, d.x) / 2 pi` (column 0 at +x, u growing towards +z),
//!   `v = acos(d.y) / pi`, the map turned by `R_y(rotation)`. Mitsuba: `u = atan2(d.x, -d.z) /
//!   2 pi` (column 0 at -z, growing towards +x), `v = acos(d.y) / pi`, in the emitter's local
//!   frame. A ggx map direction `d` has Mitsuba local direction `R_y(90°) d = (d.z, d.y, -d.x)`,
//!   so `to_world = R_y(rotation) R_y(-90°) = R_y(rotation - 90°)` ([`to_world`]).
//! * **Rows.** ggx's texels are cells: row `r` covers `v` in `[r / H, (r + 1) / H]`. Mitsuba's
//!   are grid points: row `j` of an `H'`-row image sits at `v = j / (H' - 1)`, the first and last
//!   on the poles. Columns are cell centres in both.
//! * **Filtering.** ggx looks up the nearest texel; Mitsuba interpolates bilinearly.
//!
//! [`resample`] therefore writes Mitsuba's grid points as ggx's radiance there: `k` columns
//! per ggx column (`k W` cell centres) and `k H + 1` rows, a row on a boundary between two ggx
//! rows holding their average. Between grid points Mitsuba blends only the last `1 / k` of a
//! ggx texel into its neighbour, symmetrically about the boundary, so the radiance a region
//! receives stays ggx's to first order and the difference shrinks as `1 / k`.

use ggx_film::Vec3;
use ggx_scene::EnvMap;

/// The largest accepted upsampling factor.
pub const MAX_UPSAMPLE: u32 = 8;

/// Mitsuba's envmap image for `map` with `k` grid points per ggx texel (`k` clamped to
/// `1..=MAX_UPSAMPLE`): `(width, height, row-major RGB, top row first)` with
/// `width = k W`, `height = k H + 1`; texels unscaled (the scale goes into the XML).
pub fn resample(map: &EnvMap, k: u32) -> (u32, u32, Vec<Vec3>) {
    let k = k.clamp(1, MAX_UPSAMPLE);
    let (w, h) = (map.width, map.height);
    let (out_w, out_h) = (w * k, h * k + 1);
    let texel = |col: u32, row: u32| {
        let t = map.texels[(row * w + col) as usize];
        Vec3::new(t[0], t[1], t[2])
    };
    let mut pixels = Vec::with_capacity(out_w as usize * out_h as usize);
    for j in 0..out_h {
        for c in 0..out_w {
            // Cell centre (c + 0.5) / (k W) lies inside ggx column floor((c + 0.5) / k) = c / k.
            let col = c / k;
            let value = if j == 0 {
                texel(col, 0)
            } else if j == out_h - 1 {
                texel(col, h - 1)
            } else if j % k == 0 {
                // On the boundary v = r / H between rows r - 1 and r.
                let r = j / k;
                (texel(col, r - 1) + texel(col, r)) * 0.5
            } else {
                texel(col, j / k)
            };
            pixels.push(value);
        }
    }
    (out_w, out_h, pixels)
}

/// Mitsuba's `to_world` of the envmap as a row-major 4x4 matrix: `R_y(rotation - 90°)` with
/// `R_y(t) = [[cos t, 0, sin t], [0, 1, 0], [-sin t, 0, cos t]]` (`rotation` in radians, as
/// [`EnvMap::rotation`]), computed in `f64`; entries within 1e-15 of 0 or ±1 are snapped so
/// that the file reads cleanly.
pub fn to_world(rotation: f32) -> [[f64; 4]; 4] {
    let t = f64::from(rotation) - std::f64::consts::FRAC_PI_2;
    let snap = |x: f64| {
        if x.abs() < 1e-15 {
            0.0
        } else if (x.abs() - 1.0).abs() < 1e-15 {
            x.signum()
        } else {
            x
        }
    };
    let (s, c) = (snap(t.sin()), snap(t.cos()));
    [[c, 0.0, s, 0.0], [0.0, 1.0, 0.0, 0.0], [-s, 0.0, c, 0.0], [0.0, 0.0, 0.0, 1.0]]
}

/// Mitsuba's local direction -> `(u, v)` (`envmap.cpp`'s `direction_to_uv`), `u` wrapped to
/// `[0, 1)`: the reference the tests check [`to_world`] against.
#[cfg(test)]
fn mitsuba_uv(d: [f64; 3]) -> (f64, f64) {
    let u = d[0].atan2(-d[2]) / std::f64::consts::TAU;
    (u - u.floor(), d[1].clamp(-1.0, 1.0).acos() / std::f64::consts::PI)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn map(w: u32, h: u32, rotation: f32) -> EnvMap {
        let texels = (0..w * h).map(|i| [i as f32, 2.0 * i as f32, 1.0, 1.0]).collect();
        EnvMap::new(w, h, texels, 1.0, rotation).unwrap()
    }

    #[test]
    fn grid_points_hold_ggx_texels_and_row_boundaries_average() {
        let m = map(4, 3, 0.0);
        let (w, h, px) = resample(&m, 2);
        assert_eq!((w, h, px.len()), (8, 7, 56));
        // Row 0 (north pole) is ggx row 0; columns 0 and 1 both fall in ggx column 0.
        assert_eq!(px[0], Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(px[1], px[0]);
        assert_eq!(px[2], Vec3::new(1.0, 2.0, 1.0));
        // Row 1 lies inside ggx row 0, row 2 on the boundary of rows 0 and 1 (texels 0 and 4).
        assert_eq!(px[8], px[0]);
        assert_eq!(px[16], Vec3::new(2.0, 4.0, 1.0));
        // The last row (south pole) is ggx row 2.
        assert_eq!(px[6 * 8], Vec3::new(8.0, 16.0, 1.0));
        let (w1, h1, _) = resample(&m, 0);
        assert_eq!((w1, h1), (4, 4), "k is at least 1");
    }

    /// Mitsuba's local direction of `(u, v)` (`envmap.cpp`'s `uv_to_direction`).
    fn mitsuba_direction(u: f64, v: f64) -> [f64; 3] {
        let (st, ct) = (std::f64::consts::PI * v).sin_cos();
        let (sp, cp) = (std::f64::consts::TAU * u).sin_cos();
        [sp * st, ct, -cp * st]
    }

    /// Every Mitsuba grid point off a ggx row boundary, turned into the world by `to_world`,
    /// looks up (with ggx's own `EnvMap::radiance`) the texel the grid point holds.
    #[test]
    fn to_world_maps_grid_points_onto_their_ggx_texels() {
        for rotation_deg in [0.0f32, 30.0, -75.0, 180.0] {
            let m = map(16, 8, rotation_deg);
            let k = 3;
            let (mw, mh, px) = resample(&m, k);
            let t = to_world(m.rotation());
            for j in (1..mh - 1).filter(|j| j % k != 0) {
                for c in 0..mw {
                    let local =
                        mitsuba_direction((f64::from(c) + 0.5) / f64::from(mw), f64::from(j) / f64::from(mh - 1));
                    let world = [0, 1, 2].map(|r| (0..3).map(|i| t[r][i] * local[i]).sum::<f64>() as f32);
                    let ggx = m.radiance(Vec3::from(world));
                    assert_eq!(px[(j * mw + c) as usize], ggx, "rotation {rotation_deg}: grid point ({c}, {j})");
                }
            }
            // Round trip of the reference functions.
            let (u, v) = mitsuba_uv(mitsuba_direction(0.3, 0.6));
            assert!((u - 0.3).abs() < 1e-12 && (v - 0.6).abs() < 1e-12);
        }
    }

    #[test]
    fn to_world_at_zero_rotation() {
        let t = to_world(0.0);
        assert_eq!(t[0], [0.0, 0.0, -1.0, 0.0]);
        assert_eq!(t[2], [1.0, 0.0, 0.0, 0.0]);
    }
}
