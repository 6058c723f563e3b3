"""mrbrake.haptic.wall agrees with `mrbrake haptic wall --json` / `--csv` for the same inputs."""

import csv

import numpy as np
import pytest

import mrbrake


@pytest.mark.parametrize("device,scenario", [("bidirectional", "press-withdraw"),
                                             ("conventional", "slide-hold")])
def test_wall_metrics_and_trace_equal_the_cli(cli, tmp_path, device, scenario):
    trace_csv = tmp_path / "trace.csv"
    expected = cli.json("haptic", "wall", "--device", device, "--scenario", scenario,
                        "--stiffness-nm-per-rad", "40", "--duration", "2s", "--csv", trace_csv)
    run = mrbrake.haptic.wall(device, scenario=scenario, stiffness=40.0, duration="2s")
    assert run.metrics == expected
    table = np.genfromtxt(trace_csv, delimiter=",", names=True)
    trace = run.trace
    n = len(table)
    assert n > 1000
    for name in trace:
        assert trace[name].dtype == np.float64 and trace[name].shape[0] == n
    assert trace["current_a"].shape == (n, 2)
    # The CSV rounds to 4-7 decimals; the arrays are the full-precision values.
    np.testing.assert_allclose(trace["time_s"], table["time_s"], atol=1e-4)
    np.testing.assert_allclose(trace["angle_rad"], table["angle_rad"], atol=1e-6)
    np.testing.assert_allclose(trace["current_a"][:, 1], table["current2_A"], atol=1e-5)
    np.testing.assert_allclose(trace["hand_torque_nm"], table["hand_torque_Nm"], atol=1e-5)


def test_wall_bad_input(cli):
    with pytest.raises(ValueError, match="device 'brake'"):
        mrbrake.haptic.wall("brake")
    # The library's range, named by the keyword (the CLI names its flag --stiffness).
    with pytest.raises(ValueError, match=r"^stiffness: haptic \(got -1; allowed: \[0, 100000\]\)"):
        mrbrake.haptic.wall("motor", stiffness=-1.0)
    with pytest.raises(ValueError, match=r"^damping: haptic \(got NaN"):
        mrbrake.haptic.wall("motor", damping=float("nan"))
    code, message = cli.fail("haptic", "wall", "--device", "motor", "--duration", "5000s")
    with pytest.raises(ValueError) as caught:
        mrbrake.haptic.wall("motor", duration="5000s")
    assert code == 2 and str(caught.value) in message


def test_rig_characterize_equals_the_cli_log(cli, tmp_path):
    cli.json("rig", "characterize", "--out", tmp_path, "--seed", "7")
    table = np.genfromtxt(tmp_path / "characterization.csv", delimiter=",", names=True)
    got = mrbrake.rig.characterize(seed=7)
    assert set(got) == {"time_s", "current_a", "torque_nm", "speed_rad_s"}
    for name, column in [("time_s", "time_s"), ("current_a", "current_A"),
                         ("torque_nm", "torque_Nm"), ("speed_rad_s", "speed_rad_s")]:
        assert got[name].dtype == np.float64 and got[name].shape == (len(table),)
        # The CSV has 7 decimals.
        np.testing.assert_allclose(got[name], table[column], rtol=0, atol=1e-7)
    assert got["current_a"].max() > 0.5


def test_rig_freqresp_equals_the_cli_logs(cli, tmp_path):
    cli.json("rig", "freqresp", "--out", tmp_path, "--seed", "3")
    with open(tmp_path / "manifest.csv", newline="") as f:
        manifest = [(float(r["frequency_rad_s"]), r["file"]) for r in csv.DictReader(f)]
    runs = mrbrake.rig.freqresp(seed=3)
    assert len(runs) == len(manifest) > 1
    for run, row in zip(runs, manifest):
        omega, name = row
        assert abs(run["frequency_rad_s"] - omega) <= 1e-12 * omega
        table = np.genfromtxt(tmp_path / name, delimiter=",", names=True)
        for name, column in [("time_s", "time_s"), ("input_nm", "input"),
                             ("output_nm", "output"), ("current_a", "current_A")]:
            assert run[name].dtype == np.float64 and run[name].shape == (len(table),)
            np.testing.assert_allclose(run[name], table[column], rtol=0, atol=1e-7)
