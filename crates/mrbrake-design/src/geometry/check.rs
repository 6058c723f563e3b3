//! The rules of a spec that need positions: the parts fit radially before assembly
//! ([`check_fit`]), then the assembled parts do not overlap, every fluid gap lies between a
//! rotating and a static wall, and the device fits its envelope ([`check_assembled`]). Both report
//! through the spec's one validation ([`BrakeSpec::validate`]).

use super::{BrakeGeometry, GapInfo, GapOrientation, PartKind, Region};
use crate::spec::{BrakeSpec, CoilPlacement, Disc, Drum, Problems, WorkingSurfaces, fmt_mm};

/// Radial fit rules, each naming the field to change and the allowed range.
pub(crate) fn check_fit(spec: &BrakeSpec, p: &mut Problems) {
    match spec.configuration.surfaces() {
        WorkingSurfaces::Drums(drum) => check_drum_fit(spec, drum, p),
        WorkingSurfaces::Discs(disc) => check_disc_fit(spec, disc, p),
    }
}

/// Core inside the stack, stack inside the case, coil window between core and case shell.
fn check_drum_fit(spec: &BrakeSpec, d: &Drum, p: &mut Problems) {
    let h = &spec.housing;
    let c = &spec.coil;
    let r_s = spec.shaft.radius.m();
    let r_out = h.outer_radius.m();
    let shell_in = r_out - h.case_thickness.m();
    let b = c.bobbin_wall.m();
    let cw = c.window_width.m();
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
            format!("{} does not fit between the core (r = {}) and the case shell (r = {}) with two bobbin walls: {}", fmt_mm(cw), fmt_mm(d.r0.m()), fmt_mm(shell_in), allowed_window(shell_in - d.r0.m() - 2.0 * b, b, "increase housing.outer_radius or reduce drum.r0")),
        );
    }
}

/// Discs outside the shaft, discs (and an outer coil) inside the case shell, an inner coil between
/// the core ring and the discs.
fn check_disc_fit(spec: &BrakeSpec, d: &Disc, p: &mut Problems) {
    let h = &spec.housing;
    let c = &spec.coil;
    let r_s = spec.shaft.radius.m();
    let r_out = h.outer_radius.m();
    let shell_in = r_out - h.case_thickness.m();
    let b = c.bobbin_wall.m();
    let cw = c.window_width.m();
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
                format!("{} does not fit the inner coil between the core ring (r = {}) and disc.inner_radius = {} with two bobbin walls: {}", fmt_mm(cw), fmt_mm(core_out), fmt_mm(r1), allowed_window(r1 - core_out - 2.0 * b, b, "increase disc.inner_radius or reduce housing.inner_case_thickness")),
            );
        }
    }
}

/// The allowed window width: "allowed ≤ limit", or, when the two bobbin walls (each `wall_m`)
/// leave no room at all, that no width fits and `remedy`.
fn allowed_window(limit_m: f64, wall_m: f64, remedy: &str) -> String {
    if limit_m > 0.0 {
        format!("allowed ≤ {}", fmt_mm(limit_m))
    } else {
        format!(
            "no width fits, the two bobbin walls of coil.bobbin_wall = {} already take the room; {remedy}",
            fmt_mm(wall_m)
        )
    }
}

/// The rules on the assembled parts: no overlaps, every gap between a rotating and a static wall,
/// the device inside its envelope.
pub(crate) fn check_assembled(spec: &BrakeSpec, g: &BrakeGeometry, p: &mut Problems) {
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
    let field = if spec.configuration.is_drum() { "drum.gap" } else { "disc.gap" };
    for gap in &g.gaps {
        match (wall_region(g, gap, true), wall_region(g, gap, false)) {
            (Some(a), Some(b)) if a.rotates.is_some() != b.rotates.is_some() => {}
            _ => p.error(
                field,
                format!(
                    "gap {} (unit {}) is not a fluid layer between a rotating and a static wall",
                    gap.index_in_unit + 1,
                    gap.unit + 1
                ),
            ),
        }
    }
    check_envelope(spec, g, p);
}

/// The part just beyond the gap's inner (smaller r or z) or outer wall.
fn wall_region<'g>(g: &'g BrakeGeometry, gap: &GapInfo, inner: bool) -> Option<&'g Region> {
    let r = gap.rect;
    let eps = 1e-7;
    let point = match (gap.orientation, inner) {
        (GapOrientation::Cylindrical, true) => [r.r0 - eps, 0.5 * (r.z0 + r.z1)],
        (GapOrientation::Cylindrical, false) => [r.r1 + eps, 0.5 * (r.z0 + r.z1)],
        (GapOrientation::Annular, true) => [0.5 * (r.r0 + r.r1), r.z0 - eps],
        (GapOrientation::Annular, false) => [0.5 * (r.r0 + r.r1), r.z1 + eps],
    };
    g.regions.iter().find(|reg| reg.rects.iter().any(|rc| rc.contains(point)))
}

fn check_envelope(spec: &BrakeSpec, g: &BrakeGeometry, p: &mut Problems) {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Issue 19: a window limit at or below zero said "allowed ≤ -0 mm".
    #[test]
    fn no_room_says_so_instead_of_a_negative_limit() {
        assert_eq!(allowed_window(2.5e-3, 1e-3, "x"), "allowed ≤ 2.5000 mm");
        for limit in [0.0, -0.0, -1e-13, -2e-3] {
            let text = allowed_window(limit, 1e-3, "increase housing.outer_radius");
            assert!(text.starts_with("no width fits"), "{text}");
            assert!(text.contains("coil.bobbin_wall = 1 mm") && !text.contains('-'), "{text}");
        }
        assert_eq!(fmt_mm(-1e-12), "0 mm");
        assert_eq!(fmt_mm(-2e-3), "-2 mm");
    }
}
