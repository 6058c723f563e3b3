//! Every input the fuzzer ever crashed on and every hostile input of issue 18
//! (`regressions/<target>/*`) runs again without a panic and is refused (`ok-*` files accepted),
//! and a short fuzz of every target finds no crash (the bounded CI run of `.ci/run` is longer).

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Duration;

use mrbrake_fuzz::{Budget, Outcome, fuzz, targets};

/// The targets that run in this process. The `cli-*` targets run the `mrbrake` binary, which a
/// test of this crate alone may find missing or stale; CI's fuzz run exercises them with the
/// fresh release binary, and their findings are regression tests of the CLI
/// (`crates/mrbrake-cli/tests/it/hardening2_cli.rs`).
fn in_process(target: &mrbrake_fuzz::Target) -> bool {
    !target.name.starts_with("cli-")
}

#[test]
fn recorded_crashes_stay_fixed() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("regressions");
    let mut replayed = 0;
    for target in targets().into_iter().filter(in_process) {
        let Ok(entries) = std::fs::read_dir(root.join(target.name)) else { continue };
        for entry in entries.flatten() {
            let input = std::fs::read(entry.path()).unwrap();
            let result = catch_unwind(AssertUnwindSafe(|| (target.run)(&input)));
            let name = entry.file_name().to_string_lossy().into_owned();
            match result {
                // Hostile inputs are refused with an error; a file named ok-* must be accepted.
                Ok(outcome) => assert_eq!(
                    outcome == Outcome::Ok,
                    name.starts_with("ok-"),
                    "{}: {name}: {outcome:?}",
                    target.name
                ),
                Err(_) => panic!("{} panics on {}", target.name, entry.path().display()),
            }
            replayed += 1;
        }
    }
    assert!(replayed > 0, "no regression inputs found under {}", root.display());
}

#[test]
fn every_target_accepts_its_seeds_and_survives_a_short_fuzz() {
    for target in targets().into_iter().filter(in_process) {
        assert!(!target.seeds.is_empty(), "{} has no seeds", target.name);
        for seed in &target.seeds {
            let outcome = (target.run)(seed);
            assert_eq!(outcome, Outcome::Ok, "{} refuses its own seed", target.name);
        }
        let executions = if target.name == "spec-mesh" { 10 } else { 150 };
        let budget = Budget {
            time: Duration::from_secs(30),
            max_executions: executions,
            slow_after: Duration::from_secs(60),
            seed: 11,
        };
        let report = fuzz(&target, budget, |_| {});
        assert!(report.crashes.is_empty(), "{}: {:?}", target.name, report.crashes);
        assert!(report.outcomes >= 2, "{}: the mutations never changed the outcome", target.name);
    }
}
