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
    let material_names: Vec<String> = raw.materials.keys().cloned().collect();
    let mut materials =
        raw.materials.iter().map(|(name, m)| material_build::build(src, name, m)).collect::<Result<Vec<_>, _>>()?;
    if let Some(on) = integrator.energy_compensation {
        materials.iter_mut().for_each(|m| *m = m.with_compensation(on));
    }
    let mut prepared = Vec::with_capacity(raw.shapes.len());
    let mut budget = Budget::new(limits);
    for (index, shape) in raw.shapes.iter().enumerate() {
        let name = shape.material.get_ref();
        let Some(material) = material_names.iter().position(|n| n == name) else {
            let msg = format!("unknown material \"{}\" (defined: {})", short(name), defined(&material_names));
            let field = format!("shapes[{index}].material");
            return Err(src.error(shape.material.span(), &field, ErrorKind::UnknownMaterial, msg));
        };
        let p = shape_build::prepare(src, index, shape, base_dir, &mut budget)?;
        budget
            .add_triangles(index, p.triangles())
            .map_err(|msg| src.error(shape.kind.span(), &format!("shapes[{index}]"), ErrorKind::Limit, msg))?;
        prepared.push((p, material));
    }
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
    let mut used = vec![false; materials.len()];
    let mut power = 0.0f64;
    for (index, (shape, (p, material))) in raw.shapes.iter().zip(prepared).enumerate() {
        used[material] = true;
        let first = mesh.triangles.len() as u32;
        let area = p.append(src, index, shape, material as u32, &mut mesh)?;
        if let Material::Emissive { radiance } = materials[material] {
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
    let features = features(&materials, &used, &mesh, &lights, environment.as_ref(), raw.shapes.len());
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
        shape_count: raw.shapes.len(),
        source: PathBuf::from(src.file),
        inputs: inputs(raw, base_dir),
    })
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
    }
}
