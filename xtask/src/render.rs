//! Shared by `diff` and `bench`: finding the scenes, loading one with overrides, and rendering
//! it on either backend with the same seed, so both commands measure exactly what `ggx render`
//! runs.

use ggx_cpu::{AccelKind, RenderControl, RenderOptions, RenderResult, Renderer};
use ggx_scene::Scene;
use ggx_wgpu::{GpuContext, GpuOptions, WgpuRenderer};
use std::path::{Path, PathBuf};

/// The workspace root (xtask lives one level below it).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).parent().map_or_else(|| PathBuf::from("."), Path::to_path_buf)
}

/// `scenes/` of the workspace.
pub fn scenes_dir() -> PathBuf {
    workspace_root().join("scenes")
}

/// `target/xtask/<what>/` of the workspace, created.
pub fn output_dir(what: &str) -> Result<PathBuf, String> {
    let dir = workspace_root().join("target").join("xtask").join(what);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    Ok(dir)
}

/// Every `scenes/*.toml`, sorted by name, or the ones named (by stem, e.g. `cornell`, or by path).
pub fn scene_paths(names: &[String]) -> Result<Vec<PathBuf>, String> {
    if !names.is_empty() {
        return names
            .iter()
            .map(|n| {
                let direct = PathBuf::from(n);
                let path = if direct.is_file() { direct } else { scenes_dir().join(format!("{n}.toml")) };
                if path.is_file() { Ok(path) } else { Err(format!("no scene `{n}` (looked for {})", path.display())) }
            })
            .collect();
    }
    let dir = scenes_dir();
    let mut paths: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "toml"))
        .collect();
    paths.sort();
    Ok(paths)
}

/// The file stem of a scene path (`scenes/cornell.toml` -> `cornell`).
pub fn scene_name(path: &Path) -> String {
    path.file_stem().unwrap_or_default().to_string_lossy().into_owned()
}

/// Image size and sample count that replace the scene file's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Overrides {
    /// Width in pixels; the height follows the scene's aspect ratio (at least 1).
    pub width: u32,
    /// Samples per pixel.
    pub spp: u32,
}

/// Loads a scene and applies `overrides`; the time budget is dropped so the sample count is exact.
pub fn load(path: &Path, overrides: Overrides) -> Result<Scene, String> {
    let mut scene = ggx_scene::load_scene(path).map_err(|e| e.to_string())?;
    let [w, h] = scene.camera.resolution;
    let width = overrides.width.max(1);
    let height = ((u64::from(h) * u64::from(width) + u64::from(w) / 2) / u64::from(w.max(1))).max(1) as u32;
    scene.camera.resolution = [width, height];
    scene.integrator.spp = overrides.spp.max(1);
    scene.integrator.time_budget = None;
    Ok(scene)
}

/// Which renderer runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Backend {
    /// ggx-cpu on every core.
    Cpu,
    /// ggx-wgpu on the context's adapter.
    Wgpu,
}

impl Backend {
    /// `cpu` or `wgpu`.
    pub fn name(self) -> &'static str {
        match self {
            Backend::Cpu => "cpu",
            Backend::Wgpu => "wgpu",
        }
    }
}

/// The wgpu adapter, or an error that says how to get one (never a silent skip).
pub fn gpu_context() -> Result<GpuContext, String> {
    let ctx = GpuContext::new(GpuOptions::default()).map_err(|e| format!("the wgpu backend has no adapter: {e}"))?;
    eprintln!("wgpu adapter: {}", ctx.describe());
    Ok(ctx)
}

/// Renders `scene` on `backend` (the default CPU BVH, as `ggx render` uses), specialized to the
/// scene's features or with the generic kernel. `gpu` must be given for [`Backend::Wgpu`].
pub fn render(
    scene: &Scene,
    backend: Backend,
    specialize: bool,
    gpu: Option<&GpuContext>,
) -> Result<RenderResult, String> {
    render_with(scene, backend, specialize, gpu, AccelKind::default())
}

/// [`render`] with the CPU backend's BVH layout chosen (the wgpu backend always traces a BVH2).
pub fn render_with(
    scene: &Scene,
    backend: Backend,
    specialize: bool,
    gpu: Option<&GpuContext>,
    accel: AccelKind,
) -> Result<RenderResult, String> {
    let options = RenderOptions { specialize, ..RenderOptions::default() };
    let control = RenderControl::default();
    match backend {
        Backend::Cpu => Renderer::new(scene, accel).render(&options, &control).map_err(|e| e.to_string()),
        Backend::Wgpu => {
            let ctx = gpu.ok_or("the wgpu backend needs an adapter")?;
            WgpuRenderer::new(scene, ctx).and_then(|r| r.render(&options, &control)).map_err(|e| e.to_string())
        }
    }
}
