//! glTF 2.0 loading: every file of the corpus in `scenes/gltf/` (Khronos glTF-Sample-Assets
//! and a GLB written by trimesh, `scenes/gltf/LICENSES.md`), glTF shapes in TOML scenes, TOML
//! textures, and the errors a broken file gets.

use std::path::{Path, PathBuf};

use ggx_scene::{
    ErrorKind, GltfEnvironment, GltfOptions, Limits, Material, SceneError, load_gltf_scene, load_scene, parse_scene,
};

fn corpus(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/gltf").join(name)
}

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn load(name: &str) -> ggx_scene::Scene {
    load_gltf_scene(&corpus(name), &Limits::default(), &GltfOptions::default())
        .unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn metal_rough(scene: &ggx_scene::Scene) -> Vec<ggx_scene::MetalRough> {
    scene
        .materials
        .iter()
        .filter_map(|m| match m {
            Material::MetalRough(r) => Some(*r),
            _ => None,
        })
        .collect()
}

#[test]
fn every_corpus_file_loads_with_the_expected_content() {
    // (file, triangles, materials, textured materials, cameras)
    let expected = [
        ("Box.gltf", 12, 1, 0, 0),
        ("BoxTextured.gltf", 12, 1, 1, 0),
        ("BoxVertexColors.gltf", 12, 1, 0, 0),
        ("Cameras.gltf", 2, 1, 0, 1),
        ("OrientationTest.gltf", 524, 7, 0, 0),
        ("SimpleMeshes.gltf", 2, 1, 0, 0),
        ("SimpleSparseAccessor.gltf", 12, 1, 0, 0),
        ("TextureCoordinateTest.gltf", 10, 5, 4, 0),
        ("TriangleWithoutIndices.gltf", 1, 1, 0, 0),
        ("trimesh-export.glb", 0, 0, 0, 0),
    ];
    for (file, triangles, materials, textured, cameras) in expected {
        let s = load(file);
        if file.ends_with(".glb") {
            assert!(!s.mesh.triangles.is_empty(), "{file}");
            continue;
        }
        assert_eq!(s.mesh.triangles.len(), triangles, "{file} triangles");
        assert_eq!(s.materials.len(), materials, "{file} materials");
        let t = metal_rough(&s).iter().filter(|m| m.is_textured()).count();
        assert_eq!(t, textured, "{file} textured materials");
        assert_eq!(s.cameras.len(), cameras, "{file} cameras");
        assert!(s.mesh.triangles.iter().all(|t| t.area().is_finite()), "{file}");
        // No file brings light: the default environment, said in a warning.
        assert!(s.environment.is_some() && s.features.constant_env, "{file}");
        assert!(s.warnings().iter().any(|w| w.contains("uniform white environment")), "{file}");
    }
}

#[test]
fn the_node_hierarchy_and_sparse_accessors_place_the_vertices() {
    // SimpleMeshes: one mesh instanced by two nodes, the second translated by x + 1.
    let s = load("SimpleMeshes.gltf");
    let (lo, hi) = s.mesh.bounds().unwrap();
    assert_eq!((lo.x, hi.x), (0.0, 2.0), "{lo} {hi}");
    // SimpleSparseAccessor: the sparse substitution lifts 8 vertices to y = 4 (base y <= 2).
    let s = load("SimpleSparseAccessor.gltf");
    let (_, hi) = s.mesh.bounds().unwrap();
    assert_eq!(hi.y, 4.0);
}

#[test]
fn textures_are_decoded_once_and_shared() {
    let s = load("BoxTextured.gltf");
    assert_eq!(s.textures.infos.len(), 1);
    let m = metal_rough(&s)[0];
    assert!(m.base_color_texture.is_some() && !m.normal_texture.is_some());
    assert_eq!(s.mesh.uvs.len(), s.mesh.shading_normals.len(), "textured triangles carry coordinates");
    // TextureCoordinateTest: four materials over one image.
    let s = load("TextureCoordinateTest.gltf");
    let images: std::collections::HashSet<u32> = s.textures.infos.iter().map(|i| i.offset).collect();
    assert_eq!(images.len(), 1, "{:?}", s.textures.infos);
}

#[test]
fn a_normal_map_without_tangents_gets_mikktspace_tangents() {
    let mut json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(corpus("BoxTextured.gltf")).unwrap()).unwrap();
    json["materials"][0]["normalTexture"] = serde_json::json!({ "index": 0, "scale": 0.5 });
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf_mikktspace");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("normal.gltf");
    std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
    let s = load_gltf_scene(&path, &Limits::default(), &GltfOptions::default()).unwrap();
    assert_eq!(s.mesh.tangents.len(), 12, "one record per triangle");
    for (t, n) in s.mesh.tangents.iter().zip(&s.mesh.shading_normals) {
        for (tv, nv) in t.tangents.iter().zip(&n.normals) {
            let (tv3, nv3) = (glam::Vec3::from_slice(&tv[..3]), glam::Vec3::from_slice(&nv[..3]));
            assert!(
                tv[3].abs() == 1.0 && (tv3.length() - 1.0).abs() < 1e-4 && tv3.dot(nv3).abs() < 1e-4,
                "{tv:?} {nv:?}"
            );
        }
    }
    assert_eq!(metal_rough(&s)[0].normal_scale, 0.5);
}

#[test]
fn cameras_by_name_or_framing_and_the_environment_option() {
    let s = load("Cameras.gltf");
    assert_eq!(s.camera.position.to_array(), [0.5, 0.5, 3.0]);
    assert_eq!(s.camera.resolution, [640, 640], "the file's aspect ratio 1.0");
    let e = load_gltf_scene(
        &corpus("Cameras.gltf"),
        &Limits::default(),
        &GltfOptions { camera: Some("nope".into()), environment: None },
    )
    .unwrap_err();
    assert!(e.to_string().contains("no camera named \"nope\""), "{e}");
    // Without a camera: one that frames the bounds, looking at their centre.
    let s = load("Box.gltf");
    let (lo, hi) = s.mesh.bounds().unwrap();
    let centre = 0.5 * (lo + hi);
    let to_centre = (centre - s.camera.position).normalize();
    assert!(to_centre.dot(s.camera.forward) > 0.9999, "{to_centre} {}", s.camera.forward);
    let options =
        GltfOptions { camera: None, environment: Some(GltfEnvironment::Constant(glam::Vec3::new(0.5, 0.25, 0.0))) };
    let s = load_gltf_scene(&corpus("Box.gltf"), &Limits::default(), &options).unwrap();
    assert!(matches!(s.environment, Some(ggx_scene::Environment::Constant(c)) if c.x == 0.5));
    assert!(s.warnings().iter().all(|w| !w.contains("uniform white")));
}

#[test]
fn a_gltf_shape_in_a_toml_scene() {
    let text = r#"
        [camera]
        position = [0, 1, 4]
        look_at = [0, 0, 0]
        [materials.red]
        type = "diffuse"
        albedo = [0.8, 0.1, 0.1]
        [[shapes]]
        type = "gltf"
        file = "gltf/BoxTextured.gltf"
        transform = { translate = [10, 0, 0] }
        [[shapes]]
        type = "gltf"
        file = "gltf/Box.gltf"
        material = "red"
    "#;
    let s = parse_scene(text, "t.toml", &scenes_dir()).unwrap();
    assert_eq!(s.mesh.triangles.len(), 24);
    assert_eq!(s.material_names, ["red", "gltf/BoxTextured.gltf#Texture"]);
    // The first shape is translated, the second keeps its own material override.
    assert!(s.mesh.triangles[..12].iter().all(|t| t.v0[0] > 9.0 && t.material == 1));
    assert!(s.mesh.triangles[12..].iter().all(|t| t.material == 0));
    assert!(s.features.textures && s.features.metal_rough);
    // Every other shape type still needs its material.
    let text = "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n[[shapes]]\ntype = \"box\"\n";
    let e = parse_scene(text, "t.toml", &scenes_dir()).unwrap_err();
    assert!(e.to_string().contains("shapes[0].material: `material` is required"), "{e}");
}

#[test]
fn toml_textures_and_their_errors() {
    let s = load_scene(&scenes_dir().join("textured.toml")).unwrap();
    assert!(s.features.textures);
    // Three image files plus the glTF's, one shared by two slots with other samplers.
    assert!(s.textures.infos.len() >= 5, "{:?}", s.textures.infos);
    assert!(s.inputs.iter().any(|p| p.ends_with("textures/checker.png")));
    let memory = ggx_scene::estimate_memory(&s);
    assert!(memory.texture_bytes > s.textures.bytes() && memory.to_string().contains(", textures "), "{memory}");
    let floor = &s.materials[s.material_index("floor").unwrap()];
    assert!(matches!(floor, Material::MetalRough(m) if m.metallic == 0.0 && m.specular == 0.0));
    let lights: Vec<_> = s.lights.lights.iter().map(|l| l.material).collect();
    assert!(lights.contains(&(s.material_index("glow").unwrap() as u32)), "an emissive metal-rough is a light");

    let scene = |material: &str| {
        format!(
            "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n[materials.m]\n{material}\n\
             [[shapes]]\ntype = \"rectangle\"\nmaterial = \"m\"\n"
        )
    };
    let err = |material: &str| -> SceneError { parse_scene(&scene(material), "t.toml", &scenes_dir()).unwrap_err() };
    let e = err("type = \"plastic\"\nroughness = 0.1\nalbedo = { texture = \"textures/checker.png\" }");
    assert!(e.to_string().contains("materials.m.albedo: textures apply to"), "{e}");
    let e = err("type = \"conductor\"\npreset = \"gold\"\nroughness = { texture = \"textures/roughmetal.png\" }");
    assert!(e.to_string().contains("materials.m.roughness: textures apply to"), "{e}");
    let e = err("type = \"diffuse\"\nalbedo = { texture = \"textures/missing.png\" }");
    assert_eq!(e.kind(), ErrorKind::File);
    assert!(e.to_string().contains("texture not found") && e.to_string().contains("missing.png"), "{e}");
    let e = err("type = \"diffuse\"\nalbedo = { texture = \"make_textures.py\" }");
    assert!(e.to_string().starts_with("t.toml:"), "{e}");
    let e = err("type = \"metal-rough\"\nalpha = 0.1");
    assert!(e.to_string().contains("alpha: does not apply to type \"metal-rough\""), "{e}");
    let e = err("type = \"metal-rough\"\nroughness = [0.1, 0.2]");
    assert!(e.to_string().contains("isotropic"), "{e}");
    let e = err("type = \"diffuse\"\nalbedo = [1, 1, 1]\nnormal_scale = 2");
    assert!(e.to_string().contains("`normal_scale` needs `normal_map`"), "{e}");
    let e = err("type = \"diffuse\"\nalbedo = { texture = \"textures/checker.png\", channel = \"q\" }");
    assert_eq!(e.kind(), ErrorKind::Schema, "{e}");
    let e = err("type = \"metal-rough\"\nmetallic = { texture = \"textures/checker.png\", rotation = 1e39 }");
    assert_eq!(e.kind(), ErrorKind::NonFinite, "{e}");
    let e = err("type = \"metal-rough\"\nclearcoat_roughness = 0.2");
    assert!(e.to_string().contains("materials.m.clearcoat_roughness: `clearcoat_roughness` needs `clearcoat`"), "{e}");
    let e = err("type = \"metal-rough\"\nclearcoat = 1.5");
    assert!(e.to_string().contains("materials.m.clearcoat"), "{e}");
    let e = err("type = \"diffuse\"\nalbedo = [1, 1, 1]\nclearcoat = 0.5");
    assert!(e.to_string().contains("clearcoat: does not apply to type \"diffuse\""), "{e}");
    let s = parse_scene(
        &scene("type = \"metal-rough\"\nclearcoat = 0.5\nclearcoat_roughness = 0.3"),
        "t.toml",
        &scenes_dir(),
    )
    .unwrap();
    let Material::MetalRough(m) = s.materials[0] else { panic!("{:?}", s.materials[0]) };
    assert_eq!((m.clearcoat, m.clearcoat_roughness), (0.5, 0.3));
}

/// An edit of a glTF's JSON.
type Edit = fn(&mut serde_json::Value);

/// A minimal glTF (one triangle) with `edit` applied to its JSON, written to `dir/name`.
fn broken(name: &str, edit: impl Fn(&mut serde_json::Value)) -> Result<ggx_scene::Scene, SceneError> {
    use base64::Engine as _;
    let mut bin = Vec::new();
    for v in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
        v.iter().for_each(|c| bin.extend_from_slice(&c.to_le_bytes()));
    }
    for i in [0u16, 1, 2, 7] {
        bin.extend_from_slice(&i.to_le_bytes());
    }
    let uri =
        format!("data:application/octet-stream;base64,{}", base64::engine::general_purpose::STANDARD.encode(&bin));
    let mut json = serde_json::json!({
        "asset": { "version": "2.0" },
        "scene": 0,
        "scenes": [{ "nodes": [0] }],
        "nodes": [{ "mesh": 0 }],
        "meshes": [{ "primitives": [{ "attributes": { "POSITION": 0 }, "indices": 1 }] }],
        "accessors": [
            { "bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0] },
            { "bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR" }
        ],
        "bufferViews": [
            { "buffer": 0, "byteOffset": 0, "byteLength": 36 },
            { "buffer": 0, "byteOffset": 36, "byteLength": 8 }
        ],
        "buffers": [{ "byteLength": 44, "uri": uri }]
    });
    edit(&mut json);
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf_broken");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, serde_json::to_vec(&json).unwrap()).unwrap();
    load_gltf_scene(&path, &Limits::default(), &GltfOptions::default())
}

#[test]
fn broken_files_get_errors_that_name_the_file_and_the_json_path() {
    assert_eq!(broken("ok.gltf", |_| {}).unwrap().mesh.triangles.len(), 1);
    let cases: [(&str, Edit, &str); 10] = [
        ("index.gltf", |j| j["accessors"][1]["count"] = 4.into(), "accessors[1] (indices): index 7 at position 3"),
        ("range.gltf", |j| j["bufferViews"][0]["byteLength"] = 100.into(), "lies outside buffer 0"),
        (
            "count.gltf",
            |j| j["accessors"][0]["count"] = 4.into(),
            "4 elements of 12 bytes every 12 from byte 0 do not fit in bufferViews[0]",
        ),
        ("huge.gltf", |j| j["accessors"][0]["count"] = 4_000_000_000u64.into(), "count 4000000000 is over the"),
        ("zero.gltf", |j| j["accessors"][0]["count"] = 0.into(), "count is 0"),
        ("type.gltf", |j| j["accessors"][0]["type"] = "VEC2".into(), "POSITION: accessors[0]: type Vec2"),
        (
            "draco.gltf",
            |j| j["extensionsRequired"] = serde_json::json!(["KHR_draco_mesh_compression"]),
            "extensionsRequired: KHR_draco_mesh_compression is not supported",
        ),
        ("buffer.gltf", |j| j["buffers"][0]["uri"] = "missing.bin".into(), "missing.bin"),
        ("short.gltf", |j| j["buffers"][0]["byteLength"] = 4000.into(), "where byteLength is 4000"),
        ("stride.gltf", |j| j["bufferViews"][0]["byteStride"] = 8.into(), "byteStride 8 is smaller"),
    ];
    for (name, edit, want) in cases {
        let e = broken(name, edit).unwrap_err().to_string();
        assert!(e.contains(name), "{name}: {e}");
        assert!(e.contains(want), "{name}: expected {want:?} in {e}");
        assert!(e.contains("meshes[0].primitives[0]") || !want.starts_with("accessors"), "{name}: {e}");
    }
    // Transmission: a rough dielectric with an absorbing inside under KHR_materials_volume,
    // else a thin sheet.
    let glass = |volume: bool| {
        move |j: &mut serde_json::Value| {
            let mut ext = serde_json::json!({ "KHR_materials_transmission": { "transmissionFactor": 1.0 } });
            if volume {
                ext["KHR_materials_volume"] = serde_json::json!({
                    "thicknessFactor": 1.0, "attenuationDistance": 2.0, "attenuationColor": [0.5, 1.0, 1.0]
                });
            }
            j["materials"] = serde_json::json!([{
                "pbrMetallicRoughness": { "roughnessFactor": 0.5, "baseColorFactor": [1, 0.5, 1, 1] },
                "extensions": ext
            }]);
            j["meshes"][0]["primitives"][0]["material"] = 0.into();
            j["extensionsUsed"] = serde_json::json!(["KHR_materials_transmission", "KHR_materials_volume"]);
        }
    };
    let s = broken("glass.gltf", glass(true)).unwrap();
    let Material::Dielectric { alpha_x, thin, absorption, transmittance, ior, .. } = s.materials[0] else {
        panic!("{:?}", s.materials[0]);
    };
    assert_eq!((alpha_x, thin, ior, transmittance.y), (0.25, false, 1.5, 0.5));
    assert!((absorption.x - std::f32::consts::LN_2 / 2.0).abs() < 1e-6 && absorption.y == 0.0, "{absorption}");
    let s = broken("sheet.gltf", glass(false)).unwrap();
    assert!(matches!(s.materials[0], Material::Dielectric { thin: true, .. }), "{:?}", s.materials[0]);
    assert!(s.warnings().iter().any(|w| w.contains("smooth thin sheet")), "{:?}", s.warnings());
    // Anisotropy: strength and rotation from the extension's JSON.
    let s = broken("aniso.gltf", |j| {
        j["materials"] = serde_json::json!([{
            "extensions": { "KHR_materials_anisotropy": { "anisotropyStrength": 0.6, "anisotropyRotation": 1.25 } }
        }]);
        j["meshes"][0]["primitives"][0]["material"] = 0.into();
        j["extensionsUsed"] = serde_json::json!(["KHR_materials_anisotropy"]);
    })
    .unwrap();
    let Material::MetalRough(m) = s.materials[0] else { panic!("{:?}", s.materials[0]) };
    assert_eq!((m.anisotropy, m.anisotropy_rotation), (0.6, 1.25));
    assert!(m.is_textured() && s.features.textures, "anisotropy follows the mesh's tangents at each point");
    assert!(!s.warnings().iter().any(|w| w.contains("ignores the extensions")), "{:?}", s.warnings());
    // Clearcoat: factor and roughness factor from the extension's JSON; textures ignored, said.
    let s = broken("coat.gltf", |j| {
        j["materials"] = serde_json::json!([{
            "extensions": { "KHR_materials_clearcoat": {
                "clearcoatFactor": 0.75, "clearcoatRoughnessFactor": 0.25, "clearcoatTexture": { "index": 0 }
            } }
        }]);
        j["meshes"][0]["primitives"][0]["material"] = 0.into();
        j["extensionsUsed"] = serde_json::json!(["KHR_materials_clearcoat"]);
        // Required: ggx reads it although gltf-json has no feature for it.
        j["extensionsRequired"] = serde_json::json!(["KHR_materials_clearcoat"]);
    })
    .unwrap();
    let Material::MetalRough(m) = s.materials[0] else { panic!("{:?}", s.materials[0]) };
    assert_eq!((m.clearcoat, m.clearcoat_roughness), (0.75, 0.25));
    assert!(!m.is_textured(), "a coat by its factors is the same at every point");
    let w = s.warnings();
    assert!(w.iter().any(|w| w.contains("clearcoat textures are ignored")), "{w:?}");
    assert!(!w.iter().any(|w| w.contains("ignores the extensions")), "{w:?}");
    // Out-of-range factors are clamped, NaN-free.
    let s = broken("coat2.gltf", |j| {
        j["materials"] = serde_json::json!([{
            "extensions": { "KHR_materials_clearcoat": { "clearcoatFactor": 7.0, "clearcoatRoughnessFactor": -1.0 } }
        }]);
        j["meshes"][0]["primitives"][0]["material"] = 0.into();
    })
    .unwrap();
    let Material::MetalRough(m) = s.materials[0] else { panic!("{:?}", s.materials[0]) };
    assert_eq!((m.clearcoat, m.clearcoat_roughness), (1.0, 0.0));
    // Not glTF at all.
    let e = broken("json.gltf", |j| *j = serde_json::json!([1, 2])).unwrap_err().to_string();
    assert!(e.contains("json.gltf: invalid glTF"), "{e}");
}
