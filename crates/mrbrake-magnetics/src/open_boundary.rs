//! The asymptotic open boundary: a small air box that behaves like unbounded space.
//!
//! Far from the sources `A_phi` is a dipole field, `A ∝ sin θ / ρ²` in spherical coordinates
//! centred on the axis, so on a sphere of radius `ρ = R`, `(n × B)_phi = −∂A/∂n − n_r A/r =
//! 2A/R − A/R = A/R`, and the natural boundary term of the weak form ([`crate::form`]) becomes
//! `∮ ν0 (A/R) φ_i r dl` added to the left-hand side: a constant coupling
//! `m_ab = ν0/R ∫_edge φ_a φ_b r dl` over the DOFs of each boundary edge, integrated exactly by the
//! core's edge rule ([`mrbrake_fem::workflow::boundary::edge_matrices`]). This is the axisymmetric form of
//! the asymptotic boundary condition of Chen & Konrad, IEEE Trans. Magn. 33(1) 1997, §III, and the
//! coefficient FEMM uses for axisymmetric open boundaries (`c0 = 1/(μ0 R)`).

use mrbrake_fem::discretisation::basis::Basis;
use mrbrake_fem::workflow::assemble::LocalMatrix;
use mrbrake_fem::workflow::boundary::edge_matrices;
use mrbrake_materials::MU_0;

use crate::MagneticsError;
use crate::problem::{BoundaryCondition, Problem};

/// The couplings of every open boundary of `problem`, in the order of its boundaries. An error
/// when an open boundary's nodes do not lie on a circle centred on the axis (2 % tolerance).
pub(crate) fn open_boundary_couplings(
    basis: &Basis,
    problem: &Problem,
) -> Result<Vec<LocalMatrix>, MagneticsError> {
    let mut couplings = Vec::new();
    for boundary in &problem.boundaries {
        let BoundaryCondition::Open { centre_z_m } = boundary.condition else { continue };
        let radius = |p: [f64; 2]| p[0].hypot(p[1] - centre_z_m);
        check_on_circle(basis, boundary.tag, centre_z_m, radius)?;
        let matrices = edge_matrices(basis, boundary.tag, |[pa, pb], q, a, b| {
            let big_r = 0.5 * (radius(pa) + radius(pb));
            q.weight * q.phi[a] * q.phi[b] / (MU_0 * big_r)
        })
        .map_err(|e| MagneticsError::field("boundary", format!("open {e}")))?;
        couplings.extend(matrices);
    }
    Ok(couplings)
}

/// The nodes of the edges tagged `tag` lie on a circle centred on the axis at `z = centre_z_m`.
fn check_on_circle(
    basis: &Basis,
    tag: u32,
    centre_z_m: f64,
    radius: impl Fn([f64; 2]) -> f64,
) -> Result<(), MagneticsError> {
    let mesh = basis.mesh();
    let radii: Vec<f64> = mesh
        .edges
        .iter()
        .zip(&mesh.edge_tags)
        .filter(|(_, t)| **t == tag)
        .flat_map(|(e, _)| e.map(|v| radius(mesh.nodes[v])))
        .collect();
    let r_min = radii.iter().cloned().fold(f64::INFINITY, f64::min);
    let r_max = radii.iter().cloned().fold(0.0, f64::max);
    if r_min.is_nan() || r_min <= 0.0 || (r_max - r_min) > 0.02 * r_max {
        return Err(MagneticsError::field(
            format!("boundary[physical={tag}]"),
            format!(
                "open boundary {tag}: its nodes must lie on a circle centred on the axis at z = {centre_z_m} m \
             (distances range from {r_min:.4e} to {r_max:.4e} m)"
            ),
        ));
    }
    Ok(())
}
