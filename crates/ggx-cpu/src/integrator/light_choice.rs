//! Which light class next-event estimation picks, and how emission that BSDF sampling finds
//! is weighted: per scene, shared by `trace` and the packet's steps.

use crate::scene_data::SceneData;
use ggx_core::mis::power_heuristic;
use ggx_scene::LightStrategy;

/// How next-event estimation picks a light, and how emission that BSDF sampling finds is
/// weighted: the same for every path of a scene (and kernel variant).
#[derive(Clone, Copy)]
pub struct LightChoice {
    /// Next-event estimation is on.
    pub(super) use_nee: bool,
    /// Light and BSDF samples are combined by the power heuristic.
    pub(super) use_mis: bool,
    /// Area lights take part.
    pub(super) has_area: bool,
    /// An environment is present.
    pub(super) has_env: bool,
    /// The environment takes part in next-event estimation (not a constant or uniform one
    /// under MIS compensation: `Environment::for_integrator`).
    pub(super) env_light: bool,
    /// Punctual lights take part.
    pub(super) has_punctual: bool,
    /// Probabilities of picking area lights, punctual lights and the environment.
    pub(super) p_area: f32,
    pub(super) p_punctual: f32,
    pub(super) p_env: f32,
}

impl LightChoice {
    /// The choice for `scene` in the kernel variant `AREA`, `ENV`: area lights, punctual
    /// lights and the environment share the selection equally.
    #[inline(always)]
    pub fn for_scene<const AREA: bool, const ENV: bool>(scene: &SceneData) -> Self {
        let strategy = scene.light_strategy;
        let has_area = AREA && !scene.lights.is_empty();
        let has_env = ENV && scene.environment.is_some();
        let env_light = has_env && scene.environment_is_light;
        let has_punctual = AREA && !scene.punctual_lights.is_empty();
        let classes = u32::from(has_area) + u32::from(env_light) + u32::from(has_punctual);
        let p_class = if classes > 0 { 1.0 / classes as f32 } else { 0.0 };
        let p_area = if has_area { p_class } else { 0.0 };
        let p_punctual = if has_punctual { p_class } else { 0.0 };
        let p_env = if env_light { 1.0 - p_area - p_punctual } else { 0.0 };
        LightChoice {
            use_nee: strategy != LightStrategy::Bsdf,
            use_mis: strategy == LightStrategy::Mis,
            has_area,
            has_env,
            env_light,
            has_punctual,
            p_area,
            p_punctual,
            p_env,
        }
    }

    /// Which light class next-event estimation picks with `select`: `(area, punctual)`, the
    /// environment when neither is picked and it takes part.
    #[inline(always)]
    pub(super) fn pick(&self, select: f32) -> (bool, bool) {
        let pick_area = self.has_area && select < self.p_area;
        let pick_punctual = !pick_area && self.has_punctual && select < self.p_area + self.p_punctual;
        (pick_area, pick_punctual)
    }

    /// Whether next-event estimation samples the environment with `select` (the branch
    /// `trace` takes when neither an area nor a punctual light is picked).
    #[inline(always)]
    pub(super) fn picks_environment(&self, select: f32) -> bool {
        let (pick_area, pick_punctual) = self.pick(select);
        self.use_nee && self.env_light && !pick_area && !pick_punctual
    }

    /// Weight of emission found by a BSDF sample of MIS density `prev_pdf` (+inf: a delta lobe
    /// or the camera ray), `pdf_light` its density under next-event estimation: 1 without
    /// next-event estimation, the power heuristic with MIS, and next-event estimation alone
    /// counts only what it cannot find (a delta direction).
    #[inline(always)]
    pub(super) fn emission_weight(&self, prev_pdf: f32, pdf_light: impl FnOnce() -> f32) -> f32 {
        if !self.use_nee {
            1.0
        } else if self.use_mis {
            power_heuristic(1.0, prev_pdf, 1.0, pdf_light())
        } else if prev_pdf == f32::INFINITY {
            1.0
        } else {
            0.0
        }
    }
}
