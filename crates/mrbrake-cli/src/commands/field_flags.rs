//! The flags of the libraries' option and argument names: their field errors name `points`,
//! `tau_y`, `insulation_class` or `max_evaluations`, the CLI prints `--points`, `--tau-y`,
//! `--insulation-class`, `--max-evaluations`.

use mrbrake::design::DesignError;
use mrbrake::design::analysis::ElementOrder;
use mrbrake::design::thermal::ThermalError;
use mrbrake::error::FieldError;
use mrbrake::explore::ExploreError;

/// `(library name, flag)` of every option of `analyze`, `sweep`, `report`, `response`, `thermal`
/// and `formula` whose rule the design library checks. One table serves every command: a name
/// means the same flag wherever it occurs.
const FLAGS: &[(&str, &str)] = &[
    // Analysis options.
    ("mesh", "--mesh"),
    ("points", "--points"),
    ("speed", "--speed"),
    ("seal_friction", "--seal-friction"),
    ("temperature", "--temperature"),
    ("order", "--order"),
    // Hysteresis-loop options.
    ("peak", "--peak"),
    ("loop_points", "--loop-points"),
    ("demag_reverse_limit", "--demag-reverse-limit"),
    ("forc_levels", "--forc-levels"),
    ("forc_steps", "--forc-steps"),
    // Response options.
    ("duration", "--duration"),
    ("step", "--step"),
    ("bias", "--bias"),
    ("conductivity", "--conductivity"),
    ("fluid_lag", "--fluid-lag"),
    ("eddy_at", "--eddy-at"),
    // Thermal options.
    ("current", "--current"),
    ("duty", "--duty"),
    ("period", "--period"),
    ("ambient", "--ambient"),
    ("h", "--h"),
    ("emissivity", "--emissivity"),
    ("insulation_class", "--insulation-class"),
    ("time", "--time"),
    ("dt", "--dt"),
    // Closed-form formulas.
    ("discs", "--discs"),
    ("r1", "--r1"),
    ("r2", "--r2"),
    ("r0", "--r0"),
    ("r", "--r"),
    ("d", "--d"),
    ("g", "--g"),
    ("surfaces", "--surfaces"),
    ("tau_y", "--tau-y"),
    ("b", "--b"),
    ("eta", "--eta"),
    ("gap", "--gap"),
    ("window_width", "--window-width"),
    ("window_height", "--window-height"),
    ("awg", "--awg"),
    ("wire_diameter", "--wire-diameter"),
    ("inner_radius", "--inner-radius"),
    ("turns", "--turns"),
];

/// `(library name, flag)` of the arguments of `sweep` and `optimize` whose rules the study
/// library checks (not the keys of a problem file: those errors name the file and its key).
const STUDY_FLAGS: &[(&str, &str)] = &[
    ("vary", "--vary"),
    ("sample", "--sample"),
    ("shard", "--shard"),
    ("set", "--set"),
    ("generations", "--generations"),
    ("max_evaluations", "--max-evaluations"),
    ("polish", "--polish"),
    ("polish_objective", "--polish-objective"),
    ("polish_evaluations", "--polish-evaluations"),
    ("mesh", "--mesh"),
    ("speed", "--speed"),
    ("order", "--order"),
    ("points", "--points"),
    ("parameter", "--parameter"),
];

/// The element order of `--order` by the library's rule (1 or 2), an error naming the flag.
pub fn order(degree: u8) -> Result<ElementOrder, Box<FieldError>> {
    ElementOrder::try_from(i64::from(degree))
        .map_err(|e| Box::new(e.renamed(&[("order", "--order")])))
}

/// A design error with the field of an input error named by its flag.
pub fn design(e: DesignError) -> DesignError {
    e.with_field_names(FLAGS)
}

/// A study error with the field of an input error named by its flag.
pub fn study(e: ExploreError) -> ExploreError {
    e.with_field_names(STUDY_FLAGS)
}

/// A thermal error with the field of an input error named by its flag.
pub fn thermal(e: ThermalError) -> ThermalError {
    e.with_field_names(FLAGS)
}
