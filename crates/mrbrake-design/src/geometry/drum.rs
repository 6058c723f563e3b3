//! Unit 1 of a drum-family brake (drum, multi-drum, each unit of the bidirectional brake): the
//! static circuit, the cylinder stack with its 2n fluid gaps, and the coil beside the stack (see
//! the layout in [`super`]).

use super::assemble::Builder;
use super::{CoilInfo, Direction, GapInfo, GapOrientation, PartKind, Rect, RotatingWall};
use crate::spec::{BrakeSpec, CoilPlacement, Drum};

/// The radial and axial stations of a drum unit (m).
struct Stations {
    r_s: f64,
    r_out: f64,
    shell_in: f64,
    r0: f64,
    core_in: f64,
    /// Outer radius of the last gap.
    stack_out: f64,
    /// Axial end of the cover, of the rotor disc, of the stack, of the coil space, of the end plate.
    z_cover: f64,
    z_rotor: f64,
    z_stack: f64,
    z_coil: f64,
    z_end: f64,
}

impl Stations {
    fn of(spec: &BrakeSpec, drum: &Drum) -> Self {
        let h = &spec.housing;
        let bw = spec.coil.bobbin_wall.m();
        let r_out = h.outer_radius.m();
        let r0 = drum.r0.m();
        // Validation guarantees drums have a cover and a rotor disc.
        let z_cover = h.cover_thickness.map_or(0.0, |t| t.m());
        let z_rotor = z_cover + h.rotor_disc_thickness.map_or(0.0, |t| t.m());
        let z_stack = z_rotor + drum.height.m();
        let z_coil = z_stack + spec.coil.window_height.m() + 2.0 * bw;
        Self {
            r_s: spec.shaft.radius.m(),
            r_out,
            shell_in: r_out - h.case_thickness.m(),
            r0,
            core_in: r0 - h.inner_case_thickness.m(),
            stack_out: drum.surface_radius_m(drum.surfaces() - 1) + drum.gap.m(),
            z_cover,
            z_rotor,
            z_stack,
            z_coil,
            z_end: z_coil + h.end_plate_thickness.m(),
        }
    }
}

/// Builds unit 1 of a drum-family brake, its rotating parts turning in `direction`; returns the
/// unit's axial length.
pub(super) fn drum_unit(
    spec: &BrakeSpec,
    drum: &Drum,
    b: &mut Builder,
    direction: Direction,
) -> f64 {
    let s = Stations::of(spec, drum);
    static_circuit(spec, drum, &s, b, direction);
    cylinders(spec, drum, &s, b, direction);
    gaps(spec, drum, &s, b, direction);
    coil(spec, &s, b);
    s.z_end
}

/// Shaft, case shell, cover, rotor disc, inner core, case wall and end plate.
fn static_circuit(
    spec: &BrakeSpec,
    drum: &Drum,
    s: &Stations,
    b: &mut Builder,
    direction: Direction,
) {
    let m = &spec.materials;
    let unit = Some(0);
    let steel = |b: &mut Builder, name: &str, rect: Rect| {
        b.add(format!("unit1.{name}"), &m.flux_path, PartKind::FluxPath, vec![rect], unit, None);
    };
    b.add(
        "shaft".into(),
        &m.shaft,
        PartKind::Shaft,
        vec![Rect::new(0.0, s.r_s, 0.0, s.z_end)],
        unit,
        Some(direction),
    );
    steel(b, "case_shell", Rect::new(s.shell_in, s.r_out, 0.0, s.z_end));
    b.add(
        "unit1.cover".into(),
        &m.non_magnetic,
        PartKind::NonMagnetic,
        vec![Rect::new(s.r_s, s.shell_in, 0.0, s.z_cover)],
        unit,
        None,
    );
    let rotor_outer = drum.surface_radius_m(drum.surfaces() - 1);
    b.add(
        "unit1.rotor_disc".into(),
        &m.non_magnetic,
        PartKind::NonMagnetic,
        vec![Rect::new(s.r_s, rotor_outer, s.z_cover, s.z_rotor)],
        unit,
        Some(direction),
    );
    steel(b, "core", Rect::new(s.core_in, s.r0, s.z_rotor, s.z_coil));
    steel(b, "case_wall", Rect::new(s.stack_out, s.shell_in, s.z_rotor, s.z_stack));
    steel(b, "end_plate", Rect::new(s.core_in, s.shell_in, s.z_coil, s.z_end));
}

/// Cylinders j = 1..2n-1 between gaps j-1 and j; odd ones rotate (4.5: R_j = R_{j-1} + d + g).
fn cylinders(spec: &BrakeSpec, drum: &Drum, s: &Stations, b: &mut Builder, direction: Direction) {
    let g = drum.gap.m();
    for j in 1..drum.surfaces() {
        let rect = Rect::new(
            drum.surface_radius_m(j - 1) + g,
            drum.surface_radius_m(j),
            s.z_rotor,
            s.z_stack,
        );
        let rotating = j % 2 == 1;
        let name = if rotating {
            format!("unit1.rotor_cylinder{}", j.div_ceil(2))
        } else {
            format!("unit1.static_cylinder{}", j / 2)
        };
        b.add(
            name,
            &spec.materials.flux_path,
            PartKind::FluxPath,
            vec![rect],
            Some(0),
            rotating.then_some(direction),
        );
    }
}

/// The 2n cylindrical fluid gaps, gap k at R_k (4.5).
fn gaps(spec: &BrakeSpec, drum: &Drum, s: &Stations, b: &mut Builder, direction: Direction) {
    let (g, height) = (drum.gap.m(), drum.height.m());
    for k in 0..drum.surfaces() {
        let rk = drum.surface_radius_m(k);
        let rect = Rect::new(rk, rk + g, s.z_rotor, s.z_stack);
        let name = format!("unit1.gap{}", k + 1);
        let tag = b.add(name, &spec.materials.fluid, PartKind::Fluid, vec![rect], Some(0), None);
        let walls = b.wall_tags();
        let mid = rk + 0.5 * g;
        b.gaps.push(GapInfo {
            index: b.gaps.len(),
            index_in_unit: k as usize,
            unit: 0,
            tag,
            rect,
            orientation: GapOrientation::Cylindrical,
            shear_radius_m: rk,
            mean_radius_m: mid,
            height_m: height,
            width_m: g,
            // Gap k lies between cylinder k (inner wall; the static core for k = 0) and cylinder k+1.
            rotating_wall: if k % 2 == 1 { RotatingWall::Inner } else { RotatingWall::Outer },
            direction,
            sample_line: [[mid, s.z_rotor], [mid, s.z_stack]],
            inner_wall_tag: walls.0,
            outer_wall_tag: walls.1,
        });
    }
}

/// The coil window beside the stack, against the core (inner) or the case shell (outer).
fn coil(spec: &BrakeSpec, s: &Stations, b: &mut Builder) {
    let c = &spec.coil;
    let bw = c.bobbin_wall.m();
    let coil_r0 = match c.placement {
        CoilPlacement::Outer => s.shell_in - bw - c.window_width.m(),
        _ => s.r0 + bw,
    };
    let rect = Rect::new(
        coil_r0,
        coil_r0 + c.window_width.m(),
        s.z_stack + bw,
        s.z_stack + bw + c.window_height.m(),
    );
    let tag =
        b.add("unit1.coil".into(), &spec.materials.coil, PartKind::Coil, vec![rect], Some(0), None);
    b.coils.push(CoilInfo { tag, unit: 0, rect, turns: spec.turns(), current_sign: 1.0 });
}
