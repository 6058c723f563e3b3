//! Hostile output targets and leftovers (issue 18, classes 6 and 8), through the binary: outputs
//! through a symbolic link, into `/dev/null`, `/dev/full` and a FIFO; temporary files removed on
//! SIGTERM; no store left behind by an invalid optimisation problem or a failed merge; no `-wal` /
//! `-shm` files beside merged inputs; a huge TOML line not echoed whole.

use crate::common;

use common::{expect_input_error, mrbrake, path_str};

use std::path::{Path, PathBuf};

const SPEC: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../examples/specs/single-disc.toml");

/// Writes the exact frequency response of 1 / (1 + s/100) at 20 log-spaced points.
fn write_frd(path: &Path) {
    let mut text = String::from("omega_rad_s,re,im\n");
    for k in 0..20 {
        let omega = 10f64.powf(4.0 * f64::from(k) / 19.0);
        let x = omega / 100.0;
        text.push_str(&format!("{omega},{},{}\n", 1.0 / (1.0 + x * x), -x / (1.0 + x * x)));
    }
    std::fs::write(path, text).expect("FRD written");
}

/// `tfest FRD --poles 1 --save TARGET` (the JSON result written to TARGET).
fn tfest_save(frd: &Path, target: &Path) -> std::process::Output {
    mrbrake(&["tfest", path_str(frd), "--poles", "1", "--save", path_str(target)])
}

fn hidden_temp_files(directory: &Path) -> Vec<String> {
    std::fs::read_dir(directory)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|name| name.contains(".tmp-"))
        .collect()
}

#[cfg(unix)]
#[test]
fn save_through_a_symlink_keeps_the_link_and_writes_its_target() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let frd = dir.path().join("frd.csv");
    write_frd(&frd);
    std::fs::create_dir(dir.path().join("results")).expect("folder");
    let target = dir.path().join("results/fit.json");
    std::fs::write(&target, "old").expect("old contents");
    let link = dir.path().join("fit.json");
    std::os::unix::fs::symlink("results/fit.json", &link).expect("symlink");

    let out = tfest_save(&frd, &link);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::symlink_metadata(&link).expect("link").file_type().is_symlink());
    let saved: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&target).expect("target")).expect("JSON");
    assert!(saved["poles"].is_array(), "{saved}");
    assert!(hidden_temp_files(dir.path()).is_empty());
    assert!(hidden_temp_files(&dir.path().join("results")).is_empty());
}

#[cfg(unix)]
#[test]
fn dev_null_stays_a_device_and_dev_full_is_an_error_naming_it() {
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().expect("temporary directory");
    let frd = dir.path().join("frd.csv");
    write_frd(&frd);
    let out = tfest_save(&frd, Path::new("/dev/null"));
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    assert!(std::fs::symlink_metadata("/dev/null").expect("null").file_type().is_char_device());

    if Path::new("/dev/full").exists() {
        let out = tfest_save(&frd, Path::new("/dev/full"));
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "a full device is an I/O failure: {err}");
        assert!(err.contains("/dev/full"), "{err}");
        assert!(std::fs::symlink_metadata("/dev/full").expect("full").file_type().is_char_device());
    }
}

/// A FIFO at `directory/name`, or `None` where `mkfifo` is missing.
#[cfg(unix)]
fn fifo(directory: &Path, name: &str) -> Option<PathBuf> {
    let path = directory.join(name);
    let made = std::process::Command::new("mkfifo").arg(&path).status();
    made.is_ok_and(|status| status.success()).then_some(path)
}

#[cfg(unix)]
#[test]
fn save_into_a_fifo_writes_through_it_and_keeps_it() {
    use std::io::Read;
    use std::os::unix::fs::FileTypeExt;
    let dir = tempfile::tempdir().expect("temporary directory");
    let frd = dir.path().join("frd.csv");
    write_frd(&frd);
    let Some(pipe) = fifo(dir.path(), "fit.pipe") else { return };
    let reader_end = pipe.clone();
    let reader = std::thread::spawn(move || {
        let mut text = String::new();
        std::fs::File::open(reader_end)
            .expect("open FIFO")
            .read_to_string(&mut text)
            .expect("read");
        text
    });
    let out = tfest_save(&frd, &pipe);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let text = reader.join().expect("reader");
    let saved: serde_json::Value = serde_json::from_str(&text).expect("JSON through the FIFO");
    assert!(saved["poles"].is_array(), "{saved}");
    assert!(std::fs::symlink_metadata(&pipe).expect("fifo").file_type().is_fifo());
}

/// SIGTERM while an output is being written removes its temporary file. The write is held at a
/// known point by a FIFO nobody reads yet: the finished temporary file waits (in TMPDIR) to be
/// copied into it.
#[cfg(unix)]
#[test]
fn sigterm_during_a_write_leaves_no_temporary_file() {
    use std::os::unix::process::ExitStatusExt;
    let dir = tempfile::tempdir().expect("temporary directory");
    let frd = dir.path().join("frd.csv");
    write_frd(&frd);
    let Some(pipe) = fifo(dir.path(), "fit.pipe") else { return };
    let tmp = dir.path().join("tmp");
    std::fs::create_dir(&tmp).expect("TMPDIR");
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_mrbrake"))
        .args(["tfest", path_str(&frd), "--poles", "1", "--save", path_str(&pipe)])
        .env("TMPDIR", &tmp)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("start mrbrake");
    let deadline = std::time::Instant::now() + std::time::Duration::from_secs(60);
    while hidden_temp_files(&tmp).is_empty() {
        assert!(std::time::Instant::now() < deadline, "no temporary file appeared");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    let killed = std::process::Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .expect("kill");
    assert!(killed.success());
    let status = child.wait().expect("wait");
    assert_eq!(status.signal(), Some(15), "dies of SIGTERM: {status:?}");
    assert!(hidden_temp_files(&tmp).is_empty(), "{:?}", hidden_temp_files(&tmp));
}

/// A problem file `directory/name` for a tiny optimisation over the single-disc spec.
fn problem_file(directory: &Path, name: &str, variables: &[&str], algorithm: &str) -> PathBuf {
    let mut text = format!("spec = \"{SPEC}\"\nmesh = \"coarse\"\n");
    for name in variables {
        text.push_str(&format!(
            "[[variable]]\nname = \"{name}\"\nmin = \"0.3mm\"\nmax = \"1mm\"\n"
        ));
    }
    text.push_str("[[objective]]\nmetric = \"rotor_inertia_kg_m2\"\n");
    text.push_str(algorithm);
    let path = directory.join(name);
    std::fs::write(&path, text).expect("problem written");
    path
}

#[test]
fn an_invalid_optimisation_problem_creates_no_store() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let store = dir.path().join("study.sqlite");
    let cases = [
        (
            problem_file(
                dir.path(),
                "zero.toml",
                &["g"],
                "[algorithm]\nkind = \"pattern-search\"\nmax_evaluations = 0\n",
            ),
            "max_evaluations",
        ),
        (
            problem_file(
                dir.path(),
                "twice.toml",
                &["g", "g"],
                "[algorithm]\nkind = \"pattern-search\"\n",
            ),
            "twice",
        ),
    ];
    for (problem, needle) in cases {
        let name = problem.file_name().expect("name").to_string_lossy().into_owned();
        expect_input_error(
            &["optimize", path_str(&problem), "--store", path_str(&store)],
            &[needle, &name],
        );
        assert!(!store.exists(), "{needle}: a store was left behind");
    }
}

fn side_files(path: &Path) -> Vec<PathBuf> {
    ["-wal", "-shm"]
        .iter()
        .map(|suffix| PathBuf::from(format!("{}{suffix}", path.display())))
        .filter(|side| side.exists())
        .collect()
}

#[test]
fn merge_leaves_no_empty_output_and_no_side_files() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let text = dir.path().join("text.sqlite");
    std::fs::write(&text, "not a store\n").expect("text file");
    let out = dir.path().join("out.sqlite");
    expect_input_error(&["merge", path_str(&out), path_str(&text)], &["text.sqlite"]);
    assert!(!out.exists(), "a failed merge left an output store");

    let shard = dir.path().join("shard.sqlite");
    let sweep = mrbrake(&[
        "sweep",
        SPEC,
        "--vary",
        "g=0.4mm,0.6mm",
        "--mesh",
        "coarse",
        "--store",
        path_str(&shard),
    ]);
    assert!(sweep.status.success(), "{}", String::from_utf8_lossy(&sweep.stderr));
    assert!(side_files(&shard).is_empty(), "{:?}", side_files(&shard));
    let merged = mrbrake(&["merge", path_str(&out), path_str(&shard)]);
    assert!(merged.status.success(), "{}", String::from_utf8_lossy(&merged.stderr));
    assert!(side_files(&shard).is_empty(), "merge left {:?}", side_files(&shard));
    assert!(side_files(&out).is_empty(), "merge left {:?}", side_files(&out));
}

#[test]
fn a_huge_toml_line_is_not_echoed_whole() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let spec = dir.path().join("long.toml");
    let line = format!("name = \"{}\" junk\n", "x".repeat(200_000));
    std::fs::write(&spec, line).expect("spec written");
    let out = mrbrake(&["analyze", path_str(&spec)]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{}", &err[..err.len().min(400)]);
    assert!(err.contains("long.toml"), "{}", &err[..err.len().min(400)]);
    assert!(err.len() < 2_000, "{} bytes of error: {}", err.len(), &err[..400]);
}
