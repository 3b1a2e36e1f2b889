//! [`ToneMap`]: the curves that compress linear radiance into the displayable `[0, 1]` range.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use crate::ParseToneMapError;

/// A tone-mapping operator. Every operator maps 0 to 0, returns values in `[0, 1]` and never
/// darkens a channel when the colour is scaled up (`Aces` and `Clamp` act on each channel
/// alone; `Reinhard` couples the channels through the luminance). Inputs are sanitised first: NaN and
/// negative values become 0, `+inf` becomes `f32::MAX` (so it maps to full intensity).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ToneMap {
    /// Narkowicz 2015 fit of the ACES filmic curve, per channel:
    /// `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`, clamped to `[0, 1]` (it reaches 1
    /// at `x ≈ 7.24`).
    #[default]
    Aces,
    /// Reinhard 2002 `L / (1 + L)` applied to the Rec. 709 luminance `L`, with every channel
    /// scaled by the same factor `1 / (1 + L)` so the hue and saturation are kept. Channels
    /// that end up above 1 (bright saturated colours) are clipped to 1.
    Reinhard,
    /// `min(x, 1)` per channel: no compression, highlights clip.
    Clamp,
}

impl ToneMap {
    /// Every operator, in the order of their names in [`ToneMap::name`].
    pub const ALL: [ToneMap; 3] = [ToneMap::Aces, ToneMap::Reinhard, ToneMap::Clamp];

    /// The lowercase name parsed by `from_str`: `"aces"`, `"reinhard"` or `"clamp"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Aces => "aces",
            Self::Reinhard => "reinhard",
            Self::Clamp => "clamp",
        }
    }

    /// Tone-maps one linear RGB colour into `[0, 1]^3` (any input, see the type's docs).
    pub fn apply(self, rgb: Vec3) -> Vec3 {
        let rgb = Vec3::new(sanitize(rgb.x), sanitize(rgb.y), sanitize(rgb.z));
        match self {
            Self::Aces => Vec3::new(aces(rgb.x), aces(rgb.y), aces(rgb.z)),
            Self::Reinhard => reinhard_luminance(rgb),
            Self::Clamp => rgb.min(Vec3::ONE),
        }
    }
}

impl fmt::Display for ToneMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for ToneMap {
    type Err = ParseToneMapError;

    /// Parses `"aces"`, `"reinhard"` or `"clamp"` (ASCII case-insensitive).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|t| t.name().eq_ignore_ascii_case(s))
            .ok_or_else(|| ParseToneMapError { input: s.to_owned() })
    }
}

/// NaN and negative values -> 0, `+inf` -> `f32::MAX`, everything else unchanged.
#[inline]
fn sanitize(x: f32) -> f32 {
    // f32::max/min ignore a NaN operand.
    x.max(0.0).min(f32::MAX)
}

/// Narkowicz 2015, "ACES Filmic Tone Mapping Curve": `x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)`,
/// clamped to `[0, 1]`; for `x >= 8` (past the crossing at 7.24) it returns 1 without
/// evaluating, so `x^2` cannot overflow.
#[inline]
fn aces(x: f32) -> f32 {
    if x >= 8.0 {
        return 1.0;
    }
    (x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14)).max(0.0).min(1.0)
}

/// Reinhard et al. 2002 eq. 3 on luminance: `rgb * (L / (1 + L)) / L = rgb / (1 + L)` with
/// `L = 0.2126 r + 0.7152 g + 0.0722 b` (Rec. 709), computed in f64 so no step overflows;
/// each channel clipped to 1.
#[inline]
fn reinhard_luminance(rgb: Vec3) -> Vec3 {
    let (r, g, b) = (f64::from(rgb.x), f64::from(rgb.y), f64::from(rgb.z));
    let scale = 1.0 / (1.0 + 0.2126 * r + 0.7152 * g + 0.0722 * b);
    let map = |c: f64| (c * scale).min(1.0) as f32;
    Vec3::new(map(r), map(g), map(b))
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPECIAL: [f32; 8] = [f32::NAN, -f32::NAN, f32::NEG_INFINITY, -1.0, -0.0, f32::MIN, f32::MIN_POSITIVE, 1e-45];

    #[test]
    fn zero_maps_to_zero_and_known_values() {
        for t in ToneMap::ALL {
            assert_eq!(t.apply(Vec3::ZERO), Vec3::ZERO, "{t}");
        }
        // x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14) at 1 and 0.5.
        assert!((ToneMap::Aces.apply(Vec3::ONE).x - 2.54 / 3.16).abs() < 1e-6);
        assert!((ToneMap::Aces.apply(Vec3::splat(0.5)).y - 0.616_306_96).abs() < 1e-6);
        // Grey: L = x, so x / (1 + x).
        assert!((ToneMap::Reinhard.apply(Vec3::ONE) - Vec3::splat(0.5)).abs().max_element() < 1e-6);
        assert_eq!(ToneMap::Clamp.apply(Vec3::new(0.25, 1.0, 7.0)), Vec3::new(0.25, 1.0, 1.0));
    }

    #[test]
    fn reinhard_keeps_hue() {
        let c = Vec3::new(0.4, 0.2, 0.1);
        let out = ToneMap::Reinhard.apply(c);
        let l = 0.2126 * 0.4 + 0.7152 * 0.2 + 0.0722 * 0.1;
        assert!((out - c / (1.0 + l)).abs().max_element() < 1e-6);
        assert!((out.x / out.y - 2.0).abs() < 1e-5 && (out.y / out.z - 2.0).abs() < 1e-5);
    }

    #[test]
    fn monotonic_and_in_unit_range() {
        for t in ToneMap::ALL {
            let mut prev = Vec3::ZERO;
            for i in 0..=20_000 {
                let x = (i as f32 * 1e-3).powi(3); // 0 .. 8000, dense near 0.
                let v = t.apply(Vec3::new(x, 0.5 * x, 2.0 * x));
                assert!(v.cmpge(prev).all(), "{t} not monotonic at {x}: {prev} -> {v}");
                assert!(v.cmpge(Vec3::ZERO).all() && v.cmple(Vec3::ONE).all(), "{t}({x}) = {v}");
                prev = v;
            }
            assert_eq!(t.apply(Vec3::splat(f32::MAX)), Vec3::ONE, "{t}");
        }
    }

    #[test]
    fn nan_inf_and_negative_inputs_are_safe() {
        for t in ToneMap::ALL {
            for s in SPECIAL {
                let v = t.apply(Vec3::new(s, s, s));
                assert!(v.cmpge(Vec3::ZERO).all() && v.cmple(Vec3::ONE).all(), "{t}({s}) = {v}");
                if !(s > 0.0) {
                    assert_eq!(v, Vec3::ZERO, "{t}({s})");
                }
            }
            assert_eq!(t.apply(Vec3::INFINITY), Vec3::ONE, "{t}");
            let red = t.apply(Vec3::new(f32::INFINITY, f32::NAN, -5.0));
            assert_eq!(red, Vec3::new(1.0, 0.0, 0.0), "{t}");
        }
    }

    #[test]
    fn names_parse_and_print() {
        for t in ToneMap::ALL {
            assert_eq!(t.to_string().parse::<ToneMap>(), Ok(t));
        }
        assert_eq!("ACES".parse::<ToneMap>(), Ok(ToneMap::Aces));
        assert_eq!(ToneMap::default(), ToneMap::Aces);
        let err = "filmic".parse::<ToneMap>().unwrap_err();
        assert_eq!(err.to_string(), "unknown tone map \"filmic\" (expected one of: aces, reinhard, clamp)");
    }
}
