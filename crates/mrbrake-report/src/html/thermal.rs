//! The heat section of a design report: the brake's temperatures, continuous current rating and
//! duty cycle, what heat does to it, the temperature map and the warm-up curve
//! ([`mrbrake_design::thermal`], the numbers of `mrbrake thermal --json`).

use mrbrake_design::thermal::{TemperatureField, ThermalResult};

use super::{Cell, Section, Table, figure, inline_svg};
use crate::ReportError;
use crate::field_map::scalar_map_svg;
use crate::thermal::{temperature_map, temperature_map_title, warmup_figure};

fn row(table: &mut Table, what: &str, value: Cell, unit: &str) {
    table.row(vec![Cell::text(what), value, Cell::text(unit)]);
}

/// The table of the run's numbers.
fn numbers(r: &ThermalResult) -> Table {
    let mut table = Table::new("Temperatures and rating", &["quantity", "value", "unit"]);
    if let Some(st) = &r.steady {
        row(&mut table, "coil hot spot, steady", Cell::number(st.coil_max_t_c, 1), "°C");
        row(&mut table, "coil mean, steady", Cell::number(st.coil_mean_t_c, 1), "°C");
        row(&mut table, "fluid max, steady", Cell::number(st.fluid_max_t_c, 1), "°C");
        row(&mut table, "housing max, steady", Cell::number(st.housing_max_t_c, 1), "°C");
        row(&mut table, "heat", Cell::number(st.heat_w, 2), "W");
    } else {
        row(&mut table, "steady state", Cell::text("none (thermal runaway)"), "");
    }
    row(&mut table, "continuous current", Cell::number(r.continuous_current_a, 3), "A");
    row(
        &mut table,
        "largest duty at the maximum current",
        Cell::number(r.max_duty_at_max_current, 3),
        "",
    );
    let to_limit = r.time_to_limit_s.map_or(Cell::text("not reached"), |t| Cell::number(t, 0));
    row(&mut table, "time to the insulation limit", to_limit, "s");
    if let Some(b) = &r.behaviour {
        row(&mut table, "coil resistance cold", Cell::number(b.coil_resistance_cold_ohm, 3), "Ω");
        row(&mut table, "coil resistance hot", Cell::number(b.coil_resistance_hot_ohm, 3), "Ω");
        row(
            &mut table,
            "off-state torque cold",
            Cell::number(b.off_state_torque_cold_nm * 1e3, 3),
            "mN·m",
        );
        row(
            &mut table,
            "off-state torque hot",
            Cell::number(b.off_state_torque_hot_nm * 1e3, 3),
            "mN·m",
        );
        let v = &b.voltage_drive;
        row(&mut table, "voltage drive: current hot", Cell::number(v.current_hot_a, 3), "A");
        row(&mut table, "voltage drive: torque cold", Cell::number(b.torque_cold_nm, 4), "N·m");
        row(&mut table, "voltage drive: torque hot", Cell::number(v.torque_hot_nm, 4), "N·m");
    }
    table
}

/// The section (anchor `heat`).
pub fn section(r: &ThermalResult, field: &TemperatureField) -> Result<Section, ReportError> {
    let mut s = Section::new("heat", "Heat: temperatures, warm-up and current rating");
    s.body.paragraph(&format!(
        "The device (air box dropped) with the coil's Joule loss I²R(T) at {:.3} A and duty {:.3}, \
         the winding homogenised (copper fill {:.3}), the outer surface cooled by {} convection \
         (h = {:.2} W/(m² K)) to {:.1} °C; insulation limit {:.0} °C.",
        r.current_a,
        r.duty,
        r.fill_factor,
        r.cooling.kind,
        r.cooling.h_w_per_m2k,
        r.ambient_c,
        r.limit_c
    ));
    s.body.table(&numbers(r));
    let title = temperature_map_title(r, field);
    let map = inline_svg(&scalar_map_svg(&temperature_map(&title, field))?, "temperature map")?;
    figure(&mut s.body, &map, "Temperature of the cross-section, with isotherms.");
    let warmup = inline_svg(&warmup_figure(r).to_svg()?, "warm-up curve")?;
    figure(&mut s.body, &warmup, "Coil hot spot during the warm-up from the ambient.");
    Ok(s)
}
