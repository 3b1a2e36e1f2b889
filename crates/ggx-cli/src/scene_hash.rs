//! The scene hash of a film file: what must be equal for two renders' samples to be added.

use std::fmt::Write as _;

use ggx_scene::Scene;
use sha2::{Digest, Sha256};

/// The scene hash: SHA-256 (first 128 bits, hex) of everything in the loaded scene that decides
/// a sample's value ([`Scene::write_sample_inputs`]: materials, geometry, lights, environment,
/// textures and the integrator settings except the sample count and time budget), then the
/// camera of the frame. File paths are left out, so the same scene hashes alike in any
/// directory. Everything but the camera is hashed once for all the frames of an animation.
pub struct SceneHash(Vec<u8>);

impl SceneHash {
    /// Hashes everything but the camera.
    pub fn new(scene: &Scene) -> SceneHash {
        let mut hasher = Sha256::new();
        scene.write_sample_inputs(&mut |bytes| hasher.update(bytes));
        SceneHash(hasher.finalize().to_vec())
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

    /// What the old `Debug`-text hash left out, textures and punctual lights, and each table
    /// written as bytes: changing one value in any of them changes the hash.
    #[test]
    fn every_table_counts() {
        let studio = SCENE.replace(
            "[environment]\ntype = \"constant\"\nradiance = [0.5, 0.5, 0.5]",
            "[environment]\ntype = \"procedural\"\npreset = \"studio\"\nresolution = [64, 32]",
        );
        let scene = load(&studio);
        let base = scene_hash(&scene);
        assert_ne!(base, scene_hash(&load(SCENE)), "the environment");
        assert_eq!(scene_hash(&load(&studio)), base, "loading twice");
        let rotated = studio.replace("resolution = [64, 32]", "resolution = [64, 32]\nrotation = 10");
        assert_ne!(scene_hash(&load(&rotated)), base, "the rotation");
        type Edit = (&'static str, fn(&mut Scene));
        let edits: [Edit; 6] = [
            ("a texel word", |s| s.textures.words[7] ^= 1),
            ("a punctual light", |s| {
                s.punctual_lights.push(ggx_scene::PunctualLight {
                    position: [0.0; 3],
                    kind: ggx_scene::PUNCTUAL_POINT,
                    direction: [0.0, -1.0, 0.0],
                    range: 0.0,
                    intensity: [1.0; 3],
                    spot_scale: 0.0,
                    spot_offset: 0.0,
                    pad: [0; 3],
                })
            }),
            ("a triangle", |s| s.mesh.triangles[5].v1[2] = s.mesh.triangles[5].v1[2].next_up()),
            ("an environment texel", |s| {
                if let Some(ggx_scene::Environment::Map(m)) = &mut s.environment {
                    m.texels[100][1] *= 2.0;
                }
            }),
            ("a material name", |s| s.material_names[0].push('x')),
            ("a feature", |s| s.features = ggx_scene::SceneFeatures::default()),
        ];
        for (what, edit) in edits {
            let mut edited = scene.clone();
            edit(&mut edited);
            assert_ne!(edited, scene, "{what}: the edit must change the scene");
            assert_ne!(scene_hash(&edited), base, "{what}");
        }
    }
}
