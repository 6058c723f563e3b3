//! The small-signal response of each direction of the bidirectional brake
//! (`ResponseModel::frequency_response_of`): direction 2 is analysed on its own coils and gaps,
//! not copied from direction 1. The thesis brake's units are mirror images (spec assumption A6),
//! so their responses agree up to the mesh, which is not mirrored. A brake whose direction-2 coil
//! has twice the turns differs the way the physics says: far from saturation under voltage drive
//! direction 2 is slower, its coil's electrical time constant L/R grown as N (L ∝ N², R ∝ N:
//! thesis (4.2)–(4.3) for R, the flux linkage for L); at half the maximum current under current
//! drive it is faster, its flux path more saturated (a lower incremental permeability shortens
//! the eddy-current diffusion time τ ∝ μσd², Stoll, *The analysis of eddy currents*, 1974, ch. 1).

use std::sync::Arc;

use mrbrake_design::mesh_build::{MeshLevel, mesh_spec};
use mrbrake_design::response::{ResponseDrive, ResponseModel, ResponseOptions};
use mrbrake_design::spec::{BrakeSpec, default_spec};

/// The bandwidths (rad/s) and DC gains (N·m/A) of both directions at `bias` amperes;
/// `turns_dir2` scales the turns of direction 2's coils (1: the spec as it is).
fn both_directions(
    spec: &BrakeSpec,
    options: &ResponseOptions,
    turns_dir2: u32,
    bias: f64,
) -> [(f64, f64); 2] {
    let mut geometry = spec.validate().unwrap().geometry;
    let mesh = Arc::new(mesh_spec(spec, &geometry, options.mesh).unwrap());
    for coil in geometry.coils.iter_mut().filter(|c| c.unit == 1) {
        coil.turns *= turns_dir2;
    }
    let model = ResponseModel::on_mesh(spec, options, geometry, mesh).unwrap();
    assert_eq!(model.units(), 2);
    [0, 1].map(|unit| {
        let (gain, _, bandwidth) = model.frequency_response_of(unit, bias).unwrap();
        (bandwidth.expect("a bandwidth within the analysed frequencies"), gain)
    })
}

#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: frequency sweeps of the whole brake")]
fn each_direction_is_analysed_on_its_own_circuit() {
    let spec = default_spec();
    let current = ResponseOptions { mesh: MeshLevel::Coarse, ..ResponseOptions::default() };
    let half = 0.5 * spec.coil.max_current.a();
    let [(b1, g1), (b2, g2)] = both_directions(&spec, &current, 1, half);
    println!(
        "thesis brake, current drive: bandwidth {b1:.2} / {b2:.2} rad/s, gain {g1:.4} / {g2:.4} N·m/A"
    );
    // Mirror images: equal up to the discretisation of two differently meshed halves (2 %).
    assert!((b2 - b1).abs() <= 0.02 * b1, "{b1} vs {b2}");
    assert!((g2 - g1).abs() <= 0.02 * g1, "{g1} vs {g2}");
    // The direction that does not exist is an input error naming it.
    let model = ResponseModel::new(&spec, &current).unwrap();
    assert!(model.frequency_response_of(2, 1.0).unwrap_err().to_string().contains("direction"));

    // Twice the ampere-turns at the same bias saturate direction 2's flux path further: a lower
    // incremental permeability, a shorter eddy-current diffusion time (τ ∝ μσd²), a faster
    // direction 2 under current drive.
    let [(c1, _), (c2, _)] = both_directions(&spec, &current, 2, half);
    println!(
        "current drive, bias {half} A, twice the turns in direction 2: {c1:.2} / {c2:.2} rad/s"
    );
    assert!((c1 - b1).abs() <= 1e-9 * b1, "direction 1 does not see direction 2's coil");
    assert!(c2 > 1.2 * c1, "{c1} vs {c2}");

    // Far from saturation (0.1 A) under voltage drive, twice the turns double the coil's L/R:
    // direction 2 is slower, by at most the factor 2 of that pole (the eddy lag does not scale).
    let voltage = ResponseOptions { drive: ResponseDrive::Voltage, ..current };
    let [(v1, _), (v2, _)] = both_directions(&spec, &voltage, 1, 0.1);
    let [(w1, _), (w2, _)] = both_directions(&spec, &voltage, 2, 0.1);
    println!(
        "voltage drive, bias 0.1 A: {v1:.2} / {v2:.2} rad/s; twice the turns: {w1:.2} / {w2:.2} rad/s"
    );
    assert!((v2 - v1).abs() <= 0.02 * v1, "{v1} vs {v2}");
    assert!((w1 - v1).abs() <= 1e-9 * v1, "direction 1 does not see direction 2's coil");
    assert!(w2 < 0.8 * w1 && w2 > 0.45 * w1, "{w1} vs {w2}");
}

/// `response` (the command's analysis) reports direction 2's small-signal response beside
/// direction 1's, the same numbers as `ResponseModel::frequency_response_of`.
#[test]
#[cfg_attr(not(heavy_tests), ignore = "release only: frequency sweeps of the whole brake")]
fn the_response_reports_both_directions() {
    let spec = default_spec();
    let options =
        ResponseOptions { mesh: MeshLevel::Coarse, duration_s: 2e-3, ..ResponseOptions::default() };
    let response = mrbrake_design::response::response(&spec, &options).unwrap();
    let second = response.direction_2.as_ref().expect("the bidirectional brake's direction 2");
    let model = ResponseModel::new(&spec, &options).unwrap();
    let (gain, frd, bandwidth) = model.frequency_response_of(1, response.bias_a).unwrap();
    assert!((second.dc_gain_nm_per_a - gain).abs() <= 1e-12 * gain.abs());
    assert_eq!(second.frequency_response.points.len(), frd.points.len());
    let (b, expected) = (second.bandwidth_rad_s.unwrap(), bandwidth.unwrap());
    assert!((b - expected).abs() <= 1e-9 * expected, "{b} vs {expected}");
    let json = serde_json::to_value(&response).unwrap();
    assert!(json["direction_2"]["bandwidth_rad_s"].as_f64().is_some(), "{}", json["direction_2"]);
}
