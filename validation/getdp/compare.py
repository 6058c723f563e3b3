#!/usr/bin/env python3
"""Compare one mrbrake solve with one GetDP solve of the same problem on the same mesh (stdlib only).

Usage:
  compare.py --label NAME --mesh MESH.msh --mrbrake-json R.json --mrbrake-vtu R.vtu
             --getdp-dir DIR --turns N --tol-integral REL --tol-probe REL [--tol-nodal REL]

Quantities (SI units, over the whole body of revolution):
  flux_linkage_Wb   mrbrake coils[0].flux_linkage_Wb; GetDP (N/S) * int_coil 2 pi r A dS
  HB_integral_J     int H.B dV = W + W' (mrbrake energy_J + coenergy_J; GetDP int nu |B|^2 dV)
  mean_B_<region>   volume-weighted mean |B| (mrbrake regions[].mean_B_T; GetDP int |B| dV / V)
  B_abs_<probe>     |B| at the probes: mrbrake's recovered field; for GetDP the same recovery
                    (Zienkiewicz-Zhu simple averaging: at each node the area-weighted mean of the
                    centroid B of the triangles of the same region around it, B_r = 0 on the axis,
                    then linear interpolation) applied here to GetDP's element-centroid B
  nodal_A_max       max over nodes |A_mrbrake - A_GetDP| / max |A| (not a relative difference of
                    one number: the relative sup-norm distance of the two potentials)

Prints a table (quantity, mrbrake, GetDP, relative difference, tolerance) and exits with status 1
if a relative difference exceeds its tolerance.
"""

import argparse
import json
import math
import os
import re
import sys

REGION_NAMES = {1: "steel", 2: "coil", 3: "air"}


def read_msh22(path):
    """Nodes {tag: (x, y)} and triangles [(tag, physical, (n1, n2, n3))] of a MSH 2.2 ASCII file."""
    with open(path, encoding="ascii") as f:
        lines = f.read().splitlines()
    nodes, triangles = {}, []
    i = 0
    while i < len(lines):
        if lines[i] == "$Nodes":
            count = int(lines[i + 1])
            for k in range(count):
                tag, x, y, _ = lines[i + 2 + k].split()
                nodes[int(tag)] = (float(x), float(y))
            i += 2 + count
        elif lines[i] == "$Elements":
            count = int(lines[i + 1])
            for k in range(count):
                v = [int(t) for t in lines[i + 2 + k].split()]
                if v[1] == 2:
                    ntags = v[2]
                    triangles.append((v[0], v[3], tuple(v[3 + ntags:6 + ntags])))
            i += 2 + count
        else:
            i += 1
    return nodes, triangles


def read_getdp_scalar(path):
    with open(path, encoding="ascii") as f:
        return float(f.read().split()[1])


def read_getdp_node_table(path):
    with open(path, encoding="ascii") as f:
        values = f.read().split()
    count = int(values[0])
    return {int(values[1 + 2 * k]): float(values[2 + 2 * k]) for k in range(count)}


def read_getdp_element_b(path):
    """Element number -> (B_r, B_z) at the centroid (Print ... Depth 0, Format Table)."""
    out = {}
    with open(path, encoding="ascii") as f:
        for line in f:
            v = line.split()
            if len(v) >= 11:
                out[int(v[1])] = (float(v[8]), float(v[9]))
    return out


def read_vtu_array(path, name):
    with open(path, encoding="ascii") as f:
        text = f.read()
    m = re.search(r'<DataArray[^>]*Name="' + re.escape(name) + r'"[^>]*>(.*?)</DataArray>', text, re.S)
    if not m:
        sys.exit(f"{path}: no DataArray {name}")
    return [float(t) for t in m.group(1).split()]


def read_vtu_points(path):
    with open(path, encoding="ascii") as f:
        text = f.read()
    m = re.search(r"<Points>\s*<DataArray[^>]*>(.*?)</DataArray>", text, re.S)
    values = [float(t) for t in m.group(1).split()]
    return [(values[3 * k], values[3 * k + 1]) for k in range(len(values) // 3)]


def triangle_area(p):
    (x1, y1), (x2, y2), (x3, y3) = p
    return 0.5 * ((x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1))


def barycentric(p, q):
    (x1, y1), (x2, y2), (x3, y3) = p
    det = (y2 - y3) * (x1 - x3) + (x3 - x2) * (y1 - y3)
    l1 = ((y2 - y3) * (q[0] - x3) + (x3 - x2) * (q[1] - y3)) / det
    l2 = ((y3 - y1) * (q[0] - x3) + (x1 - x3) * (q[1] - y3)) / det
    return (l1, l2, 1.0 - l1 - l2)


def recovered_b_at(nodes, triangles, element_b, point):
    """Averaging recovery of the element B at `point` (same rule as mrbrake's Solver::b_at)."""
    found = None
    for tag, phys, tri in triangles:
        lam = barycentric([nodes[n] for n in tri], point)
        if min(lam) >= -1e-12:
            found = (tag, phys, tri, lam)
            break
    if found is None:
        return None
    _, phys, tri, lam = found
    total = [0.0, 0.0]
    for n, weight in zip(tri, lam):
        acc, area_sum = [0.0, 0.0], 0.0
        for tag, phys2, tri2 in triangles:
            if phys2 == phys and n in tri2:
                area = abs(triangle_area([nodes[m] for m in tri2]))
                b = element_b[tag]
                acc[0] += area * b[0]
                acc[1] += area * b[1]
                area_sum += area
        br, bz = acc[0] / area_sum, acc[1] / area_sum
        if abs(nodes[n][0]) < 1e-15:
            br = 0.0  # symmetry: no radial field on the axis
        total[0] += weight * br
        total[1] += weight * bz
    return total


def rel(a, b):
    scale = max(abs(a), abs(b))
    return 0.0 if scale == 0.0 else abs(a - b) / scale


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--label", required=True)
    ap.add_argument("--mesh", required=True)
    ap.add_argument("--mrbrake-json", required=True)
    ap.add_argument("--mrbrake-vtu", required=True)
    ap.add_argument("--getdp-dir", required=True)
    ap.add_argument("--turns", type=float, required=True)
    ap.add_argument("--tol-integral", type=float, required=True)
    ap.add_argument("--tol-probe", type=float, required=True)
    ap.add_argument("--tol-nodal", type=float, default=None)
    ap.add_argument("--probe-floor-t", type=float, default=0.01,
                    help="probes where both |B| are below this (T) are listed but not asserted")
    args = ap.parse_args()

    with open(args.mrbrake_json, encoding="utf-8") as f:
        m = json.load(f)
    g = lambda name: read_getdp_scalar(os.path.join(args.getdp_dir, name))
    rows = []  # (quantity, mrbrake, getdp, tolerance or None)

    coil_area = g("area_coil.txt")
    rows.append(("flux_linkage_Wb", m["coils"][0]["flux_linkage_Wb"],
                 args.turns / coil_area * g("a_coil.txt"), args.tol_integral))
    rows.append(("HB_integral_J", m["energy_J"] + m["coenergy_J"], g("hb_total.txt"), args.tol_integral))
    for region in m["regions"]:
        name = REGION_NAMES[region["physical"]]
        getdp_mean = g(f"babs_{name}.txt") / g(f"volume_{name}.txt")
        rows.append((f"mean_B_{name}_T", region["mean_B_T"], getdp_mean, args.tol_integral))

    nodes, triangles = read_msh22(args.mesh)
    element_b = read_getdp_element_b(os.path.join(args.getdp_dir, "b_elements.txt"))
    missing = [t for t, _, _ in triangles if t not in element_b]
    if missing:
        sys.exit(f"{args.getdp_dir}/b_elements.txt: no B for {len(missing)} triangles (e.g. {missing[0]})")
    for probe in m["probes"]:
        b = recovered_b_at(nodes, triangles, element_b, (probe["r"], probe["z"]))
        if b is None:
            sys.exit(f"probe {probe['name']} is outside the mesh")
        b_abs = math.hypot(b[0], b[1])
        tol = args.tol_probe if max(b_abs, probe["B_abs_T"]) >= args.probe_floor_t else None
        rows.append((f"B_abs_{probe['name']}_T", probe["B_abs_T"], b_abs, tol))

    # Nodal potentials: the VTU points are the mesh nodes in file order (checked here).
    points = read_vtu_points(args.mrbrake_vtu)
    a_mrbrake = read_vtu_array(args.mrbrake_vtu, "A_phi_Wb_per_m")
    a_getdp = read_getdp_node_table(os.path.join(args.getdp_dir, "a_nodes.txt"))
    tags = sorted(nodes)
    if len(tags) != len(points):
        sys.exit(f"{args.mrbrake_vtu}: {len(points)} points but the mesh has {len(tags)} nodes")
    worst, a_max = 0.0, 0.0
    for k, tag in enumerate(tags):
        x, y = nodes[tag]
        if abs(points[k][0] - x) > 1e-12 + 1e-9 * abs(x) or abs(points[k][1] - y) > 1e-12 + 1e-9 * abs(y):
            sys.exit(f"{args.mrbrake_vtu}: point {k} is not mesh node {tag}")
        worst = max(worst, abs(a_mrbrake[k] - a_getdp[tag]))
        a_max = max(a_max, abs(a_mrbrake[k]), abs(a_getdp[tag]))
    nodal = worst / a_max

    print(f"\n== {args.label}: {len(nodes)} nodes, {len(triangles)} triangles ==")
    print(f"{'quantity':<26} {'mrbrake':>14} {'GetDP':>14} {'rel. diff':>10} {'tolerance':>10}")
    failures = 0
    for name, a, b, tol in rows:
        d = rel(a, b)
        flag = ""
        if tol is not None and d > tol:
            flag = "  FAIL"
            failures += 1
        tol_text = f"{tol:.1e}" if tol is not None else "(info)"
        print(f"{name:<26} {a:>14.7g} {b:>14.7g} {d:>10.2e} {tol_text:>10}{flag}")
    tol = args.tol_nodal
    flag = "  FAIL" if tol is not None and nodal > tol else ""
    failures += 1 if flag else 0
    tol_text = f"{tol:.1e}" if tol is not None else "(info)"
    print(f"{'nodal_A_max (sup-norm)':<26} {'':>14} {'':>14} {nodal:>10.2e} {tol_text:>10}{flag}")
    newton = m["newton_iterations"]
    print(f"mrbrake Newton iterations: {newton}, converged: {m['converged']}")
    if failures:
        print(f"{failures} quantit{'y' if failures == 1 else 'ies'} beyond tolerance")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
