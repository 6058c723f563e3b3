//! Helpers shared by the study-metric test files (each uses a subset, hence the `dead_code`
//! allowance).
#![allow(dead_code)]

use std::path::Path;

use mrbrake_explore::problem::OptimizationProblem;

/// A problem file on the embedded thesis brake, coarse mesh, asking for `record` with `extra`
/// tables.
pub fn problem(record: &str, extra: &str) -> OptimizationProblem {
    OptimizationProblem::from_toml_str(&problem_text(record, extra), Path::new("study.toml"))
        .unwrap()
}

/// The text of [`problem`].
pub fn problem_text(record: &str, extra: &str) -> String {
    format!(
        r#"
spec = "thesis.toml"
mesh = "coarse"
record = [{record}]
{extra}
[[variable]]
name = "g"
min = "0.4mm"
max = "0.6mm"
[[objective]]
metric = "rotor_inertia_kg_m2"
[algorithm]
kind = "nsga2"
population = 4
generations = 0
"#
    )
}
