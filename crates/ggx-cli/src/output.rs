//! Checks the output path before any work is done, so a long render is never lost to a
//! typo in the file name.

use std::path::Path;

use anyhow::{Result, bail};
use ggx_film::SUPPORTED_EXTENSIONS;

/// Fails unless `path` has an extension `ggx_film::write_image` understands, its
/// directory exists and it is not itself a directory.
pub fn check(path: &Path) -> Result<()> {
    let shown = path.display();
    let supported = SUPPORTED_EXTENSIONS.map(|e| format!(".{e}")).join(", ");
    match path.extension().map(|e| e.to_string_lossy().to_ascii_lowercase()) {
        Some(ext) if SUPPORTED_EXTENSIONS.contains(&ext.as_str()) => {}
        Some(ext) => bail!("{shown}: unsupported output format `.{ext}` (supported: {supported})"),
        None => bail!("{shown}: the output file needs an extension ({supported})"),
    }
    let dir = match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => dir,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        bail!("{shown}: output directory {} does not exist", dir.display());
    }
    if path.is_dir() {
        bail!("{shown}: is a directory");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn extension_must_be_supported() {
        check(Path::new("x.png")).unwrap();
        check(Path::new("./x.EXR")).unwrap();
        let msg = check(Path::new("x.jpg")).unwrap_err().to_string();
        assert_eq!(msg, "x.jpg: unsupported output format `.jpg` (supported: .exr, .png)");
        let msg = check(Path::new("x")).unwrap_err().to_string();
        assert_eq!(msg, "x: the output file needs an extension (.exr, .png)");
    }

    #[test]
    fn directory_must_exist() {
        let msg = check(Path::new("no/such/dir/x.png")).unwrap_err().to_string();
        assert_eq!(msg, "no/such/dir/x.png: output directory no/such/dir does not exist");
        let dir = std::env::temp_dir().join(format!("ggx-cli-output-test-{}.png", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert!(check(&dir).unwrap_err().to_string().ends_with("is a directory"));
        std::fs::remove_dir(&dir).unwrap();
    }
}
