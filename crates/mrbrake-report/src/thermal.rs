//! Presentation of a brake's thermal analysis ([`mrbrake_design::thermal`], `mrbrake thermal`):
//! the text summary (its JSON is the serialised `ThermalResult`), the temperature map of the
//! cross-section and the warm-up curve.

use std::fmt::Write as _;
use std::path::Path;

use mrbrake_design::thermal::behaviour::HotBehaviour;
use mrbrake_design::thermal::{TemperatureField, ThermalResult};

use crate::ReportError;
use crate::chart::{Figure, Panel, Series};
use crate::field_map::{ScalarMap, save_scalar_map};

/// The text summary of `r` for the design read from `source`.
pub fn text(r: &ThermalResult, source: &str) -> String {
    let mut s = String::new();
    let _ = writeln!(
        s,
        "thermal analysis ({source}): {:.3} A at duty {:.3}, ambient {:.1} °C, insulation limit {:.0} °C",
        r.current_a, r.duty, r.ambient_c, r.limit_c
    );
    let c = &r.cooling;
    let _ = match (c.h_side_w_per_m2k, c.h_ends_w_per_m2k, c.rayleigh_d) {
        (Some(side), Some(ends), Some(ra)) => writeln!(
            s,
            "cooling: natural convection, axis horizontal (D {:.1} mm, L {:.1} mm): h {:.2} W/(m² K) \
             (side {side:.2}, ends {ends:.2}, Ra_D {ra:.3e})",
            c.diameter_m * 1e3,
            c.length_m * 1e3,
            c.h_w_per_m2k
        ),
        _ => writeln!(
            s,
            "cooling: {} h {:.2} W/(m² K) on the whole outer surface",
            c.kind, c.h_w_per_m2k
        ),
    };
    let _ = writeln!(
        s,
        "coil: R20 {:.3} Ω, copper fill factor {:.3}; mesh {} nodes\n",
        r.coil_resistance_20c_ohm, r.fill_factor, r.nodes
    );
    steady_text(&mut s, r);
    let _ = writeln!(
        s,
        "\ncontinuous current (steady hot spot = {:.0} °C): {:.3} A",
        r.limit_c, r.continuous_current_a
    );
    let _ = writeln!(
        s,
        "largest duty cycle at the maximum current {:.3} A: {:.3}",
        r.max_current_a, r.max_duty_at_max_current
    );
    warmup_text(&mut s, r);
    if let Some(b) = &r.behaviour {
        behaviour_text(&mut s, r, b);
    }
    let _ = write!(s, "\ntime: {:.2} s", r.timings_s.total);
    s
}

fn steady_text(s: &mut String, r: &ThermalResult) {
    let Some(st) = &r.steady else {
        let _ = writeln!(
            s,
            "steady state: none (thermal runaway: the Joule loss grows faster with temperature than \
             the housing removes it)"
        );
        return;
    };
    let _ = writeln!(s, "steady state:");
    let rows = [
        ("coil hot spot", st.coil_max_t_c),
        ("coil mean", st.coil_mean_t_c),
        ("fluid max", st.fluid_max_t_c),
        ("fluid mean", st.fluid_mean_t_c),
        ("housing max", st.housing_max_t_c),
        ("housing mean", st.housing_mean_t_c),
    ];
    for (name, t) in rows {
        let _ = writeln!(s, "  {name:<14} {t:>8.1} °C");
    }
    let _ = writeln!(
        s,
        "  heat {:.3} W, coil resistance {:.3} Ω (at its mean temperature), energy balance {:.1e} W",
        st.heat_w, st.coil_resistance_ohm, st.energy_balance_w
    );
}

fn warmup_text(s: &mut String, r: &ThermalResult) {
    let w = &r.warmup;
    let end = w.time_s.last().copied().unwrap_or(0.0);
    let _ = writeln!(s, "\nwarm-up from {:.1} °C (coil hot spot):", r.ambient_c);
    let marks = [60.0, 600.0, 1800.0, 3600.0, 7200.0, end];
    let mut last = f64::NAN;
    for &mark in marks.iter().filter(|&&m| m <= end) {
        let k = w.time_s.iter().position(|&t| t >= mark - 1e-9).unwrap_or(w.time_s.len() - 1);
        if (w.time_s[k] - last).abs() < 1e-9 {
            continue;
        }
        last = w.time_s[k];
        let _ = writeln!(s, "  t = {:>7.0} s  {:>8.1} °C", w.time_s[k], w.coil_max_t_c[k]);
    }
    let _ = match r.time_to_limit_s {
        Some(t) => {
            writeln!(s, "  reaches {:.0} °C after {:.0} s ({:.1} min)", r.limit_c, t, t / 60.0)
        }
        None => writeln!(s, "  does not reach {:.0} °C within {:.0} s", r.limit_c, end),
    };
}

fn behaviour_text(s: &mut String, r: &ThermalResult, b: &HotBehaviour) {
    let v = &b.voltage_drive;
    let _ =
        writeln!(s, "\nwhat heat does to the brake (steady state, cold = {:.1} °C):", r.ambient_c);
    let _ = writeln!(
        s,
        "  fluid viscosity {:.4} Pa·s at {:.1} °C -> {:.4} Pa·s at {:.1} °C (Andrade, B = {:.0} K, trust {:?})",
        b.viscosity_cold.pa_s,
        b.viscosity_cold.temperature_c,
        b.viscosity_hot.pa_s,
        b.viscosity_hot.temperature_c,
        b.viscosity_hot.activation_temperature_k,
        b.viscosity_hot.provenance.trust
    );
    let _ = writeln!(
        s,
        "  off-state torque at {:.3} rad/s: {:.3} mN·m cold -> {:.3} mN·m hot",
        b.speed_rad_s,
        b.off_state_torque_cold_nm * 1e3,
        b.off_state_torque_hot_nm * 1e3
    );
    let _ = writeln!(
        s,
        "  coil: {:.3} Ω, {:.2} W cold -> {:.3} Ω, {:.2} W hot (at {:.3} A when on)",
        b.coil_resistance_cold_ohm,
        b.coil_power_cold_w,
        b.coil_resistance_hot_ohm,
        b.coil_power_hot_w,
        r.current_a
    );
    let _ = writeln!(
        s,
        "  current drive: torque {:.4} N·m cold, {:.4} N·m hot",
        b.torque_cold_nm, b.torque_hot_current_drive_nm
    );
    let _ = writeln!(
        s,
        "  voltage drive {:.3} V: current {:.3} A hot (coil mean {:.1} °C, hot spot {:.1} °C), \
         torque {:.4} N·m ({:+.1} %)",
        v.voltage_v,
        v.current_hot_a,
        v.coil_mean_t_c,
        v.coil_max_t_c,
        v.torque_hot_nm,
        v.torque_change_percent
    );
}

/// The warm-up figure: the coil's hot spot against time, with the insulation limit.
pub fn warmup_figure(r: &ThermalResult) -> Figure {
    let w = &r.warmup;
    let points: Vec<(f64, f64)> =
        w.time_s.iter().zip(&w.coil_max_t_c).map(|(t, c)| (t / 60.0, *c)).collect();
    let end = w.time_s.last().copied().unwrap_or(0.0) / 60.0;
    let mut panel = Panel::new("time [min]", "coil hot spot [°C]")
        .series(Series::line(format!("{:.2} A, duty {:.2}", r.current_a, r.duty), points).color(0));
    panel = panel.series(
        Series::dashed(
            format!("insulation limit {:.0} °C", r.limit_c),
            vec![(0.0, r.limit_c), (end, r.limit_c)],
        )
        .color(3),
    );
    if let Some(st) = &r.steady {
        panel = panel.series(
            Series::dashed(
                format!("steady {:.0} °C", st.coil_max_t_c),
                vec![(0.0, st.coil_max_t_c), (end, st.coil_max_t_c)],
            )
            .color(1),
        );
    }
    Figure::new("warm-up of the coil").panel(panel)
}

/// The title of the temperature map.
pub fn temperature_map_title(r: &ThermalResult, field: &TemperatureField) -> String {
    format!("temperature, {} at {:.2} A, duty {:.2}", field.state, r.current_a, r.duty)
}

/// The temperature map of `field` titled `title`.
pub fn temperature_map<'a>(title: &'a str, field: &'a TemperatureField) -> ScalarMap<'a> {
    ScalarMap {
        title,
        nodes: &field.nodes,
        triangles: &field.triangles,
        region_tags: &field.region_tags,
        values: &field.t_c,
        label: "T [°C]",
        levels: 8,
        window: None,
    }
}

/// Writes `temperature_map.svg` and `warmup.svg` into `dir` (and PNG copies with `png`).
pub fn write_plots(
    r: &ThermalResult,
    field: &TemperatureField,
    dir: &Path,
    png: bool,
) -> Result<(), ReportError> {
    let title = temperature_map_title(r, field);
    let map = temperature_map(&title, field);
    let figure = warmup_figure(r);
    for ext in if png { &["svg", "png"][..] } else { &["svg"][..] } {
        save_scalar_map(&map, &dir.join(format!("temperature_map.{ext}")))?;
        figure.save(&dir.join(format!("warmup.{ext}")))?;
    }
    Ok(())
}
