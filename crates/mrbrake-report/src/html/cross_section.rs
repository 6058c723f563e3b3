//! The cross-section drawing of a brake geometry: the half-section in the r–z plane (the axis on
//! the left), every part filled by its kind, rotating parts hatched, each part numbered where it is
//! large enough to carry a number, with mm axes; and the legend table naming each part and its
//! material. Written directly as SVG (rectangles only), so it is exact and deterministic.

use std::fmt::Write as _;

use mrbrake_design::geometry::{BrakeGeometry, PartKind, Rect};

use super::writer::{Cell, Table, escape};

/// Largest drawing width and height of the section itself, px.
const MAX_W: f64 = 520.0;
const MAX_H: f64 = 640.0;
/// Margins for the axes, px.
const LEFT: f64 = 56.0;
const BOTTOM: f64 = 44.0;
const TOP: f64 = 16.0;
const RIGHT: f64 = 16.0;

/// Fill colour of a part kind (steel grey, aluminium, stainless, copper, fluid blue, spacer).
fn fill(kind: PartKind) -> &'static str {
    match kind {
        PartKind::FluxPath => "#8f9aa6",
        PartKind::NonMagnetic => "#dfe3e8",
        PartKind::Bobbin => "#b9a7d6",
        PartKind::Shaft => "#59636e",
        PartKind::Coil => "#d4893a",
        PartKind::Fluid => "#1f78c8",
        PartKind::Spacer => "#e3d49b",
        PartKind::Air => "none",
    }
}

/// The kind in words.
pub fn kind_name(kind: PartKind) -> &'static str {
    match kind {
        PartKind::FluxPath => "flux path (steel)",
        PartKind::NonMagnetic => "non-magnetic structure",
        PartKind::Bobbin => "coil bobbin",
        PartKind::Shaft => "shaft",
        PartKind::Coil => "coil",
        PartKind::Fluid => "MR-fluid gap",
        PartKind::Spacer => "spacer",
        PartKind::Air => "air",
    }
}

/// The parts drawn: every region but the air, numbered from 1 in the geometry's order.
fn parts(
    geometry: &BrakeGeometry,
) -> impl Iterator<Item = (usize, &mrbrake_design::geometry::Region)> {
    geometry.regions.iter().filter(|r| r.kind != PartKind::Air).enumerate().map(|(k, r)| (k + 1, r))
}

/// The drawing as an SVG element; `id` prefixes the element ids (hatch pattern) so that several
/// drawings can share a page.
pub fn svg(geometry: &BrakeGeometry, id: &str, title: &str) -> String {
    let d = geometry.device;
    let (w_mm, h_mm) = ((d.r1 - d.r0.min(0.0)) * 1e3, (d.z1 - d.z0) * 1e3);
    let s = (MAX_W / w_mm).min(MAX_H / h_mm);
    let (width, height) = (LEFT + w_mm * s + RIGHT, TOP + h_mm * s + BOTTOM);
    let x = |r: f64| LEFT + r * 1e3 * s;
    let y = |z: f64| TOP + (d.z1 - z) * 1e3 * s;
    let mut out = String::new();
    let _ = write!(
        out,
        "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 {width:.0} {height:.0}\" \
         width=\"{width:.0}\" height=\"{height:.0}\" class=\"figure\" role=\"img\" aria-label=\"{}\">",
        escape(title)
    );
    let _ = write!(
        out,
        "<defs><pattern id=\"{id}-hatch\" width=\"6\" height=\"6\" patternUnits=\"userSpaceOnUse\" \
         patternTransform=\"rotate(45)\"><line x1=\"0\" y1=\"0\" x2=\"0\" y2=\"6\" stroke=\"#000\" \
         stroke-opacity=\"0.35\" stroke-width=\"1.2\"/></pattern></defs>"
    );
    let _ = write!(
        out,
        "<rect x=\"0\" y=\"0\" width=\"{width:.0}\" height=\"{height:.0}\" fill=\"#fff\"/>"
    );
    for (_, region) in parts(geometry) {
        for rect in &region.rects {
            let (rx, ry) = (x(rect.r0), y(rect.z1));
            let (rw, rh) = ((rect.r1 - rect.r0) * 1e3 * s, (rect.z1 - rect.z0) * 1e3 * s);
            let tip = format!("{} ({})", region.name, region.material);
            let _ = write!(
                out,
                "<rect x=\"{rx:.2}\" y=\"{ry:.2}\" width=\"{rw:.2}\" height=\"{rh:.2}\" fill=\"{}\" \
                 stroke=\"#222\" stroke-width=\"0.6\"><title>{}</title></rect>",
                fill(region.kind),
                escape(&tip)
            );
            if region.rotates.is_some() {
                let _ = write!(
                    out,
                    "<rect x=\"{rx:.2}\" y=\"{ry:.2}\" width=\"{rw:.2}\" height=\"{rh:.2}\" \
                     fill=\"url(#{id}-hatch)\" stroke=\"none\"/>"
                );
            }
        }
    }
    numbers(&mut out, geometry, &x, &y, s);
    axes(&mut out, &d, &x, &y, width, height);
    out.push_str("</svg>");
    out
}

/// Each part's number at the centre of its largest rectangle, when that is large enough.
fn numbers(
    out: &mut String,
    g: &BrakeGeometry,
    x: &dyn Fn(f64) -> f64,
    y: &dyn Fn(f64) -> f64,
    s: f64,
) {
    for (k, region) in parts(g) {
        let Some(rect) = region.rects.iter().max_by(|a, b| a.area_m2().total_cmp(&b.area_m2()))
        else {
            continue;
        };
        let (rw, rh) = ((rect.r1 - rect.r0) * 1e3 * s, (rect.z1 - rect.z0) * 1e3 * s);
        if rw < 16.0 || rh < 13.0 {
            continue;
        }
        let [rc, zc] = rect.centre();
        let colour =
            if matches!(region.kind, PartKind::Shaft | PartKind::Fluid) { "#fff" } else { "#000" };
        let _ = write!(
            out,
            "<text x=\"{:.1}\" y=\"{:.1}\" font-size=\"11\" font-family=\"sans-serif\" \
             text-anchor=\"middle\" dominant-baseline=\"central\" fill=\"{colour}\">{k}</text>",
            x(rc),
            y(zc)
        );
    }
}

/// The axis of symmetry and the r and z axes with ticks every 10 mm (5 mm for small devices).
fn axes(
    out: &mut String,
    d: &Rect,
    x: &dyn Fn(f64) -> f64,
    y: &dyn Fn(f64) -> f64,
    w: f64,
    h: f64,
) {
    let font = "font-size=\"12\" font-family=\"sans-serif\" fill=\"#000\"";
    let (bottom, left) = (h - BOTTOM, LEFT);
    let _ = write!(
        out,
        "<line x1=\"{left}\" y1=\"{:.1}\" x2=\"{left}\" y2=\"{:.1}\" stroke=\"#c00\" stroke-width=\"1\" \
         stroke-dasharray=\"8 3 2 3\"/>",
        TOP - 8.0,
        bottom + 4.0
    );
    let span_mm = ((d.r1 - d.r0.min(0.0)).max(d.z1 - d.z0)) * 1e3;
    let step = if span_mm > 60.0 { 10.0 } else { 5.0 };
    let mut r = 0.0;
    while r <= d.r1 * 1e3 + 1e-9 {
        let px = x(r / 1e3);
        let _ = write!(
            out,
            "<line x1=\"{px:.1}\" y1=\"{bottom:.1}\" x2=\"{px:.1}\" y2=\"{:.1}\" stroke=\"#000\"/>\
             <text x=\"{px:.1}\" y=\"{:.1}\" text-anchor=\"middle\" {font}>{r:.0}</text>",
            bottom + 5.0,
            bottom + 18.0
        );
        r += step;
    }
    let mut z = (d.z0 * 1e3 / step).ceil() * step;
    while z <= d.z1 * 1e3 + 1e-9 {
        let py = y(z / 1e3);
        let _ = write!(
            out,
            "<line x1=\"{:.1}\" y1=\"{py:.1}\" x2=\"{left:.1}\" y2=\"{py:.1}\" stroke=\"#000\"/>\
             <text x=\"{:.1}\" y=\"{py:.1}\" text-anchor=\"end\" dominant-baseline=\"central\" {font}>{z:.0}</text>",
            left - 5.0,
            left - 8.0
        );
        z += step;
    }
    let _ = write!(
        out,
        "<text x=\"{:.1}\" y=\"{:.1}\" text-anchor=\"middle\" {font}>r [mm] (axis of symmetry dashed)</text>\
         <text x=\"14\" y=\"{:.1}\" text-anchor=\"middle\" transform=\"rotate(-90 14 {:.1})\" {font}>z [mm]</text>",
        (left + w - RIGHT) / 2.0,
        h - 6.0,
        (TOP + bottom) / 2.0,
        (TOP + bottom) / 2.0
    );
}

/// The legend: one row per part with its number, colour, name, kind, material and motion.
pub fn legend(geometry: &BrakeGeometry) -> Table {
    let mut t = Table::new(
        "Parts of the cross-section (hatched: rotates with the shaft)",
        &["#", "part", "kind", "material", "rotates", "volume [cm³]"],
    );
    for (k, r) in parts(geometry) {
        let rotates = match r.rotates {
            None => "no".to_string(),
            Some(dir) => format!("yes ({dir:?})").to_lowercase(),
        };
        t.row(vec![
            Cell::text(k.to_string()),
            Cell::text(r.name.clone()),
            Cell::text(kind_name(r.kind)),
            Cell::text(r.material.clone()),
            Cell::text(rotates),
            Cell::number(r.volume_m3() * 1e6, 2),
        ]);
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use mrbrake_design::geometry::build;
    use mrbrake_design::spec::default_spec;

    #[test]
    fn every_part_is_drawn_and_listed() {
        let g = build(&default_spec()).unwrap();
        let drawing = svg(&g, "x", "section");
        let solid = g.regions.iter().filter(|r| r.kind != PartKind::Air);
        let rects: usize = solid.clone().map(|r| r.rects.len()).sum();
        assert_eq!(drawing.matches("<title>").count(), rects);
        assert!(drawing.contains("url(#x-hatch)"));
        assert_eq!(legend(&g).rows.len(), solid.count());
        assert!(drawing.starts_with("<svg ") && drawing.ends_with("</svg>"));
    }
}
