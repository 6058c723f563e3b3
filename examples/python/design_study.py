"""A design study from Python: analyse the thesis brake, plot its field and torque curve (when
matplotlib is installed), and fit a transfer function to the coil's current response.

Run from the repository root after `pip install ./crates/mrbrake-py`:

    python examples/python/design_study.py [OUTPUT_DIR] [--mesh coarse|default|fine]

It asserts its key numbers, so the test suite runs it (crates/mrbrake-py/tests/test_example.py).
"""

import argparse
import pathlib

import numpy as np

import mrbrake


def analyse(mesh):
    a = mrbrake.analyze(mesh=mesh)  # the embedded thesis bidirectional brake
    print(f"{a.name} ({a.configuration}), mesh {a.mesh['elements']} triangles")
    print(f"  torque at {a.max_current_a:g} A: {a.torque_nm[-1]:.3f} N·m, "
          f"off-state {a.torque['off_state_Nm']:.3f} N·m")
    print(f"  coil: {a.coil['turns']} turns, {a.coil['resistance_ohm']:.2f} Ω, "
          f"L = {a.coil['inductance_H'] * 1e3:.2f} mH, τ = {a.coil['time_constant_s'] * 1e3:.2f} ms")
    print(f"  analysis took {a.timings_s['total']:.2f} s")
    assert a.torque_nm[-1] == a.to_dict()["torque_current_curve"][-1]["torque_Nm"]
    assert np.all(np.diff(a.torque_nm) > 0), "torque rises with current"
    return a


def plot(a, out):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("  (matplotlib is not installed: no plots)")
        return []
    nodes, triangles, b_abs = a.field()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.5))
    pc = ax1.tripcolor(nodes[:, 0] * 1e3, nodes[:, 1] * 1e3, triangles, facecolors=b_abs,
                       cmap="viridis")
    ax1.tricontour(nodes[:, 0] * 1e3, nodes[:, 1] * 1e3, triangles, a.flux_function(), 20,
                   colors="w", linewidths=0.5)
    ax1.set(xlabel="r (mm)", ylabel="z (mm)", title=f"|B| at {a.max_current_a:g} A",
            aspect="equal")
    fig.colorbar(pc, ax=ax1, label="|B| (T)")
    ax2.plot(a.current_a, a.torque_nm, "o-", label="field solution")
    ax2.plot(a.current_a, a.thesis_formula_nm, "--", label="thesis method")
    ax2.set(xlabel="current (A)", ylabel="torque (N·m)", title="torque–current curve")
    ax2.legend()
    fig.tight_layout()
    path = out / "design_study.png"
    fig.savefig(path, dpi=100)
    print(f"  wrote {path}")
    return [path]


def fit_current_response(a):
    """The coil current answers a voltage step as a first-order lag of τ = L/R: sample that
    response with 1 % noise, fit one pole, and get τ back."""
    tau = a.coil["time_constant_s"]
    omega = np.logspace(0, 5, 40) / tau / 1e2
    rng = np.random.default_rng(1)
    g = 1.0 / (1j * omega * tau + 1.0) * (1.0 + 0.01 * rng.standard_normal(omega.size))
    fit = mrbrake.sysid.tfest(omega, g, poles=1)
    d = fit.to_dict()
    tau_fit = -1.0 / d["poles"][0][0]
    print(f"  fitted current response: pole at {d['poles'][0][0]:.1f} rad/s, τ = "
          f"{tau_fit * 1e3:.3f} ms (coil {tau * 1e3:.3f} ms), fit {fit.fit_percent:.1f} %")
    assert abs(tau_fit / tau - 1.0) < 0.02
    return tau_fit


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", nargs="?", default=".", type=pathlib.Path)
    parser.add_argument("--mesh", default="default")
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    a = analyse(args.mesh)
    plot(a, args.out)
    fit_current_response(a)


if __name__ == "__main__":
    main()
