//! `cargo xtask <command>`: project automation in Rust, so it runs wherever cargo runs
//! (the rust-analyzer convention). Commands:
//!
//! * `ci`: everything CI checks, in order, stopping at the first failure: rustfmt, clippy
//!   with `-D warnings`, the `no_std` build proof, and the whole test suite.

use std::process::{Command, ExitCode};
use std::time::Instant;

/// The crate that proves ggx-core builds without std. It must be built on its own: built
/// together with crates that enable ggx-core's `std` feature, feature unification would
/// pull std in and its `#[panic_handler]` would clash with std's.
const NOSTD_CHECK: &str = "ggx-nostd-check";

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let result = match args.first().map(String::as_str) {
        Some("ci") => ci(),
        _ => {
            eprintln!(
                "usage: cargo xtask ci\n\n  ci    rustfmt check, clippy -D warnings, no_std build check, all tests"
            );
            return ExitCode::from(2);
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("xtask: {e}");
            ExitCode::FAILURE
        }
    }
}

/// Runs `cargo <args>` and fails with the command line if it fails.
fn cargo(args: &[&str]) -> Result<(), String> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let line = format!("cargo {}", args.join(" "));
    eprintln!("\n==> {line}");
    let start = Instant::now();
    let status = Command::new(cargo).args(args).status().map_err(|e| format!("{line}: {e}"))?;
    eprintln!("<== {line}: {:.1} s", start.elapsed().as_secs_f64());
    if status.success() { Ok(()) } else { Err(format!("`{line}` failed ({status})")) }
}

fn ci() -> Result<(), String> {
    let start = Instant::now();
    cargo(&["fmt", "--all", "--check"])?;
    cargo(&["clippy", "--workspace", "--all-targets", "--exclude", NOSTD_CHECK, "--", "-D", "warnings"])?;
    // no_std proofs: the core without default features, and a #![no_std] consumer that
    // defines its own panic handler (a duplicate lang item error if std were linked).
    cargo(&["build", "-p", "ggx-core", "--no-default-features"])?;
    cargo(&["clippy", "-p", NOSTD_CHECK, "--", "-D", "warnings"])?;
    cargo(&["test", "--workspace", "--exclude", NOSTD_CHECK])?;
    eprintln!("\nxtask ci: all checks passed in {:.0} s", start.elapsed().as_secs_f64());
    Ok(())
}
