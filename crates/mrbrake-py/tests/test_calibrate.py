"""`mrbrake.calibrate` against `mrbrake calibrate --json`: the same inputs give the same fit, and
bad input is the CLI's error as a ValueError."""

import mrbrake

ARGS = ["--parameter", "fluid.yield_stress_scale=0.3..1.5", "--mesh", "coarse", "--points", "5",
        "--max-evaluations", "10"]


def _log(cli, tmp_path):
    out = tmp_path / "rig"
    done = cli.run("rig", "characterize", "--out", out)
    assert done.returncode == 0, done.stderr
    return out / "characterization.csv"


def test_calibrate_matches_the_cli(cli, tmp_path):
    log = _log(cli, tmp_path)
    report = mrbrake.calibrate(log=log, parameters=["fluid.yield_stress_scale=0.3..1.5"],
                               mesh="coarse", points=5, max_evaluations=10)
    expected = cli.json("calibrate", "--log", log, *ARGS)
    assert report["parameters"] == expected["parameters"]
    assert report["correlation"] == expected["correlation"]
    assert report["curve"] == expected["curve"]
    assert "# calibrated:" in report["calibrated_spec"]
    estimate = report["parameters"][0]["estimate"]
    assert 0.3 < estimate < 1.0, estimate  # the prototype brakes less than the drawing predicts


def test_calibrate_bad_parameter_is_value_error(cli, tmp_path):
    log = _log(cli, tmp_path)
    code, message = cli.fail("calibrate", "--log", log, "--parameter", "coil.turns")
    try:
        mrbrake.calibrate(log=log, parameters="coil.turns")
    except ValueError as e:
        assert code == 2 and str(e) in message, (str(e), message)
    else:
        raise AssertionError("a whole-number parameter must be a ValueError")
