"""mrbrake.sweep / mrbrake.optimize write the same store as the CLI; store.load reads it back."""

import textwrap

import mrbrake

SWEEP_ARGS = ["--vary", "g=0.4mm,0.5mm", "--mesh", "coarse", "--jobs", "2"]
SAME = ("key", "status", "reason", "variables", "metrics", "solver_version")


def _same(record):
    return {k: record[k] for k in SAME}


def test_sweep_store_round_trip(cli, tmp_path):
    store = tmp_path / "py.sqlite"
    report = mrbrake.sweep(vary={"g": ["0.4mm", 0.0005]}, store=store, mesh="coarse", jobs=2)
    assert len(report["designs"]) == 2 and report["summary"]["computed"] == 2
    records = mrbrake.store.records(store)
    exported = cli.json("export", store)
    assert records == exported and len(records) == 2
    rows = mrbrake.store.load(store)
    rows = rows.to_dict("records") if hasattr(rows, "to_dict") else rows
    assert [r["key"] for r in rows] == [r["key"] for r in exported]
    assert all(r["status"] == "ok" for r in rows)

    # The CLI's sweep of the same plan: the same designs (keys), values and metrics.
    cli_store = tmp_path / "cli.sqlite"
    cli_report = cli.json("sweep", *SWEEP_ARGS, "--store", cli_store)
    assert sorted(map(_same, cli.json("export", cli_store)), key=lambda r: r["key"]) == \
        sorted(map(_same, exported), key=lambda r: r["key"])
    assert set(report) == set(cli_report)

    # Resuming computes nothing; without resume an existing store is refused as by the CLI.
    again = mrbrake.sweep(vary=["g=0.4mm,0.5mm"], store=store, mesh="coarse", resume=True)
    assert again["summary"]["computed"] == 0 and again["summary"]["reused"] == 2
    code, message = cli.fail("sweep", *SWEEP_ARGS, "--store", store)
    try:
        mrbrake.sweep(vary=["g=0.4mm,0.5mm"], store=store, mesh="coarse")
    except ValueError as e:
        assert code == 2 and str(e) in message
    else:
        raise AssertionError("an existing store without resume must be refused")


def test_sweep_bad_variable_is_value_error(cli, tmp_path):
    code, message = cli.fail("sweep", "--vary", "nope=1mm", "--store", tmp_path / "c.sqlite")
    try:
        mrbrake.sweep(vary={"nope": "1mm"}, store=tmp_path / "p.sqlite")
    except ValueError as e:
        assert code == 2 and str(e) in message
    else:
        raise AssertionError("an unknown variable must be a ValueError")


def test_optimize_small_pattern_search(cli, tmp_path):
    problem = tmp_path / "tiny.toml"
    spec = (mrbrake_root() / "examples/specs/thesis-bidirectional.toml").as_posix()
    problem.write_text(textwrap.dedent(f"""\
        spec = "{spec}"
        mesh = "coarse"
        [[variable]]
        name = "h"
        min = "8mm"
        max = "10mm"
        [[objective]]
        metric = "rotor_inertia_kg_m2"
        goal = "minimize"
        [algorithm]
        kind = "pattern-search"
        max_evaluations = 3
        """))
    got = mrbrake.optimize(problem, store=tmp_path / "py.sqlite", jobs=1)
    expected = cli.json("optimize", problem, "--store", tmp_path / "cli.sqlite", "--jobs", "1")
    assert _strip(got) == _strip(expected)
    assert mrbrake.store.records(tmp_path / "py.sqlite") == cli.json("export", tmp_path / "py.sqlite")


def mrbrake_root():
    from conftest import ROOT
    return ROOT


def _strip(document):
    """The optimisation report without wall times, rates and store paths (they differ between
    runs)."""
    if isinstance(document, dict):
        return {k: _strip(v) for k, v in document.items()
                if not (k.endswith("_s") or k.endswith("seconds")
                         or k in ("store", "evaluations_per_min", "store_overhead"))}
    if isinstance(document, list):
        return [_strip(v) for v in document]
    return document
