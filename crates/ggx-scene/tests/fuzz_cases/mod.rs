//! `GGX_FUZZ_CASES`, the number of cases per property of the fuzz tests (`fuzz.rs`,
//! `readers_fuzz.rs`), read the same way by every test: a `u32`, surrounding whitespace
//! ignored; a value that is not one stops the test with a message rather than falling back
//! to the default.

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
