#!/usr/bin/env bash
# bench/regions.sh [BUILD_DIR] -- what regions (materials) cost, on meshes
# made here by the real meshers (Debian's gmsh and python3-netgen):
#   * a two-material gmsh part: an aluminium block with a steel pin through
#     it (data/two_materials.geo, finer: REGIONS_GMSH_SIZE, default 0.055,
#     about 200k vertices), .msh 4.1 with its physical volumes;
#   * a Netgen part: a brick with a bore and a spherical steel inclusion, two
#     domains (REGIONS_NETGEN_MAXH, default 0.05, about 60k vertices), as
#     Netgen exports it (gmsh 2.0).
# Per mesh: meshenc with the regions and with --no-regions (bytes, bits per
# vertex, the regions' bytes, levels, the interfaces' distance both ways),
# meshdec of each to .vtu, one sequential CGAL construction of the same
# points (bench_hierarchy ... cgal), and beside them the .msh under xz -9 and
# the mesh as a zlib-compressed .vtu (meshio's default). Whole processes,
# GNU time. Writes bench/results/REGIONS.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
enc=$build/tools/meshenc
dec=$build/tools/meshdec
bench=$build/bench/bench_hierarchy
py=/usr/bin/python3
work=$build/regions-data
mkdir -p "$work"
cd "$work"
size=${REGIONS_GMSH_SIZE:-0.055}
maxh=${REGIONS_NETGEN_MAXH:-0.05}

sed "s/Mesh.CharacteristicLengthMax = .*/Mesh.CharacteristicLengthMax = $size;/" "$root/data/two_materials.geo" > gmsh_part.geo
[ -f gmsh_part.msh ] || gmsh -3 -nt 2 gmsh_part.geo -format msh41 -o gmsh_part.msh > gmsh.log
[ -f netgen_part.msh ] || "$py" - "$maxh" > netgen.log <<'PY'
import sys
from netgen.csg import CSGeometry, OrthoBrick, Cylinder, Sphere, Pnt
geo = CSGeometry()
inclusion = Sphere(Pnt(1.4, 0.5, 0.5), 0.3)
geo.Add(OrthoBrick(Pnt(0, 0, 0), Pnt(2, 1, 1)) - Cylinder(Pnt(0.5, 0.5, -1), Pnt(0.5, 0.5, 2), 0.2) - inclusion)
geo.Add(inclusion)
geo.GenerateMesh(maxh=float(sys.argv[1])).Export("netgen_part.msh", "Gmsh2 Format")
PY

# The points as a TetGen .node (one construction reads it) and the mesh as
# meshio writes a .vtu by default (zlib).
for m in gmsh_part netgen_part; do
  "$py" - $m <<'PY'
import sys, meshio, numpy as np
m = sys.argv[1]
mesh = meshio.read(m + ".msh")
p = mesh.points
with open(m + ".node", "w") as f:
    f.write("%d 3 0 0\n" % len(p))
    for i, (x, y, z) in enumerate(p):
        f.write("%d %.17g %.17g %.17g\n" % (i, x, y, z))
tets = [b for b in mesh.cells if b.type == "tetra"]
cell_data = {"gmsh:physical": [mesh.cell_data_dict["gmsh:physical"]["tetra"]]}
meshio.write(m + "_zlib.vtu", meshio.Mesh(p, [("tetra", np.vstack([b.data for b in tets]))], cell_data=cell_data))
PY
  xz -9 -k -f -T1 $m.msh
done

run() {  # NAME OUTPUT command...: "seconds peak_kib" into NAME.time
  local name=$1; shift
  /usr/bin/time -f "%e %M" -o "$name.time" "$@" > "$name.out" 2>&1
}
for m in gmsh_part netgen_part; do
  run $m.regions "$enc" $m.msh -o $m.regions.dtm --report $m.regions.json
  run $m.plain "$enc" $m.msh -o $m.plain.dtm --report $m.plain.json --no-regions
  run $m.decode "$dec" $m.regions.dtm -o $m.decoded.vtu -q
  run $m.construction "$bench" --peak-memory $m.node cgal
done

"$py" - "$root" <<'PY'
import json, os, sys
root = sys.argv[1]
def time_of(name):
    s, kib = open(name + ".time").read().split()[-2:]
    return float(s), int(kib) / 1024
rows = []
for m, what in (("gmsh_part", "gmsh 4.8, two physical volumes, .msh 4.1"),
                ("netgen_part", "Netgen 6.2, two domains, gmsh 2.0 export")):
    r = json.load(open(m + ".regions.json"))
    p = json.load(open(m + ".plain.json"))
    n = r["input_points"]
    regions = r.get("regions", [])
    region_bytes = r.get("region_table_bytes", 0) + sum(l.get("region_bytes", 0) for l in r["levels"])
    level0 = r["levels"][0]
    rows.append(dict(
        model=m, what=what, vertices=n, tets=level0["tetrahedra"], levels=len(r["levels"]),
        regions=len(regions),
        bytes=r["stream_bytes"], plain=p["stream_bytes"], region_bytes=region_bytes,
        level0_region_bytes=level0.get("region_bytes", 0),
        xz=os.path.getsize(m + ".msh.xz"), vtu=os.path.getsize(m + "_zlib.vtu"),
        worst=max(max(l["reference_to_level_max"], l["level_to_reference_max"]) for l in r["levels"]),
        dmax=r["dmax"],
        encode=time_of(m + ".regions"), encode_plain=time_of(m + ".plain"), decode=time_of(m + ".decode"),
        construction=time_of(m + ".construction")))
out = ["# Regions: what materials cost", "",
       "Made by `bench/regions.sh` (meshes made there by Debian's gmsh 4.8.4 and Netgen 6.2; "
       "whole processes on this project's 2-core machine, one run each). Bits per vertex are the "
       "whole file's over the mesh's vertices.", "",
       "| mesh | vertices | tetrahedra (level 0) | levels | regions | with regions | without | regions' bytes (level 0) | .msh, xz -9 | .vtu, zlib (meshio) |",
       "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
bpv = lambda b, n: "%.2f" % (8.0 * b / n)
for x in rows:
    out.append("| %s (%s) | %d | %d | %d | %d | %d B, %s bpv | %d B, %s bpv | %d (%d): %s bpv, %.3f bits per level-0 cell | %s bpv | %s bpv |" % (
        x["model"], x["what"], x["vertices"], x["tets"], x["levels"], x["regions"],
        x["bytes"], bpv(x["bytes"], x["vertices"]), x["plain"], bpv(x["plain"], x["vertices"]),
        x["region_bytes"], x["level0_region_bytes"], bpv(x["region_bytes"], x["vertices"]),
        8.0 * x["level0_region_bytes"] / x["tets"], bpv(x["xz"], x["vertices"]), bpv(x["vtu"], x["vertices"])))
out += ["", "| mesh | one construction | encode (regions) | encode (without) | decode to .vtu | worst shape error, both ways, boundary and interfaces (D_max) |",
        "|---|---:|---:|---:|---:|---:|"]
for x in rows:
    c = x["construction"][0]
    f = lambda t: "%.2f s, %.0f MiB (%.1fx)" % (t[0], t[1], t[0] / c)
    out.append("| %s | %.2f s, %.0f MiB | %s | %s | %s | %.4g (%.4g) |" % (
        x["model"], c, x["construction"][1], f(x["encode"]), f(x["encode_plain"]), f(x["decode"]),
        x["worst"], x["dmax"]))
out += ["", "Commands: `meshenc MESH.msh -o M.dtm --report M.json` (with regions), the same with "
        "`--no-regions`, `meshdec M.dtm -o M.vtu`, `bench_hierarchy --peak-memory MESH.node cgal` "
        "(one sequential CGAL construction of the same points); `xz -9` of the mesher's .msh; "
        "`meshio.write(\"M.vtu\", mesh)` of its tetrahedra and physical tags (zlib, meshio's default)."]
open(os.path.join(root, "bench/results/REGIONS.md"), "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
