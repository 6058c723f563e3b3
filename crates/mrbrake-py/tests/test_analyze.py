"""mrbrake.analyze against `mrbrake analyze --json`: the same keys and numbers, NumPy arrays of the
right dtype and shape, specs given as a path, TOML text or a dict."""

import math
import sys

import numpy as np
import pytest

import mrbrake

SPEC = "examples/specs/single-disc.toml"


def without_timings(doc):
    doc = dict(doc)
    doc.pop("timings_s")
    return doc


def assert_same(a, b, path="$"):
    """Equal documents: same keys and types; floats equal to 1e-12 relative (the parallel
    assembly may sum in another order)."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), path
        for k in a:
            assert_same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{path}[{i}]")
    elif isinstance(a, float) or isinstance(b, float):
        assert math.isclose(a, b, rel_tol=1e-12, abs_tol=1e-300), f"{path}: {a} != {b}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


@pytest.fixture(scope="module")
def single_disc(root):
    return mrbrake.analyze(str(root / SPEC), mesh="coarse")


def test_to_dict_equals_the_cli_json(cli, single_disc):
    expected = cli.json("analyze", SPEC, "--mesh", "coarse")
    got = single_disc.to_dict()
    assert got.keys() == expected.keys()
    assert_same(without_timings(got), without_timings(expected))
    assert got["timings_s"].keys() == expected["timings_s"].keys()


def test_the_embedded_thesis_brake_equals_the_cli(cli):
    expected = cli.json("analyze", "--mesh", "coarse", "--points", "5")
    got = mrbrake.analyze(mesh="coarse", currents=5).to_dict()
    assert_same(without_timings(got), without_timings(expected))


def test_attributes_are_numpy_arrays_and_dicts(single_disc):
    a = single_disc
    doc = a.to_dict()
    for name in ["current_a", "torque_nm", "yield_torque_nm", "thesis_formula_nm", "mean_b_t",
                 "flux_linkage_wb"]:
        column = getattr(a, name)
        assert isinstance(column, np.ndarray) and column.dtype == np.float64, name
        assert column.shape == (21,), name
    curve = doc["torque_current_curve"]
    assert a.current_a.tolist() == [p["current_A"] for p in curve]
    assert a.torque_nm.tolist() == [p["torque_Nm"] for p in curve]
    assert a.current_a[-1] == a.max_current_a
    assert np.all(np.diff(a.torque_nm) > 0), "torque rises with current"
    assert a.coil == doc["coil"] and a.mechanics == doc["mechanics"] and a.gaps == doc["gaps"]
    assert a.torque == doc["torque"] and a.mesh == doc["mesh"]
    assert a.name == doc["name"] and a.configuration == "single-disc"
    assert set(a.timings_s) == {"mesh", "setup", "solve", "post", "total"}
    assert "single-disc" in repr(a)


def test_field_is_ready_for_tripcolor(single_disc):
    nodes, triangles, b_abs = single_disc.field()
    mesh = single_disc.mesh
    assert nodes.dtype == np.float64 and nodes.shape == (mesh["nodes"], 2)
    assert triangles.dtype == np.int64 and triangles.shape == (mesh["elements"], 3)
    assert b_abs.dtype == np.float64 and b_abs.shape == (mesh["elements"],)
    assert triangles.min() == 0 and triangles.max() == mesh["nodes"] - 1
    assert np.all(nodes[:, 0] >= 0.0), "axisymmetric: r >= 0"
    # The gap's mean |B| at the maximum current is in the range of the field's values.
    assert 0.0 < single_disc.torque["mean_B_T"] < b_abs.max()
    psi = single_disc.flux_function()
    assert psi.shape == (mesh["nodes"],) and psi.dtype == np.float64
    tags, names = single_disc.regions()
    assert tags.shape == (mesh["elements"],) and set(np.unique(tags)) <= set(names)
    assert any(material == "mrf-122eg" and "gap" in name for name, material in names.values())


def test_spec_as_toml_text_and_dict_give_the_same_result(root, single_disc):
    text = (root / SPEC).read_text()
    from_text = mrbrake.analyze(text, mesh="coarse").to_dict()
    assert_same(without_timings(from_text), without_timings(single_disc.to_dict()))
    if sys.version_info >= (3, 11):
        import tomllib

        from_dict = mrbrake.analyze(tomllib.loads(text), mesh="coarse").to_dict()
        assert_same(without_timings(from_dict), without_timings(single_disc.to_dict()))


def test_options_as_numbers_or_strings(root):
    a = mrbrake.analyze(str(root / SPEC), mesh="coarse", currents=3, speed="60rpm",
                        seal_friction=0.05, temperature="75C")
    b = mrbrake.analyze(str(root / SPEC), mesh="coarse", currents=3, speed=2 * math.pi,
                        seal_friction="50mNm", temperature=75.0)
    assert a.current_a.shape == (3,)
    assert_same(without_timings(a.to_dict()), without_timings(b.to_dict()))
    assert a.to_dict()["speed_rad_s"] == pytest.approx(2 * math.pi)
