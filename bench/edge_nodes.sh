#!/usr/bin/env bash
# bench/edge_nodes.sh [BUILD_DIR] -- what keeping a second-order mesh's edge
# nodes costs (meshenc --exact, format 18.0, spec/FORMAT.md §3.11), on
# meshes gmsh and Netgen make here: the gmsh part of data/two_materials.geo
# (a block and a cylinder) at three sizes, a gmsh ball, and Netgen's pin part
# (python3-netgen). Per mesh: vertices, edge nodes, those off their edge's
# midpoint (a curved boundary's), the exact stream of the linear mesh and
# of the second-order one, the edge node section's bits per vertex and per
# moved node, and how far the decoded nodes lie from the input's (meshdec's
# .msh read back); then, with two smooth fields at every node (format 19.0),
# each field's bits per value at the vertices and at the edge nodes.
# Writes bench/results/EDGE_NODES.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
enc=$build/tools/meshenc
dec=$build/tools/meshdec
info=$build/tools/meshinfo
py=/usr/bin/python3
work=$build/edge-nodes-data
mkdir -p "$work"
cd "$work"
sed 's/Mesh.CharacteristicLengthMax = 0.7;/Mesh.CharacteristicLengthMax = 0.35;/' "$root/data/two_materials.geo" >part_fine.geo
sed 's/Mesh.CharacteristicLengthMax = 0.7;/Mesh.CharacteristicLengthMax = 0.15;/' "$root/data/two_materials.geo" >part_finer.geo
cat >ball.geo <<'GEO'
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 1};
Mesh.MeshSizeMax = 0.08;
Physical Volume("ball", 1) = {1};
GEO
for g in "$root/data/two_materials.geo" part_fine.geo part_finer.geo ball.geo; do
  name=$(basename "$g" .geo)
  gmsh "$g" -3 -nt 1 -format msh41 -o "$name.msh" >/dev/null
  gmsh "$g" -3 -nt 1 -order 2 -format msh41 -o "${name}_2.msh" >/dev/null
done
"$py" - <<'PY'
from netgen.csg import CSGeometry, OrthoBrick, Cylinder, Pnt
geo = CSGeometry()
box = OrthoBrick(Pnt(0, 0, 0), Pnt(1, 1, 1)).bc("outer")
pin = Cylinder(Pnt(0.5, 0.5, -1), Pnt(0.5, 0.5, 2), 0.2).bc("pin")
geo.Add((box - pin).mat("aluminium"))
geo.Add((box * pin).mat("steel"))
mesh = geo.GenerateMesh(maxh=0.06)
mesh.Save("netgen.vol")
mesh.SecondOrder()
mesh.Save("netgen_2.vol")
PY
out=$root/bench/results/EDGE_NODES.md
# (What the table shows, written by hand below it, is kept.)
notes=$(sed -n '/^## What it shows/,$p' "$out" 2>/dev/null || true)
{
  echo "# --exact of second-order meshes: the edge nodes"
  echo
  echo "Made by \`bench/edge_nodes.sh\` (one run each, this project's 2-core machine). Per mesh, \`meshenc M --exact\` of the linear mesh and of the second-order one (gmsh \`-order 2\`, Netgen's \`SecondOrder()\`: the same corners and cells), default grid (q=14). *Moved*: edge nodes off their edge's midpoint in the input (a curved boundary's). *Edge node section*: its bits per vertex of the mesh and per moved node. *Decoded*: meshdec's \`.msh\` read back (meshio), each node against the input's, in grid steps (at most 0.5: the corners' own rounding; 0.25 for a moved node). *float32*: the nodes as three float32 each, for scale."
  echo
  echo "| mesh | vertices | cells | edge nodes | moved | exact stream (linear) | with edge nodes | extra bits/vertex | bits per moved node | largest error (steps) | float32 bits/vertex |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
  for m in two_materials part_fine part_finer ball netgen; do
    ext=msh
    [ $m = netgen ] && ext=vol
    "$enc" $m.$ext --exact -q -o $m.dtm --report $m.json >/dev/null
    "$enc" ${m}_2.$ext --exact -q -o ${m}_2.dtm --report ${m}_2.json >/dev/null
    "$dec" ${m}_2.dtm -q -o ${m}_2.out.msh >/dev/null
    "$py" - "$m" "$ext" "$("$info" ${m}_2.dtm --json)" <<'PY'
import contextlib, io, json, os, sys
import meshio
import numpy as np
m, ext, info = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
linear, second = json.load(open(m + ".json")), json.load(open(m + "_2.json"))
step = info["step"]
with contextlib.redirect_stdout(io.StringIO()):  # (meshio prints blank lines reading some)
    a, b = meshio.read(m + "_2." + ext), meshio.read(m + "_2.out.msh")
t = np.concatenate([c.data for c in a.cells if c.type == "tetra10"])
u = np.concatenate([c.data for c in b.cells if c.type == "tetra10"])
pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
node = {}
for c in t:
    for k, (i, j) in enumerate(pairs):
        node[frozenset((c[i], c[j]))] = a.points[c[4 + k]]
corners = np.unique(t[:, :4])
# Each decoded corner's input corner: the one in the same grid cell.
key = lambda p: tuple(np.floor((p - np.array(info["origin"])) / step + 0.5).astype(np.int64))
by_key = {key(a.points[i]): i for i in corners}
near = {i: by_key[key(b.points[i])] for i in np.unique(u[:, :4])}
worst = max(np.abs(b.points[c[4 + k]] - node[frozenset((near[c[i]], near[c[j]]))]).max()
            for c in u for k, (i, j) in enumerate(pairs))
n = len(corners)
e = second["edge_nodes"]
extra = second["stream_bytes"] - linear["stream_bytes"]
name = {"two_materials": "gmsh part (data/two_materials.geo)", "part_fine": "the same at size 0.35",
        "part_finer": "the same at size 0.15",
        "ball": "gmsh ball (size 0.08)", "netgen": "Netgen pin part (maxh 0.06)"}[m]
print("| %s | %d | %d | %d | %d | %d | %d | %.2f | %.1f | %.3f | %.1f |" % (
    name, n, len(t), e["nodes"], e["moved"], linear["stream_bytes"], second["stream_bytes"], 8.0 * extra / n,
    8.0 * e["bytes"] / e["moved"] if e["moved"] else 0, worst / step, 96.0 * e["nodes"] / n))
PY
  done
  echo
  echo "## The fields' values at the nodes (format 19.0)"
  echo
  echo "The second-order meshes above with two smooth fields at every node, as a solver's results on 10-node tetrahedra: *temperature* = sin(2x) + yz and *displacement* = (x², cos y, z) (float64; the part's coordinates scaled to a unit box first), written with the mesh by meshio (\`.vtu\`). \`meshenc --exact\`: each field's bits per value at the vertices (its value sections over every layer) and at the edge nodes (the edge value section, each node predicted from its edge's corners), lossless and within E = 1e-4 (\`--field-error\`). *Decode*: \`meshdec -o x.vtu\` of the lossless stream, whole process, against the same mesh's stream without fields (\`--no-fields\`)."
  echo
  echo "| mesh | vertices | edge nodes | temperature, lossless: vertices / nodes | displacement, lossless | temperature, E = 1e-4 | displacement, E = 1e-4 | decode with / without fields |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|"
  for m in two_materials part_fine part_finer ball netgen; do
    ext=msh
    [ $m = netgen ] && ext=vol
    "$py" - "$m" "$ext" <<'PY'
import contextlib, io, sys
import meshio
import numpy as np
m, ext = sys.argv[1], sys.argv[2]
with contextlib.redirect_stdout(io.StringIO()):  # (meshio prints blank lines reading some)
    a = meshio.read(m + "_2." + ext)
p = a.points
u = (p - p.min(axis=0)) / (p.max(axis=0) - p.min(axis=0)).max()
data = {"temperature": np.sin(2 * u[:, 0]) + u[:, 1] * u[:, 2],
        "displacement": np.stack([u[:, 0] ** 2, np.cos(u[:, 1]), u[:, 2]], axis=1)}
meshio.Mesh(p, [c for c in a.cells if c.type == "tetra10"], point_data=data).write(m + "_fields.vtu")
PY
    "$enc" ${m}_fields.vtu --exact -q -o ${m}_fields.dtm --report ${m}_fields.json >/dev/null
    "$enc" ${m}_fields.vtu --exact -q --field-error temperature=1e-4 --field-error displacement=1e-4 \
      -o ${m}_lossy.dtm --report ${m}_lossy.json >/dev/null
    "$enc" ${m}_fields.vtu --exact -q --no-fields -o ${m}_bare.dtm >/dev/null
    with=$( { /usr/bin/time -f %e "$dec" ${m}_fields.dtm -q -o ${m}_fields.out.vtu >/dev/null; } 2>&1)
    without=$( { /usr/bin/time -f %e "$dec" ${m}_bare.dtm -q -o ${m}_bare.out.vtu >/dev/null; } 2>&1)
    "$py" - "$m" "$with" "$without" <<'PY'
import json, sys
m, with_s, without_s = sys.argv[1], float(sys.argv[2]), float(sys.argv[3])
name = {"two_materials": "gmsh part", "part_fine": "the same at size 0.35", "part_finer": "the same at size 0.15",
        "ball": "gmsh ball (size 0.08)", "netgen": "Netgen pin part"}[m]
cells = []
vertices = nodes = 0
for kind in ("fields", "lossy"):
    r = json.load(open("%s_%s.json" % (m, kind)))
    vertices, nodes = r["levels"][0]["vertices"], r["edge_nodes"]["nodes"]
    for f in ("temperature", "displacement"):
        d = next(x for x in r["fields"] if x["name"] == f)
        c = 3 if f == "displacement" else 1
        cells.append("%.2f / %.2f" % (8.0 * d["bytes"] / (vertices * c), 8.0 * d["edge_value_bytes"] / (nodes * c)))
print("| %s | %d | %d | %s | %.2f / %.2f s |" % (name, vertices, nodes, " | ".join(cells), with_s, without_s))
PY
  done
  [ -n "$notes" ] && printf '\n%s\n' "$notes"
} >"$out"
cat "$out"
