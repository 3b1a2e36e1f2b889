//! `--a-rev REV` / `--b-rev REV`: the release `ggx` of a git revision, built in a checkout and a
//! target directory of its own under `target/xtask/ab/builds/<commit>/`, and kept there for the
//! next run.
//!
//! Why a target directory of its own: cargo names a workspace crate's artifacts by a hash of its
//! path *relative to the workspace root*, so an old revision checked out elsewhere but built into
//! this checkout's `target/` writes artifacts with the same names, newer than this checkout's
//! sources. The next `cargo build` here then takes them as fresh and links the old revision's
//! crates into the new binary (seen on 2026-12-06: a profile of the "new" binary whose ggx-core
//! came from the old revision, with its hot functions out of line).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Runs `git` in `repo` and returns its trimmed standard output.
fn git(repo: &Path, args: &[&str]) -> Result<String, String> {
    let out = Command::new("git")
        .arg("-C")
        .arg(repo)
        .args(args)
        .stdin(Stdio::null())
        .output()
        .map_err(|e| format!("git {}: {e}", args.join(" ")))?;
    if !out.status.success() {
        let err = String::from_utf8_lossy(&out.stderr);
        return Err(format!("git {} in {}: {}", args.join(" "), repo.display(), err.trim()));
    }
    Ok(String::from_utf8_lossy(&out.stdout).trim().to_owned())
}

/// The full commit hash `rev` names in `repo` (`git rev-parse --verify REV^{commit}`).
pub(super) fn resolve(repo: &Path, rev: &str) -> Result<String, String> {
    if rev.starts_with('-') {
        return Err(format!("`{rev}` is not a revision"));
    }
    git(repo, &["rev-parse", "--verify", "--quiet", &format!("{rev}^{{commit}}")])
        .map_err(|_| format!("`{rev}` names no commit in {}", repo.display()))
}

/// Where commit `commit`'s build lives under `builds`: `<builds>/<first 12 hex digits>/`.
pub(super) fn build_dir(builds: &Path, commit: &str) -> PathBuf {
    builds.join(&commit[..commit.len().min(12)])
}

/// The release `ggx` of revision `rev` of `repo`, built with `cargo` (a program name or path)
/// into `builds` (see the module docs), or the one an earlier run built. The checkout is a
/// detached `git worktree`, removed once the binary is built; a build that fails leaves no
/// binary, so the next run builds again. Returns the binary and the full commit hash.
pub(super) fn build(repo: &Path, rev: &str, builds: &Path, cargo: &Path) -> Result<(PathBuf, String), String> {
    let commit = resolve(repo, rev)?;
    let dir = build_dir(builds, &commit);
    let bin = dir.join("target").join("release").join("ggx");
    if bin.is_file() {
        eprintln!("ab: {rev} ({}) already built: {}", &commit[..12], bin.display());
        return Ok((bin, commit));
    }
    let src = dir.join("src");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    remove_checkout(repo, &src)?;
    let src_arg = src.to_string_lossy().into_owned();
    git(repo, &["worktree", "add", "--detach", "--quiet", &src_arg, &commit])?;
    eprintln!("ab: building {rev} ({}) in {}", &commit[..12], src.display());
    let status = Command::new(cargo)
        .current_dir(&src)
        .args(["build", "--release", "--locked", "-p", "ggx-cli", "--target-dir"])
        .arg(dir.join("target"))
        .env_remove("CARGO_TARGET_DIR")
        .status()
        .map_err(|e| format!("{}: {e}", cargo.display()));
    let removed = remove_checkout(repo, &src);
    let status = status?;
    if !status.success() {
        return Err(format!("building {rev} ({commit}) failed ({status})"));
    }
    removed?;
    if !bin.is_file() {
        return Err(format!("building {rev} ({commit}) made no {}", bin.display()));
    }
    Ok((bin, commit))
}

/// Removes the worktree checkout at `src` (if any) and git's record of it.
fn remove_checkout(repo: &Path, src: &Path) -> Result<(), String> {
    if src.exists() {
        std::fs::remove_dir_all(src).map_err(|e| format!("{}: {e}", src.display()))?;
    }
    git(repo, &["worktree", "prune"]).map(drop)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scratch git repository with two commits whose `marker` file says `one`, then `two`.
    fn repository(dir: &Path) -> PathBuf {
        let repo = dir.join("repo");
        let _ = std::fs::remove_dir_all(&repo);
        std::fs::create_dir_all(&repo).unwrap();
        let run = |args: &[&str]| {
            let ok = Command::new("git")
                .arg("-C")
                .arg(&repo)
                .args(["-c", "user.name=ab", "-c", "user.email=ab@example.com", "-c", "commit.gpgsign=false"])
                .args(args)
                .stdout(Stdio::null())
                .status()
                .unwrap()
                .success();
            assert!(ok, "git {args:?}");
        };
        run(&["init", "--quiet"]);
        for text in ["one", "two"] {
            std::fs::write(repo.join("marker"), text).unwrap();
            run(&["add", "marker"]);
            run(&["commit", "--quiet", "-m", text]);
        }
        repo
    }

    /// A stand-in `cargo` that checks it was asked for a release build of ggx-cli into a
    /// target directory of its own, and writes as `target/release/ggx` the `marker` of the
    /// checkout it runs in; it counts its calls in `calls`; `fail`: exits 1.
    fn stub_cargo(dir: &Path, name: &str, fail: bool) -> PathBuf {
        let calls = dir.join(format!("{name}.calls"));
        let _ = std::fs::remove_file(&calls);
        let body = if fail {
            "exit 1".to_owned()
        } else {
            format!(
                "echo x >> '{}'\n\
                 [ \"$1 $2 $3 $4 $5 $6\" = 'build --release --locked -p ggx-cli --target-dir' ] || exit 3\n\
                 mkdir -p \"$7/release\" && cp marker \"$7/release/ggx\"",
                calls.display()
            )
        };
        super::super::write_shell_script(&dir.join(name), &body)
    }

    /// Each revision is built from its own checkout into its own directory, once: the second
    /// request reuses the binary; the checkouts are gone afterwards; a revision that names no
    /// commit and a failing build are errors, and a failed build leaves no binary.
    #[test]
    fn builds_each_revision_once_in_a_directory_of_its_own() {
        let dir = crate::render::output_dir("ab-test-revision").unwrap();
        let repo = repository(&dir);
        let builds = dir.join("builds");
        let _ = std::fs::remove_dir_all(&builds);
        let cargo = stub_cargo(&dir, "cargo", false);
        let (old, _) = build(&repo, "HEAD~1", &builds, &cargo).unwrap();
        let (new, head) = build(&repo, "HEAD", &builds, &cargo).unwrap();
        assert_eq!(std::fs::read_to_string(&old).unwrap(), "one");
        assert_eq!(std::fs::read_to_string(&new).unwrap(), "two");
        assert_eq!(head, resolve(&repo, "HEAD").unwrap());
        assert_eq!(head.len(), 40);
        assert_eq!(new, build_dir(&builds, &head).join("target/release/ggx"));
        assert_eq!(build(&repo, &head, &builds, &cargo).unwrap(), (new.clone(), head.clone()));
        assert_eq!(std::fs::read_to_string(dir.join("cargo.calls")).unwrap().lines().count(), 2);
        for bin in [&old, &new] {
            assert!(!bin.parent().unwrap().join("../../src").exists(), "{}", bin.display());
        }
        assert_eq!(git(&repo, &["worktree", "list"]).unwrap().lines().count(), 1);

        for bad in ["no-such-branch", "--all", "HEAD~5"] {
            let err = build(&repo, bad, &builds, &cargo).unwrap_err();
            assert!(err.contains(bad), "{err}");
        }
        let _ = std::fs::remove_dir_all(&builds);
        let err = build(&repo, "HEAD", &builds, &stub_cargo(&dir, "broken", true)).unwrap_err();
        assert!(err.contains("failed"), "{err}");
        assert!(!build_dir(&builds, &head).join("target/release/ggx").exists());
        assert_eq!(git(&repo, &["worktree", "list"]).unwrap().lines().count(), 1);
    }
}
