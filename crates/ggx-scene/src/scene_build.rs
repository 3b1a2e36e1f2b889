//! Assembles a [`Scene`] from the parsed file: validates every section, tessellates shapes,
//! collects area lights and derives the [`SceneFeatures`].

use std::path::{Path, PathBuf};

use crate::camera::Camera;
use crate::environment::{self, Environment};
use crate::error::{ErrorKind, SceneError, Source};
use crate::features::SceneFeatures;
use crate::integrator::IntegratorSettings;
use crate::lights::{AreaLight, AreaLights};
use crate::material::Material;
use crate::material_build;
use crate::mesh::TriangleMesh;
use crate::raw::RawScene;
use crate::scene::Scene;
use crate::shape_build::add_shape;

/// Validates `raw` (parsed from `src`) into a [`Scene`]; relative files resolve against
/// `base_dir`.
pub(crate) fn build(src: Source<'_>, raw: &RawScene, base_dir: &Path) -> Result<Scene, SceneError> {
    let camera = Camera::from_raw(src, &raw.camera)?;
    let integrator = IntegratorSettings::from_raw(src, raw.integrator.as_ref())?;
    let material_names: Vec<String> = raw.materials.keys().cloned().collect();
    let materials =
        raw.materials.iter().map(|(name, m)| material_build::build(src, name, m)).collect::<Result<Vec<_>, _>>()?;
    let mut mesh = TriangleMesh::default();
    let mut lights = Vec::new();
    let mut used = vec![false; materials.len()];
    for (index, shape) in raw.shapes.iter().enumerate() {
        let name = shape.material.get_ref();
        let Some(material) = material_names.iter().position(|n| n == name) else {
            let msg = format!("unknown material \"{name}\" (defined: {})", defined(&material_names));
            let field = format!("shapes[{index}].material");
            return Err(src.error(shape.material.span(), &field, ErrorKind::UnknownMaterial, msg));
        };
        used[material] = true;
        let first = mesh.triangles.len() as u32;
        let area = add_shape(src, index, shape, material as u32, base_dir, &mut mesh)?;
        if let Material::Emissive { radiance } = materials[material] {
            if area <= 0.0 || !area.is_finite() {
                let msg = format!("emissive shape has degenerate area {area} (zero-area or overflowing light)");
                return Err(src.error(shape.kind.span(), &format!("shapes[{index}]"), ErrorKind::Degenerate, msg));
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
    let environment = raw.environment.as_ref().map(|e| environment::build(src, e, base_dir)).transpose()?;
    let features = features(&materials, &used, &mesh, &lights, environment.as_ref(), raw.shapes.len());
    Ok(Scene {
        camera,
        integrator,
        materials,
        material_names,
        mesh,
        lights,
        environment,
        features,
        shape_count: raw.shapes.len(),
        source: PathBuf::from(src.file),
    })
}

fn defined(names: &[String]) -> String {
    if names.is_empty() { "none".to_owned() } else { names.join(", ") }
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
        anisotropic: used().any(Material::is_anisotropic),
        shading_normals: !mesh.shading_normals.is_empty(),
        emissive_only: shapes > 0 && used().all(|m| matches!(m, Material::Emissive { .. })),
    }
}
