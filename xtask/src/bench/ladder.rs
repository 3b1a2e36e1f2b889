//! The spp ladder of one scene and configuration: 1, 2, 4, ... spp, every rung an independent
//! render with the same fixed seed (so rung `2n` repeats rung `n`'s samples and adds as many),
//! timed by the renderer (`RenderResult::elapsed`: BVH build and pipeline compilation excluded)
//! and compared with the reference.

use super::configs::Config;
use super::robust;
use crate::render;
use ggx_film::Vec3;
use ggx_scene::Scene;
use ggx_wgpu::GpuContext;

/// Seed of every ladder render (references use [`super::reference::REFERENCE_SEED`]).
pub const LADDER_SEED: u64 = 1;

/// One render of the ladder.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rung {
    /// Samples per pixel.
    pub spp: u32,
    /// Render time in seconds.
    pub seconds: f64,
    /// RMSE against the reference.
    pub rmse: f64,
    /// Relative MSE against the reference (`ggx_film::compare`'s convention).
    pub rel_mse: f64,
    /// Relative MSE without the [`robust::TRIM`] share of pixels with the largest errors
    /// ([`robust::trimmed_rel_mse`]): what the convergence check judges.
    pub rel_mse_trimmed: f64,
    /// Camera samples traced.
    pub camera_samples: u64,
    /// Rays traced.
    pub rays: u64,
}

impl Rung {
    /// Camera samples per second (0 when the time is not positive).
    pub fn samples_per_second(&self) -> f64 {
        if self.seconds > 0.0 { self.camera_samples as f64 / self.seconds } else { 0.0 }
    }
}

/// Every rung of one configuration on one scene, in spp order.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// The configuration.
    pub config: Config,
    /// The rungs, spp increasing.
    pub rungs: Vec<Rung>,
}

/// Powers of two from 1 up to `max` (at least `[1]`).
pub fn spp_ladder(max: u32) -> Vec<u32> {
    std::iter::successors(Some(1u32), |&s| s.checked_mul(2)).take_while(|&s| s <= max.max(1)).collect()
}

/// Renders `config`'s ladder up to `max_spp` on `base` (the scene at the bench resolution) and
/// measures each rung against `reference`. `gpu` is needed for the wgpu backend.
pub fn run(
    base: &Scene,
    config: Config,
    max_spp: u32,
    reference: &[Vec3],
    gpu: Option<&GpuContext>,
) -> Result<Series, String> {
    let name = config.name();
    let mut rungs = Vec::new();
    for spp in spp_ladder(max_spp) {
        let mut scene = base.clone();
        config.apply(&mut scene);
        scene.integrator.seed = LADDER_SEED;
        scene.integrator.spp = spp;
        let result =
            render::render(&scene, config.backend, config.specialize, gpu).map_err(|e| format!("{name}: {e}"))?;
        if result.spp != spp {
            return Err(format!("{name}: rendered {} of {spp} spp", result.spp));
        }
        let image = result.film.mean();
        let metrics = ggx_film::compare(&image, reference, 1.0).map_err(|e| format!("{name} at {spp} spp: {e}"))?;
        let rung = Rung {
            spp,
            seconds: result.elapsed.as_secs_f64(),
            rmse: metrics.rmse,
            rel_mse: metrics.rel_mse,
            rel_mse_trimmed: robust::trimmed_rel_mse(&image, reference, robust::TRIM),
            camera_samples: result.camera_samples,
            rays: result.rays,
        };
        eprintln!(
            "    {name:<28} {spp:>5} spp {:>9.4} s  relMSE {:.3e} (trimmed {:.3e})  {:.2} M samples/s",
            rung.seconds,
            rung.rel_mse,
            rung.rel_mse_trimmed,
            rung.samples_per_second() * 1e-6
        );
        rungs.push(rung);
    }
    Ok(Series { config, rungs })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ladder_is_powers_of_two() {
        assert_eq!(spp_ladder(16), [1, 2, 4, 8, 16]);
        assert_eq!(spp_ladder(20), [1, 2, 4, 8, 16]);
        assert_eq!(spp_ladder(1), [1]);
        assert_eq!(spp_ladder(0), [1]);
        assert_eq!(spp_ladder(u32::MAX).len(), 32);
    }
}
