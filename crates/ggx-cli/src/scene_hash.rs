//! The scene hash of a film file: what must be equal for two renders' samples to be added.

use std::fmt::Write as _;

use ggx_scene::Scene;
use sha2::{Digest, Sha256};

/// The scene hash: SHA-256 (first 128 bits, hex) of everything in the loaded scene that decides
/// a sample's value: the camera of the frame, materials, geometry, lights, environment and the
/// integrator settings except the sample count and time budget (which decide how many
/// samples, not their values). File paths are left out, so the same scene hashes alike in any
/// directory. Everything but the camera is hashed once for all the frames of an animation
/// (formatting a large mesh is the slow part).
pub struct SceneHash(Vec<u8>);

impl SceneHash {
    /// Hashes everything but the camera.
    pub fn new(scene: &Scene) -> SceneHash {
        let mut hasher = HashWriter(Sha256::new());
        let settings = ggx_scene::IntegratorSettings { spp: 0, time_budget: None, ..scene.integrator };
        // Writing to a hasher cannot fail.
        let _ = write!(
            hasher,
            "{:?}{:?}{:?}{:?}{:?}{:?}{:?}",
            settings,
            scene.materials,
            scene.material_names,
            scene.mesh,
            scene.lights,
            scene.environment,
            scene.features
        );
        SceneHash(hasher.0.finalize().to_vec())
    }

    /// The scene hash with `camera` (a frame's), as hex.
    pub fn with_camera(&self, camera: &ggx_scene::Camera) -> String {
        let mut hasher = HashWriter(Sha256::new());
        hasher.0.update(&self.0);
        let _ = write!(hasher, "{camera:?}");
        hasher.0.finalize()[..16].iter().fold(String::new(), |mut s, b| {
            let _ = write!(s, "{b:02x}");
            s
        })
    }
}

/// Feeds formatted text to a hasher without building the string.
struct HashWriter(Sha256);

impl std::fmt::Write for HashWriter {
    fn write_str(&mut self, s: &str) -> std::fmt::Result {
        self.0.update(s.as_bytes());
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SCENE: &str = r#"
[camera]
position = [0, 0, 5]
look_at = [0, 0, 0]
[integrator]
spp = 4
[environment]
type = "constant"
radiance = [0.5, 0.5, 0.5]
[materials.white]
type = "diffuse"
albedo = [0.8, 0.8, 0.8]
[[shapes]]
type = "sphere"
material = "white"
radius = 1
"#;

    fn load(text: &str) -> Scene {
        ggx_scene::parse_scene(text, "s.toml", std::path::Path::new(".")).unwrap()
    }

    fn scene_hash(scene: &Scene) -> String {
        SceneHash::new(scene).with_camera(&scene.camera)
    }

    #[test]
    fn spp_and_paths_do_not_matter_the_rest_does() {
        let base = scene_hash(&load(SCENE));
        assert_eq!(base.len(), 32);
        let elsewhere = ggx_scene::parse_scene(SCENE, "other/s.toml", std::path::Path::new("other")).unwrap();
        assert_eq!(scene_hash(&elsewhere), base, "another directory");
        assert_eq!(scene_hash(&load(&SCENE.replace("spp = 4", "spp = 400\ntime = 3"))), base);
        for (from, to) in [("spp = 4", "spp = 4\nseed = 9"), ("0.8, 0.8", "0.8, 0.7"), ("radius = 1", "radius = 1.01")]
        {
            assert_ne!(scene_hash(&load(&SCENE.replace(from, to))), base, "{to}");
        }
    }
}
