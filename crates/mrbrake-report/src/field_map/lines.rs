//! The polylines of a map: level lines of a nodal function (marching triangles on its
//! piecewise-linear interpolant), region outlines, both joined into polylines (one path per line
//! instead of one per triangle: a smaller SVG, and lines without joints) and clipped to the
//! drawn window.

use std::collections::HashMap;
use std::hash::Hash;

/// A point `(r, z)` in metres.
pub type Point = (f64, f64);

/// The window `[r_lo, z_lo]`–`[r_hi, z_hi]` (m) a map shows.
pub type Window = ([f64; 2], [f64; 2]);

/// Segments `[(r, z), (r, z)]` of the contour `ψ = level` in every triangle.
pub fn contour_segments(
    nodes: &[[f64; 2]],
    triangles: &[[usize; 3]],
    psi: &[f64],
    level: f64,
) -> Vec<[Point; 2]> {
    let (at, pieces) = crossings(nodes, triangles, psi, level);
    pieces.iter().map(|p| [at[&p[0]], at[&p[1]]]).collect()
}

/// The contour `ψ = level` as polylines: the per-triangle segments joined across the mesh edges
/// they share.
pub fn contour_lines(
    nodes: &[[f64; 2]],
    triangles: &[[usize; 3]],
    psi: &[f64],
    level: f64,
) -> Vec<Vec<Point>> {
    let (at, pieces) = crossings(nodes, triangles, psi, level);
    chain(&pieces).into_iter().map(|keys| keys.iter().map(|k| at[k]).collect()).collect()
}

/// Where `ψ = level` crosses each mesh edge (keyed by the edge's sorted node pair), and the pair
/// of crossed edges of every triangle the level passes through, in triangle order.
#[allow(clippy::type_complexity)]
fn crossings(
    nodes: &[[f64; 2]],
    triangles: &[[usize; 3]],
    psi: &[f64],
    level: f64,
) -> (HashMap<(usize, usize), Point>, Vec<[(usize, usize); 2]>) {
    let mut at = HashMap::new();
    let mut pieces = Vec::new();
    for tri in triangles {
        let mut crossed = Vec::with_capacity(2);
        for k in 0..3 {
            let (a, b) = (tri[k].min(tri[(k + 1) % 3]), tri[k].max(tri[(k + 1) % 3]));
            let (fa, fb) = (psi[a] - level, psi[b] - level);
            if (fa < 0.0) != (fb < 0.0) {
                // Computed from the sorted pair, so both triangles of an edge agree exactly.
                at.entry((a, b)).or_insert_with(|| {
                    let s = fa / (fa - fb);
                    (
                        nodes[a][0] + s * (nodes[b][0] - nodes[a][0]),
                        nodes[a][1] + s * (nodes[b][1] - nodes[a][1]),
                    )
                });
                crossed.push((a, b));
            }
        }
        if crossed.len() == 2 {
            pieces.push([crossed[0], crossed[1]]);
        }
    }
    (at, pieces)
}

/// Joins pieces (pairs of end keys) into chains of keys: open chains start at keys with an odd
/// number of pieces (in sorted order), closed ones at the first unused piece. Deterministic.
pub fn chain<K: Copy + Eq + Hash + Ord>(pieces: &[[K; 2]]) -> Vec<Vec<K>> {
    let mut ends: HashMap<K, Vec<usize>> = HashMap::with_capacity(2 * pieces.len());
    for (i, p) in pieces.iter().enumerate() {
        ends.entry(p[0]).or_default().push(i);
        ends.entry(p[1]).or_default().push(i);
    }
    let mut odd: Vec<K> =
        pieces.iter().flat_map(|p| p.iter().copied()).filter(|k| ends[k].len() % 2 == 1).collect();
    odd.sort_unstable();
    odd.dedup();
    let mut used = vec![false; pieces.len()];
    let mut chains = Vec::new();
    let starts = odd.into_iter().chain(pieces.iter().map(|p| p[0]));
    for start in starts {
        let mut line = vec![start];
        let mut key = start;
        while let Some(&i) = ends[&key].iter().find(|&&i| !used[i]) {
            used[i] = true;
            key = if pieces[i][0] == key { pieces[i][1] } else { pieces[i][0] };
            line.push(key);
        }
        if line.len() > 1 {
            chains.push(line);
        }
    }
    chains
}

/// The parts of `line` inside `window` (Liang–Barsky on each segment).
pub fn clip_polyline(line: &[Point], window: Window) -> Vec<Vec<Point>> {
    let mut out = Vec::new();
    let mut current: Vec<Point> = Vec::new();
    let flush = |current: &mut Vec<Point>, out: &mut Vec<Vec<Point>>| {
        if current.len() > 1 {
            out.push(std::mem::take(current));
        }
        current.clear();
    };
    for w in line.windows(2) {
        let (a, b) = (w[0], w[1]);
        match clip_segment(a, b, window) {
            Some((t0, t1)) => {
                let lerp = |t: f64| (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                if t0 > 0.0 || current.is_empty() {
                    flush(&mut current, &mut out);
                    current.push(lerp(t0));
                }
                current.push(lerp(t1));
                if t1 < 1.0 {
                    flush(&mut current, &mut out);
                }
            }
            None => flush(&mut current, &mut out),
        }
    }
    flush(&mut current, &mut out);
    out
}

/// The parameter interval `[t0, t1]` of the segment `a + t (b − a)` inside `window`, if any.
fn clip_segment(a: Point, b: Point, window: Window) -> Option<(f64, f64)> {
    let (lo, hi) = window;
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0_f64, 1.0_f64);
    for (p, q) in [(-dx, a.0 - lo[0]), (dx, hi[0] - a.0), (-dy, a.1 - lo[1]), (dy, hi[1] - a.1)] {
        if p.abs() < 1e-300 {
            if q < 0.0 {
                return None;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
        }
    }
    (t0 <= t1).then_some((t0, t1))
}

/// Edges shared by triangles of different regions (in triangle order), then the boundary edges
/// (sorted).
pub fn outline_edges(triangles: &[[usize; 3]], region_tags: &[u32]) -> Vec<[usize; 2]> {
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

/// The region outlines as polylines clipped to `window`.
pub fn outline_lines(
    nodes: &[[f64; 2]],
    triangles: &[[usize; 3]],
    region_tags: &[u32],
    window: Window,
) -> Vec<Vec<Point>> {
    let at = |v: usize| (nodes[v][0], nodes[v][1]);
    chain(&outline_edges(triangles, region_tags))
        .iter()
        .flat_map(|keys| clip_polyline(&keys.iter().map(|&v| at(v)).collect::<Vec<_>>(), window))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chains_join_open_and_closed_lines() {
        // An open line 1-2-3-4 given out of order and a triangle loop 7-8-9.
        let pieces = [[3, 4], [7, 8], [1, 2], [9, 7], [2, 3], [8, 9]];
        let chains = chain(&pieces);
        assert_eq!(chains.len(), 2, "{chains:?}");
        assert_eq!(chains[0], vec![1, 2, 3, 4]);
        assert_eq!(chains[1].len(), 4);
        assert_eq!(chains[1].first(), chains[1].last());
    }

    #[test]
    fn clipping_keeps_the_inside_parts() {
        let window = ([0.0, 0.0], [1.0, 1.0]);
        // In, out through the right side, back in through the top.
        let line = [(0.5, 0.5), (1.5, 0.5), (1.5, 1.5), (0.5, 0.5)];
        let parts = clip_polyline(&line, window);
        assert_eq!(parts.len(), 2, "{parts:?}");
        assert!((parts[0][1].0 - 1.0).abs() < 1e-12 && (parts[0][1].1 - 0.5).abs() < 1e-12);
        assert!((parts[1][0].0 - 1.0).abs() < 1e-12 && (parts[1][0].1 - 1.0).abs() < 1e-12);
        assert!(clip_polyline(&[(2.0, 2.0), (3.0, 3.0)], window).is_empty());
    }

    #[test]
    fn contour_lines_are_joined_segments() {
        // A 4 x 4 grid of squares, each split in two; ψ = r crosses every row once.
        let n = 4;
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
        let psi: Vec<f64> = nodes.iter().map(|p| p[0]).collect();
        let segments = contour_segments(&nodes, &triangles, &psi, 1.5);
        let lines = contour_lines(&nodes, &triangles, &psi, 1.5);
        assert_eq!(lines.len(), 1, "{lines:?}");
        assert_eq!(lines[0].len(), segments.len() + 1);
        assert!(lines[0].iter().all(|p| (p.0 - 1.5).abs() < 1e-12));
    }
}
