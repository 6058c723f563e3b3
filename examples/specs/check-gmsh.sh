#!/bin/sh
# Optional cross-check (not part of the test suite): export every example spec as a Gmsh .geo file
# with `mrbrake export-geo` and let Gmsh mesh it, to confirm that the exported geometry and physical
# groups are valid for another tool. Needs `mrbrake` on PATH (or MRBRAKE=path) and `gmsh`
# (Debian: apt-get install -y gmsh).
set -eu
MRBRAKE=${MRBRAKE:-mrbrake}
here=$(cd "$(dirname "$0")" && pwd)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for spec in "$here"/*.toml; do
    name=$(basename "$spec" .toml)
    "$MRBRAKE" export-geo "$spec" -o "$out/$name.geo" >/dev/null
    gmsh -2 "$out/$name.geo" -o "$out/$name.msh" -v 2 >/dev/null
    nodes=$(awk '/^\$Nodes/{getline; print $2; exit}' "$out/$name.msh")
    groups=$(awk '/^\$PhysicalNames/{getline; print $1; exit}' "$out/$name.msh")
    echo "$name: gmsh meshed it: $nodes nodes, $groups physical groups"
done
