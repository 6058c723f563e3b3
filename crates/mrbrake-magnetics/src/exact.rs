//! Closed-form axisymmetric fields used to validate the solver (SI units; `A_phi` in Wb/m, B in T).
//!
//! - [`elliptic_k_e`]: complete elliptic integrals K(m), E(m) by the arithmetic–geometric mean
//!   (Abramowitz & Stegun 17.6.1–17.6.4).
//! - [`loop_a_phi`]: vector potential of a circular current loop (Jackson, Classical Electrodynamics,
//!   3rd ed., eq. 5.37): `A_phi = μ0 I / (π k) √(a/r) [(1 − k²/2) K(k²) − E(k²)]`,
//!   `k² = 4 a r / ((a + r)² + z²)`.
//! - [`thick_coil_a_phi`]: a rectangular-section coil of uniform current density, by Gauss–Legendre
//!   integration of the loop potential over the section (exact to quadrature outside the section).
//! - [`loop_b_r`], [`coaxial_loops_force_z`], [`thick_coils_force_z`]: the radial field of a loop
//!   and the axial force between coaxial loops, `F_z = −2π b I₂ B_r,1(b, d)` (the Lorentz force
//!   on loop 2 in the field of loop 1), with `B_r = μ0 I z / (2π r √((a+r)²+z²)) [−K + (a²+r²+z²)
//!   / ((a−r)²+z²) E]` (Smythe, *Static and Dynamic Electricity*, 3rd ed., §7.10; equal to
//!   `I₁ I₂ ∂M/∂d` of the mutual inductance `M = μ0 √(ab) [(2/k − k) K − (2/k) E]`, Maxwell's
//!   formula, checked in the tests), integrated over two rectangular sections by Gauss–Legendre.
//! - [`thick_coil_axis_bz`]: on-axis B of that coil in closed form (integral of the loop's axial
//!   field `μ0 I a² / (2 (a² + u²)^{3/2})` over the section).
//! - [`long_solenoid_a_phi`]: infinitely long thick solenoid, `B_z(r) = μ0 J (r2 − max(r, r1))` inside,
//!   0 outside, `A_phi = (1/r) ∫_0^r B_z s ds`.
//! - [`sphere_a_phi`]: permeable sphere in a uniform field `B0 e_z` (Jackson §5.11 / Griffiths ex. 6.3
//!   form for magnetostatics): inside `B = 3 μr/(μr + 2) B0` uniform, outside the uniform field plus a
//!   dipole `A = B0 r/2 + B0 K a³ r / ρ³`, `K = (μr − 1)/(μr + 2)`.
//! - Eddy currents: [`conducting_cylinder_potential`] (the skin effect in a long conductor in a
//!   uniform time-harmonic axial field, complex Bessel functions [`bessel_j0_j1`]) and
//!   [`cylinder_step_flux`] (the flux diffusing into it after a step, a series over the zeros of
//!   `J0`, [`bessel_j0_zeros`]).

use std::f64::consts::PI;

use crate::material::MU_0;
use mrbrake_fem::discretisation::quadrature::gauss_legendre_unit;

/// Complete elliptic integrals of the first and second kind, `(K(m), E(m))`, parameter `m = k²` in `[0, 1)`.
pub fn elliptic_k_e(m: f64) -> (f64, f64) {
    let mut a = 1.0;
    let mut b = (1.0 - m).sqrt();
    let mut c = m.sqrt();
    let mut sum = 0.5 * c * c; // 2^{n−1} c_n² for n = 0
    let mut power = 1.0;
    for _ in 0..40 {
        if c.abs() < 1e-17 {
            break;
        }
        let a_next = 0.5 * (a + b);
        let b_next = (a * b).sqrt();
        c = 0.5 * (a - b);
        a = a_next;
        b = b_next;
        sum += power * c * c;
        power *= 2.0;
    }
    let k = std::f64::consts::PI / (2.0 * a);
    (k, k * (1.0 - sum))
}

/// `A_phi` (Wb/m) at `(r, z)` of a loop of radius `a` at `z = 0` carrying `current` (A).
pub fn loop_a_phi(a: f64, current: f64, r: f64, z: f64) -> f64 {
    if r <= 0.0 {
        return 0.0;
    }
    let m = 4.0 * a * r / ((a + r) * (a + r) + z * z);
    // Small m: (1 − m/2) K − E = π m² / 32 (1 + 3m/4 + O(m²)) avoids the cancellation.
    let bracket = if m < 1e-4 {
        std::f64::consts::PI * m * m / 32.0 * (1.0 + 0.75 * m)
    } else {
        let (k, e) = elliptic_k_e(m);
        (1.0 - 0.5 * m) * k - e
    };
    MU_0 * current / (std::f64::consts::PI * m.sqrt()) * (a / r).sqrt() * bracket
}

/// Rectangular coil section `[r1, r2] × [z1, z2]` with current density `j` (A/m²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoilSection {
    /// Inner radius (m).
    pub r1: f64,
    /// Outer radius (m).
    pub r2: f64,
    /// Lower axial end (m).
    pub z1: f64,
    /// Upper axial end (m).
    pub z2: f64,
    /// Current density (A/m²).
    pub j: f64,
}

/// `A_phi` of the coil at `(r, z)` outside its section, by `panels² × 8²` Gauss points.
pub fn thick_coil_a_phi(coil: &CoilSection, r: f64, z: f64, panels: usize) -> f64 {
    let (points, dr, dz) = section_quadrature(coil, panels);
    let mut sum = 0.0;
    for (a, zc, weight) in points {
        sum += weight * loop_a_phi(a, 1.0, r, z - zc);
    }
    sum * coil.j * dr * dz
}

/// The quadrature of a coil section: `panels × panels` cells of 8 × 8 Gauss–Legendre points, as
/// `(r, z, w_r w_z)` in the unit cell's weights, and the cell sizes `(dr, dz)` (m) that scale them.
fn section_quadrature(coil: &CoilSection, panels: usize) -> (Vec<(f64, f64, f64)>, f64, f64) {
    let (x, w) = gauss_legendre_unit(8);
    let panels = panels.max(1);
    let (dr, dz) = ((coil.r2 - coil.r1) / panels as f64, (coil.z2 - coil.z1) / panels as f64);
    let mut out = Vec::with_capacity(panels * panels * x.len() * x.len());
    for pr in 0..panels {
        for pz in 0..panels {
            for (xr, wr) in x.iter().zip(&w) {
                for (xz, wz) in x.iter().zip(&w) {
                    let r = coil.r1 + dr * (pr as f64 + xr);
                    let z = coil.z1 + dz * (pz as f64 + xz);
                    out.push((r, z, wr * wz));
                }
            }
        }
    }
    (out, dr, dz)
}

/// `B_r` (T) at `(r, z)` of a loop of radius `a` at `z = 0` carrying `current` (A) (module docs;
/// 0 on the axis and in the loop's plane).
pub fn loop_b_r(a: f64, current: f64, r: f64, z: f64) -> f64 {
    if r <= 0.0 {
        return 0.0;
    }
    let outer = (a + r) * (a + r) + z * z;
    let (k, e) = elliptic_k_e(4.0 * a * r / outer);
    let bracket = -k + (a * a + r * r + z * z) / ((a - r) * (a - r) + z * z) * e;
    MU_0 * current * z / (2.0 * PI * r * outer.sqrt()) * bracket
}

/// Axial force (N) on a loop of radius `b` carrying `i2` (A) at height `d` above a coaxial loop of
/// radius `a` carrying `i1`: negative (towards it) when the currents flow the same way.
pub fn coaxial_loops_force_z(a: f64, i1: f64, b: f64, i2: f64, d: f64) -> f64 {
    -2.0 * PI * b * i2 * loop_b_r(a, i1, b, d)
}

/// Mutual inductance (H) of two coaxial loops of radii `a` and `b` at axial distance `d`
/// (Maxwell's formula, module docs).
pub fn coaxial_loops_mutual_inductance(a: f64, b: f64, d: f64) -> f64 {
    let m = 4.0 * a * b / ((a + b) * (a + b) + d * d);
    let k = m.sqrt();
    let (kk, ee) = elliptic_k_e(m);
    MU_0 * (a * b).sqrt() * ((2.0 / k - k) * kk - 2.0 / k * ee)
}

/// Axial force (N) on coil `on` in the field of coil `by` (disjoint sections), by `panels² × 8²`
/// Gauss points in each section: `∫∫ j_by j_on F_loops dS dS`.
pub fn thick_coils_force_z(by: &CoilSection, on: &CoilSection, panels: usize) -> f64 {
    // Each point as a loop carrying its share of the section's current.
    let points = |coil: &CoilSection| -> Vec<(f64, f64, f64)> {
        let (points, dr, dz) = section_quadrature(coil, panels);
        points.into_iter().map(|(r, z, w)| (r, z, w * dr * dz * coil.j)).collect()
    };
    let (sources, targets) = (points(by), points(on));
    let mut force = 0.0;
    for &(a, za, ia) in &sources {
        for &(b, zb, ib) in &targets {
            force += coaxial_loops_force_z(a, ia, b, ib, zb - za);
        }
    }
    force
}

/// On-axis `B_z` (T) of the coil at axial position `z`.
pub fn thick_coil_axis_bz(coil: &CoilSection, z: f64) -> f64 {
    let f = |u: f64| u * ((coil.r2 + coil.r2.hypot(u)) / (coil.r1 + coil.r1.hypot(u))).ln();
    0.5 * MU_0 * coil.j * (f(coil.z2 - z) - f(coil.z1 - z))
}

/// `A_phi` (Wb/m) at radius `r` of an infinitely long solenoid `r1 <= r <= r2` with current density `j`.
pub fn long_solenoid_a_phi(j: f64, r1: f64, r2: f64, r: f64) -> f64 {
    if r <= 0.0 {
        return 0.0;
    }
    let b0 = MU_0 * j * (r2 - r1);
    // ∫_0^s B_z(t) t dt.
    let flux_integral = |s: f64| {
        if s <= r1 {
            0.5 * b0 * s * s
        } else {
            let s = s.min(r2);
            0.5 * b0 * r1 * r1
                + MU_0 * j * (0.5 * r2 * (s * s - r1 * r1) - (s.powi(3) - r1.powi(3)) / 3.0)
        }
    };
    flux_integral(r) / r
}

/// `B_z` (T) at radius `r` of the infinitely long solenoid.
pub fn long_solenoid_bz(j: f64, r1: f64, r2: f64, r: f64) -> f64 {
    if r <= r1 {
        MU_0 * j * (r2 - r1)
    } else if r <= r2 {
        MU_0 * j * (r2 - r)
    } else {
        0.0
    }
}

/// `A_phi` at `(r, z)` for a sphere of radius `a` (centre at the origin) and relative permeability
/// `mu_r` in the uniform far field `b0 e_z`.
pub fn sphere_a_phi(b0: f64, mu_r: f64, a: f64, r: f64, z: f64) -> f64 {
    let rho = r.hypot(z);
    let k = (mu_r - 1.0) / (mu_r + 2.0);
    if rho <= a {
        0.5 * 3.0 * mu_r / (mu_r + 2.0) * b0 * r
    } else {
        0.5 * b0 * r + b0 * k * a.powi(3) * r / rho.powi(3)
    }
}

/// `J0(z)` and `J1(z)` for complex `z` by their power series (Abramowitz & Stegun 9.1.10):
/// `J_n(z) = (z/2)^n Σ_k (−z²/4)^k / (k! (n+k)!)`. Summed until the terms stop mattering; the
/// largest term is about `e^{|z|}/|z|`, so the result keeps about `16 − log10(e^{|z|})` digits:
/// enough (better than 1e-9 relative) for `|z| <= 20`, the range of the skin-effect tests.
pub fn bessel_j0_j1(z: num_complex::Complex64) -> (num_complex::Complex64, num_complex::Complex64) {
    let q = -z * z / 4.0;
    let (mut term0, mut term1) = (num_complex::Complex64::new(1.0, 0.0), z / 2.0);
    let (mut j0, mut j1) = (term0, term1);
    for k in 1..200 {
        let k = k as f64;
        term0 *= q / (k * k);
        term1 *= q / (k * (k + 1.0));
        j0 += term0;
        j1 += term1;
        if term0.norm() < 1e-18 * j0.norm().max(1e-300) && term1.norm() < 1e-18 * j1.norm() {
            break;
        }
    }
    (j0, j1)
}

/// The first `n` positive zeros `α_m` of `J0`: the first five from Abramowitz & Stegun Table
/// 9.5, the rest from McMahon's expansion (A&S 9.5.12) with `β = (m − 1/4)π`,
/// `α ≈ β + 1/(8β) − 124/(3 (8β)³) + 120928/(15 (8β)⁵)`, accurate to better than 1e-12 from the
/// sixth zero on.
pub fn bessel_j0_zeros(n: usize) -> Vec<f64> {
    const TABLE: [f64; 5] = [
        2.404_825_557_695_773,
        5.520_078_110_286_311,
        8.653_727_912_911_013,
        11.791_534_439_014_281,
        14.930_917_708_487_786,
    ];
    (1..=n)
        .map(|m| {
            if m <= TABLE.len() {
                return TABLE[m - 1];
            }
            let beta = (m as f64 - 0.25) * PI;
            let x = 8.0 * beta;
            beta + 1.0 / x - 124.0 / (3.0 * x.powi(3)) + 120_928.0 / (15.0 * x.powi(5))
        })
        .collect()
}

/// A long solid conductor (radius `a`, permeability `mu`, conductivity `sigma`) in a uniform
/// axial field `H0 e^{jωt}` at its surface: `H_z(r) = H0 J0(kr)/J0(ka)`, `k² = −jωμσ`
/// (the classical skin-effect solution, e.g. R. L. Stoll, *The Analysis of Eddy Currents*,
/// Clarendon 1974, ch. 2), so `A_phi(r) = μ H0 J1(kr)/(k J0(ka))` (from `r A = ∫ B_z r dr` and
/// `(x J1)' = x J0`) and the flux through the section is `Φ = 2π a A_phi(a)`. Returns `A_phi(r)`.
pub fn conducting_cylinder_potential(
    r: f64,
    a: f64,
    mu: f64,
    sigma: f64,
    omega: f64,
    h0: f64,
) -> num_complex::Complex64 {
    use num_complex::Complex64;
    if omega * sigma <= 0.0 {
        return Complex64::new(0.5 * mu * h0 * r, 0.0);
    }
    let k = (Complex64::new(0.0, -omega * mu * sigma)).sqrt();
    let (j0_ka, _) = bessel_j0_j1(k * a);
    let (_, j1_kr) = bessel_j0_j1(k * r);
    mu * h0 * j1_kr / (k * j0_ka)
}

/// The flux `Φ(t)` through a long conductor of radius `a` after a step of the surface field from
/// 0 to `H0` at `t = 0`: `Φ/Φ∞ = 1 − Σ_m (4/α_m²) exp(−α_m² t/τ)`, `τ = μσa²`, `Φ∞ = πa²μH0`
/// (the diffusion equation in a cylinder with a prescribed surface value, Carslaw & Jaeger,
/// *Conduction of Heat in Solids*, 2nd ed., §7.4, integrated over the section; `α_m` the zeros
/// of `J0`; `B_z` obeys the same equation with diffusivity `1/(μσ)`). `terms` zeros are
/// summed (the tail is below `exp(−α_terms² t/τ)`).
pub fn cylinder_step_flux(t: f64, a: f64, mu: f64, sigma: f64, h0: f64, terms: usize) -> f64 {
    let tau = mu * sigma * a * a;
    let tail: f64 = bessel_j0_zeros(terms)
        .iter()
        .map(|alpha| 4.0 / (alpha * alpha) * (-alpha * alpha * t / tau).exp())
        .sum();
    PI * a * a * mu * h0 * (1.0 - tail)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn elliptic_integrals_match_tables() {
        // A&S Table 17.1: K(0.5) = 1.854_074_677_301_372, E(0.5) = 1.350_643_881_047_675.
        let (k, e) = elliptic_k_e(0.5);
        assert!((k - 1.854_074_677_301_372).abs() < 1e-14);
        assert!((e - 1.350_643_881_047_675).abs() < 1e-14);
        let (k0, e0) = elliptic_k_e(0.0);
        let half_pi = std::f64::consts::FRAC_PI_2;
        assert!((k0 - half_pi).abs() < 1e-15 && (e0 - half_pi).abs() < 1e-15);
        // K(0.99) = 3.695_637_362_989_875.
        assert!((elliptic_k_e(0.99).0 - 3.695_637_362_989_875).abs() < 1e-12);
    }

    #[test]
    fn loop_far_field_is_a_dipole_and_axis_field_matches_biot_savart() {
        let (a, i) = (0.05, 2.0);
        // Far field: A = μ0 m sinθ / (4π ρ²), m = I π a².
        let (r, z) = (3.0, 4.0);
        let rho: f64 = 5.0;
        let dipole = MU_0 * i * std::f64::consts::PI * a * a * (r / rho)
            / (4.0 * std::f64::consts::PI * rho * rho);
        assert!((loop_a_phi(a, i, r, z) - dipole).abs() < 1e-3 * dipole);
        // Near the axis B_z ≈ 2A/r = μ0 I a² / (2 (a² + z²)^{3/2}).
        let (r, z) = (1e-5, 0.03);
        let bz = 2.0 * loop_a_phi(a, i, r, z) / r;
        let exact = MU_0 * i * a * a / (2.0 * (a * a + z * z).powf(1.5));
        assert!((bz - exact).abs() < 1e-6 * exact);
    }

    #[test]
    fn loop_force_is_the_mutual_inductance_gradient_and_b_r_the_potential_derivative() {
        let (a, b, i1, i2) = (0.02, 0.03, 3.0, -2.0);
        for d in [0.001, 0.01, 0.04, -0.02] {
            let h = 1e-7;
            let gradient = (coaxial_loops_mutual_inductance(a, b, d + h)
                - coaxial_loops_mutual_inductance(a, b, d - h))
                / (2.0 * h);
            let force = coaxial_loops_force_z(a, i1, b, i2, d);
            assert!((force - i1 * i2 * gradient).abs() < 1e-6 * force.abs(), "d = {d}");
            // B_r = −∂A/∂z.
            let b_r = -(loop_a_phi(a, i1, b, d + h) - loop_a_phi(a, i1, b, d - h)) / (2.0 * h);
            assert!((loop_b_r(a, i1, b, d) - b_r).abs() < 1e-6 * b_r.abs(), "d = {d}");
        }
        // Currents the same way attract: the upper loop is pulled down.
        assert!(coaxial_loops_force_z(a, 1.0, b, 1.0, 0.01) < 0.0);
        // Far apart, two dipoles: F = −3 μ0 m1 m2 / (2π d⁴).
        let d: f64 = 2.0;
        let dipoles = -3.0 * MU_0 * (PI * a * a) * (PI * b * b) / (2.0 * PI * d.powi(4));
        assert!((coaxial_loops_force_z(a, 1.0, b, 1.0, d) - dipoles).abs() < 1e-3 * dipoles.abs());
    }

    #[test]
    fn thick_coil_axis_matches_integrated_loops() {
        let coil = CoilSection { r1: 0.01, r2: 0.02, z1: -0.01, z2: 0.015, j: 1e6 };
        let z = 0.04;
        let r = 1e-6;
        let bz_from_a = 2.0 * thick_coil_a_phi(&coil, r, z, 2) / r;
        let bz = thick_coil_axis_bz(&coil, z);
        assert!((bz_from_a - bz).abs() < 1e-6 * bz, "{bz_from_a} vs {bz}");
    }

    #[test]
    fn solenoid_and_sphere_are_continuous() {
        let (j, r1, r2) = (1e6, 0.01, 0.02);
        for r in [r1, r2] {
            let below = long_solenoid_a_phi(j, r1, r2, r * (1.0 - 1e-9));
            let above = long_solenoid_a_phi(j, r1, r2, r * (1.0 + 1e-9));
            assert!((below - above).abs() < 1e-6 * below.abs());
        }
        let (b0, mu, a) = (0.1, 100.0, 0.02);
        let inside = sphere_a_phi(b0, mu, a, 0.6 * a, 0.8 * a * (1.0 - 1e-12));
        let outside = sphere_a_phi(b0, mu, a, 0.6 * a, 0.8 * a * (1.0 + 1e-12));
        assert!((inside - outside).abs() < 1e-9 * inside);
    }
}
