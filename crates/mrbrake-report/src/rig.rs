//! The virtual rig's output folder: its logs and the configuration that produced them, and the report
//! of what was written.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use mrbrake_sim::rig::{RigConfig, RigFile};
use serde_json::{Value, json};

use crate::{ReportError, write_atomic};

/// Writes the rig's `files` and its configuration (`rig.toml`, to repeat the run) into `dir`,
/// creating the folder if needed; returns the paths written, the configuration last.
pub fn write_rig_folder(
    dir: &Path,
    config: &RigConfig,
    files: &[RigFile],
) -> Result<Vec<PathBuf>, ReportError> {
    std::fs::create_dir_all(dir)
        .map_err(|source| ReportError::Folder { path: dir.to_path_buf(), source })?;
    let mut written = Vec::new();
    for f in files {
        let path = dir.join(&f.name);
        write_atomic(&path, f.csv.as_bytes())?;
        written.push(path);
    }
    let path = dir.join("rig.toml");
    write_atomic(&path, config.to_toml().as_bytes())?;
    written.push(path);
    Ok(written)
}

/// The JSON report of a rig run: the files written.
pub fn rig_json(written: &[PathBuf]) -> Value {
    json!({ "files": written })
}

/// The text report of a rig run: `what` and the folder, then the files to give to the next command
/// (the characterisation log or the frequency-response manifest).
pub fn rig_text(what: &str, dir: &Path, written: &[PathBuf]) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "{what}: {} files in {}", written.len(), dir.display());
    for p in written.iter().filter(|p| {
        p.file_name().is_some_and(|n| n == "manifest.csv" || n == "characterization.csv")
    }) {
        let _ = writeln!(out, "  {}", p.display());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folder_holds_the_logs_and_the_configuration() {
        let dir = tempfile::tempdir().unwrap();
        let out = dir.path().join("run");
        let files = [RigFile { name: "characterization.csv".into(), csv: "time_s\n0\n".into() }];
        let written = write_rig_folder(&out, &RigConfig::default(), &files).unwrap();
        assert_eq!(written, vec![out.join("characterization.csv"), out.join("rig.toml")]);
        let config = std::fs::read_to_string(out.join("rig.toml")).unwrap();
        assert_eq!(RigConfig::from_toml("rig.toml", &config).unwrap(), RigConfig::default());
        let text = rig_text("characterization log", &out, &written);
        assert!(text.starts_with("characterization log: 2 files in "), "{text}");
        assert_eq!(text.lines().count(), 2, "only the log is listed: {text}");
    }
}
