//! `cargo xtask fuzz [--cases N]`: the mutation tests of every reader of user files (scene
//! TOML, OBJ, HDR, EXR, film files) and ggx-core's any-f32 contract, with a long budget.
//!
//! The same tests run in `cargo xtask ci` (through `cargo test`) with a small default budget;
//! here `GGX_FUZZ_CASES` raises it, and the release profile makes the
//! cases cheap. Each target asserts no panic, no abort and bounded memory.

use std::process::Command;
use std::time::Instant;

/// Mutated files per reader by default.
const DEFAULT_CASES: u32 = 20_000;

/// The test targets: (package, test file).
const TARGETS: [(&str, &str); 5] = [
    ("ggx-scene", "fuzz"),
    ("ggx-scene", "readers_fuzz"),
    ("ggx-scene", "gltf_fuzz"),
    ("ggx-film", "film_fuzz"),
    ("ggx-core", "contract"),
];

/// Parses `[--cases N]` and runs every target with that budget.
pub fn run(args: &[String]) -> Result<(), String> {
    let mut cases = DEFAULT_CASES;
    let mut args = args.iter();
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "--cases" => {
                let value = args.next().ok_or("fuzz: --cases needs a value")?;
                cases = value
                    .replace('_', "")
                    .parse()
                    .ok()
                    .filter(|&n: &u32| n > 0)
                    .ok_or_else(|| format!("fuzz: `{value}` is not a case count in [1, {}]", u32::MAX))?;
            }
            a => return Err(format!("fuzz: unknown argument `{a}` (usage: cargo xtask fuzz [--cases N])")),
        }
    }
    let cargo = crate::cargo_program();
    let start = Instant::now();
    for (package, test) in TARGETS {
        let line = format!("GGX_FUZZ_CASES={cases} cargo test --release -p {package} --test {test}");
        eprintln!("\n==> {line}");
        let target_start = Instant::now();
        let status = Command::new(&cargo)
            .args(["test", "--release", "-p", package, "--test", test])
            .env("GGX_FUZZ_CASES", cases.to_string())
            .status()
            .map_err(|e| format!("{line}: {e}"))?;
        eprintln!("<== {line}: {:.1} s", target_start.elapsed().as_secs_f64());
        if !status.success() {
            return Err(format!("`{line}` failed ({status})"));
        }
    }
    eprintln!("\nxtask fuzz: {cases} cases per target passed in {:.0} s", start.elapsed().as_secs_f64());
    Ok(())
}
