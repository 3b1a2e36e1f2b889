//! What the kernels read: the scene's triangles, BVH, precomputed BSDFs and lights.

use crate::accel::{Accel, AccelKind};
use ggx_core::Sampling;
use ggx_render::{Bsdf, sampling_for};
use ggx_scene::{
    AreaLights, Camera, Environment, LightStrategy, Material, MetalRough, PunctualLight, RayGenerator, Scene,
    SceneFeatures, ShadingNormals, TextureSet, Triangle, TriangleTangents, TriangleUvs,
};
use glam::Vec3;

/// Immutable per-render scene data shared by all threads.
pub struct SceneData {
    /// The acceleration structure.
    pub accel: Accel,
    /// World-space triangles (scene order).
    pub triangles: Vec<Triangle>,
    /// [`Triangle::geometric_normal`] of each triangle, computed once (a hit and an area-light
    /// sample each read one).
    pub geometric_normals: Vec<Vec3>,
    /// Per-vertex shading normals referenced by `Triangle::normals`.
    pub shading_normals: Vec<ShadingNormals>,
    /// One BSDF per scene material.
    pub bsdfs: Vec<Bsdf>,
    /// Emitted radiance per scene material.
    pub emission: Vec<Vec3>,
    /// Area lights and their power distribution.
    pub lights: AreaLights,
    /// The environment, if any, as [`Environment::for_integrator`] gives it (a map's
    /// distribution MIS-compensated under MIS).
    pub environment: Option<Environment>,
    /// Next-event estimation samples the environment ([`Environment::for_integrator`]).
    pub environment_is_light: bool,
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
    /// Point, spot and directional lights.
    pub punctual_lights: Vec<PunctualLight>,
    /// Every texture of the scene.
    pub textures: TextureSet,
    /// Per scene material: the metallic-roughness material when it reads a texture (its BSDF,
    /// normal or emission is then looked up at each shading point), else `None`.
    pub textured: Vec<Option<MetalRough>>,
    /// Texture coordinates, parallel to `shading_normals` (empty without textures).
    pub uvs: Vec<TriangleUvs>,
    /// Mesh tangents, parallel to `shading_normals` (empty when no mesh gave any).
    pub tangents: Vec<TriangleTangents>,
    /// The technique of the textured materials' specular lobes.
    pub sampling: Sampling,
    /// Some material reads the lobe sample ([`Bsdf::uses_lobe_sample`]): every bounce draws
    /// it, whatever the kernel variant.
    pub uses_lobe_sample: bool,
}

impl SceneData {
    /// Texture coordinates of triangle `tri` at barycentrics `(b1, b2)` (zero without any).
    #[inline]
    pub fn uv_at(&self, tri: &Triangle, b1: f32, b2: f32) -> glam::Vec2 {
        self.uvs.get(tri.normals as usize).map_or(glam::Vec2::ZERO, |uv| uv.interpolate(b1, b2))
    }

    /// Emitted radiance of `material` on triangle `tri` at barycentrics `(b1, b2)`: the
    /// material's, times its emission texture when it has one.
    #[inline]
    pub fn emission_at(&self, material: usize, tri: &Triangle, b1: f32, b2: f32) -> Vec3 {
        match self.textured.get(material) {
            Some(Some(m)) if m.has_emission_texture() => {
                ggx_render::emission_at(m, &self.textures, self.uv_at(tri, b1, b2))
            }
            _ => self.emission.get(material).copied().unwrap_or(Vec3::ZERO),
        }
    }

    /// Precomputes everything from a validated scene.
    pub fn new(scene: &Scene, accel: AccelKind) -> SceneData {
        let strategy = scene.integrator.bsdf_sampling;
        let bsdfs: Vec<Bsdf> = scene.materials.iter().map(|m| Bsdf::new(m, strategy)).collect();
        let (environment, environment_is_light) = match &scene.environment {
            Some(e) => {
                let (e, is_light) = e.for_integrator(&scene.integrator);
                (Some(e.into_owned()), is_light)
            }
            None => (None, false),
        };
        SceneData {
            uses_lobe_sample: bsdfs.iter().any(Bsdf::uses_lobe_sample),
            accel: Accel::build(&scene.mesh.triangles, accel),
            triangles: scene.mesh.triangles.clone(),
            geometric_normals: scene.mesh.triangles.iter().map(Triangle::geometric_normal).collect(),
            shading_normals: scene.mesh.shading_normals.clone(),
            bsdfs,
            emission: scene.materials.iter().map(|m| m.emission()).collect(),
            lights: scene.lights.clone(),
            environment,
            environment_is_light,
            camera: scene.camera,
            ray_generator: scene.camera.ray_generator(),
            light_strategy: scene.integrator.light_strategy,
            max_depth: scene.integrator.max_depth,
            roulette_depth: scene.integrator.russian_roulette,
            features: scene.features,
            textures: scene.textures.clone(),
            punctual_lights: scene.punctual_lights.clone(),
            textured: scene
                .materials
                .iter()
                .map(|m| match m {
                    Material::MetalRough(r) if r.is_textured() || r.has_emission_texture() => Some(*r),
                    _ => None,
                })
                .collect(),
            uvs: scene.mesh.uvs.clone(),
            tangents: scene.mesh.tangents.clone(),
            sampling: Bsdf::metal_rough_sampling(sampling_for(strategy)),
        }
    }
}
