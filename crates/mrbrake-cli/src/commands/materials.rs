//! `mrbrake materials …`: the built-in material library (names, curves, derived values, provenance).

use clap::{Args, Subcommand};
use mrbrake::materials::library;
use mrbrake::report::materials::{self as report, DEFAULT_B_T, DEFAULT_H_A_PER_M};
use mrbrake::units::{Dimension, parse};

use crate::error::CommandResult;
use crate::output::{print_json, print_text};

/// `mrbrake materials` subcommands.
#[derive(Debug, Subcommand)]
pub enum MaterialsCommand {
    /// List every built-in material with its kind, trust level and description.
    List(ListArgs),
    /// Show one material: B-H points, derived values (B at 1/5/20 kA/m, τ_y at chosen B), provenance.
    Show(ShowArgs),
}

/// Arguments of `materials list`.
#[derive(Debug, Args)]
pub struct ListArgs {
    /// Print a JSON object instead of a table.
    #[arg(long)]
    json: bool,
}

/// Arguments of `materials show`.
#[derive(Debug, Args)]
pub struct ShowArgs {
    /// Material name, case-insensitive (see `mrbrake materials list`), e.g. steel-1008 or mrf-122eg.
    name: String,
    /// Flux densities at which to report τ_y for an MR fluid, comma-separated (e.g. 0.3T,460mT).
    #[arg(long, value_name = "FLUX_DENSITY", value_delimiter = ',', allow_hyphen_values = true)]
    b: Vec<String>,
    /// Field strengths at which to report B (and τ_y for a fluid), comma-separated (e.g. 1kA/m,50kA/m).
    #[arg(long, value_name = "FIELD_STRENGTH", value_delimiter = ',', allow_hyphen_values = true)]
    h: Vec<String>,
    /// Leave the table of curve points out of the text output.
    #[arg(long)]
    no_points: bool,
    /// Print a JSON object instead of text.
    #[arg(long)]
    json: bool,
}

/// Runs a `materials` subcommand.
pub fn run(command: MaterialsCommand) -> CommandResult {
    match command {
        MaterialsCommand::List(a) => list(&a),
        MaterialsCommand::Show(a) => show(&a),
    }
}

fn list(a: &ListArgs) -> CommandResult {
    let mut rows = Vec::new();
    for (name, _) in library::names() {
        rows.push(library::get(name)?);
    }
    if a.json {
        return print_json(&report::list_json(&rows));
    }
    print_text(&report::list_text(&rows))
}

/// Parses the curve points of `--b` or `--h` (`flag`), of one dimension, checked by the library's
/// rule ([`library::check_curve_points`]).
fn curve_points(flag: &str, texts: &[String], dim: Dimension) -> CommandResult<Vec<f64>> {
    let values = texts.iter().map(|t| parse(t, dim)).collect::<Result<Vec<f64>, _>>()?;
    library::check_curve_points(flag, &values, dim.si_unit())?;
    Ok(values)
}

fn show(a: &ShowArgs) -> CommandResult {
    let material = library::get(&a.name)?;
    let b_values = if a.b.is_empty() {
        DEFAULT_B_T.to_vec()
    } else {
        curve_points("--b", &a.b, Dimension::FluxDensity)?
    };
    let h_values = if a.h.is_empty() {
        DEFAULT_H_A_PER_M.to_vec()
    } else {
        curve_points("--h", &a.h, Dimension::FieldStrength)?
    };
    if a.json {
        return print_json(&report::show_json(material, &b_values, &h_values));
    }
    print_text(&report::show_text(material, &b_values, &h_values, !a.no_points))
}
