//! Closed-form temperatures of long cylinders (no axial variation) that the validation tests
//! compare with. References: Incropera, DeWitt, Bergman and Lavine, *Fundamentals of Heat and
//! Mass Transfer*, 6th ed. (2007), §3.3 and §3.5 (steady radial conduction), §5.6 (transient
//! series solution, eqs. 5.49–5.50), §5.3 (lumped capacitance, eq. 5.6); Carslaw and Jaeger,
//! *Conduction of Heat in Solids*, 2nd ed. (1959), §7.6 (cylinder with heat generation).

/// Solid cylinder of radius `radius`, uniform generation `q`, conductivity `k`, convection `h` to
/// `t_amb`: `T(r) = T_∞ + q R/(2h) + q (R² − r²)/(4k)` (Incropera eqs. 3.53 and 3.55 with the
/// surface energy balance).
pub fn solid_cylinder(r: f64, radius: f64, q: f64, k: f64, h: f64, t_amb: f64) -> f64 {
    t_amb + q * radius / (2.0 * h) + q * (radius * radius - r * r) / (4.0 * k)
}

/// Hollow cylinder `r1 ≤ r ≤ r2` with `T(r1) = t1`, `T(r2) = t2`:
/// `T = t1 + (t2 − t1) ln(r/r1)/ln(r2/r1)` (Incropera eq. 3.26).
pub fn hollow_cylinder(r: f64, r1: f64, r2: f64, t1: f64, t2: f64) -> f64 {
    t1 + (t2 - t1) * (r / r1).ln() / (r2 / r1).ln()
}

/// Two-layer composite cylinder: `r1..r2` with `k1`, `r2..r3` with `k2`, `T(r1) = t1`, convection
/// `h` to `t_amb` at `r3`. The heat per length `q' = (t1 − T_∞)/R'_tot` through the series of
/// resistances `ln(r2/r1)/(2πk1) + ln(r3/r2)/(2πk2) + 1/(2π r3 h)` (Incropera eq. 3.32); each
/// layer's profile is logarithmic.
pub fn composite_cylinder(
    r: f64,
    radii: [f64; 3],
    k: [f64; 2],
    h: f64,
    t1: f64,
    t_amb: f64,
) -> f64 {
    let [r1, r2, r3] = radii;
    let two_pi = 2.0 * std::f64::consts::PI;
    let resistance = (r2 / r1).ln() / (two_pi * k[0])
        + (r3 / r2).ln() / (two_pi * k[1])
        + 1.0 / (two_pi * r3 * h);
    let q = (t1 - t_amb) / resistance;
    if r <= r2 {
        t1 - q * (r / r1).ln() / (two_pi * k[0])
    } else {
        t1 - q * (r2 / r1).ln() / (two_pi * k[0]) - q * (r / r2).ln() / (two_pi * k[1])
    }
}

/// Solid cylinder with the Joule law `q(T) = q20 (1 + α (T − T20))` and convection `h` to
/// `t_amb` at `R`: with `θ = T − T20 + 1/α`, `k ∇²θ + q20 α θ = 0`, so `θ = A J0(m r)`,
/// `m = √(q20 α / k)`, and the surface balance gives `A = h θ_∞ / (h J0(mR) − k m J1(mR))`
/// (Carslaw and Jaeger §7.6 for a source linear in temperature). `None` when the denominator is
/// not positive, i.e. when `mR` reaches the first root `ζ1` of `ζ J1(ζ) = Bi J0(ζ)`,
/// `Bi = hR/k` (the fundamental mode of the cooling problem grows): thermal runaway, no steady
/// state.
pub fn joule_cylinder(
    r: f64,
    radius: f64,
    q20: f64,
    alpha: f64,
    t20: f64,
    k: f64,
    h: f64,
    t_amb: f64,
) -> Option<f64> {
    let m = (q20 * alpha / k).sqrt();
    if m * radius >= cylinder_eigenvalues(h * radius / k, 1)[0] {
        return None;
    }
    let denominator = h * libm::j0(m * radius) - k * m * libm::j1(m * radius);
    let theta_amb = t_amb - t20 + 1.0 / alpha;
    let a = h * theta_amb / denominator;
    Some(a * libm::j0(m * r) + t20 - 1.0 / alpha)
}

/// The first `n` positive roots of `ζ J1(ζ) = Bi J0(ζ)` (Incropera eq. 5.50), by bracketing on a
/// fine grid and bisection.
pub fn cylinder_eigenvalues(biot: f64, n: usize) -> Vec<f64> {
    let f = |z: f64| z * libm::j1(z) - biot * libm::j0(z);
    let mut roots = Vec::with_capacity(n);
    let (mut a, step) = (1e-9, 1e-2);
    while roots.len() < n {
        let b = a + step;
        if f(a).signum() != f(b).signum() {
            let (mut lo, mut hi) = (a, b);
            for _ in 0..100 {
                let mid = 0.5 * (lo + hi);
                if f(lo).signum() == f(mid).signum() { lo = mid } else { hi = mid }
            }
            roots.push(0.5 * (lo + hi));
        }
        a = b;
    }
    roots
}

/// Transient infinite cylinder, initially at `t0`, convection `h` to `t_amb` from `t = 0`:
/// `(T − T_∞)/(T0 − T_∞) = Σ C_n exp(−ζ_n² Fo) J0(ζ_n r/R)`, `C_n = 2 J1(ζ_n) / (ζ_n (J0²(ζ_n) +
/// J1²(ζ_n)))`, `Fo = κ t/R²` (Incropera eq. 5.49), summed over `eigenvalues` (the roots of
/// [`cylinder_eigenvalues`] for `Bi = hR/k`).
pub fn transient_cylinder(
    r: f64,
    t: f64,
    radius: f64,
    k: f64,
    rho_c: f64,
    t0: f64,
    t_amb: f64,
    eigenvalues: &[f64],
) -> f64 {
    let fourier = k / rho_c * t / (radius * radius);
    let sum: f64 = eigenvalues
        .iter()
        .map(|&z| {
            let (j0, j1) = (libm::j0(z), libm::j1(z));
            2.0 * j1 / (z * (j0 * j0 + j1 * j1))
                * (-z * z * fourier).exp()
                * libm::j0(z * r / radius)
        })
        .sum();
    t_amb + (t0 - t_amb) * sum
}

/// Lumped capacitance of a cylinder (valid for `Bi ≪ 1`): `T = T_∞ + (T0 − T_∞) exp(−t/τ)`,
/// `τ = ρc V/(h A) = ρc R/(2h)` (Incropera eq. 5.6).
pub fn lumped_cylinder(t: f64, radius: f64, rho_c: f64, h: f64, t0: f64, t_amb: f64) -> f64 {
    t_amb + (t0 - t_amb) * (-t * 2.0 * h / (rho_c * radius)).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eigenvalues_match_incropera_table_5_1() {
        // Incropera Table 5.1, infinite cylinder: Bi = 1.0 → ζ1 = 1.2558, C1 = 1.2071.
        let z = cylinder_eigenvalues(1.0, 2);
        assert!((z[0] - 1.2558).abs() < 1e-4, "{z:?}");
        let (j0, j1) = (libm::j0(z[0]), libm::j1(z[0]));
        let c1 = 2.0 * j1 / (z[0] * (j0 * j0 + j1 * j1));
        assert!((c1 - 1.2071).abs() < 1e-4, "{c1}");
    }

    #[test]
    fn joule_cylinder_tends_to_the_constant_source_for_small_alpha() {
        let (radius, q, k, h, ta) = (0.01, 1e6, 1.0, 50.0, 300.0);
        let with = joule_cylinder(0.003, radius, q, 1e-9, 293.15, k, h, ta).unwrap();
        let without = solid_cylinder(0.003, radius, q, k, h, ta);
        assert!((with - without).abs() < 1e-4, "{with} vs {without}");
        let series = transient_cylinder(
            0.0,
            1e9,
            radius,
            k,
            1e6,
            400.0,
            ta,
            &cylinder_eigenvalues(h * radius / k, 5),
        );
        assert!((series - ta).abs() < 1e-9);
    }
}
