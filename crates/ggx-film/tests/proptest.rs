//! Property tests: display conversion and comparison accept any `f32`.

use ggx_film::{OutputOptions, ToneMap, Vec3, compare, tonemap_to_srgb8};
use proptest::prelude::*;

fn any_pixel() -> impl Strategy<Value = Vec3> {
    use proptest::num::f32::ANY;
    (ANY, ANY, ANY).prop_map(|(x, y, z)| Vec3::new(x, y, z))
}

fn any_tonemap() -> impl Strategy<Value = ToneMap> {
    prop_oneof![Just(ToneMap::Aces), Just(ToneMap::Reinhard), Just(ToneMap::Clamp)]
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 2000,
        rng_seed: proptest::test_runner::RngSeed::Fixed(0x6767_7866),
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn tonemap_to_srgb8_never_panics(
        pixels in proptest::collection::vec(any_pixel(), 0..32),
        exposure in proptest::num::f32::ANY,
        tonemap in any_tonemap(),
    ) {
        let bytes = tonemap_to_srgb8(&pixels, &OutputOptions { exposure, tonemap });
        prop_assert_eq!(bytes.len(), 3 * pixels.len());
        for (p, b) in pixels.iter().zip(bytes.chunks_exact(3)) {
            for (c, &byte) in p.to_array().into_iter().zip(b) {
                if !(c > 0.0) {
                    prop_assert_eq!(byte, 0, "channel {} of {}", c, p);
                }
                if c == f32::INFINITY {
                    prop_assert_eq!(byte, 255, "channel {} of {}", c, p);
                }
            }
        }
    }

    #[test]
    fn compare_is_never_nan(
        pairs in proptest::collection::vec((any_pixel(), any_pixel()), 1..16),
        tolerance in 0.0f64..10.0,
    ) {
        let (a, b): (Vec<Vec3>, Vec<Vec3>) = pairs.into_iter().unzip();
        let m = compare(&a, &b, tolerance).unwrap();
        for v in [m.rmse, m.rel_mse, m.max_rel, m.over_tolerance] {
            prop_assert!(v >= 0.0, "{:?}", m);
        }
        prop_assert!((0.0..=1.0).contains(&m.over_tolerance));
        let same = compare(&a, &a, tolerance).unwrap();
        prop_assert_eq!(same, ggx_film::ImageMetrics::default());
    }
}
