//! Bounded reads: every input file is read through one helper with a stated size limit per kind of
//! input, checked on the file's length before reading and again while streaming (a FIFO, a device
//! such as `/dev/zero` or a file that grows has no trustworthy length). A file over its limit is an
//! input error ([`std::io::ErrorKind::FileTooLarge`], which [`crate::Kind`] classes as input) whose
//! message names the kind and the limit; the reader that called adds the path, as for any read
//! error.
//!
//! The limits are far above any real input of their kind (the thesis's rig logs are ~1 MB, its
//! meshes ~5 MB) and far below what exhausts memory once parsed (issue 33: a waveform CSV, a mesh or
//! a brake model pointed at `/dev/zero` used to be read until 4–6 GB were allocated).

use std::io::Read;
use std::path::Path;

/// A kind of input file and the largest size read of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct InputLimit {
    /// What the file is, in words ("brake model", "mesh").
    pub what: &'static str,
    /// The largest size read (bytes).
    pub max_bytes: u64,
}

const MIB: u64 = 1024 * 1024;

/// Brake specifications, problem files, rig configurations, optimisation problems (TOML).
pub const SETTINGS: InputLimit = InputLimit { what: "settings file (TOML)", max_bytes: 4 * MIB };
/// Gmsh meshes (ASCII MSH): a million elements take ~60 MB.
pub const MESH: InputLimit = InputLimit { what: "mesh", max_bytes: 256 * MIB };
/// Measured or generated time series: rig logs, sine-test logs, manifests, measured loops.
pub const LOG: InputLimit = InputLimit { what: "log (CSV)", max_bytes: 256 * MIB };
/// Brake model files, inverse model files, frequency-response data, B–H curves, waveform tables.
pub const MODEL: InputLimit = InputLimit { what: "model or curve file", max_bytes: 64 * MIB };

impl InputLimit {
    /// The error of a file larger than this limit.
    fn too_large(self, seen: &str) -> std::io::Error {
        std::io::Error::new(
            std::io::ErrorKind::FileTooLarge,
            format!(
                "{seen} exceeds the size limit of a {} ({} MiB): not read",
                self.what,
                self.max_bytes / MIB
            ),
        )
    }
}

/// Opens `path` for reading at most `limit` bytes: refused at once when its length is known and
/// too large; the returned reader fails with the same error when the stream goes past the limit.
pub fn open(path: &Path, limit: InputLimit) -> std::io::Result<impl Read> {
    let file = std::fs::File::open(path)?;
    let meta = file.metadata()?;
    if meta.is_file() && meta.len() > limit.max_bytes {
        return Err(limit.too_large(&format!("the file ({} bytes)", meta.len())));
    }
    Ok(Bounded { inner: file.take(limit.max_bytes + 1), read: 0, limit })
}

/// The bytes of `path`, at most `limit` of them ([`open`]).
pub fn bytes(path: &Path, limit: InputLimit) -> std::io::Result<Vec<u8>> {
    let mut out = Vec::new();
    open(path, limit)?.read_to_end(&mut out)?;
    Ok(out)
}

/// The text of `path`, at most `limit` bytes of UTF-8 ([`open`]).
pub fn text(path: &Path, limit: InputLimit) -> std::io::Result<String> {
    let mut out = String::new();
    open(path, limit)?.read_to_string(&mut out)?;
    Ok(out)
}

/// A reader that fails once more than `limit.max_bytes` bytes came through.
struct Bounded<R> {
    inner: R,
    read: u64,
    limit: InputLimit,
}

impl<R: Read> Read for Bounded<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        self.read += n as u64;
        if self.read > self.limit.max_bytes {
            return Err(self.limit.too_large("the stream"));
        }
        Ok(n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{ErrorKind, Kind};

    #[test]
    fn a_file_over_its_limit_is_an_input_error_and_a_small_one_reads() {
        let dir = std::env::temp_dir().join(format!("mrbrake-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("small.txt");
        std::fs::write(&path, "0123456789").unwrap();
        let tiny = InputLimit { what: "test file", max_bytes: 4 };
        let e = text(&path, tiny).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::FileTooLarge);
        assert_eq!(Kind::kind(&e), ErrorKind::Input);
        assert!(e.to_string().contains("size limit of a test file"), "{e}");
        assert_eq!(text(&path, SETTINGS).unwrap(), "0123456789");
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[cfg(unix)]
    #[test]
    fn an_endless_stream_stops_at_the_limit() {
        let limit = InputLimit { what: "test stream", max_bytes: 1 << 16 };
        let e = bytes(Path::new("/dev/zero"), limit).unwrap_err();
        assert_eq!(e.kind(), std::io::ErrorKind::FileTooLarge);
        assert!(e.to_string().contains("the stream"), "{e}");
    }
}
