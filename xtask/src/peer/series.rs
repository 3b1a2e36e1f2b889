//! What the peer run renders: the renderer configurations, their ladders and what they
//! measured.

use super::metrics::Rung;

/// A renderer and its sampler or variant.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Renderer {
    /// ggx (release `ggx render`), Owen-scrambled Sobol' (its default).
    GgxSobol,
    /// ggx with the independent sampler.
    GgxIndependent,
    /// Mitsuba 3, `llvm_ad_rgb` (JIT-compiled wavefront), independent sampler.
    MitsubaLlvm,
    /// Mitsuba 3, `scalar_rgb`, independent sampler.
    MitsubaScalar,
}

impl Renderer {
    /// Short name for files and CSV: `ggx-sobol`, `ggx-independent`, `mitsuba-llvm`,
    /// `mitsuba-scalar`.
    pub fn name(self) -> &'static str {
        match self {
            Self::GgxSobol => "ggx-sobol",
            Self::GgxIndependent => "ggx-independent",
            Self::MitsubaLlvm => "mitsuba-llvm",
            Self::MitsubaScalar => "mitsuba-scalar",
        }
    }

    /// For tables: `ggx (Sobol')`, `Mitsuba llvm_ad_rgb`, ...
    pub fn label(self) -> &'static str {
        match self {
            Self::GgxSobol => "ggx (Sobol')",
            Self::GgxIndependent => "ggx (independent)",
            Self::MitsubaLlvm => "Mitsuba llvm_ad_rgb",
            Self::MitsubaScalar => "Mitsuba scalar_rgb",
        }
    }

    /// Mitsuba's variant, `None` for ggx.
    pub fn variant(self) -> Option<&'static str> {
        match self {
            Self::GgxSobol | Self::GgxIndependent => None,
            Self::MitsubaLlvm => Some("llvm_ad_rgb"),
            Self::MitsubaScalar => Some("scalar_rgb"),
        }
    }

    /// The sampler.
    pub fn sampler(self) -> &'static str {
        match self {
            Self::GgxSobol => "sobol",
            _ => "independent",
        }
    }
}

/// One ladder: a renderer at a thread count up to a top rung.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Config {
    /// Which renderer.
    pub renderer: Renderer,
    /// Worker threads (ggx `--threads`, Dr.Jit's `set_thread_count`).
    pub threads: usize,
    /// Top of its ladder.
    pub max_spp: u32,
}

impl Config {
    /// `ggx-sobol-2t`, `mitsuba-llvm-1t`, ...
    pub fn name(&self) -> String {
        format!("{}-{}t", self.renderer.name(), self.threads)
    }

    /// `ggx (Sobol'), 2 threads`.
    pub fn label(&self) -> String {
        format!("{}, {} thread{}", self.renderer.label(), self.threads, if self.threads == 1 { "" } else { "s" })
    }
}

/// The configurations of a run with `threads` cores: ggx Sobol' and independent and Mitsuba's
/// LLVM variant on every core up to `max_spp`, ggx and Mitsuba LLVM on one thread up to
/// `single`, Mitsuba's scalar variant on every core up to `min(max_spp, 64)` and on one thread
/// up to `max(single / 4, 1)` (it is the slowest). The first is the baseline.
pub fn configs(threads: usize, max_spp: u32, single: u32) -> Vec<Config> {
    let c = |renderer, threads, max_spp| Config { renderer, threads, max_spp };
    let mut v = vec![
        c(Renderer::GgxSobol, threads, max_spp),
        c(Renderer::GgxIndependent, threads, max_spp),
        c(Renderer::MitsubaLlvm, threads, max_spp),
        c(Renderer::MitsubaScalar, threads, max_spp.min(64)),
    ];
    if threads > 1 {
        v.extend([
            c(Renderer::GgxSobol, 1, single),
            c(Renderer::MitsubaLlvm, 1, single),
            c(Renderer::MitsubaScalar, 1, (single / 4).max(1)),
        ]);
    }
    v
}

/// A configuration's measured rungs.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    /// The configuration.
    pub config: Config,
    /// Rungs in spp order.
    pub rungs: Vec<Rung>,
}

/// Mitsuba's first render of a scene in a variant, with a cold kernel cache.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FirstRender {
    /// The variant.
    pub renderer: Renderer,
    /// Samples per pixel.
    pub spp: u32,
    /// Wall-clock seconds (tracing, JIT compilation and rendering).
    pub seconds: f64,
    /// Of which JIT compilation.
    pub jit_seconds: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn configurations_of_a_two_core_run() {
        let v = configs(2, 256, 64);
        let names: Vec<String> = v.iter().map(Config::name).collect();
        assert_eq!(
            names,
            [
                "ggx-sobol-2t",
                "ggx-independent-2t",
                "mitsuba-llvm-2t",
                "mitsuba-scalar-2t",
                "ggx-sobol-1t",
                "mitsuba-llvm-1t",
                "mitsuba-scalar-1t"
            ]
        );
        assert_eq!(v.iter().map(|c| c.max_spp).collect::<Vec<_>>(), [256, 256, 256, 64, 64, 64, 16]);
        assert_eq!(configs(1, 16, 4).len(), 4, "one core: no separate 1-thread ladders");
        assert_eq!(v[5].label(), "Mitsuba llvm_ad_rgb, 1 thread");
        assert_eq!(Renderer::MitsubaScalar.variant(), Some("scalar_rgb"));
    }
}
