//! Roughness parameterisation and the alpha range the core works in.
//!
//! `alpha` is the GGX width parameter (the RMS slope scale). Artists usually edit a
//! perceptually linear *roughness*; we use the Burley 2012 (Disney) mapping
//! `alpha = roughness^2`, the one used by UE4, Filament, Blender and Bevy.
//!
//! Every constructor clamps alphas to `[ALPHA_MIN, ALPHA_MAX]`; a lobe whose larger alpha
//! is below [`DELTA_ALPHA`] is treated as a perfect mirror (a delta lobe): its `eval` and
//! `pdf` are zero and `sample` returns the mirror direction with `is_delta = true`.

/// Smallest alpha used in any formula. Below about 1.7e-4, `1 - alpha^2` rounds to 1 in
/// f32 and the anisotropic stretch loses all precision (Falcor's note); we keep a margin.
pub const ALPHA_MIN: f32 = 1e-4;
/// Largest alpha accepted (roughness 1).
pub const ALPHA_MAX: f32 = 1.0;
/// Lobes with `max(alpha_x, alpha_y) < DELTA_ALPHA` are rendered as a mirror (pbrt-v4 and
/// Bevy use the same 1e-3 threshold).
pub const DELTA_ALPHA: f32 = 1e-3;

/// Clamps an alpha into `[ALPHA_MIN, ALPHA_MAX]`; NaN becomes `ALPHA_MIN`.
#[inline]
pub fn clamp_alpha(alpha: f32) -> f32 {
    // f32::max/min ignore a NaN operand.
    alpha.max(ALPHA_MIN).min(ALPHA_MAX)
}

/// `alpha = roughness^2` (Burley 2012), roughness clamped to `[0, 1]` first (NaN -> 0).
#[inline]
pub fn roughness_to_alpha(roughness: f32) -> f32 {
    let r = roughness.max(0.0).min(1.0);
    r * r
}

/// Inverse of [`roughness_to_alpha`]: `roughness = sqrt(alpha)`.
#[inline]
pub fn alpha_to_roughness(alpha: f32) -> f32 {
    crate::math::safe_sqrt(alpha.max(0.0).min(1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mapping_round_trips_and_clamps() {
        for r in [0.0f32, 0.05, 0.3, 0.7, 1.0] {
            assert!((alpha_to_roughness(roughness_to_alpha(r)) - r).abs() < 1e-6);
        }
        assert_eq!(roughness_to_alpha(2.0), 1.0);
        assert_eq!(roughness_to_alpha(f32::NAN), 0.0);
        assert_eq!(clamp_alpha(f32::NAN), ALPHA_MIN);
        assert_eq!(clamp_alpha(1e-7), ALPHA_MIN);
        assert_eq!(clamp_alpha(f32::INFINITY), ALPHA_MAX);
        assert_eq!(clamp_alpha(0.3), 0.3);
    }
}
