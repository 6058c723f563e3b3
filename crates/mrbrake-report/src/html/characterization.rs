//! The HTML report of a characterisation (`mrbrake report --log LOG.csv [--frd FRD.csv]`): the
//! hysteresis loop with its branch fits (thesis §5.3.1, Figure 5.6), the inverse model the
//! controller uses (current for a desired torque on each branch), and with frequency-response
//! data the Bode diagram with the fitted transfer function (§5.3.2).
//!
//! Every number in its tables is a value of [`CharacterizationPage::json`]:
//! `{"characterization": …, "transfer_function": …}`, the documents `mrbrake characterize --json`
//! and `mrbrake tfest --json` print for the same inputs.

use mrbrake_control::Branch;
use mrbrake_sysid::request::TransferFunctionFit;
use serde_json::{Value, json};

use super::writer::{Cell, Table};
use super::{Page, Section, figure, inline_svg, png_figure};
use crate::ReportError;
use crate::bode::bode_figure;
use crate::chart::{Figure, Panel, Series, SeriesLabelPosition};
use crate::hysteresis::hysteresis_figure;
use crate::identification::{CharacterizationReport, tfest_bode_curves};

/// A characterisation to report.
#[derive(Debug, Clone, Copy)]
pub struct CharacterizationPage<'a> {
    /// The characterisation and its log.
    pub report: CharacterizationReport<'a>,
    /// The log's current samples, A.
    pub current_a: &'a [f64],
    /// The log's torque samples, N·m.
    pub torque_nm: &'a [f64],
    /// The frequency response and its fitted transfer function, if given
    /// ([`mrbrake_sysid::request`]).
    pub frequency: Option<&'a TransferFunctionFit>,
}

/// Points of the inverse-model curves.
const INVERSE_POINTS: usize = 120;

impl CharacterizationPage<'_> {
    /// The JSON document the page's numbers point into.
    pub fn json(&self) -> Result<Value, ReportError> {
        let tf = match &self.frequency {
            Some(f) => serde_json::to_value(&f.summary)?,
            None => Value::Null,
        };
        Ok(json!({ "characterization": self.report.json()?, "transfer_function": tf }))
    }

    /// The HTML page.
    pub fn html(self) -> Result<String, ReportError> {
        let r = &self.report;
        let mut facts = vec![format!(
            "Log {} ({} samples, {:.1} Hz).",
            r.log.display(),
            r.samples,
            r.sample_rate_hz
        )];
        if let Some(f) = &self.frequency {
            facts.push(format!(
                "Frequency response {} ({} frequencies).",
                f.frd_path.display(),
                f.frd.len()
            ));
        }
        let mut sections = vec![self.loop_section()?, self.fits_section(), self.inverse_section()?];
        if let Some(f) = &self.frequency {
            sections.push(frequency_section(f)?);
        }
        Ok(Page { title: "Brake characterisation".into(), facts, sections }.render())
    }

    fn loop_section(&self) -> Result<Section, ReportError> {
        let c = self.report.characterization;
        let mut s = Section::new("loop", "Hysteresis loop");
        let title = format!("Torque–current loop ({} repetitions)", c.repetitions);
        let plot = self.report.hysteresis_plot(self.current_a, self.torque_nm);
        let fig = hysteresis_figure(&title, &plot);
        png_figure(
            &mut s.body,
            &fig.to_png()?,
            fig.size,
            &title,
            "Raw samples, the repetition-averaged rising and falling branches and their polynomial fits (thesis Figure 5.6).",
        );
        let mut t = Table::new("The loop", &["quantity", "value", "unit"]);
        for (what, v, d, p, unit) in [
            ("repetitions", c.repetitions as f64, 0, "/characterization/repetitions", "–"),
            ("lowest current", c.current_min_a, 4, "/characterization/current_min_A", "A"),
            ("highest current", c.current_max_a, 4, "/characterization/current_max_A", "A"),
            (
                "off-state torque (thesis 0.15 N·m)",
                c.off_state_torque_nm,
                4,
                "/characterization/off_state_torque_Nm",
                "N·m",
            ),
            (
                "largest torque of the fits (thesis 3.84 N·m at 2 A)",
                c.max_torque_nm,
                4,
                "/characterization/max_torque_Nm",
                "N·m",
            ),
            (
                "widest hysteresis",
                c.max_hysteresis_nm,
                4,
                "/characterization/max_hysteresis_Nm",
                "N·m",
            ),
            (
                "… at the current",
                c.max_hysteresis_current_a,
                3,
                "/characterization/max_hysteresis_current_A",
                "A",
            ),
        ] {
            t.row(vec![Cell::text(what), Cell::json(v, d, p, 1.0), Cell::text(unit)]);
        }
        s.body.table(&t);
        Ok(s)
    }

    fn fits_section(&self) -> Section {
        let c = self.report.characterization;
        let mut s = Section::new("fits", "Branch fits");
        let order = c.rising.coefficients.len().max(c.falling.coefficients.len());
        let mut headers: Vec<String> = vec![
            "branch".into(),
            "fit, raw [%]".into(),
            "fit, averaged [%]".into(),
            "samples".into(),
        ];
        headers.extend((0..order).map(|k| format!("c{k} [N·m/A^{k}]")));
        let headers: Vec<&str> = headers.iter().map(String::as_str).collect();
        let mut t = Table::new(
            "T(I) = Σ cₖ Iᵏ, ascending powers of the current in A (the inverse-model file's coefficients)",
            &headers,
        );
        for (name, b) in [("rising", &c.rising), ("falling", &c.falling)] {
            let at = |f: &str| format!("/characterization/{name}/{f}");
            let mut row = vec![
                Cell::text(name),
                Cell::json(b.fit_percent, 2, at("fit_percent"), 1.0),
                Cell::json(b.fit_percent_mean, 2, at("fit_percent_mean"), 1.0),
                Cell::json(b.samples as f64, 0, at("samples"), 1.0),
            ];
            row.extend(
                b.coefficients
                    .iter()
                    .enumerate()
                    .map(|(k, &v)| Cell::json(v, 6, at(&format!("coefficients/{k}")), 1.0)),
            );
            t.row(row);
        }
        s.body.table(&t);
        s.body.paragraph("Fit: 100·(1 − ‖T − T̂‖/‖T − mean T‖) over the branch's raw samples (all repetitions) and against the repetition-averaged branch.");
        s
    }

    fn inverse_section(&self) -> Result<Section, ReportError> {
        let c = self.report.characterization;
        let mut s = Section::new("inverse", "Inverse model");
        let model = match c.model() {
            Ok(m) => m,
            Err(e) => {
                s.body.paragraph(&format!(
                    "The branches do not make an inverse model the controller accepts: {e}"
                ));
                return Ok(s);
            }
        };
        let (lo, hi) = (c.off_state_torque_nm, c.max_torque_nm);
        let targets: Vec<f64> = (0..=INVERSE_POINTS)
            .map(|k| lo + (hi - lo) * k as f64 / INVERSE_POINTS as f64)
            .collect();
        let curve = |b: Branch| {
            targets.iter().map(|&t| (t, model.current_for(b, t, c.current_max_a))).collect()
        };
        let fig = Figure::new("Inverse model: the current for a desired torque").panel(
            Panel::new("desired torque [N·m]", "current [A]")
                .legend(SeriesLabelPosition::UpperLeft)
                .series(Series::line("rising branch (torque increasing)", curve(Branch::Rising)))
                .series(Series::dashed(
                    "falling branch (torque decreasing)",
                    curve(Branch::Falling),
                )),
        );
        figure(
            &mut s.body,
            &inline_svg(&fig.to_svg()?, "inverse model")?,
            "The controller's compensation: on the branch the torque is moving along, the current whose fitted torque is the desired one.",
        );
        let mut t = Table::new(
            "Current for a desired torque (controller's inverse, mrbrake_control::InverseModel)",
            &["desired torque [N·m]", "rising [A]", "falling [A]"],
        );
        for k in 0..=5 {
            let target = lo + (hi - lo) * k as f64 / 5.0;
            t.row(vec![
                Cell::number(target, 3),
                Cell::number(model.current_for(Branch::Rising, target, c.current_max_a), 4),
                Cell::number(model.current_for(Branch::Falling, target, c.current_max_a), 4),
            ]);
        }
        s.body.table(&t);
        Ok(s)
    }
}

/// The Bode diagram of the data and the fitted model, and the model's table.
fn frequency_section(f: &TransferFunctionFit) -> Result<Section, ReportError> {
    let sm = &f.summary;
    let mut s = Section::new("bode", "Frequency response and transfer function");
    let title = format!(
        "Estimated transfer function ({} poles, {} zeros, fit {:.2} %)",
        f.poles, f.zeros, f.fit.fit_percent
    );
    let fig = bode_figure(&title, &tfest_bode_curves(&f.frd, &f.fit));
    figure(
        &mut s.body,
        &inline_svg(&fig.to_svg()?, "Bode diagram")?,
        "Measured gain and phase (points) and the fitted model (line); the thesis's fit is 1/(1.791e-5 s² + 0.01702 s + 1), bandwidth 63 rad/s (§5.3.2).",
    );
    let mut t = Table::new("G(s) = N(s)/D(s), highest power first", &["quantity", "value", "unit"]);
    for (k, v) in sm.numerator.iter().enumerate() {
        t.row(vec![
            Cell::text(format!("numerator b{k}")),
            Cell::json(*v, 8, format!("/transfer_function/numerator/{k}"), 1.0),
            Cell::text("–"),
        ]);
    }
    for (k, v) in sm.denominator.iter().enumerate() {
        t.row(vec![
            Cell::text(format!("denominator a{k}")),
            Cell::json(*v, 8, format!("/transfer_function/denominator/{k}"), 1.0),
            Cell::text("–"),
        ]);
    }
    for (k, p) in sm.poles.iter().enumerate() {
        t.row(vec![
            Cell::text(format!("pole {} (real)", k + 1)),
            Cell::json(p[0], 3, format!("/transfer_function/poles/{k}/0"), 1.0),
            Cell::text("rad/s"),
        ]);
        t.row(vec![
            Cell::text(format!("pole {} (imaginary)", k + 1)),
            Cell::json(p[1], 3, format!("/transfer_function/poles/{k}/1"), 1.0),
            Cell::text("rad/s"),
        ]);
    }
    for (k, w) in sm.corner_frequencies_rad_s.iter().enumerate() {
        t.row(vec![
            Cell::text(format!("corner frequency {}", k + 1)),
            Cell::json(*w, 3, format!("/transfer_function/corner_frequencies_rad_s/{k}"), 1.0),
            Cell::text("rad/s"),
        ]);
    }
    match sm.bandwidth_rad_s {
        Some(b) => {
            _ = t.row(vec![
                Cell::text("bandwidth (−3 dB)"),
                Cell::json(b, 3, "/transfer_function/bandwidth_rad_s", 1.0),
                Cell::text("rad/s"),
            ])
        }
        None => {
            _ = t.row(vec![
                Cell::text("bandwidth (−3 dB)"),
                Cell::text("undefined"),
                Cell::text("rad/s"),
            ])
        }
    }
    t.row(vec![
        Cell::text("DC gain"),
        Cell::json(sm.dc_gain, 6, "/transfer_function/dc_gain", 1.0),
        Cell::text("–"),
    ]);
    t.row(vec![
        Cell::text("fit"),
        Cell::json(sm.fit_percent, 3, "/transfer_function/fit_percent", 1.0),
        Cell::text("%"),
    ]);
    t.row(vec![Cell::text("stable"), Cell::text(sm.stable.to_string()), Cell::text("")]);
    s.body.table(&t);
    Ok(s)
}
