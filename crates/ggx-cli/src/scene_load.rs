//! Loading the scene a command names: a TOML scene file, or a glTF file (`.gltf`, `.glb`)
//! with `--camera` and `--env`.

use std::path::{Path, PathBuf};

use anyhow::{Result, bail};
use clap::Args;
use ggx_film::Vec3;
use ggx_scene::{GltfEnvironment, GltfOptions, Limits, Scene, is_gltf_path};

/// `--camera` and `--env`, for glTF files.
#[derive(Debug, Default, Args)]
pub struct GltfArgs {
    /// glTF only: the camera to render by name [default: the file's first camera, else one
    /// that frames the whole scene].
    #[arg(long, value_name = "NAME")]
    pub camera: Option<String>,

    /// glTF only: the environment, a constant radiance `R,G,B` or an .hdr/.exr map file
    /// [default: none when the file has emissive materials, else a uniform 1,1,1].
    #[arg(long, value_name = "FILE|R,G,B")]
    pub env: Option<String>,
}

impl GltfArgs {
    /// The options, or why `--env` is not a colour or a file.
    fn options(&self) -> Result<GltfOptions> {
        let environment = match &self.env {
            None => None,
            Some(e) => Some(parse_env(e)?),
        };
        Ok(GltfOptions { camera: self.camera.clone(), environment })
    }
}

/// `R,G,B` (three finite numbers >= 0) or a file path.
fn parse_env(text: &str) -> Result<GltfEnvironment> {
    let parts: Vec<&str> = text.split(',').map(str::trim).collect();
    if parts.len() == 3 && parts.iter().all(|p| p.parse::<f32>().is_ok()) {
        let v: Vec<f32> = parts.iter().filter_map(|p| p.parse().ok()).collect();
        let c = Vec3::new(v[0], v[1], v[2]);
        if !c.is_finite() || c.min_element() < 0.0 {
            bail!("--env {text}: a radiance must be three finite numbers >= 0");
        }
        return Ok(GltfEnvironment::Constant(c));
    }
    let path = PathBuf::from(text);
    if !path.is_file() {
        bail!("--env {text}: neither R,G,B nor an existing .hdr/.exr file");
    }
    Ok(GltfEnvironment::Map(path))
}

/// Loads `path` within `limits`: a glTF file with `gltf`'s options, or a TOML scene (which
/// takes neither option).
pub fn load(path: &Path, limits: &Limits, gltf: &GltfArgs) -> Result<Scene> {
    if is_gltf_path(path) {
        return Ok(ggx_scene::load_gltf_scene(path, limits, &gltf.options()?)?);
    }
    if gltf.camera.is_some() || gltf.env.is_some() {
        bail!("--camera and --env apply to glTF files (.gltf, .glb); {} is a scene file", path.display());
    }
    Ok(ggx_scene::load_scene_with(path, limits)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn env_is_a_colour_or_a_file() {
        assert_eq!(parse_env("1, 0.5,0").unwrap(), GltfEnvironment::Constant(Vec3::new(1.0, 0.5, 0.0)));
        assert!(parse_env("1,-1,0").unwrap_err().to_string().contains(">= 0"));
        assert!(parse_env("inf,1,1").is_err());
        assert!(parse_env("no-such-file.hdr").unwrap_err().to_string().contains("neither"));
        assert_eq!(parse_env("Cargo.toml").unwrap(), GltfEnvironment::Map(PathBuf::from("Cargo.toml")));
    }
}
