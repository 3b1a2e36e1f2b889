//! Ctrl-C and SIGTERM, honoured at once in every phase of `ggx render`:
//!
//! * **preparing** (loading the scene, building the BVH, uploading to the GPU): nothing has
//!   been rendered, so the process exits at once;
//! * **rendering**: the first signal stops the render after the tiles in flight (it keeps
//!   every completed pass and the image is still written), the second exits at once;
//! * **writing**: a first signal lets the write finish (the image on disk is complete); a
//!   second removes the temporary file being written and exits at once, leaving any old
//!   image untouched.
//!
//! Signals are counted over the whole run, as "press it again to quit now" promises: after
//! a Ctrl-C that stopped the render, the next one quits even while the image is written.
//! The exit code after a signal is always 130.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicU8, AtomicU32, Ordering};

use anyhow::{Context, Result};
use indicatif::ProgressBar;

use crate::exit::INTERRUPTED;

/// What `ggx render` is doing, for the signal handler.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u8)]
pub enum Phase {
    /// Loading, building, uploading: nothing to keep.
    Preparing = 0,
    /// Accumulating passes.
    Rendering = 1,
    /// Writing the image.
    Writing = 2,
}

/// The installed handler's shared state.
#[derive(Debug)]
struct State {
    /// Set by the first signal: the renderer's cancel flag.
    cancel: AtomicBool,
    /// Signals received so far.
    signals: AtomicU32,
    /// The current [`Phase`] as `u8`.
    phase: AtomicU8,
}

/// The handle `ggx render` keeps: the cancel flag and the phase the handler acts on.
#[derive(Clone, Debug)]
pub struct Interrupt(Arc<State>);

impl Interrupt {
    /// Installs the handler in [`Phase::Preparing`]. Messages are printed around `bar`.
    pub fn install(bar: ProgressBar) -> Result<Self> {
        let state = Arc::new(State {
            cancel: AtomicBool::new(false),
            signals: AtomicU32::new(0),
            phase: AtomicU8::new(Phase::Preparing as u8),
        });
        let shared = Arc::clone(&state);
        ctrlc::set_handler(move || on_signal(&shared, &bar)).context("cannot install the Ctrl-C handler")?;
        Ok(Self(state))
    }

    /// Enters `phase`.
    pub fn set_phase(&self, phase: Phase) {
        self.0.phase.store(phase as u8, Ordering::SeqCst);
    }

    /// The flag the renderer polls: set by the first signal.
    pub fn cancel_flag(&self) -> &AtomicBool {
        &self.0.cancel
    }

    /// Whether a signal has been received.
    pub fn requested(&self) -> bool {
        self.0.cancel.load(Ordering::SeqCst)
    }
}

/// The handler (it runs on ctrlc's own thread, so it may print, lock and exit).
fn on_signal(state: &State, bar: &ProgressBar) {
    let count = state.signals.fetch_add(1, Ordering::SeqCst) + 1;
    state.cancel.store(true, Ordering::SeqCst);
    let phase = state.phase.load(Ordering::SeqCst);
    let say = |msg: &str| bar.suspend(|| eprintln!("{msg}"));
    if phase == Phase::Preparing as u8 {
        say("\ninterrupted before rendering started: no image written");
        exit_now();
    } else if phase == Phase::Rendering as u8 {
        if count == 1 {
            say("interrupting: stopping the render, then writing the image so far (Ctrl-C again to quit now)");
        } else {
            say("\ninterrupted again: exiting without writing the image");
            exit_now();
        }
    } else if count == 1 {
        say("interrupted while writing: finishing the image (Ctrl-C again to quit now, without it)");
    } else {
        say("\ninterrupted again: removing the unfinished image and exiting; any old image is untouched");
        exit_now();
    }
}

/// Removes the temporary files of writes in progress and exits with code 130.
fn exit_now() -> ! {
    ggx_film::remove_pending_temp_files();
    std::process::exit(i32::from(INTERRUPTED));
}
