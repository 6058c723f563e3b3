//! Assembly of the parts: unit 1 of the configuration ([`super::drum`] or [`super::disc`]), for the
//! bidirectional brake unit 2 mirrored about the spacer, the bobbins and the non-magnetic filler
//! (cut from the same rectangles), and the air box.
//! Tags are given in the order parts are added, so this order is part of the mesh's contract.

use super::{
    AXIS_TAG, BrakeGeometry, CoilInfo, Direction, FIRST_WALL_TAG, GapInfo, OUTER_TAG, PartKind,
    Rect, Region, disc, drum,
};
use crate::spec::{BrakeSpec, Configuration, Spacer};

/// Collects the parts, gaps and coils and hands out their tags.
pub(super) struct Builder {
    pub regions: Vec<Region>,
    pub gaps: Vec<GapInfo>,
    pub coils: Vec<CoilInfo>,
    next_tag: u32,
    next_wall_tag: u32,
}

impl Builder {
    fn new() -> Self {
        Self {
            regions: Vec::new(),
            gaps: Vec::new(),
            coils: Vec::new(),
            next_tag: 1,
            next_wall_tag: FIRST_WALL_TAG,
        }
    }

    /// Adds a part; returns its tag.
    pub fn add(
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

    /// The edge tags of a new gap's two walls (inner, outer).
    pub fn wall_tags(&mut self) -> (u32, u32) {
        let walls = (self.next_wall_tag, self.next_wall_tag + 1);
        self.next_wall_tag += 2;
        walls
    }
}

/// Assembles the parts of a spec whose fields are valid (the geometric rules are checked on the
/// result by [`super::check_assembled`]).
pub(crate) fn assemble(spec: &BrakeSpec) -> BrakeGeometry {
    let mut b = Builder::new();
    let (device_length, mirror_z) = match &spec.configuration {
        Configuration::SingleDisc(d) | Configuration::MultiDisc(d) => {
            (disc::disc_unit(spec, d, &mut b), None)
        }
        Configuration::Drum(d) | Configuration::MultiDrum(d) => {
            (drum::drum_unit(spec, d, &mut b, Direction::Both), None)
        }
        Configuration::Bidirectional { drum: d, spacer } => {
            let unit_length = drum::drum_unit(spec, d, &mut b, Direction::Clockwise);
            let z_mirror = add_second_unit(spec, spacer, &mut b, unit_length);
            (2.0 * unit_length + spacer.thickness.m(), Some(z_mirror))
        }
    };
    let units = spec.configuration.units();
    let r_out = spec.housing.outer_radius.m();
    let device = Rect::new(0.0, r_out, 0.0, device_length);
    fill_gaps_with_filler(spec, &mut b, device, units);
    let domain = add_air(spec, &mut b, device);
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

/// Unit 2 of the bidirectional brake: unit 1 (of axial length `unit_length`) mirrored about the
/// middle of the spacer, turning counter-clockwise; then the spacer, and the shaft through both
/// units. Returns the mirror plane's `z`.
fn add_second_unit(spec: &BrakeSpec, spacer: &Spacer, b: &mut Builder, unit_length: f64) -> f64 {
    let spacer = spacer.thickness.m();
    let z_mirror = unit_length + 0.5 * spacer;
    let unit1: Vec<Region> = b.regions.clone();
    for r in unit1.iter().filter(|r| r.kind != PartKind::Shaft) {
        let name = r.name.replacen("unit1.", "unit2.", 1);
        let rects = r.rects.iter().map(|rc| rc.mirrored(z_mirror)).collect();
        let rotates = r.rotates.map(|_| Direction::CounterClockwise);
        let new_tag = b.add(name, &r.material, r.kind, rects, Some(1), rotates);
        if let Some(g) = b.gaps.iter().find(|g| g.tag == r.tag).cloned() {
            let walls = b.wall_tags();
            let line = g.sample_line.map(|p| [p[0], 2.0 * z_mirror - p[1]]);
            b.gaps.push(GapInfo {
                index: b.gaps.len(),
                unit: 1,
                tag: new_tag,
                rect: g.rect.mirrored(z_mirror),
                direction: Direction::CounterClockwise,
                sample_line: [line[1], line[0]],
                inner_wall_tag: walls.0,
                outer_wall_tag: walls.1,
                ..g
            });
        }
        if let Some(c) = b.coils.iter().find(|c| c.tag == r.tag).cloned() {
            b.coils.push(CoilInfo { tag: new_tag, unit: 1, rect: c.rect.mirrored(z_mirror), ..c });
        }
    }
    // The spacer spans from the shaft to the case shell's outer radius.
    let r_s = spec.shaft.radius.m();
    let r_out = spec.housing.outer_radius.m();
    let m = &spec.materials;
    b.add(
        "spacer".into(),
        m.spacer(),
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
    z_mirror
}

/// The air box around the device, `model.air_margin` wide; returns the modelled domain.
fn add_air(spec: &BrakeSpec, b: &mut Builder, device: Rect) -> Rect {
    let m = spec.model.air_margin.m();
    let (r_out, length) = (device.r1, device.z1);
    b.add(
        "air".into(),
        &spec.materials.surroundings,
        PartKind::Air,
        vec![
            Rect::new(0.0, r_out, -m, 0.0),
            Rect::new(0.0, r_out, length, length + m),
            Rect::new(r_out, r_out + m, -m, length + m),
        ],
        None,
        None,
    );
    Rect::new(0.0, r_out + m, -m, length + m)
}

/// Covers the device's bounding box: every grid cell (from all rectangle edges) not inside a part
/// becomes non-magnetic filler; cells are merged along r into rectangles, one filler region per unit.
/// The rectangles of a unit's filler that lie in a bobbin wall of one of its coils
/// ([`in_bobbin`]) are the unit's bobbin instead, added just before its filler.
fn fill_gaps_with_filler(spec: &BrakeSpec, b: &mut Builder, device: Rect, units: usize) {
    let wall = spec.coil.bobbin_wall.m();
    for (unit, rects) in filler_rects(b, device, units).into_iter().enumerate() {
        let windows: Vec<Rect> =
            b.coils.iter().filter(|c| c.unit == unit).map(|c| c.rect).collect();
        let (bobbin, filler): (Vec<Rect>, Vec<Rect>) =
            rects.into_iter().partition(|r| windows.iter().any(|w| in_bobbin(r, w, wall)));
        let parts = [
            ("bobbin", spec.materials.bobbin(), PartKind::Bobbin, bobbin),
            ("filler", spec.materials.non_magnetic.as_str(), PartKind::NonMagnetic, filler),
        ];
        for (name, material, kind, rects) in parts {
            if !rects.is_empty() {
                b.add(format!("unit{}.{name}", unit + 1), material, kind, rects, Some(unit), None);
            }
        }
    }
}

/// The uncovered cells of the device's bounding box merged along r into rectangles, per unit, in
/// order of z then r.
fn filler_rects(b: &Builder, device: Rect, units: usize) -> Vec<Vec<Rect>> {
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
    filler
}

/// True when the filler rectangle `rect` lies in a bobbin wall (`wall` thick) of the winding
/// `window`: beside it (radially within one wall of its inner or outer side, over its height and
/// flanges) or across one of its ends (axially within one wall, overlapping it radially: the
/// flanges reach across the coil pocket). Distances are compared to 1 pm, the geometry's grid.
fn in_bobbin(rect: &Rect, window: &Rect, wall: f64) -> bool {
    const TOL: f64 = 1e-12;
    let within = |a0: f64, a1: f64, b0: f64, b1: f64| a0 >= b0 - TOL && a1 <= b1 + TOL;
    let overlaps = |a0: f64, a1: f64, b0: f64, b1: f64| a0 < b1 - TOL && b0 < a1 - TOL;
    let (w, r) = (window, rect);
    let flange = (within(r.z0, r.z1, w.z0 - wall, w.z0) || within(r.z0, r.z1, w.z1, w.z1 + wall))
        && overlaps(r.r0, r.r1, w.r0, w.r1);
    let side = (within(r.r0, r.r1, w.r0 - wall, w.r0) || within(r.r0, r.r1, w.r1, w.r1 + wall))
        && overlaps(r.z0, r.z1, w.z0 - wall, w.z1 + wall);
    flange || side
}
