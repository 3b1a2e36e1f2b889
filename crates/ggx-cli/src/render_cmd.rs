//! `ggx render`: load, apply overrides, render each frame with a progress bar, write the image
//! (also after Ctrl-C), the checkpoints and statistics, and print a summary.

use std::cell::{Cell, RefCell};
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use ggx_cpu::{Progress, RenderControl, RenderOptions, RenderResult, Renderer};
use ggx_film::{Film, FilmInfo, OutputOptions, ToneMap};
use ggx_scene::Scene;
use ggx_wgpu::{GpuContext, GpuError, WgpuRenderer};
use indicatif::ProgressBar;

use crate::args::{Backend, RenderArgs, ToneMapArg};
use crate::backend::{self, Device};
use crate::exit::Outcome;
use crate::interrupt::{Interrupt, Phase};
use crate::progress::RenderProgress;
use crate::stats::{self, PassLog, Stats};
use crate::{accel, film_out, frames, memory, output, overrides};

/// Runs `ggx render`.
pub fn run(args: &RenderArgs) -> Result<Outcome> {
    // Signals are honoured from the start: until rendering begins they exit at once.
    let bar = crate::progress::new_bar();
    let interrupt = Interrupt::install(bar.clone())?;
    // Everything that can be checked without rendering is checked first.
    let device = backend::select(args.backend)?;
    let first_output = frames::output_path(&args.output, args.frames.map(|f| f[0]))?;
    output::check(&first_output, &[&args.scene])?;
    // A part (of the samples or the pixels) is only useful as an exact film.
    if let Some(flag) = [("--samples", args.samples.is_some()), ("--crop", args.crop.is_some())]
        .into_iter()
        .find_map(|(name, on)| on.then_some(name))
    {
        film_out::require_exr(&first_output, flag)?;
    }
    if let Some(path) = &args.checkpoint {
        film_out::require_exr(path, "--checkpoint")?;
        output::check_side_file(path, "exr", "checkpoint", &first_output, &[&args.scene])?;
    }
    if let Some(stats) = &args.stats {
        output::check_stats(&frames::output_path(stats, args.frames.map(|f| f[0]))?, &first_output, &[&args.scene])?;
    }

    let limits = args.limits.limits();
    eprintln!("loading {}", args.scene.display());
    let mut scene = crate::scene_load::load(&args.scene, &limits, &args.gltf)?;
    overrides::apply(&mut scene, args)?;
    let input_files = scene.inputs.clone();
    let inputs: Vec<&Path> = input_files.iter().map(PathBuf::as_path).collect();
    for path in [Some(&first_output), args.stats.as_ref(), args.checkpoint.as_ref()].into_iter().flatten() {
        output::check_not_input(path, &inputs)?;
    }
    memory::check(&scene, &limits)?;
    for warning in scene.warnings() {
        eprintln!("warning: {warning}");
    }

    let frame_list = match (args.frames, args.frame) {
        (Some([a, b]), _) => a..b,
        (None, Some(f)) => f..f + 1,
        (None, None) => 0..1,
    };
    check_frames(&scene, frame_list.clone())?;
    // Everything but the camera, hashed once for every frame.
    let hash = crate::scene_hash::SceneHash::new(&scene);
    for frame in frame_list.clone() {
        // Between frames nothing is being rendered: a signal exits at once.
        interrupt.set_phase(Phase::Preparing);
        scene.set_frame(frame).with_context(|| format!("{}", args.scene.display()))?;
        let out = frames::output_path(&args.output, args.frames.map(|_| frame))?;
        let stats = args.stats.as_ref().map(|s| frames::output_path(s, args.frames.map(|_| frame))).transpose()?;
        if out != first_output {
            output::check(&out, &inputs)?;
        }
        if let Some(stats) = &stats {
            output::check_stats(stats, &out, &inputs)?;
        }
        let target =
            Target { image: &out, stats: stats.as_deref(), frame, scene_hash: hash.with_camera(&scene.camera) };
        if frame_list.len() > 1 {
            eprintln!("frame {frame} ({} of {})", frame - frame_list.start + 1, frame_list.len());
        }
        let outcome = render_frame(&scene, args, &device, &target, bar.clone(), &interrupt)?;
        if outcome == Outcome::Interrupted {
            return Ok(outcome);
        }
    }
    Ok(Outcome::Done)
}

/// Whether an EXR output carries the exact film: for a part (of the samples or the pixels)
/// and for a render that checkpoints or continues one, so that it can be merged or resumed.
fn exact(args: &RenderArgs) -> bool {
    args.samples.is_some() || args.crop.is_some() || args.checkpoint.is_some() || args.resume.is_some()
}

/// Where one frame goes and what identifies it.
struct Target<'a> {
    image: &'a Path,
    stats: Option<&'a Path>,
    frame: u32,
    scene_hash: String,
}

/// The backend as a film file names it: what must be the same for two films' bits to add up
/// (the CPU's acceleration structure decides ties between triangles; a GPU's adapter and
/// driver its arithmetic).
fn backend_id(device: &Device, args: &RenderArgs) -> String {
    match device {
        Device::Cpu => format!("cpu {}", accel::name(args.accel)),
        Device::Wgpu(ctx) => format!("wgpu {}", ctx.describe()),
    }
}

/// Renders one frame of `scene` to `target`.
fn render_frame(
    scene: &Scene,
    args: &RenderArgs,
    device: &Device,
    target: &Target<'_>,
    bar: ProgressBar,
    interrupt: &Interrupt,
) -> Result<Outcome> {
    let out = target.image;
    let spp = scene.integrator.spp.max(1);
    let mut info = FilmInfo {
        scene: args.scene.display().to_string(),
        scene_hash: target.scene_hash.clone(),
        seed: scene.integrator.seed,
        frame: target.frame,
        samples: args.samples.unwrap_or([0, spp]),
        total: spp.max(args.samples.map_or(0, |s| s[1])),
        window: args.crop.unwrap_or([0, 0, scene.camera.resolution[0], scene.camera.resolution[1]]),
        backend: backend_id(device, args),
        version: env!("CARGO_PKG_VERSION").to_owned(),
        stats: Vec::new(),
    };
    let [width, height] = scene.camera.resolution;
    let mut start_film = None;
    if let Some(path) = &args.resume {
        let (saved, film) = film_out::read_for_resume(path, &info)?;
        (info.samples, info.window) = film_out::resumed_job(&saved, args.samples, args.crop)?;
        info.total = saved.total.max(info.samples[1]);
        let held: u64 = film.pixels().iter().map(|p| u64::from(p.samples)).sum();
        let [a, b] = info.samples;
        eprintln!("continuing {}: {held} camera samples of {a}..{b} held", path.display());
        start_film = Some((path, film));
    }
    let options = RenderOptions {
        threads: usize::from(args.threads),
        specialize: !args.generic,
        samples: Some(info.samples),
        window: Some(info.window),
    };
    // The range, window and film to continue are checked before the BVH is built.
    let checked = ggx_cpu::Job::new(&options, spp, [width, height])?;
    let film = match start_film {
        Some((path, film)) => {
            checked.check_film(&film, [width, height]).with_context(|| format!("{}", path.display()))?;
            film
        }
        None => Film::try_new(width, height).with_context(|| format!("cannot allocate the {width}x{height} image"))?,
    };

    let passes = PassLog::default();
    let checkpoint = Checkpoint::new(args, &info);
    let job = Job { scene, args, options, passes: &passes, checkpoint: &checkpoint, interrupt };
    let cpu = || (format!("cpu {}", accel::name(args.accel)), stats::cpu_adapter(usize::from(args.threads)));
    let (result, (backend, adapter)) = match device {
        Device::Cpu => (job.cpu(bar, film)?, cpu()),
        Device::Wgpu(ctx) => match job.wgpu(ctx, bar.clone(), film.clone()) {
            Err(e) if args.backend == Backend::Auto && too_large_for_gpu(&e) && args.resume.is_none() => {
                eprintln!("{}: rendering on the CPU", crate::exit::message(&e));
                (job.cpu(bar, film)?, cpu())
            }
            other => (other?, (format!("wgpu {}", ctx.describe()), ctx.describe())),
        },
    };
    info.backend = backend;
    let requested = info.samples[1] - info.samples[0];
    if result.camera_samples == 0 && args.resume.is_none() {
        eprintln!("interrupted before the first pass was done: no image written");
        return Ok(Outcome::Interrupted);
    }
    if result.interrupted {
        eprintln!("interrupted with {} of {requested} spp in every pixel: writing what was rendered", result.spp);
    } else if result.spp < requested {
        let budget = scene.integrator.time_budget.unwrap_or(0.0);
        eprintln!("time budget of {budget} s reached after {} of {requested} spp", result.spp);
    }

    interrupt.set_phase(Phase::Writing);
    let backend_kind = if info.backend.starts_with("cpu") { "cpu" } else { "wgpu" };
    let context = stats::StatsContext {
        scene: &args.scene,
        output: out,
        backend: backend_kind,
        adapter,
        spp_requested: requested,
    };
    let stats = Stats::new(context, &result, passes.passes());
    info.stats = stats.header_pairs();
    let options = OutputOptions { exposure: args.exposure, tonemap: tone_map(args.tonemap) };
    // The errors name the path and what failed.
    film_out::write(out, &result.film, &info, exact(args), &options)?;
    checkpoint.write(&result.film, &info)?;
    if let Some(path) = target.stats {
        stats.write(path)?;
    }

    // A signal that came while a complete image was written still ends with code 130, but
    // the summary says what the image is.
    let line = summary(&result, [width, height], &out.display().to_string());
    writeln!(std::io::stdout(), "{line}").context("cannot write to stdout")?;
    Ok(if result.interrupted || interrupt.requested() { Outcome::Interrupted } else { Outcome::Done })
}

/// `--checkpoint`: the film written every `--checkpoint-every` seconds at the end of a pass.
struct Checkpoint {
    path: Option<PathBuf>,
    every: f64,
    info: RefCell<FilmInfo>,
    last: Cell<Instant>,
    failed: Cell<bool>,
}

impl Checkpoint {
    fn new(args: &RenderArgs, info: &FilmInfo) -> Self {
        Checkpoint {
            path: args.checkpoint.clone(),
            every: f64::from(args.checkpoint_every),
            info: RefCell::new(info.clone()),
            last: Cell::new(Instant::now()),
            failed: Cell::new(false),
        }
    }

    /// Writes the film when the interval has passed since the last write; a failure is
    /// reported once and the render goes on (the final write reports it as an error).
    fn on_pass(&self, film: &Film) {
        let Some(path) = &self.path else { return };
        if self.last.get().elapsed().as_secs_f64() < self.every {
            return;
        }
        self.last.set(Instant::now());
        if let Err(e) = film_out::write(path, film, &self.info.borrow(), true, &OutputOptions::default())
            && !self.failed.replace(true)
        {
            eprintln!("warning: checkpoint not written: {}", crate::exit::message(&e));
        }
    }

    /// Names the backend that renders (the CPU after a GPU fallback), before any write.
    fn set_backend(&self, backend: String) {
        self.info.borrow_mut().backend = backend;
    }

    /// The final write, at the end of the render (also after Ctrl-C).
    fn write(&self, film: &Film, info: &FilmInfo) -> Result<()> {
        match &self.path {
            Some(path) => film_out::write(path, film, info, true, &OutputOptions::default()),
            None => Ok(()),
        }
    }
}

/// One frame's render, on either backend.
struct Job<'a> {
    scene: &'a Scene,
    args: &'a RenderArgs,
    options: RenderOptions,
    passes: &'a PassLog,
    checkpoint: &'a Checkpoint,
    interrupt: &'a Interrupt,
}

impl Job<'_> {
    /// Builds the BVH and renders on the CPU.
    fn cpu(&self, bar: ProgressBar, film: Film) -> Result<RenderResult> {
        self.checkpoint.set_backend(format!("cpu {}", accel::name(self.args.accel)));
        let renderer = Renderer::new(self.scene, accel::kind(self.args.accel));
        let where_ = format!(
            "the CPU, {} built in {}",
            accel::name(self.args.accel),
            accel::format_build_time(renderer.build_time())
        );
        self.announce(&where_);
        self.run(bar, film, |control, film| Ok(renderer.render_film(&self.options, control, film)?))
    }

    /// Uploads the scene and renders on the GPU.
    fn wgpu(&self, ctx: &GpuContext, bar: ProgressBar, film: Film) -> Result<RenderResult> {
        self.checkpoint.set_backend(format!("wgpu {}", ctx.describe()));
        let renderer = WgpuRenderer::new(self.scene, ctx)?;
        self.announce(&format!("{}, BVH2", ctx.adapter_info().name));
        self.run(bar, film, |control, film| Ok(renderer.render_film(&self.options, control, film)?))
    }

    /// Runs `render` with the progress display, the pass log, the checkpoints and the cancel
    /// flag hooked in.
    fn run(
        &self,
        bar: ProgressBar,
        film: Film,
        render: impl FnOnce(&RenderControl<'_>, Film) -> Result<RenderResult>,
    ) -> Result<RenderResult> {
        let progress = self.progress(bar, &film);
        let on_progress = |p: Progress| {
            if p.pass_end {
                self.passes.record(&p);
            }
            progress.update(&p);
        };
        let on_pass = |film: &Film| self.checkpoint.on_pass(film);
        let control = RenderControl {
            cancel: Some(self.interrupt.cancel_flag()),
            progress: Some(&on_progress),
            pass_film: Some(&on_pass),
        };
        let result = render(&control, film);
        progress.finish();
        result
    }

    /// The line that says what is rendered where.
    fn announce(&self, where_: &str) {
        let [width, height] = self.scene.camera.resolution;
        let kernel = if self.args.generic { "generic kernel" } else { "specialized kernel" };
        let [a, b] = self.options.samples.unwrap_or_default();
        let range = if a == 0 { format!("{b} spp") } else { format!("samples {a}..{b}") };
        let window = match self.options.window {
            Some([x0, y0, x1, y1]) if [x1 - x0, y1 - y0] != [width, height] => format!(", pixels {x0},{y0},{x1},{y1}"),
            _ => String::new(),
        };
        eprintln!(
            "rendering {} on {where_}: {width}x{height}{window}, {range}{}, {kernel}",
            self.args.scene.display(),
            self.scene.integrator.time_budget.map_or(String::new(), |t| format!(" or {t} s")),
        );
        self.interrupt.set_phase(Phase::Rendering);
    }

    /// The progress display for this job, starting from what `film` holds.
    fn progress(&self, bar: ProgressBar, film: &Film) -> RenderProgress {
        let [a, b] = self.options.samples.unwrap_or_default();
        let [x0, y0, x1, y1] = self.options.window.unwrap_or_default();
        let pixels = u64::from(x1 - x0) * u64::from(y1 - y0);
        let held = film.pixels().iter().map(|p| u64::from(p.samples)).sum();
        RenderProgress::start(bar, b - a, pixels, held, self.scene.integrator.time_budget)
    }
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

/// The film crate's tone map for `--tonemap`.
pub fn tone_map(tonemap: ToneMapArg) -> ToneMap {
    match tonemap {
        ToneMapArg::Aces => ToneMap::Aces,
        ToneMapArg::Reinhard => ToneMap::Reinhard,
        ToneMapArg::Clamp => ToneMap::Clamp,
    }
}

/// Refuses a frame list on a scene without that many frames.
pub fn check_frames(scene: &Scene, frames: std::ops::Range<u32>) -> Result<()> {
    let count = scene.frame_count();
    if frames.end > count {
        bail!("{}: has frames 0..{count}, not {}..{}", scene.source.display(), frames.start, frames.end);
    }
    Ok(())
}
