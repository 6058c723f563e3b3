//! Brake specification: the TOML file a researcher writes to describe an MR brake.
//!
//! Brief overview: [`BrakeSpec`] is the whole file; [`BrakeSpec::from_toml_str`] parses it (lengths
//! as strings with units, `"25mm"`, or bare SI numbers, `0.025`, read by [`mrbrake_units`]) and
//! [`BrakeSpec::validate`] checks every rule, returning the warnings or an input error that names
//! the field and its allowed range. [`default_spec`] is the embedded thesis bidirectional brake
//! (`examples/specs/thesis-bidirectional.toml`).
//!
//! Configurations (thesis ch. 3 and 4): single disc (3.7), multi-disc (3.8), drum (3.9),
//! multi-drum (4.4, 4.5), and the bidirectional brake (two identical multi-drum units on one shaft,
//! separated by a non-magnetic spacer, each with its own coil and a one-way bearing engaging in the
//! opposite direction, thesis 4.3). Coil placement inner / outer / two-sided (thesis 3.1.4).
//!
//! The geometric meaning of every dimension (which part it sizes, and where) is documented on the
//! field and drawn by [`crate::geometry`]; rules that need the assembled parts (overlaps, gaps bounded
//! by a rotating and a static wall, envelope) are checked there too, and reported through
//! [`BrakeSpec::validate`].

use serde::{Deserialize, Deserializer, Serialize};

use mrbrake_units::{Dimension, parse};

use crate::DesignError;

/// The embedded default specification: the thesis's bidirectional multi-drum brake.
pub const DEFAULT_SPEC_TOML: &str =
    include_str!("../../../examples/specs/thesis-bidirectional.toml");

/// Parses the embedded default specification.
pub fn default_spec() -> BrakeSpec {
    BrakeSpec::from_toml_str(DEFAULT_SPEC_TOML, "thesis-bidirectional.toml (embedded)")
        .expect("the embedded default spec is checked by the test suite")
}

/// A length read from TOML: a string with a unit (`"25mm"`) or a bare number in metres.
/// Serialised as a bare SI number (metres), which the reader accepts.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Serialize)]
pub struct Length(pub f64);

impl Length {
    /// The value in metres.
    pub fn m(self) -> f64 {
        self.0
    }
}

/// A current read from TOML: a string with a unit (`"2A"`, `"500mA"`) or a bare number in amperes.
/// Serialised as a bare SI number (amperes), which the reader accepts.
#[derive(Debug, Clone, Copy, PartialEq, PartialOrd, Serialize)]
pub struct Current(pub f64);

impl Current {
    /// The value in amperes.
    pub fn a(self) -> f64 {
        self.0
    }
}

fn quantity<'de, D: Deserializer<'de>>(d: D, dim: Dimension) -> Result<f64, D::Error> {
    #[derive(Deserialize)]
    #[serde(untagged)]
    enum Raw {
        Number(f64),
        Integer(i64),
        Text(String),
    }
    match Raw::deserialize(d)? {
        Raw::Number(x) => Ok(x),
        Raw::Integer(i) => Ok(i as f64),
        Raw::Text(t) => parse(&t, dim).map_err(serde::de::Error::custom),
    }
}

impl<'de> Deserialize<'de> for Length {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        quantity(d, Dimension::Length).map(Length)
    }
}

impl<'de> Deserialize<'de> for Current {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        quantity(d, Dimension::Current).map(Current)
    }
}

/// The brake configuration (thesis 3.1.3 and 4.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Configuration {
    /// One rotating disc between two static case faces, two fluid surfaces (3.7).
    SingleDisc,
    /// n rotating discs interleaved with n-1 static discs, 2n fluid surfaces (3.8).
    MultiDisc,
    /// One rotating cylinder between a static core and the case, two fluid surfaces (3.9).
    Drum,
    /// n rotating cylinders interleaved with static cylinders, 2n fluid surfaces (4.4, 4.5).
    MultiDrum,
    /// Two identical multi-drum units on one shaft, separated by a non-magnetic spacer, each with
    /// its own coil and a one-way bearing engaging in the opposite direction (thesis 4.3).
    Bidirectional,
}

impl Configuration {
    /// True for the configurations whose fluid surfaces are cylinders (flux crosses them radially).
    pub fn is_drum(self) -> bool {
        matches!(self, Self::Drum | Self::MultiDrum | Self::Bidirectional)
    }

    /// The name used in TOML.
    pub fn name(self) -> &'static str {
        match self {
            Self::SingleDisc => "single-disc",
            Self::MultiDisc => "multi-disc",
            Self::Drum => "drum",
            Self::MultiDrum => "multi-drum",
            Self::Bidirectional => "bidirectional",
        }
    }
}

/// Where the coil sits (thesis 3.1.4, Figures 3.7–3.9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CoilPlacement {
    /// Discs: radially inside the working surfaces (around the core on the shaft side).
    /// Drums: beside the drum stack, against the static inner core.
    Inner,
    /// Discs: radially outside the working surfaces, in the case.
    /// Drums: beside the drum stack, against the outer case wall.
    Outer,
    /// Discs only: one coil inside and one outside the working surfaces, driven with opposite
    /// current signs so that both push flux the same way through the discs (thesis 3.1.4).
    TwoSided,
}

/// Material names of the parts, from the `mrbrake_materials` library (e.g. `steel-1008`,
/// `aluminium`, `stainless-304`, `mrf-122eg`, `copper`, `air`).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Materials {
    /// Low-carbon steel of the flux path (core, case wall, end plates, cylinders or discs).
    pub flux_path: String,
    /// Non-magnetic structural parts (rotor hub, bobbin, covers, fillers).
    pub non_magnetic: String,
    /// The shaft.
    pub shaft: String,
    /// The MR fluid in the gaps.
    pub fluid: String,
    /// The coil conductor.
    #[serde(default = "default_copper")]
    pub coil: String,
    /// The spacer between the two units of a bidirectional brake.
    #[serde(default)]
    pub spacer: Option<String>,
    /// What surrounds the device in the model (the air box).
    #[serde(default = "default_air")]
    pub surroundings: String,
}

fn default_copper() -> String {
    "copper".into()
}

fn default_air() -> String {
    "air".into()
}

/// The shaft.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Shaft {
    /// Shaft radius (thesis Table 4.5: 5 mm).
    pub radius: Length,
}

/// The static magnetic circuit and the non-magnetic closures around the working surfaces.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Housing {
    /// Outer radius of the case (half the device diameter).
    pub outer_radius: Length,
    /// Radial thickness of the steel case wall beside the coil and rotor (the wall is thicker
    /// where it reaches inwards to bound the working surfaces).
    pub case_thickness: Length,
    /// Axial thickness of the steel end plate that closes the flux loop beyond the coil.
    pub end_plate_thickness: Length,
    /// Drums: radial thickness of the static steel inner core ("inner case", thesis Table 4.5: 7 mm).
    /// Discs: radial thickness of the steel pole ring inside an inner coil.
    pub inner_case_thickness: Length,
    /// Drums only: axial thickness of the non-magnetic cover at the rotor end.
    #[serde(default)]
    pub cover_thickness: Option<Length>,
    /// Drums only: axial thickness of the non-magnetic rotary part (rotor disc) that carries the
    /// rotating cylinders to the hub on the shaft.
    #[serde(default)]
    pub rotor_disc_thickness: Option<Length>,
}

/// Multi-drum working surfaces (thesis 4.4, 4.5, Figure 4.15).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Drum {
    /// R0: outer radius of the static inner core, the first fluid surface.
    pub r0: Length,
    /// h: axial height of the cylinders and fluid gaps.
    pub height: Length,
    /// d: radial thickness of each cylinder.
    pub cylinder_thickness: Length,
    /// g: radial width of each fluid gap.
    pub gap: Length,
    /// n: number of rotating cylinders (fluid surfaces = 2n; `drum` requires 1).
    pub rotating_cylinders: u32,
}

impl Drum {
    /// R_k = R0 + k (d + g) (4.5): radius of fluid surface k (inner wall of gap k), m.
    pub fn surface_radius_m(&self, k: u32) -> f64 {
        self.r0.m() + f64::from(k) * (self.cylinder_thickness.m() + self.gap.m())
    }

    /// Number of fluid surfaces (gaps), 2n.
    pub fn surfaces(&self) -> u32 {
        2 * self.rotating_cylinders
    }
}

/// Disc working surfaces (thesis 3.6–3.8, Figure 3.11).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Disc {
    /// R1: inner radius of the fluid annulus.
    pub inner_radius: Length,
    /// R2: outer radius of the fluid annulus.
    pub outer_radius: Length,
    /// d: axial thickness of each disc.
    pub thickness: Length,
    /// g: axial width of each fluid gap.
    pub gap: Length,
    /// n: number of rotating discs (`single-disc` requires 1); fluid surfaces = 2n.
    pub count: u32,
}

/// The wire: by AWG gauge or by bare copper diameter.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Wire {
    /// American wire gauge (thesis Table 4.6).
    #[serde(default)]
    pub awg: Option<u32>,
    /// Copper diameter.
    #[serde(default)]
    pub diameter: Option<Length>,
    /// Current rating of the wire (thesis Table 4.6: 2.1 A for AWG 24 at 75 °C); checked against
    /// the maximum current as a warning.
    #[serde(default)]
    pub rated_current: Option<Current>,
}

/// The coil (thesis 4.2.2: window C_w × C_h, (4.1)–(4.3)).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Coil {
    /// Where the coil sits.
    pub placement: CoilPlacement,
    /// C_w: radial width of the winding window.
    pub window_width: Length,
    /// C_h: axial height of the winding window.
    pub window_height: Length,
    /// Non-magnetic bobbin wall between the window and its neighbours.
    pub bobbin_wall: Length,
    /// The wire.
    pub wire: Wire,
    /// Number of turns; if absent, computed from the window by (4.2), (4.3).
    #[serde(default)]
    pub turns: Option<u32>,
    /// Maximum operating current.
    pub max_current: Current,
}

/// The spacer between the two units of a bidirectional brake.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Spacer {
    /// Axial thickness of the non-magnetic spacer.
    pub thickness: Length,
}

/// The envelope the device must fit in.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Envelope {
    /// Maximum outer diameter.
    pub diameter: Length,
    /// Maximum axial length.
    pub length: Length,
}

/// Model (not device) settings.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Air margin around the device, radially and axially, before the outer (A = 0) boundary.
    pub air_margin: Length,
}

impl Default for Model {
    fn default() -> Self {
        Self { air_margin: Length(0.02) }
    }
}

/// A whole brake specification.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BrakeSpec {
    /// A short name for reports.
    pub name: String,
    /// The configuration.
    pub configuration: Configuration,
    /// Material of each part.
    pub materials: Materials,
    /// The shaft.
    pub shaft: Shaft,
    /// The static circuit.
    pub housing: Housing,
    /// Drum working surfaces (drum, multi-drum, bidirectional).
    #[serde(default)]
    pub drum: Option<Drum>,
    /// Disc working surfaces (single-disc, multi-disc).
    #[serde(default)]
    pub disc: Option<Disc>,
    /// The coil (one per unit).
    pub coil: Coil,
    /// The spacer (bidirectional only).
    #[serde(default)]
    pub spacer: Option<Spacer>,
    /// The envelope.
    pub envelope: Envelope,
    /// Model settings.
    #[serde(default)]
    pub model: Model,
}

/// A validation finding that does not stop the analysis.
#[derive(Debug, Clone, PartialEq)]
pub struct Warning {
    /// The field concerned, e.g. `coil.max_current`.
    pub field: String,
    /// What is unusual and why it matters.
    pub message: String,
}

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "warning: {}: {}", self.field, self.message)
    }
}

impl Wire {
    /// The copper diameter (m): given, or from the AWG gauge.
    pub fn diameter_m(&self) -> Option<f64> {
        self.diameter
            .map(Length::m)
            .or_else(|| self.awg.map(mrbrake_materials::wire::awg_diameter_m))
    }

    /// The current rating (A): given, or from thesis Table 4.6 for AWG 20–26.
    pub fn rated_current_a(&self) -> Option<f64> {
        self.rated_current
            .map(Current::a)
            .or_else(|| self.awg.and_then(mrbrake_materials::wire::thesis_current_rating_a))
    }
}

/// Collects errors, each naming its field and allowed range.
#[derive(Debug, Default)]
pub(crate) struct Problems {
    pub errors: Vec<String>,
    pub warnings: Vec<Warning>,
}

impl Problems {
    pub fn error(&mut self, field: &str, message: impl Into<String>) {
        self.errors.push(format!("{field}: {}", message.into()));
    }

    pub fn warn(&mut self, field: &str, message: impl Into<String>) {
        self.warnings.push(Warning { field: field.into(), message: message.into() });
    }

    /// A length that must be > 0 (and below a sanity bound of 10 m).
    pub fn positive(&mut self, field: &str, value: Length) {
        let v = value.m();
        if !(v.is_finite() && v > 0.0 && v < 10.0) {
            self.error(field, format!("{} must be a length in (0, 10 m)", fmt_mm(v)));
        }
    }
}

/// Formats a length in millimetres for messages.
pub(crate) fn fmt_mm(m: f64) -> String {
    format!("{:.4} mm", m * 1e3).replace(".0000 mm", " mm")
}

impl BrakeSpec {
    /// Parses TOML text; `origin` (a file name) prefixes error messages.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, DesignError> {
        toml::from_str(text).map_err(|e| DesignError::Input(format!("{origin}: {e}")))
    }

    /// The spec as TOML, lengths and currents as bare SI numbers: a file [`Self::from_toml_str`] reads
    /// back to an equal spec (design studies write their chosen designs this way).
    pub fn to_toml_string(&self) -> Result<String, DesignError> {
        toml::to_string(self).map_err(|e| {
            DesignError::Numerical(format!("cannot write spec '{}' as TOML: {e}", self.name))
        })
    }

    /// Reads and parses a spec file.
    pub fn from_path(path: &std::path::Path) -> Result<Self, DesignError> {
        let text = std::fs::read_to_string(path).map_err(|e| {
            DesignError::Input(format!("{}: cannot read the spec: {e}", path.display()))
        })?;
        Self::from_toml_str(&text, &path.display().to_string())
    }

    /// Checks every rule; returns the warnings, or an input error listing every broken rule (each
    /// naming its field and the allowed range). Includes the geometric rules (overlaps, fluid gaps,
    /// envelope) by building the geometry.
    pub fn validate(&self) -> Result<Vec<Warning>, DesignError> {
        let mut p = Problems::default();
        self.check_fields(&mut p);
        if p.errors.is_empty() {
            crate::geometry::check_assembly(self, &mut p);
        }
        if p.errors.is_empty() {
            Ok(p.warnings)
        } else {
            Err(DesignError::Input(format!(
                "invalid brake spec '{}':\n  {}",
                self.name,
                p.errors.join("\n  ")
            )))
        }
    }

    /// The wire diameter (m); validation guarantees it exists.
    pub fn wire_diameter_m(&self) -> f64 {
        self.coil.wire.diameter_m().unwrap_or(f64::NAN)
    }

    /// The number of turns: given, or computed in the window by (4.2), (4.3).
    pub fn turns(&self) -> u32 {
        match self.coil.turns {
            Some(n) => n,
            None => turns_in_window(
                self.coil.window_width.m(),
                self.coil.window_height.m(),
                self.wire_diameter_m() / 2.0,
            ),
        }
    }

    fn check_materials(&self, p: &mut Problems) {
        use mrbrake_materials::MaterialKind;
        let library = mrbrake_materials::library::names();
        let kind_of = |name: &str| {
            let wanted = name.trim().to_ascii_lowercase();
            library.iter().find(|(n, _)| *n == wanted).map(|(_, k)| *k)
        };
        let names_of = |kind: Option<MaterialKind>| -> String {
            library
                .iter()
                .filter(|(_, k)| kind.is_none_or(|want| *k == want))
                .map(|(n, _)| *n)
                .collect::<Vec<_>>()
                .join(", ")
        };
        let m = &self.materials;
        let mut entries = vec![
            ("materials.flux_path", &m.flux_path, None),
            ("materials.non_magnetic", &m.non_magnetic, None),
            ("materials.shaft", &m.shaft, None),
            ("materials.fluid", &m.fluid, Some(MaterialKind::MrFluid)),
            ("materials.coil", &m.coil, Some(MaterialKind::Linear)),
            ("materials.surroundings", &m.surroundings, Some(MaterialKind::Linear)),
        ];
        if let Some(spacer) = &m.spacer {
            entries.push(("materials.spacer", spacer, None));
        }
        for (field, name, wanted) in entries {
            match (kind_of(name), wanted) {
                (None, _) => p.error(
                    field,
                    format!("'{name}' is not in the material library; known: {}", names_of(wanted)),
                ),
                (Some(kind), Some(want)) if kind != want => p.error(
                    field,
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
            ("materials.non_magnetic", &m.non_magnetic),
            ("materials.spacer", m.spacer.as_ref().unwrap_or(&m.non_magnetic)),
        ] {
            if kind_of(name) == Some(MaterialKind::Steel) {
                p.warn(
                    field,
                    format!("'{name}' is a steel: this part is meant to block flux (thesis 4.3.1)"),
                );
            }
        }
    }

    fn check_fields(&self, p: &mut Problems) {
        if self.name.trim().is_empty() {
            p.error("name", "must not be empty");
        }
        self.check_materials(p);
        p.positive("shaft.radius", self.shaft.radius);
        let h = &self.housing;
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
                None if self.configuration.is_drum() => p.error(
                    field,
                    format!(
                        "configuration '{}' needs it (a length > 0)",
                        self.configuration.name()
                    ),
                ),
                None => {}
            }
        }
        p.positive("envelope.diameter", self.envelope.diameter);
        p.positive("envelope.length", self.envelope.length);
        p.positive("model.air_margin", self.model.air_margin);

        let config = self.configuration;
        if config.is_drum() {
            match &self.drum {
                None => p.error(
                    "drum",
                    format!("configuration '{}' needs a [drum] table", config.name()),
                ),
                Some(d) => {
                    p.positive("drum.r0", d.r0);
                    p.positive("drum.height", d.height);
                    p.positive("drum.cylinder_thickness", d.cylinder_thickness);
                    p.positive("drum.gap", d.gap);
                    let range = if config == Configuration::Drum { 1..=1 } else { 1..=20 };
                    if !range.contains(&d.rotating_cylinders) {
                        p.error(
                            "drum.rotating_cylinders",
                            format!(
                                "{} is outside the allowed range {}..={} for '{}'",
                                d.rotating_cylinders,
                                range.start(),
                                range.end(),
                                config.name()
                            ),
                        );
                    }
                }
            }
            if self.disc.is_some() {
                p.error(
                    "disc",
                    format!("configuration '{}' uses [drum], not [disc]", config.name()),
                );
            }
            if self.coil.placement == CoilPlacement::TwoSided {
                p.error(
                    "coil.placement",
                    "'two-sided' is defined for disc configurations (thesis 3.1.4, Figure 3.9); drums accept 'inner' or 'outer'",
                );
            }
        } else {
            match &self.disc {
                None => p.error(
                    "disc",
                    format!("configuration '{}' needs a [disc] table", config.name()),
                ),
                Some(d) => {
                    p.positive("disc.inner_radius", d.inner_radius);
                    p.positive("disc.outer_radius", d.outer_radius);
                    p.positive("disc.thickness", d.thickness);
                    p.positive("disc.gap", d.gap);
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
                    let range = if config == Configuration::SingleDisc { 1..=1 } else { 1..=20 };
                    if !range.contains(&d.count) {
                        p.error(
                            "disc.count",
                            format!(
                                "{} is outside the allowed range {}..={} for '{}'",
                                d.count,
                                range.start(),
                                range.end(),
                                config.name()
                            ),
                        );
                    }
                }
            }
            if self.drum.is_some() {
                p.error(
                    "drum",
                    format!("configuration '{}' uses [disc], not [drum]", config.name()),
                );
            }
        }
        if config == Configuration::Bidirectional {
            match &self.spacer {
                None => p.error(
                    "spacer",
                    "the bidirectional brake needs a [spacer] table (its thickness)",
                ),
                Some(s) => p.positive("spacer.thickness", s.thickness),
            }
            if self.materials.spacer.as_deref().is_none_or(|s| s.trim().is_empty()) {
                p.error(
                    "materials.spacer",
                    "the bidirectional brake needs the spacer's (non-magnetic) material",
                );
            }
        } else if self.spacer.is_some() {
            p.error(
                "spacer",
                format!("only the bidirectional brake has a spacer, not '{}'", config.name()),
            );
        }

        let c = &self.coil;
        p.positive("coil.window_width", c.window_width);
        p.positive("coil.window_height", c.window_height);
        p.positive("coil.bobbin_wall", c.bobbin_wall);
        match (&c.wire.awg, &c.wire.diameter) {
            (None, None) => p.error("coil.wire", "give either awg (18..=40) or diameter"),
            (Some(_), Some(_)) => p.error("coil.wire", "give either awg or diameter, not both"),
            (Some(g), None) if !(18..=40).contains(g) => {
                p.error("coil.wire.awg", format!("{g} is outside 18..=40"))
            }
            (None, Some(d)) => p.positive("coil.wire.diameter", *d),
            _ => {}
        }
        let current = c.max_current.a();
        if !(current.is_finite() && current > 0.0 && current <= 100.0) {
            p.error("coil.max_current", format!("{current} A must be in (0, 100] A"));
        }
        if let Some(d) = c.wire.diameter_m().filter(|d| *d > 0.0) {
            if d > c.window_width.m() || d > c.window_height.m() {
                p.error("coil.wire", format!("a {} wire does not fit the coil window", fmt_mm(d)));
            } else {
                let turns_fit = turns_in_window(c.window_width.m(), c.window_height.m(), d / 2.0);
                match c.turns {
                    Some(0) => p.error("coil.turns", "must be at least 1"),
                    Some(n) if n > turns_fit => p.error(
                        "coil.turns",
                        format!("{n} turns do not fit the window: at most {turns_fit} by (4.2), (4.3) with a {} wire", fmt_mm(d)),
                    ),
                    _ => {}
                }
                // (4.1): J = I / (sqrt(3) d^2), the thesis's current density for hexagonal packing.
                let j_a_per_mm2 = current / (3f64.sqrt() * (d * 1e3).powi(2));
                if j_a_per_mm2 > 6.0 {
                    p.warn(
                        "coil.max_current",
                        format!("current density (4.1) {j_a_per_mm2:.2} A/mm² exceeds the 2.5–6 A/mm² range the thesis allows for copper (4.2.2)"),
                    );
                }
            }
            if let Some(rating) = c.wire.rated_current_a()
                && current > rating
            {
                p.warn(
                    "coil.max_current",
                    format!("{current} A exceeds the wire rating {rating} A"),
                );
            }
        }
    }
}

/// Turns that fit a C_w × C_h window with wire radius r, thesis (4.2), (4.3)
/// ([`crate::formula::turns_in_window`]); 0 when not even one wire fits.
pub fn turns_in_window(window_width_m: f64, window_height_m: f64, wire_radius_m: f64) -> u32 {
    crate::formula::turns_in_window(window_width_m, window_height_m, wire_radius_m)
        .map_or(0, |t| t.turns)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lengths_accept_units_and_bare_si() {
        #[derive(Deserialize)]
        struct T {
            a: Length,
            b: Length,
            c: Current,
        }
        let t: T = toml::from_str("a = \"25mm\"\nb = 0.0005\nc = \"500mA\"").unwrap();
        assert!((t.a.m() - 0.025).abs() < 1e-15);
        assert!((t.b.m() - 0.0005).abs() < 1e-15);
        assert!((t.c.a() - 0.5).abs() < 1e-15);
        let err = toml::from_str::<T>("a = \"25kg\"\nb = 1\nc = 1").err().unwrap().to_string();
        assert!(err.contains("kg"), "{err}");
    }

    #[test]
    fn awg_24_resolves_to_0_511_mm_and_2_1_a() {
        let wire = Wire { awg: Some(24), diameter: None, rated_current: None };
        assert!((wire.diameter_m().unwrap() * 1e3 - 0.511).abs() < 0.001);
        assert!((wire.rated_current_a().unwrap() - 2.1).abs() < 1e-12);
    }

    #[test]
    fn turns_formula_matches_hand_count() {
        // r = 0.25 mm, C_h = 5 mm: i = floor(4.5 / 0.4330) = 10; C_w = 5 mm: N = 10*11 - 5 = 105.
        assert_eq!(turns_in_window(5e-3, 5e-3, 0.25e-3), 105);
    }
}
