//! Region labels on a map: what each region is (steel, MR fluid, coil, non-magnetic, air), from
//! its part's role in the geometry ([`PartKind`]) and, for structural parts, its library
//! material, and where on the map its label goes.
//!
//! A structural part whose material is not in the library (e.g. a B-H curve from a CSV file) gets
//! no label rather than a guess.

use std::collections::{HashMap, HashSet};

use mrbrake_design::analysis::FieldRegion;
use mrbrake_design::geometry::PartKind;
use mrbrake_materials::MaterialKind;

use super::lines::{Point, Window};

/// What a region of the map is made of, as far as a reader of the picture cares.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RegionKind {
    /// Soft-magnetic steel (the flux path).
    Steel,
    /// MR fluid in the gaps.
    Fluid,
    /// The coil window.
    Coil,
    /// Non-magnetic solids (aluminium, stainless steel, spacer, shaft).
    NonMagnetic,
    /// The air around the device.
    Air,
}

impl RegionKind {
    /// The kind of a part with role `part` made of the library material `material`: air, coil,
    /// fluid and flux path by their role; the shaft, spacer and other structure by their
    /// material (a steel shaft carries flux); `None` for a structural part of a material the
    /// library does not know.
    pub fn of(part: PartKind, material: &str) -> Option<Self> {
        match part {
            PartKind::Air => return Some(Self::Air),
            PartKind::Coil => return Some(Self::Coil),
            PartKind::Fluid => return Some(Self::Fluid),
            PartKind::FluxPath => return Some(Self::Steel),
            PartKind::Shaft | PartKind::NonMagnetic | PartKind::Bobbin | PartKind::Spacer => {}
        }
        let material = material.trim().to_ascii_lowercase();
        let kind = mrbrake_materials::library::names()
            .into_iter()
            .find(|(known, _)| *known == material)
            .map(|(_, kind)| kind)?;
        Some(match kind {
            MaterialKind::Steel => Self::Steel,
            MaterialKind::MrFluid => Self::Fluid,
            MaterialKind::Linear => Self::NonMagnetic,
        })
    }

    /// The label drawn on the map (`None`: not labelled).
    pub fn label(self) -> Option<&'static str> {
        match self {
            Self::Steel => Some("steel"),
            Self::Fluid => Some("MR fluid gaps"),
            Self::Coil => Some("coil"),
            Self::NonMagnetic => Some("non-magnetic"),
            Self::Air => None,
        }
    }
}

/// A label on the map: its text, the point it names (m) and, when the region is too thin to
/// hold the text, where the text goes instead (joined to the point by a leader line).
#[derive(Debug, Clone, PartialEq)]
pub struct Label {
    /// The text.
    pub text: &'static str,
    /// The labelled point `(r, z)` (m).
    pub anchor: Point,
    /// Where the text sits when it is not on the anchor.
    pub moved_to: Option<Point>,
}

/// Candidate triangles examined per kind (a large region has thousands; a few hundred spread
/// over it find a roomy spot).
const CANDIDATES: usize = 300;

/// One label per labelled kind present in `window`, at the point of its regions farthest from
/// any other kind and from the window's edges; moved below (or above) the kind's extent when that point is closer than
/// `room_m` to another kind.
pub fn place(
    nodes: &[[f64; 2]],
    triangles: &[[usize; 3]],
    region_tags: &[u32],
    regions: &[FieldRegion],
    window: Window,
    room_m: f64,
) -> Vec<Label> {
    let kinds: HashMap<u32, RegionKind> = regions
        .iter()
        .filter_map(|r| Some((r.tag, RegionKind::of(r.kind, &r.material)?)))
        .collect();
    let kind_of: Vec<Option<RegionKind>> =
        region_tags.iter().map(|t| kinds.get(t).copied()).collect();
    let borders = border_nodes(triangles, &kind_of);
    let centroid = |t: &[usize; 3]| {
        let c = |k: usize| t.iter().map(|&v| nodes[v][k]).sum::<f64>() / 3.0;
        (c(0), c(1))
    };
    let inside = |p: Point| {
        let m = [0.03 * (window.1[0] - window.0[0]), 0.03 * (window.1[1] - window.0[1])];
        p.0 > window.0[0] + m[0]
            && p.0 < window.1[0] - m[0]
            && p.1 > window.0[1] + m[1]
            && p.1 < window.1[1] - m[1]
    };
    let mut labels = Vec::new();
    for kind in [RegionKind::Steel, RegionKind::Fluid, RegionKind::Coil, RegionKind::NonMagnetic] {
        let Some(text) = kind.label() else { continue };
        let mine: Vec<Point> = triangles
            .iter()
            .zip(&kind_of)
            .filter(|(_, k)| **k == Some(kind))
            .map(|(t, _)| centroid(t))
            .filter(|&p| inside(p))
            .collect();
        if mine.is_empty() {
            continue;
        }
        let border: Vec<Point> = borders
            .get(&kind)
            .map(|set| set.iter().map(|&v| (nodes[v][0], nodes[v][1])).collect())
            .unwrap_or_default();
        // Room around a point: to the nearest other kind and to the window's edges.
        let clearance = |p: Point| {
            let edges = (p.0 - window.0[0])
                .min(window.1[0] - p.0)
                .min(p.1 - window.0[1])
                .min(window.1[1] - p.1);
            border.iter().map(|b| (b.0 - p.0).hypot(b.1 - p.1)).fold(edges, f64::min)
        };
        let stride = mine.len().div_ceil(CANDIDATES).max(1);
        let candidates: Vec<(Point, f64)> =
            mine.iter().step_by(stride).map(|&p| (p, clearance(p))).collect();
        // Plenty of room: the label's half width (about 0.3 `room_m` per character at the
        // map's font) and half a room beyond it, at least twice the room a label needs.
        let half_width = 0.3 * text.len() as f64 * room_m;
        let (anchor, room) =
            roomiest(&candidates, &mine, (half_width + 0.5 * room_m).max(2.0 * room_m));
        let moved_to = (room < room_m).then(|| beside(&mine, anchor, window, room_m));
        labels.push(Label { text, anchor, moved_to });
    }
    labels
}

/// The candidate `(point, clearance)` for a label: among those with at least `plenty` of room,
/// the one nearest the centre of the kind's `points` (a label in the middle of its region reads
/// best); else the one with the most room.
fn roomiest(candidates: &[(Point, f64)], points: &[Point], plenty: f64) -> (Point, f64) {
    let n = points.len().max(1) as f64;
    let centre = points.iter().fold((0.0, 0.0), |c, p| (c.0 + p.0 / n, c.1 + p.1 / n));
    let off_centre = |p: Point| (p.0 - centre.0).hypot(p.1 - centre.1);
    let roomy = candidates
        .iter()
        .filter(|c| c.1 >= plenty)
        .min_by(|a, b| off_centre(a.0).total_cmp(&off_centre(b.0)));
    let most = candidates.iter().max_by(|a, b| a.1.total_cmp(&b.1));
    roomy.or(most).copied().unwrap_or(((0.0, 0.0), 0.0))
}

/// Where the label of a thin kind goes: centred under its extent `points`, or over it when there
/// is no room below in `window`.
fn beside(points: &[Point], anchor: Point, window: Window, room_m: f64) -> Point {
    let (z_lo, z_hi) = points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| (lo.min(p.1), hi.max(p.1)));
    let below = z_lo - 1.6 * room_m;
    let z = if below > window.0[1] + room_m { below } else { z_hi + 1.6 * room_m };
    (anchor.0, z)
}

/// For every kind, the nodes of its triangles that also belong to a triangle of another kind (or
/// of no kind).
fn border_nodes(
    triangles: &[[usize; 3]],
    kind_of: &[Option<RegionKind>],
) -> HashMap<RegionKind, HashSet<usize>> {
    let mut node_kinds: HashMap<usize, Vec<Option<RegionKind>>> = HashMap::new();
    for (t, k) in triangles.iter().zip(kind_of) {
        for &v in t {
            let entry = node_kinds.entry(v).or_default();
            if !entry.contains(k) {
                entry.push(*k);
            }
        }
    }
    let mut borders: HashMap<RegionKind, HashSet<usize>> = HashMap::new();
    for (v, ks) in node_kinds.iter().filter(|(_, ks)| ks.len() > 1) {
        for kind in ks.iter().flatten() {
            borders.entry(*kind).or_default().insert(*v);
        }
    }
    borders
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kinds_come_from_part_roles_and_library_materials() {
        assert_eq!(RegionKind::of(PartKind::FluxPath, "steel-1008"), Some(RegionKind::Steel));
        assert_eq!(RegionKind::of(PartKind::Fluid, "mrf-122eg"), Some(RegionKind::Fluid));
        assert_eq!(RegionKind::of(PartKind::Coil, "copper"), Some(RegionKind::Coil));
        assert_eq!(RegionKind::of(PartKind::Spacer, "aluminium"), Some(RegionKind::NonMagnetic));
        assert_eq!(RegionKind::of(PartKind::Shaft, "steel-1008"), Some(RegionKind::Steel));
        assert_eq!(RegionKind::of(PartKind::Air, "air"), Some(RegionKind::Air));
        // A structural part of a material from a CSV file: no label, not a guess.
        assert_eq!(RegionKind::of(PartKind::NonMagnetic, "my-bh-curve.csv"), None);
        assert_eq!(RegionKind::Air.label(), None);
    }

    /// The labels of the thesis brake's parts are those its part names once implied: the role
    /// now comes from the geometry, and no name is read.
    #[test]
    fn every_part_of_the_thesis_brake_has_the_kind_of_its_role() {
        let geometry = mrbrake_design::geometry::build(&mrbrake_design::spec::default_spec())
            .expect("the thesis brake builds");
        for region in &geometry.regions {
            let kind = RegionKind::of(region.kind, &region.material);
            let expected = match region.kind {
                PartKind::Air => Some(RegionKind::Air),
                PartKind::Coil => Some(RegionKind::Coil),
                PartKind::Fluid => Some(RegionKind::Fluid),
                PartKind::FluxPath => Some(RegionKind::Steel),
                _ => kind,
            };
            assert!(kind.is_some(), "{} ({}) has no kind", region.name, region.material);
            assert_eq!(kind, expected, "{}", region.name);
        }
    }
}
