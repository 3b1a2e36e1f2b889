//! Mutation testing of the glTF loader: numbers in the JSON set to hostile values (counts,
//! offsets, lengths, strides, indices, component types), bytes of a `.gltf` and of a GLB
//! flipped, cut, spliced and overwritten. The loader must return a scene within the limits
//! or an error that names the file; never panic, never allocate from an unchecked count. On
//! Linux every test runs again in a child process whose address space is capped at
//! [`fuzz_cases::ADDRESS_SPACE_CAP`], so an allocation sized by a header field aborts the child and fails
//! the test. `GGX_FUZZ_CASES` sets the number of cases per target (default [`DEFAULT_CASES`]).

mod fuzz_cases;
#[allow(dead_code)]
mod readers_support;

use std::path::{Path, PathBuf};

use ggx_scene::{GltfOptions, Limits, load_gltf_scene};
use proptest::prelude::*;
use readers_support::{mutate, mutation};

/// Cases per target when `GGX_FUZZ_CASES` is unset.
const DEFAULT_CASES: u32 = 64;

/// The limits the mutated files are loaded under.
const SMALL: Limits = Limits {
    max_scene_bytes: 1 << 20,
    max_mesh_bytes: 1 << 20,
    max_map_pixels: 1 << 16,
    max_triangles: 1 << 14,
    max_memory: 64 << 20,
};

fn cases() -> u32 {
    fuzz_cases::fuzz_cases(DEFAULT_CASES)
}

/// [`fuzz_cases::ran_capped`] for this binary.
fn ran_capped(name: &str) -> bool {
    fuzz_cases::ran_capped(name, "GGX_GLTF_FUZZ_CHILD")
}

fn corpus(name: &str) -> Vec<u8> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/gltf").join(name);
    std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn dir(name: &str) -> PathBuf {
    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf_fuzz").join(name);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Loads `bytes` as `path` under [`SMALL`]: a scene within the limits, or an error naming it.
fn check(path: &Path, bytes: &[u8]) -> Result<(), TestCaseError> {
    std::fs::write(path, bytes).unwrap();
    match load_gltf_scene(path, &SMALL, &GltfOptions::default()) {
        Ok(scene) => {
            prop_assert!(scene.mesh.triangles.len() as u64 <= SMALL.max_triangles);
            prop_assert!(scene.mesh.triangles.iter().all(|t| t.vertices().iter().all(|v| v.is_finite())));
            let parallel = |n: usize| n == 0 || n == scene.mesh.shading_normals.len();
            prop_assert!(parallel(scene.mesh.uvs.len()) && parallel(scene.mesh.tangents.len()));
        }
        Err(e) => {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            prop_assert!(e.to_string().contains(&name), "{e}");
        }
    }
    Ok(())
}

/// Every number in `v`, as JSON pointers.
fn numbers(v: &serde_json::Value, at: String, out: &mut Vec<String>) {
    match v {
        serde_json::Value::Number(_) => out.push(at),
        serde_json::Value::Array(a) => a.iter().enumerate().for_each(|(i, x)| numbers(x, format!("{at}/{i}"), out)),
        serde_json::Value::Object(o) => o.iter().for_each(|(k, x)| numbers(x, format!("{at}/{k}"), out)),
        _ => {}
    }
}

fn hostile_number() -> impl Strategy<Value = serde_json::Value> {
    prop_oneof![
        Just(serde_json::json!(0)),
        Just(serde_json::json!(1)),
        Just(serde_json::json!(-1)),
        Just(serde_json::json!(3)),
        Just(serde_json::json!(255)),
        Just(serde_json::json!(65535)),
        Just(serde_json::json!(u32::MAX)),
        Just(serde_json::json!(i64::MAX)),
        Just(serde_json::json!(1u64 << 53)),
        Just(serde_json::json!(1e308)),
        Just(serde_json::json!(-0.0)),
        Just(serde_json::json!(5121)),
        Just(serde_json::json!(5126)),
        (0u64..100_000).prop_map(|n| serde_json::json!(n)),
    ]
}

#[test]
fn hostile_numbers_in_the_json_are_loaded_or_refused() {
    if ran_capped("hostile_numbers_in_the_json_are_loaded_or_refused") {
        return;
    }
    let out = dir("numbers");
    // BoxTextured with its texture as a normal map too: MikkTSpace runs on the mutated mesh.
    let mut normal_mapped: serde_json::Value = serde_json::from_slice(&corpus("BoxTextured.gltf")).unwrap();
    normal_mapped["materials"][0]["normalTexture"] = serde_json::json!({ "index": 0 });
    let files =
        ["BoxTextured.gltf", "SimpleSparseAccessor.gltf", "TextureCoordinateTest.gltf", "Cameras.gltf", "normal.gltf"];
    for file in files {
        let json: serde_json::Value = match file {
            "normal.gltf" => normal_mapped.clone(),
            _ => serde_json::from_slice(&corpus(file)).unwrap(),
        };
        let mut pointers = Vec::new();
        numbers(&json, String::new(), &mut pointers);
        let path = out.join(file);
        let config = ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() };
        proptest!(config, |(edits in proptest::collection::vec((any::<prop::sample::Index>(), hostile_number()), 1..4))| {
            let mut j = json.clone();
            for (i, value) in &edits {
                if let Some(slot) = j.pointer_mut(&pointers[i.index(pointers.len())]) {
                    *slot = value.clone();
                }
            }
            check(&path, &serde_json::to_vec(&j).unwrap())?;
        });
    }
}

#[test]
fn mutated_bytes_of_gltf_and_glb_files_are_loaded_or_refused() {
    if ran_capped("mutated_bytes_of_gltf_and_glb_files_are_loaded_or_refused") {
        return;
    }
    let out = dir("bytes");
    for file in ["trimesh-export.glb", "SimpleMeshes.gltf", "BoxTextured.gltf"] {
        let valid = corpus(file);
        let path = out.join(file);
        let config = ProptestConfig { cases: cases(), failure_persistence: None, ..ProptestConfig::default() };
        proptest!(config, |(mutations in proptest::collection::vec(mutation(), 1..4))| {
            let mut bytes = valid.clone();
            mutate(&mut bytes, &mutations);
            check(&path, &bytes)?;
        });
    }
}

#[test]
fn glb_chunk_lengths_are_checked() {
    // The JSON chunk's length set past the end of the file, to 0, and to u32::MAX.
    let valid = corpus("trimesh-export.glb");
    let path = dir("chunks").join("chunk.glb");
    for len in [0u32, 1, u32::MAX, valid.len() as u32] {
        let mut bytes = valid.clone();
        bytes[12..16].copy_from_slice(&len.to_le_bytes());
        std::fs::write(&path, &bytes).unwrap();
        let e = load_gltf_scene(&path, &SMALL, &GltfOptions::default()).unwrap_err();
        assert!(e.to_string().contains("chunk.glb"), "{e}");
    }
}
