//! The text of `mrbrake fem solve` for magnetic problem files (magnetostatic, transient,
//! harmonic): the report a solve returns (`mrbrake_magnetics::problem_file::SolveReport`, whose
//! JSON is its serialisation) as the lines the CLI prints, lengths in mm. Heat files have theirs in
//! [`crate::heat`].

use std::fmt::Write as _;

use mrbrake_fem::workflow::time::Scheme;
use mrbrake_magnetics::dynamics::harmonic::HarmonicPoint;
use mrbrake_magnetics::dynamics::transient::TransientResult;
use mrbrake_magnetics::problem_file::dynamics::TransientReport;
use mrbrake_magnetics::problem_file::{DynamicsReport, SolveReport};

/// The text report of a magnetic solve of the problem named `name`.
pub fn solve_text(report: &SolveReport, name: &str) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{name}: {} nodes, {} triangles, {} unknowns (P{}); Newton {} iteration(s), converged: {}",
        report.nodes,
        report.elements,
        report.unknowns,
        report.order,
        report.newton_iterations,
        report.converged
    );
    for p in &report.probes {
        let _ = writeln!(
            out,
            "  probe {:<16} r = {:>9.4} mm  z = {:>9.4} mm  B_r = {:>9.5} T  B_z = {:>9.5} T  |B| = {:.5} T",
            p.name,
            p.r * 1e3,
            p.z * 1e3,
            p.b_r_t,
            p.b_z_t,
            p.b_abs_t
        );
    }
    for r in &report.regions {
        let _ = writeln!(
            out,
            "  region {:>4}: area {:.4e} m²  mean |B| {:.4} T  max |B| {:.4} T",
            r.physical, r.area_m2, r.mean_b_t, r.max_b_t
        );
    }
    write_coils_and_lines(report, &mut out);
    if let Some(dynamics) = &report.dynamics {
        write_dynamics(dynamics, &mut out);
    }
    let t = report.timings_s;
    let _ = writeln!(
        out,
        "  time: read {:.3} s, assemble {:.3} s, solve {:.3} s, post {:.3} s, total {:.3} s",
        t.read, t.assemble, t.solve, t.post, t.total
    );
    out
}

fn write_coils_and_lines(report: &SolveReport, out: &mut String) {
    for c in &report.coils {
        let _ = writeln!(
            out,
            "  coil {:>4}: flux linkage {:.5e} Wb  L = {:.5e} H  dλ/dI = {:.5e} H",
            c.physical, c.flux_linkage_wb, c.inductance_h, c.incremental_inductance_h
        );
    }
    for l in &report.lines {
        let max = l.points.iter().map(|p| p.b_abs_t).fold(0.0, f64::max);
        let _ = writeln!(out, "  line {}: {} samples, max |B| {max:.4} T", l.name, l.points.len());
    }
    let _ =
        writeln!(out, "  energy {:.5e} J, co-energy {:.5e} J", report.energy_j, report.coenergy_j);
}

/// The text of the dynamic part (conductivities, then the transient or harmonic table).
fn write_dynamics(dynamics: &DynamicsReport, out: &mut String) {
    let (conducting, insulating): (Vec<_>, Vec<_>) =
        dynamics.conductors.iter().partition(|c| c.conductivity_s_per_m > 0.0);
    for c in conducting {
        let _ = writeln!(
            out,
            "  conductivity, region {:>4}: {:.4e} S/m ({})",
            c.physical, c.conductivity_s_per_m, c.source
        );
    }
    if !insulating.is_empty() {
        let tags: Vec<String> = insulating.iter().map(|c| c.physical.to_string()).collect();
        let _ = writeln!(out, "  not conducting: region(s) {}", tags.join(", "));
    }
    if let Some(t) = &dynamics.transient {
        write_transient(t, dynamics.dynamics_s, out);
    }
    if let Some(points) = &dynamics.harmonic {
        let about = match (dynamics.harmonic_bias_a, dynamics.harmonic_bias_coils.as_slice()) {
            (Some(b), _) => format!("small-signal about the DC state at {b} A"),
            (None, []) => "linear about a = 0 (initial permeability)".to_string(),
            (None, coils) => {
                let each: Vec<String> = coils
                    .iter()
                    .map(|c| format!("coil {} at {} A", c.physical, c.current_a))
                    .collect();
                format!("small-signal about the DC state with {}", each.join(", "))
            }
        };
        write_harmonic(points, &about, dynamics.dynamics_s, out);
    }
}

/// Up to 11 time levels, evenly spread over the run, first and last included.
fn sample_levels(n: usize) -> Vec<usize> {
    let mut levels: Vec<usize> =
        (0..=10).map(|k| ((k * (n - 1)) as f64 / 10.0).round() as usize).collect();
    levels.dedup();
    levels
}

fn write_transient(t: &TransientReport, seconds: f64, out: &mut String) {
    let r = &t.result;
    let scheme = match t.scheme {
        Scheme::Bdf2 => "BDF2",
        Scheme::ImplicitEuler => "implicit Euler",
    };
    let _ = writeln!(
        out,
        "  transient ({scheme}): {} steps to t = {:.4e} s, Newton {} iteration(s) in all, {} \
         factorisation(s), {} rejected step(s), {seconds:.3} s",
        r.time_s.len() - 1,
        r.time_s.last().copied().unwrap_or(0.0),
        r.newton_iterations.iter().sum::<usize>(),
        r.factorizations,
        r.rejected_steps
    );
    let mut header = format!("  {:>11}", "t (s)");
    for c in &r.coils {
        let _ = write!(
            header,
            " {:>11} {:>11} {:>11}",
            format!("i{} (A)", c.physical),
            "λ (Wb)",
            "v (V)"
        );
    }
    for p in &r.probes {
        let _ = write!(header, " {:>11} {:>11}", format!("{} B_r", p.name), "B_z (T)");
    }
    let _ = writeln!(out, "{header} {:>11}", "eddy (W)");
    for n in sample_levels(r.time_s.len()) {
        let _ = write!(out, "  {:>11.4e}", r.time_s[n]);
        for c in &r.coils {
            let _ = write!(
                out,
                " {:>11.4e} {:>11.4e} {:>11.4e}",
                c.current_a[n], c.flux_linkage_wb[n], c.voltage_v[n]
            );
        }
        for p in &r.probes {
            let _ = write!(out, " {:>11.4e} {:>11.4e}", p.b_r_t[n], p.b_z_t[n]);
        }
        let _ = writeln!(out, " {:>11.4e}", r.eddy_loss_w[n]);
    }
    write_energy_balance(r, out);
}

/// Source energy against the change in stored energy plus the eddy loss over the run.
fn write_energy_balance(r: &TransientResult, out: &mut String) {
    let (Some(first), Some(last)) = (r.stored_energy_j.first(), r.stored_energy_j.last()) else {
        return;
    };
    let source = r.source_energy_j.last().copied().unwrap_or(0.0);
    let eddy = r.eddy_energy_j.last().copied().unwrap_or(0.0);
    let stored = last - first;
    let _ = writeln!(
        out,
        "  energy over the run: from the coils {source:.5e} J = stored {stored:.5e} J + eddy \
         losses {eddy:.5e} J (mismatch {:.3e} J)",
        source - stored - eddy
    );
}

fn write_harmonic(points: &[HarmonicPoint], about: &str, seconds: f64, out: &mut String) {
    let _ = writeln!(
        out,
        "  harmonic ({about}; peak phasors, time factor exp(+jωt)): {} frequencies, {seconds:.3} s",
        points.len()
    );
    for p in points {
        let _ = write!(out, "  f = {:>10.4e} Hz", p.frequency_hz);
        for c in &p.coils {
            let (re, im) = (c.impedance_ohm[0], c.impedance_ohm[1]);
            let lambda = c.flux_linkage_wb[0].hypot(c.flux_linkage_wb[1]);
            let _ = write!(
                out,
                "  coil {}: Z = {re:.4e} {im:+.4e}j Ω |λ| = {lambda:.4e} Wb",
                c.physical
            );
        }
        for probe in &p.probes {
            let b_z = probe.b_z_t[0].hypot(probe.b_z_t[1]);
            let _ = write!(out, "  {} |B_z| = {b_z:.4e} T", probe.name);
        }
        let _ = writeln!(out, "  eddy loss {:.4e} W", p.eddy_loss_w);
    }
}

#[cfg(test)]
mod tests {
    use mrbrake_magnetics::problem_file::dynamics::{CoilBias, ConductorReport};
    use mrbrake_magnetics::problem_file::{CoilReport, MagneticsTimings};

    use super::*;

    fn report(dynamics: Option<DynamicsReport>) -> SolveReport {
        SolveReport {
            probes: Vec::new(),
            regions: Vec::new(),
            coils: vec![CoilReport {
                physical: 3,
                flux_linkage_wb: 1e-3,
                inductance_h: 2e-3,
                incremental_inductance_h: 1.5e-3,
            }],
            lines: Vec::new(),
            energy_j: 1.0,
            coenergy_j: 1.5,
            newton_iterations: 4,
            converged: true,
            residual_history: vec![1.0, 1e-10],
            nodes: 10,
            elements: 12,
            order: 1,
            unknowns: 8,
            timings_s: MagneticsTimings::default(),
            dynamics,
        }
    }

    /// The static report: a header line, the coil, the energies and the timings.
    #[test]
    fn a_static_solve_has_its_header_coils_energy_and_time() {
        let text = solve_text(&report(None), "p.toml");
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(
            lines[0],
            "p.toml: 10 nodes, 12 triangles, 8 unknowns (P1); Newton 4 iteration(s), converged: true"
        );
        assert!(lines[1].starts_with("  coil    3: flux linkage 1.00000e-3 Wb"), "{text}");
        assert!(lines[3].starts_with("  time: read "), "{text}");
        assert!(text.ends_with('\n') && !text.ends_with("\n\n"));
    }

    /// A harmonic solve about a per-coil bias names every coil's current, and its table the
    /// time factor of its phasors.
    #[test]
    fn a_harmonic_solve_names_its_bias_and_time_factor() {
        let conductor = |physical, conductivity_s_per_m| ConductorReport {
            physical,
            conductivity_s_per_m,
            source: "file".into(),
        };
        let dynamics = DynamicsReport {
            conductors: vec![conductor(1, 5.8e6), conductor(2, 0.0)],
            transient: None,
            harmonic: Some(vec![HarmonicPoint {
                frequency_hz: 50.0,
                coils: Vec::new(),
                probes: Vec::new(),
                eddy_loss_w: 0.25,
            }]),
            harmonic_bias_a: None,
            harmonic_bias_coils: vec![
                CoilBias { physical: 3, current_a: 0.5 },
                CoilBias { physical: 4, current_a: 0.0 },
            ],
            harmonic_potentials: Vec::new(),
            dynamics_s: 0.1,
        };
        let text = solve_text(&report(Some(dynamics)), "p.toml");
        assert!(text.contains("conductivity, region    1: 5.8000e6 S/m (file)"), "{text}");
        assert!(text.contains("not conducting: region(s) 2"), "{text}");
        assert!(text.contains("coil 3 at 0.5 A, coil 4 at 0 A"), "{text}");
        assert!(text.contains("time factor exp(+jωt)): 1 frequencies"), "{text}");
        assert!(text.contains("eddy loss 2.5000e-1 W"), "{text}");
    }
}
