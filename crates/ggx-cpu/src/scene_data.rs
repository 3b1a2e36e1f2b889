//! What the kernels read: the scene's triangles, BVH, precomputed BSDFs and lights.

use crate::accel::{Accel, AccelKind};
use ggx_render::Bsdf;
use ggx_scene::{
    AreaLights, Camera, Environment, LightStrategy, RayGenerator, Scene, SceneFeatures, ShadingNormals, Triangle,
};
use glam::Vec3;

/// Immutable per-render scene data shared by all threads.
pub struct SceneData {
    /// The acceleration structure.
    pub accel: Accel,
    /// World-space triangles (scene order).
    pub triangles: Vec<Triangle>,
    /// Per-vertex shading normals referenced by `Triangle::normals`.
    pub shading_normals: Vec<ShadingNormals>,
    /// One BSDF per scene material.
    pub bsdfs: Vec<Bsdf>,
    /// Emitted radiance per scene material.
    pub emission: Vec<Vec3>,
    /// Area lights and their power distribution.
    pub lights: AreaLights,
    /// The environment, if any.
    pub environment: Option<Environment>,
    /// The camera.
    pub camera: Camera,
    /// The camera's primary rays, its per-camera terms computed once.
    pub ray_generator: RayGenerator,
    /// Light sampling strategy.
    pub light_strategy: LightStrategy,
    /// Maximum number of bounces.
    pub max_depth: u32,
    /// Depth from which Russian roulette applies (0 = never).
    pub roulette_depth: u32,
    /// What the scene uses.
    pub features: SceneFeatures,
    /// Some material reads the lobe sample ([`Bsdf::uses_lobe_sample`]): every bounce draws
    /// it, whatever the kernel variant.
    pub uses_lobe_sample: bool,
}

impl SceneData {
    /// Precomputes everything from a validated scene.
    pub fn new(scene: &Scene, accel: AccelKind) -> SceneData {
        let strategy = scene.integrator.bsdf_sampling;
        let bsdfs: Vec<Bsdf> = scene.materials.iter().map(|m| Bsdf::new(m, strategy)).collect();
        SceneData {
            uses_lobe_sample: bsdfs.iter().any(Bsdf::uses_lobe_sample),
            accel: Accel::build(&scene.mesh.triangles, accel),
            triangles: scene.mesh.triangles.clone(),
            shading_normals: scene.mesh.shading_normals.clone(),
            bsdfs,
            emission: scene.materials.iter().map(|m| m.emission()).collect(),
            lights: scene.lights.clone(),
            environment: scene.environment.clone(),
            camera: scene.camera,
            ray_generator: scene.camera.ray_generator(),
            light_strategy: scene.integrator.light_strategy,
            max_depth: scene.integrator.max_depth,
            roulette_depth: scene.integrator.russian_roulette,
            features: scene.features,
        }
    }
}
