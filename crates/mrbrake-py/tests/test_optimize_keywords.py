"""`mrbrake.optimize`'s keywords are the CLI's flags: `max_evaluations=` (`--max-evaluations`),
`generations=` (`--generations`), `seed=` and `set=` (`--set PATH=VALUE`, a dict or a list)."""

import textwrap

import pytest

import mrbrake
from test_study import _strip, mrbrake_root


def _problem(tmp_path):
    problem = tmp_path / "tiny.toml"
    spec = (mrbrake_root() / "examples/specs/thesis-bidirectional.toml").as_posix()
    problem.write_text(textwrap.dedent(f"""\
        spec = "{spec}"
        mesh = "coarse"
        [[variable]]
        name = "h"
        min = "8mm"
        max = "10mm"
        [[variable]]
        name = "g"
        min = "0.4mm"
        max = "0.6mm"
        [[objective]]
        metric = "rotor_inertia_kg_m2"
        [[objective]]
        metric = "torque_max_Nm"
        goal = "maximize"
        [algorithm]
        kind = "nsga2"
        population = 4
        generations = 5
        """))
    return problem


def test_optimize_keywords_are_the_cli_flags(cli, tmp_path):
    problem = _problem(tmp_path)
    got = mrbrake.optimize(problem, store=tmp_path / "py.sqlite", jobs=1, generations=0,
                           set={"drum.gap": "0.5mm"}, seed=7)
    expected = cli.json("optimize", problem, "--store", tmp_path / "cli.sqlite", "--jobs", "1",
                        "--generations", "0", "--set", "drum.gap=0.5mm", "--seed", "7")
    assert _strip(got) == _strip(expected)
    # g is fixed by the set: every design has the same gap, and only the population was run.
    records = mrbrake.store.records(tmp_path / "py.sqlite")
    assert got["requested"] == expected["requested"]
    assert len({r["variables"].get("g") for r in records}) <= 1

    budget = mrbrake.optimize(problem, store=tmp_path / "py2.sqlite", jobs=1,
                              max_evaluations=4, set=["drum.gap=0.5mm"])
    cli_budget = cli.json("optimize", problem, "--store", tmp_path / "cli2.sqlite", "--jobs",
                          "1", "--max-evaluations", "4", "--set", "drum.gap=0.5mm")
    assert _strip(budget) == _strip(cli_budget)


def test_optimize_bad_keyword_is_value_error(cli, tmp_path):
    problem = _problem(tmp_path)
    code, message = cli.fail("optimize", problem, "--store", tmp_path / "c.sqlite",
                             "--max-evaluations", "0")
    with pytest.raises(ValueError, match="max_evaluations") as raised:
        mrbrake.optimize(problem, store=tmp_path / "p.sqlite", max_evaluations=0)
    assert code == 2 and message.startswith("--max-evaluations")
    assert str(raised.value).split(": ", 1)[1] == message.split(": ", 1)[1]
