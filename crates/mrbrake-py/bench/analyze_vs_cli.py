"""Wall-clock time of `mrbrake.analyze()` against the release CLI's `mrbrake analyze` on the
embedded thesis brake (the issue asks for the binding within 5 % of the CLI), and of
`mrbrake.sysid.characterize` on a 450 k-sample log (arrays borrowed in place).

    python crates/mrbrake-py/bench/analyze_vs_cli.py [RUNS]

Runs alternate between the two so that machine load hits both alike; prints medians.
Not a test: timings go in the README, not in assertions.
"""

import pathlib
import statistics
import subprocess
import sys
import time

import numpy as np

import mrbrake

ROOT = pathlib.Path(__file__).resolve().parents[3]
CLI = ROOT / "target" / "release" / "mrbrake"


def time_cli():
    t0 = time.perf_counter()
    subprocess.run([str(CLI), "analyze", "--json"], check=True, capture_output=True)
    return time.perf_counter() - t0


def time_python():
    t0 = time.perf_counter()
    a = mrbrake.analyze()
    a.to_dict()
    return time.perf_counter() - t0


def ramp_log(samples):
    up = np.linspace(0.0, 2.0, 2001)
    one = np.concatenate([up, up[::-1][1:], np.zeros(500)])
    reps = samples // one.size
    current = np.concatenate([np.zeros(samples - reps * one.size)] + [one] * reps)
    rising = np.concatenate([[True], np.diff(current) >= 0])
    torque = 0.15 + 1.9 * current - 0.12 * current**2 + np.where(rising, -0.04, 0.04) * current
    return np.arange(samples) * 1e-3, current, torque


def main():
    runs = int(sys.argv[1]) if len(sys.argv) > 1 else 5
    time_python()  # warm the page cache and the library
    cli, py = [], []
    for _ in range(runs):
        cli.append(time_cli())
        py.append(time_python())
    c, p = statistics.median(cli), statistics.median(py)
    print(f"analyze, thesis brake, {runs} runs: CLI median {c:.3f} s, Python median {p:.3f} s "
          f"({100 * (p / c - 1):+.1f} %)")
    t, i, tau = ramp_log(450_000)
    assert np.ascontiguousarray(t, dtype=np.float64) is t, "no copy on the Python side"
    times = []
    for _ in range(runs):
        t0 = time.perf_counter()
        mrbrake.sysid.characterize(t, i, tau)
        times.append(time.perf_counter() - t0)
    print(f"characterize, 450000 samples: median {statistics.median(times) * 1e3:.1f} ms")


if __name__ == "__main__":
    main()
