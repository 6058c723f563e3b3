//! Brake specification: the TOML file a researcher writes to describe an MR brake.
//!
//! Brief overview: [`BrakeSpec`] is the whole file; [`BrakeSpec::from_toml_str`] parses it (lengths
//! as strings with units, `"25mm"`, or bare SI numbers, `0.025`, read by [`mrbrake_units`]) and
//! [`BrakeSpec::validate`] checks every rule once, returning a [`Validated`] spec (its geometry,
//! assembled once, and the warnings) or an input error listing every invalid field with its allowed
//! range, file and line. [`default_spec`] is the embedded thesis bidirectional brake
//! (`examples/specs/thesis-bidirectional.toml`).
//!
//! Configurations (thesis ch. 3 and 4): single disc (3.7), multi-disc (3.8), drum (3.9),
//! multi-drum (4.4, 4.5), and the bidirectional brake (two identical multi-drum units on one shaft,
//! separated by a non-magnetic spacer, each with its own coil and a one-way bearing engaging in the
//! opposite direction, thesis 4.3). Coil placement inner / outer / two-sided (thesis 3.1.4).
//!
//! A [`Configuration`] carries the tables it needs (a drum brake its [`Drum`], the bidirectional
//! brake its [`Drum`] and [`Spacer`]), so a configuration without its working surfaces cannot be
//! represented; the file keeps its flat form (`configuration = "bidirectional"` beside `[drum]` and
//! `[spacer]` tables), read and written through the private `raw` module, which reports a missing
//! or superfluous table as an input error naming it. The JSON of a spec (the results store's design
//! keys hash it) is that same flat form.
//!
//! The numeric fields a design study may vary are listed beside each table's definition
//! (`Drum::FIELDS`, …) and collected by [`numeric_fields`]; a test checks the list against the
//! serialised spec of every configuration.
//!
//! The geometric meaning of every dimension (which part it sizes, and where) is documented on the
//! field and drawn by [`crate::geometry`]; rules that need the assembled parts (overlaps, gaps bounded
//! by a rotating and a static wall, envelope) are checked there too, and reported through
//! [`BrakeSpec::validate`].

mod factors;
mod raw;
mod schema;
mod source;
mod validate;

use schemars::JsonSchema;
use serde::{Deserialize, Deserializer, Serialize};

use mrbrake_materials::MaterialKind;
use mrbrake_units::{Dimension, parse};

use crate::DesignError;

pub use factors::{
    CONDUCTIVITY_BOUNDS, FILL_FRACTION_BOUNDS, FluidFactors, SCALE_BOUNDS, SteelFactors,
};
pub use schema::schema;
pub use source::SpecSource;
pub(crate) use validate::Problems;
pub use validate::Validated;

/// The embedded default specification: the thesis's bidirectional multi-drum brake.
pub const DEFAULT_SPEC_TOML: &str =
    include_str!("../../../../examples/specs/thesis-bidirectional.toml");

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

pub(crate) fn quantity<'de, D: Deserializer<'de>>(d: D, dim: Dimension) -> Result<f64, D::Error> {
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

/// What a numeric spec field holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// A length ([`Length`], m).
    Length,
    /// A current ([`Current`], A).
    Current,
    /// A whole number (turns, cylinders, discs, AWG gauge).
    Integer,
    /// A dimensionless factor or fraction (`fluid.yield_stress_scale`, `fluid.fill_fraction`).
    Factor,
    /// An electrical conductivity (S/m).
    Conductivity,
    /// A torque (N·m): the drag of a seal or a freewheel (`drag.seal_torque`).
    Torque,
}

impl Quantity {
    /// The SI unit, for messages and CSV headers (empty for whole numbers).
    pub fn unit(self) -> &'static str {
        match self {
            Self::Length => "m",
            Self::Current => "A",
            Self::Integer | Self::Factor => "",
            Self::Conductivity => "S/m",
            Self::Torque => "N·m",
        }
    }
}

/// The values a numeric field accepts (SI): what [`BrakeSpec::validate`] checks and what the
/// schema ([`schema`]) publishes, from this one definition.
pub use mrbrake_schema::Bounds;

/// Every length of a spec: positive, below a sanity bound of 10 m.
pub const LENGTH_BOUNDS: Bounds = Bounds::open(0.0, 10.0);
/// A fluid gap (m): positive, at most 10 mm. This tool's plausibility limit, not a law: the field
/// a coil drives across the fluid falls with the gap's width, and the thesis's gaps are 0.5–1 mm
/// (4.2.3, "depending on the manufacturing facility's capability"). Checked with the field itself,
/// so a gap written as a bare `0.5` (metres) is named before the envelope it overflows.
pub const GAP_BOUNDS: Bounds = Bounds::open_closed(0.0, 0.01);
/// The maximum current (A): positive, at most 100 A.
pub const MAX_CURRENT_BOUNDS: Bounds = Bounds::open_closed(0.0, 100.0);
/// The wire's American wire gauge: 18 to 40 (the gauges `mrbrake_materials::wire` tabulates).
pub const AWG_BOUNDS: Bounds = Bounds::closed(18.0, 40.0);
/// The number of turns: at least one (at most what fits the window, checked with the wire).
pub const TURNS_BOUNDS: Bounds = Bounds::closed(1.0, u32::MAX as f64);
/// Rotating discs or cylinders: at least one, at most [`MAX_ROTORS`] (one for the single disc and
/// the drum, [`ConfigurationKind::max_rotors`]).
pub const ROTOR_BOUNDS: Bounds = Bounds::closed(1.0, MAX_ROTORS as f64);
/// The most rotating discs or cylinders of the multi-disc and multi-drum families (a sanity bound).
pub const MAX_ROTORS: u32 = 20;
/// A rated current of the wire (A): positive, at most 1000 A.
pub const RATED_CURRENT_BOUNDS: Bounds = Bounds::open_closed(0.0, 1000.0);

/// A numeric field of the spec: its dotted TOML path, what it holds and the values it accepts.
/// Fields are equal when their paths are (the path decides the rest).
#[derive(Debug, Clone, Copy)]
pub struct SpecField {
    /// The dotted TOML path, e.g. `drum.gap`.
    pub path: &'static str,
    /// What it holds.
    pub quantity: Quantity,
    /// The values it accepts (SI).
    pub bounds: Bounds,
}

impl PartialEq for SpecField {
    fn eq(&self, other: &Self) -> bool {
        self.path == other.path
    }
}

impl Eq for SpecField {}

impl SpecField {
    const fn length(path: &'static str) -> Self {
        Self { path, quantity: Quantity::Length, bounds: LENGTH_BOUNDS }
    }

    const fn gap(path: &'static str) -> Self {
        Self { path, quantity: Quantity::Length, bounds: GAP_BOUNDS }
    }

    const fn current(path: &'static str, bounds: Bounds) -> Self {
        Self { path, quantity: Quantity::Current, bounds }
    }

    const fn integer(path: &'static str, bounds: Bounds) -> Self {
        Self { path, quantity: Quantity::Integer, bounds }
    }
}

/// Every numeric field of a spec, of every configuration (the tables' `FIELDS`, in file order):
/// the fields a design study may vary.
pub fn numeric_fields() -> impl Iterator<Item = &'static SpecField> + Clone {
    [
        Shaft::FIELDS,
        Housing::FIELDS,
        Drum::FIELDS,
        Disc::FIELDS,
        Coil::FIELDS,
        Wire::FIELDS,
        Spacer::FIELDS,
        Envelope::FIELDS,
        Model::FIELDS,
        FluidFactors::FIELDS,
        SteelFactors::FIELDS,
        crate::drag::Drag::FIELDS,
    ]
    .into_iter()
    .flatten()
}

/// The name of a configuration, as the file writes it (`configuration = "multi-drum"`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ConfigurationKind {
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

impl ConfigurationKind {
    /// True for the configurations whose fluid surfaces are cylinders (flux crosses them radially).
    pub fn is_drum(self) -> bool {
        matches!(self, Self::Drum | Self::MultiDrum | Self::Bidirectional)
    }

    /// Whether the file of this configuration has the optional table `table` (one of
    /// [`OPTIONAL_TABLES`]): drums their `[drum]`, discs their `[disc]`, the bidirectional brake
    /// also its `[spacer]`; a configuration must not have the others.
    pub fn requires_table(self, table: &str) -> bool {
        match table {
            "drum" => self.is_drum(),
            "disc" => !self.is_drum(),
            "spacer" => self == Self::Bidirectional,
            _ => false,
        }
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

    /// The most rotating discs or cylinders the configuration allows: one for the single disc and
    /// the drum, twenty (a sanity bound) for the multi-disc and multi-drum families.
    pub fn max_rotors(self) -> u32 {
        match self {
            Self::SingleDisc | Self::Drum => 1,
            Self::MultiDisc | Self::MultiDrum | Self::Bidirectional => MAX_ROTORS,
        }
    }
}

/// The tables a spec file has or not depending on its configuration
/// ([`ConfigurationKind::requires_table`]).
pub const OPTIONAL_TABLES: [&str; 3] = ["drum", "disc", "spacer"];

/// The brake configuration (thesis 3.1.3 and 4.3) with its working surfaces: each configuration
/// holds exactly the tables it needs.
#[derive(Debug, Clone, PartialEq)]
pub enum Configuration {
    /// One rotating disc (`count` 1) between two static case faces, two fluid surfaces (3.7).
    SingleDisc(Disc),
    /// n rotating discs interleaved with n-1 static discs, 2n fluid surfaces (3.8).
    MultiDisc(Disc),
    /// One rotating cylinder (`rotating_cylinders` 1) between a static core and the case (3.9).
    Drum(Drum),
    /// n rotating cylinders interleaved with static cylinders, 2n fluid surfaces (4.4, 4.5).
    MultiDrum(Drum),
    /// Two identical multi-drum units on one shaft, separated by a non-magnetic spacer, each with
    /// its own coil and a one-way bearing engaging in the opposite direction (thesis 4.3).
    Bidirectional {
        /// The working surfaces of each unit.
        drum: Drum,
        /// The spacer between the units.
        spacer: Spacer,
    },
}

/// The working surfaces of a configuration: cylinders (drums) or annuli (discs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum WorkingSurfaces<'a> {
    /// Cylindrical fluid gaps (drum, multi-drum, each unit of the bidirectional brake).
    Drums(&'a Drum),
    /// Annular fluid gaps (single disc, multi-disc).
    Discs(&'a Disc),
}

impl Configuration {
    /// The configuration's name.
    pub fn kind(&self) -> ConfigurationKind {
        match self {
            Self::SingleDisc(_) => ConfigurationKind::SingleDisc,
            Self::MultiDisc(_) => ConfigurationKind::MultiDisc,
            Self::Drum(_) => ConfigurationKind::Drum,
            Self::MultiDrum(_) => ConfigurationKind::MultiDrum,
            Self::Bidirectional { .. } => ConfigurationKind::Bidirectional,
        }
    }

    /// The name used in TOML.
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }

    /// True for the configurations whose fluid surfaces are cylinders (flux crosses them radially).
    pub fn is_drum(&self) -> bool {
        self.kind().is_drum()
    }

    /// The working surfaces.
    pub fn surfaces(&self) -> WorkingSurfaces<'_> {
        match self {
            Self::SingleDisc(disc) | Self::MultiDisc(disc) => WorkingSurfaces::Discs(disc),
            Self::Drum(drum) | Self::MultiDrum(drum) | Self::Bidirectional { drum, .. } => {
                WorkingSurfaces::Drums(drum)
            }
        }
    }

    /// The drum surfaces of a drum configuration.
    pub fn drum(&self) -> Option<&Drum> {
        match self.surfaces() {
            WorkingSurfaces::Drums(drum) => Some(drum),
            WorkingSurfaces::Discs(_) => None,
        }
    }

    /// The disc surfaces of a disc configuration.
    pub fn disc(&self) -> Option<&Disc> {
        match self.surfaces() {
            WorkingSurfaces::Discs(disc) => Some(disc),
            WorkingSurfaces::Drums(_) => None,
        }
    }

    /// The drum surfaces of a drum configuration, to change them.
    pub fn drum_mut(&mut self) -> Option<&mut Drum> {
        match self {
            Self::Drum(drum) | Self::MultiDrum(drum) | Self::Bidirectional { drum, .. } => {
                Some(drum)
            }
            Self::SingleDisc(_) | Self::MultiDisc(_) => None,
        }
    }

    /// The disc surfaces of a disc configuration, to change them.
    pub fn disc_mut(&mut self) -> Option<&mut Disc> {
        match self {
            Self::SingleDisc(disc) | Self::MultiDisc(disc) => Some(disc),
            Self::Drum(_) | Self::MultiDrum(_) | Self::Bidirectional { .. } => None,
        }
    }

    /// The spacer of the bidirectional brake.
    pub fn spacer(&self) -> Option<&Spacer> {
        match self {
            Self::Bidirectional { spacer, .. } => Some(spacer),
            _ => None,
        }
    }

    /// Number of units on the shaft: 2 for the bidirectional brake, else 1.
    pub fn units(&self) -> usize {
        if self.spacer().is_some() { 2 } else { 1 }
    }
}

/// Where the coil sits (thesis 3.1.4, Figures 3.7–3.9).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize, JsonSchema)]
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
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Materials {
    /// Low-carbon steel of the flux path (core, case wall, end plates, cylinders or discs).
    pub flux_path: String,
    /// Non-magnetic structural parts (rotor hub, covers, fillers; the bobbin too unless
    /// `bobbin` is given).
    pub non_magnetic: String,
    /// The coil's bobbin (the walls between the winding and the core or case, and its flanges);
    /// default: the `non_magnetic` material. A conducting bobbin (aluminium) is a shorted turn
    /// around the flux path; a polymer one (`pom`) is not.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub bobbin: Option<String>,
    /// The shaft.
    pub shaft: String,
    /// The MR fluid in the gaps.
    pub fluid: String,
    /// The coil conductor.
    #[serde(default = "default_copper")]
    pub coil: String,
    /// The spacer between the two units of a bidirectional brake (required there).
    #[serde(default)]
    pub spacer: Option<String>,
    /// What surrounds the device in the model (the air box).
    #[serde(default = "default_air")]
    pub surroundings: String,
}

impl Materials {
    /// The bobbin's material: `bobbin`, or the `non_magnetic` material when it is not given.
    pub fn bobbin(&self) -> &str {
        self.bobbin.as_deref().unwrap_or(&self.non_magnetic)
    }

    /// The key of the first `materials` field that names `material` (`materials.flux_path`), for
    /// an error about a part made of it; `None` when no field names it.
    pub fn key_of(&self, material: &str) -> Option<&'static str> {
        let keys = [
            ("materials.flux_path", Some(&self.flux_path)),
            ("materials.non_magnetic", Some(&self.non_magnetic)),
            ("materials.bobbin", self.bobbin.as_ref()),
            ("materials.shaft", Some(&self.shaft)),
            ("materials.fluid", Some(&self.fluid)),
            ("materials.coil", Some(&self.coil)),
            ("materials.spacer", self.spacer.as_ref()),
            ("materials.surroundings", Some(&self.surroundings)),
        ];
        keys.into_iter().find(|(_, name)| name.is_some_and(|n| n == material)).map(|(key, _)| key)
    }

    /// The spacer's material: `spacer`, or the `non_magnetic` material when it is not given.
    pub fn spacer(&self) -> &str {
        self.spacer.as_deref().unwrap_or(&self.non_magnetic)
    }

    /// The material the part at a field of [`MATERIAL_FIELDS`] is made of: as [`Self::get`], with
    /// the defaults of the optional fields (the bobbin and the spacer are the non-magnetic
    /// material unless given).
    pub fn in_use(&self, path: &str) -> Option<&str> {
        match path {
            "materials.bobbin" => Some(self.bobbin()),
            "materials.spacer" => Some(self.spacer()),
            other => self.get(other),
        }
    }

    /// The material named at a field of [`MATERIAL_FIELDS`] (`materials.bobbin`, …), if the spec
    /// gives one.
    pub fn get(&self, path: &str) -> Option<&str> {
        Some(match path {
            "materials.flux_path" => &self.flux_path,
            "materials.non_magnetic" => &self.non_magnetic,
            "materials.bobbin" => self.bobbin.as_deref()?,
            "materials.shaft" => &self.shaft,
            "materials.fluid" => &self.fluid,
            "materials.coil" => &self.coil,
            "materials.spacer" => self.spacer.as_deref()?,
            "materials.surroundings" => &self.surroundings,
            _ => return None,
        })
    }
}

/// A material field of the spec (the material of a part role) and the library kinds it takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MaterialField {
    /// The dotted TOML path, e.g. `materials.bobbin`.
    pub path: &'static str,
    /// The part in words, for messages ("the bobbin").
    pub part: &'static str,
    /// The kind the part must have (`None`: any kind is read; [`Self::suits`] says which fit).
    pub required: Option<MaterialKind>,
    /// The kinds that suit the part: a spec with another kind gets a warning, a study variable's
    /// level of another kind is refused.
    pub suits: &'static [MaterialKind],
}

/// Every material field of a spec, in file order: the part roles whose material a study may vary
/// (a categorical variable) and the kinds that suit each.
pub const MATERIAL_FIELDS: &[MaterialField] = &[
    MaterialField {
        path: "materials.flux_path",
        part: "the flux path",
        required: None,
        suits: &[MaterialKind::Steel],
    },
    MaterialField {
        path: "materials.non_magnetic",
        part: "the non-magnetic parts",
        required: None,
        suits: &[MaterialKind::Linear],
    },
    MaterialField {
        path: "materials.bobbin",
        part: "the bobbin",
        required: None,
        suits: &[MaterialKind::Linear],
    },
    MaterialField {
        path: "materials.shaft",
        part: "the shaft",
        required: None,
        suits: &[MaterialKind::Steel, MaterialKind::Linear],
    },
    MaterialField {
        path: "materials.fluid",
        part: "the fluid gaps",
        required: Some(MaterialKind::MrFluid),
        suits: &[MaterialKind::MrFluid],
    },
    MaterialField {
        path: "materials.coil",
        part: "the coil conductor",
        required: Some(MaterialKind::Linear),
        suits: &[MaterialKind::Linear],
    },
    MaterialField {
        path: "materials.spacer",
        part: "the spacer",
        required: None,
        suits: &[MaterialKind::Linear],
    },
    MaterialField {
        path: "materials.surroundings",
        part: "the surroundings",
        required: Some(MaterialKind::Linear),
        suits: &[MaterialKind::Linear],
    },
];

impl MaterialField {
    /// The field at `path` (`materials.bobbin`), if it is one.
    pub fn at(path: &str) -> Option<&'static MaterialField> {
        MATERIAL_FIELDS.iter().find(|f| f.path == path)
    }

    /// The library names whose kind suits the part, in library order.
    pub fn suitable(&self) -> Vec<&'static str> {
        mrbrake_materials::library::names()
            .into_iter()
            .filter(|(_, kind)| self.suits.contains(kind))
            .map(|(name, _)| name)
            .collect()
    }

    /// Checks that `name` is a library material that suits the part; the error names the field,
    /// the material and the allowed materials.
    pub fn check_suits(&self, name: &str) -> Result<(), Box<mrbrake_error::FieldError>> {
        let wanted = name.trim().to_ascii_lowercase();
        let kind = mrbrake_materials::library::names()
            .into_iter()
            .find(|(n, _)| *n == wanted)
            .map(|(_, kind)| kind);
        let error = |message: String| {
            let e = mrbrake_error::FieldError::new(self.path, message)
                .with_value(format!("'{name}'"))
                .with_allowed(self.suitable().join(", "));
            Box::new(e)
        };
        match kind {
            None => Err(error(format!("not in the material library (for {})", self.part))),
            Some(kind) if !self.suits.contains(&kind) => Err(error(format!(
                "a {} material, which does not suit {}",
                kind.as_str(),
                self.part
            ))),
            Some(_) => Ok(()),
        }
    }
}

fn default_copper() -> String {
    "copper".into()
}

fn default_air() -> String {
    "air".into()
}

/// The shaft.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Shaft {
    /// Shaft radius (thesis Table 4.5: 5 mm).
    pub radius: Length,
}

impl Shaft {
    /// The numeric fields of `[shaft]`.
    pub const FIELDS: &'static [SpecField] = &[SpecField::length("shaft.radius")];
}

/// The static magnetic circuit and the non-magnetic closures around the working surfaces.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
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
    /// Drums (required there): axial thickness of the non-magnetic cover at the rotor end.
    #[serde(default)]
    pub cover_thickness: Option<Length>,
    /// Drums (required there): axial thickness of the non-magnetic rotary part (rotor disc) that
    /// carries the rotating cylinders to the hub on the shaft.
    #[serde(default)]
    pub rotor_disc_thickness: Option<Length>,
}

impl Housing {
    /// The numeric fields of `[housing]`.
    pub const FIELDS: &'static [SpecField] = &[
        SpecField::length("housing.outer_radius"),
        SpecField::length("housing.case_thickness"),
        SpecField::length("housing.end_plate_thickness"),
        SpecField::length("housing.inner_case_thickness"),
        SpecField::length("housing.cover_thickness"),
        SpecField::length("housing.rotor_disc_thickness"),
    ];
}

/// Multi-drum working surfaces (thesis 4.4, 4.5, Figure 4.15).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
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
    /// The numeric fields of `[drum]`.
    pub const FIELDS: &'static [SpecField] = &[
        SpecField::length("drum.r0"),
        SpecField::length("drum.height"),
        SpecField::length("drum.cylinder_thickness"),
        SpecField::gap("drum.gap"),
        SpecField::integer("drum.rotating_cylinders", ROTOR_BOUNDS),
    ];

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
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
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

impl Disc {
    /// The numeric fields of `[disc]`.
    pub const FIELDS: &'static [SpecField] = &[
        SpecField::length("disc.inner_radius"),
        SpecField::length("disc.outer_radius"),
        SpecField::length("disc.thickness"),
        SpecField::gap("disc.gap"),
        SpecField::integer("disc.count", ROTOR_BOUNDS),
    ];
}

/// The wire: by AWG gauge or by bare copper diameter.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
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

impl Wire {
    /// The numeric fields of `coil.wire`.
    pub const FIELDS: &'static [SpecField] = &[
        SpecField::integer("coil.wire.awg", AWG_BOUNDS),
        SpecField::length("coil.wire.diameter"),
        SpecField::current("coil.wire.rated_current", RATED_CURRENT_BOUNDS),
    ];

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

/// The coil (thesis 4.2.2: window C_w × C_h, (4.1)–(4.3)).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
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

impl Coil {
    /// The numeric fields of `[coil]` outside its wire ([`Wire::FIELDS`]).
    pub const FIELDS: &'static [SpecField] = &[
        SpecField::length("coil.window_width"),
        SpecField::length("coil.window_height"),
        SpecField::length("coil.bobbin_wall"),
        SpecField::integer("coil.turns", TURNS_BOUNDS),
        SpecField::current("coil.max_current", MAX_CURRENT_BOUNDS),
    ];
}

/// The spacer between the two units of a bidirectional brake.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Spacer {
    /// Axial thickness of the non-magnetic spacer.
    pub thickness: Length,
}

impl Spacer {
    /// The numeric fields of `[spacer]`.
    pub const FIELDS: &'static [SpecField] = &[SpecField::length("spacer.thickness")];
}

/// The envelope the device must fit in.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Envelope {
    /// Maximum outer diameter.
    pub diameter: Length,
    /// Maximum axial length.
    pub length: Length,
}

impl Envelope {
    /// The numeric fields of `[envelope]`.
    pub const FIELDS: &'static [SpecField] =
        &[SpecField::length("envelope.diameter"), SpecField::length("envelope.length")];
}

/// Model (not device) settings.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// Air margin around the device, radially and axially, before the outer (A = 0) boundary.
    pub air_margin: Length,
}

impl Model {
    /// The numeric fields of `[model]`.
    pub const FIELDS: &'static [SpecField] = &[SpecField::length("model.air_margin")];
}

impl Default for Model {
    fn default() -> Self {
        Self { air_margin: Length(0.02) }
    }
}

/// A whole brake specification. Read and written in the file's flat form (see the module docs);
/// two specs are equal when they describe the same brake, wherever they were read from.
#[derive(Debug, Clone)]
pub struct BrakeSpec {
    /// A short name for reports.
    pub name: String,
    /// The configuration and its working surfaces (`[drum]` or `[disc]`, and `[spacer]`).
    pub configuration: Configuration,
    /// Material of each part.
    pub materials: Materials,
    /// The shaft.
    pub shaft: Shaft,
    /// The static circuit.
    pub housing: Housing,
    /// The coil (one per unit).
    pub coil: Coil,
    /// The envelope.
    pub envelope: Envelope,
    /// Model settings.
    pub model: Model,
    /// Factors on the fluid's library data (`[fluid]`, all at their defaults when absent).
    pub fluid: FluidFactors,
    /// Factors on the flux-path steel's library data (`[steel]`).
    pub steel: SteelFactors,
    /// The mechanical drag besides the fluid (`[drag]`: seals, bearings, freewheels), for the
    /// off-state torque's breakdown ([`crate::drag`]).
    pub drag: crate::drag::Drag,
    /// Where it was read from, so that validation errors name the file and line.
    pub(crate) source: SpecSource,
}

impl PartialEq for BrakeSpec {
    fn eq(&self, other: &Self) -> bool {
        // Destructured so that a new field cannot be forgotten; `source` is where, not what.
        let Self {
            name,
            configuration,
            materials,
            shaft,
            housing,
            coil,
            envelope,
            model,
            fluid,
            steel,
            drag,
            source: _,
        } = self;
        *name == other.name
            && *configuration == other.configuration
            && *materials == other.materials
            && *shaft == other.shaft
            && *housing == other.housing
            && *coil == other.coil
            && *envelope == other.envelope
            && *model == other.model
            && *fluid == other.fluid
            && *steel == other.steel
            && *drag == other.drag
    }
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

/// Formats a length in millimetres for messages.
pub(crate) fn fmt_mm(m: f64) -> String {
    let text = format!("{:.4} mm", m * 1e3).replace(".0000 mm", " mm");
    // A length that rounds to zero is "0 mm", never "-0 mm".
    if text == "-0 mm" { "0 mm".to_string() } else { text }
}

impl BrakeSpec {
    /// Parses TOML text; `origin` (a file name) names the file in error messages, and validation
    /// errors name its lines too.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Self, DesignError> {
        Self::parse(text, origin, || SpecSource::read(origin, text))
    }

    /// Parses TOML text a program generated (a design study's point): like
    /// [`Self::from_toml_str`], but its invalid fields are reported without file and line, which
    /// would point into a text the user never saw.
    pub fn from_generated_toml(text: &str, origin: &str) -> Result<Self, DesignError> {
        Self::parse(text, origin, SpecSource::default)
    }

    fn parse(
        text: &str,
        origin: &str,
        source: impl FnOnce() -> SpecSource,
    ) -> Result<Self, DesignError> {
        let raw: raw::RawSpec = toml::from_str(text)
            .map_err(|e| DesignError::Parse { origin: origin.to_string(), error: Box::new(e) })?;
        raw.into_spec(source())
    }

    /// The spec as TOML, lengths and currents as bare SI numbers: a file [`Self::from_toml_str`] reads
    /// back to an equal spec (design studies write their chosen designs this way).
    pub fn to_toml_string(&self) -> Result<String, DesignError> {
        toml::to_string(self)
            .map_err(|source| DesignError::WriteToml { name: self.name.clone(), source })
    }

    /// Reads and parses a spec file.
    pub fn from_path(path: &std::path::Path) -> Result<Self, DesignError> {
        let text = mrbrake_error::read::text(path, mrbrake_error::read::SETTINGS)
            .map_err(|source| DesignError::Read { path: path.to_path_buf(), source })?;
        Self::from_toml_str(&text, &path.display().to_string())
    }

    /// Where the spec was read from.
    pub fn source(&self) -> &SpecSource {
        &self.source
    }

    /// The wire diameter (m); validation guarantees it exists.
    pub fn wire_diameter_m(&self) -> f64 {
        self.coil.wire.diameter_m().unwrap_or(f64::NAN)
    }

    /// The copper fill factor of the winding, copper area / window area
    /// ([`crate::formula::copper_fill_factor`]).
    pub fn fill_factor(&self) -> f64 {
        crate::formula::copper_fill_factor(
            self.turns(),
            self.wire_diameter_m(),
            self.coil.window_width.m(),
            self.coil.window_height.m(),
        )
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
