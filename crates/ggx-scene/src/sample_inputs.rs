//! [`Scene::write_sample_inputs`]: the bytes of a loaded scene that decide a sample's value,
//! for a content hash (what must be equal for two renders' samples to be added).

use crate::distribution::{Distribution1D, Distribution2D};
use crate::environment::Environment;
use crate::integrator::IntegratorSettings;
use crate::lights::AreaLights;
use crate::mesh::TriangleMesh;
use crate::scene::Scene;
use crate::texture::TextureSet;

/// Where [`Scene::write_sample_inputs`] writes: a hasher's `update`.
pub type SampleInputSink<'a> = dyn FnMut(&[u8]) + 'a;

/// Writes one length-prefixed part, so that no two different sequences of parts give the
/// same bytes.
fn part(out: &mut SampleInputSink<'_>, bytes: &[u8]) {
    out(&(bytes.len() as u64).to_le_bytes());
    out(bytes);
}

/// Writes a small value through its `Debug` text (every field, floats shortest round-trip).
fn debug_part(out: &mut SampleInputSink<'_>, value: &dyn std::fmt::Debug) {
    part(out, format!("{value:?}").as_bytes());
}

/// Writes a table of plain records as its bytes, in the machine's byte order (the large
/// tables: formatting their floats as text was most of a render's start-up). x86-64 and
/// AArch64, where the CLI is built and tested, are both little-endian, so parts rendered on
/// either hash alike.
pub(crate) fn pod_part<T: bytemuck::Pod>(out: &mut SampleInputSink<'_>, records: &[T]) {
    part(out, bytemuck::cast_slice(records));
}

impl Scene {
    /// Writes everything that decides a sample's value except the camera, as length-prefixed
    /// parts: the integrator settings without the sample count and time budget (which decide
    /// how many samples, not their values), materials and their names, triangles and their
    /// attributes, area and punctual lights, the environment, textures and the feature set.
    /// File paths, warnings and the glTF camera list are left out, so the same scene writes
    /// alike from any directory. Small parts go as `Debug` text, large tables as their bytes.
    pub fn write_sample_inputs(&self, out: &mut SampleInputSink<'_>) {
        // Exhaustive: a new field of `Scene` does not compile until it is placed here.
        let Scene {
            camera: _,
            camera_path: _,
            integrator,
            materials,
            material_names,
            mesh,
            lights,
            environment,
            features,
            textures,
            cameras: _,
            punctual_lights,
            warnings: _,
            shape_count: _,
            source: _,
            inputs: _,
        } = self;
        debug_part(out, &IntegratorSettings { spp: 0, time_budget: None, ..*integrator });
        debug_part(out, materials);
        debug_part(out, material_names);
        write_mesh(out, mesh);
        write_area_lights(out, lights);
        pod_part(out, punctual_lights);
        write_environment(out, environment.as_ref());
        write_textures(out, textures);
        debug_part(out, features);
    }
}

/// Triangles, shading normals, texture coordinates and tangents.
fn write_mesh(out: &mut SampleInputSink<'_>, mesh: &TriangleMesh) {
    let TriangleMesh { triangles, shading_normals, uvs, tangents } = mesh;
    pod_part(out, triangles);
    pod_part(out, shading_normals);
    pod_part(out, uvs);
    pod_part(out, tangents);
}

/// The emissive shapes, their emitting triangles and the power distribution over them.
fn write_area_lights(out: &mut SampleInputSink<'_>, lights: &AreaLights) {
    let AreaLights { lights, emitters, distribution } = lights;
    debug_part(out, lights);
    pod_part(out, emitters);
    write_distribution_1d(out, distribution);
}

/// No environment, a constant one, or a map with its scale, rotation and distribution.
fn write_environment(out: &mut SampleInputSink<'_>, environment: Option<&Environment>) {
    match environment {
        None => part(out, b"none"),
        Some(Environment::Constant(radiance)) => {
            part(out, b"constant");
            pod_part(out, &[*radiance]);
        }
        Some(Environment::Map(map)) => {
            part(out, b"map");
            map.write_sample_inputs(out);
        }
    }
}

/// Texture records and every texel word.
fn write_textures(out: &mut SampleInputSink<'_>, textures: &TextureSet) {
    let TextureSet { infos, words } = textures;
    pod_part(out, infos);
    pod_part(out, words);
}

/// Weights, CDF, integral and guide table.
fn write_distribution_1d(out: &mut SampleInputSink<'_>, d: &Distribution1D) {
    let Distribution1D { func, cdf, integral, guide } = d;
    pod_part(out, func);
    pod_part(out, cdf);
    pod_part(out, &[*integral]);
    pod_part(out, guide);
}

/// Size, weights, conditional CDFs and guides, and the marginal distribution.
pub(crate) fn write_distribution_2d(out: &mut SampleInputSink<'_>, d: &Distribution2D) {
    let Distribution2D { width, height, func, conditional_cdf, conditional_guide, marginal } = d;
    pod_part(out, &[*width, *height]);
    pod_part(out, func);
    pod_part(out, conditional_cdf);
    pod_part(out, conditional_guide);
    write_distribution_1d(out, marginal);
}
