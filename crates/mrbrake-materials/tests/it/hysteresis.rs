//! Validation of the energy-based hysteresis model (`mrbrake_materials::hysteresis`): the B-driven
//! and H-driven forms agree, `dH/dB` matches finite differences, the loop area equals the closed-form
//! dissipation `Σ 4 κ_k J_k(H_m − κ_k)`, the model is passive over random histories (proptest),
//! minor loops close, the anhysteretic limit is single-valued, identification recovers the parameters
//! of a noisy self-generated loop, and hostile input never yields NaN.

use mrbrake_materials::MU_0;
use mrbrake_materials::hysteresis::identify::{
    IdentifyOptions, fit, fit_major_loop, read_loop_csv, read_loop_file,
};
use mrbrake_materials::hysteresis::{
    HysteresisParams, HysteresisState, Term, library, loop_measures, major_loop,
};
use proptest::prelude::*;

fn term(cell: usize, js: f64, a: f64) -> Term {
    Term { cell, polarisation_t: js, field_a_per_m: a }
}

/// A three-cell steel-like set: a reversible cell and two pinned cells.
fn steel_like() -> HysteresisParams {
    HysteresisParams::new(
        &[0.0, 150.0, 400.0],
        &[
            term(0, 0.3, 300.0),
            term(1, 0.6, 300.0),
            term(1, 0.2, 20_000.0),
            term(2, 0.8, 300.0),
            term(2, 0.2, 20_000.0),
        ],
    )
    .unwrap()
}

/// H waypoints: virgin to 20 kA/m, major loop, then nested minor loops.
fn field_history() -> Vec<f64> {
    let waypoints = [0.0, 20_000.0, -20_000.0, 3_000.0, -500.0, 800.0, 100.0, 20_000.0];
    let mut h = vec![0.0];
    for pair in waypoints.windows(2) {
        for i in 1..=400 {
            h.push(pair[0] + (pair[1] - pair[0]) * i as f64 / 400.0);
        }
    }
    h
}

#[test]
fn b_driven_and_h_driven_forms_agree() {
    let p = steel_like();
    let mut forward = HysteresisState::demagnetised();
    let mut inverse = HysteresisState::demagnetised();
    for h in field_history() {
        let f = forward.step_h(&p, h);
        let i = inverse.step(&p, f.b);
        assert!(i.accepted && i.iterations <= 30, "iterations {}", i.iterations);
        assert!((i.h - h).abs() <= 1e-6 * (1.0 + h.abs()), "H {} vs {h}", i.h);
        assert!((i.dh_db - f.dh_db).abs() <= 1e-6 * f.dh_db, "dH/dB {} vs {}", i.dh_db, f.dh_db);
        for (a, b) in inverse.reversible_a_per_m().iter().zip(forward.reversible_a_per_m()) {
            assert!((a - b).abs() <= 1e-6 * (1.0 + b.abs()));
        }
    }
}

#[test]
fn dh_db_matches_finite_differences_of_the_step_map() {
    let p = steel_like();
    let mut state = HysteresisState::demagnetised();
    let mut checked = 0;
    for h in field_history().into_iter().step_by(7) {
        let target = {
            let mut probe = state;
            probe.step_h(&p, h).b
        };
        let delta = target - state.b();
        if delta.abs() > 1e-6 {
            let (response, _) = state.trial(&p, target);
            // One-sided, in the direction of the step; if a cell starts moving inside
            // [target, target + step] the difference sees the kink, so halve the step once.
            let mut step = 1e-7 * delta.signum();
            let mut fd = (state.trial(&p, target + step).0.h - response.h) / step;
            if (fd - response.dh_db).abs() > 1e-4 * response.dh_db {
                step *= 0.01;
                fd = (state.trial(&p, target + step).0.h - response.h) / step;
            }
            assert!(
                (fd - response.dh_db).abs() <= 1e-3 * response.dh_db,
                "{fd} vs {}",
                response.dh_db
            );
            checked += 1;
        }
        state.step(&p, target);
    }
    assert!(checked > 300, "{checked}");
}

#[test]
fn loop_area_equals_the_closed_form_dissipation() {
    // Over a symmetric cycle of amplitude H_m every cell k swings between ±(H_m − κ_k), so
    // ∮ H dB = Σ_k κ_k ∫|dJ_k| = Σ_k 4 κ_k J_k(H_m − κ_k) (the dissipation of the dry-friction law, Henrotte et al. 2006).
    let p = steel_like();
    let h_max: f64 = 5000.0;
    let cell_j = |k: usize, h: f64| -> f64 {
        p.terms()
            .iter()
            .filter(|t| t.cell == k)
            .map(|t| {
                let x = h / t.field_a_per_m;
                t.polarisation_t * x / (1.0 + x.abs())
            })
            .sum()
    };
    let exact: f64 = p
        .pinning_a_per_m()
        .iter()
        .enumerate()
        .map(|(k, &kappa)| 4.0 * kappa * cell_j(k, h_max - kappa))
        .sum();
    let samples = major_loop(&p, h_max, 20_000);
    let measured = loop_measures(&samples).area_j_per_m3;
    assert!(
        (measured / exact - 1.0).abs() < 1e-5,
        "trapezoid {measured} vs closed form {exact} J/m3"
    );
    // The same from the states' own dissipation along a B-driven cycle.
    let mut state = HysteresisState::demagnetised();
    state.step_h(&p, h_max);
    let b_tip = state.b();
    let mut dissipated = 0.0;
    for i in 1..=4000 {
        let phase = std::f64::consts::TAU * i as f64 / 4000.0;
        let before = state;
        state.step(&p, b_tip * phase.cos());
        dissipated += before.dissipation_to(&p, &state);
    }
    assert!((dissipated / exact - 1.0).abs() < 1e-9, "dissipation {dissipated} vs {exact}");
    println!(
        "loop area at H_m = 5 kA/m: closed form {exact:.3} J/m3, trapezoid {measured:.3}, dissipation {dissipated:.3}"
    );
}

#[test]
fn minor_loops_close_return_point_memory() {
    let p = steel_like();
    let mut state = HysteresisState::demagnetised();
    state.step(&p, 1.8);
    state.step(&p, 0.4);
    let reversal = state;
    for b in [1.1, 0.7, 1.3, 0.4] {
        state.step(&p, b);
    }
    assert!((state.h() - reversal.h()).abs() < 1e-6, "{} vs {}", state.h(), reversal.h());
    for (a, b) in state.reversible_a_per_m().iter().zip(reversal.reversible_a_per_m()) {
        assert!((a - b).abs() < 1e-6);
    }
}

#[test]
fn anhysteretic_limit_is_single_valued() {
    let p = steel_like().with_pinning_scaled(0.0).unwrap();
    let samples = major_loop(&p, 20_000.0, 4000);
    let m = loop_measures(&samples);
    assert!(m.area_j_per_m3.abs() < 1e-6, "area {}", m.area_j_per_m3);
    assert!(m.remanence_t.unwrap_or(0.0).abs() < 1e-9);
    for &(h, b) in &samples {
        assert!((b - p.anhysteretic_b(h)).abs() < 1e-12);
    }
}

#[test]
fn library_steel_sets_reproduce_their_library_curves() {
    for name in library::steel_names().unwrap() {
        let set = library::steel(&name).unwrap();
        let hc = set.coercivity_a_per_m.value;
        println!(
            "{name}: Hc {:.0} A/m (fitted loop {:.0}), Br {:.3} T, Js {:.3} T, normal-curve rms {:.4} T, trust {}",
            hc,
            set.fitted_coercivity_a_per_m,
            set.remanence_t,
            set.params.saturation_polarisation_t(),
            set.normal_curve_rms_t,
            set.provenance.trust
        );
        assert!(set.normal_curve_rms_t < 0.02, "{name}: {}", set.normal_curve_rms_t);
        assert!((set.fitted_coercivity_a_per_m / hc - 1.0).abs() < 0.03, "{name}");
        let js = set.params.saturation_polarisation_t();
        assert!((1.9..2.4).contains(&js), "{name}: Js {js}");
        assert!(set.remanence_t > 0.3 && set.remanence_t < 1.5, "{name}: Br {}", set.remanence_t);
        assert_eq!(set.provenance.trust, mrbrake_materials::Trust::Low);
        // The anhysteretic limit lies above the normal curve (it has no pinning to overcome).
        let curve = mrbrake_materials::library::bh_curve(&name).unwrap();
        for h in [200.0, 1000.0, 5000.0] {
            assert!(set.params.anhysteretic_b(h) >= curve.b_of_h(h) - 0.03, "{name} at {h}");
        }
    }
}

/// A deterministic Gaussian sequence (LCG + Box–Muller) for reproducible noise.
fn noise(n: usize, sigma: f64) -> Vec<f64> {
    let mut state: u64 = 0x2545_f491_4f6c_dd1d;
    let mut uniform = move || {
        state =
            state.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        ((state >> 11) as f64 + 0.5) / (1u64 << 53) as f64
    };
    (0..n)
        .map(|_| sigma * (-2.0 * uniform().ln()).sqrt() * (std::f64::consts::TAU * uniform()).cos())
        .collect()
}

#[test]
fn identification_recovers_the_parameters_of_a_noisy_self_generated_loop() {
    let truth = steel_like();
    let clean = major_loop(&truth, 20_000.0, 300);
    let options = IdentifyOptions {
        pinning_a_per_m: vec![0.0, 150.0, 400.0],
        term_fields_a_per_m: vec![300.0, 20_000.0],
    };
    // Noise-free: exact recovery.
    let exact = fit_major_loop(&clean, Some(&options)).unwrap();
    let amplitude = |params: &HysteresisParams, cell: usize, a: f64| -> f64 {
        params
            .terms()
            .iter()
            .filter(|t| t.cell == cell && (t.field_a_per_m - a).abs() < 1e-6 * a)
            .map(|t| t.polarisation_t)
            .sum()
    };
    for cell in 0..3 {
        for a in [300.0, 20_000.0] {
            let (found, true_value) =
                (amplitude(&exact.params, cell, a), amplitude(&truth, cell, a));
            assert!(
                (found - true_value).abs() < 1e-6,
                "cell {cell}, a {a}: {found} vs {true_value}"
            );
        }
    }
    // With 2 mT noise: amplitudes within 10 %, coercivity and remanence within 1 %.
    let sigma = 2e-3;
    let noisy: Vec<(f64, f64)> =
        clean.iter().zip(noise(clean.len(), sigma)).map(|(&(h, b), e)| (h, b + e)).collect();
    let fitted = fit_major_loop(&noisy, Some(&options)).unwrap();
    println!("noisy fit: rms {:.3e} T, warnings {:?}", fitted.rms_residual_t, fitted.warnings);
    assert!(fitted.rms_residual_t > 0.8 * sigma && fitted.rms_residual_t < 1.2 * sigma);
    let truth_terms = truth.terms();
    for t in &truth_terms {
        let found: f64 = fitted
            .params
            .terms()
            .iter()
            .filter(|f| f.cell == t.cell && (f.field_a_per_m - t.field_a_per_m).abs() < 1e-6)
            .map(|f| f.polarisation_t)
            .sum();
        assert!((found / t.polarisation_t - 1.0).abs() < 0.1, "{t:?}: {found}");
    }
    let (m_true, m_fit) =
        (loop_measures(&clean), loop_measures(&major_loop(&fitted.params, 20_000.0, 300)));
    let rel = |a: Option<f64>, b: Option<f64>| (a.unwrap() / b.unwrap() - 1.0).abs();
    assert!(rel(m_fit.coercivity_a_per_m, m_true.coercivity_a_per_m) < 0.01);
    assert!(rel(m_fit.remanence_t, m_true.remanence_t) < 0.01);
    // The default grids (from the data) reproduce the loop to the noise level.
    let default = fit_major_loop(&noisy, None).unwrap();
    assert!(default.rms_residual_t < 1.3 * sigma, "default grid rms {}", default.rms_residual_t);
}

#[test]
fn identification_warns_about_what_the_loop_does_not_determine() {
    // A minor loop (tip 300 A/m) stays far from saturation; a pinning field of 5 kA/m never moves.
    let truth = steel_like();
    let small = major_loop(&truth, 300.0, 200);
    let options = IdentifyOptions {
        pinning_a_per_m: vec![0.0, 150.0, 5000.0],
        term_fields_a_per_m: vec![300.0, 3000.0, 20_000.0],
    };
    let fitted =
        fit(&[mrbrake_materials::hysteresis::Observation::major_loop("small", &small)], &options)
            .unwrap();
    let text = fitted.warnings.join("\n");
    assert!(text.contains("5000.0000 A/m is not exercised"), "{text}");
    assert!(text.contains("saturation polarisation"), "{text}");
}

#[test]
fn loop_csv_errors_name_the_file_line_and_column() {
    let header = "H_A_per_m,B_T\n";
    let rows: String = (0..10).map(|i| format!("{},{}\n", i * 10, i as f64 * 0.1)).collect();
    assert_eq!(read_loop_csv(&format!("{header}{rows}"), "loop.csv").unwrap().len(), 10);
    let err = read_loop_csv(&format!("H,B\n{rows}"), "loop.csv").unwrap_err().to_string();
    assert!(err.starts_with("loop.csv:1:") && err.contains("H_A_per_m,B_T"), "{err}");
    let err = read_loop_csv(&format!("{header}{rows}5,NaN\n"), "loop.csv").unwrap_err().to_string();
    assert!(err.starts_with("loop.csv:12:") && err.contains("B_T"), "{err}");
    let err = read_loop_csv(&format!("{header}1,x\n"), "loop.csv").unwrap_err().to_string();
    assert!(err.starts_with("loop.csv:2:") && err.contains("B_T"), "{err}");
    let err =
        read_loop_csv(&format!("{header}1,0.1\n2,0.2\n"), "loop.csv").unwrap_err().to_string();
    assert!(err.contains("a loop needs 8"), "{err}");
    let huge = "0,0\n".repeat(1_100_000);
    let err = read_loop_csv(&format!("{header}{huge}"), "big.csv").unwrap_err().to_string();
    assert!(err.contains("bytes"), "{err}");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("loop.csv");
    std::fs::write(&path, format!("{header}{rows}")).unwrap();
    assert_eq!(read_loop_file(&path).unwrap().len(), 10);
    let missing = read_loop_file(&dir.path().join("none.csv")).unwrap_err();
    assert_eq!(mrbrake_error::Kind::kind(&missing), mrbrake_error::ErrorKind::Input);
}

#[test]
fn hostile_input_is_rejected_without_nan() {
    let p = steel_like();
    let mut state = HysteresisState::demagnetised();
    state.step(&p, 1.2);
    let kept = state;
    for bad in [f64::NAN, f64::INFINITY, -f64::INFINITY, 1e300, -1e6] {
        let r = state.step(&p, bad);
        assert!(!r.accepted && r.h.is_finite() && r.dh_db.is_finite());
        assert_eq!(state, kept);
    }
    // Deep saturation both ways: finite, and dH/dB tends to 1/μ0.
    for b in [50.0, -50.0, 99.0] {
        let r = state.step(&p, b);
        assert!(r.accepted && r.h.is_finite());
        assert!((r.dh_db * MU_0 - 1.0).abs() < 1e-2, "{}", r.dh_db * MU_0);
    }
}

/// Random parameter sets: 1–4 cells, pinning fields 0–2 kA/m, 1–3 terms per cell.
fn arbitrary_params() -> impl Strategy<Value = HysteresisParams> {
    prop::collection::vec(
        (0.0..2000.0_f64, prop::collection::vec((0.05..1.0_f64, 10.0..50_000.0_f64), 1..4)),
        1..5,
    )
    .prop_map(|cells| {
        let pinning: Vec<f64> = cells.iter().map(|c| c.0).collect();
        let terms: Vec<Term> = cells
            .iter()
            .enumerate()
            .flat_map(|(k, c)| c.1.iter().map(move |&(js, a)| term(k, js, a)))
            .collect();
        HysteresisParams::new(&pinning, &terms).unwrap()
    })
}

/// `J_k(h)` of cell `k` and its antiderivative `∫_0^h J_k = Σ J_t a (|x| − ln(1 + |x|))`,
/// `x = h/a`, computed here from the terms (independently of the library's energy functions).
fn cell_j(p: &HysteresisParams, k: usize, h: f64) -> (f64, f64) {
    p.terms().iter().filter(|t| t.cell == k).fold((0.0, 0.0), |(j, f), t| {
        let x = h / t.field_a_per_m;
        let ax = x.abs();
        (
            j + t.polarisation_t * x / (1.0 + ax),
            f + t.polarisation_t * t.field_a_per_m * (ax - ax.ln_1p()),
        )
    })
}

/// The exact work `∫ H dB` of one step between two states: `[H B] − ∫ B dH`, where along the step
/// each cell stays frozen until the field has moved `κ_k` past it and then follows it (the play
/// rule), so `∫ J_k dH` is `J_k(frozen)·(H_act − H₀) + ∫ J_k` over the cell's own motion.
fn exact_work(p: &HysteresisParams, before: &HysteresisState, after: &HysteresisState) -> f64 {
    let (h0, h1) = (before.h(), after.h());
    let s = (h1 - h0).signum();
    let mut integral_b_dh = 0.5 * MU_0 * (h1 * h1 - h0 * h0);
    let (mut b0, mut b1) = (MU_0 * h0, MU_0 * h1);
    for (k, &kappa) in p.pinning_a_per_m().iter().enumerate() {
        let (r0, r1) = (before.reversible_a_per_m()[k], after.reversible_a_per_m()[k]);
        let ((j0, f0), (j1, f1)) = (cell_j(p, k, r0), cell_j(p, k, r1));
        b0 += j0;
        b1 += j1;
        integral_b_dh += if (r1 - r0).abs() > 0.0 {
            j0 * (r0 + s * kappa - h0) + (f1 - f0)
        } else {
            j0 * (h1 - h0)
        };
    }
    h1 * b1 - h0 * b0 - integral_b_dh
}

/// What a B-driven history did: the exact work `∫ H dB` (per step, [`exact_work`]), the gross work `∫ |H dB|`, the energy the states report as
/// dissipated and the free energy at the end, J/m³. Each segment is driven in 64 steps.
struct Driven {
    work: f64,
    gross: f64,
    dissipated: f64,
    stored: f64,
}

fn drive(p: &HysteresisParams, state: &mut HysteresisState, waypoints: &[f64]) -> Driven {
    let mut d = Driven { work: 0.0, gross: 0.0, dissipated: 0.0, stored: 0.0 };
    let mut b0 = state.b();
    for &target in waypoints {
        for i in 1..=64 {
            let b = b0 + (target - b0) * i as f64 / 64.0;
            let before = *state;
            let r = state.step(p, b);
            assert!(
                r.accepted
                    && r.h.is_finite()
                    && r.dh_db > 0.0
                    && r.dh_db <= 1.0 / MU_0 * (1.0 + 1e-12)
            );
            let work = exact_work(p, &before, state);
            d.work += work;
            d.gross += work.abs();
            d.dissipated += before.dissipation_to(p, state);
        }
        b0 = target;
    }
    d.stored = state.free_energy(p);
    d
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Passivity: from the demagnetised state, the work done on the material over any B history
    /// returning to its start is ≥ 0 (computed exactly per step from the play kinematics); a second
    /// pass of the same closed history is a periodic cycle whose work equals the dissipation (the
    /// loop area is the hysteresis loss).
    #[test]
    fn the_model_never_creates_energy(
        p in arbitrary_params(),
        mut waypoints in prop::collection::vec(-2.4..2.4_f64, 2..10),
    ) {
        waypoints.push(0.0);
        let mut state = HysteresisState::demagnetised();
        let first = drive(&p, &mut state, &waypoints);
        let tolerance = 1e-9 * first.gross + 1e-12;
        prop_assert!(first.work >= -tolerance, "first pass work {} (tolerance {tolerance})", first.work);
        // Exact balance from the demagnetised state (zero stored energy): W = Ψ_end + D.
        let balance = first.stored + first.dissipated;
        prop_assert!((first.work - balance).abs() <= tolerance, "{} vs {balance}", first.work);
        // The same closed history again: now a periodic cycle, whose work is its dissipation.
        let second = drive(&p, &mut state, &waypoints);
        let tolerance = 1e-9 * second.gross + 1e-12;
        prop_assert!(second.work >= -tolerance, "second pass work {}", second.work);
        prop_assert!(
            (second.work - second.dissipated).abs() <= tolerance,
            "{} vs {}",
            second.work,
            second.dissipated
        );
    }

    /// Any finite history yields finite H and a positive, bounded dH/dB.
    #[test]
    fn random_histories_stay_finite(p in arbitrary_params(), bs in prop::collection::vec(-90.0..90.0_f64, 1..40)) {
        let mut state = HysteresisState::demagnetised();
        for b in bs {
            let r = state.step(&p, b);
            prop_assert!(r.accepted && r.h.is_finite() && r.dh_db.is_finite() && r.dh_db > 0.0);
            prop_assert!(r.iterations <= mrbrake_materials::hysteresis::MAX_ITERATIONS);
        }
    }
}

#[test]
fn an_fea_selects_the_law_by_material_name() {
    let steel = library::for_material("Steel-1008").unwrap();
    assert_eq!(steel.name, "steel-1008");
    for name in ["air", "mrf-122eg", "aluminium"] {
        let err = library::for_material(name).unwrap_err();
        let text = err.to_string();
        assert!(
            text.contains(name)
                && text.contains("no hysteresis model")
                && text.contains("steel-1018"),
            "{text}"
        );
        assert_eq!(mrbrake_error::Kind::kind(&err), mrbrake_error::ErrorKind::Input);
    }
    let unknown = library::for_material("unobtainium").unwrap_err();
    assert!(unknown.to_string().contains("unknown material"), "{unknown}");
    let bad = library::steel_with_coercivity(
        "steel-1010",
        mrbrake_materials::Sourced::new(
            -5.0,
            mrbrake_materials::Provenance::user_file("spec.toml"),
        ),
    )
    .unwrap_err();
    assert!(bad.to_string().contains("coercivity_A_per_m"), "{bad}");
}

#[test]
fn the_normal_curve_is_a_consistent_single_valued_law() {
    use mrbrake_materials::Reluctivity;
    let set = library::steel("steel-1008").unwrap();
    let law = mrbrake_materials::hysteresis::NormalCurve::new(set.params.clone());
    let curve = mrbrake_materials::library::bh_curve("steel-1008").unwrap();
    for b in [0.2_f64, 0.8, 1.2, 1.5, 1.8, 2.1] {
        let (nu, dnu) = law.nu_and_dnu_db2(b * b);
        // Newton's Jacobian coefficient ν + 2B² dν/dB² is the differential reluctivity.
        let h = law.h_of_b(b);
        let step = 1e-6;
        let slope = (law.h_of_b(b + step) - law.h_of_b(b - step)) / (2.0 * step);
        assert!((nu * b - h).abs() < 1e-9 * h.abs().max(1.0));
        assert!(
            ((nu + 2.0 * b * b * dnu) / slope - 1.0).abs() < 1e-3,
            "B {b}: {} vs {slope}",
            nu + 2.0 * b * b * dnu
        );
        // Close to the library curve it was fitted to (the set's normal-curve rms is 8 mT).
        let b_model = law.b_of_h(curve.h_of_b(b));
        println!(
            "B {b}: library H {:.1} A/m, model H {:.1} A/m, model B at library H {b_model:.4} T",
            curve.h_of_b(b),
            h
        );
        assert!((b_model - b).abs() < 0.1, "B {b}: model {b_model}");
    }
    let magnetic = mrbrake_materials::Magnetic::NonLinear(std::sync::Arc::new(law));
    assert!(magnetic.nu_of_b2(0.0).is_finite() && magnetic.nu_of_b2(0.0) > 0.0);
}

#[test]
fn a_warm_start_gives_the_same_step_whatever_the_guess() {
    let p = steel_like();
    let mut state = HysteresisState::demagnetised();
    state.step(&p, 1.6);
    state.step(&p, 0.3);
    for (b, guess) in [(0.35, 0.0), (0.35, 1e9), (-0.4, f64::NAN), (-0.4, -123.0), (1.0, 500.0)] {
        let (cold, cold_state) = state.trial(&p, b);
        let (warm, warm_state) = state.trial_near(&p, b, guess);
        assert!((warm.h - cold.h).abs() <= 1e-6 * (1.0 + cold.h.abs()), "B {b}, guess {guess}");
        assert!((warm.dh_db - cold.dh_db).abs() <= 1e-9 * cold.dh_db);
        assert!((warm_state.h() - cold_state.h()).abs() <= 1e-6 * (1.0 + cold.h.abs()));
    }
    // A good guess (the field of a nearby trial) converges in two evaluations.
    let near = state.trial(&p, 0.3499).0.h;
    assert!(state.trial_near(&p, 0.35, near).0.iterations <= 3);
}
