//! The pass schedule, the stream seed and the time budget: the same on every backend, so the
//! backends trace the same samples in the same passes.

use std::time::Duration;

use ggx_scene::IntegratorSettings;

/// Largest number of samples per pixel in one pass.
pub const MAX_PASS_SPP: u32 = 16;

/// The end of the pass that holds sample `s`: passes end at samples 1, 2, 4, 8, 16 and then
/// every 16 (`MAX_PASS_SPP`), so the passes are 1, 1, 2, 4, 8, 16, 16, ... samples from 0 (early
/// passes give a quick first image and a rate estimate for the time budget). The boundaries
/// are absolute: a render of samples `[A, B)` stops at the same ones, so its passes are those
/// of a render from 0 (the GPU sums a pass in `f32`: same passes, same bits).
pub fn pass_end(s: u32) -> u32 {
    if s < MAX_PASS_SPP { (s + 1).next_power_of_two() } else { (s / MAX_PASS_SPP + 1).saturating_mul(MAX_PASS_SPP) }
}

/// The 32-bit seed of the sample streams: the scene's seed, which the scene loader and the
/// CLI keep in `[0, ggx_scene::MAX_SEED]` so that distinct seeds give distinct streams;
/// a larger value (from code that builds settings by hand) is folded, `seed ^ (seed >> 32)`.
pub fn stream_seed(seed: u64) -> u32 {
    (seed ^ (seed >> 32)) as u32
}

/// The render's time budget: `None` for none, for a non-positive or non-finite value, and
/// for one too long for a [`Duration`] (a budget of 1e38 s is no budget in effect).
pub fn time_budget(settings: &IntegratorSettings) -> Option<Duration> {
    settings.time_budget.filter(|t| *t > 0.0).and_then(|t| Duration::try_from_secs_f32(t).ok())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn passes_double_up_to_sixteen() {
        let mut ends = vec![0];
        while ends.len() < 9 {
            ends.push(pass_end(*ends.last().unwrap()));
        }
        assert_eq!(ends, [0, 1, 2, 4, 8, 16, 32, 48, 64]);
        assert_eq!((pass_end(3), pass_end(5), pass_end(17), pass_end(47)), (4, 8, 32, 48));
        assert_eq!(pass_end(u32::MAX - 3), u32::MAX);
    }

    #[test]
    fn seeds_up_to_u32_max_are_kept() {
        assert_eq!(stream_seed(0), 0);
        assert_eq!(stream_seed(7), 7);
        assert_eq!(stream_seed(u64::from(u32::MAX)), u32::MAX);
    }

    #[test]
    fn huge_and_odd_budgets_are_no_budget() {
        let with = |t: Option<f32>| time_budget(&IntegratorSettings { time_budget: t, ..Default::default() });
        assert_eq!(with(Some(1.5)), Some(Duration::from_millis(1500)));
        for none in [None, Some(0.0), Some(-1.0), Some(f32::NAN), Some(f32::INFINITY), Some(2e19), Some(1e38)] {
            assert_eq!(with(none), None, "{none:?}");
        }
    }
}
