//! Ctrl-C and SIGTERM: the first asks the renderer to stop (it keeps every completed pass,
//! and the image rendered so far is still written), the second exits at once.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result};
use indicatif::ProgressBar;

use crate::exit::INTERRUPTED;

/// Installs the handler; returns the flag it sets. Messages are printed around `bar`.
pub fn install(bar: ProgressBar) -> Result<Arc<AtomicBool>> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = Arc::clone(&cancel);
    ctrlc::set_handler(move || {
        if flag.swap(true, Ordering::SeqCst) {
            eprintln!("\ninterrupted again: exiting without writing the image");
            std::process::exit(i32::from(INTERRUPTED));
        }
        bar.suspend(|| {
            eprintln!("interrupting: stopping the render, then writing the image so far (Ctrl-C again to quit now)");
        });
    })
    .context("cannot install the Ctrl-C handler")?;
    Ok(cancel)
}
