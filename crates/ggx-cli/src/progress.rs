//! The render progress bar on stderr: spp done of the target, camera samples per second,
//! ETA, and elapsed time against the time budget when there is one. When stderr is not a
//! terminal (a log file, a batch job) the bar is hidden and the same figures go out as
//! `progress: ...` lines instead, at most one a second (and always for the pass that
//! reaches the target spp; a render a time budget or a signal ends early closes with its
//! summary line instead).

use std::io::IsTerminal;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Duration;

use ggx_cpu::Progress;
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Resolution of the bar: it counts thousandths of the render.
const STEPS: u64 = 1000;

/// A bar that draws nothing until [`RenderProgress::start`].
pub fn new_bar() -> ProgressBar {
    let target =
        if std::io::stderr().is_terminal() { ProgressDrawTarget::stderr() } else { ProgressDrawTarget::hidden() };
    let bar = ProgressBar::with_draw_target(Some(STEPS), target);
    let style =
        ProgressStyle::with_template("{spinner} [{bar:30}] {msg}").unwrap_or_else(|_| ProgressStyle::default_bar());
    bar.set_style(style.progress_chars("=> "));
    bar
}

/// Least time between two progress lines, in seconds.
const LINE_INTERVAL: f64 = 1.0;

/// Shows a render's [`Progress`] on a bar, or as lines when stderr is not a terminal.
pub struct RenderProgress {
    bar: ProgressBar,
    pixels: u64,
    held: u64,
    budget: Option<Duration>,
    /// Print `progress:` lines (stderr is not a terminal).
    lines: bool,
    /// Render time of the last line printed, as `f64` bits (`-inf` before the first).
    last_line: AtomicU64,
}

impl RenderProgress {
    /// Starts showing `bar` for a render of `pixels` pixels that holds `held` camera samples
    /// already (a resumed render), with an optional time budget in seconds.
    pub fn start(bar: ProgressBar, spp_target: u32, pixels: u64, held: u64, budget: Option<f32>) -> Self {
        let budget = budget.and_then(|b| Duration::try_from_secs_f32(b).ok());
        let lines = !std::io::stderr().is_terminal();
        let last_line = AtomicU64::new(f64::NEG_INFINITY.to_bits());
        let this = Self { bar, pixels, held, budget, lines, last_line };
        this.update(&Progress {
            spp_done: u32::try_from(held / pixels.max(1)).unwrap_or(u32::MAX),
            spp_target,
            samples_done: held,
            samples_target: u64::from(spp_target) * pixels,
            pass_end: false,
            elapsed: Duration::ZERO,
        });
        this.bar.enable_steady_tick(Duration::from_millis(120));
        this
    }

    pub fn update(&self, p: &Progress) {
        let spp_fraction = if p.samples_target == 0 { 1.0 } else { p.samples_done as f64 / p.samples_target as f64 };
        let time_fraction = self.budget.map_or(0.0, |b| p.elapsed.as_secs_f64() / b.as_secs_f64().max(1e-9));
        let fraction = spp_fraction.max(time_fraction).min(1.0);
        self.bar.set_position((fraction * STEPS as f64) as u64);
        self.bar.set_message(self.message(p));
        if self.lines && self.line_due(p) {
            eprintln!("progress: {}", self.message(p));
        }
    }

    /// Whether `p` gets a line: a pass has completed and at least [`LINE_INTERVAL`] went by
    /// since the last line, or it is the last pass; records the line's time.
    fn line_due(&self, p: &Progress) -> bool {
        let now = p.elapsed.as_secs_f64();
        let last = f64::from_bits(self.last_line.load(Ordering::Relaxed));
        let finished = p.samples_done >= p.samples_target && p.pass_end;
        let due = p.samples_done > self.held && (now - last >= LINE_INTERVAL || finished);
        if due {
            self.last_line.store(now.to_bits(), Ordering::Relaxed);
        }
        due
    }

    fn message(&self, p: &Progress) -> String {
        let secs = p.elapsed.as_secs_f64();
        let spp = p.samples_done as f64 / self.pixels.max(1) as f64;
        let mut msg = if spp.fract() == 0.0 {
            format!("{spp}/{} spp", p.spp_target)
        } else {
            format!("{spp:.1}/{} spp", p.spp_target)
        };
        let traced = p.samples_done.saturating_sub(self.held);
        if traced > 0 && secs > 0.0 {
            msg += &format!("  {}", per_second(traced as f64 / secs, "samples"));
        }
        if let Some(budget) = self.budget {
            msg += &format!("  {secs:.1}/{:.1} s", budget.as_secs_f64());
        }
        if let Some(eta) = self.eta(p) {
            msg += &format!("  ETA {}", format_duration(eta));
        }
        msg
    }

    /// Time left: by the spp rate so far, capped by the budget.
    fn eta(&self, p: &Progress) -> Option<f64> {
        let secs = p.elapsed.as_secs_f64();
        let traced = p.samples_done.saturating_sub(self.held);
        let left = p.samples_target.saturating_sub(p.samples_done);
        let by_spp = (traced > 0).then(|| secs * left as f64 / traced as f64);
        let by_budget = self.budget.map(|b| (b.as_secs_f64() - secs).max(0.0));
        match (by_spp, by_budget) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

/// `rate` in millions per second, e.g. `12.35 M samples/s` (as in the final summary).
fn per_second(rate: f64, what: &str) -> String {
    format!("{:.2} M {what}/s", rate * 1e-6)
}

/// `secs` as `42s`, `3m05s` or `2h07m`.
fn format_duration(secs: f64) -> String {
    let s = secs.round().min(1e9) as u64;
    match s {
        0..60 => format!("{s}s"),
        60..3600 => format!("{}m{:02}s", s / 60, s % 60),
        _ => format!("{}h{:02}m", s / 3600, s / 60 % 60),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn progress(spp_done: u32, spp_target: u32, secs: f32) -> Progress {
        Progress {
            spp_done,
            spp_target,
            samples_done: u64::from(spp_done) * 1_000_000,
            samples_target: u64::from(spp_target) * 1_000_000,
            pass_end: true,
            elapsed: Duration::from_secs_f32(secs),
        }
    }

    fn hidden(budget: Option<Duration>) -> RenderProgress {
        let last_line = AtomicU64::new(f64::NEG_INFINITY.to_bits());
        RenderProgress { bar: ProgressBar::hidden(), pixels: 1_000_000, held: 0, budget, lines: true, last_line }
    }

    #[test]
    fn lines_come_at_most_once_a_second_and_for_the_last_pass() {
        let p = hidden(None);
        let due: Vec<bool> = [(0, 0.0), (1, 0.1), (2, 0.5), (4, 1.2), (8, 1.9), (16, 2.3), (32, 2.4)]
            .iter()
            .map(|&(spp, t)| p.line_due(&progress(spp, 32, t)))
            .collect();
        assert_eq!(due, [false, true, false, true, false, true, true]);
    }

    #[test]
    fn message_shows_rate_budget_and_eta() {
        let p = hidden(None);
        assert_eq!(p.message(&progress(0, 64, 0.0)), "0/64 spp");
        assert_eq!(p.message(&progress(16, 64, 2.0)), "16/64 spp  8.00 M samples/s  ETA 6s");
        let p = hidden(Some(Duration::from_secs(10)));
        assert_eq!(p.message(&progress(0, 1000, 0.0)), "0/1000 spp  0.0/10.0 s  ETA 10s");
        assert_eq!(p.message(&progress(4, 1000, 2.0)), "4/1000 spp  2.00 M samples/s  2.0/10.0 s  ETA 8s");
    }

    #[test]
    fn tiles_move_the_message_and_resumed_samples_are_not_a_rate() {
        let mut p = hidden(None);
        let mut mid = progress(16, 64, 2.0);
        mid.samples_done += 500_000;
        assert_eq!(p.message(&mid), "16.5/64 spp  8.25 M samples/s  ETA 6s");
        p.held = 16_000_000;
        assert_eq!(p.message(&progress(16, 64, 0.0)), "16/64 spp");
        assert!(!p.line_due(&progress(16, 64, 0.0)), "nothing traced yet");
        assert_eq!(p.message(&progress(32, 64, 2.0)), "32/64 spp  8.00 M samples/s  ETA 4s");
    }

    #[test]
    fn durations_and_rates() {
        assert_eq!(format_duration(59.4), "59s");
        assert_eq!(format_duration(185.0), "3m05s");
        assert_eq!(format_duration(7620.0), "2h07m");
        assert_eq!(format_duration(f64::INFINITY), "277777h46m");
        assert_eq!(per_second(1.5e4, "rays"), "0.01 M rays/s");
        assert_eq!(per_second(2.5e9, "rays"), "2500.00 M rays/s");
    }
}
