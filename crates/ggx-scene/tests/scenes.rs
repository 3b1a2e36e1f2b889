//! Every scene in `scenes/` loads, and each declares the features it is meant to exercise.

use std::path::{Path, PathBuf};

use ggx_scene::{Environment, Material, Scene, SceneFeatures, load_scene};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn load(name: &str) -> Scene {
    let path = scenes_dir().join(name);
    load_scene(&path).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn every_scene_file_loads() {
    let mut count = 0;
    for entry in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let scene = load_scene(&path).unwrap_or_else(|e| panic!("{e}"));
            assert!(!scene.mesh.triangles.is_empty(), "{}", path.display());
            assert!(scene.environment.is_some() || !scene.lights.is_empty(), "{} has no light", path.display());
            count += 1;
        }
    }
    assert!(count >= 6, "found only {count} scenes");
}

#[test]
fn cornell_box() {
    let s = load("cornell.toml");
    let f = s.features;
    assert!(f.area_lights && f.diffuse && f.conductors && f.shading_normals);
    assert!(!f.env_map && !f.constant_env && !f.plastics && !f.anisotropic && !f.emissive_only);
    assert_eq!((s.camera.resolution, s.integrator.spp), ([256, 256], 64));
    assert_eq!(s.lights.lights.len(), 1);
    assert!((s.lights.total_area() - 0.25).abs() < 1e-5);
    let alphas: Vec<f32> = s
        .materials
        .iter()
        .filter_map(|m| match m {
            Material::Conductor { alpha_x, .. } => Some(*alpha_x),
            _ => None,
        })
        .collect();
    for roughness in [0.05f32, 0.25, 0.6] {
        assert!(alphas.iter().any(|a| (a - roughness * roughness).abs() < 1e-6), "{alphas:?}");
    }
    let (lo, hi) = s.mesh.bounds().unwrap();
    assert!(
        (lo - glam::Vec3::new(-1.0, 0.0, -1.0)).length() < 1e-5
            && (hi - glam::Vec3::splat(1.0).with_y(2.0)).length() < 1e-5
    );
    // The light faces down into the box.
    let light = &s.mesh.triangles[s.lights.emitters[0].triangle as usize];
    assert!((light.geometric_normal() - -glam::Vec3::Y).length() < 1e-5);
}

#[test]
fn roughness_sweep() {
    let s = load("roughness-sweep.toml");
    let f = s.features;
    assert!(f.area_lights && f.env_map && f.conductors && f.diffuse && !f.anisotropic && !f.constant_env);
    let mut alphas: Vec<f32> = s
        .materials
        .iter()
        .filter_map(|m| if let Material::Conductor { alpha_x, .. } = m { Some(*alpha_x) } else { None })
        .collect();
    alphas.sort_by(f32::total_cmp);
    assert_eq!(alphas.len(), 7);
    assert!((alphas[0] - 0.01).abs() < 1e-6 && (alphas[6] - 1.0).abs() < 1e-6);
    for w in alphas.windows(2) {
        assert!((w[1] / w[0] - 100f32.powf(1.0 / 6.0)).abs() < 1e-3, "not log spaced: {alphas:?}");
    }
}

#[test]
fn anisotropic() {
    let f = load("anisotropic.toml").features;
    assert!(f.anisotropic && f.conductors && f.env_map && !f.area_lights && !f.diffuse);
}

#[test]
fn grazing() {
    let s = load("grazing.toml");
    let f = s.features;
    assert!(f.area_lights && f.env_map && f.conductors && !f.diffuse);
    // The view direction is nearly parallel to the plane.
    assert!(s.camera.forward.y.abs() < 0.02);
}

#[test]
fn furnace() {
    let s = load("furnace.toml");
    let expected = SceneFeatures {
        constant_env: true,
        diffuse: true,
        conductors: true,
        plastics: true,
        dielectrics: true,
        ..Default::default()
    };
    assert_eq!(s.features, expected);
    assert!(matches!(s.environment, Some(Environment::Constant(l)) if l == glam::Vec3::ONE));
    assert!(s.materials.iter().any(|m| matches!(m, Material::Diffuse { albedo } if *albedo == glam::Vec3::ONE)));
    assert!(
        s.materials.iter().any(|m| matches!(m, Material::Conductor { fresnel: ggx_scene::ConductorFresnel::One, .. }))
    );
    // Compensated by default; `--energy-compensation off` shows the loss.
    let dielectrics = s.materials.iter().filter(|m| matches!(m, Material::Dielectric { compensate: true, .. }));
    assert_eq!(dielectrics.count(), 2);
    assert!(s.materials.iter().all(|m| !matches!(
        m,
        Material::Conductor { compensate: false, .. }
            | Material::Plastic { compensate: false, .. }
            | Material::Dielectric { compensate: false, .. }
    )));
}

#[test]
fn glass() {
    let s = load("glass.toml");
    let f = s.features;
    assert!(f.dielectrics && f.area_lights && f.constant_env && f.diffuse && !f.conductors);
    let alphas: Vec<f32> = s
        .materials
        .iter()
        .filter_map(|m| match m {
            Material::Dielectric { alpha_x, ior, .. } if *ior == 1.5 => Some(*alpha_x),
            _ => None,
        })
        .collect();
    assert_eq!(alphas, [0.0, 0.02, 0.1, 0.3, 1.0]);
    let bunny = load("glass-bunny.toml");
    assert!(bunny.features.dielectrics && bunny.features.env_map && bunny.features.shading_normals);
    assert!(bunny.materials.iter().any(|m| matches!(m, Material::Dielectric { absorption, .. } if absorption.x > 0.0)));
}

#[test]
fn bunny() {
    let s = load("bunny.toml");
    let f = s.features;
    assert!(f.env_map && f.conductors && f.shading_normals && !f.area_lights && !f.constant_env);
    assert_eq!(s.integrator.spp, 512);
    assert_eq!(s.integrator.bsdf_sampling, ggx_scene::BsdfStrategy::Vndf);
    assert!(s.stats().triangles > 3600);
    let gold = s.material_index("gold").unwrap();
    assert!(
        matches!(s.materials[gold], Material::Conductor { alpha_x, alpha_y, .. } if alpha_x == 0.05 && alpha_y == 0.05)
    );
    let (_, hi) = s.mesh.bounds().unwrap();
    assert!(hi.y > 0.9 && hi.y < 1.0, "bunny height {}", hi.y);
}

#[test]
fn stats_and_summary() {
    let s = load("cornell.toml");
    let stats = s.stats();
    assert_eq!(stats.shapes, 9);
    assert_eq!(stats.lights, 1);
    assert_eq!(stats.emitters, 2);
    assert_eq!(stats.materials, 7);
    assert_eq!(stats.triangles, 6 * 2 + 3 * 20 * 256);
    assert!(stats.to_string().contains("triangles: 15372 (15360 with shading normals)"));
    assert_eq!(s.features.summary(), "area_lights, diffuse, conductors, shading_normals");
}

#[test]
fn empty_and_unlit_scenes_are_warned_about() {
    let parse = |text: &str| ggx_scene::parse_scene(text, "w.toml", std::path::Path::new(".")).unwrap();
    let camera = "[camera]\nposition = [0, 0, 5]\nlook_at = [0, 0, 0]\n";
    let env = "[environment]\ntype = \"constant\"\nradiance = [1, 1, 1]\n";
    let shape = "[materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n[[shapes]]\ntype = \"sphere\"\nmaterial = \"w\"\n";
    assert_eq!(parse(camera).warnings(), ["w.toml has no shapes: the image shows nothing: it is black"]);
    assert_eq!(
        parse(&format!("{camera}{env}")).warnings(),
        ["w.toml has no shapes: the image shows only the environment"]
    );
    let unlit = parse(&format!("{camera}{shape}")).warnings();
    assert_eq!(unlit.len(), 1);
    assert!(unlit[0].contains("nothing emits light") && unlit[0].contains("black"), "{unlit:?}");
    assert!(parse(&format!("{camera}{env}{shape}")).warnings().is_empty());
    assert!(load("cornell.toml").warnings().is_empty() && load("furnace.toml").warnings().is_empty());
}

/// The complete scene file in the workspace README parses, and is lit.
#[test]
fn the_readme_scene_file_is_valid() {
    let readme = std::fs::read_to_string(scenes_dir().join("../README.md")).unwrap();
    let after = &readme[readme.find("A complete scene file").expect("README has the example")..];
    let start = after.find("```toml\n").expect("a toml block") + "```toml\n".len();
    let text = &after[start..start + after[start..].find("```").expect("closed block")];
    let s = ggx_scene::parse_scene(text, "README.md", std::path::Path::new(".")).unwrap_or_else(|e| panic!("{e}"));
    assert!(s.features.dielectrics && s.features.constant_env && s.warnings().is_empty());
}
