//! Atomic file output for the bench's text and PNG files: written to a temporary file next to
//! the target, then renamed over it, so an interrupted run never leaves a half-written file.

use std::path::Path;

/// Writes `bytes` to `path` through `.<name>.tmp-<pid>` in the same directory and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let name = path.file_name().ok_or_else(|| format!("{}: not a file path", path.display()))?;
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(name);
    temp_name.push(format!(".tmp-{}", std::process::id()));
    let temp = path.with_file_name(temp_name);
    let result = std::fs::write(&temp, bytes).map_err(|e| format!("{}: {e}", temp.display())).and_then(|()| {
        std::fs::rename(&temp, path).map_err(|e| format!("{}: cannot rename over it: {e}", path.display()))
    });
    if result.is_err() {
        let _ = std::fs::remove_file(&temp);
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn writes_and_replaces() {
        let dir = std::env::temp_dir().join(format!("ggx-bench-files-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("a.txt");
        write_atomic(&path, b"one").unwrap();
        write_atomic(&path, b"two").unwrap();
        assert_eq!(std::fs::read(&path).unwrap(), b"two");
        assert_eq!(std::fs::read_dir(&dir).unwrap().count(), 1, "no temporary file left");
        assert!(write_atomic(&dir.join("missing/a.txt"), b"x").is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
