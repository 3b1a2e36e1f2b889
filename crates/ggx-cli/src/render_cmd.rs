//! `ggx render`: load, apply overrides, render with a progress bar, write the image (also
//! after Ctrl-C) and print a summary.

use std::io::Write as _;
use std::path::PathBuf;

use anyhow::{Context, Result};
use ggx_cpu::{Progress, RenderControl, RenderOptions, RenderResult, Renderer};
use ggx_film::{OutputOptions, ToneMap};
use ggx_scene::Scene;
use ggx_wgpu::{GpuContext, GpuError, WgpuRenderer};
use indicatif::ProgressBar;

use crate::args::{Backend, RenderArgs, ToneMapArg};
use crate::backend::{self, Device};
use crate::exit::Outcome;
use crate::interrupt::{Interrupt, Phase};
use crate::progress::RenderProgress;
use crate::stats::{self, PassLog, Stats};
use crate::{accel, memory, output, overrides};

/// Runs `ggx render`.
pub fn run(args: &RenderArgs) -> Result<Outcome> {
    // Signals are honoured from the start: until rendering begins they exit at once.
    let bar = crate::progress::new_bar();
    let interrupt = Interrupt::install(bar.clone())?;
    // Everything that can be checked without rendering is checked first.
    let device = backend::select(args.backend)?;
    output::check(&args.output, &[&args.scene])?;
    if let Some(stats) = &args.stats {
        output::check_stats(stats, &args.output, &[&args.scene])?;
    }

    let limits = args.limits.limits();
    eprintln!("loading {}", args.scene.display());
    let mut scene = ggx_scene::load_scene_with(&args.scene, &limits)?;
    overrides::apply(&mut scene, args)?;
    let inputs: Vec<&std::path::Path> = scene.inputs.iter().map(PathBuf::as_path).collect();
    output::check_not_input(&args.output, &inputs)?;
    if let Some(stats) = &args.stats {
        output::check_not_input(stats, &inputs)?;
    }
    memory::check(&scene, &limits)?;
    for warning in scene.warnings() {
        eprintln!("warning: {warning}");
    }

    let passes = PassLog::default();
    let cpu = || ("cpu", stats::cpu_adapter(usize::from(args.threads)));
    let (result, (backend, adapter)) = match device {
        Device::Cpu => (render_cpu(&scene, args, bar, &interrupt, &passes)?, cpu()),
        Device::Wgpu(ctx) => match render_wgpu(&scene, args, &ctx, bar.clone(), &interrupt, &passes) {
            Err(e) if args.backend == Backend::Auto && too_large_for_gpu(&e) => {
                eprintln!("{}: rendering on the CPU", crate::exit::message(&e));
                (render_cpu(&scene, args, bar, &interrupt, &passes)?, cpu())
            }
            other => (other?, ("wgpu", ctx.describe())),
        },
    };
    let requested = scene.integrator.spp;
    if result.spp == 0 {
        eprintln!("interrupted before the first pass was done: no image written");
        return Ok(Outcome::Interrupted);
    }
    if result.interrupted {
        eprintln!("interrupted after {} of {requested} spp: writing the partial image", result.spp);
    } else if result.spp < requested {
        let budget = scene.integrator.time_budget.unwrap_or(0.0);
        eprintln!("time budget of {budget} s reached after {} of {requested} spp", result.spp);
    }

    interrupt.set_phase(Phase::Writing);
    let options = OutputOptions { exposure: args.exposure, tonemap: tone_map(args.tonemap) };
    let (width, height) = (result.film.width(), result.film.height());
    // The error names the path and what failed.
    ggx_film::write_image(&args.output, width, height, &result.film.mean(), &options)?;
    if let Some(path) = &args.stats {
        let context = stats::StatsContext {
            scene: &args.scene,
            output: &args.output,
            backend,
            adapter,
            spp_requested: requested,
        };
        Stats::new(context, &result, passes.passes()).write(path)?;
    }

    // A signal that came while a complete image was written still ends with code 130, but
    // the summary says what the image is.
    let line = summary(&result, [width, height], &args.output.display().to_string());
    writeln!(std::io::stdout(), "{line}").context("cannot write to stdout")?;
    Ok(if result.interrupted || interrupt.requested() { Outcome::Interrupted } else { Outcome::Done })
}

/// Builds the BVH and renders on the CPU.
fn render_cpu(
    scene: &Scene,
    args: &RenderArgs,
    bar: ProgressBar,
    interrupt: &Interrupt,
    passes: &PassLog,
) -> Result<RenderResult> {
    let renderer = Renderer::new(scene, accel::kind(args.accel));
    let [width, height] = scene.camera.resolution;
    let kernel = if args.generic { "generic kernel" } else { "specialized kernel" };
    eprintln!(
        "rendering {} on the CPU: {width}x{height}, {} spp{}, {} built in {}, {kernel}",
        args.scene.display(),
        scene.integrator.spp,
        scene.integrator.time_budget.map_or(String::new(), |t| format!(" or {t} s")),
        accel::name(args.accel),
        accel::format_build_time(renderer.build_time()),
    );
    interrupt.set_phase(Phase::Rendering);
    let progress = RenderProgress::start(
        bar,
        scene.integrator.spp,
        u64::from(width) * u64::from(height),
        scene.integrator.time_budget,
    );
    let on_progress = |p: Progress| {
        passes.record(&p);
        progress.update(&p);
    };
    let control = RenderControl { cancel: Some(interrupt.cancel_flag()), progress: Some(&on_progress) };
    let options = RenderOptions { threads: usize::from(args.threads), specialize: !args.generic };
    let result = renderer.render(&options, &control);
    progress.finish();
    Ok(result?)
}

/// Uploads the scene and renders on the GPU.
fn render_wgpu(
    scene: &Scene,
    args: &RenderArgs,
    ctx: &GpuContext,
    bar: ProgressBar,
    interrupt: &Interrupt,
    passes: &PassLog,
) -> Result<RenderResult> {
    let renderer = WgpuRenderer::new(scene, ctx)?;
    let [width, height] = scene.camera.resolution;
    let kernel = if args.generic { "generic kernel" } else { "specialized kernel" };
    eprintln!(
        "rendering {} on {}: {width}x{height}, {} spp{}, BVH2, {kernel}",
        args.scene.display(),
        ctx.adapter_info().name,
        scene.integrator.spp,
        scene.integrator.time_budget.map_or(String::new(), |t| format!(" or {t} s")),
    );
    interrupt.set_phase(Phase::Rendering);
    let progress = RenderProgress::start(
        bar,
        scene.integrator.spp,
        u64::from(width) * u64::from(height),
        scene.integrator.time_budget,
    );
    let on_progress = |p: Progress| {
        passes.record(&p);
        progress.update(&p);
    };
    let control = RenderControl { cancel: Some(interrupt.cancel_flag()), progress: Some(&on_progress) };
    let options = RenderOptions { threads: 0, specialize: !args.generic };
    let result = renderer.render(&options, &control);
    progress.finish();
    Ok(result?)
}

/// Whether `err` says the scene or image does not fit the GPU's buffers.
fn too_large_for_gpu(err: &anyhow::Error) -> bool {
    err.chain().any(|c| matches!(c.downcast_ref::<GpuError>(), Some(GpuError::TooLarge { .. })))
}

/// The final line: time, spp, size, throughput, kernel variant, output.
fn summary(result: &RenderResult, [width, height]: [u32; 2], output: &str) -> String {
    let secs = result.elapsed.as_secs_f64();
    // Always in M/s so that runs compare at a glance.
    let rate = |n: u64| if secs > 0.0 { format!("{:.2}", n as f64 / secs * 1e-6) } else { "-".to_owned() };
    format!(
        "{}: {secs:.3} s, {} spp, {width}x{height}, {} M camera samples/s, {} M rays/s, kernel {} -> {output}",
        if result.interrupted { "interrupted" } else { "done" },
        result.spp,
        rate(result.camera_samples),
        rate(result.rays),
        result.kernel,
    )
}

fn tone_map(tonemap: ToneMapArg) -> ToneMap {
    match tonemap {
        ToneMapArg::Aces => ToneMap::Aces,
        ToneMapArg::Reinhard => ToneMap::Reinhard,
        ToneMapArg::Clamp => ToneMap::Clamp,
    }
}
