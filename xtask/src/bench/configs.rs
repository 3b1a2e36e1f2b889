//! The configurations of the study: the baseline (VNDF, MIS, sobol, cpu, specialized kernel)
//! and one axis changed at a time, since the full cross product (5 x 3 x 2 x 2 x 2 = 120 per
//! scene) would not fit a benchmark run: 5 BSDF samplers (the baseline's VNDF among them),
//! 2 other light strategies, 1 other sampler, 1 other backend and 1 other kernel, 10 in all.

use crate::render::Backend;
use ggx_scene::{BsdfStrategy, LightStrategy, SamplerKind, Scene};

/// Which setting a configuration changes from the baseline.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Axis {
    /// The baseline itself.
    Baseline,
    /// BSDF importance sampling.
    Bsdf,
    /// Light strategy.
    Light,
    /// Sample sequence.
    Sampler,
    /// Renderer backend.
    Backend,
    /// Specialized or generic kernel.
    Kernel,
}

impl Axis {
    /// Short name for the CSV (`baseline`, `bsdf`, `light`, `sampler`, `backend`, `kernel`).
    pub fn name(self) -> &'static str {
        match self {
            Axis::Baseline => "baseline",
            Axis::Bsdf => "bsdf",
            Axis::Light => "light",
            Axis::Sampler => "sampler",
            Axis::Backend => "backend",
            Axis::Kernel => "kernel",
        }
    }
}

/// One way of rendering a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Config {
    /// BSDF importance sampling.
    pub bsdf: BsdfStrategy,
    /// How lights are sampled.
    pub light: LightStrategy,
    /// The sample sequence.
    pub sampler: SamplerKind,
    /// The renderer.
    pub backend: Backend,
    /// Scene-specialized (true) or generic kernel.
    pub specialize: bool,
}

/// The best configuration: VNDF, MIS, sobol, cpu, specialized. References use it too.
pub const BASELINE: Config = Config {
    bsdf: BsdfStrategy::Vndf,
    light: LightStrategy::Mis,
    sampler: SamplerKind::Sobol,
    backend: Backend::Cpu,
    specialize: true,
};

/// The study's configurations in a fixed order: the baseline, then the BSDF, light, sampler,
/// backend (only with `wgpu`) and kernel axes.
pub fn all(wgpu: bool) -> Vec<Config> {
    let mut configs = vec![BASELINE];
    for bsdf in [BsdfStrategy::Cosine, BsdfStrategy::Ndf, BsdfStrategy::SphericalCaps, BsdfStrategy::Bounded] {
        configs.push(Config { bsdf, ..BASELINE });
    }
    for light in [LightStrategy::Bsdf, LightStrategy::Nee] {
        configs.push(Config { light, ..BASELINE });
    }
    configs.push(Config { sampler: SamplerKind::Independent, ..BASELINE });
    if wgpu {
        configs.push(Config { backend: Backend::Wgpu, ..BASELINE });
    }
    configs.push(Config { specialize: false, ..BASELINE });
    configs
}

/// Short name of a BSDF strategy.
pub fn bsdf_name(b: BsdfStrategy) -> &'static str {
    match b {
        BsdfStrategy::Cosine => "cosine",
        BsdfStrategy::Ndf => "ndf",
        BsdfStrategy::Vndf => "vndf",
        BsdfStrategy::SphericalCaps => "caps",
        BsdfStrategy::Bounded => "bounded",
    }
}

/// Short name of a light strategy.
fn light_name(l: LightStrategy) -> &'static str {
    match l {
        LightStrategy::Bsdf => "bsdf",
        LightStrategy::Nee => "nee",
        LightStrategy::Mis => "mis",
    }
}

/// Short name of a sampler.
fn sampler_name(s: SamplerKind) -> &'static str {
    match s {
        SamplerKind::Independent => "indep",
        SamplerKind::Sobol => "sobol",
    }
}

impl Config {
    /// Stable short name, e.g. `vndf-mis-sobol-cpu-spec` or `cosine-mis-sobol-cpu-spec`.
    pub fn name(&self) -> String {
        format!(
            "{}-{}-{}-{}-{}",
            bsdf_name(self.bsdf),
            light_name(self.light),
            sampler_name(self.sampler),
            self.backend.name(),
            if self.specialize { "spec" } else { "generic" }
        )
    }

    /// The axis on which this configuration differs from [`BASELINE`] (the first one found;
    /// the study's configurations differ on at most one).
    pub fn axis(&self) -> Axis {
        if self.bsdf != BASELINE.bsdf {
            Axis::Bsdf
        } else if self.light != BASELINE.light {
            Axis::Light
        } else if self.sampler != BASELINE.sampler {
            Axis::Sampler
        } else if self.backend != BASELINE.backend {
            Axis::Backend
        } else if self.specialize != BASELINE.specialize {
            Axis::Kernel
        } else {
            Axis::Baseline
        }
    }

    /// Human label saying what differs from the baseline, e.g. `BSDF sampling: NDF`.
    pub fn label(&self) -> String {
        match self.axis() {
            Axis::Baseline => "baseline (VNDF, MIS, sobol, cpu, specialized)".into(),
            Axis::Bsdf => format!(
                "BSDF sampling: {}",
                match self.bsdf {
                    BsdfStrategy::Cosine => "cosine",
                    BsdfStrategy::Ndf => "NDF",
                    BsdfStrategy::Vndf => "VNDF",
                    BsdfStrategy::SphericalCaps => "spherical caps",
                    BsdfStrategy::Bounded => "bounded VNDF",
                }
            ),
            Axis::Light => format!(
                "lights: {}",
                match self.light {
                    LightStrategy::Bsdf => "BSDF sampling only",
                    LightStrategy::Nee => "NEE only",
                    LightStrategy::Mis => "MIS",
                }
            ),
            Axis::Sampler => format!("sampler: {}", sampler_name(self.sampler)),
            Axis::Backend => format!("backend: {}", self.backend.name()),
            Axis::Kernel => format!("kernel: {}", if self.specialize { "specialized" } else { "generic" }),
        }
    }

    /// Sets the scene's integrator strategies to this configuration (backend and kernel are
    /// chosen at render time).
    pub fn apply(&self, scene: &mut Scene) {
        scene.integrator.bsdf_sampling = self.bsdf;
        scene.integrator.light_strategy = self.light;
        scene.integrator.sampler = self.sampler;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ten_configurations_with_unique_names_one_axis_each() {
        let configs = all(true);
        assert_eq!(configs.len(), 10);
        assert_eq!(all(false).len(), 9);
        let names: Vec<String> = configs.iter().map(Config::name).collect();
        assert_eq!(names[0], "vndf-mis-sobol-cpu-spec");
        for (i, n) in names.iter().enumerate() {
            assert!(!names[..i].contains(n), "duplicate {n}");
        }
        assert!(names.contains(&"cosine-mis-sobol-cpu-spec".to_string()));
        assert!(names.contains(&"vndf-mis-sobol-wgpu-spec".to_string()));
        assert!(names.contains(&"vndf-mis-sobol-cpu-generic".to_string()));
        assert_eq!(configs.iter().filter(|c| c.axis() == Axis::Baseline).count(), 1);
        assert_eq!(configs.iter().filter(|c| c.axis() == Axis::Bsdf).count(), 4);
        assert_eq!(configs.iter().filter(|c| c.axis() == Axis::Light).count(), 2);
        for axis in [Axis::Sampler, Axis::Backend, Axis::Kernel] {
            assert_eq!(configs.iter().filter(|c| c.axis() == axis).count(), 1, "{axis:?}");
        }
        assert_eq!(Config { bsdf: BsdfStrategy::Ndf, ..BASELINE }.label(), "BSDF sampling: NDF");
    }
}
