//! Atomic file output: write to a temporary file in the same directory, flush, then rename.
//!
//! A rename within one file system replaces the target in one step, so an interrupted run leaves either
//! the old file or the new one, never a truncated mix.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::ReportError;

/// Writes `bytes` to `path` atomically (temporary file in the same directory + rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ReportError> {
    let io_err = |source| ReportError::Io { path: path.to_path_buf(), source };
    let tmp = temp_path_for(path)?;
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        // Best effort: the temporary file is garbage once the write failed.
        let _ = std::fs::remove_file(&tmp);
        return Err(io_err(e));
    }
    Ok(())
}

/// A temporary file name in the same directory as `path` (hidden, unique to this process), so that a
/// rename onto `path` stays within one file system.
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
    Ok(dir.join(format!(".{}.tmp-{}-{n}", file_name.to_string_lossy(), std::process::id())))
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_error::Kind as _;

    #[test]
    fn writes_and_replaces() {
        let dir = std::env::temp_dir().join(format!("mrbrake-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("out.txt");
        write_atomic(&p, b"first").unwrap();
        write_atomic(&p, b"second").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"second");
        let leftovers: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .filter_map(|e| e.ok())
            .filter(|e| e.file_name().to_string_lossy().contains(".tmp-"))
            .collect();
        assert!(leftovers.is_empty());
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn missing_directory_is_an_input_error() {
        let e = write_atomic(Path::new("/nonexistent-mrbrake-dir/x.svg"), b"x").unwrap_err();
        assert!(e.is_input_error());
        assert!(e.to_string().contains("/nonexistent-mrbrake-dir/x.svg"));
    }
}
