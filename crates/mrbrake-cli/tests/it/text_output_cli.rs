//! Every command's text output ends with exactly one newline (issue 31: `response` and `thermal`
//! once ended without one, and the shell prompt ran into their last line): all of them print
//! through the one text writer, `output::print_text`, and this test runs each subcommand once.

use crate::common;

use std::path::Path;

use common::{mrbrake, path_str};

const SPEC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/single-disc.toml");
const FEM: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/fem");

/// Runs `mrbrake ARGS…`, asserts success, and returns stdout.
fn stdout(args: &[&str]) -> String {
    let out = mrbrake(args);
    assert!(out.status.success(), "{args:?}: {}", String::from_utf8_lossy(&out.stderr));
    String::from_utf8(out.stdout).expect("UTF-8 output")
}

/// Asserts that the text output of `mrbrake ARGS…` is not empty and ends with one newline.
fn ends_with_one_newline(args: &[&str]) {
    let text = stdout(args);
    assert!(!text.trim().is_empty(), "{args:?}: no text output");
    assert!(text.ends_with('\n'), "{args:?}: no final newline: {:?}", tail(&text));
    assert!(!text.ends_with("\n\n"), "{args:?}: a blank last line: {:?}", tail(&text));
}

fn tail(text: &str) -> &str {
    &text[text.len().saturating_sub(80)..]
}

/// The file named `name` in `dir`, as a `String` argument.
fn file(dir: &Path, name: &str) -> String {
    path_str(&dir.join(name)).to_owned()
}

#[test]
fn design_commands_end_their_text_with_one_newline() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    ends_with_one_newline(&["analyze", SPEC, "--mesh", "coarse", "--points", "2"]);
    ends_with_one_newline(&["response", SPEC, "--mesh", "coarse", "--duration", "2ms"]);
    ends_with_one_newline(&["thermal", SPEC, "--mesh", "coarse", "--time", "60s"]);
    ends_with_one_newline(&["export-geo", SPEC, "--output", &file(d, "b.geo")]);
    ends_with_one_newline(&["study", "thesis-tables", "--mesh", "coarse"]);
    let disc = ["--r1", "22.5mm", "--r2", "27.5mm", "--tau-y", "24kPa"];
    ends_with_one_newline(&[&["formula", "single-disc"][..], &disc].concat());
    ends_with_one_newline(&[&["formula", "multi-disc", "--discs", "3"][..], &disc].concat());
    ends_with_one_newline(&["formula", "drum", "--r", "25mm", "--h", "9mm", "--b", "0.4T"]);
    ends_with_one_newline(&[
        "formula",
        "multi-drum",
        "--r0",
        "25mm",
        "--h",
        "9mm",
        "--d",
        "1mm",
        "--g",
        "0.5mm",
        "--surfaces",
        "4",
        "--tau-y",
        "25kPa",
    ]);
    ends_with_one_newline(&[
        "formula",
        "coil",
        "--window-width",
        "10mm",
        "--window-height",
        "12mm",
        "--awg",
        "24",
    ]);
    ends_with_one_newline(&["materials", "list"]);
    ends_with_one_newline(&["materials", "show", "steel-1008"]);
    ends_with_one_newline(&["fem", "solve", &format!("{FEM}/potcore.toml")]);
    ends_with_one_newline(&["fem", "solve", &format!("{FEM}/potcore-heat.toml")]);
    // The HTML report says what it wrote on stderr; stdout stays empty.
    let page = file(d, "r.html");
    let report = stdout(&["report", SPEC, "--mesh", "coarse", "--points", "2", "-o", &page]);
    assert!(report.is_empty(), "{report:?}");
}

#[test]
fn study_commands_end_their_text_with_one_newline() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (a, b, merged) = (file(d, "a.sqlite"), file(d, "b.sqlite"), file(d, "m.sqlite"));
    for (store, gap) in [(&a, "g=0.5mm"), (&b, "g=0.6mm")] {
        ends_with_one_newline(&[
            "sweep", SPEC, "--vary", gap, "--mesh", "coarse", "--store", store,
        ]);
    }
    ends_with_one_newline(&["merge", &merged, &a, &b]);
    ends_with_one_newline(&["export", &merged]);
    ends_with_one_newline(&["optimize", "--list-metrics"]);
}

#[test]
fn rig_sysid_and_haptic_commands_end_their_text_with_one_newline() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let (char_dir, freq_dir) = (file(d, "char"), file(d, "freq"));
    ends_with_one_newline(&["rig", "config"]);
    ends_with_one_newline(&["rig", "characterize", "--out", &char_dir]);
    ends_with_one_newline(&["rig", "minor-loops", "--out", &file(d, "minor")]);
    ends_with_one_newline(&["rig", "track", "--out", &file(d, "track")]);
    ends_with_one_newline(&["rig", "freqresp", "--out", &freq_dir]);
    let log = std::fs::read_dir(&char_dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|x| x == "csv"))
        .expect("a characterisation log");
    ends_with_one_newline(&["characterize", path_str(&log)]);
    ends_with_one_newline(&[
        "calibrate",
        "--log",
        path_str(&log),
        "--parameter",
        "fluid.yield_stress_scale",
        "--mesh",
        "coarse",
        "--points",
        "3",
        "--max-evaluations",
        "3",
    ]);
    ends_with_one_newline(&["freqresp", &format!("{freq_dir}/manifest.csv")]);
    ends_with_one_newline(&["tfest", &format!("{freq_dir}/frd.csv"), "--poles", "2"]);
    ends_with_one_newline(&["haptic", "wall", "--device", "bidirectional"]);
    ends_with_one_newline(&["haptic", "zwidth", "--points", "2"]);
}
