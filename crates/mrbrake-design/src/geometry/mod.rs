//! Geometry builder: a [`BrakeSpec`] → named, tagged axisymmetric regions in the (r, z) half-plane.
//!
//! Brief overview: [`build`] (or [`BrakeSpec::validate`], which assembles it once while checking the
//! spec's geometric rules) returns a [`BrakeGeometry`]: every part as a [`Region`] (one or more
//! axis-aligned rectangles, a physical tag, a material name, a [`PartKind`], whether and in which
//! direction it rotates), the fluid gaps with the metadata the torque integration needs
//! ([`GapInfo`]: index, shear radius, height, rotating side, direction, the line along which |B| is
//! sampled, the tags of its walls), the coils ([`CoilInfo`]: turns, current sign), and the tags of
//! the axis (r = 0) and of the outer boundary of the air box, both Dirichlet A_phi = 0.
//!
//! Layouts (z grows from the rotor end to the coil end of a unit):
//!
//! * Drum family (drum, multi-drum, one unit of the bidirectional brake). Radially: shaft, a
//!   non-magnetic bore sleeve, the static steel inner core (thickness `housing.inner_case_thickness`,
//!   outer radius R0), the stack of 2n fluid gaps and 2n−1 cylinders with R_k = R0 + k(d + g) (4.5)
//!   (odd cylinders rotate, even ones are static), the steel case wall from the last gap to the
//!   outer radius. Axially: non-magnetic cover, non-magnetic rotor disc (carries the rotating
//!   cylinders to the hub on the shaft), the stack of height h, the coil window beside the stack
//!   (against the core for `inner` placement, against the case for `outer`) in a non-magnetic
//!   bobbin, and the steel end plate joining core and case. Flux loop: core → end plate → case →
//!   radially inwards through all 2n gaps in series → core, so every surface works over its full
//!   height h, as (4.4) assumes.
//! * Disc family (single-disc, multi-disc). Axially: steel plate, the working level, steel plate.
//!   In the working level: the disc stack over R1..R2 (n rotating discs, n−1 static discs, 2n gaps of
//!   width g, steel poles filling the rest of the level's height over R1..R2), an outer coil
//!   (radially outside R2, in the case) and/or an inner coil (inside R1, around a steel core ring on
//!   the shaft). Flux crosses the gaps axially, once.
//! * Bidirectional: unit 1 and unit 2 = unit 1 mirrored about the mid-plane of the spacer; their end
//!   plates face the non-magnetic spacer (thesis 4.3: two identical drums mounted opposite to each
//!   other, divided by a separator), shaft shared.
//!
//! Any area of a unit's bounding box not covered by a named part is non-magnetic filler (seals,
//! hub, bore: modelled with `materials.non_magnetic`), except the coil's bobbin: the filler within
//! one bobbin wall (`coil.bobbin_wall`) of a winding window, beside it (the wall between the
//! winding and the core or case it is wound against) or across its ends (the flanges, which reach
//! across the coil pocket), is the unit's `bobbin` part ([`PartKind::Bobbin`], `materials.bobbin`).
//! The bobbin is cut from the filler's own rectangles, so it adds no line to the mesh: a spec
//! whose bobbin is the non-magnetic material meshes and solves exactly as before the bobbin was a
//! part. Mechanical details that do not carry flux (bearings, seals, bolts) are not modelled.
//!
//! Code: `drum` and `disc` build unit 1 of their family, `assemble` adds the bidirectional brake's
//! mirrored unit 2, the filler and the air box (tags in that order), `check` holds the geometric
//! rules of the spec's validation. Each configuration is one arm of the `match` in `assemble`.

mod assemble;
mod check;
mod disc;
mod drum;

pub(crate) use assemble::assemble;
pub(crate) use check::{check_assembled, check_fit};

use crate::DesignError;
use crate::spec::BrakeSpec;

/// An axis-aligned rectangle `[r0, r1] × [z0, z1]` (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// Inner radius.
    pub r0: f64,
    /// Outer radius.
    pub r1: f64,
    /// Lower axial coordinate.
    pub z0: f64,
    /// Upper axial coordinate.
    pub z1: f64,
}

impl Rect {
    /// A rectangle from its radial and axial ranges.
    pub fn new(r0: f64, r1: f64, z0: f64, z1: f64) -> Self {
        Self { r0, r1, z0, z1 }
    }

    /// Planar area (m²).
    pub fn area_m2(&self) -> f64 {
        (self.r1 - self.r0) * (self.z1 - self.z0)
    }

    /// Volume of the ring this rectangle sweeps around the axis, π (r1² − r0²)(z1 − z0) (m³).
    pub fn ring_volume_m3(&self) -> f64 {
        std::f64::consts::PI * (self.r1 * self.r1 - self.r0 * self.r0) * (self.z1 - self.z0)
    }

    /// The centre point.
    pub fn centre(&self) -> [f64; 2] {
        [0.5 * (self.r0 + self.r1), 0.5 * (self.z0 + self.z1)]
    }

    /// True when the interiors overlap by more than `tol` in both directions.
    pub fn overlaps(&self, other: &Rect, tol: f64) -> bool {
        self.r0 < other.r1 - tol
            && other.r0 < self.r1 - tol
            && self.z0 < other.z1 - tol
            && other.z0 < self.z1 - tol
    }

    /// True when the point lies strictly inside.
    pub fn contains(&self, p: [f64; 2]) -> bool {
        p[0] > self.r0 && p[0] < self.r1 && p[1] > self.z0 && p[1] < self.z1
    }

    fn mirrored(&self, z_mirror: f64) -> Rect {
        Rect::new(self.r0, self.r1, 2.0 * z_mirror - self.z1, 2.0 * z_mirror - self.z0)
    }
}

/// What a part does magnetically and mechanically.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartKind {
    /// The shaft.
    Shaft,
    /// A low-carbon steel part of the flux path.
    FluxPath,
    /// A non-magnetic structural part (rotor disc, cover, filler).
    NonMagnetic,
    /// A coil's bobbin (`materials.bobbin`): static, non-magnetic, and a shorted turn around the
    /// flux path when it conducts.
    Bobbin,
    /// A coil (copper winding window).
    Coil,
    /// An MR-fluid gap.
    Fluid,
    /// The spacer between the units of a bidirectional brake.
    Spacer,
    /// The air around the device.
    Air,
}

/// The direction of rotation a rotor takes part in (the bidirectional brake's one-way bearings).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Direction {
    /// Coupled to the shaft in both directions (single-unit brakes).
    Both,
    /// Unit 1 of the bidirectional brake: its one-way bearing engages for clockwise shaft rotation.
    Clockwise,
    /// Unit 2: engages for counter-clockwise shaft rotation.
    CounterClockwise,
}

/// A named, tagged part.
#[derive(Debug, Clone, PartialEq)]
pub struct Region {
    /// Physical tag of its triangles.
    pub tag: u32,
    /// Name, e.g. `unit1.core`, `unit1.gap2`.
    pub name: String,
    /// Material name (library name from the spec).
    pub material: String,
    /// Kind of part.
    pub kind: PartKind,
    /// The rectangles it is made of.
    pub rects: Vec<Rect>,
    /// Unit index (0 or 1 for the bidirectional brake, 0 otherwise; `None` for shared parts).
    pub unit: Option<usize>,
    /// `Some(direction)` when the part rotates with the shaft (through its unit's bearing).
    pub rotates: Option<Direction>,
}

impl Region {
    /// Planar area of the part (m²).
    pub fn area_m2(&self) -> f64 {
        self.rects.iter().map(Rect::area_m2).sum()
    }

    /// Volume of the part (m³).
    pub fn volume_m3(&self) -> f64 {
        self.rects.iter().map(Rect::ring_volume_m3).sum()
    }
}

/// Orientation of a fluid gap.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GapOrientation {
    /// Cylindrical gap (drums): flux crosses it radially; the sheared surface is a cylinder.
    Cylindrical,
    /// Annular gap (discs): flux crosses it axially; the sheared surface is a flat annulus.
    Annular,
}

/// Which wall of a gap belongs to the rotor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RotatingWall {
    /// The wall at smaller r (drums) or smaller z (discs).
    Inner,
    /// The wall at larger r (drums) or larger z (discs).
    Outer,
}

/// A fluid gap with the data the torque integration needs.
#[derive(Debug, Clone, PartialEq)]
pub struct GapInfo {
    /// Global index (0-based over all units). Every report (text, JSON, plots, region names,
    /// the Gmsh export) shows it 1-based, as gap 1, 2, … (docs/CONVENTIONS.md).
    pub index: usize,
    /// Index within its unit, 0-based: k of (4.4) for drums (shown 1-based, like `index`).
    pub index_in_unit: usize,
    /// The unit it belongs to, 0-based (shown as unit 1 or 2).
    pub unit: usize,
    /// Physical tag of the gap's triangles.
    pub tag: u32,
    /// Geometry of the gap.
    pub rect: Rect,
    /// Orientation.
    pub orientation: GapOrientation,
    /// Drums: R_k, the radius of the gap's inner wall, as in (4.4). Discs: the mean radius.
    pub shear_radius_m: f64,
    /// Mean radius (m).
    pub mean_radius_m: f64,
    /// Drums: the axial height h of the sheared surface; discs: the radial span R2 − R1 (m).
    pub height_m: f64,
    /// Width across the gap, g (m).
    pub width_m: f64,
    /// Which wall rotates.
    pub rotating_wall: RotatingWall,
    /// The direction of shaft rotation this gap brakes.
    pub direction: Direction,
    /// The sample line along the middle of the gap, from one end of the sheared surface to the
    /// other (drums: along z at the mid radius; discs: along r at the mid height).
    pub sample_line: [[f64; 2]; 2],
    /// Edge tag of the wall at smaller r (drums) or smaller z (discs).
    pub inner_wall_tag: u32,
    /// Edge tag of the opposite wall.
    pub outer_wall_tag: u32,
}

/// A coil.
#[derive(Debug, Clone, PartialEq)]
pub struct CoilInfo {
    /// Physical tag of the coil's triangles.
    pub tag: u32,
    /// Unit index.
    pub unit: usize,
    /// The winding window.
    pub rect: Rect,
    /// Number of turns.
    pub turns: u32,
    /// +1 or −1: the sign of the azimuthal current for a positive drive current (the outer coil
    /// of a two-sided pair is driven backwards, thesis 3.1.4).
    pub current_sign: f64,
}

/// The whole model.
#[derive(Debug, Clone, PartialEq)]
pub struct BrakeGeometry {
    /// Every part, including the fluid gaps, coils and the air box.
    pub regions: Vec<Region>,
    /// The fluid gaps.
    pub gaps: Vec<GapInfo>,
    /// The coils (one per unit, two for a two-sided coil).
    pub coils: Vec<CoilInfo>,
    /// Edge tag of the axis r = 0 (Dirichlet A = 0).
    pub axis_tag: u32,
    /// Edge tag of the outer boundary of the air box (Dirichlet A = 0).
    pub outer_tag: u32,
    /// The device's bounding box.
    pub device: Rect,
    /// The modelled domain (device plus air margin).
    pub domain: Rect,
    /// Number of units (2 for the bidirectional brake).
    pub units: usize,
    /// The bidirectional brake's mirror plane `z` (m): unit 2 and its coil are unit 1 mirrored
    /// about it, and so are the domain and the field of one energised unit (used to warm-start
    /// one direction's solve from the other's). `None` for a single unit.
    pub mirror_z: Option<f64>,
}

/// Edge tag of the axis.
pub const AXIS_TAG: u32 = 1;
/// Edge tag of the outer boundary.
pub const OUTER_TAG: u32 = 2;
/// First edge tag used for gap walls.
const FIRST_WALL_TAG: u32 = 10;

impl BrakeGeometry {
    /// The region with this tag.
    pub fn region(&self, tag: u32) -> Option<&Region> {
        self.regions.iter().find(|r| r.tag == tag)
    }

    /// The region with this name.
    pub fn region_named(&self, name: &str) -> Option<&Region> {
        self.regions.iter().find(|r| r.name == name)
    }
}

/// The geometry of a spec: validates it (an invalid spec is an input error) and returns the
/// geometry the validation assembled. Callers that also need the warnings use
/// [`BrakeSpec::validate`].
pub fn build(spec: &BrakeSpec) -> Result<BrakeGeometry, DesignError> {
    spec.validate().map(|validated| validated.geometry)
}
