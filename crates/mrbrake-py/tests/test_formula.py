"""mrbrake.formula agrees with `mrbrake formula ... --json` for the same inputs."""

import pytest

import mrbrake


def test_single_disc_given_tau_y_with_viscous_term(cli):
    expected = cli.json("formula", "single-disc", "--r1", "22.5mm", "--r2", "27.5mm",
                        "--tau-y", "24.315kPa", "--speed", "60rpm", "--gap", "0.5mm")
    got = mrbrake.formula.single_disc("22.5mm", 0.0275, tau_y=24315.0, speed="60rpm", gap="0.5mm")
    assert got == expected
    assert got["torque_Nm"] > got["yield_torque_Nm"] > 0.0


def test_multi_disc_from_flux_density(cli):
    expected = cli.json("formula", "multi-disc", "--discs", "3", "--r1", "20mm", "--r2", "30mm",
                        "--b", "0.46T", "--fluid", "mrf-132dg")
    got = mrbrake.formula.multi_disc(3, "20mm", "30mm", b=0.46, fluid="mrf-132dg")
    assert got == expected
    assert got["inputs"]["tau_y_source"].endswith("tau_y(B) at 0.46 T")


def test_drum_and_multi_drum(cli):
    expected = cli.json("formula", "drum", "--r", "25mm", "--h", "9mm", "--b", "0.5T",
                        "--speed", "10rad/s", "--gap", "0.5mm", "--eta", "0.1Pa.s")
    assert mrbrake.formula.drum(0.025, "9mm", b="0.5T", speed=10.0, gap=5e-4, eta=0.1) == expected
    expected = cli.json("formula", "multi-drum", "--r0", "25mm", "--h", "9mm", "--d", "1mm",
                        "--g", "0.5mm", "--surfaces", "4", "--tau-y", "25.67kPa", "--speed", "60rpm")
    got = mrbrake.formula.multi_drum("25mm", "9mm", "1mm", "0.5mm", 4, tau_y="25.67kPa",
                                     speed="60rpm")
    assert got == expected
    assert len(got["inputs"]["radii_m"]) == 4


def test_coil(cli):
    expected = cli.json("formula", "coil", "--window-width", "12mm", "--window-height", "12mm",
                        "--awg", "24", "--current", "1.5A", "--temperature", "75C")
    got = mrbrake.formula.coil("12mm", 0.012, awg=24, current=1.5, temperature="75C")
    assert got == expected
    expected = cli.json("formula", "coil", "--window-width", "10mm", "--window-height", "8mm",
                        "--wire-diameter", "0.5mm", "--turns", "100")
    assert mrbrake.formula.coil(0.01, 0.008, wire_diameter="0.5mm", turns=100) == expected


def test_bad_input_is_value_error(cli):
    with pytest.raises(ValueError, match="tau_y or b"):
        mrbrake.formula.single_disc(0.02, 0.03)
    with pytest.raises(ValueError, match="needs gap"):
        mrbrake.formula.drum(0.02, 0.01, tau_y=1e4, speed=1.0)
    with pytest.raises(ValueError, match="between 0 T and 3 T"):
        mrbrake.formula.drum(0.02, 0.01, b=5.0)
    code, message = cli.fail("formula", "single-disc", "--r1", "30mm", "--r2", "20mm",
                             "--tau-y", "1kPa")
    with pytest.raises(ValueError) as caught:
        mrbrake.formula.single_disc(0.03, 0.02, tau_y=1000.0)
    assert code == 2 and str(caught.value) in message
