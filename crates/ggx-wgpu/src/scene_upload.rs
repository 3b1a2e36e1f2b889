//! The scene as the flat, `bytemuck::Pod` tables `path_tracer.wgsl` reads: BVH nodes and
//! leaf-order triangles, shading normals, materials (ggx-render's precomputed [`Bsdf`]s), one `f32`
//! table for the light and environment CDFs and texels, one `u32` table for emitters, lights and
//! what textured materials read at a hit ([`SceneTables::surface`]), and the [`Params`].
//!
//! The `surface` table (binding 7, WGSL `surface: array<u32>`, `f32` read with `bitcast`) holds
//! the sections below, each only when the scene has what it holds (a scene with no emitter, no
//! textured material and no punctual light uploads one zero word):
//!
//! | section | offset | words |
//! |---|---|---|
//! | [`MetalRoughRecord`]s of the textured materials | [`MaterialRecord::surface`] | 60 each |
//! | [`Emitter`]s (triangle as a leaf index, light, area, pmf) | [`Params::emitters`] | 4 x [`Params::emitter_count`] |
//! | [`PunctualLight`]s (`KHR_lights_punctual`), in the scene's order | [`Params::punctual_lights`] | 16 x [`Params::punctual_count`] |
//! | [`TriangleUvs`], parallel to the shading normals | [`Params::uvs`] | 8 x [`Params::uv_count`] |
//! | [`TriangleTangents`], parallel to the shading normals | [`Params::tangents`] | 12 x [`Params::tangent_count`] |
//! | [`TextureInfo`]s | [`Params::texture_infos`] | 4 x [`Params::texture_count`] |
//! | `i / 255` for `i` in `0..256` (8-bit channels, the CPU's `b as f32 / 255.0`) | [`Params::texture_unorm`] | 256 |
//! | [`TextureSet::words`] (sRGB table, then texels), last | [`Params::texture_words`] | the rest |
//!
//! The sections from the texture coordinates on exist only when some material is textured.

use crate::bvh_flat::{BvhNode, EMPTY_TREE, FlatBvh};
use bytemuck::{Pod, Zeroable};
use ggx_core::{GgxConductor, GltfMetalRough, Sampling};
use ggx_render::{Bsdf, stream_seed};
use ggx_scene::{
    Emitter, Environment, LightStrategy, Material, MetalRough, NO_INDEX, SamplerKind, Scene, ShadingNormals,
    TextureRef, TextureSet, Triangle,
};
#[cfg(doc)]
use ggx_scene::{PunctualLight, TextureInfo, TriangleTangents, TriangleUvs};
use glam::{Quat, Vec3};

/// A material as the shader shades it, 128 bytes (WGSL `Material`).
///
/// | `kind` | `conductor` | `albedo` | `ior` | `extra` | `compensation` |
/// |---|---|---|---|---|---|
/// | `MAT_DIFFUSE` 0 | - | albedo | - | - | - |
/// | `MAT_CONDUCTOR` 1 | the BRDF | - | - | `F_avg` | Kulla-Conty lobe on |
/// | `MAT_PLASTIC` 2 | the coat | base albedo | coat ior | - | `1 - E` base coupling on |
/// | `MAT_BLACK` 3 | - | - | - | - | - |
/// | `MAT_DIELECTRIC` 4 | alphas in `distribution` | transmittance | eta | absorption | energy scale on |
/// | `MAT_THIN` 5 | - | transmittance | eta | - | - |
/// | `MAT_METAL_ROUGH` 6 | alphas in `distribution` | base colour | metallic | `f0` | - |
/// | `MAT_CLEARCOAT` 7 | as 6, and the coat in `fresnel.a` | base colour | metallic | `f0` | - |
///
/// `MAT_METAL_ROUGH` is ggx-core's `GltfMetalRough` of the material's factors (ggx-render's
/// `Bsdf::MetalRough`): `base_color` in `albedo`, `metallic` in `ior`, `f0` in `extra`,
/// `specular_weight` and `p_specular` in the fields of those names, the alphas in
/// `conductor.distribution`. A material whose parameters, normal or emission read a texture
/// also has `surface`, the offset of its [`MetalRoughRecord`] in [`SceneTables::surface`]
/// (else [`NO_INDEX`]), from which the kernel with `TEXTURES` builds the BRDF at each hit.
/// `MAT_CLEARCOAT` is ggx-core's `GltfClearcoat` (ggx-render's `Bsdf::Clearcoat`): its base
/// packed as `MAT_METAL_ROUGH`, `conductor.fresnel.a` = (coat `alpha_x`, `alpha_y`, `weight`,
/// `base_albedo`).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MaterialRecord {
    /// The conductor (or a plastic's coat, or a dielectric's distribution), from ggx-core.
    pub conductor: GgxConductor,
    /// Albedo of a diffuse material or a plastic's base; a dielectric's transmittance.
    pub albedo: [f32; 3],
    /// One of the `MAT_*` kinds in the table.
    pub kind: u32,
    /// Emitted radiance (zero unless emissive).
    pub emission: [f32; 3],
    /// Coat index of refraction of a plastic; relative index of a dielectric.
    pub ior: f32,
    /// A conductor's `F_avg` (`ggx_core::GgxConductorMs::f_avg`); a dielectric's absorption.
    pub extra: [f32; 3],
    /// `ggx_core::Sampling` discriminant of the conductor, coat or dielectric lobe.
    pub sampling: u32,
    /// Non-zero: energy compensation on (see the table).
    pub compensation: u32,
    /// Offset of a textured metal-rough material's [`MetalRoughRecord`] in
    /// [`SceneTables::surface`], [`NO_INDEX`] for every other material.
    pub surface: u32,
    /// `GltfMetalRough::specular_weight` of a metal-rough material.
    pub specular_weight: f32,
    /// `GltfMetalRough::p_specular` of a metal-rough material.
    pub p_specular: f32,
}

impl MaterialRecord {
    /// The record of a ggx-render BSDF and its emission.
    pub fn new(bsdf: &Bsdf, emission: Vec3) -> MaterialRecord {
        let mut r = MaterialRecord::zeroed();
        r.emission = emission.to_array();
        r.kind = 3;
        r.surface = NO_INDEX;
        match *bsdf {
            Bsdf::Diffuse { albedo } => (r.kind, r.albedo) = (0, albedo.to_array()),
            Bsdf::Conductor { brdf, sampling } => {
                (r.kind, r.conductor, r.sampling) = (1, brdf.conductor, sampling as u32);
                (r.extra, r.compensation) = (brdf.f_avg, brdf.compensation);
            }
            Bsdf::Plastic { coat, ior, albedo, sampling, compensate } => {
                (r.kind, r.conductor, r.ior, r.albedo, r.sampling) = (2, coat, ior, albedo.to_array(), sampling as u32);
                r.compensation = u32::from(compensate);
            }
            Bsdf::Dielectric { bsdf, transmittance, absorption, sampling } => {
                r.kind = 4;
                r.conductor.distribution = bsdf.dielectric.distribution;
                (r.ior, r.albedo, r.extra) = (bsdf.dielectric.eta, transmittance.to_array(), absorption.to_array());
                (r.sampling, r.compensation) = (sampling as u32, bsdf.compensation);
            }
            Bsdf::Thin { sheet, transmittance } => (r.kind, r.ior, r.albedo) = (5, sheet.eta, transmittance.to_array()),
            Bsdf::MetalRough { brdf, sampling } => r.set_metal_rough(6, &brdf, sampling),
            Bsdf::Clearcoat { brdf, sampling } => {
                r.set_metal_rough(7, &brdf.base, sampling);
                r.conductor.fresnel.a = [brdf.coat.alpha_x, brdf.coat.alpha_y, brdf.weight, brdf.base_albedo];
            }
            Bsdf::Black => {}
        }
        r
    }

    /// Packs `brdf` as the table's `MAT_METAL_ROUGH` columns, with `kind`.
    fn set_metal_rough(&mut self, kind: u32, brdf: &GltfMetalRough, sampling: Sampling) {
        (self.kind, self.albedo, self.ior, self.extra) = (kind, brdf.base_color, brdf.metallic, brdf.f0);
        (self.specular_weight, self.p_specular) = (brdf.specular_weight, brdf.p_specular);
        (self.conductor.distribution, self.sampling) = (brdf.distribution, sampling as u32);
    }
}

/// A textured metal-rough material as the shader reads it from [`SceneTables::surface`]
/// (ggx-scene's [`MetalRough`]; `path_tracer.wgsl` reads each field at its `MR_*` word offset),
/// 240 bytes = 60 words.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct MetalRoughRecord {
    /// Base colour factor.
    pub base_color: [f32; 3],
    /// Metallic factor.
    pub metallic: f32,
    /// Emitted radiance factor.
    pub emission: [f32; 3],
    /// Perceptual roughness factor.
    pub roughness: f32,
    /// Specular colour.
    pub specular_color: [f32; 3],
    /// Specular weight.
    pub specular: f32,
    /// Index of refraction.
    pub ior: f32,
    /// Scale of the normal map's X and Y.
    pub normal_scale: f32,
    /// `KHR_materials_anisotropy`'s strength (0: isotropic).
    pub anisotropy: f32,
    /// The anisotropy direction's rotation from the tangent, radians (the shader reads its
    /// cosine and sine, [`MetalRoughRecord::anisotropy_cos_sin`]).
    pub anisotropy_rotation: f32,
    /// Base colour texture (words 16..24).
    pub base_color_texture: TextureRef,
    /// Metallic texture (words 24..32).
    pub metallic_texture: TextureRef,
    /// Roughness texture (words 32..40).
    pub roughness_texture: TextureRef,
    /// Normal map (words 40..48).
    pub normal_texture: TextureRef,
    /// Emission texture (words 48..56).
    pub emission_texture: TextureRef,
    /// `(cos, sin)` of [`MetalRoughRecord::anisotropy_rotation`] (words 56, 57), by the CPU's
    /// `f32::sin_cos` as ggx-render's `anisotropy_direction` computes them: a GPU's `sin` and
    /// `cos` need not round like the CPU's, and the values are the same at every hit.
    pub anisotropy_cos_sin: [f32; 2],
    /// `KHR_materials_clearcoat`'s weight (word 58; 0: no coat).
    pub clearcoat: f32,
    /// The coat's perceptual roughness (word 59).
    pub clearcoat_roughness: f32,
}

impl MetalRoughRecord {
    /// The record of `m`.
    pub fn new(m: &MetalRough) -> MetalRoughRecord {
        MetalRoughRecord {
            base_color: m.base_color.to_array(),
            metallic: m.metallic,
            emission: m.emission.to_array(),
            roughness: m.roughness,
            specular_color: m.specular_color.to_array(),
            specular: m.specular,
            ior: m.ior,
            normal_scale: m.normal_scale,
            anisotropy: m.anisotropy,
            anisotropy_rotation: m.anisotropy_rotation,
            base_color_texture: m.base_color_texture,
            metallic_texture: m.metallic_texture,
            roughness_texture: m.roughness_texture,
            normal_texture: m.normal_texture,
            emission_texture: m.emission_texture,
            anisotropy_cos_sin: {
                let (s, c) = m.anisotropy_rotation.sin_cos();
                [c, s]
            },
            clearcoat: m.clearcoat,
            clearcoat_roughness: m.clearcoat_roughness,
        }
    }
}

/// The material `m` when the renderers look it up at each hit (ggx-cpu's
/// `SceneData::textured`): a metal-rough material whose parameters, normal or emission read a
/// texture.
pub fn textured(m: &Material) -> Option<&MetalRough> {
    match m {
        Material::MetalRough(r) if r.is_textured() || r.has_emission_texture() => Some(r),
        _ => None,
    }
}

/// Appends `textures` to `surface` as the shader reads them (the texture infos, the `i / 255`
/// table, then the word table, which stays last so that a word index past the end reads 0 as on
/// the CPU) and sets their offsets in `params`.
pub fn push_textures(surface: &mut Vec<u32>, textures: &TextureSet, params: &mut Params) {
    params.texture_count = textures.infos.len() as u32;
    params.texture_infos = push_words(surface, bytemuck::cast_slice(&textures.infos));
    let unorm: Vec<u32> = (0..=255u8).map(|b| (f32::from(b) / 255.0).to_bits()).collect();
    params.texture_unorm = push_words(surface, &unorm);
    params.texture_words = push_words(surface, &textures.words);
}

/// What the kernel reads of the render and of one dispatch (WGSL `Params`), 256 bytes. A
/// read-only storage buffer, not a uniform one: lavapipe re-specializes a kernel on the values of
/// a uniform that steers control flow ([`Params::y0`], [`Params::s0`]...) at every dispatch, which
/// cost 2 s per pass of the path tracer (97.9 s for 48 passes of 20x20 pixels; 0.71 s from storage).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Params {
    /// Camera position.
    pub cam_position: [f32; 3],
    /// `tan(fov_y / 2)`.
    pub tan_half_fov: f32,
    /// Camera forward.
    pub cam_forward: [f32; 3],
    /// Width / height.
    pub aspect: f32,
    /// Camera right.
    pub cam_right: [f32; 3],
    /// Width as `f32`.
    pub width_f: f32,
    /// Camera up.
    pub cam_up: [f32; 3],
    /// Height as `f32`.
    pub height_f: f32,
    /// Radiance of a constant environment.
    pub env_radiance: [f32; 3],
    /// Multiplier of the environment map's texels.
    pub env_scale: f32,
    /// Quaternion taking world directions to map directions.
    pub env_to_map: [f32; 4],
    /// Quaternion taking map directions to world directions.
    pub env_to_world: [f32; 4],
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// First row of this dispatch.
    pub y0: u32,
    /// Rows in this dispatch.
    pub rows: u32,
    /// First sample index of the pass.
    pub s0: u32,
    /// One past the last sample index of the pass.
    pub s1: u32,
    /// `SequenceKind` discriminant.
    pub sequence: u32,
    /// Stream seed ([`stream_seed`]).
    pub seed: u32,
    /// 0 BSDF sampling only, 1 next-event estimation, 2 MIS.
    pub light_strategy: u32,
    /// Maximum bounces.
    pub max_depth: u32,
    /// Depth from which Russian roulette applies (0 = never).
    pub roulette_depth: u32,
    /// 1 when bounces draw a lobe sample (`Bsdf::uses_lobe_sample` of some material).
    pub draw_lobe: u32,
    /// Number of emitters.
    pub emitter_count: u32,
    /// 0 no environment, 1 constant, 2 map.
    pub env_kind: u32,
    /// Map columns.
    pub env_width: u32,
    /// Map rows.
    pub env_height: u32,
    /// Offset of the light CDF (`emitter_count + 1` values) in the table.
    pub light_cdf: u32,
    /// Offset of the map's cell weights.
    pub env_func: u32,
    /// Offset of the map's conditional CDFs.
    pub env_conditional_cdf: u32,
    /// Offset of the map's marginal CDF.
    pub env_marginal_cdf: u32,
    /// Offset of the map's texels (4 values each).
    pub env_texels: u32,
    /// Integral of the map's distribution over the square.
    pub env_marginal_integral: f32,
    /// Offset of ggx-core's energy-compensation tables ([`energy_tables`]) in the table;
    /// unused (0) when no material is compensated.
    pub energy_tables: u32,
    /// Offset (words) of the texture coordinates in [`SceneTables::surface`].
    pub uvs: u32,
    /// Number of texture-coordinate records (0: none).
    pub uv_count: u32,
    /// Offset (words) of the tangents in [`SceneTables::surface`].
    pub tangents: u32,
    /// Number of tangent records (0: none).
    pub tangent_count: u32,
    /// Offset (words) of the texture infos in [`SceneTables::surface`].
    pub texture_infos: u32,
    /// Number of textures.
    pub texture_count: u32,
    /// Offset (words) of the 256 values `i / 255` in [`SceneTables::surface`].
    pub texture_unorm: u32,
    /// Offset (words) of the texture word table (sRGB table first) in [`SceneTables::surface`].
    pub texture_words: u32,
    /// Offset (words) of the punctual lights in [`SceneTables::surface`].
    pub punctual_lights: u32,
    /// Number of punctual lights (0: none).
    pub punctual_count: u32,
    /// Offset (words) of the emitters in [`SceneTables::surface`] (read only when
    /// [`Params::emitter_count`] is not 0).
    pub emitters: u32,
    /// 1 when next-event estimation samples the environment ([`Environment::for_integrator`]:
    /// 0 for a constant or uniform one under MIS compensation).
    pub env_light: u32,
    /// Padding.
    pub pad3: u32,
}

/// Everything the shader reads, on the CPU.
pub struct SceneTables {
    /// Flattened BVH with triangles in leaf order.
    pub bvh: FlatBvh,
    /// Shading normals.
    pub normals: Vec<ShadingNormals>,
    /// One record per scene material.
    pub materials: Vec<MaterialRecord>,
    /// Light CDF, environment tables and texels.
    pub table: Vec<f32>,
    /// Emitters (`triangle` pointing into the leaf-order triangles), textured materials, punctual
    /// lights, texture coordinates, tangents and textures (see the module docs); empty when the
    /// scene has none of them.
    pub surface: Vec<u32>,
    /// The parameters, `y0`, `rows`, `s0`, `s1` left zero.
    pub params: Params,
}

impl SceneTables {
    /// Flattens `scene`.
    pub fn new(scene: &Scene) -> SceneTables {
        let bvh = FlatBvh::build(&scene.mesh.triangles);
        let strategy = scene.integrator.bsdf_sampling;
        let bsdfs: Vec<Bsdf> = scene.materials.iter().map(|m| Bsdf::new(m, strategy)).collect();
        let mut materials: Vec<MaterialRecord> =
            bsdfs.iter().zip(&scene.materials).map(|(b, m)| MaterialRecord::new(b, m.emission())).collect();
        let mut surface = Vec::new();
        for (record, material) in materials.iter_mut().zip(&scene.materials) {
            if let Some(m) = textured(material) {
                record.surface = push_words(&mut surface, bytemuck::cast_slice(&[MetalRoughRecord::new(m)]));
            }
        }
        let any_textured = !surface.is_empty();
        let mut leaf_of = vec![u32::MAX; scene.mesh.triangles.len()];
        for (leaf, &t) in bvh.primitive_to_triangle.iter().enumerate().rev() {
            if let Some(slot) = leaf_of.get_mut(t as usize) {
                *slot = leaf as u32;
            }
        }
        let emitters: Vec<Emitter> = scene
            .lights
            .emitters
            .iter()
            .map(|e| Emitter { triangle: leaf_of.get(e.triangle as usize).copied().unwrap_or(u32::MAX), ..*e })
            .collect();
        let cam = &scene.camera;
        let [width, height] = cam.resolution;
        let it = &scene.integrator;
        let mut params = Params {
            cam_position: cam.position.to_array(),
            tan_half_fov: cam.tan_half_fov(),
            cam_forward: cam.forward.to_array(),
            aspect: cam.aspect(),
            cam_right: cam.right.to_array(),
            width_f: width as f32,
            cam_up: cam.up.to_array(),
            height_f: height as f32,
            width,
            height,
            sequence: match it.sampler {
                SamplerKind::Independent => 0,
                SamplerKind::Sobol => 1,
            },
            seed: stream_seed(it.seed),
            light_strategy: match it.light_strategy {
                LightStrategy::Bsdf => 0,
                LightStrategy::Nee => 1,
                LightStrategy::Mis => 2,
            },
            max_depth: it.max_depth,
            roulette_depth: it.russian_roulette,
            draw_lobe: u32::from(bsdfs.iter().any(Bsdf::uses_lobe_sample)),
            emitter_count: scene.lights.emitters.len() as u32,
            env_to_map: [0.0, 0.0, 0.0, 1.0],
            env_to_world: [0.0, 0.0, 0.0, 1.0],
            ..Params::zeroed()
        };
        if !emitters.is_empty() {
            params.emitters = push_words(&mut surface, bytemuck::cast_slice(&emitters));
        }
        let mut table = Vec::new();
        params.light_cdf = push(&mut table, &scene.lights.distribution.cdf);
        let environment = scene.environment.as_ref().map(|e| e.for_integrator(it));
        params.env_light = u32::from(environment.as_ref().is_some_and(|e| e.1));
        match environment.as_ref().map(|e| &*e.0) {
            None => {}
            Some(Environment::Constant(l)) => (params.env_kind, params.env_radiance) = (1, l.to_array()),
            Some(Environment::Map(m)) => {
                let d = &m.distribution;
                params.env_kind = 2;
                (params.env_width, params.env_height, params.env_scale) = (m.width, m.height, m.scale);
                params.env_to_map = Quat::from_rotation_y(-m.rotation()).to_array();
                params.env_to_world = Quat::from_rotation_y(m.rotation()).to_array();
                params.env_marginal_integral = d.marginal.integral;
                params.env_func = push(&mut table, &d.func);
                params.env_conditional_cdf = push(&mut table, &d.conditional_cdf);
                params.env_marginal_cdf = push(&mut table, &d.marginal.cdf);
                params.env_texels = push(&mut table, m.texels.as_flattened());
            }
        }
        if bsdfs.iter().any(Bsdf::is_compensated) {
            params.energy_tables = table.len() as u32;
            for t in energy_tables() {
                table.extend_from_slice(t);
            }
        }
        if !scene.punctual_lights.is_empty() {
            params.punctual_lights = push_words(&mut surface, bytemuck::cast_slice(&scene.punctual_lights));
            params.punctual_count = count(&scene.punctual_lights);
        }
        if any_textured {
            let mesh = &scene.mesh;
            (params.uvs, params.uv_count) =
                (push_words(&mut surface, bytemuck::cast_slice(&mesh.uvs)), count(&mesh.uvs));
            params.tangents = push_words(&mut surface, bytemuck::cast_slice(&mesh.tangents));
            params.tangent_count = count(&mesh.tangents);
            push_textures(&mut surface, &scene.textures, &mut params);
        }
        SceneTables { bvh, normals: scene.mesh.shading_normals.clone(), materials, table, surface, params }
    }

    /// The nodes, never empty: an empty scene gets [`EMPTY_TREE`], which the traversal
    /// recognises before it tests any box.
    pub fn nodes(&self) -> Vec<BvhNode> {
        if self.bvh.nodes.is_empty() {
            return vec![EMPTY_TREE];
        }
        self.bvh.nodes.clone()
    }

    /// The leaf-order triangles (for the shader's bindings, at least one).
    pub fn triangles(&self) -> Vec<Triangle> {
        non_empty(&self.bvh.triangles)
    }
}

/// ggx-core's energy-compensation tables in the order `energy.wgsl` reads them from
/// `Params::energy_tables` on (its `ENERGY_*` offsets): the conductor's `E` (row-major) and
/// `E_avg`, then the dielectric's `E_T` outside and inside, the coat's `E_R` and `E_R_avg`
/// (`ggx_core::energy_dielectric`'s flat tables).
pub fn energy_tables() -> [&'static [f32]; 6] {
    use ggx_core::energy_dielectric::*;
    [
        ggx_core::energy_tables::E.as_flattened(),
        &ggx_core::energy_tables::E_AVG,
        dielectric_albedo_outside_table().0,
        dielectric_albedo_inside_table().0,
        coat_albedo_table().0,
        coat_average_albedo_table().0,
    ]
}

/// `values` appended to `table`; returns their offset.
fn push(table: &mut Vec<f32>, values: &[f32]) -> u32 {
    let offset = table.len() as u32;
    table.extend_from_slice(values);
    offset
}

/// `words` appended to `surface`; returns their offset (saturated: a table past `u32` words is
/// refused by the buffer size check before it is used).
fn push_words(surface: &mut Vec<u32>, words: &[u32]) -> u32 {
    let offset = u32::try_from(surface.len()).unwrap_or(u32::MAX);
    surface.extend_from_slice(words);
    offset
}

/// `values.len()` as `u32` (saturated).
fn count<T>(values: &[T]) -> u32 {
    u32::try_from(values.len()).unwrap_or(u32::MAX)
}

/// `values`, or one zeroed record when empty (bindings cannot be empty).
pub fn non_empty<T: Pod>(values: &[T]) -> Vec<T> {
    if values.is_empty() { vec![T::zeroed()] } else { values.to_vec() }
}

#[cfg(test)]
mod tests {
    use super::*;
    use ggx_scene::{PUNCTUAL_POINT, PUNCTUAL_SPOT, PunctualLight};
    use std::path::Path;

    /// Punctual lights are one section of `surface`, the scene's `PunctualLight`s word for word;
    /// a scene without any uploads what it did before they existed (nothing in `surface`).
    #[test]
    fn punctual_lights_are_uploaded_only_when_the_scene_has_some() {
        let text = "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nresolution = [8, 8]\n\
                    [materials.m]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
                    [[shapes]]\ntype = \"sphere\"\nmaterial = \"m\"\ncenter = [0, 0, 0]\nradius = 1\n\
                    [environment]\ntype = \"constant\"\nradiance = [1, 1, 1]\n";
        let mut scene = ggx_scene::parse_scene(text, "s.toml", Path::new(".")).expect("scene");
        let plain = SceneTables::new(&scene);
        assert!(plain.surface.is_empty());
        assert_eq!((plain.params.punctual_lights, plain.params.punctual_count), (0, 0));
        let spot = PunctualLight {
            position: [1.0, 2.0, 3.0],
            kind: PUNCTUAL_SPOT,
            direction: [0.0, -1.0, 0.0],
            range: 4.0,
            intensity: [1.0, 2.0, 3.0],
            spot_scale: 5.0,
            spot_offset: -4.0,
            pad: [0; 3],
        };
        scene.punctual_lights = vec![spot, PunctualLight { kind: PUNCTUAL_POINT, range: 0.0, ..spot }];
        let lit = SceneTables::new(&scene);
        assert_eq!(lit.params.punctual_count, 2);
        let o = lit.params.punctual_lights as usize;
        assert_eq!(lit.surface.get(o..o + 32), Some(bytemuck::cast_slice::<_, u32>(&scene.punctual_lights)));
        assert_eq!(lit.surface.len(), 32, "no texture sections without a textured material");
        assert_eq!(Params { punctual_lights: 0, punctual_count: 0, ..lit.params }, plain.params);
        assert_eq!((&lit.materials, &lit.table), (&plain.materials, &plain.table));
    }

    /// Emitters are a section of `surface`: per emitter its triangle's leaf index (the triangle
    /// the BVH leaf order put there), its light, area and pmf, word for word.
    #[test]
    fn emitters_are_uploaded_in_surface_with_leaf_indices() {
        let text = "[camera]\nposition = [0, 0, 3]\nlook_at = [0, 0, 0]\nresolution = [8, 8]\n\
                    [materials.m]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
                    [materials.lamp]\ntype = \"emissive\"\nradiance = [4, 4, 4]\n\
                    [[shapes]]\ntype = \"sphere\"\nmaterial = \"m\"\ncenter = [0, 0, 0]\nradius = 1\n\
                    [[shapes]]\ntype = \"sphere\"\nmaterial = \"lamp\"\ncenter = [0, 3, 0]\nradius = 0.5\n";
        let scene = ggx_scene::parse_scene(text, "s.toml", Path::new(".")).expect("scene");
        let emitters = &scene.lights.emitters;
        assert!(emitters.len() > 8, "a meshed sphere of emitters");
        let tables = SceneTables::new(&scene);
        assert_eq!(tables.params.emitter_count as usize, emitters.len());
        let o = tables.params.emitters as usize;
        let words = tables.surface.get(o..o + 4 * emitters.len()).expect("the emitter section");
        let leaves = &tables.bvh.primitive_to_triangle;
        for (e, (w, emitter)) in words.chunks_exact(4).zip(emitters).enumerate() {
            assert_eq!(leaves.get(w[0] as usize), Some(&emitter.triangle), "emitter {e}: its triangle's leaf");
            let rest = [emitter.light, emitter.area.to_bits(), emitter.pmf.to_bits()];
            assert_eq!(w[1..], rest, "emitter {e}");
        }
        // The emitters are the only section: no texture or punctual-light words follow.
        assert_eq!(tables.surface.len(), o + 4 * emitters.len());
    }
}
