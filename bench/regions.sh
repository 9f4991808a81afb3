#!/usr/bin/env bash
# bench/regions.sh [BUILD_DIR] -- what regions (materials) and tagged faces
# (boundary conditions' patches) cost, on meshes
# made here by the real meshers (Debian's gmsh and python3-netgen):
#   * a two-material gmsh part: an aluminium block with a steel pin through
#     it and two tagged surfaces (data/two_materials.geo, finer:
#     REGIONS_GMSH_SIZE, default 0.1, about 190k vertices), .msh 4.1 with its
#     physical volumes and surfaces;
#   * a Netgen part: a brick with a bore and a spherical steel inclusion, two
#     domains (REGIONS_NETGEN_MAXH, default 0.038, about 60k vertices), as
#     Netgen exports it (gmsh 2.0: its surface triangles tagged by boundary
#     condition).
# Per mesh: meshenc with the regions and tagged faces, with the regions
# alone (--no-face-tags) and with neither (--no-regions --no-face-tags):
# bytes, bits per vertex, the regions' and faces' bytes, levels, the
# surfaces' distance both ways (boundary and interfaces),
# meshdec of each to .vtu, one sequential CGAL construction of the same
# points (bench_hierarchy ... cgal), and beside them the .msh under xz -9 and
# the mesh (tetrahedra and tagged triangles) as a zlib-compressed .vtu
# (meshio's default). Whole processes,
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
size=${REGIONS_GMSH_SIZE:-0.1}
maxh=${REGIONS_NETGEN_MAXH:-0.038}

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
# Its tetrahedra and tagged triangles with their physical tags.
physical = mesh.cell_data_dict["gmsh:physical"]
cells = [(t, np.vstack([b.data for b in mesh.cells if b.type == t])) for t in ("tetra", "triangle") if t in physical]
meshio.write(m + "_zlib.vtu", meshio.Mesh(p, cells, cell_data={"gmsh:physical": [physical[t] for t, _ in cells]}))
PY
  xz -9 -k -f -T1 $m.msh
done

run() {  # NAME OUTPUT command...: "seconds peak_kib" into NAME.time
  local name=$1; shift
  /usr/bin/time -f "%e %M" -o "$name.time" "$@" > "$name.out" 2>&1
}
for m in gmsh_part netgen_part; do
  run $m.regions "$enc" $m.msh -o $m.regions.dtm --report $m.regions.json
  run $m.regions_only "$enc" $m.msh -o $m.regions_only.dtm --report $m.regions_only.json --no-face-tags
  run $m.plain "$enc" $m.msh -o $m.plain.dtm --report $m.plain.json --no-regions --no-face-tags
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
    ro = json.load(open(m + ".regions_only.json"))
    p = json.load(open(m + ".plain.json"))
    n = r["input_points"]
    regions = r.get("regions", [])
    region_bytes = r.get("region_table_bytes", 0) + sum(l.get("region_bytes", 0) for l in r["levels"])
    face_bytes = r.get("face_table_bytes", 0) + sum(l.get("face_bytes", 0) for l in r["levels"])
    level0 = r["levels"][0]
    rows.append(dict(
        model=m, what=what, vertices=n, tets=level0["tetrahedra"], levels=len(r["levels"]),
        regions=len(regions),
        bytes=r["stream_bytes"], regions_only=ro["stream_bytes"], plain=p["stream_bytes"], region_bytes=region_bytes,
        level0_region_bytes=level0.get("region_bytes", 0), face_bytes=face_bytes,
        level0_face_bytes=level0.get("face_bytes", 0), face_tags=len(r.get("face_tags", [])),
        tagged=r.get("tagged_faces", 0), tagged_kept=r.get("tagged_faces_kept", 0),
        plain_levels=len(p["levels"]),
        xz=os.path.getsize(m + ".msh.xz"), vtu=os.path.getsize(m + "_zlib.vtu"),
        worst=max(max(l["reference_to_level_max"], l["level_to_reference_max"]) for l in r["levels"]),
        dmax=r["dmax"],
        encode=time_of(m + ".regions"), encode_plain=time_of(m + ".plain"), decode=time_of(m + ".decode"),
        construction=time_of(m + ".construction")))
out = ["# Regions and tagged faces: what a simulation mesh's materials and boundary conditions cost", "",
       "Made by `bench/regions.sh` (meshes made there by Debian's gmsh 4.8.4 and Netgen 6.2; "
       "whole processes on this project's 2-core machine, one run each). Bits per vertex are the "
       "whole file's over the mesh's vertices.", "",
       "| mesh | vertices | tetrahedra (level 0) | levels (without) | regions, tags | with both | regions alone | neither | .msh, xz -9 | .vtu, zlib (meshio) |",
       "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
bpv = lambda b, n: "%.2f" % (8.0 * b / n)
for x in rows:
    out.append("| %s (%s) | %d | %d | %d (%d) | %d, %d | %d B, %s bpv | %d B, %s bpv | %d B, %s bpv | %s bpv | %s bpv |" % (
        x["model"], x["what"], x["vertices"], x["tets"], x["levels"], x["plain_levels"], x["regions"], x["face_tags"],
        x["bytes"], bpv(x["bytes"], x["vertices"]), x["regions_only"], bpv(x["regions_only"], x["vertices"]),
        x["plain"], bpv(x["plain"], x["vertices"]), bpv(x["xz"], x["vertices"]), bpv(x["vtu"], x["vertices"])))
out += ["", "| mesh | regions' sections (level 0's) | per vertex | per level-0 cell | tagged faces' sections (level 0's) | per vertex | tagged triangles kept exactly by level 0 |",
        "|---|---:|---:|---:|---:|---:|---:|"]
for x in rows:
    out.append("| %s | %d B (%d) | %s bits | %.3f bits | %d B (%d) | %s bits | %d of %d |" % (
        x["model"], x["region_bytes"], x["level0_region_bytes"], bpv(x["region_bytes"], x["vertices"]),
        8.0 * x["level0_region_bytes"] / x["tets"], x["face_bytes"], x["level0_face_bytes"],
        bpv(x["face_bytes"], x["vertices"]), x["tagged_kept"], x["tagged"]))
out += ["", "| mesh | one construction | encode (both) | encode (neither) | decode to .vtu | worst shape error, both ways, boundary and interfaces (D_max) |",
        "|---|---:|---:|---:|---:|---:|"]
for x in rows:
    c = x["construction"][0]
    f = lambda t: "%.2f s, %.0f MiB (%.1fx)" % (t[0], t[1], t[0] / c)
    out.append("| %s | %.2f s, %.0f MiB | %s | %s | %s | %.4g (%.4g) |" % (
        x["model"], c, x["construction"][1], f(x["encode"]), f(x["encode_plain"]), f(x["decode"]),
        x["worst"], x["dmax"]))
for x in rows:
    extra = x["bytes"] - x["plain"]
    out += ["", "**%s**: the regions and tags add %d bytes (%.1f%% of the stream, %.2f bits per vertex); the "
            "stream is %.0fx smaller than the mesher's file under xz -9 and %.0fx smaller than meshio's zlib "
            ".vtu of the same tetrahedra and tags; encoding takes %.2fx the time without them (a solid and a "
            "surface measurement per region, the interfaces in the repair); %d levels against %d without "
            "(the interfaces are held within D_max, and the quality floor binds the coarse levels)." % (
                x["model"], extra, 100.0 * extra / x["bytes"], 8.0 * extra / x["vertices"],
                x["xz"] / x["bytes"], x["vtu"] / x["bytes"], x["encode"][0] / x["encode_plain"][0],
                x["levels"], x["plain_levels"])]
out += ["", "Commands: `meshenc MESH.msh -o M.dtm --report M.json` (with regions and tagged faces), the same "
        "with `--no-face-tags` and with `--no-regions --no-face-tags`, `meshdec M.dtm -o M.vtu`, `bench_hierarchy --peak-memory MESH.node cgal` "
        "(one sequential CGAL construction of the same points); `xz -9` of the mesher's .msh; "
        "`meshio.write(\"M.vtu\", mesh)` of its tetrahedra and physical tags (zlib, meshio's default)."]
open(os.path.join(root, "bench/results/REGIONS.md"), "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
