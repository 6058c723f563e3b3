//! The uncertainty section of a design report: a propagation of `mrbrake uncertainty` (run with
//! the report or saved with `--json`, read back as an [`UncertaintyDocument`]): the declared
//! inputs, every output's band, the torque–current band with measured points (and whether each
//! falls inside the band), the tornado chart and the Sobol' indices of every output.

use super::{Cell, Section, Table, figure, inline_svg};
use crate::ReportError;
use mrbrake_explore::uncertainty::band::torque_at;

use crate::uncertainty::document::{BandEntry, UncertaintyDocument};
use crate::uncertainty::plots::{Measured, Tornado, band_figure};

/// The section (anchor `uncertainty`); `source` says where the propagation comes from.
pub fn section(
    doc: &UncertaintyDocument,
    source: &str,
    measured: Option<&Measured>,
) -> Result<Section, ReportError> {
    let mut s = Section::new("uncertainty", "Uncertainty: bands and sensitivities");
    s.body.paragraph(&format!(
        "{} scrambled Sobol' samples of the declared inputs, each a full analysis ({} in the \
         statistics, {} left out{}), from {source}. Bands are the samples' 5 %, 50 % and 95 % \
         points; the sensitivities are Sobol' indices of a polynomial-chaos surrogate fitted to \
         the same samples, with bootstrap 95 % intervals.",
        doc.samples,
        doc.evaluated,
        doc.left_out,
        doc.left_out_reason.as_ref().map_or(String::new(), |r| format!("; first reason: {r}")),
    ));
    s.body.table(&inputs_table(doc));
    s.body.table(&outputs_table(doc));
    if !doc.torque_band.is_empty() {
        let title = "torque–current band";
        let svg = inline_svg(&band_figure(doc, title, measured)?.to_svg()?, title)?;
        figure(
            &mut s.body,
            &svg,
            "The samples' torque at each current: 5–95 % shaded, the median, the nominal design.",
        );
        if let Some(m) = measured {
            s.body.paragraph(&measured_verdicts(doc, m));
        }
    }
    if let Some(metric) = doc.main_metric() {
        let svg = inline_svg(&Tornado::new(doc, metric)?.to_svg()?, "tornado chart")?;
        let caption = format!(
            "What explains the variance of {metric}: the first-order index is an input's share \
             alone, the total index with its interactions."
        );
        figure(&mut s.body, &svg, &caption);
    }
    s.body.table(&sobol_table(doc));
    Ok(s)
}

fn inputs_table(doc: &UncertaintyDocument) -> Table {
    let mut t = Table::new("Uncertain inputs", &["input", "law", "mean", "std", "unit"]);
    for i in &doc.inputs {
        t.row(vec![
            Cell::text(&i.name),
            Cell::text(&i.distribution),
            Cell::number(i.moments.mean, 6),
            Cell::number(i.moments.std, 6),
            Cell::text(&i.unit),
        ]);
    }
    t
}

fn outputs_table(doc: &UncertaintyDocument) -> Table {
    let headers = ["metric", "nominal", "mean", "std", "5 %", "50 %", "95 %"];
    let mut t = Table::new("Outputs (each in its metric's unit)", &headers);
    for (metric, o) in &doc.outputs {
        let nominal = o.nominal.map_or(Cell::text("—"), |v| Cell::number(v, 5));
        let values = [o.mean, o.std, o.p5, o.p50, o.p95].map(|v| Cell::number(v, 5));
        t.row([vec![Cell::text(metric), nominal], values.to_vec()].concat());
    }
    t
}

fn sobol_table(doc: &UncertaintyDocument) -> Table {
    let headers = ["output", "input", "first", "95 % interval", "total", "95 % interval"];
    let mut t = Table::new("Sobol' indices", &headers);
    let interval = |ci: [f64; 2]| Cell::text(format!("{:.3} – {:.3}", ci[0], ci[1]));
    for metric in doc.sobol.keys() {
        let loo = doc
            .surrogates
            .get(metric)
            .map_or(String::new(), |s| format!(" (LOO error {:.3})", s.loo_error));
        let mut ranked = doc.indices(metric).unwrap_or_default();
        ranked.sort_by(|a, b| b.1.total.total_cmp(&a.1.total));
        for (input, ix) in ranked {
            t.row(vec![
                Cell::text(format!("{metric}{loo}")),
                Cell::text(input),
                Cell::number(ix.first, 3),
                interval(ix.first_ci),
                Cell::number(ix.total, 3),
                interval(ix.total_ci),
            ]);
        }
    }
    t
}

/// For each measured point: where it falls against the band at its current (linear between the
/// band's currents; a point outside the band's current range is said to be so).
fn measured_verdicts(doc: &UncertaintyDocument, m: &Measured) -> String {
    let verdicts: Vec<String> = m
        .points
        .iter()
        .map(|&(current, torque)| match band_at(doc, current) {
            Some((p5, p95)) => {
                let place = if torque < p5 {
                    "below the 5 % point"
                } else if torque > p95 {
                    "above the 95 % point"
                } else {
                    "inside the 5–95 % band"
                };
                format!("{torque:.3} N·m at {current:.3} A is {place} ({p5:.3} – {p95:.3} N·m)")
            }
            None => format!("{torque:.3} N·m at {current:.3} A is outside the band's currents"),
        })
        .collect();
    format!("{}: {}.", m.label, verdicts.join("; "))
}

/// The band's 5 % and 95 % torques at `current` (linear between its currents).
pub fn band_at(doc: &UncertaintyDocument, current: f64) -> Option<(f64, f64)> {
    let edge = |f: fn(&BandEntry) -> f64| -> Vec<(f64, f64)> {
        doc.torque_band.iter().map(|p| (p.current_a, f(p))).collect()
    };
    Some((torque_at(&edge(|p| p.p5_nm), current)?, torque_at(&edge(|p| p.p95_nm), current)?))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::html::Page;
    use crate::uncertainty::document::SAMPLE;
    use crate::uncertainty::plots::thesis_prototype;

    #[test]
    fn the_section_has_its_figures_tables_and_the_measured_verdict() {
        let doc: UncertaintyDocument = serde_json::from_str(SAMPLE).unwrap();
        let measured = thesis_prototype();
        let s = section(&doc, "u.json", Some(&measured)).unwrap();
        let page = Page { title: "t".into(), facts: vec![], sections: vec![s] }.render();
        let options = roxmltree::ParsingOptions { allow_dtd: true, ..Default::default() };
        roxmltree::Document::parse_with_options(&page, options).expect("well-formed XHTML");
        assert!(page.contains("<section id=\"uncertainty\">"));
        assert_eq!(page.matches("<svg").count(), 2, "band and tornado");
        assert!(page.contains("Sobol&#39; indices") || page.contains("Sobol' indices"));
        // At 2 A the band is 3–5 N·m: 3.84 N·m is inside; at 0 A it is 0.1 N·m: 0.15 is above.
        assert!(page.contains("3.840 N·m at 2.000 A is inside the 5–95 % band"), "{page}");
        assert!(page.contains("0.150 N·m at 0.000 A is above the 95 % point"));
    }

    #[test]
    fn the_band_is_read_between_its_currents() {
        let doc: UncertaintyDocument = serde_json::from_str(SAMPLE).unwrap();
        let (p5, p95) = band_at(&doc, 1.0).unwrap();
        assert!((p5 - 1.55).abs() < 1e-12 && (p95 - 2.55).abs() < 1e-12);
        assert_eq!(band_at(&doc, 2.5), None);
    }
}
