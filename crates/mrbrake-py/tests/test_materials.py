"""mrbrake.materials against `mrbrake materials list/show --json`; curves as float64 arrays."""

import numpy as np
import pytest

import mrbrake


def test_list_equals_the_cli(cli):
    assert mrbrake.materials.list() == cli.json("materials", "list")


@pytest.mark.parametrize("name", ["steel-1008", "mrf-122eg", "copper", "air"])
def test_show_equals_the_cli(cli, name):
    m = mrbrake.materials.get(name)
    assert m.to_dict() == cli.json("materials", "show", name)
    assert m.name == name and m.provenance == m.to_dict()["provenance"]


def test_show_at_chosen_points_equals_the_cli(cli):
    m = mrbrake.materials.get("mrf-122eg")
    got = m.to_dict(b=np.array([0.3, 0.46]), h=np.array([2000.0]))
    assert got == cli.json("materials", "show", "mrf-122eg", "--b", "0.3T,0.46T", "--h", "2kA/m")


def test_curves_are_arrays():
    steel = mrbrake.materials.get("steel-1008")
    h, b = steel.bh_curve
    assert h.dtype == b.dtype == np.float64 and h.shape == b.shape and h.ndim == 1
    assert np.all(np.diff(h) > 0) and np.all(np.diff(b) > 0)
    b_mid = steel.b_of_h(h)
    assert np.allclose(b_mid, b, rtol=1e-9), "the curve passes through its points"
    assert steel.yield_stress_curve is None
    fluid = mrbrake.materials.get("mrf-122eg")
    x, tau, variable = fluid.yield_stress_curve
    assert x.shape == tau.shape and variable in ("B", "H", "B_T", "H_A_per_m") or variable
    tau_at = fluid.tau_y_of_b(np.array([0.0, 0.46]))
    assert tau_at[0] < tau_at[1]
    assert mrbrake.materials.get("air").bh_curve is None
    with pytest.raises(ValueError):
        steel.tau_y_of_b(np.array([0.5]))
    with pytest.raises(ValueError):
        steel.b_of_h(np.array([-1.0]))
