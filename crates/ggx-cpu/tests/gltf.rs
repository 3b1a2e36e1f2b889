//! glTF scenes in the CPU renderer: `KHR_lights_punctual` lights against their closed forms
//! over a Lambertian plane, and textured scenes bit-identical for any thread count.

mod support;

use std::f32::consts::PI;
use std::path::{Path, PathBuf};

use ggx_cpu::{AccelKind, RenderControl, RenderOptions, Renderer};
use ggx_scene::{GltfOptions, Limits, load_gltf_scene, load_scene};
use glam::Vec3;
use support::{mean, render};

/// A 4 x 4 plane at y = 0 facing +y with a Lambertian material of albedo 0.5 (metal-rough,
/// metallic 0, `KHR_materials_specular` factor 0), a camera at (0, 0.5, 0) looking straight
/// down with a 2-degree field of view, and the light `light` at the node `(translation,
/// rotation)`.
fn plane_with_light(name: &str, light: serde_json::Value, translation: [f32; 3], rotation: [f32; 4]) -> PathBuf {
    use base64::Engine as _;
    let mut bin = Vec::new();
    for v in [[-2.0f32, 0.0, 2.0], [2.0, 0.0, 2.0], [2.0, 0.0, -2.0], [-2.0, 0.0, -2.0]] {
        v.iter().for_each(|c| bin.extend_from_slice(&c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 0, 2, 3] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let uri =
        format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bin));
    // Looking down: the camera's -Z turned to -Y (a -90 degree rotation about x).
    let down = [-std::f32::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2];
    let json = serde_json::json!({
        "asset": { "version": "2.0" },
        "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular"],
        "extensions": { "KHR_lights_punctual": { "lights": [light] } },
        "scene": 0,
        "scenes": [{ "nodes": [0, 1, 2] }],
        "nodes": [
            { "mesh": 0 },
            { "camera": 0, "translation": [0, 0.5, 0], "rotation": down },
            { "translation": translation, "rotation": rotation, "extensions": { "KHR_lights_punctual": { "light": 0 } } }
        ],
        "cameras": [{ "type": "perspective", "perspective": { "yfov": 2.0f32.to_radians(), "znear": 0.01, "aspectRatio": 1.0 } }],
        "materials": [{
            "pbrMetallicRoughness": { "baseColorFactor": [0.5, 0.5, 0.5, 1], "metallicFactor": 0, "roughnessFactor": 0.5 },
            "extensions": { "KHR_materials_specular": { "specularFactor": 0 } }
        }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1, "material": 0 }] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2, 0, -2], "max": [2, 0, 2] },
            { "bufferView": 1, "componentType": 5123, "count": 6, "type": "SCALAR" }
        ],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 48 },
            { "buffer": 0, "byteOffset": 48, "byteLength": 12 }
        ],
        "buffers": [{ "byteLength": 60, "uri": uri }]
    });
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf_lights");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
    path
}

/// The mean radiance the camera sees, at 16x16 pixels and 16 spp.
fn seen(path: &Path) -> Vec3 {
    let mut scene = load_gltf_scene(path, &Limits::default(), &GltfOptions::default()).unwrap();
    assert!(scene.features.punctual_lights && scene.environment.is_none(), "{:?}", scene.features);
    scene.camera.resolution = [16, 16];
    scene.integrator.spp = 16;
    mean(&render(&scene).film.mean())
}

const NO_ROTATION: [f32; 4] = [0.0, 0.0, 0.0, 1.0];

#[test]
fn a_point_light_lights_a_lambertian_plane_by_the_inverse_square_law() {
    // L = albedo / pi * I cos / d^2 with I = 10 * (1, 0.5, 0.25), d = 2, cos = 1 (the
    // visible patch is 0.009 wide: cos and d vary by < 1e-5).
    let light = serde_json::json!({ "type": "point", "color": [1.0, 0.5, 0.25], "intensity": 10.0 });
    let got = seen(&plane_with_light("point.gltf", light, [0.0, 2.0, 0.0], NO_ROTATION));
    let want = Vec3::new(1.0, 0.5, 0.25) * (0.5 / PI * 10.0 / 4.0);
    assert!((got / want - Vec3::ONE).abs().max_element() < 1e-3, "{got} vs {want}");
    // A range shorter than the distance: nothing.
    let light = serde_json::json!({ "type": "point", "intensity": 10.0, "range": 1.5 });
    assert_eq!(seen(&plane_with_light("range.gltf", light, [0.0, 2.0, 0.0], NO_ROTATION)), Vec3::ZERO);
}

#[test]
fn spot_and_directional_lights() {
    // A spot pointing down (its -Z to -Y): inside its inner cone it is a point light.
    let down = [-std::f32::consts::FRAC_1_SQRT_2, 0.0, 0.0, std::f32::consts::FRAC_1_SQRT_2];
    let spot = serde_json::json!({ "type": "spot", "intensity": 8.0, "spot": { "innerConeAngle": 0.2, "outerConeAngle": 0.4 } });
    let got = seen(&plane_with_light("spot.gltf", spot.clone(), [0.0, 2.0, 0.0], down));
    let want = 0.5 / PI * 8.0 / 4.0;
    assert!((got.x / want - 1.0).abs() < 1e-3, "{got} vs {want}");
    // Moved 2 units aside, the plane under the camera is 45 degrees off its axis: dark.
    assert_eq!(seen(&plane_with_light("spot-off.gltf", spot, [2.0, 2.0, 0.0], down)), Vec3::ZERO);
    // A directional light 60 degrees from the zenith: L = albedo / pi * E cos 60.
    let tilt = (-60.0f32.to_radians() - std::f32::consts::FRAC_PI_2) * 0.5;
    let sun = serde_json::json!({ "type": "directional", "intensity": 3.0 });
    let got = seen(&plane_with_light("sun.gltf", sun, [0.0, 5.0, 0.0], [tilt.sin(), 0.0, 0.0, tilt.cos()]));
    let want = 0.5 / PI * 3.0 * 0.5;
    assert!((got.x / want - 1.0).abs() < 1e-3, "{got} vs {want}");
}

#[test]
fn textured_scenes_are_bit_identical_for_any_thread_count() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/textured.toml");
    let mut scene = load_scene(&path).unwrap();
    scene.camera.resolution = [48, 36];
    scene.integrator.spp = 4;
    let renderer = Renderer::new(&scene, AccelKind::default());
    let run = |threads, specialize| {
        let options = RenderOptions { threads, specialize, ..RenderOptions::default() };
        renderer.render(&options, &RenderControl::default()).unwrap().film.mean()
    };
    let one = run(1, true);
    assert_eq!(one, run(2, true));
    assert_eq!(one, run(2, false));
    assert!(one.iter().all(|p| p.is_finite()));
    assert!(mean(&one).min_element() > 0.01, "{}", mean(&one));
}
