//! End-to-end tests of `ggx export --format mitsuba`: the XML is well formed and names the
//! expected plugins, the meshes hold every triangle ggx renders, the environment map is written,
//! a plastic is refused by name, and files are written atomically (no temporary files left,
//! nothing written on refusal).

mod support;

use std::path::Path;

use support::{TempDir, ggx, scene, stdout_of};

/// Checks that `xml` is well formed in the subset the exporter writes (declaration, comments,
/// elements with quoted attributes, self-closing or closed in order) and returns the element
/// names in document order.
fn elements(xml: &str) -> Vec<String> {
    let mut rest = xml.strip_prefix("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n").expect("declaration");
    let mut stack: Vec<String> = Vec::new();
    let mut names = Vec::new();
    while let Some(open) = rest.find('<') {
        assert!(rest[..open].trim().is_empty(), "text outside tags: {:?}", &rest[..open]);
        rest = &rest[open..];
        if let Some(after) = rest.strip_prefix("<!--") {
            let end = after.find("-->").expect("closed comment");
            assert!(!after[..end].contains("--"), "`--` inside a comment");
            rest = &after[end + 3..];
            continue;
        }
        let end = rest.find('>').expect("closed tag");
        let tag = &rest[1..end];
        rest = &rest[end + 1..];
        if let Some(name) = tag.strip_prefix('/') {
            assert_eq!(stack.pop().as_deref(), Some(name), "closing tag out of order");
            continue;
        }
        let (body, empty) = match tag.strip_suffix('/') {
            Some(b) => (b, true),
            None => (tag, false),
        };
        let name = body.split_whitespace().next().expect("a name").to_owned();
        // Attributes: name="value" pairs, no raw `<` or `"` inside values.
        let attrs = &body[name.len()..];
        assert_eq!(attrs.matches('"').count() % 2, 0, "unbalanced quotes in <{body}>");
        assert!(!attrs.contains('<'), "raw < in <{body}>");
        names.push(name.clone());
        if !empty {
            stack.push(name);
        }
    }
    assert!(rest.trim().is_empty() && stack.is_empty(), "unclosed elements: {stack:?}");
    names
}

/// `(vertices, faces)` from a PLY header.
fn ply_counts(path: &Path) -> (usize, usize) {
    let bytes = std::fs::read(path).unwrap();
    let end = bytes.windows(11).position(|w| w == b"end_header\n").expect("a PLY header");
    let header = std::str::from_utf8(&bytes[..end]).unwrap();
    assert!(header.starts_with("ply\nformat binary_little_endian 1.0\n"), "{header}");
    let count = |element: &str| -> usize {
        header.lines().find_map(|l| l.strip_prefix(&format!("element {element} "))).unwrap().parse().unwrap()
    };
    (count("vertex"), count("face"))
}

fn no_temporary_files(dir: &Path) {
    for e in std::fs::read_dir(dir).unwrap() {
        let name = e.unwrap().file_name().to_string_lossy().into_owned();
        assert!(!name.contains(".tmp-"), "temporary file left: {name}");
    }
}

#[test]
fn exports_the_peer_scene_with_every_triangle() {
    let dir = TempDir::new("export-peer");
    let xml = dir.path().join("peer.xml");
    let out = ggx(&["export", &scene("peer/three-spheres.toml"), "--format", "mitsuba", "-o", xml.to_str().unwrap()]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(stdout_of(&out).contains("exported 15364 triangles, 5 files, 256x256"), "{}", stdout_of(&out));
    let text = std::fs::read_to_string(&xml).unwrap();
    let names = elements(&text);
    for name in ["scene", "integrator", "sensor", "sampler", "film", "rfilter", "bsdf", "shape", "emitter", "lookat"] {
        assert!(names.iter().any(|n| n == name), "no <{name}>: {text}");
    }
    for part in [
        "<integrator type=\"path\">",
        "name=\"max_depth\" value=\"5\"",
        "name=\"fov_axis\" value=\"y\"",
        "<bsdf type=\"roughconductor\">",
        "name=\"alpha\" value=\"0.05\"",
        "<bsdf type=\"diffuse\">",
        "<emitter type=\"area\">",
        "<emitter type=\"constant\">",
    ] {
        assert!(text.contains(part), "missing {part}: {text}");
    }
    let loaded = ggx_scene::load_scene(Path::new(&scene("peer/three-spheres.toml"))).unwrap();
    let mut faces = 0;
    for i in 0..5 {
        let ply = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().path())
            .find(|p| p.file_name().unwrap().to_string_lossy().starts_with(&format!("peer-{i}-")))
            .expect("a mesh per material");
        assert!(text.contains(&format!("value=\"{}\"", ply.file_name().unwrap().to_string_lossy())), "{text}");
        let (v, f) = ply_counts(&ply);
        assert!(v > 0 && v <= 3 * f, "{}: {v} vertices, {f} faces", ply.display());
        faces += f;
    }
    assert_eq!(faces, loaded.mesh.triangles.len());
    no_temporary_files(dir.path());
}

#[test]
fn exports_an_environment_map_and_obj_meshes() {
    let dir = TempDir::new("export-bunny");
    let xml = dir.path().join("b.xml");
    let args = [
        "export",
        &scene("peer/bunny.toml"),
        "-o",
        xml.to_str().unwrap(),
        "--mesh-format",
        "obj",
        "--env-upsample",
        "1",
    ];
    let out = ggx(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = std::fs::read_to_string(&xml).unwrap();
    elements(&text);
    assert!(text.contains("<emitter type=\"envmap\">") && text.contains("value=\"b-envmap.exr\""), "{text}");
    assert!(text.contains("<shape type=\"obj\">"), "{text}");
    // The studio map is 1024x512: Mitsuba's grid has one more row (both poles).
    let (w, h, pixels) = ggx_film::read_exr(&dir.path().join("b-envmap.exr")).unwrap();
    assert_eq!((w, h), (1024, 513));
    assert!(pixels.iter().all(|p| p.is_finite() && p.min_element() >= 0.0));
    let obj = std::fs::read_to_string(dir.path().join("b-0-gold.obj")).unwrap();
    let faces = obj.lines().filter(|l| l.starts_with("f ")).count();
    assert_eq!(faces, 3674, "the bunny's triangles");
    assert!(obj.lines().any(|l| l.starts_with("vn ")), "the smooth bunny keeps its normals");
    // Exporting again replaces the files in place.
    let out = ggx(&args);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert_eq!(std::fs::read_to_string(&xml).unwrap(), text);
    no_temporary_files(dir.path());
}

#[test]
fn refuses_a_plastic_by_name_and_writes_nothing() {
    let dir = TempDir::new("export-plastic");
    let xml = dir.path().join("x.xml");
    let out = ggx(&["export", &scene("three-spheres.toml"), "--format", "mitsuba", "-o", xml.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("material `floor` (plastic) has no one-to-one Mitsuba 3 twin"), "{err}");
    assert!(err.contains("roughplastic"), "{err}");
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing written");
    // A compensated conductor, then the same scene with compensation off.
    let bunny = scene("bunny.toml");
    let out = ggx(&["export", &bunny, "-o", xml.to_str().unwrap(), "--env-upsample", "1"]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--energy-compensation off"));
    let out =
        ggx(&["export", &bunny, "-o", xml.to_str().unwrap(), "--env-upsample", "1", "--energy-compensation", "off"]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
}

#[test]
fn bad_outputs_are_refused_before_loading() {
    let dir = TempDir::new("export-output");
    let out = ggx(&["export", &scene("peer/three-spheres.toml"), "-o", dir.path().join("x.txt").to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&out.stderr).contains("must end in .xml"));
    let missing = dir.path().join("no/such/dir/x.xml");
    let out = ggx(&["export", &scene("peer/three-spheres.toml"), "-o", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(1));
    let out = ggx(&["export", &scene("peer/three-spheres.toml"), "--format", "pbrt", "-o", "x.xml"]);
    assert_eq!(out.status.code(), Some(2), "a usage error");
}
