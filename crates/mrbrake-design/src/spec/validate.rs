//! The one validation of a spec: every field against its allowed range, then the rules that need
//! the assembled parts (fit, overlaps, fluid gaps, envelope; [`crate::geometry`]). The geometry is
//! assembled once and handed to the caller in the [`Validated`] result.

use mrbrake_error::FieldErrors;
use mrbrake_materials::MaterialKind;

use super::{
    AWG_BOUNDS, BrakeSpec, CoilPlacement, Configuration, ConfigurationKind, Disc, Drum, GAP_BOUNDS,
    LENGTH_BOUNDS, Length, MATERIAL_FIELDS, MAX_CURRENT_BOUNDS, RATED_CURRENT_BOUNDS, TURNS_BOUNDS,
    Warning, WorkingSurfaces, fmt_mm, turns_in_window,
};
use crate::DesignError;
use crate::geometry::{self, BrakeGeometry};

/// A spec that passed every rule: its geometry (assembled once, during the validation) and the
/// findings that do not stop an analysis.
#[derive(Debug, Clone)]
pub struct Validated {
    /// The brake's parts, gaps and coils.
    pub geometry: BrakeGeometry,
    /// Warnings (e.g. a current above the wire's rating).
    pub warnings: Vec<Warning>,
}

/// Collects the invalid fields, each naming its allowed range, and the warnings.
#[derive(Debug, Default)]
pub(crate) struct Problems {
    pub errors: FieldErrors,
    pub warnings: Vec<Warning>,
}

impl Problems {
    pub fn error(&mut self, field: &str, message: impl Into<String>) {
        self.errors.add(field, message);
    }

    pub fn warn(&mut self, field: &str, message: impl Into<String>) {
        self.warnings.push(Warning { field: field.into(), message: message.into() });
    }

    /// True while no error was found.
    pub fn ok(&self) -> bool {
        self.errors.is_empty()
    }

    /// A length that must be within [`LENGTH_BOUNDS`] (> 0, below a sanity bound of 10 m).
    pub fn positive(&mut self, field: &str, value: Length) {
        let v = value.m();
        if !LENGTH_BOUNDS.contains(v) {
            let max = LENGTH_BOUNDS.max;
            self.error(field, format!("{} must be a length in (0, {max} m)", fmt_mm(v)));
        }
    }

    /// A fluid gap within [`GAP_BOUNDS`].
    pub fn gap(&mut self, field: &str, value: Length) {
        let v = value.m();
        if !GAP_BOUNDS.contains(v) {
            self.error(
                field,
                format!(
                    "{} must be a fluid gap in (0, {}]; the thesis's gaps are 0.5–1 mm",
                    fmt_mm(v),
                    fmt_mm(GAP_BOUNDS.max)
                ),
            );
        }
    }
}

impl BrakeSpec {
    /// Checks every rule and assembles the geometry once; returns it with the warnings, or an input
    /// error listing every broken rule (each naming its field, the allowed range, and the file and
    /// line the spec was read from). The geometric rules (fit, overlaps, fluid gaps, envelope) are
    /// checked once the fields are valid.
    pub fn validate(&self) -> Result<Validated, DesignError> {
        let mut p = Problems::default();
        check_fields(self, &mut p);
        if p.ok() {
            geometry::check_fit(self, &mut p);
        }
        if !p.ok() {
            return Err(self.invalid(p.errors));
        }
        let geometry = geometry::assemble(self);
        geometry::check_assembled(self, &geometry, &mut p);
        if p.ok() {
            Ok(Validated { geometry, warnings: p.warnings })
        } else {
            Err(self.invalid(p.errors))
        }
    }

    pub(crate) fn invalid(&self, errors: FieldErrors) -> DesignError {
        DesignError::Spec { name: self.name.clone(), errors: self.source.locate(errors) }
    }
}

/// Every field on its own, in file order.
fn check_fields(spec: &BrakeSpec, p: &mut Problems) {
    if spec.name.trim().is_empty() {
        p.error("name", "must not be empty");
    }
    check_materials(spec, p);
    p.positive("shaft.radius", spec.shaft.radius);
    check_housing(spec, p);
    p.positive("envelope.diameter", spec.envelope.diameter);
    p.positive("envelope.length", spec.envelope.length);
    p.positive("model.air_margin", spec.model.air_margin);
    spec.drag.check(&mut p.errors);
    let kind = spec.configuration.kind();
    match spec.configuration.surfaces() {
        WorkingSurfaces::Drums(drum) => check_drum(drum, kind, p),
        WorkingSurfaces::Discs(disc) => check_disc(disc, kind, p),
    }
    if kind.is_drum() && spec.coil.placement == CoilPlacement::TwoSided {
        p.error(
            "coil.placement",
            "'two-sided' is defined for disc configurations (thesis 3.1.4, Figure 3.9); drums accept 'inner' or 'outer'",
        );
    }
    if let Configuration::Bidirectional { spacer, .. } = &spec.configuration {
        p.positive("spacer.thickness", spacer.thickness);
        if spec.materials.spacer.as_deref().is_none_or(|s| s.trim().is_empty()) {
            p.error(
                "materials.spacer",
                "the bidirectional brake needs the spacer's (non-magnetic) material",
            );
        }
    }
    check_coil(spec, p);
    super::factors::check(&spec.fluid, &spec.steel, p);
}

/// Each material is in the library and of the kind its part needs ([`MATERIAL_FIELDS`]); a flux
/// path that is not steel and a flux blocker (non-magnetic parts, bobbin, spacer) that is steel are
/// warnings.
fn check_materials(spec: &BrakeSpec, p: &mut Problems) {
    let m = &spec.materials;
    for field in MATERIAL_FIELDS {
        let Some(name) = m.get(field.path) else { continue };
        let wanted = field.required;
        match (kind_of(name), wanted) {
            (None, _) => p.error(
                field.path,
                format!("'{name}' is not in the material library; known: {}", names_of(wanted)),
            ),
            (Some(kind), Some(want)) if kind != want => p.error(
                field.path,
                format!(
                    "'{name}' is a {} material; this part needs a {} material: {}",
                    kind.as_str(),
                    want.as_str(),
                    names_of(Some(want))
                ),
            ),
            _ => {}
        }
    }
    if kind_of(&m.flux_path).is_some_and(|k| k != MaterialKind::Steel) {
        p.warn(
            "materials.flux_path",
            format!("'{}' is not a steel: the flux path will be non-magnetic", m.flux_path),
        );
    }
    for (field, name) in [
        ("materials.non_magnetic", m.non_magnetic.as_str()),
        ("materials.bobbin", m.bobbin()),
        ("materials.spacer", m.spacer()),
    ] {
        // A bobbin left to the default is the non-magnetic material, warned about there.
        if field == "materials.bobbin" && m.bobbin.is_none() {
            continue;
        }
        if kind_of(name) == Some(MaterialKind::Steel) {
            p.warn(
                field,
                format!("'{name}' is a steel: this part is meant to block flux (thesis 4.3.1)"),
            );
        }
    }
}

/// The library kind of a material name (case and surrounding blanks ignored).
fn kind_of(name: &str) -> Option<MaterialKind> {
    let wanted = name.trim().to_ascii_lowercase();
    mrbrake_materials::library::names().iter().find(|(n, _)| *n == wanted).map(|(_, k)| *k)
}

/// The library's names of a kind (all names for `None`), comma-separated.
fn names_of(kind: Option<MaterialKind>) -> String {
    mrbrake_materials::library::names()
        .iter()
        .filter(|(_, k)| kind.is_none_or(|want| *k == want))
        .map(|(n, _)| *n)
        .collect::<Vec<_>>()
        .join(", ")
}

/// The housing's lengths; drums need the cover and the rotor disc too.
fn check_housing(spec: &BrakeSpec, p: &mut Problems) {
    let h = &spec.housing;
    p.positive("housing.outer_radius", h.outer_radius);
    p.positive("housing.case_thickness", h.case_thickness);
    p.positive("housing.end_plate_thickness", h.end_plate_thickness);
    p.positive("housing.inner_case_thickness", h.inner_case_thickness);
    for (field, value) in [
        ("housing.cover_thickness", h.cover_thickness),
        ("housing.rotor_disc_thickness", h.rotor_disc_thickness),
    ] {
        match value {
            Some(v) => p.positive(field, v),
            None if spec.configuration.is_drum() => p.error(
                field,
                format!("configuration '{}' needs it (a length > 0)", spec.configuration.name()),
            ),
            None => {}
        }
    }
}

fn check_drum(d: &Drum, kind: ConfigurationKind, p: &mut Problems) {
    p.positive("drum.r0", d.r0);
    p.positive("drum.height", d.height);
    p.positive("drum.cylinder_thickness", d.cylinder_thickness);
    p.gap("drum.gap", d.gap);
    check_rotor_count("drum.rotating_cylinders", d.rotating_cylinders, kind, p);
}

fn check_disc(d: &Disc, kind: ConfigurationKind, p: &mut Problems) {
    p.positive("disc.inner_radius", d.inner_radius);
    p.positive("disc.outer_radius", d.outer_radius);
    p.positive("disc.thickness", d.thickness);
    p.gap("disc.gap", d.gap);
    if d.outer_radius.m() <= d.inner_radius.m() {
        p.error(
            "disc.outer_radius",
            format!(
                "{} must be greater than disc.inner_radius = {}",
                fmt_mm(d.outer_radius.m()),
                fmt_mm(d.inner_radius.m())
            ),
        );
    }
    check_rotor_count("disc.count", d.count, kind, p);
}

/// 1 rotating disc or cylinder for the single disc and the drum, 1..=20 otherwise.
fn check_rotor_count(field: &str, count: u32, kind: ConfigurationKind, p: &mut Problems) {
    let range = 1..=kind.max_rotors();
    if !range.contains(&count) {
        p.error(
            field,
            format!(
                "{count} is outside the allowed range {}..={} for '{}'",
                range.start(),
                range.end(),
                kind.name()
            ),
        );
    }
}

/// The window, the wire (gauge or diameter) and the current; then the winding in the window.
fn check_coil(spec: &BrakeSpec, p: &mut Problems) {
    let c = &spec.coil;
    p.positive("coil.window_width", c.window_width);
    p.positive("coil.window_height", c.window_height);
    p.positive("coil.bobbin_wall", c.bobbin_wall);
    let (awg_min, awg_max) = (AWG_BOUNDS.min, AWG_BOUNDS.max);
    match (&c.wire.awg, &c.wire.diameter) {
        (None, None) => {
            p.error("coil.wire", format!("give either awg ({awg_min}..={awg_max}) or diameter"))
        }
        (Some(_), Some(_)) => p.error("coil.wire", "give either awg or diameter, not both"),
        (Some(g), None) if !AWG_BOUNDS.contains(f64::from(*g)) => {
            p.error("coil.wire.awg", format!("{g} is outside {awg_min}..={awg_max}"))
        }
        (None, Some(d)) => p.positive("coil.wire.diameter", *d),
        _ => {}
    }
    if let Some(rating) = c.wire.rated_current.map(super::Current::a)
        && !RATED_CURRENT_BOUNDS.contains(rating)
    {
        let max = RATED_CURRENT_BOUNDS.max;
        p.error("coil.wire.rated_current", format!("{rating} A must be in (0, {max}] A"));
    }
    let current = c.max_current.a();
    if !MAX_CURRENT_BOUNDS.contains(current) {
        let max = MAX_CURRENT_BOUNDS.max;
        p.error("coil.max_current", format!("{current} A must be in (0, {max}] A"));
    }
    if let Some(d) = c.wire.diameter_m().filter(|d| *d > 0.0) {
        check_winding(spec, d, current, p);
    }
}

/// The warning of a winding whose copper fill factor ([`BrakeSpec::fill_factor`]) is above what a
/// winding reaches in practice ([`crate::formula::FILL_FACTOR_LIMIT`]), if it is.
fn fill_factor_warning(spec: &BrakeSpec) -> Option<Warning> {
    let (fill, limit) = (spec.fill_factor(), crate::formula::FILL_FACTOR_LIMIT);
    (fill > limit).then(|| Warning {
        field: "coil.turns".into(),
        message: format!(
            "{} turns fill the window to a copper fill factor of {fill:.3}, above the {limit} an \
             orthocyclic winding of enamelled wire reaches in practice (a random winding \
             reaches 0.45–0.5); fewer turns, a thinner wire or a larger window",
            spec.turns()
        ),
    })
}

/// A wire of diameter `d` (m) in the window: it fits, the turns fit (4.2), (4.3), the current
/// density (4.1) and the wire's rating at the maximum current.
fn check_winding(spec: &BrakeSpec, d: f64, current: f64, p: &mut Problems) {
    let c = &spec.coil;
    if d > c.window_width.m() || d > c.window_height.m() {
        p.error("coil.wire", format!("a {} wire does not fit the coil window", fmt_mm(d)));
    } else {
        let turns_fit = turns_in_window(c.window_width.m(), c.window_height.m(), d / 2.0);
        match c.turns {
            Some(n) if !TURNS_BOUNDS.contains(f64::from(n)) => {
                p.error("coil.turns", format!("must be at least {}", TURNS_BOUNDS.min))
            }
            Some(n) if n > turns_fit => p.error(
                "coil.turns",
                format!(
                    "{n} turns do not fit the window: at most {turns_fit} by (4.2), (4.3) with a {} wire",
                    fmt_mm(d)
                ),
            ),
            _ => {
                if let Some(warning) = fill_factor_warning(spec) {
                    p.warnings.push(warning);
                }
            }
        }
        // (4.1): J = I / (sqrt(3) d^2), the thesis's current density for hexagonal packing.
        let j_a_per_mm2 = current / (3f64.sqrt() * (d * 1e3).powi(2));
        if j_a_per_mm2 > 6.0 {
            p.warn(
                "coil.max_current",
                format!(
                    "current density (4.1) {j_a_per_mm2:.2} A/mm² exceeds the 2.5–6 A/mm² range the thesis allows for copper (4.2.2)"
                ),
            );
        }
    }
    if let Some(rating) = c.wire.rated_current_a()
        && current > rating
    {
        p.warn("coil.max_current", format!("{current} A exceeds the wire rating {rating} A"));
    }
}
