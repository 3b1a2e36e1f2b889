//! A glTF file rendered on its own (`ggx render model.glb`): the asset as the scene's one
//! shape, its first camera (or the one named) or a camera that frames its bounds, and an
//! environment when the file brings no light.

use std::path::{Path, PathBuf};

use glam::Vec3;

use crate::camera::{Camera, MAX_RESOLUTION};
use crate::error::{ErrorKind, SceneError};
use crate::limits::Limits;
use crate::scene::Scene;
use crate::shorten::{short, short_path};

/// The light of a glTF scene: a constant radiance or an equirectangular map file.
#[derive(Clone, Debug, PartialEq)]
pub enum GltfEnvironment {
    /// Constant radiance (linear RGB).
    Constant(Vec3),
    /// An `.hdr` or `.exr` map.
    Map(PathBuf),
}

/// How a glTF file becomes a scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct GltfOptions {
    /// The camera to use, by name (default: the file's first camera, else one framing the
    /// scene).
    pub camera: Option<String>,
    /// The environment (default: none when the file has emissive materials, else a constant
    /// radiance of 1).
    pub environment: Option<GltfEnvironment>,
}

/// Image width of a glTF scene before `--width`/`--height`; the height follows the camera's
/// aspect ratio (4:3 without one).
pub const GLTF_DEFAULT_WIDTH: u32 = 640;
/// Vertical field of view of the camera that frames a glTF without cameras, in degrees.
const FRAMING_FOV: f32 = 40.0;

/// True for a path that names a glTF file (`.gltf` or `.glb`, any case).
pub fn is_gltf_path(path: &Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("gltf") || e.eq_ignore_ascii_case("glb"))
}

/// Loads the glTF file at `path` as a scene within `limits` (see [`GltfOptions`]).
pub fn load_gltf_scene(path: &Path, limits: &Limits, options: &GltfOptions) -> Result<Scene, SceneError> {
    let name = path.display().to_string();
    let fail = |kind, message: String| SceneError::Unreadable { path: name.clone(), kind, message };
    let file_name = path.file_name().map(|f| f.to_string_lossy().into_owned()).unwrap_or_default();
    let mut text = format!(
        "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n\n[[shapes]]\ntype = \"gltf\"\nfile = {}\n",
        quoted(&file_name)
    );
    match &options.environment {
        Some(GltfEnvironment::Constant(c)) => {
            text += &format!("\n[environment]\ntype = \"constant\"\nradiance = [{}, {}, {}]\n", c.x, c.y, c.z);
        }
        Some(GltfEnvironment::Map(p)) => {
            let abs = std::path::absolute(p).unwrap_or_else(|_| p.clone());
            text += &format!("\n[environment]\ntype = \"map\"\nfile = {}\n", quoted(&abs.to_string_lossy()));
        }
        None => {}
    }
    let base_dir = path.parent().unwrap_or(Path::new("."));
    // Errors inside the generated text are the glTF file's (or the --env file's): report them
    // by their own message, which names the file.
    let shown = short_path(path);
    let mut scene = crate::parse_scene_with(&text, &name, base_dir, limits).map_err(|e| match e {
        SceneError::At { kind, message, .. } if message.starts_with(&shown) => fail(kind, message),
        SceneError::At { kind, message, .. } => fail(kind, format!("{shown}: {message}")),
        other => other,
    })?;
    if options.environment.is_none() && scene.lights.is_empty() && scene.punctual_lights.is_empty() {
        let env = crate::parse_scene_with(
            "[camera]\nposition = [0, 0, 1]\nlook_at = [0, 0, 0]\n[environment]\ntype = \"constant\"\nradiance = [1, 1, 1]\n",
            &name,
            base_dir,
            limits,
        )?;
        scene.environment = env.environment;
        scene.features.constant_env = true;
        scene.warnings.push(format!(
            "{}: no emissive material and no light: lit by a uniform white environment (--env FILE|R,G,B to choose one)",
            short_path(path)
        ));
    }
    let (pose, aspect) = match &options.camera {
        Some(want) => {
            let c = scene.cameras.iter().find(|c| &c.name == want).ok_or_else(|| {
                let names: Vec<_> = scene.cameras.iter().map(|c| format!("\"{}\"", short(&c.name))).collect();
                let known =
                    if names.is_empty() { "it has none".to_owned() } else { format!("it has {}", names.join(", ")) };
                fail(ErrorKind::Schema, format!("{}: no camera named \"{}\" ({known})", short_path(path), short(want)))
            })?;
            ((c.position, c.forward, c.up, c.fov_y_degrees), c.aspect)
        }
        None => match scene.cameras.first() {
            Some(c) => ((c.position, c.forward, c.up, c.fov_y_degrees), c.aspect),
            None => (framing(&scene), None),
        },
    };
    let aspect = aspect.filter(|a| a.is_finite() && *a > 0.0).unwrap_or(4.0 / 3.0);
    let height = ((GLTF_DEFAULT_WIDTH as f32 / aspect).round() as u32).clamp(1, MAX_RESOLUTION);
    let (position, forward, up, fov) = pose;
    scene.camera =
        Camera::look_at(position, position + forward, up, fov, [GLTF_DEFAULT_WIDTH, height]).ok_or_else(|| {
            fail(ErrorKind::Degenerate, format!("{}: the camera's up is parallel to its view", short_path(path)))
        })?;
    Ok(scene)
}

/// `s` as a TOML basic string: quotes, backslashes and control characters escaped.
fn quoted(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if c.is_control() => out.push_str(&format!("\\u{:04X}", c as u32)),
            c => out.push(c),
        }
    }
    out.push('"');
    out
}

/// A camera that sees the whole mesh: from the front, right and above (direction
/// `(0.5, 0.4, 1)` from the centre of the bounds), far enough that the bounding sphere fits
/// the field of view with a margin.
fn framing(scene: &Scene) -> (Vec3, Vec3, Vec3, f32) {
    let (lo, hi) = scene.mesh.bounds().unwrap_or((Vec3::splat(-1.0), Vec3::ONE));
    let center = 0.5 * (lo + hi);
    let radius = (0.5 * (hi - lo).length()).max(1e-3);
    let dir = Vec3::new(0.5, 0.4, 1.0).normalize();
    let distance = 1.1 * radius / (0.5 * FRAMING_FOV.to_radians()).sin();
    let position = center + dir * distance;
    (position, -dir, Vec3::Y, FRAMING_FOV)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_are_quoted_for_toml() {
        assert_eq!(quoted(r#"a"b\c"#), r#""a\"b\\c""#);
        assert_eq!(quoted("x\ny"), r#""x\u000Ay""#);
        assert!(is_gltf_path(Path::new("a/B.GLB")) && is_gltf_path(Path::new("m.gltf")));
        assert!(!is_gltf_path(Path::new("m.toml")));
    }
}
