//! Assembles a [`Scene`] from the parsed file: validates every section, tessellates shapes,
//! collects area lights and derives the [`SceneFeatures`].

use std::f32::consts::PI;
use std::path::{Path, PathBuf};

use crate::camera_build;
use crate::environment::{self, Environment};
use crate::error::{ErrorKind, SceneError, Source};
use crate::features::SceneFeatures;
use crate::integrator::IntegratorSettings;
use crate::lights::{AreaLight, AreaLights};
use crate::limits::{LimitError, Limits};
use crate::material::{Material, luminance};
use crate::material_build;
use crate::mesh::TriangleMesh;
use crate::raw::RawScene;
use crate::scene::Scene;
use crate::shape_build::{self, Budget};
use crate::shorten::{short, short_list};
use crate::texture_load::TextureLoader;
use glam::Vec3;

/// Validates `raw` (parsed from `src`) into a [`Scene`]; relative files resolve against
/// `base_dir`, and files, triangles and memory stay within `limits`.
///
/// Every shape is validated and its triangles counted before any is tessellated, so a scene
/// over [`Limits::max_triangles`] or [`Limits::max_memory`] fails at the shape that crosses
/// the limit without allocating its triangles. Each mesh file is parsed once, within what
/// the shapes before it leave of the limits, and its arrays count against `max_memory`; the
/// environment map is loaded within what the triangles leave of `max_memory`.
pub(crate) fn build(src: Source<'_>, raw: &RawScene, base_dir: &Path, limits: &Limits) -> Result<Scene, SceneError> {
    let (camera, camera_path) = camera_build::build(src, &raw.camera)?;
    let integrator = IntegratorSettings::from_raw(src, raw.integrator.as_ref())?;
    let mut material_names: Vec<String> = raw.materials.keys().cloned().collect();
    let mut gltf_warnings = Vec::new();
    let mut cameras = Vec::new();
    let mut punctual_lights = Vec::new();
    let mut loader = TextureLoader::new(base_dir, limits);
    let mut materials = raw
        .materials
        .iter()
        .map(|(name, m)| material_build::build(src, name, m, &mut loader))
        .collect::<Result<Vec<_>, _>>()?;
    let texture_inputs = std::mem::take(&mut loader.inputs);
    if let Some(on) = integrator.energy_compensation {
        materials.iter_mut().for_each(|m| *m = m.with_compensation(on));
    }
    let mut prepared = Vec::with_capacity(raw.shapes.len());
    let mut budget = Budget::new(limits);
    budget.textures = loader.set;
    for (index, shape) in raw.shapes.iter().enumerate() {
        let p = shape_build::prepare(src, index, shape, base_dir, &mut budget)?;
        let field = format!("shapes[{index}].material");
        let material = match (&shape.material, p.gltf()) {
            (Some(name), _) => {
                let Some(m) = material_names.iter().position(|n| n == name.get_ref()) else {
                    let msg = format!(
                        "unknown material \"{}\" (defined: {})",
                        short(name.get_ref()),
                        defined(&material_names)
                    );
                    return Err(src.error(name.span(), &field, ErrorKind::UnknownMaterial, msg));
                };
                (m as u32, true)
            }
            (None, Some(asset)) => {
                let base = materials.len() as u32;
                let file = shape.file.as_ref().map_or("", |f| f.get_ref().as_str());
                for (name, m) in &asset.materials {
                    let mut unique = format!("{file}#{name}");
                    let mut k = 1;
                    while material_names.contains(&unique) {
                        k += 1;
                        unique = format!("{file}#{name} ({k})");
                    }
                    material_names.push(unique);
                    materials.push(*m);
                }
                (base, false)
            }
            (None, None) => {
                let msg = "`material` is required (only a gltf shape takes its materials from its file)";
                return Err(src.error(shape.kind.span(), &field, ErrorKind::Schema, msg));
            }
        };
        if let Some(asset) = p.gltf() {
            gltf_warnings.extend(asset.warnings.iter().cloned());
            cameras.extend(asset.cameras.iter().cloned());
            punctual_lights.extend(p.punctual_lights());
        }
        budget
            .add_triangles(index, p.triangles())
            .map_err(|msg| src.error(shape.kind.span(), &format!("shapes[{index}]"), ErrorKind::Limit, msg))?;
        prepared.push((p, material));
    }
    let textures = std::mem::take(&mut budget.textures);
    // At most MAX_SCENE_TRIANGLES (u32::MAX): triangle, shape and shading normal indices fit
    // in u32 below NO_INDEX.
    let triangles = budget.triangles();
    drop(budget);
    let mut mesh = TriangleMesh::default();
    if mesh.triangles.try_reserve_exact(usize::try_from(triangles).unwrap_or(usize::MAX)).is_err() {
        let msg = format!("cannot allocate memory for {triangles} triangles");
        return Err(src.error(0..0, "shapes", ErrorKind::Limit, msg));
    }
    let mut lights = Vec::new();
    let textured = |m: u32| matches!(materials.get(m as usize), Some(Material::MetalRough(r)) if r.is_textured() || r.has_emission_texture());
    let mut used = vec![false; materials.len()];
    let mut power = 0.0f64;
    for (index, (shape, (p, (material, one)))) in raw.shapes.iter().zip(prepared).enumerate() {
        if one {
            used[material as usize] = true;
        } else if let Some(asset) = p.gltf() {
            for (_, slot) in &asset.primitives {
                used[material as usize + slot] = true;
            }
        }
        if !one {
            // A glTF asset: one light per emissive material, over its triangles.
            let first = mesh.triangles.len();
            p.append(src, index, shape, (material, one), &textured, &mut mesh)?;
            power = gltf_lights(src, index, shape, &materials, first, &mut mesh, &mut lights, power)?;
            continue;
        }
        let material = material as usize;
        let first = mesh.triangles.len() as u32;
        let area = p.append(src, index, shape, (material as u32, one), &textured, &mut mesh)?;
        let radiance = materials[material].emission();
        if radiance != Vec3::ZERO {
            let at = |kind, msg: String| src.error(shape.kind.span(), &format!("shapes[{index}]"), kind, msg);
            if area <= 0.0 || !area.is_finite() {
                let msg = format!("emissive shape has degenerate area {area} (zero-area or overflowing light)");
                return Err(at(ErrorKind::Degenerate, msg));
            }
            power += f64::from(PI) * f64::from(luminance(radiance)) * f64::from(area);
            if power > f64::from(f32::MAX) {
                let msg = format!(
                    "the emitted power (pi * area * luminance of the radiance) of the lights up to this shape is \
                     {power:.1e}, over f32's max {:.1e}: make the light smaller or dimmer",
                    f32::MAX
                );
                return Err(at(ErrorKind::OutOfRange, msg));
            }
            lights.push(AreaLight {
                shape: index as u32,
                first_triangle: first,
                triangle_count: mesh.triangles.len() as u32 - first,
                material: material as u32,
                radiance,
                area,
            });
        }
    }
    let lights = AreaLights::new(lights, &mut mesh);
    let environment = match &raw.environment {
        None => None,
        Some(e) => {
            let env = environment::build(src, e, base_dir, limits, triangles)?;
            check_scene_memory(limits, triangles, &env)
                .map_err(|m| src.error(e.kind.span(), "environment", ErrorKind::Limit, m.to_string()))?;
            Some(env)
        }
    };
    let mut features = features(&materials, &used, &mesh, &lights, environment.as_ref(), raw.shapes.len());
    features.punctual_lights = !punctual_lights.is_empty();
    Ok(Scene {
        camera,
        camera_path,
        integrator,
        materials,
        material_names,
        mesh,
        lights,
        environment,
        features,
        textures,
        cameras,
        punctual_lights,
        warnings: gltf_warnings,
        shape_count: raw.shapes.len(),
        source: PathBuf::from(src.file),
        inputs: inputs(raw, base_dir).into_iter().chain(texture_inputs).collect(),
    })
}

/// Adds an [`AreaLight`] for every run of triangles from `first` on (one glTF shape) whose
/// material emits, and returns the emitted power so far, checked like a TOML light's.
#[allow(clippy::too_many_arguments)]
fn gltf_lights(
    src: Source<'_>,
    index: usize,
    shape: &crate::raw::RawShape,
    materials: &[Material],
    first: usize,
    mesh: &mut TriangleMesh,
    lights: &mut Vec<AreaLight>,
    mut power: f64,
) -> Result<f64, SceneError> {
    let mut start = first;
    let end = mesh.triangles.len();
    while start < end {
        let material = mesh.triangles[start].material;
        let mut stop = start + 1;
        while stop < end && mesh.triangles[stop].material == material {
            stop += 1;
        }
        let radiance = materials.get(material as usize).map_or(Vec3::ZERO, Material::emission);
        let area: f32 = mesh.triangles[start..stop].iter().map(|t| t.area()).sum();
        if radiance != Vec3::ZERO && area > 0.0 && area.is_finite() {
            power += f64::from(PI) * f64::from(luminance(radiance)) * f64::from(area);
            if power > f64::from(f32::MAX) {
                let msg =
                    format!("the emitted power of the glTF asset's emissive materials is {power:.1e}, over f32's max");
                return Err(src.error(shape.kind.span(), &format!("shapes[{index}]"), ErrorKind::OutOfRange, msg));
            }
            lights.push(AreaLight {
                shape: index as u32,
                first_triangle: start as u32,
                triangle_count: (stop - start) as u32,
                material,
                radiance,
                area,
            });
        }
        start = stop;
    }
    Ok(power)
}

/// The mesh and map files `raw` reads, resolved against `base_dir`.
fn inputs(raw: &RawScene, base_dir: &Path) -> Vec<PathBuf> {
    let meshes = raw.shapes.iter().filter_map(|s| s.file.as_ref());
    let map = raw.environment.as_ref().and_then(|e| e.file.as_ref());
    meshes.chain(map).map(|f| base_dir.join(f.get_ref())).collect()
}

/// Checks the memory of `triangles` triangles and the environment map of `env` together
/// (the map was loaded within what the triangles leave, so this holds unless the two
/// estimates disagree).
fn check_scene_memory(limits: &Limits, triangles: u64, env: &Environment) -> Result<(), LimitError> {
    let Environment::Map(map) = env else { return Ok(()) };
    environment::check_with_triangles(limits, triangles, map.width, map.height)
}

fn defined(names: &[String]) -> String {
    if names.is_empty() { "none".to_owned() } else { short_list(names) }
}

/// What the scene uses: materials count only when `used` by a shape.
fn features(
    materials: &[Material],
    used: &[bool],
    mesh: &TriangleMesh,
    lights: &AreaLights,
    environment: Option<&Environment>,
    shapes: usize,
) -> SceneFeatures {
    let used = || materials.iter().zip(used).filter(|(_, u)| **u).map(|(m, _)| m);
    SceneFeatures {
        area_lights: !lights.is_empty(),
        env_map: matches!(environment, Some(Environment::Map(_))),
        constant_env: matches!(environment, Some(Environment::Constant(_))),
        diffuse: used().any(|m| matches!(m, Material::Diffuse { .. })),
        conductors: used().any(|m| matches!(m, Material::Conductor { .. })),
        plastics: used().any(|m| matches!(m, Material::Plastic { .. })),
        dielectrics: used().any(|m| matches!(m, Material::Dielectric { .. })),
        anisotropic: used().any(Material::is_anisotropic),
        shading_normals: !mesh.shading_normals.is_empty(),
        emissive_only: shapes > 0 && used().all(|m| matches!(m, Material::Emissive { .. })),
        metal_rough: used().any(|m| matches!(m, Material::MetalRough(_))),
        textures: used().any(|m| matches!(m, Material::MetalRough(r) if r.is_textured() || r.has_emission_texture())),
        punctual_lights: false,
    }
}
