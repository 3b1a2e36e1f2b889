//! Exit codes and how errors are shown.

use std::fmt;
use std::process::ExitCode;

/// Exit code of a usage error (clap uses the same).
pub const USAGE: u8 = 2;
/// Exit code after Ctrl-C or SIGTERM (128 + SIGINT).
pub const INTERRUPTED: u8 = 130;

/// How a command that did not fail ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Outcome {
    /// Everything was done.
    Done,
    /// Stopped early by Ctrl-C or SIGTERM.
    Interrupted,
}

impl Outcome {
    /// The process exit code.
    pub fn exit_code(self) -> ExitCode {
        match self {
            Self::Done => ExitCode::SUCCESS,
            Self::Interrupted => ExitCode::from(INTERRUPTED),
        }
    }
}

/// A request that the command line allows but this build cannot serve: exits with code 2.
#[derive(Debug)]
pub struct UsageError(pub &'static str);

impl fmt::Display for UsageError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.0)
    }
}

impl std::error::Error for UsageError {}

/// The exit code for a failed command: 2 for [`UsageError`], else 1.
pub fn error_code(err: &anyhow::Error) -> ExitCode {
    if err.chain().any(|cause| cause.is::<UsageError>()) { ExitCode::from(USAGE) } else { ExitCode::FAILURE }
}

/// The error and its causes joined with `: `, skipping a cause whose text its parent's
/// message already contains (many errors, like `SceneError`, print their source too).
pub fn message(err: &anyhow::Error) -> String {
    let mut out = String::new();
    for cause in err.chain() {
        let text = cause.to_string();
        if !out.contains(&text) {
            if !out.is_empty() {
                out.push_str(": ");
            }
            out.push_str(&text);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use anyhow::Context;

    use super::*;

    #[test]
    fn message_skips_repeated_causes() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "no such file");
        let err = Err::<(), _>(io).context("x.toml: cannot read: no such file").context("loading").unwrap_err();
        assert_eq!(message(&err), "loading: x.toml: cannot read: no such file");
        let err = Err::<(), _>(anyhow::anyhow!("inner")).context("outer").unwrap_err();
        assert_eq!(message(&err), "outer: inner");
    }

    #[test]
    fn usage_errors_exit_2() {
        let err = anyhow::Error::new(UsageError("nope")).context("while rendering");
        assert_eq!(error_code(&err), ExitCode::from(USAGE));
        assert_eq!(error_code(&anyhow::anyhow!("other")), ExitCode::FAILURE);
    }
}
