//! The memory a render needs, estimated after loading (the film's resolution may come from
//! `--width`/`--height`) and checked against `--max-memory` before the BVH and film are
//! allocated.

use anyhow::Result;
use ggx_scene::{Limit, Limits, MemoryEstimate, Scene};

/// The estimate for `scene` as it will be rendered.
pub fn estimate(scene: &Scene) -> MemoryEstimate {
    ggx_scene::estimate_memory(scene)
}

/// Fails, naming the limit and its flag, when rendering `scene` needs more than
/// `limits.max_memory`.
pub fn check(scene: &Scene, limits: &Limits) -> Result<()> {
    let e = estimate(scene);
    let [w, h] = scene.camera.resolution;
    let what = format!("rendering {} at {w}x{h} ({e})", scene.source.display());
    limits.check(Limit::Memory, what, e.total())?;
    Ok(())
}
