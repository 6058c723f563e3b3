//! CLI behaviour of `mrbrake haptic`: the sticky-wall metrics issue 6 asks for on the press-and-
//! withdraw scenario (the conventional brake resists withdrawal, the bidirectional one much less),
//! the Z-width map CSV agreeing with the passivity condition (2.2), and a bad `--duration` unit
//! giving a clear message and exit code 2.

use crate::common;

use common::{expect_input_error, json, mrbrake, number, path_str};

fn wall(device: &str) -> serde_json::Value {
    let v = json(&["haptic", "wall", "--device", device, "--json"]);
    for field in ["max_penetration_rad", "withdraw_energy_J", "release_time_s", "device_energy_J"] {
        assert!(number(&v, field).is_finite(), "{device}: {field} in {v}");
    }
    let withdraw = &v["withdraw_resisting_torque_Nm"];
    let (peak, mean) = (number(withdraw, "peak"), number(withdraw, "mean"));
    assert!(peak >= mean && mean >= 0.0, "{device}: {withdraw}");
    assert!(v["passive"].is_boolean(), "{device}: {v}");
    v
}

#[test]
fn conventional_brake_grabs_on_withdrawal_and_the_bidirectional_one_lets_go() {
    let conventional = wall("conventional");
    let bidirectional = wall("bidirectional");

    // Same hand, same wall: both press in the same way.
    let penetration = number(&conventional, "max_penetration_rad");
    assert!(penetration > 0.0);
    assert!(
        (penetration - number(&bidirectional, "max_penetration_rad")).abs() < 0.1 * penetration
    );

    // Brakes only dissipate: passive, and the device supplies no net energy.
    for v in [&conventional, &bidirectional] {
        assert_eq!(v["passive"], true, "{v}");
        assert!(number(v, "device_energy_J") <= 0.0, "{v}");
        assert!(number(v, "release_time_s") > 0.0, "{v}");
    }

    // The sticky wall: the conventional brake resists leaving the wall far more.
    let peak = |v: &serde_json::Value| number(&v["withdraw_resisting_torque_Nm"], "peak");
    let mean = |v: &serde_json::Value| number(&v["withdraw_resisting_torque_Nm"], "mean");
    assert!(
        peak(&conventional) > 2.0 * peak(&bidirectional),
        "peak withdraw torque: conventional {} vs bidirectional {} N·m",
        peak(&conventional),
        peak(&bidirectional)
    );
    assert!(mean(&conventional) > 2.0 * mean(&bidirectional));
    assert!(
        number(&conventional, "withdraw_energy_J") > number(&bidirectional, "withdraw_energy_J")
    );
}

#[test]
fn zwidth_csv_agrees_with_the_passivity_condition() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let csv = dir.path().join("zwidth.csv");
    let (points, stiffness_max, damping_max) = (4usize, 50.0, 0.02);
    let (period_s, physical_damping) = (1e-3, 0.005);
    let out = mrbrake(&[
        "haptic",
        "zwidth",
        "--points",
        &points.to_string(),
        "--stiffness-max-nm-per-rad",
        &stiffness_max.to_string(),
        "--damping-max-nms-per-rad",
        &damping_max.to_string(),
        "--period",
        "1ms",
        "--physical-damping-nms-per-rad",
        &physical_damping.to_string(),
        "--csv",
        csv.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));

    let text = std::fs::read_to_string(&csv).expect("the CSV is written");
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let column = |name: &str| {
        header.iter().position(|h| *h == name).unwrap_or_else(|| panic!("no {name}: {header:?}"))
    };
    let (k_col, b_col) = (column("stiffness_Nm_per_rad"), column("damping_Nms_per_rad"));
    let (predicted_col, brake_col) = (column("motor_predicted_passive_2_2"), column("brake"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), points * points);

    let mut predicted_passive = 0;
    for row in &rows {
        let k: f64 = row[k_col].parse().expect("K is a number");
        let b: f64 = row[b_col].parse().expect("B is a number");
        assert!((0.0..=stiffness_max * (1.0 + 1e-12)).contains(&k), "{row:?}");
        assert!((0.0..=damping_max * (1.0 + 1e-12)).contains(&b), "{row:?}");
        // Colgate's condition, thesis (2.2): passive if b > K T / 2 + B.
        let passive_by_2_2 = physical_damping > k * period_s / 2.0 + b;
        assert_eq!(row[predicted_col], passive_by_2_2.to_string(), "{row:?}");
        predicted_passive += usize::from(passive_by_2_2);
        // A brake can only dissipate.
        assert_eq!(row[brake_col], "passive", "{row:?}");
    }
    // The grid spans both sides of the boundary.
    assert!(predicted_passive > 0 && predicted_passive < rows.len(), "{predicted_passive}");
}

#[test]
fn bad_duration_exits_2() {
    for duration in ["3kg", "fast"] {
        let out = mrbrake(&["haptic", "wall", "--device", "conventional", "--duration", duration]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "--duration {duration}: {err}");
        assert!(err.contains("--duration") && err.contains(duration), "{err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

/// The prototype brake model with a Preisach table on both units: a uniform density
/// (`E(α, β) = ½ c (α − β)²`) on 8 levels of `[0, 2]` A whose reference state keeps
/// `remanent_nm` at 0 A; `edit` changes its `everett_Nm` (as JSON) before it is written.
fn preisach_model_file(
    dir: &std::path::Path,
    remanent_nm: f64,
    edit: impl Fn(&mut serde_json::Value),
) -> std::path::PathBuf {
    let mut model = serde_json::to_value(mrbrake::sim::brake_model::prototype::haptic_prototype())
        .expect("the model serialises");
    let levels: Vec<f64> = (0..=8).map(|k| 0.25 * f64::from(k)).collect();
    let everett = |a: f64, b: f64| 0.25 * (a - b) * (a - b);
    let mut hysteresis = serde_json::json!({
        "kind": "preisach",
        "levels_A": levels,
        "rising_Nm": levels.iter().map(|a| remanent_nm + 1.5 * a + everett(*a, 0.0)).collect::<Vec<_>>(),
        "everett_Nm": levels.iter().enumerate()
            .map(|(k, a)| levels[..=k].iter().map(|b| everett(*a, *b)).collect::<Vec<_>>())
            .collect::<Vec<_>>(),
        "source": "test: uniform density",
    });
    edit(&mut hysteresis["everett_Nm"]);
    for unit in model["units"].as_array_mut().expect("units") {
        unit["current_max_A"] = 2.0.into();
        unit["hysteresis"] = hysteresis.clone();
    }
    let path = dir.join(format!("preisach-{remanent_nm}.json"));
    std::fs::write(&path, model.to_string()).expect("the model is written");
    path
}

#[test]
fn a_preisach_brake_model_runs_and_its_remanence_is_felt_after_the_wall() {
    let dir = tempfile::tempdir().expect("temporary directory");
    let wall = |path: &std::path::Path| {
        json(&[
            "haptic",
            "wall",
            "--device",
            "bidirectional",
            "--brake-model",
            path_str(path),
            "--json",
        ])
    };
    let (low, high) = (0.1, 0.3);
    let (a, b) = (
        wall(&preisach_model_file(dir.path(), low, |_| {})),
        wall(&preisach_model_file(dir.path(), high, |_| {})),
    );
    for v in [&a, &b] {
        assert!(number(v, "current_peak_A") > 0.5, "{v}");
        assert_eq!(v["passive"], true, "{v}");
    }
    // After the wall brake 1 (toward the wall, lag gain 1) is back at 0 A: its drag is the
    // table's remanent torque at 0 A, so the two tables differ by their remanence there.
    let inward = |v: &serde_json::Value| number(&v["drag_after_Nm"], "inward");
    let difference = inward(&b) - inward(&a);
    assert!((difference - (high - low)).abs() < 1e-6, "{difference}: {a}\n{b}");
    assert!(inward(&a) >= low, "{a}");
}

#[test]
fn a_bad_preisach_table_or_a_doubled_remanence_is_exit_2_naming_the_field() {
    let dir = tempfile::tempdir().expect("temporary directory");
    // A dip in E(α, β) along α: a negative Preisach weight.
    let bad = preisach_model_file(dir.path(), 0.2, |e| e[5][1] = 2.0.into());
    let args = ["haptic", "wall", "--device", "bidirectional", "--brake-model", path_str(&bad)];
    expect_input_error(&args, &["units[0].hysteresis.everett_Nm["]);
    // NaN is not JSON: a table with it is refused where it stands.
    let text = std::fs::read_to_string(preisach_model_file(dir.path(), 0.2, |_| {})).unwrap();
    let nan = dir.path().join("nan.json");
    std::fs::write(&nan, text.replacen("\"everett_Nm\":[[0.0]", "\"everett_Nm\":[[NaN]", 1))
        .unwrap();
    let args = ["haptic", "wall", "--device", "bidirectional", "--brake-model", path_str(&nan)];
    expect_input_error(&args, &["nan.json"]);
    // The table holds the remanence: --remanence without its release would add it twice.
    let good = preisach_model_file(dir.path(), 0.2, |_| {});
    let demag = dir.path().join("demag.json");
    std::fs::write(&demag, r#"{"hysteresis": {"remanent_torque_Nm": 0.1, "peak_current_A": 2.0}}"#)
        .unwrap();
    let args = [
        "haptic",
        "wall",
        "--device",
        "bidirectional",
        "--brake-model",
        path_str(&good),
        "--remanence",
        path_str(&demag),
    ];
    expect_input_error(&args, &["--remanence", "twice"]);
}
