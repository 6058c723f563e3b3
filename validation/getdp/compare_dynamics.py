#!/usr/bin/env python3
"""Compare mrbrake's magnetodynamic solves with GetDP's (run_dynamics.sh writes both).

usage: compare_dynamics.py OUT TURNS FREQ...

Harmonic: the coil's complex flux linkage and the time-averaged eddy loss at every frequency.
Transient: the flux linkage at every implicit-Euler step. Both codes assemble the same algebraic
systems, so only the solvers' round-off (and mrbrake's reduced-basis sweep, whose residual check
reached round-off here) remains: exit status 1 when a relative difference exceeds 1e-9 (measured:
2.3e-13 harmonic, 4.8e-14 transient).
"""

import json
import sys


def numbers(path):
    """The numbers of the last line of a GetDP table of a global quantity: the step (0), then the
    value (real systems) or its real and imaginary parts (complex systems)."""
    with open(path) as f:
        lines = [line.split() for line in f if line.strip()]
    return [float(x) for x in lines[-1]]


def time_table(path):
    """(time, value) rows of a GetDP TimeTable of a global quantity."""
    rows = []
    with open(path) as f:
        for line in f:
            cells = line.split()
            if len(cells) >= 2:
                rows.append((float(cells[0]), float(cells[-1])))
    return rows


def main(argv):
    out, turns, freqs = argv[0], float(argv[1]), [float(f) for f in argv[2:]]
    status = 0

    def check(label, ours, theirs, tol):
        nonlocal status
        scale = max(abs(theirs), 1e-300)
        diff = abs(ours - theirs) / scale
        ok = diff <= tol
        status |= 0 if ok else 1
        print(f"{'ok  ' if ok else 'FAIL'} {label}: mrbrake {ours:.10e}, GetDP {theirs:.10e}, "
              f"relative {diff:.2e} (tol {tol:.0e})")
        return diff

    harmonic = json.load(open(f"{out}/harmonic.json"))["harmonic"]
    print("== harmonic (peak phasors, exp(+jwt)), linear conducting steel, same discrete space ==")
    worst = 0.0
    for point, f in zip(harmonic, freqs):
        d = f"{out}/getdp_harmonic_{f:g}"
        a = numbers(f"{d}/a_coil.txt")
        area = numbers(f"{d}/area_coil.txt")[1]
        lam_re, lam_im = turns / area * a[1], turns / area * a[2]
        ours = point["coils"][0]["flux_linkage_Wb"]
        magnitude = (lam_re ** 2 + lam_im ** 2) ** 0.5
        for part, (o, t) in (("re", (ours[0], lam_re)), ("im", (ours[1], lam_im))):
            # Relative to |lambda| (a small part of a phasor is not compared to itself).
            diff = abs(o - t) / magnitude
            worst = max(worst, diff)
            ok = diff <= 1e-9
            status |= 0 if ok else 1
            print(f"{'ok  ' if ok else 'FAIL'} f = {f:g} Hz, flux linkage {part}: mrbrake {o:.10e}, "
                  f"GetDP {t:.10e}, difference / |lambda| {diff:.2e} (tol 1e-09)")
        getdp_loss = numbers(f"{d}/eddy_loss.txt")[1]
        worst = max(worst, check(f"f = {f:g} Hz, eddy loss [W]", point["eddy_loss_W"], getdp_loss, 1e-9))
    print(f"largest harmonic difference {worst:.2e}")

    transient = json.load(open(f"{out}/transient.json"))["transient"]
    times, ours = transient["time_s"], transient["coils"][0]["flux_linkage_Wb"]
    area = numbers(f"{out}/getdp_transient/area_coil.txt")[1]
    theirs = time_table(f"{out}/getdp_transient/a_coil_t.txt")
    print("== transient, implicit Euler, current step, same discrete space ==")
    print(f"mrbrake {len(times) - 1} steps, GetDP {len(theirs)} saved steps")
    final = abs(ours[-1])
    worst = 0.0
    compared = 0
    for t, value in theirs:
        k = min(range(len(times)), key=lambda i: abs(times[i] - t))
        if abs(times[k] - t) > 1e-9 * max(t, 1e-12) + 1e-15:
            continue
        lam = turns / area * value
        worst = max(worst, abs(ours[k] - lam) / final)
        compared += 1
    ok = compared >= len(times) - 2 and worst <= 1e-9
    status |= 0 if ok else 1
    print(f"{'ok  ' if ok else 'FAIL'} flux linkage at {compared} common steps: largest difference "
          f"{worst:.2e} of the final flux linkage {ours[-1]:.6e} Wb (tol 1e-09)")
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
