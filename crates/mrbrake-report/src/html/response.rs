//! The dynamics section of a design report: the predicted step response and Bode diagram
//! ([`mrbrake_design::response`]), with the thesis's measured transfer functions for the embedded
//! default, and the eddy-current density map when the response kept one.

use mrbrake_design::response::Response;

use super::{Cell, Section, Table, figure, inline_svg};
use crate::ReportError;
use crate::bode::bode_figure;
use crate::field_map::scalar_map_svg;
use crate::response::{BODE_TITLE, EddyMap, bode_curves, step_figure};

/// The section (anchor `dynamics`).
pub fn section(r: &Response, thesis: bool) -> Result<Section, ReportError> {
    let mut s = Section::new("dynamics", "Dynamics: step and frequency response");
    s.body.paragraph(&format!(
        "Predicted from the design: eddy currents in the solid flux path (steel conductivity {:.2} \
         MS/m, {}), the coil driven by a {} source, a fluid lag of {:.2} ms. The frequency response \
         is the small-signal torque per current about {:.2} A, normalised by its DC gain.",
        r.flux_path_conductivity_s_per_m / 1e6,
        r.conductivity_source,
        match r.drive {
            mrbrake_design::response::ResponseDrive::Current => "current",
            mrbrake_design::response::ResponseDrive::Voltage => "voltage",
        },
        r.fluid_lag_s * 1e3,
        r.bias_a
    ));
    let mut table = Table::new("Predicted dynamics", &["quantity", "value", "unit"]);
    for step in &r.step {
        let d = step.direction;
        let ms = |t: Option<f64>| t.map_or(Cell::text("not reached"), |t| Cell::number(t * 1e3, 2));
        table.row(vec![
            Cell::text(format!("t63, direction {d}")),
            ms(step.t63_s),
            Cell::text("ms"),
        ]);
        table.row(vec![
            Cell::text(format!("t90, direction {d}")),
            ms(step.t90_s),
            Cell::text("ms"),
        ]);
    }
    table.row(vec![
        Cell::text("bandwidth (−3 dB)"),
        r.bandwidth_rad_s.map_or(Cell::text("above 1000"), |w| Cell::number(w, 1)),
        Cell::text("rad/s"),
    ]);
    table.row(vec![
        Cell::text("DC gain dT/dI"),
        Cell::number(r.dc_gain_nm_per_a, 4),
        Cell::text("N·m/A"),
    ]);
    if thesis {
        table.row(vec![
            Cell::text("thesis bandwidth, measured (5.3.2)"),
            Cell::number(63.0, 1),
            Cell::text("rad/s"),
        ]);
    }
    s.body.table(&table);
    let step = inline_svg(&step_figure(r).to_svg()?, "predicted torque step response")?;
    figure(
        &mut s.body,
        &step,
        "Torque after a current step (yield torque from B(t) in the gaps, then the fluid lag).",
    );
    let bode =
        inline_svg(&bode_figure(BODE_TITLE, &bode_curves(r, thesis)?).to_svg()?, "Bode diagram")?;
    let caption = if thesis {
        "Predicted small-signal response against the thesis's measured transfer functions (5.5), (5.6)."
    } else {
        "Predicted small-signal response."
    };
    figure(&mut s.body, &bode, caption);
    if let Some(field) = &r.eddy {
        let map = EddyMap::new(field)?;
        let svg = inline_svg(&scalar_map_svg(&map.scalar_map())?, "eddy-current density map")?;
        figure(
            &mut s.body,
            &svg,
            &format!(
                "Induced current density J_φ = −σ ∂A/∂t in the conducting parts {:.2} ms into the \
                 direction-{} step.",
                field.time_s * 1e3,
                field.direction
            ),
        );
    }
    Ok(s)
}
