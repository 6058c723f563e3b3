//! The solution and its post-processing: B at points and along lines, region statistics, flux
//! linkage and inductance, stored energy and co-energy.
//!
//! All integrals are over the full body of revolution (the `2π` dropped in the weak form is put back):
//! - flux linkage of a coil of `N` turns over its cross-section `S` (turns spread uniformly):
//!   `λ = (N/S) ∫_S 2π r A_phi dS` — each turn at radius r links `2π r A_phi` (Stokes), averaged over S;
//! - secant inductance `L = λ / I`; incremental inductance `dλ/dI` by [`Solver::incremental_inductance`];
//! - energy `W = ∫ w(B) dV`, `w(B) = ∫_0^B H db`, co-energy `W' = ∫ (H B − w) dV` (equal for linear media).
//!
//! B of the P1 potential, `B_r = −∂A/∂z`, `B_z = ∂A/∂r + A/r`, is only first-order accurate point by
//! point (and piecewise almost constant). [`Solver::b_at`] therefore returns a *recovered* field: at
//! every node, the area-weighted average of the centroid values of the triangles around it **of the
//! same region** (so the jump of tangential B at an iron/air interface is kept), interpolated
//! linearly inside the triangle — the simple averaging recovery of Zienkiewicz & Zhu (Int. J. Numer.
//! Meth. Eng. 24 (1987) 337), which is second-order accurate at interior nodes of regular meshes (the
//! thick-coil validation measures it on the axis). On the axis `B_r = 0` is imposed (symmetry).
//! Only the three corners of the triangle holding the point are recovered, from the triangles
//! around each corner (a node-to-triangle table built once per solver), so a probe costs
//! O(valence) and no pass over the whole mesh beyond locating the point (a scan for the first
//! few points, a bucket grid after [`LOCATOR_AFTER_QUERIES`] queries).
//! [`Solver::b_at_raw`] gives the unrecovered element value; on the axis (`r → 0`, where `A = 0`) it
//! uses the limit `B_z = 2 ∂A/∂r`.
//!
//! Quadratic (P2) elements: B of the P2 potential is linear in each element (plus the `A/r` term)
//! and second-order accurate point by point, so [`Solver::b_at`] evaluates it directly in the
//! triangle holding the point (the same value as [`Solver::b_at_raw`], with `B_r = 0` imposed on
//! the axis); there is no recovery. Integrals (region statistics, flux linkage, energy, errors)
//! use the P2 potential at the quadrature points in both cases, and [`Solver::flux_function`] and
//! the vertex part of [`Solution::a_phi`] give the values at the mesh nodes.

use serde::Serialize;

use std::sync::atomic::{AtomicUsize, Ordering};

use mrbrake_fem::by_order;
use mrbrake_fem::discretisation::basis::Basis;
use mrbrake_fem::discretisation::dofs::ElementOrder;
use mrbrake_fem::discretisation::element::{ElementTriP1, P1Triangle, TriangleBasis};
use mrbrake_fem::discretisation::quadrature::TrianglePoint;
use mrbrake_fem::mesh::Mesh;
use mrbrake_fem::mesh::locate::{PointLocator, locate_by_scan};

use crate::MagneticsError;
use crate::form::{curls, flux_density};
use crate::solver::{NewtonReport, Solver};

const TWO_PI: f64 = 2.0 * std::f64::consts::PI;

/// Point queries answered by scanning every triangle before the bucket grid is built: the grid
/// costs about as much to build as a few scans (two passes over the triangles).
pub const LOCATOR_AFTER_QUERIES: usize = 4;

/// The converged potential and the Newton report.
#[derive(Debug, Clone)]
pub struct Solution {
    a_phi: Vec<f64>,
    n_vertices: usize,
    /// Newton iterations, history and timings.
    pub report: NewtonReport,
}

impl Solution {
    pub(crate) fn new(a_phi: Vec<f64>, n_vertices: usize, report: NewtonReport) -> Self {
        Self { a_phi, n_vertices, report }
    }

    /// A potential that no Newton solve produced (a time step, a real or imaginary part of a
    /// harmonic solution): its report is empty.
    pub(crate) fn from_potential(a_phi: Vec<f64>, n_vertices: usize) -> Self {
        let report = NewtonReport {
            iterations: 0,
            factorizations: 0,
            converged: true,
            residual_scale: 0.0,
            final_relative_residual: 0.0,
            history: Vec::new(),
            timings: Default::default(),
        };
        Self { a_phi, n_vertices, report }
    }

    /// Values of `A_phi` (Wb/m) at every degree of freedom (usable as a warm start of the same
    /// solver): one per mesh node for P1; for P2 the mesh nodes, then the edge midpoints
    /// ([`Solver::dof_coordinates`]).
    pub fn a_phi(&self) -> &[f64] {
        &self.a_phi
    }

    /// Values of `A_phi` (Wb/m) at the mesh nodes (for P1 the whole of [`Self::a_phi`]), e.g. for
    /// point fields on the mesh.
    pub fn vertex_a_phi(&self) -> &[f64] {
        &self.a_phi[..self.n_vertices]
    }
}

/// The field of a solution as plain data, for maps, files and front ends (no solver needed to keep
/// it): the mesh, `A_phi` and the flux function at the nodes, B at the triangle centroids.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FieldSnapshot {
    /// Node coordinates `[r, z]` (m).
    pub nodes: Vec<[f64; 2]>,
    /// Triangles (node indices, counter-clockwise).
    pub triangles: Vec<[usize; 3]>,
    /// Physical (region) tag of every triangle.
    pub region_tags: Vec<u32>,
    /// `A_phi` (Wb/m) at the nodes.
    pub a_phi_wb_per_m: Vec<f64>,
    /// Flux function `ψ = r A_phi` (Wb/rad) at the nodes: flux lines are its level lines.
    pub flux_function_wb: Vec<f64>,
    /// `[B_r, B_z]` (T) at the centroid of every triangle.
    pub element_b_t: Vec<[f64; 2]>,
    /// `|B|` (T) at the centroid of every triangle.
    pub element_b_abs_t: Vec<f64>,
}

impl FieldSnapshot {
    /// The field as a ParaView `.vtu` file: `A_phi` and `r·A_phi` at the nodes, B and |B| per
    /// triangle.
    pub fn to_vtu(&self, mesh: &Mesh) -> String {
        use mrbrake_fem::mesh::vtu::{Field, to_vtu};
        let b3: Vec<f64> = self.element_b_t.iter().flat_map(|b| [b[0], b[1], 0.0]).collect();
        to_vtu(
            mesh,
            &[
                Field { name: "A_phi_Wb_per_m", components: 1, values: &self.a_phi_wb_per_m },
                Field {
                    name: "flux_function_r_A_phi",
                    components: 1,
                    values: &self.flux_function_wb,
                },
            ],
            &[
                Field { name: "B_T", components: 3, values: &b3 },
                Field { name: "B_abs_T", components: 1, values: &self.element_b_abs_t },
            ],
        )
    }
}

/// A time-harmonic field as a ParaView `.vtu` file from the snapshots of its real and imaginary
/// parts (peak phasors, time factor `exp(+jωt)`): `A_phi` and `r·A_phi` (re, im) at the nodes,
/// B (re, im) and `sqrt(|B̂_r|² + |B̂_z|²)` per triangle.
pub fn phasor_vtu(re: &FieldSnapshot, im: &FieldSnapshot, mesh: &Mesh) -> String {
    use mrbrake_fem::mesh::vtu::{Field, to_vtu};
    let b3 = |s: &FieldSnapshot| -> Vec<f64> {
        s.element_b_t.iter().flat_map(|b| [b[0], b[1], 0.0]).collect()
    };
    let (b_re, b_im) = (b3(re), b3(im));
    let norm: Vec<f64> =
        re.element_b_abs_t.iter().zip(&im.element_b_abs_t).map(|(r, i)| r.hypot(*i)).collect();
    let point = |name, values| Field { name, components: 1, values };
    to_vtu(
        mesh,
        &[
            point("A_phi_re_Wb_per_m", &re.a_phi_wb_per_m),
            point("A_phi_im_Wb_per_m", &im.a_phi_wb_per_m),
            point("flux_function_re_r_A_phi", &re.flux_function_wb),
            point("flux_function_im_r_A_phi", &im.flux_function_wb),
        ],
        &[
            Field { name: "B_re_T", components: 3, values: &b_re },
            Field { name: "B_im_T", components: 3, values: &b_im },
            Field { name: "B_phasor_norm_T", components: 1, values: &norm },
        ],
    )
}

/// The potential and flux density of a solution at one quadrature point of one triangle.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FieldSample {
    /// `[r, z]` (m).
    pub point: [f64; 2],
    /// Quadrature weight × triangle area × r (m³ per radian).
    pub weight: f64,
    /// `A_phi` (Wb/m).
    pub a: f64,
    /// `[B_r, B_z]` (T).
    pub b: [f64; 2],
}

/// Calls `f` with the field of the DOF values `a` at every point of `rule` in triangle `t`.
#[inline]
fn samples_in<E: TriangleBasis<N>, const N: usize>(
    basis: &Basis,
    t: usize,
    rule: &[TrianglePoint],
    a: &[f64],
    f: &mut impl FnMut(FieldSample),
) {
    let element = basis.element::<E, N>(t);
    let geometry = element.geometry();
    let a_local = element.dofs().map(|d| a[d]);
    for q in rule {
        let v = basis.point::<E, N>(&geometry, q);
        let b = flux_density(&curls(&v), a_local);
        let mut a_q = 0.0;
        for k in 0..N {
            a_q += v.phi[k] * a_local[k];
        }
        f(FieldSample { point: v.point, weight: v.weight, a: a_q, b });
    }
}

/// B at one point.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PointField {
    /// Radius (m).
    pub r: f64,
    /// Axial position (m).
    pub z: f64,
    /// Radial flux density (T).
    pub b_r_t: f64,
    /// Axial flux density (T).
    pub b_z_t: f64,
    /// Magnitude (T).
    pub b_abs_t: f64,
}

/// Statistics of |B| over one region (volume-weighted over the body of revolution).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RegionStats {
    /// Physical tag.
    pub physical: u32,
    /// Cross-section area (m²).
    pub area_m2: f64,
    /// Volume of the body of revolution (m³).
    pub volume_m3: f64,
    /// Volume-weighted mean |B| (T).
    pub mean_b_t: f64,
    /// Largest |B| at a quadrature point (T).
    pub max_b_t: f64,
    /// Volume-weighted 10 %, 50 % and 90 % quantiles of |B| (T).
    pub quantiles_b_t: [f64; 3],
}

/// Flux linkage and inductance of a coil.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CoilLinkage {
    /// Physical tag of the coil region.
    pub physical: u32,
    /// Turns.
    pub turns: f64,
    /// Current (A).
    pub current_a: f64,
    /// Flux linkage λ (Wb).
    pub flux_linkage_wb: f64,
    /// Secant inductance λ/I (H); NaN at zero current.
    pub inductance_h: f64,
}

/// `(N/S) ∫ 2π r A dS` over region index `ri` (`a`: the value of every DOF).
pub(crate) fn coil_flux(solver: &Solver, a: &[f64], ri: usize, turns: f64) -> f64 {
    let mut integral = 0.0;
    let rule = solver.basis().rule();
    for t in 0..solver.problem.mesh.triangles.len() {
        if solver.region_of(t) != ri {
            continue;
        }
        solver.for_each_sample(t, rule, a, |s| integral += s.weight * s.a);
    }
    TWO_PI * integral * turns / solver.region_area[ri]
}

/// The corners `3 t + k` of the triangles around every node (compressed rows, ascending `t`).
#[derive(Debug, Clone)]
pub(crate) struct NodeCorners {
    start: Vec<usize>,
    corners: Vec<usize>,
}

impl NodeCorners {
    fn new(mesh: &mrbrake_fem::mesh::Mesh) -> Self {
        let n = mesh.nodes.len();
        let mut start = vec![0usize; n + 1];
        for tri in &mesh.triangles {
            for &v in tri {
                start[v + 1] += 1;
            }
        }
        for i in 0..n {
            start[i + 1] += start[i];
        }
        let mut fill = start.clone();
        let mut corners = vec![0usize; start[n]];
        for (t, tri) in mesh.triangles.iter().enumerate() {
            for (k, &v) in tri.iter().enumerate() {
                corners[fill[v]] = 3 * t + k;
                fill[v] += 1;
            }
        }
        Self { start, corners }
    }

    fn of(&self, v: usize) -> &[usize] {
        &self.corners[self.start[v]..self.start[v + 1]]
    }
}

/// Lazily built point-query helpers of a solver (mesh-only, shared by every solution).
#[derive(Debug, Default)]
pub(crate) struct QueryCache {
    locator: std::sync::OnceLock<PointLocator>,
    node_corners: std::sync::OnceLock<NodeCorners>,
    /// The mesh's size scale (bounding-box diagonal), for the on-axis test of point queries: a
    /// pass over every node, so computed once rather than per query.
    size_scale: std::sync::OnceLock<f64>,
    queries: AtomicUsize,
}

impl Solver {
    /// The mesh's size scale (m), computed on first use.
    fn size_scale(&self) -> f64 {
        *self.queries.size_scale.get_or_init(|| self.problem.mesh.size_scale())
    }

    /// Calls `f` with the field of the DOF values `a` at every point of `rule` in triangle `t`.
    #[inline]
    pub(crate) fn for_each_sample(
        &self,
        t: usize,
        rule: &[TrianglePoint],
        a: &[f64],
        mut f: impl FnMut(FieldSample),
    ) {
        by_order!(self.options.order, samples_in(self.basis(), t, rule, a, &mut f));
    }

    /// The triangle containing `p` and its barycentric coordinates, or an input error naming `p`.
    fn locate(&self, p: [f64; 2]) -> Result<(usize, [f64; 3]), MagneticsError> {
        let mesh = &self.problem.mesh;
        let cache = &self.queries;
        let found = match cache.locator.get() {
            Some(locator) => locator.locate(mesh, p),
            None if cache.queries.fetch_add(1, Ordering::Relaxed) < LOCATOR_AFTER_QUERIES => {
                locate_by_scan(mesh, p)
            }
            None => cache.locator.get_or_init(|| PointLocator::new(mesh)).locate(mesh, p),
        };
        found.ok_or_else(|| {
            let e = mrbrake_error::FieldError::new("point", "outside the mesh");
            MagneticsError::from(e.with_value(format!("(r = {} m, z = {} m)", p[0], p[1])))
        })
    }

    /// B at `[r, z]` (m): recovered for P1, evaluated directly for P2 (see the module docs); an
    /// error if the point is outside the mesh.
    pub fn b_at(&self, solution: &Solution, p: [f64; 2]) -> Result<PointField, MagneticsError> {
        if self.options.order == ElementOrder::P2 {
            let mut field = self.b_at_raw(solution, p)?;
            if p[0] <= 1e-9 * self.size_scale() {
                field.b_r_t = 0.0;
                field.b_abs_t = field.b_z_t.abs();
            }
            return Ok(field);
        }
        let (t, bary) = self.locate(p)?;
        let scale = self.size_scale();
        let mut b = [0.0; 2];
        for k in 0..3 {
            let corner = self.recovered_corner_b(solution, t, k, scale);
            b[0] += bary[k] * corner[0];
            b[1] += bary[k] * corner[1];
        }
        Ok(PointField { r: p[0], z: p[1], b_r_t: b[0], b_z_t: b[1], b_abs_t: b[0].hypot(b[1]) })
    }

    /// Same-region nodal average of the centroid B (module docs) at corner `k` of triangle `t`:
    /// the area-weighted mean over the triangles around that node with the same region tag
    /// (`scale`: the mesh size scale, for the axis test).
    fn recovered_corner_b(&self, solution: &Solution, t: usize, k: usize, scale: f64) -> [f64; 2] {
        let mesh = &self.problem.mesh;
        let node_corners = self.queries.node_corners.get_or_init(|| NodeCorners::new(mesh));
        let v = mesh.triangles[t][k];
        let tag = mesh.triangle_tags[t];
        let (mut sum, mut weight) = ([0.0; 2], 0.0);
        for &c in node_corners.of(v) {
            let around = c / 3;
            if mesh.triangle_tags[around] != tag {
                continue;
            }
            let area = mesh.signed_area(around);
            let centroid_b = centroid_b(mesh, solution, around, scale);
            sum[0] += area * centroid_b[0];
            sum[1] += area * centroid_b[1];
            weight += area;
        }
        let mut b = [sum[0] / weight, sum[1] / weight];
        if mesh.nodes[v][0] <= 1e-9 * scale {
            b[0] = 0.0;
        }
        b
    }

    /// Unrecovered B of the potential in the triangle containing `[r, z]` (the lowest-numbered
    /// one when the point is on an edge).
    pub fn b_at_raw(&self, solution: &Solution, p: [f64; 2]) -> Result<PointField, MagneticsError> {
        let mesh = &self.problem.mesh;
        let (t, bary) = self.locate(p)?;
        let (element_dofs, scale) = (self.basis().dofs().element_dofs(), self.size_scale());
        let b = by_order!(
            self.options.order,
            b_in_element(mesh, element_dofs, &solution.a_phi, t, bary, p[0], scale)
        );
        Ok(PointField { r: p[0], z: p[1], b_r_t: b[0], b_z_t: b[1], b_abs_t: b[0].hypot(b[1]) })
    }

    /// `A_phi` (Wb/m) of `solution` at `[r, z]` (m), interpolated with the element basis (e.g. to
    /// carry a solution over to a warm start of a related problem); an error if the point is
    /// outside the mesh.
    pub fn a_phi_at(&self, solution: &Solution, p: [f64; 2]) -> Result<f64, MagneticsError> {
        let (t, bary) = self.locate(p)?;
        let element_dofs = self.basis().dofs().element_dofs();
        Ok(by_order!(self.options.order, a_in_element(element_dofs, &solution.a_phi, t, bary)))
    }

    /// B at `samples` equally spaced points along each segment of the polyline `points`
    /// (segment ends included once).
    pub fn b_along(
        &self,
        solution: &Solution,
        points: &[[f64; 2]],
        samples: usize,
    ) -> Result<Vec<PointField>, MagneticsError> {
        let mut out = Vec::new();
        let samples = samples.max(1);
        for (s, w) in points.windows(2).enumerate() {
            for k in 0..=samples {
                if s > 0 && k == 0 {
                    continue;
                }
                let f = k as f64 / samples as f64;
                let p = [w[0][0] + f * (w[1][0] - w[0][0]), w[0][1] + f * (w[1][1] - w[0][1])];
                out.push(self.b_at(solution, p)?);
            }
        }
        Ok(out)
    }

    /// |B| statistics of region `tag`.
    pub fn region_stats(
        &self,
        solution: &Solution,
        tag: u32,
    ) -> Result<RegionStats, MagneticsError> {
        let ri = self.region_position(tag)?;
        let mut samples: Vec<(f64, f64)> = Vec::new();
        for t in 0..self.problem.mesh.triangles.len() {
            if self.region_of(t) != ri {
                continue;
            }
            self.for_each_sample(t, self.basis().rule(), &solution.a_phi, |s| {
                samples.push((s.b[0].hypot(s.b[1]), TWO_PI * s.weight));
            });
        }
        let volume: f64 = samples.iter().map(|s| s.1).sum();
        let mean = samples.iter().map(|s| s.0 * s.1).sum::<f64>() / volume;
        let max = samples.iter().map(|s| s.0).fold(0.0, f64::max);
        samples.sort_by(|x, y| x.0.total_cmp(&y.0));
        let mut quantiles = [0.0; 3];
        for (k, level) in [0.1, 0.5, 0.9].iter().enumerate() {
            let mut cumulative = 0.0;
            for s in &samples {
                cumulative += s.1;
                if cumulative >= level * volume {
                    quantiles[k] = s.0;
                    break;
                }
            }
        }
        Ok(RegionStats {
            physical: tag,
            area_m2: self.region_area[ri],
            volume_m3: volume,
            mean_b_t: mean,
            max_b_t: max,
            quantiles_b_t: quantiles,
        })
    }

    /// `∫ f(p, B) dr dz` over the cross-section of region `tag`: `f` receives each quadrature point
    /// `p = [r, z]` (m) and the exact `B = [B_r, B_z]` (T) of the solution there (no recovery), and
    /// the sum is weighted by area, not by `r` (multiply by `2π r` inside `f` for a volume
    /// integral). For quantities that are non-linear in B, such as a fluid's yield stress, this is
    /// the robust alternative to sampling B at points, which lands on element edges where the
    /// tangential B of a conforming solution jumps.
    pub fn integrate_over_region(
        &self,
        solution: &Solution,
        tag: u32,
        mut f: impl FnMut([f64; 2], [f64; 2]) -> f64,
    ) -> Result<f64, MagneticsError> {
        self.region_position(tag)?;
        // Quadrature points are interior, so r > 0 and weight / r is the area weight.
        Ok(self.sum_over_samples(solution, self.basis().rule(), &[tag], |s| {
            s.weight / s.point[0] * f(s.point, s.b)
        }))
    }

    /// Flux linkage and secant inductance of every coil (regions with a turns × current source).
    pub fn coils(&self, solution: &Solution) -> Vec<CoilLinkage> {
        let mut out = Vec::new();
        for (ri, region) in self.problem.regions.iter().enumerate() {
            if let Some(crate::problem::Source::Coil { turns, current_a }) = region.source {
                let flux = coil_flux(self, &solution.a_phi, ri, turns);
                out.push(CoilLinkage {
                    physical: region.tag,
                    turns,
                    current_a,
                    flux_linkage_wb: flux,
                    inductance_h: if current_a.abs() > 0.0 { flux / current_a } else { f64::NAN },
                });
            }
        }
        out
    }

    /// Stored magnetic energy `W` and co-energy `W'` (J), whole body of revolution.
    pub fn energy(&self, solution: &Solution) -> (f64, f64) {
        use rayon::prelude::*;
        let mesh = &self.problem.mesh;
        // Element sums in parallel, then added in element order: the result does not depend on
        // how the work was split between threads.
        let per_element: Vec<(f64, f64)> = (0..mesh.triangles.len())
            .into_par_iter()
            .map(|t| {
                let material = self.form.material(t);
                let mut w_sum = 0.0;
                let mut co_sum = 0.0;
                self.for_each_sample(t, self.basis().rule(), &solution.a_phi, |s| {
                    let b2 = s.b[0] * s.b[0] + s.b[1] * s.b[1];
                    let w = material.energy_density(b2.sqrt());
                    let hb = material.nu_and_dnu_db2(b2).0 * b2;
                    w_sum += TWO_PI * s.weight * w;
                    co_sum += TWO_PI * s.weight * (hb - w);
                });
                (w_sum, co_sum)
            })
            .collect();
        per_element.iter().fold((0.0, 0.0), |sum, e| (sum.0 + e.0, sum.1 + e.1))
    }

    /// The flux function `ψ = r A_phi` (Wb/rad) at every mesh node (the vertex DOFs, also for P2):
    /// the flux through the disc of radius r at height z is `2π ψ`, so flux lines are its level
    /// lines (field maps, VTU output).
    pub fn flux_function(&self, solution: &Solution) -> Vec<f64> {
        self.problem.mesh.nodes.iter().zip(solution.vertex_a_phi()).map(|(p, a)| p[0] * a).collect()
    }

    /// The field of `solution` as plain data ([`FieldSnapshot`]).
    pub fn field_snapshot(&self, solution: &Solution) -> FieldSnapshot {
        let mesh = &self.problem.mesh;
        let element_b = self.element_b(solution);
        FieldSnapshot {
            nodes: mesh.nodes.clone(),
            triangles: mesh.triangles.clone(),
            region_tags: mesh.triangle_tags.clone(),
            a_phi_wb_per_m: solution.vertex_a_phi().to_vec(),
            flux_function_wb: self.flux_function(solution),
            element_b_abs_t: element_b.iter().map(|b| b[0].hypot(b[1])).collect(),
            element_b_t: element_b,
        }
    }

    /// B at the centroid of every triangle: `[B_r, B_z]` pairs (T), for maps and VTU output.
    pub fn element_b(&self, solution: &Solution) -> Vec<[f64; 2]> {
        use rayon::prelude::*;
        let mesh = &self.problem.mesh;
        let scale = mesh.size_scale();
        let element_dofs = self.basis().dofs().element_dofs();
        let third = [1.0 / 3.0; 3];
        (0..mesh.triangles.len())
            .into_par_iter()
            .map(|t| {
                let r = triangle(mesh, t).point(third)[0];
                by_order!(
                    self.options.order,
                    b_in_element(mesh, element_dofs, &solution.a_phi, t, third, r, scale)
                )
            })
            .collect()
    }

    /// Weighted L2 error `(∫ (A_h − A)² 2π r dS)^{1/2}` (Wb·m^{1/2}) against a reference potential,
    /// with the degree-5 triangle rule, over the regions in `tags` (all regions when empty).
    pub fn l2_error(
        &self,
        solution: &Solution,
        reference: impl Fn([f64; 2]) -> f64,
        tags: &[u32],
    ) -> f64 {
        let rule = mrbrake_fem::discretisation::quadrature::triangle_rule(5);
        let sum = self.sum_over_samples(solution, &rule, tags, |s| {
            let e = s.a - reference(s.point);
            TWO_PI * s.weight * e * e
        });
        sum.sqrt()
    }

    /// Weighted L2 error of B, `(∫ |B_h − B|² 2π r dS)^{1/2}` (T·m^{3/2}), against a reference
    /// `[B_r, B_z]`, with the degree-5 triangle rule, over the regions in `tags` (all when empty).
    /// `reference = |_| [0.0, 0.0]` gives the norm of `B_h` itself.
    pub fn b_l2_error(
        &self,
        solution: &Solution,
        reference: impl Fn([f64; 2]) -> [f64; 2],
        tags: &[u32],
    ) -> f64 {
        let rule = mrbrake_fem::discretisation::quadrature::triangle_rule(5);
        let sum = self.sum_over_samples(solution, &rule, tags, |s| {
            let b = reference(s.point);
            TWO_PI * s.weight * ((s.b[0] - b[0]).powi(2) + (s.b[1] - b[1]).powi(2))
        });
        sum.sqrt()
    }

    /// `Σ f(sample)` over the quadrature points of `rule` in the triangles of the regions in `tags`
    /// (all triangles when empty).
    fn sum_over_samples(
        &self,
        solution: &Solution,
        rule: &[TrianglePoint],
        tags: &[u32],
        mut f: impl FnMut(&FieldSample) -> f64,
    ) -> f64 {
        let mesh = &self.problem.mesh;
        let mut sum = 0.0;
        for t in 0..mesh.triangles.len() {
            if !tags.is_empty() && !tags.contains(&mesh.triangle_tags[t]) {
                continue;
            }
            self.for_each_sample(t, rule, &solution.a_phi, |s| sum += f(&s));
        }
        sum
    }

    fn region_position(&self, tag: u32) -> Result<usize, MagneticsError> {
        self.problem
            .regions
            .iter()
            .position(|r| r.tag == tag)
            .ok_or_else(|| MagneticsError::field("tag", format!("no region with physical = {tag}")))
    }
}

/// The straight-sided geometry of mesh triangle `t`.
#[inline(always)]
fn triangle(mesh: &Mesh, t: usize) -> P1Triangle {
    let [a, b, c] = mesh.triangles[t];
    P1Triangle::new([mesh.nodes[a], mesh.nodes[b], mesh.nodes[c]])
}

/// The values of `a` at the `N` DOFs of triangle `t` (`element_dofs`: `N` global DOFs per triangle).
#[inline(always)]
fn local_values<const N: usize>(element_dofs: &[usize], t: usize, a: &[f64]) -> [f64; N] {
    let dofs = &element_dofs[N * t..N * (t + 1)];
    std::array::from_fn(|i| a[dofs[i]])
}

/// B of the P1 potential at the centroid of triangle `t` (`scale`: the mesh size scale).
fn centroid_b(mesh: &Mesh, solution: &Solution, t: usize, scale: f64) -> [f64; 2] {
    let tri = triangle(mesh, t);
    let a = mesh.triangles[t].map(|v| solution.a_phi[v]);
    let centroid = tri.point([1.0 / 3.0; 3]);
    b_in_triangle::<ElementTriP1, 3>(&tri, a, [1.0 / 3.0; 3], centroid[0], scale)
}

/// B of the DOF values `a` in triangle `t` at barycentric `bary` (radius `r`).
fn b_in_element<E: TriangleBasis<N>, const N: usize>(
    mesh: &Mesh,
    element_dofs: &[usize],
    a: &[f64],
    t: usize,
    bary: [f64; 3],
    r: f64,
    scale: f64,
) -> [f64; 2] {
    let a_local = local_values::<N>(element_dofs, t, a);
    b_in_triangle::<E, N>(&triangle(mesh, t), a_local, bary, r, scale)
}

/// The potential in triangle `t` at barycentric `bary`: `Σ A_i φ_i`.
fn a_in_element<E: TriangleBasis<N>, const N: usize>(
    element_dofs: &[usize],
    a: &[f64],
    t: usize,
    bary: [f64; 3],
) -> f64 {
    let a_local = local_values::<N>(element_dofs, t, a);
    E::values(bary).iter().zip(a_local).map(|(phi, a)| phi * a).sum()
}

/// B in a triangle at barycentric `bary` (radius `r`), `B = (−∂A/∂z, ∂A/∂r + A/r)`; the axis limit
/// `B_z = 2 ∂A/∂r` below `r = 1e-9 ×` the mesh scale (where `A = 0`).
fn b_in_triangle<E: TriangleBasis<N>, const N: usize>(
    tri: &P1Triangle,
    a: [f64; N],
    bary: [f64; 3],
    r: f64,
    scale: f64,
) -> [f64; 2] {
    let values = E::values(bary);
    let gradients = E::gradients(bary, &tri.grad);
    let mut grad = [0.0; 2];
    let mut value = 0.0;
    for i in 0..N {
        grad[0] += a[i] * gradients[i][0];
        grad[1] += a[i] * gradients[i][1];
        value += a[i] * values[i];
    }
    let b_z = if r <= 1e-9 * scale { 2.0 * grad[0] } else { grad[0] + value / r };
    [-grad[1], b_z]
}
