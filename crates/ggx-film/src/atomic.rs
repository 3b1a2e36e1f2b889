//! Atomic file replacement: write a temporary file next to the target, then rename it over.
//!
//! What replacing a file keeps and refuses:
//! * A symbolic link is followed: the link stays, the file it points to (through any chain
//!   of links) is replaced, in that file's directory.
//! * The replaced file's permission bits (and, where the process may set them, owner and
//!   group) are given to the new file.
//! * Anything but a regular file (a directory, FIFO, socket or device) is refused.
//! * Temporary files being written are registered, so that a signal handler that must exit
//!   at once can remove them ([`remove_pending_temp_files`]).

use std::ffi::{OsStr, OsString};
use std::fs::{self, File, OpenOptions};
use std::io::{self, BufWriter, ErrorKind};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicU64, Ordering};

use crate::OutputError;

/// Distinguishes temporary files of concurrent writes within one process.
static COUNTER: AtomicU64 = AtomicU64::new(0);

/// Temporary files created and not yet renamed or removed.
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Attempts at finding an unused temporary name before giving up.
const MAX_ATTEMPTS: u32 = 64;

/// Most symbolic links followed when resolving an output path (Linux's own limit).
const MAX_LINKS: u32 = 40;

/// Runs `write` on a new temporary file `.<name>.tmp-<pid>-<counter>` in the directory of the
/// file `path` names (after following symbolic links), flushes and syncs it, gives it the
/// replaced file's mode and owner, then renames it over that file. On any error (or a panic
/// in `write`) the temporary file is removed and the target is untouched.
pub(crate) fn write_atomically<F>(path: &Path, write: F) -> Result<(), OutputError>
where
    F: FnOnce(&mut BufWriter<File>) -> Result<(), OutputError>,
{
    let io_error = |action: String, source: io::Error| OutputError::Io { path: path.to_owned(), action, source };
    let target = resolve_target(path).map_err(|(action, e)| io_error(action, e))?;
    let existing = existing_file(&target).map_err(|(action, e)| io_error(action, e))?;
    let (dir, name) = split(&target).map_err(|(action, e)| io_error(action, e))?;
    let (file, guard) = create_temp(dir, name)
        .map_err(|e| io_error(format!("cannot create a temporary file in {}", dir.display()), e))?;
    // Before any byte is written, so a private image is never readable by others meanwhile.
    if let Some(meta) = &existing {
        keep_mode_and_owner(&file, meta).map_err(|e| io_error("cannot give it the replaced file's mode".into(), e))?;
    }
    let mut writer = BufWriter::new(file);
    write(&mut writer)?;
    let file = writer.into_inner().map_err(|e| io_error("cannot write the image".into(), e.into_error()))?;
    file.sync_all().map_err(|e| io_error("cannot flush the image to disk".into(), e))?;
    drop(file);
    fs::rename(guard.path(), &target)
        .map_err(|e| io_error(format!("cannot rename {} over {}", guard.path().display(), target.display()), e))?;
    guard.renamed();
    sync_dir(dir);
    Ok(())
}

/// Checks, before any work is done, that [`write_atomically`] can create its temporary file
/// next to the file `path` names and replace that file: creates the temporary file and
/// removes it again.
pub(crate) fn check_replaceable(path: &Path) -> Result<(), OutputError> {
    let io_error = |action: String, source: io::Error| OutputError::Io { path: path.to_owned(), action, source };
    let target = resolve_target(path).map_err(|(action, e)| io_error(action, e))?;
    existing_file(&target).map_err(|(action, e)| io_error(action, e))?;
    let (dir, name) = split(&target).map_err(|(action, e)| io_error(action, e))?;
    let (file, guard) =
        create_temp(dir, name).map_err(|e| io_error(format!("cannot create a file in {}", dir.display()), e))?;
    drop(file);
    let removed = fs::remove_file(guard.path());
    let probe = guard.path().display().to_string();
    // Dropping the guard unregisters the probe (and retries the removal).
    drop(guard);
    removed.map_err(|e| io_error(format!("cannot remove the test file {probe}"), e))
}

/// Removes every temporary image file this process is writing. For a signal handler that
/// exits at once: the targets stay untouched and no `.NAME.tmp-PID-N` file is left behind.
pub fn remove_pending_temp_files() {
    for temp in lock_pending().iter() {
        let _ = fs::remove_file(temp);
    }
}

/// An error with the action that failed.
type Failed = (String, io::Error);

/// The file `path` names: `path` itself, or the end of its chain of symbolic links.
fn resolve_target(path: &Path) -> Result<PathBuf, Failed> {
    let mut current = path.to_owned();
    for _ in 0..MAX_LINKS {
        match fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = fs::read_link(&current)
                    .map_err(|e| (format!("cannot read the symbolic link {}", current.display()), e))?;
                current = match current.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            // Not a link, or nothing there yet: this is the file to write.
            _ => return Ok(current),
        }
    }
    let e = io::Error::other(format!("more than {MAX_LINKS} levels of symbolic links"));
    Err(("cannot follow the symbolic link".into(), e))
}

/// The metadata of the file to replace, `None` when there is none; an error when something
/// other than a regular file stands there.
fn existing_file(target: &Path) -> Result<Option<fs::Metadata>, Failed> {
    match fs::metadata(target) {
        Ok(meta) if meta.is_file() => Ok(Some(meta)),
        Ok(meta) => {
            let what = if meta.is_dir() { "a directory" } else { "not a regular file (a FIFO, socket or device)" };
            let action = format!("refusing to replace {}", target.display());
            Err((action, io::Error::other(format!("it is {what}"))))
        }
        Err(e) if e.kind() == ErrorKind::NotFound => Ok(None),
        Err(e) => Err((format!("cannot inspect {}", target.display()), e)),
    }
}

/// Directory (`.` for a bare name) and file name of `target`.
fn split(target: &Path) -> Result<(&Path, &OsStr), Failed> {
    let Some(name) = target.file_name() else {
        return Err(("not a file path".into(), io::Error::from(ErrorKind::InvalidInput)));
    };
    let dir = match target.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    if !dir.is_dir() {
        let e = io::Error::from(ErrorKind::NotFound);
        return Err((format!("output directory {} does not exist", dir.display()), e));
    }
    Ok((dir, name))
}

/// Creates `dir/.<name>.tmp-<pid>-<counter>` exclusively, skipping names that already exist,
/// and registers it (under the registry's lock, so a signal handler never misses it).
fn create_temp(dir: &Path, name: &OsStr) -> io::Result<(File, Pending)> {
    let mut last = io::Error::from(ErrorKind::AlreadyExists);
    for _ in 0..MAX_ATTEMPTS {
        let mut temp_name = OsString::from(".");
        temp_name.push(name);
        temp_name.push(format!(".tmp-{}-{}", std::process::id(), COUNTER.fetch_add(1, Ordering::Relaxed)));
        let temp = dir.join(temp_name);
        let mut pending = lock_pending();
        match OpenOptions::new().write(true).create_new(true).open(&temp) {
            Ok(file) => {
                pending.push(temp.clone());
                return Ok((file, Pending { temp, renamed: false }));
            }
            Err(e) if e.kind() == ErrorKind::AlreadyExists => last = e,
            Err(e) => return Err(e),
        }
    }
    Err(last)
}

/// Gives `file` the owner and group of `replaced` where allowed, then its permission bits
/// (in that order: a change of owner clears the set-id bits).
fn keep_mode_and_owner(file: &File, replaced: &fs::Metadata) -> io::Result<()> {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt as _;
        let mine = file.metadata()?;
        if (mine.uid(), mine.gid()) != (replaced.uid(), replaced.gid()) {
            // Only root (or the owner, for a group it belongs to) may do this: best effort, as
            // `cp -p` does; the mode is kept either way.
            let _ = std::os::unix::fs::fchown(file, Some(replaced.uid()), Some(replaced.gid()));
        }
    }
    file.set_permissions(replaced.permissions())
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

/// A registered temporary file: deleted and unregistered when dropped, unless renamed.
struct Pending {
    temp: PathBuf,
    renamed: bool,
}

impl Pending {
    fn path(&self) -> &Path {
        &self.temp
    }

    /// The file now has the target's name: unregister it without deleting.
    fn renamed(mut self) {
        self.renamed = true;
    }
}

impl Drop for Pending {
    fn drop(&mut self) {
        if !self.renamed {
            let _ = fs::remove_file(&self.temp);
        }
        lock_pending().retain(|p| p != &self.temp);
    }
}

/// The registry of temporary files; a panic elsewhere never makes it unusable.
fn lock_pending() -> std::sync::MutexGuard<'static, Vec<PathBuf>> {
    PENDING.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scratch(name: &str) -> PathBuf {
        let dir = std::env::temp_dir().join(format!("ggx-film-atomic-{}-{name}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(&dir).unwrap();
        dir
    }

    #[test]
    fn pending_temp_files_are_removed_on_request() {
        let dir = scratch("pending");
        let (file, guard) = create_temp(&dir, OsStr::new("x.png")).unwrap();
        drop(file);
        let temp = guard.path().to_owned();
        assert!(temp.exists() && lock_pending().contains(&temp), "created and registered");
        remove_pending_temp_files();
        assert!(!temp.exists());
        drop(guard);
        assert!(lock_pending().iter().all(|p| p != &temp));
        fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn the_mode_is_kept_before_any_byte_is_written() {
        use std::io::Write as _;
        use std::os::unix::fs::PermissionsExt as _;
        let dir = scratch("mode");
        let target = dir.join("private.png");
        fs::write(&target, b"secret").unwrap();
        fs::set_permissions(&target, fs::Permissions::from_mode(0o600)).unwrap();
        write_atomically(&target, |out| {
            let mode = out.get_ref().metadata().unwrap().permissions().mode() & 0o777;
            assert_eq!(mode, 0o600, "the temporary file is private while it is written");
            out.write_all(b"new").map_err(|e| OutputError::Io {
                path: target.clone(),
                action: "test".into(),
                source: e,
            })
        })
        .unwrap();
        assert_eq!(fs::read(&target).unwrap(), b"new");
        assert_eq!(fs::metadata(&target).unwrap().permissions().mode() & 0o777, 0o600);
        fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn link_chains_end_somewhere() {
        let dir = scratch("links");
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink("b", dir.join("a")).unwrap();
            std::os::unix::fs::symlink("sub/c", dir.join("b")).unwrap();
            assert_eq!(resolve_target(&dir.join("a")).unwrap(), dir.join("sub/c"));
            std::os::unix::fs::symlink("loop", dir.join("loop")).unwrap();
            let (action, e) = resolve_target(&dir.join("loop")).unwrap_err();
            assert!(action.contains("symbolic link") && e.to_string().contains("40 levels"), "{action}: {e}");
        }
        assert_eq!(resolve_target(&dir.join("none.png")).unwrap(), dir.join("none.png"));
        fs::remove_dir_all(&dir).unwrap();
    }
}
