//! `cargo xtask ab --a BIN|--a-rev REV --b BIN|--b-rev REV [--runs N] [--spp N] [--width W]
//! [SCENES...]`: which of two ggx binaries renders faster, measured on a shared machine whose load moves absolute times
//! by 5-15 % from one run to the next.
//!
//! Each run starts both binaries at once, one render thread each, pinned to CPUs 0 and 1 with
//! `taskset` and swapped every run, so that both see the same load; the answer is the median of
//! the per-run ratios of `--stats`' render time (scene load and BVH build excluded), with its
//! quartiles, and whether the two images' pixel data are identical bit for bit. Run a binary
//! against a copy of itself to see the day's noise: on the 2-vCPU Xeon of 2026-12-05, 40 runs
//! gave 0.99x-1.04x on the peer three-spheres and bunny (quartiles within 0.94-1.12), where the
//! medians of five to nine runs one after the other spread from 0.96x to 1.16x. Without two
//! CPUs or `taskset` the two run one after the other, in alternating order. A table goes to
//! stdout and to `target/xtask/ab/report.md`. A side given as a git revision is built first,
//! in a checkout and a target directory of its own ([`revision`]).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use crate::peer::ggx_side::{RenderJob, read_stats, render_args};
use crate::render::{output_dir, scene_name, scene_paths, workspace_root};

mod revision;

/// Printed for `--help` and bad arguments.
const USAGE: &str = "usage: cargo xtask ab --a BIN|--a-rev REV --b BIN|--b-rev REV [--runs N] [--spp N] [--width W]
                      [SCENES...]

  Renders each scene (default: scenes/peer/*.toml) with both ggx binaries at the same time, one
  thread each on CPUs 0 and 1 (swapped every run), and reports the median of the per-run ratios
  of A's render time to B's (above 1: B is faster), its quartiles, and whether the pixels are
  identical. SCENES are names under scenes/ (`cornell`, `peer/bunny`) or paths.

  --a BIN, --b BIN   the two ggx binaries (copy one away before rebuilding the other)
  --a-rev REV, --b-rev REV
                     a side as a git revision instead: its release ggx, built in a checkout and
                     target directory of its own under target/xtask/ab/builds/ (kept for the next
                     run; never build another revision into this checkout's target/: cargo then
                     links its stale crates into this checkout's next build)
  --runs N           paired runs per scene (default 30)
  --spp N            samples per pixel (default 16)
  --width W          image width (default: the scene's)";

/// One side of the comparison, as asked for.
#[derive(Clone, Debug, PartialEq)]
enum Side {
    /// A ggx binary.
    Binary(PathBuf),
    /// A git revision of this checkout, built by [`revision::build`].
    Revision(String),
}

/// What `ab` was asked to do.
#[derive(Clone, Debug, PartialEq)]
struct Request {
    a: Side,
    b: Side,
    runs: usize,
    spp: u32,
    width: Option<u32>,
    scenes: Vec<String>,
}

/// What `ab` measures: [`Request`] with both sides as binaries.
#[derive(Clone, Debug, PartialEq)]
struct Options {
    a: PathBuf,
    b: PathBuf,
    /// How the report names each side: its path, and the revision it was built from.
    labels: [String; 2],
    runs: usize,
    spp: u32,
    width: Option<u32>,
    scenes: Vec<String>,
}

impl Options {
    /// The options of `binaries` (A, B) for `request`, named by `labels`.
    fn new(request: Request, binaries: [PathBuf; 2], labels: [String; 2]) -> Options {
        let Request { runs, spp, width, scenes, .. } = request;
        let [a, b] = binaries;
        Options { a, b, labels, runs, spp, width, scenes }
    }
}

/// Parses the arguments after `ab`.
fn parse(args: &[String]) -> Result<Request, String> {
    let (mut a, mut b, mut runs, mut spp, mut width, mut scenes) = (None, None, 30, 16, None, Vec::new());
    let set = |side: &mut Option<Side>, value: Side, name: &str| match side {
        Some(_) => Err(format!("{name}: A and B are each given once (--a or --a-rev, --b or --b-rev)")),
        None => {
            *side = Some(value);
            Ok(())
        }
    };
    let mut it = args.iter();
    while let Some(arg) = it.next() {
        let mut value = |name: &str| it.next().cloned().ok_or_else(|| format!("{name} needs a value\n\n{USAGE}"));
        let number = |name: &str, v: String| v.parse::<u32>().map_err(|_| format!("{name}: `{v}` is not a count"));
        match arg.as_str() {
            "--a" => set(&mut a, Side::Binary(value("--a")?.into()), "--a")?,
            "--b" => set(&mut b, Side::Binary(value("--b")?.into()), "--b")?,
            "--a-rev" => set(&mut a, Side::Revision(value("--a-rev")?), "--a-rev")?,
            "--b-rev" => set(&mut b, Side::Revision(value("--b-rev")?), "--b-rev")?,
            "--runs" => runs = number("--runs", value("--runs")?)? as usize,
            "--spp" => spp = number("--spp", value("--spp")?)?,
            "--width" => width = Some(number("--width", value("--width")?)?),
            "-h" | "--help" => return Err(USAGE.to_owned()),
            flag if flag.starts_with('-') => return Err(format!("unknown option `{flag}`\n\n{USAGE}")),
            scene => scenes.push(scene.to_owned()),
        }
    }
    let (Some(a), Some(b)) = (a, b) else {
        return Err(format!("both sides are needed (--a or --a-rev, --b or --b-rev)\n\n{USAGE}"));
    };
    if runs == 0 || spp == 0 || width == Some(0) {
        return Err("--runs, --spp and --width must be at least 1".to_owned());
    }
    if scenes.is_empty() {
        scenes = ["three-spheres", "bunny", "anisotropic"].map(|s| format!("peer/{s}")).to_vec();
    }
    Ok(Request { a, b, runs, spp, width, scenes })
}

/// The binary of `side` and how the report names it: a revision is built (or found built)
/// under `target/xtask/ab/builds/`.
fn binary(side: &Side) -> Result<(PathBuf, String), String> {
    match side {
        Side::Binary(bin) if bin.is_file() => Ok((bin.clone(), format!("`{}`", bin.display()))),
        Side::Binary(bin) => Err(format!("{}: no such binary", bin.display())),
        Side::Revision(rev) => {
            let repo = workspace_root();
            let cargo = PathBuf::from(crate::cargo_program());
            let (bin, commit) = revision::build(&repo, rev, &output_dir("ab")?.join("builds"), &cargo)?;
            Ok((bin.clone(), format!("`{}` (revision {rev}, {})", bin.display(), &commit[..12])))
        }
    }
}

/// The first, second and third quartiles of `values` (linear interpolation between order
/// statistics, as numpy's default); NaN for none.
fn quartiles(values: &[f64]) -> [f64; 3] {
    let mut v: Vec<f64> = values.to_vec();
    v.sort_by(f64::total_cmp);
    [0.25, 0.5, 0.75].map(|q| {
        let Some(last) = v.len().checked_sub(1) else { return f64::NAN };
        let x = q * last as f64;
        let (i, f) = (x.floor() as usize, x - x.floor());
        let lo = v.get(i).copied().unwrap_or(f64::NAN);
        let hi = v.get(i + 1).copied().unwrap_or(lo);
        lo + (hi - lo) * f
    })
}

/// How two images' pixels compare.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Pixels {
    /// Every channel of every pixel has the same bits.
    Identical,
    /// `count` pixels differ, by at most `max_abs` in a channel.
    Differ { count: usize, max_abs: f32 },
    /// The images do not have the same size.
    Size,
}

/// Compares the pixel data of two EXR files bit for bit.
fn compare_pixels(a: &Path, b: &Path) -> Result<Pixels, String> {
    let read = |p: &Path| ggx_film::read_exr(p).map_err(|e| e.to_string());
    let ((wa, ha, pa), (wb, hb, pb)) = (read(a)?, read(b)?);
    if (wa, ha) != (wb, hb) || pa.len() != pb.len() {
        return Ok(Pixels::Size);
    }
    let (mut count, mut max_abs) = (0, 0.0f32);
    for (x, y) in pa.iter().zip(&pb) {
        if x.to_array().map(f32::to_bits) != y.to_array().map(f32::to_bits) {
            count += 1;
            max_abs = max_abs.max((*x - *y).abs().max_element());
        }
    }
    Ok(if count == 0 { Pixels::Identical } else { Pixels::Differ { count, max_abs } })
}

/// CPUs to pin A and B to in run `k` (swapped every run), when there are two to pin to.
fn cpus(k: usize) -> [usize; 2] {
    if k.is_multiple_of(2) { [0, 1] } else { [1, 0] }
}

/// True when both renders can run at once, each on a CPU of its own.
fn can_pair() -> bool {
    let two = std::thread::available_parallelism().is_ok_and(|n| n.get() >= 2);
    two && Command::new("taskset").args(["-c", "0", "true"]).stdout(Stdio::null()).status().is_ok_and(|s| s.success())
}

/// Where a render's standard error goes: a file, not a pipe, so that a render that writes much
/// never waits on the other's reader.
fn log_path(job: &RenderJob) -> PathBuf {
    job.stats.with_extension("log")
}

/// Starts `bin`'s render of `job`, pinned to `cpu` when given.
fn start(bin: &Path, job: &RenderJob, cpu: Option<usize>) -> Result<std::process::Child, String> {
    let mut cmd = match cpu {
        Some(c) => {
            let mut cmd = Command::new("taskset");
            cmd.args(["-c", &c.to_string()]).arg(bin);
            cmd
        }
        None => Command::new(bin),
    };
    let log = std::fs::File::create(log_path(job)).map_err(|e| format!("{}: {e}", log_path(job).display()))?;
    cmd.args(render_args(job)).stdout(Stdio::null()).stderr(log);
    cmd.spawn().map_err(|e| format!("{}: {e}", bin.display()))
}

/// Waits for a render started by [`start`] and reads its render time.
fn finish(mut child: std::process::Child, bin: &Path, job: &RenderJob) -> Result<f64, String> {
    let status = child.wait().map_err(|e| format!("{}: {e}", bin.display()))?;
    if !status.success() {
        let log = std::fs::read_to_string(log_path(job)).unwrap_or_default();
        return Err(format!("{} failed on {} ({status}): {}", bin.display(), job.scene.display(), log.trim()));
    }
    Ok(read_stats(job)?.seconds)
}

/// One scene's result.
struct Row {
    scene: String,
    ratio: [f64; 3],
    seconds: [f64; 2],
    pixels: Pixels,
}

/// `runs` paired renders of `scene`.
fn measure(o: &Options, scene: &Path, dir: &Path, paired: bool) -> Result<Row, String> {
    let name = scene_name(scene);
    let files = |tag: &str| (dir.join(format!("{name}-{tag}.exr")), dir.join(format!("{name}-{tag}.json")));
    let ((out_a, stats_a), (out_b, stats_b)) = (files("a"), files("b"));
    let job = |out, stats| RenderJob { scene, out, stats, spp: o.spp, seed: 0, threads: 1, width: o.width };
    let (job_a, job_b) = (job(&out_a, &stats_a), job(&out_b, &stats_b));
    let (mut ratios, mut times_a, mut times_b) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..o.runs {
        let (a, b) = if paired {
            let [ca, cb] = cpus(k);
            let (pa, pb) = (start(&o.a, &job_a, Some(ca))?, start(&o.b, &job_b, Some(cb))?);
            (finish(pa, &o.a, &job_a)?, finish(pb, &o.b, &job_b)?)
        } else if k.is_multiple_of(2) {
            let a = finish(start(&o.a, &job_a, None)?, &o.a, &job_a)?;
            (a, finish(start(&o.b, &job_b, None)?, &o.b, &job_b)?)
        } else {
            let b = finish(start(&o.b, &job_b, None)?, &o.b, &job_b)?;
            (finish(start(&o.a, &job_a, None)?, &o.a, &job_a)?, b)
        };
        ratios.push(a / b);
        times_a.push(a);
        times_b.push(b);
    }
    let pixels = compare_pixels(&out_a, &out_b)?;
    Ok(Row {
        scene: name,
        ratio: quartiles(&ratios),
        seconds: [quartiles(&times_a)[1], quartiles(&times_b)[1]],
        pixels,
    })
}

/// The report: one table row per scene.
fn report(o: &Options, rows: &[Row], paired: bool) -> String {
    let how =
        if paired { "at the same time, pinned to CPUs 0 and 1, swapped every run" } else { "one after the other" };
    let mut s = format!(
        "# ggx A/B\n\nA: {}  \nB: {}  \n{} runs per scene, {} spp, one render thread each, {how}.\n\n\
         | scene | A ÷ B time (median) | quartiles | A median s | B median s | pixels |\n|---|---:|---|---:|---:|---|\n",
        o.labels[0], o.labels[1], o.runs, o.spp
    );
    for r in rows {
        let pixels = match r.pixels {
            Pixels::Identical => "identical".to_owned(),
            Pixels::Differ { count, max_abs } => format!("{count} differ (max {max_abs:e})"),
            Pixels::Size => "sizes differ".to_owned(),
        };
        s += &format!(
            "| {} | {:.3}x | {:.3}-{:.3} | {:.3} | {:.3} | {pixels} |\n",
            r.scene, r.ratio[1], r.ratio[0], r.ratio[2], r.seconds[0], r.seconds[1]
        );
    }
    s
}

/// Runs `ab`.
pub fn run(args: &[String]) -> Result<(), String> {
    let request = parse(args)?;
    let ((a, label_a), (b, label_b)) = (binary(&request.a)?, binary(&request.b)?);
    let o = Options::new(request, [a, b], [label_a, label_b]);
    let scenes = scene_paths(&o.scenes)?;
    let dir = output_dir("ab")?;
    let paired = can_pair();
    let mut rows = Vec::new();
    for scene in &scenes {
        let row = measure(&o, scene, &dir, paired)?;
        eprintln!("{}: A ÷ B {:.3}x ({:.3}-{:.3})", row.scene, row.ratio[1], row.ratio[0], row.ratio[2]);
        rows.push(row);
    }
    let text = report(&o, &rows, paired);
    print!("{text}");
    let path = dir.join("report.md");
    std::fs::write(&path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// Writes `body` as an executable `/bin/sh` script at `path` (the tests' stand-in programs).
#[cfg(test)]
fn write_shell_script(path: &Path, body: &str) -> PathBuf {
    std::fs::write(path, format!("#!/bin/sh\n{body}\n")).unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path.to_owned()
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    fn args(s: &str) -> Vec<String> {
        s.split_whitespace().map(str::to_owned).collect()
    }

    #[test]
    fn parses_options_and_refuses_bad_ones() {
        let o = parse(&args("--a x --b y --runs 5 --spp 4 --width 64 cornell peer/bunny")).unwrap();
        assert_eq!(
            o,
            Request {
                a: Side::Binary("x".into()),
                b: Side::Binary("y".into()),
                runs: 5,
                spp: 4,
                width: Some(64),
                scenes: vec!["cornell".into(), "peer/bunny".into()]
            }
        );
        let o = parse(&args("--b y --a x")).unwrap();
        assert_eq!((o.runs, o.spp, o.width), (30, 16, None));
        assert_eq!(o.scenes, ["peer/three-spheres", "peer/bunny", "peer/anisotropic"]);
        let o = parse(&args("--a-rev HEAD~1 --b target/release/ggx")).unwrap();
        assert_eq!((o.a, o.b), (Side::Revision("HEAD~1".into()), Side::Binary("target/release/ggx".into())));
        let o = parse(&args("--b-rev main --a-rev b5ffe40")).unwrap();
        assert_eq!((o.a, o.b), (Side::Revision("b5ffe40".into()), Side::Revision("main".into())));
        let bad = [
            "--a x",
            "--b y",
            "--a x --b y --runs 0",
            "--a x --b y --spp -1",
            "--a x --b y --frob",
            "--a",
            "--a-rev",
            "--a x --a-rev HEAD --b y",
            "--a-rev HEAD --b-rev HEAD --b-rev HEAD~1",
        ];
        for bad in bad {
            assert!(parse(&args(bad)).is_err(), "{bad}");
        }
        assert!(parse(&args("--a x --a-rev HEAD --b y")).unwrap_err().contains("given once"));
        assert!(parse(&args("--help")).unwrap_err().starts_with("usage"));
    }

    #[test]
    fn quartiles_interpolate_between_order_statistics() {
        assert_eq!(quartiles(&[3.0, 1.0, 2.0, 5.0, 4.0]), [2.0, 3.0, 4.0]);
        assert_eq!(quartiles(&[1.0, 2.0, 3.0, 4.0]), [1.75, 2.5, 3.25]);
        assert_eq!(quartiles(&[7.0]), [7.0; 3]);
        assert!(quartiles(&[]).iter().all(|q| q.is_nan()));
    }

    #[test]
    fn runs_alternate_their_cpus() {
        assert_eq!((0..4).map(cpus).collect::<Vec<_>>(), [[0, 1], [1, 0], [0, 1], [1, 0]]);
    }

    /// A stand-in `ggx` (a shell script under `dir`) whose renders take `seconds` by their
    /// statistics and copy `image` to the output; `fail`: exits 1 with a message instead.
    fn stub(dir: &Path, name: &str, seconds: f64, image: &Path, fail: bool) -> PathBuf {
        let body = if fail {
            "echo 'no such scene' >&2; exit 1".to_owned()
        } else {
            format!(
                "while [ $# -gt 0 ]; do case $1 in -o) out=$2; shift;; --stats) stats=$2; shift;; \
                 --spp) spp=$2; shift;; esac; shift; done\n\
                 cp '{}' \"$out\"\n\
                 echo \"{{\\\"spp\\\": $spp, \\\"seconds\\\": {seconds}, \\\"camera_samples\\\": 4, \\\"width\\\": 2, \\\"height\\\": 2}}\" > \"$stats\"",
                image.display()
            )
        };
        write_shell_script(&dir.join(name), &body)
    }

    /// The runs, paired or one after the other, measure what each binary reports: a binary
    /// whose renders take 0.3 s against one whose take 0.1 s is 3x slower in every run; the
    /// images are compared, and a failing render is an error naming the binary.
    #[test]
    fn measures_the_ratio_of_the_reported_times() {
        let dir = output_dir("ab-test-measure").unwrap();
        let px = [Vec3::new(0.5, 0.25, 1.0), Vec3::ZERO, Vec3::splat(2.0), Vec3::ONE];
        let (image, other) = (dir.join("image.exr"), dir.join("other.exr"));
        let options = ggx_film::OutputOptions::default();
        ggx_film::write_image(&image, 2, 2, &px, &options).unwrap();
        ggx_film::write_image(&other, 2, 2, &px.map(|p| p * 2.0), &options).unwrap();
        let (slow, fast) = (stub(&dir, "slow", 0.3, &image, false), stub(&dir, "fast", 0.1, &image, false));
        let (changed, broken) = (stub(&dir, "changed", 0.1, &other, false), stub(&dir, "broken", 0.1, &image, true));
        let scene = crate::render::scenes_dir().join("cornell.toml");
        let options = |a: &Path, b: &Path| Options {
            a: a.to_owned(),
            b: b.to_owned(),
            labels: [a, b].map(|p| format!("`{}`", p.display())),
            runs: 3,
            spp: 2,
            width: None,
            scenes: vec!["cornell".into()],
        };
        for paired in [false, can_pair()] {
            let row = measure(&options(&slow, &fast), &scene, &dir, paired).unwrap();
            assert_eq!(row.scene, "cornell");
            assert!(row.ratio.iter().all(|r| (r - 3.0).abs() < 1e-12), "{:?}", row.ratio);
            assert_eq!(row.seconds, [0.3, 0.1]);
            assert_eq!(row.pixels, Pixels::Identical);
            let row = measure(&options(&fast, &changed), &scene, &dir, paired).unwrap();
            assert_eq!(row.pixels, Pixels::Differ { count: 3, max_abs: 2.0 });
            let err = measure(&options(&fast, &broken), &scene, &dir, paired).err().unwrap();
            assert!(err.contains("broken") && err.contains("no such scene"), "{err}");
        }
        let report =
            report(&options(&slow, &fast), &[measure(&options(&slow, &fast), &scene, &dir, false).unwrap()], false);
        assert!(report.contains("| cornell | 3.000x | 3.000-3.000 | 0.300 | 0.100 | identical |"), "{report}");
    }

    #[test]
    fn pixels_compare_bit_for_bit() {
        let dir = output_dir("ab-test").unwrap();
        let write = |name: &str, px: &[Vec3], w: u32| {
            let path = dir.join(name);
            let options = ggx_film::OutputOptions::default();
            ggx_film::write_image(&path, w, px.len() as u32 / w, px, &options).unwrap();
            path
        };
        let base = [Vec3::new(0.5, 0.25, 1.0), Vec3::ZERO, Vec3::splat(2.0), Vec3::new(1e-30, 0.0, 3.0)];
        let mut other = base;
        other[1].y = -0.0; // the same value, other bits
        other[3].z = 3.5;
        let (a, b, c) = (write("a.exr", &base, 2), write("b.exr", &base, 2), write("c.exr", &other, 2));
        assert_eq!(compare_pixels(&a, &b).unwrap(), Pixels::Identical);
        assert_eq!(compare_pixels(&a, &c).unwrap(), Pixels::Differ { count: 2, max_abs: 0.5 });
        assert_eq!(compare_pixels(&a, &write("d.exr", &base, 4)).unwrap(), Pixels::Size);
        assert!(compare_pixels(&a, &dir.join("missing.exr")).is_err());
    }
}
