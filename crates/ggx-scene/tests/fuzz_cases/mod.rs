//! What the fuzz tests (`fuzz.rs`, `readers_fuzz.rs`, `gltf_fuzz.rs`) share:
//! `GGX_FUZZ_CASES`, the number of cases per property, read the same way by every test (a
//! `u32`, surrounding whitespace ignored; a value that is not one stops the test with a
//! message rather than falling back to the default), and [`ran_capped`], which reruns a test
//! in a child process with its address space capped.

#![allow(dead_code)] // each test binary uses its own subset

/// Address space of the child process [`ran_capped`] runs a test in.
pub const ADDRESS_SPACE_CAP: u64 = 1 << 30;

/// On Linux, outside the child: runs test `name` of this binary in a child process with its
/// address space capped at [`ADDRESS_SPACE_CAP`] (so an allocation sized by an unchecked
/// header aborts the child), asserts that it passed, and returns `true` (the caller returns).
/// In the child (marked by the environment variable `child_var`), or where capping is not
/// available, returns `false` (the caller runs).
pub fn ran_capped(name: &str, child_var: &str) -> bool {
    if !cfg!(target_os = "linux") || std::env::var_os(child_var).is_some() {
        return false;
    }
    let exe = std::env::current_exe().expect("test binary path");
    let script = format!("ulimit -v {} && exec \"$0\" \"$@\"", ADDRESS_SPACE_CAP / 1024);
    let output = std::process::Command::new("sh")
        .args(["-c", &script])
        .arg(&exe)
        .args(["--exact", name, "--nocapture", "--test-threads=1"])
        .env(child_var, "1")
        .output();
    let Ok(output) = output else { return false };
    let text = format!("{}{}", String::from_utf8_lossy(&output.stdout), String::from_utf8_lossy(&output.stderr));
    assert!(output.status.success(), "{name} failed under a {ADDRESS_SPACE_CAP}-byte address space cap:\n{text}");
    assert!(text.contains("1 passed"), "{name} did not run in the child:\n{text}");
    true
}

/// Cases per property: `GGX_FUZZ_CASES` when set, else `default`.
///
/// # Panics
///
/// When `GGX_FUZZ_CASES` is set but is not a number of cases.
pub fn fuzz_cases(default: u32) -> u32 {
    parse_cases(std::env::var("GGX_FUZZ_CASES").ok().as_deref(), default)
}

/// `value` (of `GGX_FUZZ_CASES`) as a number of cases, `default` when it is `None`.
///
/// # Panics
///
/// When `value` is not a `u32`.
pub fn parse_cases(value: Option<&str>, default: u32) -> u32 {
    match value {
        None => default,
        Some(v) => v
            .trim()
            .parse()
            .unwrap_or_else(|e| panic!("GGX_FUZZ_CASES must be a number of cases (0 to {}), got {v:?}: {e}", u32::MAX)),
    }
}

#[test]
fn fuzz_cases_parse_as_u32() {
    assert_eq!(parse_cases(None, 96), 96);
    assert_eq!(parse_cases(Some(" 12\n"), 96), 12);
    for bad in ["", "abc", "-1", "4294967296", "1e3"] {
        let panicked = std::panic::catch_unwind(|| parse_cases(Some(bad), 96));
        let message = panicked.expect_err(bad);
        let text = message.downcast_ref::<String>().map_or("", String::as_str);
        assert!(text.starts_with("GGX_FUZZ_CASES must be a number of cases"), "{bad:?}: {text}");
    }
}
