"""mrbrake.sysid on arrays against the CLI on the same data written as CSV files."""

import numpy as np
import pytest

import mrbrake


def ramp_log(repetitions=3, dt=1e-3):
    """A synthetic repeated-ramp log: 0 -> 2 A -> 0 with a pause, hysteretic torque, no noise."""
    up = np.linspace(0.0, 2.0, 801)
    one = np.concatenate([up, up[::-1][1:], np.zeros(300)])
    current = np.concatenate([np.zeros(300)] + [one] * repetitions)
    rising = np.concatenate([[True], np.diff(current) >= 0])
    torque = 0.15 + 1.9 * current - 0.12 * current**2 + np.where(rising, -0.04, 0.04) * current
    time = np.arange(current.size) * dt
    return time, current, torque


def write_csv(path, columns):
    names = list(columns)
    rows = np.column_stack([columns[n] for n in names])
    np.savetxt(path, rows, delimiter=",", header=",".join(names), comments="", fmt="%.17g")


def test_characterize_equals_the_cli(cli, tmp_path):
    time, current, torque = ramp_log()
    path = tmp_path / "log.csv"
    write_csv(path, {"time_s": time, "current_A": current, "torque_Nm": torque})
    expected = cli.json("characterize", path)
    got = mrbrake.sysid.characterize(time, current, torque)
    assert got.pop("log") == "<arrays>"
    expected.pop("log")
    assert got == expected
    assert got["repetitions"] == 3 and got["rising"]["fit_percent"] > 99.0


def test_characterize_accepts_lists_and_strided_arrays():
    time, current, torque = ramp_log(repetitions=2)
    from_lists = mrbrake.sysid.characterize(time.tolist(), current.tolist(), torque.tolist())
    stacked = np.column_stack([time, current, torque])  # columns are strided views
    from_views = mrbrake.sysid.characterize(stacked[:, 0], stacked[:, 1], stacked[:, 2])
    assert from_lists == from_views


def test_characterize_rejects_bad_input():
    time, current, torque = ramp_log(repetitions=2)
    with pytest.raises(ValueError, match="strictly increase"):
        mrbrake.sysid.characterize(time[::-1], current, torque)
    with pytest.raises(ValueError, match="samples"):
        mrbrake.sysid.characterize(time, current[:-1], torque)
    with pytest.raises(ValueError, match=r"^order: got 13; allowed: 1\.\.=12$"):
        mrbrake.sysid.characterize(time, current, torque, order=13)


def test_freqresp_equals_the_cli(cli, tmp_path):
    omega = 20.0
    time = np.arange(0, 3.0, 1e-3)
    u = np.sin(omega * time)
    y = 0.8 * np.sin(omega * time - 0.3)
    write_csv(tmp_path / "t1.csv", {"time_s": time, "input": u, "output": y})
    (tmp_path / "manifest.csv").write_text(f"frequency_rad_s,file\n{omega},t1.csv\n")
    expected = cli.json("freqresp", tmp_path / "manifest.csv")["points"][0]
    got = mrbrake.sysid.freqresp(time, u, y, omega)
    for key in ["omega_rad_s", "magnitude_dB", "phase_deg", "re", "im", "periods"]:
        assert got[key] == expected[key], key
    assert got["magnitude_dB"] == pytest.approx(20 * np.log10(0.8), abs=1e-9)
    assert got["phase_deg"] == pytest.approx(-np.degrees(0.3), abs=1e-7)


def test_tfest_recovers_a_second_order_model_as_the_cli(cli, tmp_path):
    omega = np.logspace(-1, 3, 60)
    s = 1j * omega
    g = 400.0 / (s**2 + 28.0 * s + 400.0)
    write_csv(tmp_path / "frd.csv", {"omega_rad_s": omega, "re": g.real, "im": g.imag})
    expected = cli.json("tfest", tmp_path / "frd.csv", "--poles", "2")
    fit = mrbrake.sysid.tfest(omega, g, poles=2)
    assert fit.to_dict() == expected
    assert fit.numerator.dtype == np.float64 and fit.denominator.shape == (3,)
    assert fit.fit_percent > 99.99
    assert np.allclose(fit.response(omega), g, rtol=1e-6, atol=1e-9)
    den = fit.denominator / fit.denominator[0]
    assert den == pytest.approx([1.0, 28.0, 400.0], rel=1e-6)
    with pytest.raises(ValueError, match=r"^zeros: got 2; allowed: <= poles \(1\)$"):
        mrbrake.sysid.tfest(omega, g, poles=1, zeros=2)
    with pytest.raises(ValueError, match=r"^delay: got -1 s; allowed: >= 0 s$"):
        mrbrake.sysid.tfest(omega, g, poles=2, delay=-1.0)
    with pytest.raises(ValueError):
        mrbrake.sysid.tfest(omega, g, poles=2, weighting="cubic")
