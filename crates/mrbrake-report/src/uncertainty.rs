//! The report of `mrbrake uncertainty`: its JSON (the contract of issue 29: `samples`, `inputs`,
//! `outputs.<metric>`, `torque_band`, `sobol.<metric>.<input>`, `surrogate`, `timings_s`) and its
//! text; [`document`] reads that JSON back (for `mrbrake report`), [`plots`] draws the torque band
//! and the tornado chart of the Sobol' indices from it.

pub mod document;
pub mod plots;

use serde_json::{Map, Value, json};

use mrbrake_explore::uncertainty::{InputReport, Uncertainty};

/// One declared input: its name, law (parameters in SI, in the field's unit), truncation and
/// moments.
fn input_json(i: &InputReport) -> Value {
    // The law's parameters, without its own tag.
    let mut entry = serde_json::to_value(i.law.law()).unwrap_or(Value::Null);
    let law = entry.as_object_mut().map(std::mem::take).unwrap_or_default();
    let mut object = Map::new();
    object.insert("name".into(), json!(i.name));
    object.insert("distribution".into(), json!(i.distribution));
    object.insert("unit".into(), json!(i.unit));
    for (key, value) in law {
        object.entry(key).or_insert(value);
    }
    let truncation = i.law.truncation().map(|t| json!([t.lower, t.upper]));
    object.insert("truncation".into(), truncation.unwrap_or(Value::Null));
    // The moments after truncation (the law's own `mean`/`std_dev` are before it).
    object.insert("moments".into(), json!({ "mean": i.mean, "std": i.std }));
    Value::Object(object)
}

/// Per metric: the Sobol' indices per input, and the surrogate behind them.
fn sobol_json(u: &Uncertainty) -> (Map<String, Value>, Map<String, Value>) {
    let mut sobol = Map::new();
    let mut surrogates = Map::new();
    for (metric, s) in &u.sobol {
        let per_input: Map<String, Value> = s
            .inputs
            .iter()
            .map(|(input, ix)| {
                let v = json!({
                    "first": ix.first, "total": ix.total,
                    "first_ci": ix.first_ci, "total_ci": ix.total_ci,
                });
                (input.clone(), v)
            })
            .collect();
        sobol.insert(metric.clone(), Value::Object(per_input));
        let g = &s.surrogate;
        let v = json!({
            "kind": g.kind, "loo_error": g.loo_error, "degree": g.degree, "terms": g.terms,
            "samples": g.samples,
        });
        surrogates.insert(metric.clone(), v);
    }
    (sobol, surrogates)
}

/// The JSON of a propagation.
pub fn json(u: &Uncertainty) -> Value {
    let inputs: Vec<Value> = u.inputs.iter().map(input_json).collect();
    let outputs: Map<String, Value> = u
        .outputs
        .iter()
        .map(|(name, s)| {
            let summary = json!({
                "mean": s.mean, "std": s.std, "p5": s.p5, "p50": s.p50, "p95": s.p95,
                "nominal": nominal(u, name),
            });
            (name.clone(), summary)
        })
        .collect();
    let (sobol, surrogates) = sobol_json(u);
    let band: Vec<Value> = u
        .torque_band
        .iter()
        .map(|p| {
            let t = &p.torque;
            json!({
                "current_A": p.current_a, "p5_Nm": t.p5, "p50_Nm": t.p50, "p95_Nm": t.p95,
                "mean_Nm": t.mean, "std_Nm": t.std, "nominal_Nm": p.nominal_nm, "samples": t.count,
            })
        })
        .collect();
    let main = u.sobol.iter().find(|(m, _)| m == "torque_max_Nm").or(u.sobol.first());
    json!({
        "samples": u.samples,
        "evaluated": u.evaluated,
        "left_out": u.left_out,
        "left_out_reason": u.left_out_reason,
        "inputs": inputs,
        "outputs": outputs,
        "torque_band": band,
        "sobol": sobol,
        "surrogate": main.map(|(_, s)| json!({
            "kind": s.surrogate.kind, "loo_error": s.surrogate.loo_error,
        })),
        "surrogates": surrogates,
        "computed": u.computed,
        "timings_s": { "total": u.total_s, "evaluation": u.evaluation_s },
    })
}

fn nominal(u: &Uncertainty, metric: &str) -> Option<f64> {
    u.nominal.iter().find(|(n, _)| n == metric).map(|(_, v)| *v)
}

/// The text of a propagation: the inputs, each output's band, and the inputs ranked by their
/// total Sobol' index per output.
pub fn text(u: &Uncertainty, name: &str) -> String {
    let mut out = format!(
        "{name}: {} samples ({} evaluated, {} left out, {} analysed in this run), {:.1} s\n",
        u.samples, u.evaluated, u.left_out, u.computed, u.total_s
    );
    if let Some(reason) = &u.left_out_reason {
        out.push_str(&format!("  first left out: {reason}\n"));
    }
    out.push_str("inputs:\n");
    for i in &u.inputs {
        out.push_str(&format!(
            "  {:<28} {:<11} mean {:.6} std {:.6} {}\n",
            i.name, i.distribution, i.mean, i.std, i.unit
        ));
    }
    out.push_str("outputs (nominal, mean ± std, 5 % / 50 % / 95 %):\n");
    for (metric, s) in &u.outputs {
        let nominal = nominal(u, metric).map_or("-".into(), |v| format!("{v:.5}"));
        out.push_str(&format!(
            "  {metric:<28} {nominal:>10}  {:.5} ± {:.5}  [{:.5} / {:.5} / {:.5}]\n",
            s.mean, s.std, s.p5, s.p50, s.p95
        ));
    }
    if !u.torque_band.is_empty() {
        out.push_str("torque band (current A: nominal, mean ± std, 5 % / 50 % / 95 %, N·m):\n");
    }
    for p in &u.torque_band {
        let t = &p.torque;
        let nominal = p.nominal_nm.map_or("-".into(), |v| format!("{v:.4}"));
        out.push_str(&format!(
            "  {:>8.4}  {nominal:>8}  {:.4} ± {:.4}  [{:.4} / {:.4} / {:.4}]\n",
            p.current_a, t.mean, t.std, t.p5, t.p50, t.p95
        ));
    }
    for (metric, s) in &u.sobol {
        out.push_str(&format!(
            "sensitivity of {metric} (polynomial chaos, LOO error {:.3}; first, total [95 % CI]):\n",
            s.surrogate.loo_error
        ));
        let mut ranked: Vec<_> = s.inputs.iter().collect();
        ranked.sort_by(|a, b| b.1.total.total_cmp(&a.1.total));
        for (input, ix) in ranked {
            out.push_str(&format!(
                "  {input:<28} {:.3} [{:.3}, {:.3}]  {:.3} [{:.3}, {:.3}]\n",
                ix.first, ix.first_ci[0], ix.first_ci[1], ix.total, ix.total_ci[0], ix.total_ci[1]
            ));
        }
    }
    out.truncate(out.trim_end().len());
    out
}
