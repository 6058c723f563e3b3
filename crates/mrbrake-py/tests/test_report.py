"""`mrbrake.report` writes the page `mrbrake report` writes (the same library composition):
a design report, a study report of a store; bad input as the CLI's."""

import re

import pytest

import mrbrake


def _without_times(html):
    """The page without wall times (they differ between runs)."""
    return re.sub(r"\d+(\.\d+)?\s*(s|ms)\b", "T", html)


def test_design_report_is_the_cli_page(cli, tmp_path):
    out = tmp_path / "py.html"
    html = mrbrake.report(mesh="coarse", points=5, output=out)
    assert out.read_text() == html
    done = cli.run("report", "--mesh", "coarse", "--points", "5", "-o", tmp_path / "cli.html")
    assert done.returncode == 0, done.stderr
    expected = (tmp_path / "cli.html").read_text()
    assert html.startswith("<!DOCTYPE html>") and "thesis" in html.lower()
    assert _without_times(html) == _without_times(expected)


def test_study_report_is_the_cli_page(cli, tmp_path):
    store = tmp_path / "s.sqlite"
    mrbrake.sweep(vary={"g": ["0.4mm", "0.5mm"]}, store=store, mesh="coarse", jobs=1)
    html = mrbrake.report(store=store)
    done = cli.run("report", "--store", store, "-o", tmp_path / "cli.html")
    assert done.returncode == 0, done.stderr
    assert html == (tmp_path / "cli.html").read_text()


def test_report_bad_input_is_value_error(cli, tmp_path):
    code, message = cli.fail("report", "--mesh", "coarse", "--points", "1", "-o",
                             tmp_path / "x.html")
    with pytest.raises(ValueError, match="points"):
        mrbrake.report(mesh="coarse", points=1)
    assert code == 2 and "points" in message
    with pytest.raises(ValueError, match="store"):
        mrbrake.report(store=tmp_path / "s.sqlite", log=tmp_path / "l.csv")
