//! [`Scene`]: the validated, renderer-ready scene.

use std::path::PathBuf;

use crate::camera::Camera;
use crate::camera_path::{CameraPath, FrameError};
use crate::environment::Environment;
use crate::features::SceneFeatures;
use crate::gltf_asset::GltfCamera;
use crate::integrator::IntegratorSettings;
use crate::lights::AreaLights;
use crate::material::Material;
use crate::mesh::TriangleMesh;
use crate::punctual::PunctualLight;
use crate::stats::SceneStats;
use crate::texture::TextureSet;

/// A loaded and validated scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// The camera: the still camera, or the current frame's ([`Scene::set_frame`]; frame 0
    /// after loading) of an animated one.
    pub camera: Camera,
    /// The animation of an animated camera (`[[camera.keys]]`), `None` for a still one.
    pub camera_path: Option<CameraPath>,
    /// Sampling settings.
    pub integrator: IntegratorSettings,
    /// Materials, indexed by [`crate::Triangle::material`] (sorted by name).
    pub materials: Vec<Material>,
    /// Names of `materials`, same order.
    pub material_names: Vec<String>,
    /// All shapes as world-space triangles.
    pub mesh: TriangleMesh,
    /// Emissive shapes and their sampling distribution.
    pub lights: AreaLights,
    /// Light from infinitely far away, if any.
    pub environment: Option<Environment>,
    /// What the scene uses.
    pub features: SceneFeatures,
    /// Every texture the materials read.
    pub textures: TextureSet,
    /// The cameras of the glTF assets (world space), for `--camera NAME`.
    pub cameras: Vec<GltfCamera>,
    /// Point, spot and directional lights (`KHR_lights_punctual`), reached by next-event
    /// estimation only.
    pub punctual_lights: Vec<PunctualLight>,
    /// What the loader ignored or approximated (glTF features ggx does not render), one
    /// sentence each; [`Scene::warnings`] includes them.
    pub warnings: Vec<String>,
    /// Number of `[[shapes]]` entries.
    pub shape_count: usize,
    /// The scene file as given to the loader.
    pub source: PathBuf,
    /// The other files the scene reads (meshes, environment map), resolved; with `source`,
    /// what an output must never overwrite.
    pub inputs: Vec<PathBuf>,
}

impl Scene {
    /// Counts for `ggx info`.
    pub fn stats(&self) -> SceneStats {
        SceneStats {
            shapes: self.shape_count,
            triangles: self.mesh.triangles.len(),
            smooth_triangles: self.mesh.shading_normals.len(),
            materials: self.materials.len(),
            lights: self.lights.lights.len(),
            emitters: self.lights.emitters.len(),
            light_area: self.lights.total_area(),
            env_map: match &self.environment {
                Some(Environment::Map(m)) => Some([m.width, m.height]),
                _ => None,
            },
        }
    }

    /// What is legal but probably not meant, one sentence each (the CLI prints them as
    /// warnings before rendering): a scene without shapes, and a scene where nothing emits
    /// light (no emissive shape, no environment), whose image is black.
    pub fn warnings(&self) -> Vec<String> {
        let source = self.source.display();
        let mut out = self.warnings.clone();
        let lit = !self.lights.is_empty() || self.environment.is_some() || !self.punctual_lights.is_empty();
        if self.shape_count == 0 {
            let shows = if lit { "only the environment" } else { "nothing: it is black" };
            out.push(format!("{source} has no shapes: the image shows {shows}"));
        } else if !lit {
            out.push(format!(
                "{source}: nothing emits light (no emissive shape, no [environment]): the image is black"
            ));
        }
        out
    }

    /// Turns energy compensation on or off for every material (the command line's
    /// `--energy-compensation`, like `integrator.energy_compensation` in the file).
    pub fn set_energy_compensation(&mut self, on: bool) {
        self.integrator.energy_compensation = Some(on);
        self.materials.iter_mut().for_each(|m| *m = m.with_compensation(on));
    }

    /// Number of frames: [`CameraPath::frame_count`] (`floor(duration * fps) + 1`) for an
    /// animated camera, 1 for a still one.
    pub fn frame_count(&self) -> u32 {
        self.camera_path.as_ref().map_or(1, CameraPath::frame_count)
    }

    /// Sets [`Self::camera`] to the camera at `frame` (time `frame / fps`), keeping its
    /// resolution (which the caller may have overridden); a still camera has only frame 0.
    pub fn set_frame(&mut self, frame: u32) -> Result<(), FrameError> {
        match &self.camera_path {
            None if frame == 0 => Ok(()),
            None => Err(FrameError::NotAnimated { frame }),
            Some(path) => {
                self.camera = path.camera_at_frame(frame, self.camera.resolution)?;
                Ok(())
            }
        }
    }

    /// Index of the material called `name`.
    pub fn material_index(&self, name: &str) -> Option<usize> {
        self.material_names.iter().position(|n| n == name)
    }
}
