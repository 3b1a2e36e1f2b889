//! [`MAX_RADIANCE`]: the largest radiance a scene may emit, so that path weights stay finite.

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
