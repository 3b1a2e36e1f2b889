//! `type = "dielectric"` and `energy_compensation`: what parses to what, and every error
//! naming the file, line:column and field.

use std::path::Path;

use ggx_scene::{ErrorKind, Material, Scene, parse_scene};
use glam::Vec3;

const FILE: &str = "scenes/glass.toml";
const CAMERA: &str = "[camera]\nposition = [0, 1, 3.5]\nlook_at = [0, 1, 0]\n";

fn scene(material: &str, integrator: &str) -> String {
    format!("{CAMERA}{integrator}\n[materials.m]\n{material}\n\n[[shapes]]\ntype = \"sphere\"\nmaterial = \"m\"\n")
}

fn parse(material: &str) -> Scene {
    parse_scene(&scene(material, ""), FILE, Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

#[track_caller]
fn error(material: &str, needle: &str, field: &str, kind: ErrorKind, message: &str) {
    let text = scene(material, "");
    let e = match parse_scene(&text, FILE, Path::new(".")) {
        Ok(_) => panic!("expected an error for\n{material}"),
        Err(e) => e,
    };
    let offset = text.find(needle).unwrap_or_else(|| panic!("`{needle}` not in the text"));
    let line = text[..offset].matches('\n').count() + 1;
    let column = offset - text[..offset].rfind('\n').map_or(0, |i| i + 1) + 1;
    let shown = e.to_string();
    assert!(shown.starts_with(&format!("{FILE}:{line}:{column}: {field}: ")), "{shown}");
    assert!(shown.contains(message), "`{message}` not in `{shown}`");
    assert_eq!(e.kind(), kind, "{shown}");
}

#[test]
fn a_bare_dielectric_is_smooth_clear_compensated_glass() {
    let s = parse("type = \"dielectric\"");
    let want = Material::Dielectric {
        alpha_x: 0.0,
        alpha_y: 0.0,
        ior: 1.5,
        transmittance: Vec3::ONE,
        absorption: Vec3::ZERO,
        thin: false,
        compensate: true,
    };
    assert_eq!(s.materials, [want]);
    assert!(s.features.dielectrics && !s.features.plastics);
}

#[test]
fn every_key_is_read() {
    let s = parse(
        "type = \"dielectric\"\npreset = \"diamond\"\nroughness = [0.5, 0.3]\ntransmittance = [1, 0.5, 0.25]\n\
         absorption = [0.1, 0.2, 0.3]\nenergy_compensation = false",
    );
    let Material::Dielectric { alpha_x, alpha_y, ior, transmittance, absorption, thin, compensate } = s.materials[0]
    else {
        panic!("{:?}", s.materials[0]);
    };
    assert_eq!((alpha_x, alpha_y, ior, thin, compensate), (0.25, 0.09, 2.42, false, false));
    assert_eq!((transmittance, absorption), (Vec3::new(1.0, 0.5, 0.25), Vec3::new(0.1, 0.2, 0.3)));
    assert!(s.features.anisotropic);
    assert_eq!(
        parse("type = \"dielectric\"\npreset = \"water\"").materials[0],
        parse("type = \"dielectric\"\nior = 1.33").materials[0]
    );
    let thin = parse("type = \"dielectric\"\nthin = true\ntransmittance = [0.9, 0.9, 0.9]");
    assert!(matches!(thin.materials[0], Material::Dielectric { thin: true, .. }));
}

#[test]
fn ior_outside_the_tables_or_one_is_refused() {
    error(
        "type = \"dielectric\"\nior = 3.5",
        "3.5\n",
        "materials.m.ior",
        ErrorKind::OutOfRange,
        "must be in [0.33333334, 3]",
    );
    error("type = \"dielectric\"\nior = 1.0", "1.0", "materials.m.ior", ErrorKind::OutOfRange, "invisible");
    error("type = \"dielectric\"\nior = nan", "nan", "materials.m.ior", ErrorKind::NonFinite, "finite");
    // Inverse indices (an air bubble in water, normals pointing into the water) are fine.
    assert!(matches!(parse("type = \"dielectric\"\nior = 0.75").materials[0], Material::Dielectric { ior: 0.75, .. }));
}

#[test]
fn presets_belong_to_their_type() {
    let m = "type = \"dielectric\"\npreset = \"gold\"";
    error(m, "\"gold\"", "materials.m.preset", ErrorKind::Conflict, "conductor preset; dielectrics take glass (1.5)");
    let m = "type = \"conductor\"\nalpha = 0.1\npreset = \"glass\"";
    error(m, "\"glass\"", "materials.m.preset", ErrorKind::Conflict, "dielectric preset; conductors take gold");
    let m = "type = \"dielectric\"\npreset = \"glass\"\nior = 1.4";
    error(m, "\"glass\"", "materials.m.preset", ErrorKind::Conflict, "either `ior` or `preset`");
    let m = "type = \"dielectric\"\npreset = \"quartz\"";
    error(m, "\"quartz\"", "materials.m.preset", ErrorKind::Schema, "unknown variant");
}

#[test]
fn thin_sheets_are_smooth_and_hollow() {
    let m = "type = \"dielectric\"\nthin = true\nroughness = 0.2";
    error(m, "0.2", "materials.m.roughness", ErrorKind::Conflict, "a thin sheet is smooth");
    let m = "type = \"dielectric\"\nthin = true\nabsorption = [1, 0, 0]";
    error(m, "[1, 0, 0]", "materials.m.absorption", ErrorKind::Conflict, "no interior");
    // Explicit zeros say nothing that conflicts.
    parse("type = \"dielectric\"\nthin = true\nalpha = 0\nabsorption = [0, 0, 0]");
}

#[test]
fn dielectric_values_are_checked() {
    let m = "type = \"dielectric\"\ntransmittance = [1, 1.5, 1]";
    error(m, "[1, 1.5", "materials.m.transmittance", ErrorKind::OutOfRange, "must be in [0, 1], got 1.5");
    let m = "type = \"dielectric\"\nabsorption = [0, -1, 0]";
    error(m, "[0, -1", "materials.m.absorption", ErrorKind::OutOfRange, "must be >= 0, got -1");
    let m = "type = \"dielectric\"\nalbedo = [1, 1, 1]";
    error(m, "[1, 1, 1]", "materials.m.albedo", ErrorKind::Conflict, "does not apply to type \"dielectric\"");
    let m = "type = \"diffuse\"\nalbedo = [1, 1, 1]\nenergy_compensation = true";
    error(m, "true", "materials.m.energy_compensation", ErrorKind::Conflict, "does not apply to type \"diffuse\"");
    let m = "type = \"dielectric\"\nthin = 1";
    error(m, "1\n", "materials.m.thin", ErrorKind::Schema, "invalid type");
}

#[test]
fn the_integrator_overrides_every_material() {
    let conductor = "type = \"conductor\"\nalpha = 0.5\npreset = \"ideal\"\nenergy_compensation = true";
    let off = parse_scene(&scene(conductor, "[integrator]\nenergy_compensation = false\n"), FILE, Path::new("."))
        .unwrap_or_else(|e| panic!("{e}"));
    assert!(matches!(off.materials[0], Material::Conductor { compensate: false, .. }));
    assert_eq!(off.integrator.energy_compensation, Some(false));
    let mut on = parse("type = \"plastic\"\nalpha = 0.5\nalbedo = [1, 1, 1]\nenergy_compensation = false");
    assert!(matches!(on.materials[0], Material::Plastic { compensate: false, .. }));
    on.set_energy_compensation(true);
    assert!(matches!(on.materials[0], Material::Plastic { compensate: true, .. }));
    assert!(matches!(parse(conductor).materials[0], Material::Conductor { compensate: true, .. }));
}
