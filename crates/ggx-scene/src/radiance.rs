//! [`MAX_RADIANCE`]: the largest radiance a scene may emit, so that path weights stay finite,
//! and the check that emitters and environments share.

/// Largest radiance, per RGB channel, that an emitter or environment may have after every
/// multiplier (an environment map's `scale`) is applied.
///
/// A path tracer's estimate is `radiance * throughput / pdf` in `f32`. Throughputs are at
/// most a few units and pdfs rarely fall below about `1e-10` before a sample is discarded,
/// so bounding radiance by `1e20` keeps every such product below `1e30`, well inside
/// `f32::MAX` (about `3.4e38`), with room for sums over many samples in the film. Larger
/// values overflow to infinity and then to NaN (`inf * 0`), which renders black or poisons
/// whole pixels; no physical scene needs them (the sun's radiance is about `2e7` W/(sr m²)).
pub const MAX_RADIANCE: f32 = 1e20;

/// Why radiance over [`MAX_RADIANCE`] is refused, for every message that refuses it.
pub(crate) const OVER_MAX_RADIANCE: &str = "radiance * throughput / pdf must stay finite in f32";

/// `Ok` when every channel of `radiance` is at most [`MAX_RADIANCE`], else the message for the
/// first channel over it: `radiance 2e20 is over the largest radiance 1e20 (…)`.
pub(crate) fn check_radiance(radiance: [f32; 3]) -> Result<(), String> {
    match radiance.iter().find(|&&c| c > MAX_RADIANCE) {
        None => Ok(()),
        Some(c) => Err(format!("radiance {c:e} is over the largest radiance {MAX_RADIANCE:e} ({OVER_MAX_RADIANCE})")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radiance_over_the_bound_is_refused() {
        assert!(check_radiance([MAX_RADIANCE, 0.0, 1.0]).is_ok());
        let msg = check_radiance([1.0, 2e20, f32::INFINITY]).unwrap_err();
        assert_eq!(msg, format!("radiance 2e20 is over the largest radiance 1e20 ({OVER_MAX_RADIANCE})"));
    }
}
