//! `ggx export --format mitsuba`: a loaded ggx scene as a Mitsuba 3 scene file (XML version
//! 3.0.0) with its meshes and environment map beside it, so that both renderers see the same
//! scene.
//!
//! What carries over one to one:
//!
//! * **Geometry**: the exact world-space triangles ggx renders (spheres, boxes and disks are
//!   already tessellated), one PLY (or OBJ) per material and shading mode, with ggx's per-corner
//!   shading normals where it has them; flat meshes are marked `face_normals` so that Mitsuba
//!   does not smooth them ([`mesh`]).
//! * **Materials**: diffuse, conductors with `eta`/`k` or F = 1 (rough, anisotropic or
//!   smooth), emitters; the rest is refused by name ([`material`]).
//! * **Environment**: constant, or a map resampled onto Mitsuba's grid and axes ([`envmap`]).
//! * **Camera**: pinhole, `fov_axis = "y"` (Mitsuba's `fov` is horizontal by default), box
//!   pixel filter as ggx's uniform jitter within the pixel.
//! * **Integrator**: `path` with `max_depth = ggx max_depth + 1` (Mitsuba counts path
//!   segments, ggx bounces) and Russian roulette from the same depth, or never when ggx's is
//!   off. Both use MIS of light and BSDF sampling; Mitsuba's sampler is `independent` (ggx's
//!   Owen-scrambled Sobol' has no exact twin), seeded with ggx's seed.

pub mod envmap;
pub mod material;
pub mod mesh;
pub mod xml;

use ggx_film::Vec3;
use ggx_scene::{Environment, Material, Scene};

use self::material::{NoTwin, rgb};
use self::xml::Xml;

/// How meshes are written.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeshFormat {
    /// Binary little-endian PLY (compact; floats bit for bit).
    Ply,
    /// Wavefront OBJ (text; shortest round-trip decimals, also bit for bit).
    Obj,
}

impl MeshFormat {
    /// The file extension, also Mitsuba's shape plugin name.
    pub fn extension(self) -> &'static str {
        match self {
            Self::Ply => "ply",
            Self::Obj => "obj",
        }
    }
}

/// Export settings.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct ExportOptions {
    /// Stem of the side files' names (`<stem>-<n>-<material>.ply`, `<stem>-envmap.exr`),
    /// normally the XML file's stem.
    pub stem: String,
    /// Mesh file format.
    pub mesh_format: MeshFormat,
    /// Grid points per ggx texel in the resampled environment map (see [`envmap::resample`]).
    pub env_upsample: u32,
    /// The scene file's name, for the header comment.
    pub source: String,
}

/// A file written beside the XML, named relative to it.
#[derive(Clone, Debug, PartialEq)]
pub struct SideFile {
    /// File name (no directory).
    pub name: String,
    /// What goes into it.
    pub content: SideContent,
}

/// The content of a [`SideFile`].
#[derive(Clone, Debug, PartialEq)]
pub enum SideContent {
    /// Bytes (a mesh).
    Bytes(Vec<u8>),
    /// A linear RGB image written as EXR (the environment map).
    Image {
        /// Width.
        width: u32,
        /// Height.
        height: u32,
        /// Row-major pixels, top row first.
        pixels: Vec<Vec3>,
    },
}

/// An exported scene: the XML text and the files it references.
#[derive(Clone, Debug, PartialEq)]
pub struct Export {
    /// The Mitsuba scene file.
    pub xml: String,
    /// Meshes and environment map, to be written before the XML.
    pub files: Vec<SideFile>,
    /// Materials left out because no triangle uses them.
    pub unused_materials: Vec<String>,
}

/// `name` with every character outside `[A-Za-z0-9_-]` replaced by `_` (at most 40 kept), for
/// file names derived from material names.
pub fn file_safe(name: &str) -> String {
    let s: String = name
        .chars()
        .take(40)
        .map(|c| if c.is_ascii_alphanumeric() || c == '-' || c == '_' { c } else { '_' })
        .collect();
    if s.is_empty() { "material".to_owned() } else { s }
}

/// `x, y, z` for Mitsuba's point and vector attributes.
fn xyz(v: Vec3) -> String {
    format!("{}, {}, {}", v.x, v.y, v.z)
}

/// Exports `scene` (its current frame, resolution, spp and seed) as a Mitsuba 3 scene; refuses
/// the first used material without a one-to-one twin.
pub fn export(scene: &Scene, options: &ExportOptions) -> Result<Export, NoTwin> {
    let groups = mesh::groups(scene);
    let mut used = vec![false; scene.materials.len()];
    for g in &groups {
        if let Some(u) = used.get_mut(g.material) {
            *u = true;
        }
    }
    let name_of = |i: usize| scene.material_names.get(i).map_or_else(|| format!("material{i}"), Clone::clone);
    for (i, m) in scene.materials.iter().enumerate().filter(|(i, _)| used[*i]) {
        material::check(&name_of(i), m)?;
    }
    let unused_materials = (0..scene.materials.len()).filter(|&i| !used[i]).map(name_of).collect();

    let mut x = Xml::new();
    x.comment(&format!(
        "Exported by ggx {} (`ggx export --format mitsuba`) from {}. Every triangle ggx renders, in world space.",
        env!("CARGO_PKG_VERSION"),
        options.source
    ));
    x.open("scene", &[("version", "3.0.0")]);
    write_integrator(&mut x, scene);
    write_sensor(&mut x, scene);

    for (i, m) in scene.materials.iter().enumerate().filter(|(i, _)| used[*i]) {
        if !matches!(m, Material::Emissive { .. }) {
            material::write_bsdf(&mut x, &bsdf_id(i, &name_of(i)), m);
        }
    }

    let mut files = Vec::new();
    for (n, g) in groups.iter().enumerate() {
        let m = &scene.materials[g.material];
        let emitter = matches!(m, Material::Emissive { .. });
        // Emitters shine from the geometric front face in ggx: written flat.
        let smooth = g.smooth && !emitter;
        let uv = m.is_anisotropic();
        let group = mesh::Group { smooth, ..g.clone() };
        let indexed = mesh::build(scene, &group, uv);
        let name =
            format!("{}-{n}-{}.{}", options.stem, file_safe(&name_of(g.material)), options.mesh_format.extension());
        let comment = format!("ggx export: material {} ({} triangles)", name_of(g.material), g.triangles.len());
        let bytes = match options.mesh_format {
            MeshFormat::Ply => mesh::to_ply(&indexed, &comment),
            MeshFormat::Obj => mesh::to_obj(&indexed, &comment).into_bytes(),
        };
        x.open("shape", &[("type", options.mesh_format.extension())]);
        x.leaf("string", &[("name", "filename"), ("value", &name)]);
        if !smooth {
            x.leaf("boolean", &[("name", "face_normals"), ("value", "true")]);
        }
        if emitter {
            material::emitter_bsdf(&mut x, m.emission());
        } else {
            x.leaf("ref", &[("id", &bsdf_id(g.material, &name_of(g.material)))]);
        }
        x.close();
        files.push(SideFile { name, content: SideContent::Bytes(bytes) });
    }

    match &scene.environment {
        None => {}
        Some(Environment::Constant(l)) => {
            x.open("emitter", &[("type", "constant")]);
            x.leaf("rgb", &[("name", "radiance"), ("value", &rgb(*l))]);
            x.close();
        }
        Some(Environment::Map(map)) => {
            let (width, height, pixels) = envmap::resample(map, options.env_upsample);
            let name = format!("{}-envmap.exr", options.stem);
            x.comment(&format!(
                "ggx's {}x{} equirect map resampled onto Mitsuba's grid ({width}x{height}: poles on the first and last \
                 rows, {} points per texel); to_world = R_y(rotation - 90 degrees) maps ggx's axes onto Mitsuba's",
                map.width,
                map.height,
                options.env_upsample.clamp(1, envmap::MAX_UPSAMPLE)
            ));
            x.open("emitter", &[("type", "envmap")]);
            x.leaf("string", &[("name", "filename"), ("value", &name)]);
            x.leaf("float", &[("name", "scale"), ("value", &map.scale.to_string())]);
            x.open("transform", &[("name", "to_world")]);
            let m = envmap::to_world(map.rotation());
            let values: Vec<String> = m.iter().flatten().map(|v| format!("{v}")).collect();
            x.leaf("matrix", &[("value", &values.join(" "))]);
            x.close();
            x.close();
            files.push(SideFile { name, content: SideContent::Image { width, height, pixels } });
        }
    }
    Ok(Export { xml: x.finish(), files, unused_materials })
}

/// The id of material `i`'s BSDF: its name (ids are unique because names are).
fn bsdf_id(i: usize, name: &str) -> String {
    if name.is_empty() { format!("material{i}") } else { name.to_owned() }
}

/// `<integrator type="path">` with ggx's depth and roulette.
fn write_integrator(x: &mut Xml, scene: &Scene) {
    let i = &scene.integrator;
    let max_depth = i.max_depth.saturating_add(1);
    // ggx rolls from bounce index `russian_roulette - 1` (0 = the first hit); Mitsuba from
    // path depth `rr_depth` counted the same way. Off in ggx: past the last segment.
    let rr_depth = if i.russian_roulette == 0 { max_depth.saturating_add(1) } else { i.russian_roulette };
    x.comment(&format!(
        "ggx max_depth {} (bounces) = Mitsuba max_depth {max_depth} (path segments); russian roulette {}",
        i.max_depth,
        if i.russian_roulette == 0 { "off".to_owned() } else { format!("from depth {}", i.russian_roulette) }
    ));
    x.open("integrator", &[("type", "path")]);
    x.leaf("integer", &[("name", "max_depth"), ("value", &max_depth.to_string())]);
    x.leaf("integer", &[("name", "rr_depth"), ("value", &rr_depth.to_string())]);
    x.close();
}

/// `<sensor type="perspective">`: ggx's camera, sampler and film.
fn write_sensor(x: &mut Xml, scene: &Scene) {
    let c = &scene.camera;
    let i = &scene.integrator;
    x.open("sensor", &[("type", "perspective")]);
    x.leaf("float", &[("name", "fov"), ("value", &c.fov_y_degrees.to_string())]);
    x.leaf("string", &[("name", "fov_axis"), ("value", "y")]);
    x.open("transform", &[("name", "to_world")]);
    let target = c.position + c.forward;
    x.leaf("lookat", &[("origin", &xyz(c.position)), ("target", &xyz(target)), ("up", &xyz(c.up))]);
    x.close();
    x.comment(&format!(
        "ggx's sampler is {}; Mitsuba's independent sampler is the comparison's",
        match i.sampler {
            ggx_scene::SamplerKind::Independent => "independent",
            ggx_scene::SamplerKind::Sobol => "Owen-scrambled Sobol'",
        }
    ));
    x.open("sampler", &[("type", "independent")]);
    x.leaf("integer", &[("name", "sample_count"), ("value", &i.spp.to_string())]);
    x.leaf("integer", &[("name", "seed"), ("value", &i.seed.to_string())]);
    x.close();
    x.open("film", &[("type", "hdrfilm")]);
    x.leaf("integer", &[("name", "width"), ("value", &c.resolution[0].to_string())]);
    x.leaf("integer", &[("name", "height"), ("value", &c.resolution[1].to_string())]);
    x.leaf("string", &[("name", "pixel_format"), ("value", "rgb")]);
    x.leaf("string", &[("name", "component_format"), ("value", "float32")]);
    x.leaf("rfilter", &[("type", "box")]);
    x.close();
    x.close();
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(text: &str) -> Scene {
        ggx_scene::parse_scene(text, "t.toml", std::path::Path::new(".")).unwrap()
    }

    fn options() -> ExportOptions {
        ExportOptions { stem: "s".into(), mesh_format: MeshFormat::Ply, env_upsample: 2, source: "t.toml".into() }
    }

    const SCENE: &str = "[camera]\nposition = [0, 2, 7]\nlook_at = [0, 0.5, 0]\nfov_y = 40\nresolution = [64, 32]\n\
        [integrator]\nmax_depth = 4\nrussian_roulette = 0\nspp = 16\nseed = 7\nenergy_compensation = false\n\
        [environment]\ntype = \"procedural\"\npreset = \"sky\"\nresolution = [32, 16]\nrotation = 30\n\
        [materials.floor]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
        [materials.gold]\ntype = \"conductor\"\nalpha = 0.2\npreset = \"gold\"\n\
        [materials.unused]\ntype = \"plastic\"\nalpha = 0.2\nalbedo = [1, 1, 1]\n\
        [materials.lamp]\ntype = \"emissive\"\nradiance = [12, 11, 10]\n\
        [[shapes]]\ntype = \"rectangle\"\nmaterial = \"floor\"\ntransform = { rotate = [-90, 0, 0], scale = 10 }\n\
        [[shapes]]\ntype = \"sphere\"\nmaterial = \"gold\"\ncenter = [0, 0.5, 0]\nradius = 0.5\nsubdivisions = 2\n\
        [[shapes]]\ntype = \"rectangle\"\nmaterial = \"lamp\"\ntransform = { translate = [0.5, 4, 1], rotate = [90, 0, 0], scale = 1.5 }\n";

    #[test]
    fn writes_every_plugin_and_side_file() {
        let e = export(&scene(SCENE), &options()).unwrap();
        for part in [
            "<scene version=\"3.0.0\">",
            "<integrator type=\"path\">",
            "name=\"max_depth\" value=\"5\"",
            "name=\"rr_depth\" value=\"6\"",
            "<sensor type=\"perspective\">",
            "name=\"fov\" value=\"40\"",
            "name=\"fov_axis\" value=\"y\"",
            "<lookat origin=\"0, 2, 7\"",
            "name=\"sample_count\" value=\"16\"",
            "name=\"seed\" value=\"7\"",
            "name=\"width\" value=\"64\"",
            "<rfilter type=\"box\"/>",
            "<bsdf type=\"twosided\" id=\"floor\">",
            "<bsdf type=\"roughconductor\">",
            "<shape type=\"ply\">",
            "value=\"s-0-floor.ply\"",
            "<ref id=\"gold\"/>",
            "<emitter type=\"area\">",
            "name=\"radiance\" value=\"12, 11, 10\"",
            "<emitter type=\"envmap\">",
            "value=\"s-envmap.exr\"",
            "<matrix value=\"",
        ] {
            assert!(e.xml.contains(part), "missing {part}:\n{}", e.xml);
        }
        assert!(!e.xml.contains("unused"), "an unused plastic is not written:\n{}", e.xml);
        assert_eq!(e.unused_materials, ["unused"]);
        let names: Vec<&str> = e.files.iter().map(|f| f.name.as_str()).collect();
        assert_eq!(names, ["s-0-floor.ply", "s-1-gold.ply", "s-2-lamp.ply", "s-envmap.exr"]);
        // The smooth sphere keeps its normals; the flat floor and the lamp are face-normal meshes.
        assert_eq!(e.xml.matches("face_normals").count(), 2, "{}", e.xml);
        let SideContent::Image { width, height, .. } = &e.files[3].content else { panic!("an image") };
        assert_eq!((*width, *height), (64, 33));
        // Balanced tags.
        assert_eq!(e.xml.matches("<bsdf").count(), e.xml.matches("</bsdf>").count());
        assert_eq!(e.xml.matches("<shape").count(), e.xml.matches("</shape>").count());
    }

    #[test]
    fn refuses_a_used_plastic_and_a_compensated_conductor() {
        let plastic = SCENE.replace("material = \"floor\"", "material = \"unused\"");
        let e = export(&scene(&plastic), &options()).unwrap_err();
        assert_eq!((e.material.as_str(), e.kind), ("unused", "plastic"));
        let compensated = SCENE.replace("energy_compensation = false\n", "");
        let e = export(&scene(&compensated), &options()).unwrap_err();
        assert_eq!(e.material, "gold");
    }

    #[test]
    fn constant_environment_and_roulette() {
        let text = SCENE
            .replace(
                "type = \"procedural\"\npreset = \"sky\"\nresolution = [32, 16]\nrotation = 30",
                "type = \"constant\"\nradiance = [0.15, 0.17, 0.2]",
            )
            .replace("russian_roulette = 0", "russian_roulette = 3");
        let e = export(&scene(&text), &ExportOptions { mesh_format: MeshFormat::Obj, ..options() }).unwrap();
        assert!(
            e.xml.contains("<emitter type=\"constant\">") && e.xml.contains("value=\"0.15, 0.17, 0.2\""),
            "{}",
            e.xml
        );
        assert!(e.xml.contains("name=\"rr_depth\" value=\"3\"") && e.xml.contains("<shape type=\"obj\">"), "{}", e.xml);
        assert_eq!(e.files.len(), 3);
        assert!(e.files.iter().all(|f| f.name.ends_with(".obj")));
    }

    #[test]
    fn file_names_are_safe() {
        assert_eq!(file_safe("gold"), "gold");
        assert_eq!(file_safe("../a b/é"), "___a_b__");
        assert_eq!(file_safe(""), "material");
    }
}
