//! `[integrator]`: sample counts, path depth and the sampling strategies to use.

use serde::Deserialize;

use crate::check::Interval;
use crate::error::{ErrorKind, SceneError, Source};
use crate::raw::RawIntegrator;

/// How the BSDF's GGX lobe is importance sampled.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum BsdfStrategy {
    /// Cosine-weighted hemisphere sampling (ignores the lobe).
    Cosine,
    /// Sampling the distribution of normals D(m) cos(theta_m).
    Ndf,
    /// Sampling the distribution of visible normals (Heitz 2018).
    #[default]
    Vndf,
    /// VNDF sampling with spherical caps (Dupuy & Benyoub 2023).
    SphericalCaps,
    /// Bounded VNDF sampling (Eto & Tokuyoshi 2023).
    Bounded,
}

/// Which light-transport estimator is used for emitters and the environment.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum LightStrategy {
    /// BSDF sampling only: lights are found when a path hits them.
    Bsdf,
    /// Next-event estimation only: lights are sampled explicitly.
    Nee,
    /// BSDF sampling and next-event estimation combined with multiple importance sampling.
    #[default]
    Mis,
}

/// The sample sequence.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq, Hash)]
#[serde(rename_all = "kebab-case")]
pub enum SamplerKind {
    /// Independent uniform random numbers.
    Independent,
    /// A (scrambled) Sobol sequence.
    #[default]
    Sobol,
}

/// Validated `[integrator]` settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IntegratorSettings {
    /// Samples per pixel, >= 1.
    pub spp: u32,
    /// Maximum number of bounces, >= 1.
    pub max_depth: u32,
    /// Depth from which Russian roulette starts; 0 disables it.
    pub russian_roulette: u32,
    /// Time budget in seconds, `None` for no limit.
    pub time_budget: Option<f32>,
    /// Seed of the sample sequence, in `[0, MAX_SEED]`.
    pub seed: u64,
    /// The sample sequence.
    pub sampler: SamplerKind,
    /// How the BSDF is importance sampled.
    pub bsdf_sampling: BsdfStrategy,
    /// How lights are sampled.
    pub light_strategy: LightStrategy,
    /// Scene-wide energy compensation: `Some` overrides every material's
    /// `energy_compensation`, `None` keeps each material's own (default on).
    pub energy_compensation: Option<bool>,
    /// With `light_strategy = Mis`, next-event estimation samples the environment by its
    /// MIS-compensated distribution ([`crate::Environment::for_integrator`]); default on.
    pub mis_compensation: bool,
}

impl Default for IntegratorSettings {
    fn default() -> Self {
        Self {
            spp: 64,
            max_depth: 5,
            russian_roulette: 3,
            time_budget: None,
            seed: 0,
            sampler: SamplerKind::default(),
            bsdf_sampling: BsdfStrategy::default(),
            light_strategy: LightStrategy::default(),
            energy_compensation: None,
            mis_compensation: true,
        }
    }
}

/// Largest accepted `spp`.
pub const MAX_SPP: u32 = 1 << 24;
/// Largest accepted `max_depth`.
pub const MAX_DEPTH: u32 = 1024;
/// Largest accepted `seed`: seeds are `[0, 2^32 - 1]`, the renderers' 32-bit stream seed, so
/// that every accepted seed gives a distinct sample stream.
pub const MAX_SEED: u64 = u32::MAX as u64;

impl IntegratorSettings {
    /// MIS compensation applies: `light_strategy = Mis` and `mis_compensation` on (the rule
    /// [`crate::Environment::for_integrator`] follows).
    pub fn compensates_mis(&self) -> bool {
        self.light_strategy == LightStrategy::Mis && self.mis_compensation
    }

    /// Validates `[integrator]`; absent keys take the [`Default`] values.
    pub(crate) fn from_raw(src: Source<'_>, raw: Option<&RawIntegrator>) -> Result<Self, SceneError> {
        let d = Self::default();
        let Some(raw) = raw else { return Ok(d) };
        let int = |v: &Option<toml::Spanned<u32>>, field, lo, hi, default| {
            v.as_ref().map_or(Ok(default), |v| src.integer(v, field, lo, hi))
        };
        let time = src.number_or(raw.time.as_ref(), 0.0, "integrator.time", Interval::at_least(0.0))?;
        Ok(Self {
            spp: int(&raw.spp, "integrator.spp", 1, MAX_SPP, d.spp)?,
            max_depth: int(&raw.max_depth, "integrator.max_depth", 1, MAX_DEPTH, d.max_depth)?,
            russian_roulette: int(
                &raw.russian_roulette,
                "integrator.russian_roulette",
                0,
                MAX_DEPTH,
                d.russian_roulette,
            )?,
            time_budget: (time > 0.0).then_some(time),
            seed: seed(src, raw.seed.as_ref())?.unwrap_or(d.seed),
            sampler: raw.sampler.unwrap_or(d.sampler),
            bsdf_sampling: raw.bsdf_sampling.unwrap_or(d.bsdf_sampling),
            light_strategy: raw.light_strategy.unwrap_or(d.light_strategy),
            energy_compensation: raw.energy_compensation,
            mis_compensation: raw.mis_compensation.unwrap_or(d.mis_compensation),
        })
    }
}

/// `integrator.seed` in `[0, MAX_SEED]`.
fn seed(src: Source<'_>, raw: Option<&toml::Spanned<i64>>) -> Result<Option<u64>, SceneError> {
    let Some(v) = raw else { return Ok(None) };
    match u64::try_from(*v.get_ref()) {
        Ok(seed) if seed <= MAX_SEED => Ok(Some(seed)),
        _ => {
            let msg = format!("must be in [0, {MAX_SEED}] (2^32 - 1), got {}", v.get_ref());
            Err(src.error(v.span(), "integrator.seed", ErrorKind::OutOfRange, msg))
        }
    }
}
