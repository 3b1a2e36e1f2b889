//! `ggx render --stats FILE.json`: what a render did, machine-readable, written atomically
//! next to the image: scene, backend, adapter, kernel, spp, time, camera samples/s, rays/s and
//! the time at the end of every pass.

use std::path::Path;
use std::sync::Mutex;

use anyhow::{Context, Result};
use ggx_cpu::{Progress, RenderResult};
use serde::Serialize;

/// One completed pass: the samples per pixel accumulated and the render time when it ended.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PassTime {
    /// Samples per pixel after the pass.
    pub spp: u32,
    /// Seconds since the render started.
    pub seconds: f64,
}

/// The passes of a render, recorded from its progress callback (which may run on any thread).
#[derive(Debug, Default)]
pub struct PassLog(Mutex<Vec<PassTime>>);

impl PassLog {
    /// Records the pass that `progress` reports.
    pub fn record(&self, progress: &Progress) {
        // A poisoned lock only means another callback panicked; the log is still valid.
        let mut passes = self.0.lock().unwrap_or_else(|e| e.into_inner());
        passes.push(PassTime { spp: progress.spp_done, seconds: progress.elapsed.as_secs_f64() });
    }

    /// The recorded passes, in order.
    pub fn passes(&self) -> Vec<PassTime> {
        self.0.lock().unwrap_or_else(|e| e.into_inner()).clone()
    }
}

/// The statistics file's content.
#[derive(Debug, Serialize)]
pub struct Stats {
    /// `ggx` version.
    pub ggx_version: &'static str,
    /// The scene file as given.
    pub scene: String,
    /// The image written.
    pub output: String,
    /// `"cpu"` or `"wgpu"`.
    pub backend: &'static str,
    /// The processor (and thread count) or the GPU adapter.
    pub adapter: String,
    /// The kernel variant that ran, e.g. `"area+env"`.
    pub kernel: &'static str,
    /// Image width.
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// Samples per pixel in the image.
    pub spp: u32,
    /// Samples per pixel the scene (or `--spp`) asked for.
    pub spp_requested: u32,
    /// True when Ctrl-C or SIGTERM ended the render early.
    pub interrupted: bool,
    /// Render time in seconds (BVH build and shader compilation excluded).
    pub seconds: f64,
    /// Camera samples traced.
    pub camera_samples: u64,
    /// Camera samples per second.
    pub camera_samples_per_second: f64,
    /// Rays traced (closest-hit and shadow rays).
    pub rays: u64,
    /// Rays per second.
    pub rays_per_second: f64,
    /// Every completed pass.
    pub passes: Vec<PassTime>,
}

/// What the statistics are about, besides the render result.
pub struct StatsContext<'a> {
    /// The scene file.
    pub scene: &'a Path,
    /// The image.
    pub output: &'a Path,
    /// `"cpu"` or `"wgpu"`.
    pub backend: &'static str,
    /// The processor or adapter.
    pub adapter: String,
    /// Samples per pixel requested.
    pub spp_requested: u32,
}

impl Stats {
    /// The statistics of `result`.
    pub fn new(ctx: StatsContext<'_>, result: &RenderResult, passes: Vec<PassTime>) -> Stats {
        let seconds = result.elapsed.as_secs_f64();
        let per_second = |n: u64| if seconds > 0.0 { n as f64 / seconds } else { 0.0 };
        Stats {
            ggx_version: env!("CARGO_PKG_VERSION"),
            scene: ctx.scene.display().to_string(),
            output: ctx.output.display().to_string(),
            backend: ctx.backend,
            adapter: ctx.adapter,
            kernel: result.kernel,
            width: result.film.width(),
            height: result.film.height(),
            spp: result.spp,
            spp_requested: ctx.spp_requested,
            interrupted: result.interrupted,
            seconds,
            camera_samples: result.camera_samples,
            camera_samples_per_second: per_second(result.camera_samples),
            rays: result.rays,
            rays_per_second: per_second(result.rays),
            passes,
        }
    }

    /// The figures for an EXR header (`ggx.stats.<name>`): adapter, kernel, spp, time and rates.
    pub fn header_pairs(&self) -> Vec<(String, String)> {
        [
            ("adapter", self.adapter.clone()),
            ("kernel", self.kernel.to_owned()),
            ("spp", self.spp.to_string()),
            ("interrupted", self.interrupted.to_string()),
            ("seconds", format!("{:.6}", self.seconds)),
            ("cameraSamples", self.camera_samples.to_string()),
            ("cameraSamplesPerSecond", format!("{:.0}", self.camera_samples_per_second)),
            ("rays", self.rays.to_string()),
            ("raysPerSecond", format!("{:.0}", self.rays_per_second)),
            ("passes", self.passes.len().to_string()),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_owned(), v))
        .collect()
    }

    /// Writes the statistics as pretty-printed JSON to `path`, atomically.
    pub fn write(&self, path: &Path) -> Result<()> {
        let mut json = serde_json::to_string_pretty(self).context("cannot serialize the statistics")?;
        json.push('\n');
        ggx_film::write_file(path, json.as_bytes())?;
        Ok(())
    }
}

/// The processor's name (Linux's `/proc/cpuinfo` `model name`, else `"cpu"`) and the render
/// threads, e.g. `AMD EPYC 7B13 (2 threads)`.
pub fn cpu_adapter(threads: usize) -> String {
    let threads = if threads == 0 { std::thread::available_parallelism().map_or(1, usize::from) } else { threads };
    let model = std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|text| {
            text.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split_once(':'))
                .map(|(_, name)| name.trim().to_owned())
        })
        .filter(|name| !name.is_empty())
        .unwrap_or_else(|| "cpu".to_owned());
    format!("{model} ({threads} threads)")
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn passes_are_recorded_in_order() {
        let log = PassLog::default();
        for (spp, ms) in [(1, 10), (2, 25), (4, 60)] {
            let samples_done = u64::from(spp) * 16;
            let elapsed = Duration::from_millis(ms);
            log.record(&Progress {
                spp_done: spp,
                spp_target: 4,
                samples_done,
                samples_target: 64,
                pass_end: true,
                elapsed,
            });
        }
        let passes = log.passes();
        assert_eq!(passes.iter().map(|p| p.spp).collect::<Vec<_>>(), [1, 2, 4]);
        assert_eq!(passes[2].seconds, 0.06);
    }

    #[test]
    fn the_adapter_names_the_threads() {
        assert!(cpu_adapter(3).ends_with("(3 threads)"), "{}", cpu_adapter(3));
        assert!(!cpu_adapter(0).ends_with("(0 threads)"));
    }
}
