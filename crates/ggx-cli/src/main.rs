//! `ggx`: renders ggx scenes on the CPU or a GPU, merges renders split across machines,
//! describes scenes and exports them for Mitsuba 3. `ggx --help` for usage.
//!
//! Exit codes: 0 success, 1 error, 2 usage error, 130 interrupted by Ctrl-C or SIGTERM
//! (after writing the image rendered so far).

mod accel;
mod args;
mod backend;
mod exit;
mod export_cmd;
mod film_out;
mod frames;
mod info_cmd;
mod interrupt;
mod limits_args;
mod memory;
mod merge_cmd;
mod mitsuba;
mod output;
mod overrides;
mod progress;
mod render_cmd;
mod runtime_dir;
mod scene_hash;
mod scene_load;
mod stats;

use std::process::ExitCode;

use clap::Parser;

use crate::args::{Cli, Command};
use crate::exit::Outcome;

fn main() -> ExitCode {
    let cli = Cli::parse();
    if let Command::Render(args) = &cli.command
        && args.backend != args::Backend::Cpu
    {
        // Still single-threaded here, as `set_var` requires.
        runtime_dir::ensure_valid();
    }
    let result = match &cli.command {
        Command::Render(args) => render_cmd::run(args),
        Command::Info(args) => info_cmd::run(args).map(|()| Outcome::Done),
        Command::Merge(args) => merge_cmd::run(args),
        Command::Export(args) => export_cmd::run(args),
    };
    match result {
        Ok(outcome) => outcome.exit_code(),
        Err(err) => {
            eprintln!("error: {}", exit::message(&err));
            exit::error_code(&err)
        }
    }
}
