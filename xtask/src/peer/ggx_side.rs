//! The ggx side of the peer run, through the release `ggx` binary that users run: `ggx export
//! --format mitsuba` for Mitsuba's copy of each scene, and `ggx render ... --stats FILE.json`
//! for every rung (its `seconds` is the render time, BVH build excluded, as Mitsuba's timing
//! excludes its scene load).

use std::path::{Path, PathBuf};
use std::process::Command;

use serde::Deserialize;

/// What `--stats` reports that the peer run uses.
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct Stats {
    /// Samples per pixel in the image.
    pub spp: u32,
    /// Render time in seconds.
    pub seconds: f64,
    /// Camera samples traced.
    pub camera_samples: u64,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
}

/// One `ggx render`.
#[derive(Clone, Debug)]
pub struct RenderJob<'a> {
    /// Scene file.
    pub scene: &'a Path,
    /// Output EXR.
    pub out: &'a Path,
    /// Statistics file.
    pub stats: &'a Path,
    /// Samples per pixel.
    pub spp: u32,
    /// Seed.
    pub seed: u32,
    /// Worker threads.
    pub threads: usize,
    /// Width override.
    pub width: Option<u32>,
}

/// Runs `ggx args`, returning stdout; an error carries stderr.
fn ggx(bin: &Path, args: &[String]) -> Result<String, String> {
    let out = Command::new(bin).args(args).output().map_err(|e| format!("{}: {e}", bin.display()))?;
    if out.status.success() {
        Ok(String::from_utf8_lossy(&out.stdout).into_owned())
    } else {
        Err(format!(
            "`{} {}` failed ({}): {}",
            bin.display(),
            args.join(" "),
            out.status,
            String::from_utf8_lossy(&out.stderr).trim()
        ))
    }
}

/// `ggx export SCENE --format mitsuba -o XML [--width W] --env-upsample K`.
pub fn export(bin: &Path, scene: &Path, xml: &Path, width: Option<u32>, env_upsample: u32) -> Result<String, String> {
    let mut args = vec![
        "export".to_owned(),
        scene.display().to_string(),
        "--format".into(),
        "mitsuba".into(),
        "-o".into(),
        xml.display().to_string(),
        "--env-upsample".into(),
        env_upsample.to_string(),
    ];
    if let Some(w) = width {
        args.extend(["--width".into(), w.to_string()]);
    }
    ggx(bin, &args)
}

/// The arguments of `ggx render` for `job`.
pub fn render_args(job: &RenderJob) -> Vec<String> {
    let mut args = vec![
        "render".to_owned(),
        job.scene.display().to_string(),
        "-o".into(),
        job.out.display().to_string(),
        "--spp".into(),
        job.spp.to_string(),
        "--seed".into(),
        job.seed.to_string(),
        "--threads".into(),
        job.threads.to_string(),
        "--stats".into(),
        job.stats.display().to_string(),
    ];
    if let Some(w) = job.width {
        args.extend(["--width".into(), w.to_string()]);
    }
    args
}

/// The statistics `job`'s render wrote; fails unless every requested sample was rendered.
pub fn read_stats(job: &RenderJob) -> Result<Stats, String> {
    let text = std::fs::read_to_string(job.stats).map_err(|e| format!("{}: {e}", job.stats.display()))?;
    let stats: Stats = serde_json::from_str(&text).map_err(|e| format!("{}: {e}", job.stats.display()))?;
    if stats.spp != job.spp {
        return Err(format!("{}: rendered {} of {} spp", job.scene.display(), stats.spp, job.spp));
    }
    Ok(stats)
}

/// Renders `job` and reads its statistics; fails unless every requested sample was rendered.
pub fn render(bin: &Path, job: &RenderJob) -> Result<Stats, String> {
    ggx(bin, &render_args(job))?;
    read_stats(job)
}

/// The scene text with `[integrator] sampler = "independent"` (replacing a `sampler` line of
/// that table or added under its header, or a new table at the end) and every `file = "..."`
/// made absolute against `base_dir`, so the copy can live anywhere. A line-based edit: the
/// caller loads the result to check it.
pub fn independent_variant(text: &str, base_dir: &Path) -> String {
    let mut out = Vec::new();
    let mut section = String::new();
    let mut done = false;
    for line in text.lines() {
        let code = line.split('#').next().unwrap_or("").trim();
        if code.starts_with('[') {
            if section == "[integrator]" && !done {
                out.push("sampler = \"independent\"".to_owned());
                done = true;
            }
            section = code.to_owned();
        }
        let key = code.split('=').next().unwrap_or("").trim();
        if section == "[integrator]" && key == "sampler" && code.contains('=') {
            out.push("sampler = \"independent\"".to_owned());
            done = true;
            continue;
        }
        out.push(absolute_files(line, base_dir));
    }
    if section == "[integrator]" && !done {
        out.push("sampler = \"independent\"".to_owned());
        done = true;
    }
    if !done {
        out.push("\n[integrator]\nsampler = \"independent\"".to_owned());
    }
    let mut s = out.join("\n");
    s.push('\n');
    s
}

/// `line` with each `file = "X"` value (before any comment) replaced by `base_dir/X`.
fn absolute_files(line: &str, base_dir: &Path) -> String {
    let code_end = line.find('#').unwrap_or(line.len());
    let (code, comment) = line.split_at(code_end);
    let names = crate::bench::cache_key::referenced_files(code);
    let mut code = code.to_owned();
    for name in names {
        let abs: PathBuf = base_dir.join(&name);
        let quoted = format!("\"{}\"", abs.display().to_string().replace('\\', "\\\\").replace('"', "\\\""));
        code = code.replacen(&format!("\"{name}\""), &quoted, 1);
    }
    code + comment
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn independent_variant_replaces_or_adds_the_sampler() {
        let base = Path::new("/s/peer");
        let text = "[camera]\nposition = [0, 0, 1]\n[integrator]\nspp = 4\nsampler = \"sobol\" # x\n\
                    [[shapes]]\ntype = \"mesh\"\nfile = \"../assets/b.obj\"   # mesh\n";
        let v = independent_variant(text, base);
        assert!(v.contains("[integrator]\nspp = 4\nsampler = \"independent\"\n[[shapes]]"), "{v}");
        assert!(v.contains("file = \"/s/peer/../assets/b.obj\"   # mesh"), "{v}");
        assert!(!v.contains("sobol"));
        let added = independent_variant("[integrator]\nspp = 4\n[camera]\nfov_y = 3\n", base);
        assert_eq!(added, "[integrator]\nspp = 4\nsampler = \"independent\"\n[camera]\nfov_y = 3\n");
        let last = independent_variant("[camera]\n[integrator]\nspp = 4", base);
        assert!(last.ends_with("spp = 4\nsampler = \"independent\"\n"), "{last}");
        let none = independent_variant("[camera]\nfov_y = 3\n", base);
        assert!(none.ends_with("\n[integrator]\nsampler = \"independent\"\n"), "{none}");
    }

    #[test]
    fn the_variant_of_a_peer_scene_loads_with_the_independent_sampler() {
        let path = crate::render::scenes_dir().join("peer").join("bunny.toml");
        let text = std::fs::read_to_string(&path).unwrap();
        let dir = std::env::temp_dir().join(format!("xtask-peer-variant-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let copy = dir.join("bunny-independent.toml");
        std::fs::write(&copy, independent_variant(&text, path.parent().unwrap())).unwrap();
        let (a, b) = (ggx_scene::load_scene(&path).unwrap(), ggx_scene::load_scene(&copy));
        std::fs::remove_dir_all(&dir).unwrap();
        let b = b.unwrap();
        assert_eq!(b.integrator.sampler, ggx_scene::SamplerKind::Independent);
        assert_eq!(a.integrator.sampler, ggx_scene::SamplerKind::Sobol);
        assert_eq!(a.mesh.triangles, b.mesh.triangles);
    }
}
