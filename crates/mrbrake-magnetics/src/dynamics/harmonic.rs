//! Time-harmonic magnetodynamics, linear or linearised about a DC operating point.
//!
//! With the time factor `exp(+jωt)` (a quantity `x(t) = Re(x̂ e^{jωt})`, `x̂` its peak phasor),
//! `∂/∂t → jω` and the field equation becomes the complex-symmetric system
//!
//! `(J + jω M_σ) â = Σ_k Î_k c_k`,
//!
//! where `J` is the Jacobian of the magnetostatic residual: for linear materials the stiffness
//! `K`; about a DC bias `a_0` (the static solution at the coils' bias currents) the tangent
//! matrix with the incremental reluctivity tensor `ν I + 2 dν/dB² B⊗B` (see [`crate::form`]),
//! which gives the small-signal (incremental) response of a saturated device, e.g. its Bode
//! diagram at a bias current (Meunier (ed.), *The FEM for Electromagnetic Modeling*, §5.4 for
//! the harmonic eddy-current problem; the small-signal linearisation is that of the Newton step).
//! Without a bias the Jacobian at `a = 0` (the initial permeability) is used.
//!
//! Coils are driven by their current amplitude `Î_k` (a voltage-driven coil is refused: the
//! impedance `Z_k = jω λ̂_k / Î_k` it reports gives the current of a voltage source with series
//! resistance `R` as `V̂/(R + Z)`). Constrained DOFs carry no harmonic part. Per frequency:
//! flux linkages `λ̂_k = 2π c_k · â`, impedances, B at probes, and the time-averaged eddy loss
//! `P = ½ ω² ∫ σ |â|² 2π r dr dz`.
//!
//! Two solvers ([`HarmonicMethod`]): by default the core's reduced-basis sweep
//! ([`mrbrake_fem::linalg::sweep`]: a few real shifted Cholesky factorisations for all frequencies, every
//! frequency's residual checked to [`SweepOptions::tolerance`], the energy-norm error bounded);
//! or one complex sparse LU per frequency ([`mrbrake_fem::linalg::lu::SparseLu`], symbolic analysis once),
//! the reference the sweep is validated against.

use std::time::Instant;

use mrbrake_fem::linalg::lu::SparseLu;
use mrbrake_fem::linalg::sweep::{SweepOptions, SweepReport, sweep};
use num_complex::Complex64;
use serde::Serialize;

use super::{Drive, Dynamics, TWO_PI};
use crate::MagneticsError;
use mrbrake_fem::mesh::locate::Probe;

/// One complex LU factorisation and solve per frequency.
fn direct_sweep(
    pattern: &mrbrake_fem::linalg::pattern::SymmetricPattern,
    jacobian: &[f64],
    mass: &[f64],
    rhs: &[f64],
    frequencies_hz: &[f64],
) -> Result<Vec<Vec<Complex64>>, MagneticsError> {
    let mut lu = SparseLu::<Complex64>::new(pattern)?;
    let mut out = Vec::with_capacity(frequencies_hz.len());
    for &f in frequencies_hz {
        let omega = TWO_PI * f;
        let upper: Vec<Complex64> =
            jacobian.iter().zip(mass).map(|(&k, &m)| Complex64::new(k, omega * m)).collect();
        lu.factorize_symmetric(&upper)?;
        let mut x: Vec<Complex64> = rhs.iter().map(|&r| Complex64::new(r, 0.0)).collect();
        lu.solve_in_place(&mut x)?;
        out.push(x);
    }
    Ok(out)
}

/// A complex value as `[re, im]` in the outputs.
pub type ReIm = [f64; 2];

fn re_im(z: Complex64) -> ReIm {
    [z.re, z.im]
}

/// A coil at one frequency.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HarmonicCoil {
    /// Physical tag of the coil region.
    pub physical: u32,
    /// Flux-linkage phasor (Wb, peak).
    #[serde(rename = "flux_linkage_Wb")]
    pub flux_linkage_wb: ReIm,
    /// Impedance `jω λ̂/Î` (Ω), without the winding's DC resistance.
    #[serde(rename = "impedance_ohm")]
    pub impedance_ohm: ReIm,
}

/// B at a probe at one frequency (peak phasors).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HarmonicProbe {
    /// Probe name.
    pub name: String,
    /// `B̂_r` (T).
    #[serde(rename = "B_r_T")]
    pub b_r_t: ReIm,
    /// `B̂_z` (T).
    #[serde(rename = "B_z_T")]
    pub b_z_t: ReIm,
}

/// The response at one frequency.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HarmonicPoint {
    /// Frequency (Hz).
    #[serde(rename = "frequency_Hz")]
    pub frequency_hz: f64,
    /// Every coil.
    pub coils: Vec<HarmonicCoil>,
    /// Every probe.
    pub probes: Vec<HarmonicProbe>,
    /// Time-averaged eddy loss (W).
    #[serde(rename = "eddy_loss_W")]
    pub eddy_loss_w: f64,
}

/// A harmonic solve's potentials: `â` (every DOF) at one frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct HarmonicPotential {
    /// Frequency (Hz).
    pub frequency_hz: f64,
    /// Real part of `â` (Wb/m).
    pub re: Vec<f64>,
    /// Imaginary part of `â` (Wb/m).
    pub im: Vec<f64>,
}

/// How a harmonic sweep is solved.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum HarmonicMethod {
    /// The reduced-basis sweep of [`mrbrake_fem::linalg::sweep`] (the default).
    Reduced(SweepOptions),
    /// One complex sparse LU per frequency (the reference).
    Direct,
}

impl Default for HarmonicMethod {
    fn default() -> Self {
        Self::Reduced(SweepOptions::default())
    }
}

impl Dynamics {
    /// The harmonic potentials at `frequencies_hz`, linearised about the static solution at the
    /// coils' `bias_a` currents (one per coil) when given, by the default method.
    pub fn harmonic_potentials(
        &mut self,
        frequencies_hz: &[f64],
        bias_a: Option<&[f64]>,
    ) -> Result<Vec<HarmonicPotential>, MagneticsError> {
        Ok(self.harmonic_potentials_by(frequencies_hz, bias_a, HarmonicMethod::default())?.0)
    }

    /// [`Self::harmonic_potentials`] by `method`, with the sweep's report (`None` for
    /// [`HarmonicMethod::Direct`]).
    pub fn harmonic_potentials_by(
        &mut self,
        frequencies_hz: &[f64],
        bias_a: Option<&[f64]>,
        method: HarmonicMethod,
    ) -> Result<(Vec<HarmonicPotential>, Option<SweepReport>), MagneticsError> {
        self.check_harmonic(frequencies_hz, bias_a)?;
        let jacobian = self.tangent_values(bias_a)?;
        let mass = self.conductivity_mass_values();
        let mut rhs = vec![0.0; self.solver.assembly.n_free()];
        for coil in &self.coils {
            let current = self.excitation(coil)?;
            rhs.iter_mut().zip(&coil.free).for_each(|(r, c)| *r += current * c);
        }
        let pattern = self.solver.assembly.pattern();
        let (solutions, report) = match method {
            HarmonicMethod::Reduced(options) => {
                let omegas: Vec<f64> = frequencies_hz.iter().map(|f| TWO_PI * f).collect();
                let (x, report) = sweep(pattern, &jacobian, &mass, &rhs, &omegas, &options)?;
                (x, Some(report))
            }
            HarmonicMethod::Direct => {
                (direct_sweep(pattern, &jacobian, &mass, &rhs, frequencies_hz)?, None)
            }
        };
        let constraints = self.solver.assembly.constraints();
        let out = frequencies_hz
            .iter()
            .zip(solutions)
            .map(|(&f, x)| HarmonicPotential {
                frequency_hz: f,
                re: constraints.extend_with_zeros(&x.iter().map(|z| z.re).collect::<Vec<_>>()),
                im: constraints.extend_with_zeros(&x.iter().map(|z| z.im).collect::<Vec<_>>()),
            })
            .collect();
        Ok((out, report))
    }

    /// The harmonic response (coils, probes, eddy loss) at `frequencies_hz`.
    pub fn harmonic(
        &mut self,
        frequencies_hz: &[f64],
        bias_a: Option<&[f64]>,
        probes: &[Probe],
    ) -> Result<(Vec<HarmonicPoint>, f64), MagneticsError> {
        let start = Instant::now();
        let potentials = self.harmonic_potentials(frequencies_hz, bias_a)?;
        let mut points = Vec::with_capacity(potentials.len());
        for p in &potentials {
            points.push(self.harmonic_point(p, probes)?);
        }
        Ok((points, start.elapsed().as_secs_f64()))
    }

    /// Coils, probes and eddy loss of one harmonic potential.
    pub fn harmonic_point(
        &self,
        p: &HarmonicPotential,
        probes: &[Probe],
    ) -> Result<HarmonicPoint, MagneticsError> {
        let omega = TWO_PI * p.frequency_hz;
        let mut coils = Vec::with_capacity(self.coils.len());
        for (k, coil) in self.coils.iter().enumerate() {
            let lambda = Complex64::new(self.flux_linkage(k, &p.re), self.flux_linkage(k, &p.im));
            let current = self.excitation(coil)?;
            let impedance = Complex64::new(0.0, omega) * lambda / current;
            coils.push(HarmonicCoil {
                physical: coil.coil.tag,
                flux_linkage_wb: re_im(lambda),
                impedance_ohm: re_im(impedance),
            });
        }
        let (re, im) = (self.solution(p.re.clone()), self.solution(p.im.clone()));
        let mut probe_values = Vec::with_capacity(probes.len());
        for probe in probes {
            let (b_re, b_im) =
                (self.solver.b_at(&re, probe.point)?, self.solver.b_at(&im, probe.point)?);
            probe_values.push(HarmonicProbe {
                name: probe.name.clone(),
                b_r_t: [b_re.b_r_t, b_im.b_r_t],
                b_z_t: [b_re.b_z_t, b_im.b_z_t],
            });
        }
        let eddy_loss_w = 0.5 * omega * omega * (self.eddy_loss(&p.re) + self.eddy_loss(&p.im));
        Ok(HarmonicPoint { frequency_hz: p.frequency_hz, coils, probes: probe_values, eddy_loss_w })
    }

    fn check_harmonic(
        &self,
        frequencies_hz: &[f64],
        bias_a: Option<&[f64]>,
    ) -> Result<(), MagneticsError> {
        if frequencies_hz.is_empty() {
            return Err(MagneticsError::field("frequencies", "harmonic: no frequencies"));
        }
        if let Some(f) = frequencies_hz.iter().find(|f| !(**f >= 0.0 && f.is_finite())) {
            let e = mrbrake_error::FieldError::out_of_range(
                "frequencies",
                format!("{f} Hz"),
                "finite, >= 0 Hz",
            );
            return Err(e.into());
        }
        if let Some(bias) = bias_a
            && (bias.len() != self.coils.len() || bias.iter().any(|b| !b.is_finite()))
        {
            return Err(MagneticsError::field(
                "bias",
                format!(
                    "harmonic: {} finite bias currents needed (one per coil), got {:?}",
                    self.coils.len(),
                    bias
                ),
            ));
        }
        Ok(())
    }

    /// The excitation phasor of a coil (its current amplitude).
    fn excitation(&self, coil: &super::CoilData) -> Result<f64, MagneticsError> {
        match coil.coil.drive {
            Drive::Current { amplitude_a } if amplitude_a.abs() > 0.0 => Ok(amplitude_a),
            Drive::Current { .. } => Err(MagneticsError::field(
                format!("coils[{}].current_A", coil.coil.tag),
                format!(
                    "coil {}: a harmonic solve needs a non-zero current amplitude",
                    coil.coil.tag
                ),
            )),
            Drive::Voltage { .. } => Err(MagneticsError::field(
                format!("coils[{}].drive", coil.coil.tag),
                format!(
                    "coil {}: harmonic solves drive coils by current (give current_A); the reported \
                 impedance Z gives a voltage drive's current V/(R + Z)",
                    coil.coil.tag
                ),
            )),
        }
    }

    /// The static Jacobian's values on the pattern at the bias (or at `a = 0`).
    fn tangent_values(&mut self, bias_a: Option<&[f64]>) -> Result<Vec<f64>, MagneticsError> {
        let a = match bias_a {
            Some(bias) => self.static_solution(bias)?.a_phi().to_vec(),
            None => vec![0.0; self.solver.dof_count()],
        };
        let assembly = &mut self.solver.assembly;
        let mut residual = vec![0.0; assembly.n_free()];
        let mut values = vec![0.0; assembly.pattern().nnz()];
        assembly.evaluate(&self.solver.form, &a, &mut residual, Some(&mut values));
        Ok(values)
    }

    /// `M_σ` on the pattern (no couplings: the open boundary is in the Jacobian).
    fn conductivity_mass_values(&self) -> Vec<f64> {
        let width = self.mass.len() / self.sigma.len().max(1);
        let scaled: Vec<f64> = self
            .mass
            .chunks_exact(width)
            .zip(&self.sigma)
            .flat_map(|(m, &s)| m.iter().map(move |v| s * v))
            .collect();
        let pattern = self.solver.assembly.pattern();
        let mut values = vec![0.0; pattern.nnz()];
        pattern.assemble(&scaled, &mut values);
        values
    }
}
