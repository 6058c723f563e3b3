//! The front's designs as they are written (`designs/front-NN.toml`): in the base spec's own
//! units, rounded to a manufacturing resolution, evaluated again after rounding, and keeping the
//! base file's comments and layout.
//!
//! Brief overview: for each design of the front, [`designs`]
//!
//! 1. rounds every length variable to [`crate::problem::OptimizationProblem::manufacturing_resolution`]
//!    (default 0.01 mm) *in the unit the base spec writes that field in* (`r0 = "25mm"` gives
//!    `"15.72mm"`; a bare number in metres stays a number in metres), and every current to
//!    1 mA; counts are whole already. A value that would leave the variable's bounds moves one
//!    resolution step inwards. The rounded value is the one the written text reads back as
//!    (the text is formatted, then parsed by the spec reader's own unit parser), so the written
//!    file and the evaluated design are the same design, bit for bit;
//! 2. evaluates the rounded designs (one batch through the store: a design the rounding did not
//!    change is read back, not recomputed), so the metrics beside a written design are its own. A
//!    rounded design may break a constraint its unrounded original met (an active torque limit):
//!    its record says so, and the reports show it;
//! 3. writes the spec text with `toml_edit` from the base file's text: the `[set]` overrides of the
//!    problem and the variables are set in place, every other line, comment and blank of the base
//!    file stays as it was, a replaced value keeps its trailing comment, which then names the base
//!    value it was written for; `name` names the design.
//!    The text is read back and its design key compared with the evaluated record's: on the (not
//!    expected) mismatch the design is written as evaluated, in SI, and [`FrontDesign::note`]
//!    says why.
//!
//! A resolution of 0 writes the designs as evaluated (bare SI numbers, nothing evaluated again).

use mrbrake_design::spec::{BrakeSpec, Quantity};
use mrbrake_optim::Problem as _;
use mrbrake_optim::space::Bounds;
use mrbrake_units::Dimension;
use toml_edit::{DocumentMut, Item, Value};

use crate::design::design_key;
use crate::optimize::{Evaluated, OptimizationResult, Stage, StudyProblem};
use crate::variable::{Variable, resolve};
use crate::{Design, ExploreError};

/// The resolution currents are rounded to when written (A).
pub const CURRENT_RESOLUTION: f64 = 1e-3;

/// One written front design.
#[derive(Debug, Clone)]
pub struct FrontDesign {
    /// Its number on the front, from 1 (`front-NN.toml`).
    pub number: usize,
    /// Index into [`OptimizationResult::evaluated`] of the front design it was made from.
    pub source: usize,
    /// The written design's own record and evaluation (the source's when nothing was rounded).
    pub evaluated: Evaluated,
    /// The spec file: the base spec's text with the variables set in its units, its comments kept.
    pub spec_text: String,
    /// True when a value was rounded (the design differs from the source).
    pub rounded: bool,
    /// Set when the text could not be written in the base spec's units (written in SI instead).
    pub note: Option<String>,
}

/// A variable's value as written: its text in the file and the SI value the text reads back as.
#[derive(Debug, Clone)]
struct Written {
    si: f64,
    item: Value,
}

/// The written designs of `result`'s front (module docs), evaluated on `study`.
pub fn designs(
    study: &mut StudyProblem<'_, '_>,
    result: &OptimizationResult,
) -> Result<Vec<FrontDesign>, ExploreError> {
    if result.front.is_empty() {
        return Ok(Vec::new());
    }
    let problem = study.problem().clone();
    let base_text = mrbrake_error::read::text(&problem.spec_path, mrbrake_error::read::SETTINGS)
        .map_err(|e| {
            ExploreError::input("", format!("cannot read it: {e}"))
                .in_file(&problem.spec_path.display().to_string())
        })?;
    let writer = SpecWriter::new(&base_text, &problem, study.space().is_drum())?;
    let variables = study.space().variables().to_vec();
    let bounds = study.bounds().to_vec();
    let mut planned = Vec::with_capacity(result.front.len());
    for &i in &result.front {
        let record = &result.evaluated[i].record;
        let x: Vec<f64> = variables.iter().map(|v| v.x_in(record).unwrap_or(f64::NAN)).collect();
        let written: Vec<Written> = variables
            .iter()
            .zip(&x)
            .zip(&bounds)
            .map(|((v, &value), b)| writer.round(v, value, b, problem.manufacturing_resolution))
            .collect();
        let si: Vec<f64> = written.iter().map(|w| w.si).collect();
        let rounded = si.iter().zip(&x).any(|(a, b)| a.total_cmp(b).is_ne());
        planned.push((i, written, study.space().design(&si)?, rounded));
    }
    let batch: Vec<Design> = planned.iter().map(|p| p.2.clone()).collect();
    let records = study.run_batch(&batch, Stage::FrontDesigns)?;
    let mut out = Vec::with_capacity(planned.len());
    for (k, ((source, written, design, rounded), record)) in
        planned.into_iter().zip(records).enumerate()
    {
        let (spec_text, note) = writer.text(&variables, &written, &design, &problem.settings)?;
        let evaluation = study.evaluation_of(&record);
        out.push(FrontDesign {
            number: k + 1,
            source,
            evaluated: Evaluated { record, evaluation },
            spec_text,
            rounded,
            note,
        });
    }
    Ok(out)
}

/// The base spec's document with the problem's overrides applied, and the units its fields are
/// written in.
struct SpecWriter {
    document: DocumentMut,
}

impl SpecWriter {
    fn new(
        base_text: &str,
        problem: &crate::problem::OptimizationProblem,
        is_drum: bool,
    ) -> Result<Self, ExploreError> {
        let mut document: DocumentMut = base_text.parse().map_err(|e: toml_edit::TomlError| {
            ExploreError::input("", e.to_string()).in_file(&problem.spec_path.display().to_string())
        })?;
        for (path, text) in &problem.overrides {
            let (path, value) = override_value(path, text, is_drum)?;
            set_value(&mut document, &path, value)?;
        }
        Ok(Self { document })
    }

    /// The unit the base file writes `field` in: its scale to SI and its name (`""` for a bare
    /// SI number), or the default for a field it does not give (mm, A).
    fn unit_of(&self, variable: &Variable) -> (f64, String) {
        let dimension = match variable.quantity() {
            Some(Quantity::Length) => Dimension::Length,
            Some(Quantity::Current) => Dimension::Current,
            Some(
                Quantity::Integer | Quantity::Factor | Quantity::Conductivity | Quantity::Torque,
            )
            | None => {
                return (1.0, String::new());
            }
        };
        let default = match dimension {
            Dimension::Length => (1e-3, "mm".to_string()),
            _ => (1.0, "A".to_string()),
        };
        match get_value(&self.document, variable.path()) {
            Some(Value::Float(_) | Value::Integer(_)) => (1.0, String::new()),
            Some(Value::String(text)) => {
                let unit = unit_suffix(text.value());
                mrbrake_units::unit_scale(&unit, dimension).map_or(default, |s| (s, unit))
            }
            _ => default,
        }
    }

    /// `value` (SI) of `variable` rounded to `resolution` (m; currents to [`CURRENT_RESOLUTION`])
    /// in the base file's unit, inside `bounds`; as evaluated when `resolution` is 0 or no
    /// rounded value is inside the bounds.
    fn round(&self, variable: &Variable, value: f64, bounds: &Bounds, resolution: f64) -> Written {
        let exact = || match variable.quantity() {
            Some(Quantity::Integer) => {
                Written { si: value, item: Value::from(value.round() as i64) }
            }
            // A material: its name (the value is the index of its level).
            None => {
                Written { si: value, item: Value::from(variable.level(value).unwrap_or_default()) }
            }
            _ => Written { si: value, item: Value::from(value) },
        };
        let step = match variable.quantity() {
            Some(
                Quantity::Integer | Quantity::Factor | Quantity::Conductivity | Quantity::Torque,
            )
            | None => {
                return exact();
            }
            Some(Quantity::Length) => resolution,
            // A resolution of 0 writes every value as evaluated, currents too.
            Some(Quantity::Current) if resolution > 0.0 => CURRENT_RESOLUTION,
            Some(Quantity::Current) => 0.0,
        };
        if step <= 0.0 || !value.is_finite() {
            return exact();
        }
        let (scale, unit) = self.unit_of(variable);
        let step_in_unit = step / scale;
        let decimals = (-step_in_unit.log10() - 1e-9).ceil().clamp(0.0, 15.0) as usize;
        let nearest = (value / scale / step_in_unit).round();
        let candidates = [nearest, nearest + 1.0, nearest - 1.0];
        candidates
            .iter()
            .filter_map(|&n| {
                let number = trim_zeros(&format!("{:.decimals$}", n * step_in_unit));
                let text = format!("{number}{unit}");
                let si = variable.parse_value(&text).ok()?;
                let item = if unit.is_empty() { Value::from(si) } else { Value::from(text) };
                bounds.contains(si).then_some(Written { si, item })
            })
            .next()
            .unwrap_or_else(exact)
    }

    /// The spec text of `design` with the `written` values of `variables`, and a note if it had to
    /// be written in SI (its key did not match the evaluated design's).
    fn text(
        &self,
        variables: &[Variable],
        written: &[Written],
        design: &Design,
        settings: &crate::EvaluationSettings,
    ) -> Result<(String, Option<String>), ExploreError> {
        let mut document = self.document.clone();
        for (variable, w) in variables.iter().zip(written) {
            set_value(&mut document, variable.path(), Some(w.item.clone()))?;
        }
        if let Ok(spec) = &design.spec {
            set_value(&mut document, "name", Some(Value::from(spec.name.as_str())))?;
        }
        let text = document.to_string();
        let reread = BrakeSpec::from_toml_str(&text, "front design")
            .ok()
            .filter(|spec| spec.validate().is_ok())
            .and_then(|spec| design_key(&spec, settings).ok());
        match (&design.spec, reread) {
            (Ok(_), Some(key)) if key == design.key => Ok((text, None)),
            // An invalid design has no spec key to compare; its text is the base's, edited.
            (Err(_), _) => Ok((text, None)),
            _ => Ok((
                design.spec_toml.clone(),
                Some(
                    "written in SI: the text in the base spec's units did not read back as the \
                      evaluated design"
                        .into(),
                ),
            )),
        }
    }
}

/// The path and value of a `[set]` override as the file writes it: a study variable's field with
/// the user's quantity as text (`"30mm"`), `fill` for the turns removes them, any other field its
/// TOML value (as [`crate::variable::apply_override`] reads them).
pub(crate) fn override_value(
    path: &str,
    text: &str,
    is_drum: bool,
) -> Result<(String, Option<Value>), ExploreError> {
    let text = text.trim();
    if let Ok(variable) = resolve(path, is_drum) {
        let field = variable.path().to_string();
        if field == "coil.turns" && text.eq_ignore_ascii_case("fill") {
            return Ok((field, None));
        }
        if variable.quantity().is_none() {
            // A material, by its library name.
            return Ok((field, Some(Value::from(text.trim_matches('"')))));
        }
        let si = variable.parse_value(text)?;
        let value = match variable.quantity() {
            Some(Quantity::Integer) => Value::from(si.round() as i64),
            _ if text.parse::<f64>().is_ok() => Value::from(si),
            _ => Value::from(text),
        };
        return Ok((field, Some(value)));
    }
    let value = format!("v = {text}")
        .parse::<DocumentMut>()
        .ok()
        .and_then(|d| d.get("v").and_then(Item::as_value).cloned())
        .unwrap_or_else(|| Value::from(text));
    Ok((path.trim().to_string(), Some(value)))
}

/// The value at a dotted path (through tables and inline tables).
fn get_value<'d>(document: &'d DocumentMut, path: &str) -> Option<&'d Value> {
    let mut parts = path.split('.').peekable();
    let mut table: &dyn toml_edit::TableLike = document.as_table();
    while let Some(part) = parts.next() {
        let item = table.get(part)?;
        if parts.peek().is_none() {
            return item.as_value();
        }
        table = item.as_table_like()?;
    }
    None
}

/// Sets (`Some`) or removes (`None`) the value at a dotted path, creating missing tables; a
/// replaced value keeps its comments (decor; see [`replaced_decor`]).
pub(crate) fn set_value(
    document: &mut DocumentMut,
    path: &str,
    value: Option<Value>,
) -> Result<(), ExploreError> {
    let mut parts: Vec<&str> = path.split('.').collect();
    let last = parts
        .pop()
        .filter(|s| !s.is_empty())
        .ok_or_else(|| ExploreError::input(path, "not a dotted spec path such as drum.gap"))?;
    let mut table: &mut dyn toml_edit::TableLike = document.as_table_mut();
    for part in parts {
        if table.get(part).is_none() {
            table.insert(part, toml_edit::table());
        }
        table = table.get_mut(part).and_then(Item::as_table_like_mut).ok_or_else(|| {
            ExploreError::input(path, format!("'{part}' is a value, not a table"))
        })?;
    }
    match value {
        None => {
            table.remove(last);
        }
        Some(mut value) => {
            if let Some(old) = table.get(last).and_then(Item::as_value) {
                *value.decor_mut() = replaced_decor(old, &value);
            }
            table.insert(last, Item::Value(value));
        }
    }
    Ok(())
}

/// The decor (spacing, comments) of `old` for its replacement `new`. A trailing comment described
/// the old value (`outer_radius = "40mm"  # 80 mm diameter`): when the value changes, the comment
/// names the value it was written for (`# base "40mm": 80 mm diameter`), so that it cannot be read
/// as describing the new one.
fn replaced_decor(old: &Value, new: &Value) -> toml_edit::Decor {
    let mut decor = old.decor().clone();
    let bare = |v: &Value| {
        let mut v = v.clone();
        v.decor_mut().clear();
        v.to_string()
    };
    let was = bare(old);
    if was == bare(new) {
        return decor;
    }
    let suffix = decor.suffix().and_then(|s| s.as_str()).unwrap_or_default().to_string();
    if let Some(hash) = suffix.find('#') {
        let comment = suffix[hash + 1..].trim_start();
        decor.set_suffix(format!("{}# base {was}: {comment}", &suffix[..hash]));
    }
    decor
}

/// The unit written after the number of a quantity (`"25mm"` → `mm`, `"0.025"` → ``).
fn unit_suffix(text: &str) -> String {
    let text = text.trim();
    let start = text
        .char_indices()
        .rev()
        .take_while(|(_, c)| !c.is_ascii_digit() && *c != '.')
        .last()
        .map_or(text.len(), |(i, _)| i);
    text[start..].trim().to_string()
}

/// A decimal number without trailing zeros (`"15.700"` → `"15.7"`, `"16.000"` → `"16"`).
fn trim_zeros(number: &str) -> String {
    if number.contains('.') {
        number.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        number.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn units_are_read_from_the_text() {
        assert_eq!(unit_suffix("25mm"), "mm");
        assert_eq!(unit_suffix("0.5 mm"), "mm");
        assert_eq!(unit_suffix("2A"), "A");
        assert_eq!(unit_suffix("0.025"), "");
        assert_eq!(unit_suffix("1e-3"), "");
        assert_eq!(trim_zeros("15.700"), "15.7");
        assert_eq!(trim_zeros("16.000"), "16");
        assert_eq!(trim_zeros("120"), "120");
    }

    #[test]
    fn a_value_is_rounded_in_the_base_unit_and_kept_in_bounds_with_its_comment() {
        let base = "name = \"b\"\n# the drum\n[drum]\nr0 = \"25mm\"   # 4.4.2\ngap = 0.0005\n";
        let problem_dir = tempfile::tempdir().unwrap();
        let spec = problem_dir.path().join("b.toml");
        std::fs::write(&spec, base).unwrap();
        let writer = SpecWriter { document: base.parse().unwrap() };
        let r0 = resolve("R0", true).unwrap();
        let bounds = Bounds::continuous(0.015, 0.030);
        let w = writer.round(&r0, 0.015_716_3, &bounds, 1e-5);
        assert_eq!(w.item.as_str(), Some("15.72mm"));
        assert!((w.si - 0.01572).abs() < 1e-15);
        // Rounding up would leave the bounds: one step inwards.
        let w = writer.round(&r0, 0.029_999_8, &Bounds::continuous(0.015, 0.029_999_9), 1e-5);
        assert_eq!(w.item.as_str(), Some("29.99mm"));
        let gap = resolve("g", true).unwrap();
        let w = writer.round(&gap, 0.000_523_4, &Bounds::continuous(1e-4, 1e-3), 1e-5);
        assert_eq!(w.item.as_float(), Some(0.00052));
        let mut document = writer.document.clone();
        set_value(&mut document, "drum.r0", Some(Value::from("15.72mm"))).unwrap();
        set_value(&mut document, "spacer.thickness", Some(Value::from("4mm"))).unwrap();
        let text = document.to_string();
        // The comment stays, naming the value it was written for.
        assert!(text.contains("r0 = \"15.72mm\"   # base \"25mm\": 4.4.2"), "{text}");
        assert!(text.contains("# the drum") && text.contains("[spacer]"), "{text}");
    }
}
