//! Heat reports: the text of a `physics = "heat"` solve (its JSON is the serialised
//! `mrbrake_heat::problem_file::HeatReport`).

use std::fmt::Write;

use mrbrake_heat::problem_file::HeatReport;

/// The text report of a heat solve of `file`.
pub fn solve_text(report: &HeatReport, file: &str) -> String {
    let mut s = String::new();
    let kind = if report.transient.is_some() { "transient" } else { "steady" };
    let _ = writeln!(
        s,
        "{file}: {kind} heat conduction, P{} on {} nodes / {} elements ({} unknowns)",
        report.order, report.nodes, report.elements, report.unknowns
    );
    if let Some(t) = &report.transient {
        let end = t.time_s.last().copied().unwrap_or(0.0);
        let _ = writeln!(
            s,
            "  {:?} to t = {end} s in {} steps; largest energy imbalance {:.2e} W",
            t.scheme,
            t.time_s.len().saturating_sub(1),
            t.max_energy_imbalance_w
        );
    }
    if !report.probes.is_empty() {
        let _ = writeln!(s, "probes:");
        for p in &report.probes {
            let _ = writeln!(
                s,
                "  {:<20} r = {:8.3} mm  z = {:8.3} mm  T = {:8.2} °C",
                p.name,
                p.r * 1e3,
                p.z * 1e3,
                p.t_c
            );
        }
    }
    let _ = writeln!(s, "regions:\n  physical   mean T (°C)   max T (°C)   heat (W)");
    for r in &report.regions {
        let _ = writeln!(
            s,
            "  {:>8} {:>13.2} {:>12.2} {:>10.4}",
            r.physical, r.mean_t_c, r.max_t_c, r.heat_w
        );
    }
    let _ = writeln!(s, "boundaries:\n  physical   heat out (W)");
    for b in &report.boundaries {
        let _ = writeln!(s, "  {:>8} {:>14.4}", b.physical, b.heat_out_w);
    }
    let _ = writeln!(
        s,
        "energy balance: generated {:.4} W, generated − out{} = {:.2e} W",
        report.heat_generated_w,
        if report.transient.is_some() { " − stored" } else { "" },
        report.energy_balance_w
    );
    let _ = writeln!(
        s,
        "time: {:.3} s (read {:.3} s, solve {:.3} s)",
        report.timings_s.total, report.timings_s.read, report.timings_s.solve
    );
    s
}
