//! The binary as an input's last stage (issue 33, "Keep it found"): a mutated spec goes through
//! `mrbrake analyze FILE --mesh coarse --points 3 --json --save-model OUT`, and the front end's
//! properties are checked at every execution (a violation panics: a finding):
//! - exit 0: stdout is one JSON document without a non-finite number spelled in it, and the brake
//!   model was written, with no NaN or infinity either;
//! - exit 1 or 2: the message on stderr names the spec file or a flag, and no model file was
//!   left behind;
//! - any other end (a panic's 101, a signal, a run over 60 s) is a finding.
//!
//! The binary is the `mrbrake` next to this program (`target/release/mrbrake` beside
//! `target/release/mrbrake-fuzz`, as CI builds them) or `MRBRAKE_BIN`; without it the target has
//! nothing to run and accepts every input (said once on stderr).

use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use super::{Target, spec_seeds, write_scratch};
use crate::Outcome;

/// The target of this module.
pub fn targets() -> Vec<Target> {
    vec![Target { name: "cli-analyze", seeds: spec_seeds(), run: run_analyze }]
}

fn binary() -> Option<&'static PathBuf> {
    static BINARY: OnceLock<Option<PathBuf>> = OnceLock::new();
    BINARY
        .get_or_init(|| {
            let beside = std::env::current_exe().ok().and_then(|e| {
                e.parent().map(|d| d.join(format!("mrbrake{}", std::env::consts::EXE_SUFFIX)))
            });
            let found = std::env::var_os("MRBRAKE_BIN").map(PathBuf::from).or(beside);
            let found = found.filter(|p| p.is_file());
            if found.is_none() {
                eprintln!("cli-analyze: no mrbrake binary beside this program: skipped");
            }
            found
        })
        .as_ref()
}

/// True when `text` spells a non-finite number (`NaN`, `inf`, `Infinity`) as a word.
fn has_non_finite(text: &str) -> bool {
    text.split(|c: char| !(c.is_ascii_alphanumeric() || c == '-'))
        .any(|w| matches!(w.trim_start_matches('-'), "NaN" | "nan" | "inf" | "Infinity"))
}

fn run_analyze(input: &[u8]) -> Outcome {
    let Some(binary) = binary() else { return Outcome::Ok };
    let spec = write_scratch("cli-spec.toml", input);
    let model = spec.with_file_name("cli-model.json");
    let _ = std::fs::remove_file(&model);
    let mut child = Command::new(binary)
        .arg("analyze")
        .arg(&spec)
        .args(["--mesh", "coarse", "--points", "3", "--json", "--save-model"])
        .arg(&model)
        // A mesh budget well above the examples' coarse meshes (~20 k triangles) and far below
        // the default, so a mutated size stays a quick refusal, not minutes of meshing.
        .env(mrbrake_design::mesh_build::MAX_ELEMENTS_ENV, "200000")
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("start mrbrake");
    let start = Instant::now();
    while child.try_wait().ok().flatten().is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("mrbrake analyze ran over 60 s");
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let out = child.wait_with_output().expect("mrbrake's output");
    let (stdout, stderr) =
        (String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    match out.status.code() {
        Some(0) => {
            assert!(
                serde_json::from_str::<serde_json::Value>(&stdout).is_ok(),
                "not JSON: {stdout}"
            );
            assert!(!has_non_finite(&stdout), "exit 0 printed a non-finite number: {stdout}");
            let written = std::fs::read_to_string(&model).expect("exit 0 wrote the brake model");
            assert!(!has_non_finite(&written), "the brake model holds a non-finite number");
            Outcome::Ok
        }
        Some(code @ (1 | 2)) => {
            let named = stderr.contains("cli-spec.toml")
                || ["--save-model", "--points", "--mesh"].iter().any(|f| stderr.contains(f));
            assert!(named, "exit {code} names neither the file nor a flag: {stderr}");
            assert!(!model.exists(), "exit {code} left the brake model behind");
            Outcome::Refused(format!("exit {code}: {}", crate::normalise(&stderr)))
        }
        other => panic!("mrbrake analyze ended with {other:?}: {stderr}"),
    }
}
