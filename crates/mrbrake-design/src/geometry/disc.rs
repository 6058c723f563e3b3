//! A disc-family brake (single disc, multi-disc): steel plates, the working level with the disc
//! stack over R1..R2 and its 2n fluid gaps, and an inner and/or outer coil in the level (see the
//! layout in [`super`]).

use super::assemble::Builder;
use super::{CoilInfo, Direction, GapInfo, GapOrientation, PartKind, Rect, RotatingWall};
use crate::spec::{BrakeSpec, CoilPlacement, Disc};

/// The radial and axial stations of a disc brake (m).
struct Stations {
    r_s: f64,
    r_out: f64,
    shell_in: f64,
    r1: f64,
    r2: f64,
    /// Axial height of the working level (the stack or the coil window with its bobbin walls).
    level: f64,
    /// Axial start and end of the working level, end of the upper plate.
    z_level: f64,
    z_top: f64,
    z_end: f64,
    /// Axial ends of the disc stack, centred in the level.
    z_stack0: f64,
    z_stack1: f64,
}

impl Stations {
    fn of(spec: &BrakeSpec, disc: &Disc) -> Self {
        let h = &spec.housing;
        let c = &spec.coil;
        let r_out = h.outer_radius.m();
        let (g, d) = (disc.gap.m(), disc.thickness.m());
        let n = disc.count;
        let stack_height = f64::from(2 * n - 1) * d + f64::from(2 * n) * g;
        let level = stack_height.max(c.window_height.m() + 2.0 * c.bobbin_wall.m());
        let tp = h.end_plate_thickness.m();
        let z_level = tp;
        let z_top = tp + level;
        let z_stack0 = z_level + 0.5 * (level - stack_height);
        Self {
            r_s: spec.shaft.radius.m(),
            r_out,
            shell_in: r_out - h.case_thickness.m(),
            r1: disc.inner_radius.m(),
            r2: disc.outer_radius.m(),
            level,
            z_level,
            z_top,
            z_end: z_top + tp,
            z_stack0,
            z_stack1: z_stack0 + stack_height,
        }
    }
}

/// Builds a disc-family brake; returns its axial length.
pub(super) fn disc_unit(spec: &BrakeSpec, disc: &Disc, b: &mut Builder) -> f64 {
    let s = Stations::of(spec, disc);
    static_circuit(spec, &s, b);
    coils(spec, &s, b);
    stack(spec, disc, &s, b);
    s.z_end
}

/// Shaft, case shell, the two end plates and, where the level is taller than the stack, the steel
/// poles above and below it.
fn static_circuit(spec: &BrakeSpec, s: &Stations, b: &mut Builder) {
    let m = &spec.materials;
    let steel = |b: &mut Builder, name: &str, rect: Rect| {
        b.add(format!("unit1.{name}"), &m.flux_path, PartKind::FluxPath, vec![rect], Some(0), None);
    };
    b.add(
        "shaft".into(),
        &m.shaft,
        PartKind::Shaft,
        vec![Rect::new(0.0, s.r_s, 0.0, s.z_end)],
        Some(0),
        Some(Direction::Both),
    );
    steel(b, "case_shell", Rect::new(s.shell_in, s.r_out, 0.0, s.z_end));
    // End plates span from the shaft clearance to the shell.
    steel(b, "lower_plate", Rect::new(s.r_s, s.shell_in, 0.0, s.z_level));
    steel(b, "upper_plate", Rect::new(s.r_s, s.shell_in, s.z_top, s.z_end));
    if s.z_stack0 > s.z_level + 1e-12 {
        steel(b, "lower_pole", Rect::new(s.r1, s.r2, s.z_level, s.z_stack0));
        steel(b, "upper_pole", Rect::new(s.r1, s.r2, s.z_stack1, s.z_top));
    }
}

/// The inner coil (with the steel core ring it winds around) and/or the outer coil, centred in the
/// level.
fn coils(spec: &BrakeSpec, s: &Stations, b: &mut Builder) {
    let m = &spec.materials;
    let c = &spec.coil;
    let bw = c.bobbin_wall.m();
    let inner = matches!(c.placement, CoilPlacement::Inner | CoilPlacement::TwoSided);
    let outer = matches!(c.placement, CoilPlacement::Outer | CoilPlacement::TwoSided);
    let z0 = s.z_level + 0.5 * (s.level - c.window_height.m());
    let z1 = s.z_level + 0.5 * (s.level + c.window_height.m());
    if inner {
        let core_out = s.r_s + spec.housing.inner_case_thickness.m();
        b.add(
            "unit1.core_ring".into(),
            &m.flux_path,
            PartKind::FluxPath,
            vec![Rect::new(s.r_s, core_out, s.z_level, s.z_top)],
            Some(0),
            None,
        );
        let rect = Rect::new(s.r1 - bw - c.window_width.m(), s.r1 - bw, z0, z1);
        let tag =
            b.add("unit1.inner_coil".into(), &m.coil, PartKind::Coil, vec![rect], Some(0), None);
        b.coils.push(CoilInfo { tag, unit: 0, rect, turns: spec.turns(), current_sign: 1.0 });
    }
    if outer {
        let rect = Rect::new(s.r2 + bw, s.r2 + bw + c.window_width.m(), z0, z1);
        let tag =
            b.add("unit1.outer_coil".into(), &m.coil, PartKind::Coil, vec![rect], Some(0), None);
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
}

/// The stack from the bottom: gap, rotating disc, gap, (static disc, gap, rotating disc, gap)...
fn stack(spec: &BrakeSpec, disc: &Disc, s: &Stations, b: &mut Builder) {
    let m = &spec.materials;
    let (g, d) = (disc.gap.m(), disc.thickness.m());
    let gaps = 2 * disc.count;
    let mut z = s.z_stack0;
    for k in 0..gaps {
        let rect = Rect::new(s.r1, s.r2, z, z + g);
        let tag = b.add(
            format!("unit1.gap{}", k + 1),
            &m.fluid,
            PartKind::Fluid,
            vec![rect],
            Some(0),
            None,
        );
        let walls = b.wall_tags();
        let zm = z + 0.5 * g;
        b.gaps.push(GapInfo {
            index: b.gaps.len(),
            index_in_unit: k as usize,
            unit: 0,
            tag,
            rect,
            orientation: GapOrientation::Annular,
            shear_radius_m: 0.5 * (s.r1 + s.r2),
            mean_radius_m: 0.5 * (s.r1 + s.r2),
            height_m: s.r2 - s.r1,
            width_m: g,
            // Even gaps lie below a rotating disc, odd gaps above one.
            rotating_wall: if k % 2 == 0 { RotatingWall::Outer } else { RotatingWall::Inner },
            direction: Direction::Both,
            sample_line: [[s.r1, zm], [s.r2, zm]],
            inner_wall_tag: walls.0,
            outer_wall_tag: walls.1,
        });
        z += g;
        if k + 1 < gaps {
            let rotating = k % 2 == 0;
            let name = if rotating {
                format!("unit1.rotor_disc{}", k / 2 + 1)
            } else {
                format!("unit1.static_disc{}", k / 2 + 1)
            };
            b.add(
                name,
                &m.flux_path,
                PartKind::FluxPath,
                vec![Rect::new(s.r1, s.r2, z, z + d)],
                Some(0),
                rotating.then_some(Direction::Both),
            );
            z += d;
        }
    }
}
