"""mrbrake.fem.solve against `mrbrake fem solve --json` on the example problem files."""

import numpy as np
import pytest

import mrbrake


def without_timings(doc):
    return {k: v for k, v in doc.items() if "timing" not in k and "seconds" not in k}


@pytest.mark.parametrize("problem", ["examples/fem/potcore.toml", "examples/fem/potcore-heat.toml"])
def test_solve_equals_the_cli(cli, root, problem):
    expected = cli.json("fem", "solve", problem)
    solution = mrbrake.fem.solve(root / problem)
    got = solution.to_dict()
    assert got.keys() == expected.keys()
    assert without_timings(got) == without_timings(expected)
    nodes, triangles, values = solution.field()
    assert nodes.dtype == np.float64 and nodes.shape[1] == 2
    assert triangles.dtype == np.int64 and triangles.shape[1] == 3
    assert triangles.max() == nodes.shape[0] - 1
    if solution.physics == "heat":
        assert values.shape == (nodes.shape[0],) and solution.flux_function() is None
    else:
        assert values.shape == (triangles.shape[0],) and values.max() > 0.0
        assert solution.flux_function().shape == (nodes.shape[0],)


def test_a_missing_problem_file_has_the_cli_message(cli, tmp_path):
    missing = tmp_path / "none.toml"
    code, message = cli.fail("fem", "solve", missing)
    with pytest.raises(FileNotFoundError) as e:
        mrbrake.fem.solve(missing)
    assert str(e.value) == message
    with pytest.raises(ValueError):
        mrbrake.fem.solve(missing, order=3)
