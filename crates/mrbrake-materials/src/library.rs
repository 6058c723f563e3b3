//! The built-in material library: steels, linear materials and MR fluids, by name.
//!
//! The data are the CSV files of `data/` (vendored from the project's material survey; see
//! `data/SOURCES.md` for every source, method and trust level), compiled in with `include_str!` and
//! parsed once, on first use. Names are looked up case-insensitively:
//!
//! ```
//! let steel = mrbrake_materials::library::get("Steel-1008").unwrap();
//! assert_eq!(steel.name, "steel-1008");
//! let fluid = mrbrake_materials::library::default_fluid().unwrap();
//! let tau = fluid.tau_y_of_b(0.46);
//! assert!((tau / 24315.0 - 1.0).abs() < 1e-9); // a thesis point: the curve passes through it
//! ```

use std::sync::{Arc, OnceLock};

use crate::table::read_rows;
use crate::yield_stress::{FieldVariable, YieldStressCurve};
use crate::{
    BhCurve, Magnetic, Material, MaterialError, MaterialKind, MrFluid, Provenance, ReferencePoint,
    Sourced, Trust, Viscosity,
};

/// The default MR fluid (the thesis's choice, lowest viscosity).
pub const DEFAULT_FLUID: &str = "mrf-122eg";

/// Ceiling of MRF-122EG's yield stress \[Pa\]: the thesis says the curve "approaches to 35 kPa which is the
/// upper limit for the MRF-122EG" (Karabulut 2017, section 3.2, discussion of Figure 3.3).
pub const MRF122EG_TAU_Y_CEILING_PA: f64 = 35_000.0;

/// An embedded data file: its path in the crate and its content.
struct DataFile {
    path: &'static str,
    text: &'static str,
}

macro_rules! data_file {
    ($name:literal) => {
        DataFile { path: concat!("data/", $name), text: include_str!(concat!("../data/", $name)) }
    };
}

/// One built-in material: its name, a one-line description and how it is built from `data/`.
struct Entry {
    name: &'static str,
    description: &'static str,
    recipe: Recipe,
}

/// How a built-in material is made from the vendored data (one variant per [`MaterialKind`]).
enum Recipe {
    Steel(SteelRecipe),
    Linear(LinearRecipe),
    Fluid(FluidRecipe),
}

impl Recipe {
    fn kind(&self) -> MaterialKind {
        match self {
            Recipe::Steel(_) => MaterialKind::Steel,
            Recipe::Linear(_) => MaterialKind::Linear,
            Recipe::Fluid(_) => MaterialKind::MrFluid,
        }
    }
}

impl Entry {
    const fn steel(
        name: &'static str,
        description: &'static str,
        curve: DataFile,
        source: CurveSource,
        properties_row: Option<&'static str>,
    ) -> Self {
        Entry {
            name,
            description,
            recipe: Recipe::Steel(SteelRecipe { curve, source, properties_row }),
        }
    }

    const fn linear(
        name: &'static str,
        description: &'static str,
        femm_block: &'static str,
        density_kg_m3: f64,
        density_source: &'static str,
    ) -> Self {
        let electrical = Electrical::Femm { block: femm_block };
        let recipe = LinearRecipe { electrical, density_kg_m3, density_source };
        Entry { name, description, recipe: Recipe::Linear(recipe) }
    }

    /// An electrical insulator (a polymer): `mu_r = 1`, its conductivity the reciprocal of the
    /// smallest volume resistivity its source quotes (an upper bound), its density from a handbook.
    const fn insulator(
        name: &'static str,
        description: &'static str,
        resistivity: Insulation,
        density_kg_m3: f64,
        density_source: &'static str,
    ) -> Self {
        let electrical = Electrical::Insulator(resistivity);
        let recipe = LinearRecipe { electrical, density_kg_m3, density_source };
        Entry { name, description, recipe: Recipe::Linear(recipe) }
    }

    const fn fluid(
        name: &'static str,
        description: &'static str,
        product: &'static str,
        bh: DataFile,
        yield_stress: FluidYieldStress,
    ) -> Self {
        Entry {
            name,
            description,
            recipe: Recipe::Fluid(FluidRecipe { product, bh, yield_stress }),
        }
    }
}

/// Every built-in material, in library order: the one list of names, kinds and data sources.
const CATALOGUE: &[Entry] = &[
    Entry::steel(
        "steel-1008",
        "AISI 1008 low-carbon steel (ANSYS Maxwell library curve)",
        data_file!("steel_1008_ansys_BH.csv"),
        CurveSource::Listed {
            source: "ANSYS Maxwell/RMxprt system library curve `steel_1008` (RMxprt VBScript export; an independent \
             .aedt copy holds the same first 19 points)",
            method: "copied (20 points; the last one is a mu0-slope extrapolation in the source); monotone C1 \
             interpolation of H(B), mu0 slope beyond 1.19 MA/m",
            trust: Trust::MediumHigh,
        },
        Some("Ansys steel_1008"),
    ),
    Entry::steel(
        "steel-1008-modelica",
        "AISI 1008 steel, Modelica MSL fit formula (use below 2 T)",
        data_file!("steel_1008_modelica_fit_BH.csv"),
        CurveSource::Listed {
            source: "Modelica Standard Library, Magnetic.FluxTubes.Material.SoftMagnetic.Steel.AISI_1008 \
             (mu_rApprox fit: mu_i=200, B_myMax=1.17 T, c_a=8100, c_b=2.59, n=10; data by T. Roschke)",
            method: "fit formula evaluated for B = 0..2 T in 0.05 T steps; agrees with the ANSYS curve within 1.2 % \
             at 1/5/20 kA/m; beyond 2 T the curve is continued with slope mu0, which the fit does not \
             support (it is still at ~7.5 mu0 there)",
            trust: Trust::Medium,
        },
        None,
    ),
    Entry::steel(
        "steel-1006",
        "AISI 1006 steel (FEMM 4.2 library)",
        data_file!("steel_1006_femm_BH.csv"),
        CurveSource::Femm { block: "1006 Steel", note: "" },
        Some("FEMM 1006 Steel"),
    ),
    Entry::steel(
        "steel-1010",
        "AISI 1010 steel (FEMM 4.2 library)",
        data_file!("steel_1010_femm_BH.csv"),
        CurveSource::Femm { block: "1010 Steel", note: "" },
        Some("FEMM 1010 Steel"),
    ),
    Entry::steel(
        "steel-1010-motorproto",
        "AISI 1010 steel (MotorProto curve, softer than FEMM's)",
        data_file!("steel_1010_motorproto_BH.csv"),
        CurveSource::Listed {
            source: "MPEL/MotorProto, Materials/Steel1010.m, commit abfb602d92ed4634501463ae457b8b1ac402df6d",
            method: "copied (the last point is a mu0-slope extrapolation in the source); noticeably softer than \
             FEMM's 1010 below 2 kA/m (B(1 kA/m) = 1.04 T vs 1.42 T): treat the spread as material \
             uncertainty",
            trust: Trust::MediumLow,
        },
        Some("MotorProto Steel1010"),
    ),
    Entry::steel(
        "steel-1018",
        "AISI 1018 steel (FEMM 4.2 library, 13 coarse points)",
        data_file!("steel_1018_femm_BH.csv"),
        CurveSource::Femm {
            block: "1018 Steel",
            note: "; only 13 points at round Oersted values (probably digitised from a handbook curve), coarse \
                 below 800 A/m",
        },
        Some("FEMM 1018 Steel"),
    ),
    Entry::steel(
        "steel-1020",
        "AISI 1020 steel (FEMM 4.2 library; a cross-check: the thesis uses AISI 1008, Table 5.1)",
        data_file!("steel_1020_femm_BH.csv"),
        CurveSource::Femm { block: "1020 Steel", note: "" },
        Some("FEMM 1020 Steel"),
    ),
    Entry::linear(
        "air",
        "air (mu_r = 1)",
        "Air",
        1.204,
        "dry air at 20 °C and 101.325 kPa (ideal gas, M = 28.96 g/mol)",
    ),
    Entry::linear(
        "aluminium",
        "aluminium 6061-T6 (mu_r = 1)",
        "Aluminum, 6061-T6",
        2700.0,
        "ASM Handbook Vol. 2 (2.70 g/cm3 for 6061)",
    ),
    Entry::linear(
        "aluminium-1100",
        "aluminium 1100 (mu_r = 1)",
        "Aluminum, 1100",
        2710.0,
        "ASM Handbook Vol. 2 (2.71 g/cm3 for 1100)",
    ),
    Entry::linear(
        "stainless-304",
        "AISI 304 austenitic stainless steel, annealed (mu_r = 1)",
        "304 Stainless Steel",
        8000.0,
        "ASM Handbook Vol. 1 / AISI data (8.00 g/cm3 for 304)",
    ),
    Entry::linear(
        "stainless-316",
        "AISI 316 austenitic stainless steel, annealed (mu_r = 1)",
        "316 Stainless Steel",
        8000.0,
        "ASM Handbook Vol. 1 / AISI data (8.00 g/cm3 for 316)",
    ),
    Entry::insulator(
        "pom",
        "POM, acetal homopolymer (e.g. Delrin): a bobbin polymer, electrical insulator (mu_r = 1)",
        Insulation {
            volume_resistivity_ohm_m: 1e11,
            source: "volume resistivity >= 1e13 Ohm cm (IEC 60093) in a POM-C technical data \
             sheet (typical values); Margolis, Engineering Plastics Handbook (McGraw-Hill 2006), \
             Table 5.5, lists 1e15 Ohm cm and more for acetal homopolymer and copolymer",
        },
        1420.0,
        "R. J. Crawford, Plastics Engineering, 3rd ed. (Butterworth-Heinemann 1998), Table 1.8 p. 31, \
         acetal homopolymer (1420 kg/m3; Margolis Table 5.5: specific gravity 1.41)",
    ),
    Entry::linear(
        "copper",
        "copper, 100 % IACS (mu_r = 1)",
        "Copper",
        8960.0,
        "CRC Handbook of Chemistry and Physics (8.96 g/cm3 for Cu at 20 °C)",
    ),
    Entry::fluid(
        "mrf-122eg",
        "LORD MRF-122EG (default; tau_y(B) from the thesis's points)",
        "MRF-122EG",
        data_file!("mrf122eg_BH_carlson_fit.csv"),
        FluidYieldStress::ThesisPoints,
    ),
    Entry::fluid(
        "mrf-122eg-carlson",
        "LORD MRF-122EG modelled by Carlson's generic fit (phi = 0.22)",
        "MRF-122EG",
        data_file!("mrf122eg_BH_carlson_fit.csv"),
        // The thesis points are the comparison for the generic fit (it misses them by up to 23 %).
        FluidYieldStress::Carlson {
            tau_h: data_file!("mrf122eg_tauH_carlson_fit.csv"),
            references: References::ThesisPoints,
        },
    ),
    Entry::fluid(
        "mrf-132dg",
        "LORD MRF-132DG (Carlson's generic fit, phi = 0.32)",
        "MRF-132DG",
        data_file!("mrf132dg_BH_carlson_fit.csv"),
        FluidYieldStress::Carlson {
            tau_h: data_file!("mrf132dg_tauH_carlson_fit.csv"),
            references: References::SpotValues,
        },
    ),
    Entry::fluid(
        "mrf-140cg",
        "LORD MRF-140CG (Carlson's generic fit, phi = 0.40)",
        "MRF-140CG",
        data_file!("mrf140cg_BH_carlson_fit.csv"),
        FluidYieldStress::Carlson {
            tau_h: data_file!("mrf140cg_tauH_carlson_fit.csv"),
            references: References::SpotValues,
        },
    ),
];

/// Every built-in material name with its kind, in library order.
pub fn names() -> Vec<(&'static str, MaterialKind)> {
    CATALOGUE.iter().map(|entry| (entry.name, entry.recipe.kind())).collect()
}

/// The names of the built-in materials whose kind passes `keep`, in library order (for errors).
fn names_where(keep: impl Fn(MaterialKind) -> bool) -> Vec<String> {
    CATALOGUE
        .iter()
        .filter(|entry| keep(entry.recipe.kind()))
        .map(|entry| entry.name.to_string())
        .collect()
}

/// The material called `name` (case-insensitive, surrounding spaces ignored).
pub fn get(name: &str) -> Result<&'static Material, MaterialError> {
    let wanted = name.trim().to_ascii_lowercase();
    library()?.iter().find(|m| m.name == wanted).ok_or_else(|| MaterialError::UnknownMaterial {
        name: name.to_string(),
        known: names_where(|_| true),
    })
}

/// The MR fluid called `name` (case-insensitive); an error lists the fluids if `name` is not one.
pub fn fluid(name: &str) -> Result<&'static MrFluid, MaterialError> {
    let fluids = || names_where(|kind| kind == MaterialKind::MrFluid);
    match get(name) {
        Ok(material) => material.fluid.as_deref().ok_or_else(|| MaterialError::UnknownMaterial {
            name: name.to_string(),
            known: fluids(),
        }),
        Err(MaterialError::UnknownMaterial { name, .. }) => {
            Err(MaterialError::UnknownMaterial { name, known: fluids() })
        }
        Err(other) => Err(other),
    }
}

/// The default MR fluid, [`DEFAULT_FLUID`].
pub fn default_fluid() -> Result<&'static MrFluid, MaterialError> {
    fluid(DEFAULT_FLUID)
}

/// The B-H curve of a non-linear material (steel or fluid); an error for a linear material.
pub fn bh_curve(name: &str) -> Result<Arc<BhCurve>, MaterialError> {
    let material = get(name)?;
    match material.magnetic.bh_curve() {
        Some(curve) => Ok(Arc::new(curve.clone())),
        None => Err(MaterialError::UnknownMaterial {
            name: name.to_string(),
            known: names_where(|kind| kind != MaterialKind::Linear),
        }),
    }
}

/// Checks the points at which a material's curves are read for people (the `--b`/`--h` of
/// `mrbrake materials show`, Python's `b_of_h`, `tau_y_of_b` and `to_dict`): each finite and not
/// negative, the range the B-H and τ_y curves are tabulated on (odd and even in their variable).
/// The error names `field` with the point's index (`b[2]`), its value in `unit` and the range.
pub fn check_curve_points(
    field: &str,
    values: &[f64],
    unit: &str,
) -> Result<(), Box<mrbrake_error::FieldError>> {
    match values.iter().position(|v| !(v.is_finite() && *v >= 0.0)) {
        None => Ok(()),
        Some(k) => Err(Box::new(mrbrake_error::FieldError::out_of_range(
            format!("{field}[{k}]"),
            format!("{} {unit}", values[k]),
            format!("finite, >= 0 {unit}"),
        ))),
    }
}

/// All materials, parsed on first use.
pub fn all() -> Result<&'static [Material], MaterialError> {
    library()
}

/// The library, built on first use; an error here is a bug in the embedded data.
fn library() -> Result<&'static [Material], MaterialError> {
    static LIBRARY: OnceLock<Result<Vec<Material>, MaterialError>> = OnceLock::new();
    LIBRARY.get_or_init(|| build().map_err(MaterialError::builtin)).as_deref().map_err(Clone::clone)
}

fn build() -> Result<Vec<Material>, MaterialError> {
    let steel_props = SteelProperties::parse()?;
    CATALOGUE
        .iter()
        .map(|entry| match &entry.recipe {
            Recipe::Steel(recipe) => build_steel(entry, recipe, &steel_props),
            Recipe::Linear(recipe) => build_linear(entry, recipe),
            Recipe::Fluid(recipe) => build_fluid(entry, recipe),
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------------
// Steels

const FEMM_SOURCE: &str = "FEMM 4.2 material library matlib.dat (xfemm mirror Reoptimize-Systems/xfemm, \
     cfemm/femmcli/release/matlib.dat, commit 35baec4c89dac773efa16092a5a67cadc870d106)";

/// Handbook density of low-carbon steel, used where the curve's source gives none.
fn handbook_steel_density() -> Sourced<f64> {
    Sourced::new(
        7870.0,
        Provenance::new(
            "handbook value for plain low-carbon steel, 7.87 g/cm3 (ASM Handbook Vol. 1, physical properties \
             of carbon steels; AISI 1008-1020 are listed at 7.872)",
            "standard handbook value, not from the curve's source",
            Trust::Medium,
        ),
    )
}

/// One row of `data/steel_properties.csv` (all `None`: a curve whose source gives no properties).
#[derive(Debug, Clone, Copy, Default)]
struct SteelRow {
    sigma_s_per_m: Option<f64>,
    mu_r_linear: Option<f64>,
    density_kg_m3: Option<f64>,
}

struct SteelProperties {
    rows: Vec<(String, SteelRow)>,
}

impl SteelProperties {
    fn parse() -> Result<Self, MaterialError> {
        let file = data_file!("steel_properties.csv");
        let header = ["material", "source", "sigma_S_per_m", "mu_r_linear_field", "density_kg_m3"];
        let rows = read_rows(file.text, file.path, &header)?
            .into_iter()
            .map(|r| {
                Ok((
                    r.text(0).to_string(),
                    SteelRow {
                        sigma_s_per_m: r.optional_number(2, header[2], file.path)?,
                        mu_r_linear: r.optional_number(3, header[3], file.path)?,
                        density_kg_m3: r.optional_number(4, header[4], file.path)?,
                    },
                ))
            })
            .collect::<Result<_, MaterialError>>()?;
        Ok(Self { rows })
    }

    /// The row named `material`.
    fn get(&self, material: &str) -> Result<SteelRow, MaterialError> {
        self.rows.iter().find(|r| r.0 == material).map(|r| r.1).ok_or_else(|| {
            MaterialError::MissingRow {
                file: "data/steel_properties.csv".to_string(),
                row: material.to_string(),
            }
        })
    }
}

/// A steel of the catalogue: its B-H file, where the curve comes from, and its row in
/// `data/steel_properties.csv` (`None`: the source gives no properties).
struct SteelRecipe {
    curve: DataFile,
    source: CurveSource,
    properties_row: Option<&'static str>,
}

/// Where a steel's B-H curve comes from.
enum CurveSource {
    /// A curve with its own source, method and trust.
    Listed { source: &'static str, method: &'static str, trust: Trust },
    /// A block of FEMM's material library; `note` is appended to the method.
    Femm { block: &'static str, note: &'static str },
}

impl CurveSource {
    fn provenance(&self) -> Provenance {
        match *self {
            CurveSource::Listed { source, method, trust } => Provenance::new(source, method, trust),
            CurveSource::Femm { block, note } => femm_steel(block, note),
        }
    }
}

fn build_steel(
    entry: &Entry,
    recipe: &SteelRecipe,
    props: &SteelProperties,
) -> Result<Material, MaterialError> {
    let provenance = recipe.source.provenance();
    let curve = BhCurve::from_csv_str(recipe.curve.text, recipe.curve.path, provenance.clone())?;
    let SteelRow { sigma_s_per_m: sigma, mu_r_linear, density_kg_m3: density } =
        match recipe.properties_row {
            Some(row) => props.get(row)?,
            None => SteelRow::default(),
        };
    let props_provenance = |what: &str| {
        Provenance::new(
            format!("data/steel_properties.csv, taken from the same source as the curve ({what})"),
            "copied",
            provenance.trust.min(Trust::Medium),
        )
    };
    Ok(Material {
        name: entry.name.to_string(),
        kind: MaterialKind::Steel,
        description: entry.description.to_string(),
        magnetic: Magnetic::NonLinear(Arc::new(curve)),
        provenance: provenance.clone(),
        density_kg_m3: Some(match density {
            Some(rho) => Sourced::new(rho, props_provenance("density")),
            None => handbook_steel_density(),
        }),
        conductivity_s_per_m: sigma.map(|s| Sourced::new(s, props_provenance("conductivity"))),
        mu_r_linear,
        fluid: None,
    })
}

fn femm_steel(block: &str, note: &str) -> Provenance {
    Provenance::new(
        format!("{FEMM_SOURCE}, block \"{block}\""),
        format!(
            "copied (FEMM stores (B, H); swapped to (H, B), no smoothing){note}; monotone C1 interpolation of \
             H(B), mu0 slope beyond the last point"
        ),
        Trust::Medium,
    )
}

// ---------------------------------------------------------------------------------------------------
// Linear materials

/// A linear material of the catalogue: where its permeability and conductivity come from, and its
/// handbook density with the source.
struct LinearRecipe {
    electrical: Electrical,
    density_kg_m3: f64,
    density_source: &'static str,
}

/// The permeability and conductivity of a linear material.
enum Electrical {
    /// A block of FEMM's material library (`mu_r` and the conductivity).
    Femm { block: &'static str },
    /// An electrical insulator: `mu_r = 1` and the conductivity bound of its [`Insulation`].
    Insulator(Insulation),
}

/// The volume resistivity of an insulator and its source.
struct Insulation {
    /// The smallest volume resistivity the source quotes (Ω·m): its reciprocal bounds the
    /// conductivity from above.
    volume_resistivity_ohm_m: f64,
    source: &'static str,
}

fn build_linear(entry: &Entry, recipe: &LinearRecipe) -> Result<Material, MaterialError> {
    let femm_block = match &recipe.electrical {
        Electrical::Femm { block } => *block,
        Electrical::Insulator(insulation) => return Ok(build_insulator(entry, recipe, insulation)),
    };
    let &LinearRecipe { density_kg_m3: density, density_source, .. } = recipe;
    let name = entry.name;
    let file = data_file!("linear_materials_femm.csv");
    let header = ["material", "mu_r", "sigma_S_per_m"];
    let row = read_rows(file.text, file.path, &header)?
        .into_iter()
        .find(|r| r.text(0) == femm_block)
        .ok_or_else(|| MaterialError::MissingRow {
            file: file.path.to_string(),
            row: femm_block.to_string(),
        })?;
    let mu_r = row.number(1, header[1], file.path)?;
    let sigma = row.number(2, header[2], file.path)?;
    let mut method = "copied; B = mu0 mu_r H".to_string();
    if name.starts_with("stainless") {
        method.push_str(
            "; austenitic stainless can become weakly magnetic after cold work or welding",
        );
    }
    let provenance =
        Provenance::new(format!("{FEMM_SOURCE}, block \"{femm_block}\""), method, Trust::High);
    Ok(Material {
        name: name.to_string(),
        kind: MaterialKind::Linear,
        description: entry.description.to_string(),
        magnetic: Magnetic::Linear { mu_r },
        provenance: provenance.clone(),
        density_kg_m3: Some(Sourced::new(
            density,
            Provenance::new(
                density_source,
                "standard handbook value (not from FEMM)",
                Trust::Medium,
            ),
        )),
        conductivity_s_per_m: Some(Sourced::new(
            sigma,
            Provenance::new(
                provenance.source.clone(),
                "copied, MS/m converted to S/m",
                Trust::High,
            ),
        )),
        mu_r_linear: Some(mu_r),
        fluid: None,
    })
}

/// A polymer insulator: `B = mu0 H` (a polymer's susceptibility, of order 1e-5, is negligible),
/// its conductivity bounded by its volume resistivity.
fn build_insulator(entry: &Entry, recipe: &LinearRecipe, insulation: &Insulation) -> Material {
    let provenance = Provenance::new(
        insulation.source,
        "mu_r = 1 (a polymer's susceptibility is of order 1e-5); conductivity = 1 / (smallest volume \
         resistivity quoted), an upper bound",
        Trust::Medium,
    );
    Material {
        name: entry.name.to_string(),
        kind: MaterialKind::Linear,
        description: entry.description.to_string(),
        magnetic: Magnetic::Linear { mu_r: 1.0 },
        provenance: provenance.clone(),
        density_kg_m3: Some(Sourced::new(
            recipe.density_kg_m3,
            Provenance::new(recipe.density_source, "copied (handbook value)", Trust::Medium),
        )),
        conductivity_s_per_m: Some(Sourced::new(
            1.0 / insulation.volume_resistivity_ohm_m,
            provenance,
        )),
        mu_r_linear: Some(1.0),
        fluid: None,
    }
}

// ---------------------------------------------------------------------------------------------------
// MR fluids

const CARLSON_SOURCE: &str = "Carlson's empirical fits for LORD iron-in-hydrocarbon MR fluids (J. D. Carlson, \
     \"MR fluids and devices in the real world\", Int. J. Mod. Phys. B 19 (2005) 1463, as quoted in public \
     code): B = 1.91 phi^1.133 (1 - exp(-10.97 mu0 H)) + mu0 H; tau_y = 271700 phi^1.5239 tanh(6.33e-6 H) Pa, \
     carrier factor C = 1 assumed; phi from Kubik et al., Smart Mater. Struct. 32 (2023) 035007";

/// Saturation value of Carlson's yield-stress fit, `271700 φ^1.5239` Pa (C = 1).
fn carlson_tau_ceiling_pa(phi: f64) -> f64 {
    271_700.0 * phi.powf(1.5239)
}

struct FluidProperties {
    phi: f64,
    carrier: String,
    viscosity_30c: f64,
    viscosity_40c: Option<f64>,
    density: f64,
    density_kind: String,
}

fn fluid_properties(product: &str) -> Result<FluidProperties, MaterialError> {
    let file = data_file!("mrf_properties.csv");
    let header = [
        "fluid",
        "iron_vol_fraction",
        "carrier",
        "viscosity_30C_Pa_s",
        "viscosity_40C_Pa_s",
        "density_kg_m3",
        "density_kind",
    ];
    let row = read_rows(file.text, file.path, &header)?
        .into_iter()
        .find(|r| r.text(0) == product)
        .ok_or_else(|| MaterialError::MissingRow {
            file: file.path.to_string(),
            row: product.to_string(),
        })?;
    Ok(FluidProperties {
        phi: row.number(1, header[1], file.path)?,
        carrier: row.text(2).to_string(),
        viscosity_30c: row.number(3, header[3], file.path)?,
        viscosity_40c: row.optional_number(4, header[4], file.path)?,
        density: row.number(5, header[5], file.path)?,
        density_kind: row.text(6).to_string(),
    })
}

fn spot_values(product: &str) -> Result<Vec<ReferencePoint>, MaterialError> {
    let file = data_file!("mrf132dg_mrf140cg_spot_values_lowtrust.csv");
    let header = ["fluid", "H_A_per_m", "B_T", "tau_y_Pa"];
    read_rows(file.text, file.path, &header)?
        .into_iter()
        .filter(|r| r.text(0) == product)
        .map(|r| {
            Ok(ReferencePoint {
                b_t: Some(r.number(2, header[2], file.path)?),
                h_a_per_m: Some(r.number(1, header[1], file.path)?),
                tau_y_pa: r.number(3, header[3], file.path)?,
                source: format!(
                    "{} line {} (low trust: unpublished draft quoting the datasheet plots)",
                    file.path, r.line
                ),
            })
        })
        .collect()
}

/// An MR fluid of the catalogue: the product (its row in `data/mrf_properties.csv`), its B-H file
/// and where its yield stress comes from.
struct FluidRecipe {
    product: &'static str,
    bh: DataFile,
    yield_stress: FluidYieldStress,
}

/// Where a fluid's yield stress comes from.
enum FluidYieldStress {
    /// The thesis's `τ_y(B)` points for MRF-122EG (also the fluid's reference points).
    ThesisPoints,
    /// Carlson's generic `τ_y(H)` fit, tabulated in `tau_h`, compared against `references`.
    Carlson { tau_h: DataFile, references: References },
}

/// The points a Carlson-fit fluid is compared against.
enum References {
    /// The thesis's MRF-122EG points.
    ThesisPoints,
    /// The low-trust spot values of `data/mrf132dg_mrf140cg_spot_values_lowtrust.csv`.
    SpotValues,
}

fn build_fluid(entry: &Entry, recipe: &FluidRecipe) -> Result<Material, MaterialError> {
    let props = fluid_properties(recipe.product)?;
    let bh_provenance = Provenance::new(
        format!("{CARLSON_SOURCE}; file {}", recipe.bh.path),
        format!(
            "fit formula evaluated (phi = {}) on H = 0..1 MA/m; a generic family fit, not the product datasheet \
             (no digitised LORD B-H curve was found)",
            props.phi
        ),
        Trust::MediumLow,
    );
    let bh =
        Arc::new(BhCurve::from_csv_str(recipe.bh.text, recipe.bh.path, bh_provenance.clone())?);
    let (yield_stress, reference_points) = fluid_yield_stress(recipe, &props)?;
    let density = fluid_density(&props);
    let phi = Sourced::new(props.phi, Provenance::new(KUBIK, "copied (vol%)", Trust::Medium));
    let mut fluid = MrFluid::new(
        entry.name,
        Arc::clone(&bh),
        yield_stress,
        phi,
        props.carrier.clone(),
        fluid_viscosities(&props),
        density.clone(),
    );
    fluid.reference_points = reference_points;
    Ok(Material {
        name: entry.name.to_string(),
        kind: MaterialKind::MrFluid,
        description: entry.description.to_string(),
        magnetic: Magnetic::NonLinear(bh),
        provenance: bh_provenance,
        density_kg_m3: Some(density),
        conductivity_s_per_m: None,
        mu_r_linear: None,
        fluid: Some(Arc::new(fluid)),
    })
}

/// The fluid's yield-stress curve and the reference points it is compared against.
fn fluid_yield_stress(
    recipe: &FluidRecipe,
    props: &FluidProperties,
) -> Result<(YieldStressCurve, Vec<ReferencePoint>), MaterialError> {
    let FluidYieldStress::Carlson { tau_h: file, references } = &recipe.yield_stress else {
        return mrf122eg_thesis_yield_stress();
    };
    let ceiling = carlson_tau_ceiling_pa(props.phi);
    let provenance = Provenance::new(
        format!("{CARLSON_SOURCE}; file {}", file.path),
        format!(
            "fit formula evaluated (phi = {}) on H = 0..1 MA/m, monotone C1 interpolation in H; above \
             1 MA/m a C1 exponential tail to the fit's asymptote 271700 phi^1.5239 = {ceiling:.0} Pa; \
             tau_y(B) = tau_y(H(B)) through the fluid's B-H curve",
            props.phi
        ),
        Trust::MediumLow,
    );
    let curve = YieldStressCurve::from_csv_str(
        file.text,
        file.path,
        FieldVariable::FieldStrength,
        ceiling,
        provenance,
    )?;
    let references = match references {
        References::ThesisPoints => thesis_points()?,
        References::SpotValues => spot_values(recipe.product)?,
    };
    Ok((curve, references))
}

/// Source of the fluids' iron fractions and 30 °C viscosities.
const KUBIK: &str = "Kubik et al., Smart Mater. Struct. 32 (2023) 035007, as tabulated in public repository files \
                 (column base_viscosity_at_30C_cP; shear rate not stated)";

/// The off-state viscosities: at 30 °C (the default), and at 40 °C where known.
fn fluid_viscosities(props: &FluidProperties) -> Vec<Viscosity> {
    let mut viscosities = vec![Viscosity {
        pa_s: props.viscosity_30c,
        temperature_c: 30.0,
        provenance: Provenance::new(KUBIK, "copied, cP converted to Pa.s", Trust::Medium),
    }];
    if let Some(eta) = props.viscosity_40c {
        viscosities.push(Viscosity {
            pa_s: eta,
            temperature_c: 40.0,
            provenance: Provenance::new(
                "quoted in two independent public code files as the LORD MRF-132DG value (datasheet not seen)",
                "copied",
                Trust::Medium,
            ),
        });
    }
    viscosities
}

/// The density, low trust when `data/mrf_properties.csv` marks it as an estimate.
fn fluid_density(props: &FluidProperties) -> Sourced<f64> {
    let density_trust =
        if props.density_kind.starts_with("estimate") { Trust::Low } else { Trust::Medium };
    Sourced::new(
        props.density,
        Provenance::new(
            "data/mrf_properties.csv",
            format!(
                "{}{}",
                props.density_kind,
                if density_trust == Trust::Low {
                    ": rho = phi 7860 + (1 - phi) 786 kg/m3, carrier density back-calculated from MRF-132DG's 3050"
                } else {
                    ""
                }
            ),
            density_trust,
        ),
    )
}

/// The 14 `(B, τ_y)` points the thesis uses for MRF-122EG (its reading of the LORD datasheet).
fn thesis_points() -> Result<Vec<ReferencePoint>, MaterialError> {
    let file = data_file!("mrf122eg_tauB_thesis_reference.csv");
    Ok(crate::table::read_xy(file.text, file.path, FieldVariable::FluxDensity.header())?
        .into_iter()
        .map(|(line, b, tau)| ReferencePoint {
            b_t: Some(b),
            h_a_per_m: None,
            tau_y_pa: tau,
            source: format!("thesis (Karabulut 2017) tau_y(B) point, {} line {line}", file.path),
        })
        .collect())
}

/// MRF-122EG `τ_y(B)`: the thesis's 14 points (plus the origin) interpolated monotone C¹ (Steffen),
/// continued above 0.49 T by an exponential matched in value and slope that tends to 35 kPa.
fn mrf122eg_thesis_yield_stress() -> Result<(YieldStressCurve, Vec<ReferencePoint>), MaterialError>
{
    let references = thesis_points()?;
    let mut points = vec![(0.0, 0.0)];
    points.extend(references.iter().filter_map(|p| p.b_t.map(|b| (b, p.tau_y_pa))));
    let provenance = Provenance::new(
        "Karabulut (2017) thesis: 14 tau_y(B) points (data/mrf122eg_tauB_thesis_reference.csv), the thesis's own \
         reading of the LORD MRF-122EG datasheet (its Figures 3.2-3.3, evaluated in MATLAB); ceiling 35 kPa from \
         the thesis text (\"approaches to 35 kPa which is the upper limit for the MRF-122EG\")",
        "the origin (no field, no yield stress) plus the 14 points, interpolated monotone C1 (Steffen 1990), so \
         the curve passes through every point by construction; above 0.49 T an exponential \
         35 kPa - (35 kPa - tau_n) exp(-k (B - 0.49 T)) matched in value and slope (an assumed form: no data \
         above 0.49 T); tau_y(H) = tau_y(B(H)) through the Carlson B-H fit (phi = 0.22)",
        Trust::MediumLow,
    );
    let curve = YieldStressCurve::from_points(
        &points,
        FieldVariable::FluxDensity,
        MRF122EG_TAU_Y_CEILING_PA,
        provenance,
    )?;
    Ok((curve, references))
}
