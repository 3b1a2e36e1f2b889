//! Atomic file replacement: write a temporary file next to the target, then rename it over.

use std::ffi::OsString;
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, ErrorKind};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use crate::OutputError;

/// Distinguishes temporary files of concurrent writes within one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Attempts at finding an unused temporary name before giving up.
const MAX_ATTEMPTS: u32 = 64;

/// Runs `write` on a new temporary file `.<name>.tmp-<pid>-<counter>` in `path`'s directory,
/// flushes and syncs it, then renames it over `path`. On any error (or a panic in `write`)
/// the temporary file is removed and `path` is untouched.
pub(crate) fn write_atomically<F>(path: &Path, write: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
{
    let io_error = |action: String, source: io::Error| OutputError::Io { path: path.to_owned(), action, source };
    let Some(name) = path.file_name() else {
        return Err(io_error("not a file path".into(), io::Error::from(ErrorKind::InvalidInput)));
    };
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    let (file, temp) = create_temp(dir, name)
        .map_err(|e| io_error(format!("cannot create a temporary file in {}", dir.display()), e))?;

    let guard = RemoveOnDrop(Some(temp));
    let mut writer = BufWriter::new(file);
    write(&mut writer)?;
    let file = writer.into_inner().map_err(|e| io_error("cannot write the image".into(), e.into_error()))?;
    file.sync_all().map_err(|e| io_error("cannot flush the image to disk".into(), e))?;
    drop(file);
    let temp = guard.0.as_deref().unwrap_or(path);
    fs::rename(temp, path).map_err(|e| io_error(format!("cannot rename {} over it", temp.display()), e))?;
    guard.disarm();
    sync_dir(dir);
    Ok(())
}

/// Creates `dir/.<name>.tmp-<pid>-<counter>` exclusively, skipping names that already exist.
fn create_temp(dir: &Path, name: &std::ffi::OsStr) -> io::Result<(File, PathBuf)> {
    let mut last = io::Error::from(ErrorKind::AlreadyExists);
    for _ in 0..MAX_ATTEMPTS {
        let mut temp_name = OsString::from(".");
        temp_name.push(name);
        temp_name.push(format!(".tmp-{}-{}", std::process::id(), COUNTER.fetch_add(1, Ordering::Relaxed)));
        let temp = dir.join(temp_name);
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => return Ok((file, temp)),
            Err(e) if e.kind() == ErrorKind::AlreadyExists => last = e,
            Err(e) => return Err(e),
        }
    }
    Err(last)
}

/// Makes the rename durable on Unix (best effort; directories cannot be opened on Windows).
fn sync_dir(dir: &Path) {
    #[cfg(unix)]
    if let Ok(d) = File::open(dir) {
        let _ = d.sync_all();
    }
    #[cfg(not(unix))]
    let _ = dir;
}

/// Deletes the temporary file when dropped, unless disarmed after the rename.
struct RemoveOnDrop(Option<PathBuf>);

impl RemoveOnDrop {
    fn disarm(mut self) {
        self.0 = None;
    }
}

impl Drop for RemoveOnDrop {
    fn drop(&mut self) {
        if let Some(p) = self.0.take() {
            let _ = fs::remove_file(p);
        }
    }
}
