//! `docs/ARCHITECTURE.md` stays true: its crate table is checked against the workspace.
//!
//! For every crate in `crates/`: the table has a row; the row's "depends on" column names exactly
//! the crate's `mrbrake-*` dependencies from its `Cargo.toml` (`[dependencies]`, not dev or build
//! dependencies; `mrbrake-error`, which every library uses, is left out of the column as the note
//! under the table says); and every `pub mod` of its `lib.rs` is named in the row's description
//! (as `` `name` `` or `` `name (…) ``). Two rows are prose by design: the facade's ("all
//! libraries": it must then depend on every library crate) and the fuzzer's.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

/// One row of the crate table: the crate's name, its description, its "depends on" column.
struct Row {
    name: String,
    description: String,
    depends_on: String,
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn crate_table(architecture: &str) -> Vec<Row> {
    architecture
        .lines()
        .filter_map(|line| {
            let cells: Vec<&str> = line.strip_prefix("| `")?.splitn(2, '`').collect();
            let (name, rest) = (cells.first()?, cells.get(1)?);
            if !name.starts_with("mrbrake") {
                return None;
            }
            let rest = rest.trim().strip_prefix('|')?.trim_end().strip_suffix('|')?;
            let (description, depends_on) = rest.rsplit_once(" | ")?;
            Some(Row {
                name: name.to_string(),
                description: description.trim().to_string(),
                depends_on: depends_on.trim().to_string(),
            })
        })
        .collect()
}

fn workspace_crates(root: &Path) -> BTreeSet<String> {
    fs::read_dir(root.join("crates"))
        .expect("crates/ is readable")
        .filter_map(|entry| {
            let path = entry.ok()?.path();
            path.join("Cargo.toml")
                .is_file()
                .then(|| path.file_name()?.to_str().map(str::to_string))?
        })
        .collect()
}

/// The `mrbrake-*` crates in `[dependencies]` of `crates/<name>/Cargo.toml`, without `mrbrake-error`.
fn cargo_dependencies(root: &Path, name: &str) -> BTreeSet<String> {
    let text = fs::read_to_string(root.join("crates").join(name).join("Cargo.toml")).unwrap();
    let manifest: toml::Table = toml::from_str(&text).unwrap();
    let Some(dependencies) = manifest.get("dependencies").and_then(toml::Value::as_table) else {
        return BTreeSet::new();
    };
    dependencies
        .keys()
        .filter(|d| (d.starts_with("mrbrake-") || *d == "mrbrake") && *d != "mrbrake-error")
        .cloned()
        .collect()
}

/// The crates a "depends on" cell names (`fem, materials, observe` → `mrbrake-fem`, …); words
/// that are not workspace crates (`—`, `libm (serde optional)`) are not dependencies.
fn documented_dependencies(cell: &str, crates: &BTreeSet<String>) -> BTreeSet<String> {
    cell.split([',', ';'])
        .map(str::trim)
        .map(|word| if word == "mrbrake" { word.to_string() } else { format!("mrbrake-{word}") })
        .filter(|name| crates.contains(name) && name != "mrbrake-error")
        .collect()
}

fn public_modules(root: &Path, name: &str) -> Vec<String> {
    let Ok(lib) = fs::read_to_string(root.join("crates").join(name).join("src/lib.rs")) else {
        return Vec::new();
    };
    lib.lines()
        .filter_map(|line| line.trim().strip_prefix("pub mod "))
        .map(|rest| rest.trim_end_matches([';', '{', ' ']).to_string())
        .collect()
}

fn names_module(description: &str, module: &str) -> bool {
    [format!("`{module}`"), format!("`{module} "), format!("`{module}(")]
        .iter()
        .any(|pattern| description.contains(pattern.as_str()))
}

#[test]
fn the_crate_table_matches_the_workspace() {
    let root = workspace_root();
    let architecture = fs::read_to_string(root.join("docs/ARCHITECTURE.md")).unwrap();
    let rows = crate_table(&architecture);
    let crates = workspace_crates(&root);
    let mut problems = Vec::new();
    for name in &crates {
        let Some(row) = rows.iter().find(|r| &r.name == name) else {
            problems.push(format!("{name}: no row in the crate table"));
            continue;
        };
        let actual = cargo_dependencies(&root, name);
        match row.depends_on.as_str() {
            "the libraries it feeds" => {}
            "all libraries" => {
                let libraries: BTreeSet<String> = rows
                    .iter()
                    .filter(|r| {
                        !["all libraries", "the libraries it feeds"]
                            .contains(&r.depends_on.as_str())
                    })
                    .filter(|r| !outside_the_facade(&r.name) && r.name != "mrbrake-error")
                    .map(|r| r.name.clone())
                    .collect();
                for missing in libraries.difference(&actual) {
                    problems
                        .push(format!("{name}: \"all libraries\" but no dependency on {missing}"));
                }
            }
            cell => {
                let documented = documented_dependencies(cell, &crates);
                for extra in documented.difference(&actual) {
                    problems.push(format!(
                        "{name}: the table says it depends on {extra}; Cargo.toml does not"
                    ));
                }
                for missing in actual.difference(&documented) {
                    problems
                        .push(format!("{name}: depends on {missing}; the table does not say so"));
                }
            }
        }
        for module in public_modules(&root, name) {
            if !names_module(&row.description, &module) {
                problems.push(format!("{name}: public module `{module}` is not in its row"));
            }
        }
    }
    for row in &rows {
        if !crates.contains(&row.name) {
            problems.push(format!("{}: a row for a crate that does not exist", row.name));
        }
    }
    assert!(problems.is_empty(), "docs/ARCHITECTURE.md is out of date:\n{}", problems.join("\n"));
}

/// Crates the facade does not re-export: the front ends (CLI, Python, studio), the fuzzer, and
/// the schema conventions (used by the crates that read each format, not by users directly).
fn outside_the_facade(name: &str) -> bool {
    ["mrbrake-cli", "mrbrake-py", "mrbrake-studio", "mrbrake-fuzz", "mrbrake-schema"]
        .contains(&name)
}
