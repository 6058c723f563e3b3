//! Field map of an axisymmetric magnetostatic solution: |B| as colour on the (r, z) triangles, flux
//! lines as contours of the flux function `ψ = r A_phi`, and region outlines; and the same drawing
//! for any nodal scalar ([`ScalarMap`], e.g. a temperature with its isotherms).
//!
//! In axisymmetry the flux through the disc of radius r at height z is `Φ = 2π r A_phi`, so B is
//! tangent to the level lines of `ψ = r A_phi` and equally spaced levels of ψ give flux lines that
//! carry equal flux (their density shows |B|). Contours are traced triangle by triangle on the
//! piecewise-linear interpolant of ψ ("marching triangles"). The map knows no FEM types: it takes
//! plain node, triangle and value arrays. SVG by default, PNG when the file name ends in `.png`.

use std::collections::HashMap;
use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::ReportError;
use crate::chart::{Picture, render_svg, save_picture};

/// The data of a field map.
#[derive(Debug, Clone, Copy)]
pub struct FieldMap<'a> {
    /// Title drawn above the map.
    pub title: &'a str,
    /// Node coordinates `[r, z]` (m).
    pub nodes: &'a [[f64; 2]],
    /// Triangles (node indices).
    pub triangles: &'a [[usize; 3]],
    /// Region tag per triangle (outlines are drawn where it changes).
    pub region_tags: &'a [u32],
    /// |B| per triangle (T).
    pub b_abs_t: &'a [f64],
    /// Flux function `r A_phi` per node (Wb/rad).
    pub flux_function: &'a [f64],
    /// Number of flux lines.
    pub flux_lines: usize,
}

/// Image size in pixels for a map: width fixed, height from the aspect ratio of the mesh (plus the
/// colour bar and margins).
fn size_for(nodes: &[[f64; 2]]) -> (u32, u32) {
    let (lo, hi) = bounds(nodes);
    let aspect = ((hi[1] - lo[1]) / (hi[0] - lo[0]).max(1e-300)).clamp(0.2, 5.0);
    let plot_w = 640.0;
    (plot_w as u32 + 170, (plot_w * aspect) as u32 + 110)
}

fn bounds(nodes: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in nodes {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// Perceptually ordered colour map (an approximation of matplotlib's "viridis" by 5 anchors).
fn colour(t: f64) -> RGBColor {
    const ANCHORS: [(f64, f64, f64); 5] = [
        (68.0, 1.0, 84.0),
        (59.0, 82.0, 139.0),
        (33.0, 145.0, 140.0),
        (94.0, 201.0, 98.0),
        (253.0, 231.0, 37.0),
    ];
    let t = if t.is_finite() { t.clamp(0.0, 1.0) } else { 0.0 };
    let x = t * 4.0;
    let i = (x.floor() as usize).min(3);
    let f = x - i as f64;
    let (a, b) = (ANCHORS[i], ANCHORS[i + 1]);
    let mix = |u: f64, v: f64| (u + f * (v - u)).round() as u8;
    RGBColor(mix(a.0, b.0), mix(a.1, b.1), mix(a.2, b.2))
}

fn check(map: &FieldMap<'_>) -> Result<(), ReportError> {
    let n = map.nodes.len();
    if map.triangles.is_empty() || n == 0 {
        return Err(ReportError::Data("field map: empty mesh".into()));
    }
    if map.b_abs_t.len() != map.triangles.len()
        || map.region_tags.len() != map.triangles.len()
        || map.flux_function.len() != n
    {
        return Err(ReportError::Data(format!(
            "field map: {} triangles but {} |B| values and {} tags; {n} nodes but {} flux values",
            map.triangles.len(),
            map.b_abs_t.len(),
            map.region_tags.len(),
            map.flux_function.len()
        )));
    }
    if map.triangles.iter().any(|t| t.iter().any(|&v| v >= n)) {
        return Err(ReportError::Data("field map: a triangle references a missing node".into()));
    }
    Ok(())
}

/// Segments `[(r, z), (r, z)]` of the contour `ψ = level` in every triangle.
pub fn contour_segments(
    nodes: &[[f64; 2]],
    triangles: &[[usize; 3]],
    psi: &[f64],
    level: f64,
) -> Vec<[(f64, f64); 2]> {
    let mut segments = Vec::new();
    for tri in triangles {
        let mut crossing = Vec::with_capacity(2);
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let (fa, fb) = (psi[a] - level, psi[b] - level);
            if (fa < 0.0) != (fb < 0.0) {
                let s = fa / (fa - fb);
                crossing.push((
                    nodes[a][0] + s * (nodes[b][0] - nodes[a][0]),
                    nodes[a][1] + s * (nodes[b][1] - nodes[a][1]),
                ));
            }
        }
        if crossing.len() == 2 {
            segments.push([crossing[0], crossing[1]]);
        }
    }
    segments
}

/// Edges shared by triangles of different regions (in triangle order), then the boundary edges
/// (sorted).
fn outline_edges(triangles: &[[usize; 3]], region_tags: &[u32]) -> Vec<[usize; 2]> {
    let mut seen: HashMap<(usize, usize), (u32, bool)> =
        HashMap::with_capacity(3 * triangles.len() / 2);
    let mut outline = Vec::new();
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let key = (a.min(b), a.max(b));
            match seen.get_mut(&key) {
                Some(entry) => {
                    entry.1 = true;
                    if entry.0 != region_tags[t] {
                        outline.push([a, b]);
                    }
                }
                None => {
                    seen.insert(key, (region_tags[t], false));
                }
            }
        }
    }
    // Boundary edges in node order: the hash map's order changes from run to run, and the SVG
    // should not.
    let mut boundary: Vec<[usize; 2]> =
        seen.iter().filter(|(_, v)| !v.1).map(|(k, _)| [k.0, k.1]).collect();
    boundary.sort_unstable();
    outline.extend(boundary);
    outline
}

impl Picture for FieldMap<'_> {
    fn size(&self) -> (u32, u32) {
        size_for(self.nodes)
    }

    /// The map on the left (|B| colours, flux lines, region outlines), its colour bar on the right.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        let b_max =
            self.b_abs_t.iter().cloned().filter(|b| b.is_finite()).fold(0.0, f64::max).max(1e-12);
        let layers = Layers {
            title: self.title,
            nodes: self.nodes,
            triangles: self.triangles,
            region_tags: self.region_tags,
            fraction: &|t| self.b_abs_t[t] / b_max,
            contour_values: self.flux_function,
            contour_levels: flux_levels(self.flux_function, self.flux_lines),
        };
        draw_with_bar(root, &layers, (0.0, b_max), "|B| [T]")
    }
}

/// What one coloured triangle map draws: triangles coloured by a fraction in [0, 1], contour lines
/// of a nodal function at given levels, region outlines.
struct Layers<'a> {
    title: &'a str,
    nodes: &'a [[f64; 2]],
    triangles: &'a [[usize; 3]],
    region_tags: &'a [u32],
    /// The colour-bar fraction of triangle `t`.
    fraction: &'a dyn Fn(usize) -> f64,
    /// Nodal values whose level lines are drawn.
    contour_values: &'a [f64],
    contour_levels: Vec<f64>,
}

/// The map on the left, its colour bar (from `range.0` to `range.1`, captioned `label`) on the
/// right.
fn draw_with_bar<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    layers: &Layers<'_>,
    range: (f64, f64),
    label: &str,
) -> Result<(), ReportError> {
    crate::chart::ensure_font();
    root.fill(&WHITE).map_err(backend)?;
    let (width, _) = root.dim_in_pixel();
    let (plot_area, bar_area) = root.split_horizontally(width.saturating_sub(150));
    draw_map(layers, &plot_area)?;
    draw_colour_bar(&bar_area, range, label)
}

/// A plotters drawing error as a [`ReportError`].
fn backend<E: std::error::Error + Send + Sync>(e: DrawingAreaErrorKind<E>) -> ReportError {
    ReportError::Backend(e.to_string())
}

/// Millimetres per metre: the map's axes are in mm.
const MM: f64 = 1e3;

/// The (r, z) map in mm: every triangle in the colour of its fraction, the contour lines in white
/// and the region outlines in black.
fn draw_map<DB: DrawingBackend>(
    map: &Layers<'_>,
    area: &DrawingArea<DB, Shift>,
) -> Result<(), ReportError> {
    let (lo, hi) = bounds(map.nodes);
    let mut chart = ChartBuilder::on(area)
        .caption(map.title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(55)
        .build_cartesian_2d(lo[0] * MM..hi[0] * MM, lo[1] * MM..hi[1] * MM)
        .map_err(backend)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_desc("r [mm]")
        .y_desc("z [mm]")
        .label_style(("sans-serif", 13))
        .draw()
        .map_err(backend)?;
    let in_mm = |v: usize| (map.nodes[v][0] * MM, map.nodes[v][1] * MM);
    chart
        .draw_series(map.triangles.iter().enumerate().map(|(t, tri)| {
            let points: Vec<(f64, f64)> = tri.iter().map(|&v| in_mm(v)).collect();
            let c = colour((map.fraction)(t));
            // Stroke with the fill colour so no hairline gaps show between triangles.
            Polygon::new(points, c.filled().stroke_width(1))
        }))
        .map_err(backend)?;
    for &level in &map.contour_levels {
        let segments = contour_segments(map.nodes, map.triangles, map.contour_values, level);
        chart
            .draw_series(segments.iter().map(|s| {
                PathElement::new(
                    vec![(s[0].0 * MM, s[0].1 * MM), (s[1].0 * MM, s[1].1 * MM)],
                    WHITE.mix(0.9).stroke_width(1),
                )
            }))
            .map_err(backend)?;
    }
    chart
        .draw_series(
            outline_edges(map.triangles, map.region_tags)
                .iter()
                .map(|e| PathElement::new(vec![in_mm(e[0]), in_mm(e[1])], BLACK.stroke_width(1))),
        )
        .map_err(backend)?;
    Ok(())
}

/// `count` levels of the flux function, equally spaced and centred in its range, so that the
/// lines carry equal flux; none when the function is constant.
fn flux_levels(psi: &[f64], count: usize) -> Vec<f64> {
    let (psi_lo, psi_hi) =
        psi.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    if psi_hi > psi_lo && count > 0 {
        (1..=count).map(|k| psi_lo + (psi_hi - psi_lo) * (k as f64 - 0.5) / count as f64).collect()
    } else {
        Vec::new()
    }
}

/// The colour bar from `range.0` to `range.1`, in 64 steps, captioned `label`.
fn draw_colour_bar<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    range: (f64, f64),
    label: &str,
) -> Result<(), ReportError> {
    let (lo, hi) = range;
    let mut bar = ChartBuilder::on(area)
        .margin_top(40)
        .margin_bottom(50)
        .margin_right(60)
        .y_label_area_size(0)
        .right_y_label_area_size(50)
        .caption(label, ("sans-serif", 14))
        .build_cartesian_2d(0.0..1.0, lo..hi)
        .map_err(backend)?;
    bar.configure_mesh()
        .disable_mesh()
        .disable_x_axis()
        .y_labels(6)
        .label_style(("sans-serif", 12))
        .draw()
        .map_err(backend)?;
    let steps = 64;
    let at = |i: usize| lo + (hi - lo) * i as f64 / steps as f64;
    bar.draw_series((0..steps).map(|i| {
        Rectangle::new(
            [(0.0, at(i)), (1.0, at(i + 1))],
            colour((i as f64 + 0.5) / steps as f64).filled(),
        )
    }))
    .map_err(backend)?;
    Ok(())
}

/// Renders the map as an SVG document.
pub fn field_map_svg(map: &FieldMap<'_>) -> Result<String, ReportError> {
    check(map)?;
    render_svg(map)
}

/// Renders the map as a PNG image in memory, with its size in pixels.
pub fn field_map_png(map: &FieldMap<'_>) -> Result<(Vec<u8>, (u32, u32)), ReportError> {
    check(map)?;
    Ok((crate::chart::render_png(map)?, map.size()))
}

/// Writes the map to `path` atomically: PNG if the name ends in `.png`, SVG otherwise.
pub fn save_field_map(map: &FieldMap<'_>, path: &Path) -> Result<(), ReportError> {
    check(map)?;
    save_picture(map, path)
}

/// A nodal scalar field on the (r, z) triangles (e.g. a temperature): triangles coloured by the
/// mean of their nodes' values over the field's range, level lines (isotherms) equally spaced in
/// that range, region outlines, and a colour bar captioned `label`.
#[derive(Debug, Clone, Copy)]
pub struct ScalarMap<'a> {
    /// Title drawn above the map.
    pub title: &'a str,
    /// Node coordinates `[r, z]` (m).
    pub nodes: &'a [[f64; 2]],
    /// Triangles (node indices).
    pub triangles: &'a [[usize; 3]],
    /// Region tag per triangle.
    pub region_tags: &'a [u32],
    /// One value per node.
    pub values: &'a [f64],
    /// Caption of the colour bar, with the unit (e.g. `T [°C]`).
    pub label: &'a str,
    /// Number of level lines.
    pub levels: usize,
}

impl ScalarMap<'_> {
    fn range(&self) -> (f64, f64) {
        let (lo, hi) = self
            .values
            .iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &v| (a.min(v), b.max(v)));
        if hi > lo { (lo, hi) } else { (lo - 0.5, lo + 0.5) }
    }

    fn check(&self) -> Result<(), ReportError> {
        let n = self.nodes.len();
        if self.triangles.is_empty() || n == 0 {
            return Err(ReportError::Data("scalar map: empty mesh".into()));
        }
        if self.values.len() != n || self.region_tags.len() != self.triangles.len() {
            return Err(ReportError::Data(format!(
                "scalar map: {n} nodes but {} values; {} triangles but {} tags",
                self.values.len(),
                self.triangles.len(),
                self.region_tags.len()
            )));
        }
        if self.triangles.iter().any(|t| t.iter().any(|&v| v >= n)) {
            return Err(ReportError::Data(
                "scalar map: a triangle references a missing node".into(),
            ));
        }
        if !self.values.iter().any(|v| v.is_finite()) {
            return Err(ReportError::Data("scalar map: no finite value".into()));
        }
        Ok(())
    }
}

impl Picture for ScalarMap<'_> {
    fn size(&self) -> (u32, u32) {
        size_for(self.nodes)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), ReportError> {
        let (lo, hi) = self.range();
        let mean = |t: usize| self.triangles[t].iter().map(|&v| self.values[v]).sum::<f64>() / 3.0;
        let layers = Layers {
            title: self.title,
            nodes: self.nodes,
            triangles: self.triangles,
            region_tags: self.region_tags,
            fraction: &|t| (mean(t) - lo) / (hi - lo),
            contour_values: self.values,
            contour_levels: flux_levels(self.values, self.levels),
        };
        draw_with_bar(root, &layers, (lo, hi), self.label)
    }
}

/// Renders a scalar map as an SVG document.
pub fn scalar_map_svg(map: &ScalarMap<'_>) -> Result<String, ReportError> {
    map.check()?;
    render_svg(map)
}

/// Writes a scalar map to `path` atomically: PNG if the name ends in `.png`, SVG otherwise.
pub fn save_scalar_map(map: &ScalarMap<'_>, path: &Path) -> Result<(), ReportError> {
    map.check()?;
    save_picture(map, path)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> (Vec<[f64; 2]>, Vec<[usize; 3]>) {
        (vec![[0.0, 0.0], [0.01, 0.0], [0.01, 0.01], [0.0, 0.01]], vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn contour_of_a_linear_function_is_a_straight_line() {
        let (nodes, tris) = square();
        let psi: Vec<f64> = nodes.iter().map(|p| p[0]).collect();
        let segments = contour_segments(&nodes, &tris, &psi, 0.004);
        assert_eq!(segments.len(), 2);
        for s in segments {
            assert!((s[0].0 - 0.004).abs() < 1e-12 && (s[1].0 - 0.004).abs() < 1e-12);
        }
    }

    #[test]
    fn renders_svg_and_rejects_mismatched_data() {
        let (nodes, tris) = square();
        let psi = [0.0, 1.0, 2.0, 1.0];
        let map = FieldMap {
            title: "test",
            nodes: &nodes,
            triangles: &tris,
            region_tags: &[1, 2],
            b_abs_t: &[0.5, 1.0],
            flux_function: &psi,
            flux_lines: 5,
        };
        let svg = field_map_svg(&map).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("|B| [T]"));
        let bad = FieldMap { b_abs_t: &[0.5], ..map };
        assert!(field_map_svg(&bad).is_err());
    }

    /// The outline (and so the SVG) does not depend on the hash map's per-run order.
    #[test]
    fn the_same_map_renders_the_same_svg() {
        let n = 6;
        let nodes: Vec<[f64; 2]> =
            (0..=n).flat_map(|j| (0..=n).map(move |i| [i as f64, j as f64])).collect();
        let id = |i: usize, j: usize| j * (n + 1) + i;
        let mut triangles = Vec::new();
        for j in 0..n {
            for i in 0..n {
                triangles.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                triangles.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let tags: Vec<u32> = (0..triangles.len()).map(|t| u32::from(t % 5 == 0)).collect();
        let b: Vec<f64> = (0..triangles.len()).map(|t| t as f64 / 10.0).collect();
        let psi: Vec<f64> = nodes.iter().map(|p| p[0] * p[0]).collect();
        let map = FieldMap {
            title: "grid",
            nodes: &nodes,
            triangles: &triangles,
            region_tags: &tags,
            b_abs_t: &b,
            flux_function: &psi,
            flux_lines: 4,
        };
        let outline = outline_edges(map.triangles, map.region_tags);
        let boundary = &outline[outline.len() - 4 * n..];
        assert!(boundary.windows(2).all(|w| w[0] < w[1]), "{boundary:?}");
        let first = field_map_svg(&map).unwrap();
        for _ in 0..3 {
            assert!(field_map_svg(&map).unwrap() == first);
        }
    }

    #[test]
    fn scalar_map_renders_its_range_and_rejects_mismatched_data() {
        let (nodes, tris) = square();
        let values = [20.0, 40.0, 60.0, 40.0];
        let map = ScalarMap {
            title: "temperature",
            nodes: &nodes,
            triangles: &tris,
            region_tags: &[1, 2],
            values: &values,
            label: "T [°C]",
            levels: 3,
        };
        assert_eq!(map.range(), (20.0, 60.0));
        let svg = scalar_map_svg(&map).unwrap();
        assert!(svg.starts_with("<svg") && svg.contains("T [°C]"));
        assert!(scalar_map_svg(&ScalarMap { values: &values[..3], ..map }).is_err());
    }
}
