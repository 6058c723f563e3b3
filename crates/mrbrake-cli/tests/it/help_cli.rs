//! The command tree of `mrbrake`: the top-level help lists every subcommand, and every subcommand
//! (and every nested one) answers `--help` with exit code 0 and a usage line.

use crate::common;

use common::mrbrake;

const SUBCOMMANDS: [&str; 20] = [
    "analyze",
    "formula",
    "materials",
    "haptic",
    "characterize",
    "freqresp",
    "tfest",
    "response",
    "thermal",
    "fem",
    "rig",
    "study",
    "export-geo",
    "sweep",
    "optimize",
    "merge",
    "export",
    "report",
    "uncertainty",
    "calibrate",
];

/// The `Commands:` section of a clap help text: the first word of each entry line.
fn listed_commands(help: &str) -> Vec<String> {
    help.lines()
        .skip_while(|line| !line.starts_with("Commands:"))
        .skip(1)
        .take_while(|line| !line.trim().is_empty())
        // Entry lines are indented by two spaces; wrapped description lines by more.
        .filter(|line| line.starts_with("  ") && !line.starts_with("   "))
        .filter_map(|line| line.split_whitespace().next().map(str::to_owned))
        .collect()
}

fn help_of(args: &[&str]) -> String {
    let mut full = args.to_vec();
    full.push("--help");
    let out = mrbrake(&full);
    assert_eq!(out.status.code(), Some(0), "{full:?}: {}", String::from_utf8_lossy(&out.stderr));
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(text.contains("Usage: mrbrake"), "{full:?}:\n{text}");
    text
}

#[test]
fn top_level_help_lists_every_subcommand() {
    let help = help_of(&[]);
    let listed = listed_commands(&help);
    for name in SUBCOMMANDS {
        assert!(listed.iter().any(|c| c == name), "'{name}' missing from {listed:?}:\n{help}");
    }
}

#[test]
fn every_subcommand_answers_help() {
    let mut checked = 0;
    // Every listed command, so one added later is checked without editing this test.
    let listed = listed_commands(&help_of(&[]));
    for name in listed.iter().map(String::as_str).filter(|c| *c != "help") {
        let help = help_of(&[name]);
        checked += 1;
        // Nested commands (formula single-disc, rig characterize, …) answer too.
        for nested in listed_commands(&help).iter().filter(|c| *c != "help") {
            help_of(&[name, nested]);
            checked += 1;
        }
    }
    assert!(checked >= SUBCOMMANDS.len() + 12, "only {checked} help texts checked");
}
