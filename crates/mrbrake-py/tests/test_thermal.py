"""`mrbrake.thermal` against `mrbrake thermal --json`: the same inputs give the same document
(wall times aside), bad input is a ValueError as the CLI's exit 2, a missing spec a
FileNotFoundError."""

import pytest

import mrbrake


WALL_TIMES = ("timings_s", "analysis_s")


def _without_timings(document):
    """The document without its wall times (they differ between runs)."""
    if isinstance(document, dict):
        return {k: _without_timings(v) for k, v in document.items() if k not in WALL_TIMES}
    if isinstance(document, list):
        return [_without_timings(v) for v in document]
    return document


def test_thermal_matches_the_cli(cli):
    report = mrbrake.thermal(mesh="coarse", current="1.5A", duty=0.5, h="natural",
                             time="10min", dt=60, behaviour=False)
    expected = cli.json("thermal", "--mesh", "coarse", "--current", "1.5A", "--duty", "0.5",
                        "--h", "natural", "--time", "10min", "--dt", "60s", "--no-behaviour")
    assert _without_timings(report) == _without_timings(expected)
    assert report["continuous_current_A"] > 0


def test_thermal_with_hot_behaviour_matches_the_cli(cli):
    report = mrbrake.thermal(mesh="coarse", h=15, ambient="30C", time="5min", dt="30s")
    expected = cli.json("thermal", "--mesh", "coarse", "--h", "15", "--ambient", "30C",
                        "--time", "5min", "--dt", "30s")
    assert _without_timings(report) == _without_timings(expected)
    assert report["behaviour"] is not None


def test_thermal_bad_duty_is_value_error(cli):
    code, message = cli.fail("thermal", "--mesh", "coarse", "--duty", "1.5")
    with pytest.raises(ValueError, match="duty") as raised:
        mrbrake.thermal(mesh="coarse", duty=1.5)
    assert code == 2 and "1.5" in str(raised.value), (message, str(raised.value))


def test_missing_files_are_file_not_found(tmp_path):
    missing = tmp_path / "missing.toml"
    for call in (lambda: mrbrake.thermal(missing), lambda: mrbrake.response(missing),
                 lambda: mrbrake.analyze(missing), lambda: mrbrake.optimize(missing),
                 lambda: mrbrake.report(store=tmp_path / "missing.sqlite")):
        with pytest.raises(FileNotFoundError):
            call()
