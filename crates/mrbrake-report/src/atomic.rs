//! Safe file output: write to a temporary file beside the target, flush, then rename — unless the
//! target is not a regular file.
//!
//! A rename within one file system replaces the target in one step, so an interrupted run leaves either
//! the old file or the new one, never a truncated mix. Two kinds of targets must not be replaced:
//!
//! * a **symbolic link** is followed to its final target (a dangling link to the file it names), and
//!   the temporary file is put beside that target, so the link stays a link and the file it points
//!   to gets the new contents;
//! * a **FIFO, character or block device or socket** (`/dev/null`, `/dev/stdout`, a named pipe read
//!   by another program) is written directly, without a temporary file: renaming over it would
//!   replace the device node by a regular file. A failed write (`/dev/full`) is reported with the
//!   path.
//!
//! Temporary files in flight are registered ([`pending_temp_files`]) so that a program stopped by a
//! signal can remove them ([`remove_pending_temp_files`]); the `mrbrake` binary does so on SIGINT,
//! SIGTERM and SIGHUP.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use crate::ReportError;

/// Symbolic links followed before giving up (Linux's own limit is 40).
const MAX_SYMLINK_HOPS: usize = 40;

/// Temporary files being written right now (removed from the list once renamed or deleted).
static PENDING: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Writes `bytes` to `path` safely: atomically (temporary file in the target's directory + rename)
/// for a regular or missing file, through a symbolic link to its target, and directly into a FIFO
/// or device (see the module documentation).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    write_atomic_with(path, |tmp| {
        let mut f = std::fs::File::create(tmp)?;
        f.write_all(bytes)?;
        f.sync_all()
    })
}

/// Like [`write_atomic`], for writers that need a file name (an image backend that encodes by file
/// name): `write` creates and fills the temporary file it is given, which is then put in place. For
/// a FIFO or device target the temporary file lives in the system's temporary directory and its
/// contents are copied into the target.
pub fn write_atomic_with(
    path: &Path,
    write: impl FnOnce(&Path) -> std::io::Result<()>,
) -> Result<(), ReportError> {
    let io_err = |source| ReportError::Io { path: path.to_path_buf(), source };
    let target = resolve_symlinks(path).map_err(io_err)?;
    let special = is_special_file(&target);
    let tmp = if special {
        // Named after the path given (its extension tells an image backend the format).
        let name = path.file_name().map_or_else(|| "output".into(), |n| n.to_string_lossy());
        temp_path_for(&std::env::temp_dir().join(name.as_ref()))?
    } else {
        temp_path_for(&target)?
    };
    let _guard = PendingGuard::register(&tmp);
    let result = write(&tmp).and_then(|()| {
        if special { copy_into_special(&tmp, &target) } else { std::fs::rename(&tmp, &target) }
    });
    if special || result.is_err() {
        // Best effort: the temporary file is garbage once copied or once the write failed.
        let _ = std::fs::remove_file(&tmp);
    }
    result.map_err(io_err)
}

/// A temporary file name in the same directory as `path` (hidden, unique to this process), so that a
/// rename onto `path` stays within one file system. It ends in `path`'s extension, for writers that
/// choose the format by the name.
pub fn temp_path_for(path: &Path) -> Result<PathBuf, ReportError> {
    let dir = match path.parent() {
        Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let file_name = path.file_name().ok_or_else(|| ReportError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidInput, "the path names no file"),
    })?;
    static COUNTER: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
    let n = COUNTER.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let extension =
        path.extension().map(|e| format!(".{}", e.to_string_lossy())).unwrap_or_default();
    let name = file_name.to_string_lossy();
    Ok(dir.join(format!(".{name}.tmp-{}-{n}{extension}", std::process::id())))
}

/// A folder of outputs written in full before any of it appears (all or nothing, issue 33): the
/// files go to a hidden sibling folder first ([`StagedDir::write`]); [`StagedDir::commit`] moves
/// them into the target folder once every other output of the command succeeded too. Dropped
/// without a commit (a later step failed), the staged files are removed and the target is
/// untouched.
#[derive(Debug)]
pub struct StagedDir {
    staging: PathBuf,
    target: PathBuf,
}

impl StagedDir {
    /// Runs `write` on a fresh staging folder beside `target`; on its failure nothing is left.
    pub fn write(
        target: &Path,
        write: impl FnOnce(&Path) -> Result<(), ReportError>,
    ) -> Result<Self, ReportError> {
        let staging = temp_path_for(target)?;
        std::fs::create_dir_all(&staging)
            .map_err(|source| ReportError::Io { path: target.to_path_buf(), source })?;
        let staged = Self { staging, target: target.to_path_buf() };
        write(&staged.staging)?;
        Ok(staged)
    }

    /// Moves the staged files into the target folder (created if missing), replacing files of
    /// the same name.
    pub fn commit(self) -> Result<(), ReportError> {
        let io_err = |source| ReportError::Io { path: self.target.clone(), source };
        std::fs::create_dir_all(&self.target).map_err(io_err)?;
        for entry in std::fs::read_dir(&self.staging).map_err(io_err)? {
            let entry = entry.map_err(io_err)?;
            std::fs::rename(entry.path(), self.target.join(entry.file_name())).map_err(io_err)?;
        }
        Ok(())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        // Best effort: after a commit the folder is empty; without one it holds the garbage.
        let _ = std::fs::remove_dir_all(&self.staging);
    }
}

/// The temporary files being written at this moment.
pub fn pending_temp_files() -> Vec<PathBuf> {
    PENDING.lock().map(|list| list.clone()).unwrap_or_default()
}

/// Removes every temporary file being written (for a program about to exit on a signal) and
/// returns how many were removed. Safe to call from any thread; not from a signal handler.
pub fn remove_pending_temp_files() -> usize {
    remove_pending_where(|_| true)
}

/// Removes the pending temporary files `select` picks; returns how many were removed.
fn remove_pending_where(select: impl Fn(&Path) -> bool) -> usize {
    let list = match PENDING.lock() {
        Ok(list) => list.clone(),
        // A writer panicked while holding the lock: the list is still valid.
        Err(poisoned) => poisoned.into_inner().clone(),
    };
    list.iter().filter(|tmp| select(tmp) && std::fs::remove_file(tmp).is_ok()).count()
}

/// Registers a temporary file for [`remove_pending_temp_files`] while it lives.
struct PendingGuard(PathBuf);

impl PendingGuard {
    fn register(tmp: &Path) -> PendingGuard {
        if let Ok(mut list) = PENDING.lock() {
            list.push(tmp.to_path_buf());
        }
        PendingGuard(tmp.to_path_buf())
    }
}

impl Drop for PendingGuard {
    fn drop(&mut self) {
        if let Ok(mut list) = PENDING.lock() {
            list.retain(|p| p != &self.0);
        }
    }
}

/// `path` with every symbolic link in its last component followed (relative link targets are read
/// against the link's directory). A dangling link resolves to the missing file it names, which is
/// then created; a loop of links is an error.
fn resolve_symlinks(path: &Path) -> std::io::Result<PathBuf> {
    let mut current = path.to_path_buf();
    for _ in 0..MAX_SYMLINK_HOPS {
        match std::fs::symlink_metadata(&current) {
            Ok(meta) if meta.file_type().is_symlink() => {
                let link = std::fs::read_link(&current)?;
                current = match current.parent() {
                    Some(dir) if link.is_relative() => dir.join(link),
                    _ => link,
                };
            }
            // A regular file, something special, or nothing yet: this is the target.
            _ => return Ok(current),
        }
    }
    Err(std::io::Error::other(format!(
        "more than {MAX_SYMLINK_HOPS} symbolic links to follow (a loop?)"
    )))
}

/// True for an existing file that is neither a regular file nor a directory: a FIFO, a device, a
/// socket. Such a file is written in place, never replaced.
fn is_special_file(path: &Path) -> bool {
    std::fs::metadata(path).is_ok_and(|meta| !meta.is_file() && !meta.is_dir())
}

/// Copies the finished temporary file into the FIFO or device `target`, opened for writing without
/// creating or truncating it.
fn copy_into_special(tmp: &Path, target: &Path) -> std::io::Result<()> {
    let mut source = std::fs::File::open(tmp)?;
    let mut sink = std::fs::OpenOptions::new().write(true).open(target)?;
    std::io::copy(&mut source, &mut sink)?;
    sink.flush()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_staged_folder_appears_only_on_commit() {
        let dir = tempfile::tempdir().unwrap();
        let target = dir.path().join("plots");
        let failed = StagedDir::write(&target, |d| {
            std::fs::write(d.join("a.svg"), "a").unwrap();
            Err(ReportError::Io { path: d.to_path_buf(), source: std::io::ErrorKind::Other.into() })
        });
        assert!(failed.is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0, "nothing left behind");
        let staged = StagedDir::write(&target, |d| {
            std::fs::write(d.join("a.svg"), "a")
                .map_err(|source| ReportError::Io { path: d.to_path_buf(), source })
        })
        .unwrap();
        assert!(!target.exists());
        staged.commit().unwrap();
        assert_eq!(std::fs::read_to_string(target.join("a.svg")).unwrap(), "a");
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1, "the staging folder is gone");
    }
    use mrbrake_error::Kind as _;

    fn temp_leftovers(dir: &Path) -> Vec<String> {
        std::fs::read_dir(dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .map(|e| e.file_name().to_string_lossy().into_owned())
            .filter(|name| name.contains(".tmp-"))
            .collect()
    }

    #[test]
    fn writes_and_replaces() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.txt");
        write_atomic(&p, b"first").unwrap();
        write_atomic(&p, b"second").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        assert!(temp_leftovers(dir.path()).is_empty());
        assert!(pending_temp_files().iter().all(|t| !t.starts_with(dir.path())));
    }

    #[test]
    fn missing_directory_is_an_input_error() {
        let e = write_atomic(Path::new("/nonexistent-mrbrake-dir/x.svg"), b"x").unwrap_err();
        assert!(e.is_input_error());
        assert!(e.to_string().contains("/nonexistent-mrbrake-dir/x.svg"));
    }

    #[cfg(unix)]
    #[test]
    fn a_symlink_stays_a_link_and_its_target_is_written() {
        let dir = tempfile::tempdir().unwrap();
        let sub = dir.path().join("data");
        std::fs::create_dir(&sub).unwrap();
        let target = sub.join("real.csv");
        std::fs::write(&target, b"old").unwrap();
        // A relative link in another directory, through a second link: both are followed.
        let link = dir.path().join("link.csv");
        std::os::unix::fs::symlink("data/real.csv", &link).unwrap();
        let link2 = dir.path().join("link2.csv");
        std::os::unix::fs::symlink(&link, &link2).unwrap();
        write_atomic(&link2, b"new").unwrap();
        for l in [&link, &link2] {
            assert!(std::fs::symlink_metadata(l).unwrap().file_type().is_symlink());
        }
        assert_eq!(std::fs::read(&target).unwrap(), b"new");
        assert!(temp_leftovers(dir.path()).is_empty() && temp_leftovers(&sub).is_empty());

        // A dangling link creates the file it names.
        let dangling = dir.path().join("dangling.csv");
        std::os::unix::fs::symlink("data/new.csv", &dangling).unwrap();
        write_atomic(&dangling, b"fresh").unwrap();
        assert!(std::fs::symlink_metadata(&dangling).unwrap().file_type().is_symlink());
        assert_eq!(std::fs::read(sub.join("new.csv")).unwrap(), b"fresh");
    }

    #[cfg(unix)]
    #[test]
    fn a_symlink_loop_is_reported_with_the_path() {
        let dir = tempfile::tempdir().unwrap();
        let (a, b) = (dir.path().join("a"), dir.path().join("b"));
        std::os::unix::fs::symlink(&b, &a).unwrap();
        std::os::unix::fs::symlink(&a, &b).unwrap();
        let e = write_atomic(&a, b"x").unwrap_err();
        assert!(e.to_string().contains(&*a.to_string_lossy()), "{e}");
    }

    #[cfg(unix)]
    #[test]
    fn dev_null_stays_a_character_device() {
        use std::os::unix::fs::FileTypeExt;
        write_atomic(Path::new("/dev/null"), b"discarded").unwrap();
        let meta = std::fs::symlink_metadata("/dev/null").unwrap();
        assert!(meta.file_type().is_char_device());
    }

    #[cfg(target_os = "linux")]
    #[test]
    fn a_full_device_reports_the_error_and_stays_a_device() {
        use std::os::unix::fs::FileTypeExt;
        let full = Path::new("/dev/full");
        if !full.exists() {
            return; // Some containers have no /dev/full.
        }
        let e = write_atomic(full, b"x").unwrap_err();
        assert!(e.to_string().contains("/dev/full"), "{e}");
        assert!(!e.is_input_error(), "a full device is an I/O failure");
        assert!(std::fs::symlink_metadata(full).unwrap().file_type().is_char_device());
    }

    #[cfg(unix)]
    #[test]
    fn a_fifo_is_written_in_place() {
        use std::io::Read;
        use std::os::unix::fs::FileTypeExt;
        let dir = tempfile::tempdir().unwrap();
        let fifo = dir.path().join("pipe");
        let made = std::process::Command::new("mkfifo").arg(&fifo).status();
        if !made.is_ok_and(|s| s.success()) {
            return; // No mkfifo on this machine.
        }
        let reader_path = fifo.clone();
        let reader = std::thread::spawn(move || {
            let mut text = String::new();
            std::fs::File::open(reader_path).unwrap().read_to_string(&mut text).unwrap();
            text
        });
        write_atomic(&fifo, b"through the pipe").unwrap();
        assert_eq!(reader.join().unwrap(), "through the pipe");
        assert!(std::fs::symlink_metadata(&fifo).unwrap().file_type().is_fifo());
        assert!(temp_leftovers(dir.path()).is_empty());
    }

    #[test]
    fn a_failed_writer_leaves_nothing_and_unregisters() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("out.png");
        let e = write_atomic_with(&p, |tmp| {
            std::fs::write(tmp, b"partial")?;
            assert!(pending_temp_files().iter().any(|t| t == tmp), "registered while written");
            Err(std::io::Error::other("encoder failed"))
        })
        .unwrap_err();
        assert!(e.to_string().contains("out.png"), "{e}");
        assert!(!p.exists());
        assert!(temp_leftovers(dir.path()).is_empty());
        assert!(pending_temp_files().iter().all(|t| !t.starts_with(dir.path())));
    }

    #[test]
    fn pending_temp_files_are_removed_on_request() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("big.csv");
        write_atomic_with(&p, |tmp| {
            std::fs::write(tmp, b"half of it")?;
            // What the binary's signal handler does while a write is in flight (limited to this
            // test's folder: other tests write in parallel).
            assert_eq!(remove_pending_where(|t| t.starts_with(dir.path())), 1);
            assert!(!tmp.exists());
            Ok(())
        })
        .unwrap_err(); // The rename then finds no temporary file.
        assert!(!p.exists());
        assert!(temp_leftovers(dir.path()).is_empty());
    }
}
