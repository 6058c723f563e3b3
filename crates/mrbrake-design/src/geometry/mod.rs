//! Geometry builder: a [`BrakeSpec`] → named, tagged axisymmetric regions in the (r, z) half-plane.
//!
//! Brief overview: [`build`] returns a [`BrakeGeometry`]: every part as a [`Region`] (one or more
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
//! Any area of a unit's bounding box not covered by a named part is non-magnetic filler (bobbin,
//! seals, hub: modelled with `materials.non_magnetic`). Mechanical details that do not carry flux
//! (bearings, seals, bolts) are not modelled.

use crate::DesignError;
use crate::spec::{BrakeSpec, CoilPlacement, Configuration, Problems, fmt_mm};

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
    /// A non-magnetic structural part (rotor disc, cover, bobbin, filler).
    NonMagnetic,
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
    /// Global index (0-based over all units).
    pub index: usize,
    /// Index within its unit: k of (4.4) for drums.
    pub index_in_unit: usize,
    /// The unit it belongs to.
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

/// Builds the geometry of a validated spec (validation runs first; an invalid spec is an input error).
pub fn build(spec: &BrakeSpec) -> Result<BrakeGeometry, DesignError> {
    spec.validate()?;
    Ok(assemble(spec))
}

/// Checks the rules that need assembled parts: overlaps, gaps filled with fluid between a rotating
/// and a static wall, envelope. Called by [`BrakeSpec::validate`] once the fields are valid.
pub(crate) fn check_assembly(spec: &BrakeSpec, p: &mut Problems) {
    check_fit(spec, p);
    if !p.errors.is_empty() {
        return;
    }
    let g = assemble(spec);
    let tol = 1e-9;
    let solid: Vec<&Region> = g.regions.iter().filter(|r| r.kind != PartKind::Air).collect();
    for (i, a) in solid.iter().enumerate() {
        for b in &solid[i + 1..] {
            if a.rects.iter().any(|ra| b.rects.iter().any(|rb| ra.overlaps(rb, tol))) {
                p.error(
                    &format!("{} / {}", a.name, b.name),
                    "these parts overlap: check the dimensions that place them",
                );
            }
        }
    }
    for gap in &g.gaps {
        // Each wall of the gap must touch a flux-path part, one rotating and one static.
        let probe = |inner: bool| -> Option<&Region> {
            let r = gap.rect;
            let eps = 1e-7;
            let point = match (gap.orientation, inner) {
                (GapOrientation::Cylindrical, true) => [r.r0 - eps, 0.5 * (r.z0 + r.z1)],
                (GapOrientation::Cylindrical, false) => [r.r1 + eps, 0.5 * (r.z0 + r.z1)],
                (GapOrientation::Annular, true) => [0.5 * (r.r0 + r.r1), r.z0 - eps],
                (GapOrientation::Annular, false) => [0.5 * (r.r0 + r.r1), r.z1 + eps],
            };
            g.regions.iter().find(|reg| reg.rects.iter().any(|rc| rc.contains(point)))
        };
        let field = if spec.configuration.is_drum() { "drum.gap" } else { "disc.gap" };
        match (probe(true), probe(false)) {
            (Some(a), Some(b)) if a.rotates.is_some() != b.rotates.is_some() => {}
            _ => p.error(
                field,
                format!(
                    "gap {} (unit {}) is not a fluid layer between a rotating and a static wall",
                    gap.index_in_unit,
                    gap.unit + 1
                ),
            ),
        }
    }
    let diameter = 2.0 * (g.device.r1 - g.device.r0.min(0.0));
    let length = g.device.z1 - g.device.z0;
    if diameter > spec.envelope.diameter.m() * (1.0 + 1e-12) {
        p.error(
            "envelope.diameter",
            format!("the device is {} in diameter (2 × housing.outer_radius); the envelope allows at most {}", fmt_mm(diameter), fmt_mm(spec.envelope.diameter.m())),
        );
    }
    if length > spec.envelope.length.m() * (1.0 + 1e-12) {
        p.error(
            "envelope.length",
            format!(
                "the modelled device is {} long; the envelope allows at most {}",
                fmt_mm(length),
                fmt_mm(spec.envelope.length.m())
            ),
        );
    }
}

/// Radial and axial fit rules, each naming the field to change and the allowed range.
fn check_fit(spec: &BrakeSpec, p: &mut Problems) {
    let h = &spec.housing;
    let c = &spec.coil;
    let r_s = spec.shaft.radius.m();
    let r_out = h.outer_radius.m();
    let shell_in = r_out - h.case_thickness.m();
    let b = c.bobbin_wall.m();
    let cw = c.window_width.m();
    if spec.configuration.is_drum() {
        let Some(d) = &spec.drum else { return };
        let core_in = d.r0.m() - h.inner_case_thickness.m();
        if core_in <= r_s {
            p.error(
                "housing.inner_case_thickness",
                format!("{} leaves no room between the shaft (radius {}) and the core: must be < drum.r0 − shaft.radius = {}", fmt_mm(h.inner_case_thickness.m()), fmt_mm(r_s), fmt_mm(d.r0.m() - r_s)),
            );
        }
        let stack_out = d.surface_radius_m(d.surfaces() - 1) + d.gap.m();
        if stack_out >= shell_in {
            p.error(
                "housing.outer_radius",
                format!("{} is too small: the drum stack ends at r = {} and the case needs housing.case_thickness = {} beyond it; allowed > {}", fmt_mm(r_out), fmt_mm(stack_out), fmt_mm(h.case_thickness.m()), fmt_mm(stack_out + h.case_thickness.m())),
            );
        }
        // 1 nm of slack: a window that fits exactly must not fail on rounding.
        if d.r0.m() + 2.0 * b + cw > shell_in + 1e-9 {
            p.error(
                "coil.window_width",
                format!("{} does not fit between the core (r = {}) and the case shell (r = {}) with two bobbin walls: allowed ≤ {}", fmt_mm(cw), fmt_mm(d.r0.m()), fmt_mm(shell_in), fmt_mm(shell_in - d.r0.m() - 2.0 * b)),
            );
        }
    } else {
        let Some(d) = &spec.disc else { return };
        let (r1, r2) = (d.inner_radius.m(), d.outer_radius.m());
        if r1 <= r_s {
            p.error(
                "disc.inner_radius",
                format!("{} must be greater than shaft.radius = {}", fmt_mm(r1), fmt_mm(r_s)),
            );
        }
        let outer = matches!(c.placement, CoilPlacement::Outer | CoilPlacement::TwoSided);
        let inner = matches!(c.placement, CoilPlacement::Inner | CoilPlacement::TwoSided);
        let needed_out = if outer { r2 + 2.0 * b + cw } else { r2 };
        if needed_out >= shell_in {
            p.error(
                "housing.outer_radius",
                format!("{} is too small: the discs{} reach r = {} and the case shell needs housing.case_thickness = {}; allowed > {}", fmt_mm(r_out), if outer { " and the outer coil" } else { "" }, fmt_mm(needed_out), fmt_mm(h.case_thickness.m()), fmt_mm(needed_out + h.case_thickness.m())),
            );
        }
        if inner {
            let core_out = r_s + h.inner_case_thickness.m();
            if core_out + 2.0 * b + cw > r1 + 1e-9 {
                p.error(
                    "coil.window_width",
                    format!("{} does not fit the inner coil between the core ring (r = {}) and disc.inner_radius = {} with two bobbin walls: allowed ≤ {}", fmt_mm(cw), fmt_mm(core_out), fmt_mm(r1), fmt_mm(r1 - core_out - 2.0 * b)),
                );
            }
        }
    }
}

struct Builder {
    regions: Vec<Region>,
    gaps: Vec<GapInfo>,
    coils: Vec<CoilInfo>,
    next_tag: u32,
    next_wall_tag: u32,
}

impl Builder {
    fn add(
        &mut self,
        name: String,
        material: &str,
        kind: PartKind,
        rects: Vec<Rect>,
        unit: Option<usize>,
        rotates: Option<Direction>,
    ) -> u32 {
        let tag = self.next_tag;
        self.next_tag += 1;
        self.regions.push(Region {
            tag,
            name,
            material: material.to_string(),
            kind,
            rects,
            unit,
            rotates,
        });
        tag
    }
}

/// Assembles the parts without validation (used by validation itself).
fn assemble(spec: &BrakeSpec) -> BrakeGeometry {
    let mut b = Builder {
        regions: Vec::new(),
        gaps: Vec::new(),
        coils: Vec::new(),
        next_tag: 1,
        next_wall_tag: FIRST_WALL_TAG,
    };
    let units = if spec.configuration == Configuration::Bidirectional { 2 } else { 1 };
    let unit_length = if spec.configuration.is_drum() {
        drum_unit(spec, &mut b, 0, Direction::Both, true)
    } else {
        disc_unit(spec, &mut b)
    };
    let direction0 = if units == 2 { Direction::Clockwise } else { Direction::Both };
    // Re-label directions of unit 0 for the bidirectional brake, then mirror it for unit 1.
    let mut mirror_z = None;
    if units == 2 {
        for r in b.regions.iter_mut().filter(|r| r.rotates.is_some()) {
            r.rotates = Some(direction0);
        }
        for g in b.gaps.iter_mut() {
            g.direction = direction0;
        }
        let spacer = spec.spacer.as_ref().map_or(0.0, |s| s.thickness.m());
        let z_mirror = unit_length + 0.5 * spacer;
        mirror_z = Some(z_mirror);
        let r_out = spec.housing.outer_radius.m();
        let spacer_material =
            spec.materials.spacer.clone().unwrap_or_else(|| spec.materials.non_magnetic.clone());
        let unit0: Vec<Region> = b.regions.clone();
        for r in &unit0 {
            if r.kind == PartKind::Shaft {
                continue;
            }
            let name = r.name.replacen("unit1.", "unit2.", 1);
            let rects = r.rects.iter().map(|rc| rc.mirrored(z_mirror)).collect();
            let rotates = r.rotates.map(|_| Direction::CounterClockwise);
            let new_tag = b.add(name, &r.material, r.kind, rects, Some(1), rotates);
            if let Some(g) = b.gaps.iter().find(|g| g.tag == r.tag).cloned() {
                let walls = (b.next_wall_tag, b.next_wall_tag + 1);
                b.next_wall_tag += 2;
                let rect = g.rect.mirrored(z_mirror);
                let line = g.sample_line.map(|p| [p[0], 2.0 * z_mirror - p[1]]);
                b.gaps.push(GapInfo {
                    index: b.gaps.len(),
                    unit: 1,
                    tag: new_tag,
                    rect,
                    direction: Direction::CounterClockwise,
                    sample_line: [line[1], line[0]],
                    inner_wall_tag: walls.0,
                    outer_wall_tag: walls.1,
                    ..g
                });
            }
            if let Some(c) = b.coils.iter().find(|c| c.tag == r.tag).cloned() {
                b.coils.push(CoilInfo {
                    tag: new_tag,
                    unit: 1,
                    rect: c.rect.mirrored(z_mirror),
                    ..c
                });
            }
        }
        // The spacer spans from the shaft to the case shell's outer radius.
        let r_s = spec.shaft.radius.m();
        b.add(
            "spacer".into(),
            &spacer_material,
            PartKind::Spacer,
            vec![Rect::new(r_s, r_out, unit_length, unit_length + spacer)],
            None,
            None,
        );
        // The shared shaft runs through both units and the spacer.
        if let Some(shaft) = b.regions.iter_mut().find(|r| r.kind == PartKind::Shaft) {
            shaft.rects = vec![Rect::new(0.0, r_s, 0.0, 2.0 * unit_length + spacer)];
            shaft.unit = None;
        }
    }
    let device_length = if units == 2 {
        2.0 * unit_length + spec.spacer.as_ref().map_or(0.0, |s| s.thickness.m())
    } else {
        unit_length
    };
    let r_out = spec.housing.outer_radius.m();
    let device = Rect::new(0.0, r_out, 0.0, device_length);
    fill_gaps_with_filler(spec, &mut b, device, units);
    let m = spec.model.air_margin.m();
    let domain = Rect::new(0.0, r_out + m, -m, device_length + m);
    b.add(
        "air".into(),
        &spec.materials.surroundings,
        PartKind::Air,
        vec![
            Rect::new(0.0, r_out, -m, 0.0),
            Rect::new(0.0, r_out, device_length, device_length + m),
            Rect::new(r_out, r_out + m, -m, device_length + m),
        ],
        None,
        None,
    );
    BrakeGeometry {
        regions: b.regions,
        gaps: b.gaps,
        coils: b.coils,
        axis_tag: AXIS_TAG,
        outer_tag: OUTER_TAG,
        device,
        domain,
        units,
        mirror_z,
    }
}

/// Builds unit 1 of a drum-family brake; returns the unit's axial length.
fn drum_unit(
    spec: &BrakeSpec,
    b: &mut Builder,
    unit: usize,
    direction: Direction,
    with_shaft: bool,
) -> f64 {
    let drum = spec.drum.as_ref().expect("checked by validation: drum configurations have [drum]");
    let h = &spec.housing;
    let m = &spec.materials;
    let c = &spec.coil;
    let u = format!("unit{}.", unit + 1);
    let r_s = spec.shaft.radius.m();
    let r_out = h.outer_radius.m();
    let shell_in = r_out - h.case_thickness.m();
    let (g, hh) = (drum.gap.m(), drum.height.m());
    let n_surf = drum.surfaces();
    let r0 = drum.r0.m();
    let core_in = r0 - h.inner_case_thickness.m();
    let stack_out = drum.surface_radius_m(n_surf - 1) + g;
    let bw = c.bobbin_wall.m();
    // Axial stations.
    let z_cover = h.cover_thickness.map_or(0.0, |t| t.m());
    let z_rotor = z_cover + h.rotor_disc_thickness.map_or(0.0, |t| t.m());
    let z_stack = z_rotor + hh;
    let z_coil = z_stack + c.window_height.m() + 2.0 * bw;
    let z_end = z_coil + h.end_plate_thickness.m();
    if with_shaft {
        b.add(
            format!("{u}shaft").replace("unit1.", ""),
            &m.shaft,
            PartKind::Shaft,
            vec![Rect::new(0.0, r_s, 0.0, z_end)],
            Some(unit),
            Some(direction),
        );
    }
    b.add(
        format!("{u}case_shell"),
        &m.flux_path,
        PartKind::FluxPath,
        vec![Rect::new(shell_in, r_out, 0.0, z_end)],
        Some(unit),
        None,
    );
    b.add(
        format!("{u}cover"),
        &m.non_magnetic,
        PartKind::NonMagnetic,
        vec![Rect::new(r_s, shell_in, 0.0, z_cover)],
        Some(unit),
        None,
    );
    let rotor_outer = drum.surface_radius_m(n_surf - 1);
    b.add(
        format!("{u}rotor_disc"),
        &m.non_magnetic,
        PartKind::NonMagnetic,
        vec![Rect::new(r_s, rotor_outer, z_cover, z_rotor)],
        Some(unit),
        Some(direction),
    );
    b.add(
        format!("{u}core"),
        &m.flux_path,
        PartKind::FluxPath,
        vec![Rect::new(core_in, r0, z_rotor, z_coil)],
        Some(unit),
        None,
    );
    b.add(
        format!("{u}case_wall"),
        &m.flux_path,
        PartKind::FluxPath,
        vec![Rect::new(stack_out, shell_in, z_rotor, z_stack)],
        Some(unit),
        None,
    );
    b.add(
        format!("{u}end_plate"),
        &m.flux_path,
        PartKind::FluxPath,
        vec![Rect::new(core_in, shell_in, z_coil, z_end)],
        Some(unit),
        None,
    );
    // Cylinders j = 1..2n-1 between gaps j-1 and j; odd ones rotate (4.5: R_j = R_{j-1} + d + g).
    for j in 1..n_surf {
        let rect =
            Rect::new(drum.surface_radius_m(j - 1) + g, drum.surface_radius_m(j), z_rotor, z_stack);
        let rotating = j % 2 == 1;
        let name = if rotating {
            format!("{u}rotor_cylinder{}", j.div_ceil(2))
        } else {
            format!("{u}static_cylinder{}", j / 2)
        };
        b.add(
            name,
            &m.flux_path,
            PartKind::FluxPath,
            vec![rect],
            Some(unit),
            rotating.then_some(direction),
        );
    }
    for k in 0..n_surf {
        let rk = drum.surface_radius_m(k);
        let rect = Rect::new(rk, rk + g, z_rotor, z_stack);
        let tag =
            b.add(format!("{u}gap{k}"), &m.fluid, PartKind::Fluid, vec![rect], Some(unit), None);
        let walls = (b.next_wall_tag, b.next_wall_tag + 1);
        b.next_wall_tag += 2;
        let mid = rk + 0.5 * g;
        b.gaps.push(GapInfo {
            index: b.gaps.len(),
            index_in_unit: k as usize,
            unit,
            tag,
            rect,
            orientation: GapOrientation::Cylindrical,
            shear_radius_m: rk,
            mean_radius_m: mid,
            height_m: hh,
            width_m: g,
            // Gap k lies between cylinder k (inner wall; the static core for k = 0) and cylinder k+1.
            rotating_wall: if k % 2 == 1 { RotatingWall::Inner } else { RotatingWall::Outer },
            direction,
            sample_line: [[mid, z_rotor], [mid, z_stack]],
            inner_wall_tag: walls.0,
            outer_wall_tag: walls.1,
        });
    }
    let coil_r0 = match c.placement {
        CoilPlacement::Outer => shell_in - bw - c.window_width.m(),
        _ => r0 + bw,
    };
    let coil_rect = Rect::new(
        coil_r0,
        coil_r0 + c.window_width.m(),
        z_stack + bw,
        z_stack + bw + c.window_height.m(),
    );
    let tag = b.add(format!("{u}coil"), &m.coil, PartKind::Coil, vec![coil_rect], Some(unit), None);
    b.coils.push(CoilInfo { tag, unit, rect: coil_rect, turns: spec.turns(), current_sign: 1.0 });
    z_end
}

/// Builds a disc-family brake; returns its axial length.
fn disc_unit(spec: &BrakeSpec, b: &mut Builder) -> f64 {
    let disc = spec.disc.as_ref().expect("checked by validation: disc configurations have [disc]");
    let h = &spec.housing;
    let m = &spec.materials;
    let c = &spec.coil;
    let u = "unit1.";
    let r_s = spec.shaft.radius.m();
    let r_out = h.outer_radius.m();
    let shell_in = r_out - h.case_thickness.m();
    let (r1, r2) = (disc.inner_radius.m(), disc.outer_radius.m());
    let (g, d) = (disc.gap.m(), disc.thickness.m());
    let n = disc.count;
    let bw = c.bobbin_wall.m();
    let stack_height = f64::from(2 * n - 1) * d + f64::from(2 * n) * g;
    let level = stack_height.max(c.window_height.m() + 2.0 * bw);
    let tp = h.end_plate_thickness.m();
    let z_level = tp;
    let z_top = tp + level;
    let z_end = z_top + tp;
    let z_stack0 = z_level + 0.5 * (level - stack_height);
    let z_stack1 = z_stack0 + stack_height;
    let inner = matches!(c.placement, CoilPlacement::Inner | CoilPlacement::TwoSided);
    let outer = matches!(c.placement, CoilPlacement::Outer | CoilPlacement::TwoSided);
    let both = Direction::Both;
    b.add(
        "shaft".into(),
        &m.shaft,
        PartKind::Shaft,
        vec![Rect::new(0.0, r_s, 0.0, z_end)],
        Some(0),
        Some(both),
    );
    b.add(
        format!("{u}case_shell"),
        &m.flux_path,
        PartKind::FluxPath,
        vec![Rect::new(shell_in, r_out, 0.0, z_end)],
        Some(0),
        None,
    );
    // End plates span from the core ring (inner coil) or the shaft clearance to the shell.
    let plate_r0 = r_s;
    b.add(
        format!("{u}lower_plate"),
        &m.flux_path,
        PartKind::FluxPath,
        vec![Rect::new(plate_r0, shell_in, 0.0, z_level)],
        Some(0),
        None,
    );
    b.add(
        format!("{u}upper_plate"),
        &m.flux_path,
        PartKind::FluxPath,
        vec![Rect::new(plate_r0, shell_in, z_top, z_end)],
        Some(0),
        None,
    );
    if z_stack0 > z_level + 1e-12 {
        b.add(
            format!("{u}lower_pole"),
            &m.flux_path,
            PartKind::FluxPath,
            vec![Rect::new(r1, r2, z_level, z_stack0)],
            Some(0),
            None,
        );
        b.add(
            format!("{u}upper_pole"),
            &m.flux_path,
            PartKind::FluxPath,
            vec![Rect::new(r1, r2, z_stack1, z_top)],
            Some(0),
            None,
        );
    }
    if inner {
        let core_out = r_s + h.inner_case_thickness.m();
        b.add(
            format!("{u}core_ring"),
            &m.flux_path,
            PartKind::FluxPath,
            vec![Rect::new(r_s, core_out, z_level, z_top)],
            Some(0),
            None,
        );
        let rect = Rect::new(
            r1 - bw - c.window_width.m(),
            r1 - bw,
            z_level + 0.5 * (level - c.window_height.m()),
            z_level + 0.5 * (level + c.window_height.m()),
        );
        let tag =
            b.add(format!("{u}inner_coil"), &m.coil, PartKind::Coil, vec![rect], Some(0), None);
        b.coils.push(CoilInfo { tag, unit: 0, rect, turns: spec.turns(), current_sign: 1.0 });
    }
    if outer {
        let rect = Rect::new(
            r2 + bw,
            r2 + bw + c.window_width.m(),
            z_level + 0.5 * (level - c.window_height.m()),
            z_level + 0.5 * (level + c.window_height.m()),
        );
        let tag =
            b.add(format!("{u}outer_coil"), &m.coil, PartKind::Coil, vec![rect], Some(0), None);
        // Two-sided: the outer coil is driven backwards so both coils push flux the same way
        // through the discs (thesis 3.1.4).
        b.coils.push(CoilInfo {
            tag,
            unit: 0,
            rect,
            turns: spec.turns(),
            current_sign: if inner { -1.0 } else { 1.0 },
        });
    }
    // Stack from the bottom: gap, rotating disc, gap, (static disc, gap, rotating disc, gap)...
    let mut z = z_stack0;
    for k in 0..2 * n {
        let rect = Rect::new(r1, r2, z, z + g);
        let tag = b.add(format!("{u}gap{k}"), &m.fluid, PartKind::Fluid, vec![rect], Some(0), None);
        let walls = (b.next_wall_tag, b.next_wall_tag + 1);
        b.next_wall_tag += 2;
        let zm = z + 0.5 * g;
        b.gaps.push(GapInfo {
            index: b.gaps.len(),
            index_in_unit: k as usize,
            unit: 0,
            tag,
            rect,
            orientation: GapOrientation::Annular,
            shear_radius_m: 0.5 * (r1 + r2),
            mean_radius_m: 0.5 * (r1 + r2),
            height_m: r2 - r1,
            width_m: g,
            // Even gaps lie below a rotating disc, odd gaps above one.
            rotating_wall: if k % 2 == 0 { RotatingWall::Outer } else { RotatingWall::Inner },
            direction: both,
            sample_line: [[r1, zm], [r2, zm]],
            inner_wall_tag: walls.0,
            outer_wall_tag: walls.1,
        });
        z += g;
        if k + 1 < 2 * n {
            let rotating = k % 2 == 0;
            let name = if rotating {
                format!("{u}rotor_disc{}", k / 2 + 1)
            } else {
                format!("{u}static_disc{}", k / 2 + 1)
            };
            b.add(
                name,
                &m.flux_path,
                PartKind::FluxPath,
                vec![Rect::new(r1, r2, z, z + d)],
                Some(0),
                rotating.then_some(both),
            );
            z += d;
        }
    }
    z_end
}

/// Covers the device's bounding box: every grid cell (from all rectangle edges) not inside a part
/// becomes non-magnetic filler; cells are merged along r into rectangles, one filler region per unit.
fn fill_gaps_with_filler(spec: &BrakeSpec, b: &mut Builder, device: Rect, units: usize) {
    let mut rs: Vec<f64> = vec![device.r0, device.r1];
    let mut zs: Vec<f64> = vec![device.z0, device.z1];
    for r in &b.regions {
        for rc in &r.rects {
            rs.extend([rc.r0, rc.r1]);
            zs.extend([rc.z0, rc.z1]);
        }
    }
    let dedup = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
    };
    dedup(&mut rs);
    dedup(&mut zs);
    let mut filler: Vec<Vec<Rect>> = vec![Vec::new(); units.max(1)];
    let unit_of = |z: f64| if units == 2 && z > 0.5 * (device.z0 + device.z1) { 1 } else { 0 };
    for zw in zs.windows(2) {
        let mut run: Option<Rect> = None;
        for rw in rs.windows(2) {
            let centre = [0.5 * (rw[0] + rw[1]), 0.5 * (zw[0] + zw[1])];
            let covered = !device.contains(centre)
                || b.regions.iter().any(|r| r.rects.iter().any(|rc| rc.contains(centre)));
            match (&mut run, covered) {
                (Some(cur), false) => cur.r1 = rw[1],
                (None, false) => run = Some(Rect::new(rw[0], rw[1], zw[0], zw[1])),
                (Some(_), true) => {
                    filler[unit_of(centre[1])].push(run.take().expect("matched Some"))
                }
                (None, true) => {}
            }
        }
        if let Some(cur) = run {
            filler[unit_of(cur.centre()[1])].push(cur);
        }
    }
    for (unit, rects) in filler.into_iter().enumerate() {
        if !rects.is_empty() {
            b.add(
                format!("unit{}.filler", unit + 1),
                &spec.materials.non_magnetic,
                PartKind::NonMagnetic,
                rects,
                Some(unit),
                None,
            );
        }
    }
}
