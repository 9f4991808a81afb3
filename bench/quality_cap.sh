#!/usr/bin/env bash
# bench/quality_cap.sh [BUILD_DIR] -- levels for the best-shaped meshes: the
# codec's quality floor is 0.85x level 0's average smallest solid angle but
# at most 0.25 (--quality-floor-cap, spec/HIERARCHY.md §6.3). On meshes made
# here by the real meshers:
#   * a Netgen part (a brick with a bore and a spherical pocket, maxh
#     QUALITY_NETGEN_MAXH, default 0.03: about 71k vertices, quality 0.35);
#   * the two-material gmsh part of bench/regions.sh (about 188k vertices);
# meshenc with the cap (the default) and without (--quality-floor-cap 0):
# the levels, their vertices and quality, the worst shape error over D_max,
# bits per vertex. Writes bench/results/QUALITY_CAP.md and, of the Netgen
# part, docs/netgen_levels.png: its input surface, then every level's
# (scripts/render_levels.py).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
enc=$build/tools/meshenc
dec=$build/tools/meshdec
py=/usr/bin/python3
work=$build/regions-data
mkdir -p "$work"
cd "$work"
maxh=${QUALITY_NETGEN_MAXH:-0.03}
size=${REGIONS_GMSH_SIZE:-0.1}
[ -f netgen_fine.msh ] || "$py" - "$maxh" > netgen_fine.log <<'PY'
import sys
from netgen.csg import CSGeometry, OrthoBrick, Cylinder, Sphere, Pnt
geo = CSGeometry()
geo.Add(OrthoBrick(Pnt(0, 0, 0), Pnt(2, 1, 1)) - Cylinder(Pnt(0.5, 0.5, -1), Pnt(0.5, 0.5, 2), 0.2)
        - Sphere(Pnt(1.4, 0.5, 0.5), 0.25))
geo.GenerateMesh(maxh=float(sys.argv[1])).Export("netgen_fine.msh", "Gmsh2 Format")
PY
sed "s/Mesh.CharacteristicLengthMax = .*/Mesh.CharacteristicLengthMax = $size;/" "$root/data/two_materials.geo" > gmsh_part.geo
[ -f gmsh_part.msh ] || gmsh -3 -nt 2 gmsh_part.geo -format msh41 -o gmsh_part.msh > gmsh.log

for m in netgen_fine gmsh_part; do
  "$enc" $m.msh -q -o $m.capped.dtm --report $m.capped.json
  "$enc" $m.msh -q -o $m.uncapped.dtm --report $m.uncapped.json --quality-floor-cap 0
done

"$py" - <<'PY'
import json
out = ["# Levels for the best-shaped meshes: the quality floor's cap", "",
       "Made by `bench/quality_cap.sh` (meshes made there by Debian's Netgen 6.2 and gmsh 4.8.4; one run each on "
       "this project's 2-core machine). The codec's floor is 0.85x level 0's average smallest solid angle, "
       "capped at 0.25 (`--quality-floor-cap`; the TetGen corpus's floors are 0.218-0.246, which the cap "
       "leaves as they were: bench/results/LEVELS.md is unchanged by it).", "",
       "| mesh | vertices | level 0 quality | cap | levels | vertices per level | quality per level | worst error / D_max | bits per vertex |",
       "|---|---:|---:|---|---:|---|---|---:|---:|"]
for m, what in (("netgen_fine", "Netgen part (brick, bore, pocket)"), ("gmsh_part", "gmsh part (two materials)")):
    for kind, cap in (("capped", "0.25 (default)"), ("uncapped", "none")):
        r = json.load(open("%s.%s.json" % (m, kind)))
        levels = r["levels"]
        worst = max(l["reference_max_error"] for l in levels) / r["dmax"]
        out.append("| %s | %d | %.3f | %s | %d | %s | %s | %.2f | %.2f |" % (
            what, r["input_points"], levels[0]["avg_min_solid_angle"], cap, len(levels),
            ", ".join(str(l["vertices"]) for l in levels),
            ", ".join("%.3f" % l["avg_min_solid_angle"] for l in levels), worst,
            8.0 * r["stream_bytes"] / r["input_points"]))
out += ["", "![The Netgen part: its input surface, then every level's (docs/netgen_levels.png)]"
        "(../../docs/netgen_levels.png)", ""]
open("QUALITY_CAP.md", "w").write("\n".join(out))
print("\n".join(out))
PY
cp QUALITY_CAP.md "$root/bench/results/QUALITY_CAP.md"

# The picture: the input's surface (its boundary triangles), then each level's.
"$py" - <<'PY'
import meshio, numpy as np
m = meshio.read("netgen_fine.msh")
tri = np.vstack([b.data for b in m.cells if b.type == "triangle"])
meshio.write("netgen_fine_input.off", meshio.Mesh(m.points, [("triangle", tri)]))
PY
levels=$("$build/tools/meshinfo" netgen_fine.capped.dtm --json | "$py" -c "import json,sys; print(json.load(sys.stdin)['level_count'])")
panels=(netgen_fine_input.off)
for ((l = 0; l < levels; ++l)); do
  "$dec" netgen_fine.capped.dtm -o netgen_level$l.ply --level $l -q
  panels+=(netgen_level$l.ply)
done
"$py" "$root/scripts/render_levels.py" "$root/docs/netgen_levels.png" --elevation 60 --azimuth 30 "${panels[@]}"
