//! Checks the output path before any work is done, so a long render is never lost to a
//! typo in the file name, a directory that cannot be written, or an input it would destroy.

use std::path::Path;

use anyhow::{Result, bail};
use ggx_film::SUPPORTED_EXTENSIONS;

/// Fails unless `ggx_film::write_image` can write `path` (a supported extension, a directory
/// in which a file can be created, nothing but a regular file to replace: see
/// `ggx_film::check_output`) and `path` is none of `inputs` (through links and other names).
pub fn check(path: &Path, inputs: &[&Path]) -> Result<()> {
    let shown = path.display();
    let supported = SUPPORTED_EXTENSIONS.map(|e| format!(".{e}")).join(", ");
    match path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()) {
        Some(ext) if SUPPORTED_EXTENSIONS.contains(&ext.as_str()) => {}
        Some(ext) => bail!("{shown}: unsupported output format `.{ext}` (supported: {supported})"),
        None => bail!("{shown}: the output file needs an extension ({supported})"),
    }
    check_not_input(path, inputs)?;
    ggx_film::check_output(path)?;
    Ok(())
}

/// Fails unless the statistics file `path` can be written (see `ggx_film::check_file`): it
/// must end in `.json`, differ from the image `output` and be none of `inputs`.
pub fn check_stats(path: &Path, output: &Path, inputs: &[&Path]) -> Result<()> {
    check_side_file(path, "json", "statistics", output, inputs)
}

/// Fails unless the file `path` written beside the image (the `what` file) can be written: it
/// must end in `.ext`, differ from the image `output` and be none of `inputs`.
pub fn check_side_file(path: &Path, ext: &str, what: &str, output: &Path, inputs: &[&Path]) -> Result<()> {
    let shown = path.display();
    if !path.extension().is_some_and(|e| e.eq_ignore_ascii_case(ext)) {
        bail!("{shown}: the {what} file must end in .{ext}");
    }
    if path == output || same_file(path, output) || lexical(path) == lexical(output) {
        bail!("{shown}: is also the image output");
    }
    check_not_input(path, inputs)?;
    ggx_film::check_file(path)?;
    Ok(())
}

/// `path` made absolute and normalized without touching the file system (`.` dropped, `..`
/// taken back), so that two spellings of a file that does not exist yet compare equal.
fn lexical(path: &Path) -> std::path::PathBuf {
    use std::path::Component;
    let absolute = std::env::current_dir().map(|d| d.join(path)).unwrap_or_else(|_| path.to_owned());
    let mut out = std::path::PathBuf::new();
    for c in absolute.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir => {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// Fails when `path` is one of `inputs` (the files a loaded scene reads).
pub fn check_not_input(path: &Path, inputs: &[&Path]) -> Result<()> {
    match inputs.iter().find(|input| same_file(path, input)) {
        Some(input) => bail!("{}: is the input {}; refusing to overwrite it", path.display(), input.display()),
        None => Ok(()),
    }
}

/// Whether `a` and `b` name the same existing file (links followed).
fn same_file(a: &Path, b: &Path) -> bool {
    match (std::fs::metadata(a), std::fs::metadata(b)) {
        #[cfg(unix)]
        (Ok(ma), Ok(mb)) => {
            use std::os::unix::fs::MetadataExt as _;
            (ma.dev(), ma.ino()) == (mb.dev(), mb.ino())
        }
        #[cfg(not(unix))]
        (Ok(_), Ok(_)) => matches!((a.canonicalize(), b.canonicalize()), (Ok(x), Ok(y)) if x == y),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extension_must_be_supported() {
        let msg = check(Path::new("x.jpg"), &[]).unwrap_err().to_string();
        assert_eq!(msg, "x.jpg: unsupported output format `.jpg` (supported: .exr, .png)");
        let msg = check(Path::new("x"), &[]).unwrap_err().to_string();
        assert_eq!(msg, "x: the output file needs an extension (.exr, .png)");
    }

    #[test]
    fn directory_must_exist_and_be_writable() {
        let msg = format!("{:#}", check(Path::new("no/such/dir/x.png"), &[]).unwrap_err());
        assert!(msg.contains("output directory no/such/dir does not exist"), "{msg}");
        let dir = std::env::temp_dir().join(format!("ggx-cli-output-test-{}.png", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let msg = format!("{:#}", check(&dir, &[]).unwrap_err());
        assert!(msg.contains("a directory"), "{msg}");
        let ok = dir.join("fine.png");
        check(&ok, &[]).unwrap();
        assert!(!ok.exists(), "the check leaves nothing behind");
        std::fs::remove_dir(&dir).unwrap();
    }

    #[test]
    fn side_files_are_not_the_output_by_any_spelling() {
        let msg = check_side_file(Path::new("./a/../out.exr"), "exr", "checkpoint", Path::new("out.exr"), &[]);
        assert!(msg.unwrap_err().to_string().contains("is also the image output"));
        let msg = check_side_file(Path::new("c.json"), "exr", "checkpoint", Path::new("out.exr"), &[]);
        assert_eq!(msg.unwrap_err().to_string(), "c.json: the checkpoint file must end in .exr");
    }

    #[test]
    fn the_input_is_never_the_output() {
        let dir = std::env::temp_dir().join(format!("ggx-cli-output-input-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let scene = dir.join("x.png");
        std::fs::write(&scene, "[camera]\n").unwrap();
        let msg = check(&scene, &[&scene]).unwrap_err().to_string();
        assert!(msg.contains("is the input") && msg.contains("refusing to overwrite"), "{msg}");
        // Another name for the same file.
        let other = dir.join(".").join("x.png");
        assert!(check(&other, &[&scene]).is_err());
        check(&dir.join("y.png"), &[&scene]).unwrap();
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
