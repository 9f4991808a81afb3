#!/usr/bin/env bash
# tests/golden/make.sh [BUILD_DIR] -- (re)writes the golden streams of the
# current format version and their expected levels. Run it only when the
# format's major version changes (spec/FORMAT.md §6), after moving the
# previous version's streams to v<major>/ (as v2/ to v6/, v11/ to v14/ and v18/ to v22/ hold formats 2.0 to 6.0, 11.0 to 14.0 and 18.0 to 22.0) if
# decoders still read it: a golden stream is a promise that every later
# decoder decodes it identically or refuses its version. The streams of
# older versions it writes too need not come out the same (the encoder
# moves on: the bricked ones did by 13.0): keep those committed
# (git checkout them) unless their version is the one that changed.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${1:-$root/build}
enc=$build/tools/meshenc
info=$build/tools/meshinfo
dec=$build/tools/meshdec
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
make_one() {  # NAME INPUT meshenc-options...
  local name=$1 input=$2; shift 2
  local path=$root/data/$input
  [ -f "$path" ] || path=$tmp/$input
  "$enc" "$path" -o "$here/$name.dtm" --hash-cells -q "$@"
  "$info" "$here/$name.dtm" --json | python3 -c '
import json, sys
info = json.load(sys.stdin)
print(json.dumps({
    "format": "dtm " + info["version"],
    "qbits": info["qbits"],
    "vertices": info["vertices"],
    "levels": [{"level": l["level"], "vertices": l["vertices"],
                "new_vertices": l["new_vertices"], "cell_hash": l["cell_hash"]}
               for l in info["levels"]]}, indent=1))' >"$here/$name.expected.json"
  # With regions (9.0, 10.0): each level's cells per region label and tagged
  # faces per tag, as meshdec writes them (Medit refs).
  local format regions
  format=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["format"])' "$here/$name.expected.json")
  regions=$("$info" "$here/$name.dtm" --json | python3 -c 'import json,sys; print(len(json.load(sys.stdin)["regions"]))')
  if [ "$regions" != 0 ]; then
    local levels
    levels=$(python3 -c 'import json,sys; print(len(json.load(open(sys.argv[1]))["levels"]))' "$here/$name.expected.json")
    for ((l = 0; l < levels; ++l)); do "$dec" "$here/$name.dtm" --level $l -q -o "$tmp/level$l.mesh"; done
    python3 - "$here/$name.expected.json" "$tmp" <<'PY'
import json, sys
path, tmp = sys.argv[1], sys.argv[2]
expected = json.load(open(path))
for entry in expected["levels"]:
    lines = open("%s/level%d.mesh" % (tmp, entry["level"])).read().split("\n")
    at = lines.index("Tetrahedra")
    counts = {}
    for line in lines[at + 2: at + 2 + int(lines[at + 1])]:
        label = line.split()[4]
        counts[label] = counts.get(label, 0) + 1
    entry["region_cells"] = dict(sorted(counts.items(), key=lambda kv: int(kv[0])))
    if "Triangles" in lines:
        at = lines.index("Triangles")
        faces = {}
        for line in lines[at + 2: at + 2 + int(lines[at + 1])]:
            tag = line.split()[3]
            faces[tag] = faces.get(tag, 0) + 1
        entry["tagged_faces"] = dict(sorted(faces.items(), key=lambda kv: int(kv[0])))
json.dump(expected, open(path, "w"), indent=1)
PY
  fi
  # With cell data (10.0, 16.0): level 0's arrays as meshdec writes them (.vtu),
  # each as its count and an order-sensitive checksum of its values' bits:
  # the sum over k of (k + 1) x bits_k modulo 2^64, bits_k the k-th value's
  # bits in its own type, zero-extended.
  if [ "$format" = "dtm 10.0" ] || [ "$format" = "dtm 16.0" ]; then
    "$dec" "$here/$name.dtm" -q -o "$tmp/level0.vtu"
    /usr/bin/python3 - "$here/$name.expected.json" "$tmp/level0.vtu" <<'PY'
import json, sys
import meshio, numpy as np
path, vtu = sys.argv[1], sys.argv[2]
expected = json.load(open(path))
mesh = meshio.read(vtu)
tetra = [i for i, b in enumerate(mesh.cells) if b.type == "tetra"][0]
arrays = {}
for name, blocks in mesh.cell_data.items():
    if name == "region":
        continue
    a = np.ascontiguousarray(blocks[tetra]).reshape(-1)
    bits = a.view(np.dtype("u%d" % a.dtype.itemsize)).astype(object)
    checksum = sum((k + 1) * int(b) for k, b in enumerate(bits)) % (1 << 64)
    arrays[name] = {"type": str(a.dtype), "values": int(a.size), "checksum": "%016x" % checksum}
expected["levels"][-1]["cell_data"] = arrays
json.dump(expected, open(path, "w"), indent=1)
PY
  fi
}
make_one torus_288 torus_288.node --scale 25 --dmax 3 --quality-floor 0 --removal-share 0.3
make_one torus_288_paper torus_288.node --scale 25 --dmax 3 --preset paper --quality-guard 0.3 --quality-floor 0
make_one torus_288_grid_q10_hull torus_288_grid.node --qbits 10 --alpha hull --levels 3
make_one torus_288_q24 torus_288.node --qbits 24 --levels 1
# 7.0: a TetGen mesh whose finer layers send points beside candidates.
make_one ellipsoid_793 ellipsoid_793.node --dmax 3
# 8.0: bricked layers (several chunks in the finer layers).
make_one ellipsoid_793_bricks ellipsoid_793.node --dmax 3 --bricks --brick-points 16 --block-points 100
# 8.0: bricked layers with values (the torus's TetGen markers, int32).
make_one torus_288_bricks torus_288.node --scale 25 --dmax 3 --bricks --brick-points 8 --block-points 64
# 9.0: regions (a gmsh part of two materials, data/two_materials.geo).
xz -dc "$root/data/two_materials.msh.xz" >"$tmp/two_materials.msh"
make_one two_materials two_materials.msh --quality-floor 0 --dmax 0.2
# 15.0: its regions in bricked layers (several chunks in the finer layers;
# without its tagged faces).
make_one two_materials_bricks two_materials.msh --quality-floor 0 --dmax 0.2 --bricks --brick-points 64 \
  --block-points 400 --no-face-tags
# 17.0: with them, a face section in each chunk.
make_one two_materials_bricks_faces two_materials.msh --quality-floor 0 --dmax 0.2 --bricks --brick-points 64 \
  --block-points 400
# 10.0: the torus with cell data (a float32 of each tetrahedron's centroid
# and an int16 of its index), as a .vtu, and its vertex numbering
# (--keep-order) (small: every bit of it is flipped by the tests).
/usr/bin/python3 - "$root/data/torus_288" "$tmp/torus_288_cells.vtu" <<'PY'
import sys
import meshio, numpy as np
base, out = sys.argv[1], sys.argv[2]
points = np.loadtxt(base + ".node", comments="#", skiprows=2)[:, 1:4]
tets = np.loadtxt(base + ".ele", comments="#", skiprows=1, dtype=np.int64)[:, 1:5]
c = points[tets].mean(axis=1)
heat = (20 + 5 * np.sin(c[:, 0]) * np.cos(c[:, 1]) + c[:, 2]).astype(np.float32)
zone = (np.arange(len(tets)) % 9 - 4).astype(np.int16)
meshio.write(out, meshio.Mesh(points, [("tetra", tets)], cell_data={"heat": [heat], "zone": [zone]}))
PY
make_one torus_288_cells torus_288_cells.vtu --scale 25 --dmax 3 --quality-floor 0 --removal-share 0.3 --keep-order
# 16.0: the same cell data in bricked layers (several chunks at level 0).
make_one torus_288_cells_bricks torus_288_cells.vtu --scale 25 --dmax 3 --quality-floor 0 --removal-share 0.3 \
  --bricks --brick-points 8 --block-points 64
# 13.0: the gmsh part with --exact: level 0 is its own tetrahedra (the cell
# hash of level 0 is theirs), with its regions and tagged faces on them.
# (v11/ and v12/ hold its 11.0 and 12.0 streams, made so before 12.0 ranked
# the apexes among the candidates that fit, and before 13.0 coded the filled
# bits in context and ranked apexes in the second ring.)
make_one two_materials_exact two_materials.msh --quality-floor 0 --dmax 0.2 --exact
# 20.0 (v18/ holds its 18.0 stream, made before 19.0 predicted the nodes
# from the surface's normals, and v19/ its 19.0 streams, made before 20.0
# set the creases apart: this coarse a sphere's surface turns by more than
# 60 degrees at some edges, so that the sections differ, not the nodes): a
# second-order gmsh ball with --exact: level 0 is its own 10-node
# tetrahedra, with their edge nodes (the sphere's off their edges'
# midpoints), recorded as their count, the moved ones' and a checksum of
# their places in the order the section gives them (meshdec's .vtu lists
# them so after the vertices): the sum over k of (k + 1) x (X + 3Y + 5Z)
# modulo 2^64, (X, Y, Z) the k-th node in half grid steps.
cat >"$tmp/ball_order2.geo" <<'GEO'
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 1};
Mesh.MeshSizeMin = 0.9;
Mesh.MeshSizeMax = 0.9;
Mesh.MeshSizeFromCurvature = 0;
Physical Volume("ball", 1) = {1};
Physical Surface("skin", 2) = {1};
GEO
gmsh "$tmp/ball_order2.geo" -3 -order 2 -format msh41 -o "$tmp/ball_order2.msh" >/dev/null
make_one ball_order2_exact ball_order2.msh --exact
record_edge_nodes() {  # NAME
"$dec" "$here/$1.dtm" -q -o "$tmp/ball.vtu"
/usr/bin/python3 - "$here/$1.expected.json" "$tmp/ball.vtu" "$("$info" "$here/$1.dtm" --json)" <<'PY'
import json, sys
import meshio, numpy as np
path, vtu, info = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
expected = json.load(open(path))
mesh = meshio.read(vtu)
corners = expected["vertices"]
nodes = mesh.points[corners:]
x2 = np.rint(2 * (nodes - np.array(info["origin"])) / info["step"]).astype(np.int64)
checksum = sum((k + 1) * int(x + 3 * y + 5 * z) for k, (x, y, z) in enumerate(x2)) % (1 << 64)
t = mesh.cells_dict["tetra10"]
moved = {int(n) for k, (a, b) in enumerate([(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)])
         for n, ca, cb in zip(t[:, 4 + k], t[:, a], t[:, b])
         if np.abs(2 * mesh.points[n] - mesh.points[ca] - mesh.points[cb]).max() > 1e-9 * info["step"]}
expected["levels"][-1]["edge_nodes"] = {"nodes": len(nodes), "moved": len(moved), "checksum": "%016x" % checksum}
json.dump(expected, open(path, "w"), indent=1)
PY
}
record_edge_nodes ball_order2_exact
# 20.0 (19.0 in v19/): the same ball with a float64 and an int32 field at every node, the
# nodes' values in an edge value section; its expected level 0 records, per
# field, the nodes' values' count and the sum over k of (k + 1) x the k-th
# value's bits (in its type's width) modulo 2^64, in the section's order.
/usr/bin/python3 - "$tmp/ball_order2.msh" "$tmp/ball_order2_fields.vtu" <<'PY'
import sys
import meshio, numpy as np
mesh = meshio.read(sys.argv[1])
p = mesh.points
cells = [b for b in mesh.cells if b.type == "tetra10"]
meshio.Mesh(p, cells, point_data={"temperature": np.sin(2 * p[:, 0]) + p[:, 1] * p[:, 2],
                                  "id": np.arange(len(p), dtype=np.int32)}).write(sys.argv[2])
PY
make_one ball_order2_fields_exact ball_order2_fields.vtu --exact
record_edge_nodes ball_order2_fields_exact
"$dec" "$here/ball_order2_fields_exact.dtm" -q -o "$tmp/ball_fields.vtu"
# (The values are the input's, each decoded node's nearest input point's:
# the stream is lossless, and the record does not lean on the decoder.)
/usr/bin/python3 - "$here/ball_order2_fields_exact.expected.json" "$tmp/ball_fields.vtu" "$tmp/ball_order2_fields.vtu" <<'PY'
import json, sys
import meshio, numpy as np
path, vtu, given = sys.argv[1], sys.argv[2], sys.argv[3]
expected = json.load(open(path))
mesh, source = meshio.read(vtu), meshio.read(given)
corners = expected["vertices"]
nearest = np.array([np.argmin(np.abs(source.points - q).max(axis=1)) for q in mesh.points[corners:]])
sums = {}
for name, values in source.point_data.items():
    nodes = np.ascontiguousarray(np.asarray(values)[nearest])
    bits = nodes.view(np.uint64 if nodes.dtype.itemsize == 8 else np.uint32).reshape(-1)
    sums[name] = {"values": int(bits.size),
                  "checksum": "%016x" % (sum((k + 1) * int(b) for k, b in enumerate(bits)) % (1 << 64))}
expected["levels"][-1]["edge_values"] = sums
json.dump(expected, open(path, "w"), indent=1)
PY
# 20.0: a second-order gmsh block with a pin through it, two regions, with
# --exact: its edge nodes on the pin's side (an interface) and along the
# circles where it meets the block's faces, which 4 points a circle make
# creases that turn by 90 degrees at each vertex: every kind of crease
# edge's prediction (§3.11, *20.0: the creases apart*: a tangent from the
# crease's next vertex, the edge's own at a vertex of three creases or
# where the crease turns sharply), recorded as the ball's.
cat >"$tmp/pin_order2.geo" <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Cylinder(2) = {0.5, 0.5, 0, 0, 0, 1, 0.2};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.MeshSizeMin = 0.5;
Mesh.MeshSizeMax = 0.5;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MinimumCirclePoints = 4;
Physical Volume("block", 1) = {3};
Physical Volume("pin", 2) = {2};
GEO
gmsh "$tmp/pin_order2.geo" -3 -order 2 -format msh41 -o "$tmp/pin_order2.msh" >/dev/null
make_one pin_order2_exact pin_order2.msh --exact
record_edge_nodes pin_order2_exact
# 21.0: the ball with --exact --keep-order: its vertices and edge nodes in
# gmsh's numbering (the corners of each entity and their edge nodes
# interleaved), a node order section after the edge node section; recorded
# as the count of all nodes and the sum over k of (k + 1) x (X + 3Y + 5Z)
# modulo 2^64, (X, Y, Z) the k-th node of meshdec's .vtu in half grid steps,
# which is the input's k-th (checked here within half a step).
make_one ball_order2_numbered_exact ball_order2.msh --exact --keep-order
"$dec" "$here/ball_order2_numbered_exact.dtm" -q -o "$tmp/ball_numbered.vtu"
/usr/bin/python3 - "$here/ball_order2_numbered_exact.expected.json" "$tmp/ball_numbered.vtu" "$tmp/ball_order2.msh" \
  "$("$info" "$here/ball_order2_numbered_exact.dtm" --json)" <<'PY'
import json, sys
import meshio, numpy as np
path, vtu, given, info = sys.argv[1], sys.argv[2], sys.argv[3], json.loads(sys.argv[4])
expected = json.load(open(path))
mesh, source = meshio.read(vtu), meshio.read(given)
assert len(mesh.points) == len(source.points)
assert np.abs(mesh.points - source.points).max() <= 0.5 * info["step"] * (1 + 1e-9)
x2 = np.rint(2 * (mesh.points - np.array(info["origin"])) / info["step"]).astype(np.int64)
checksum = sum((k + 1) * int(x + 3 * y + 5 * z) for k, (x, y, z) in enumerate(x2)) % (1 << 64)
expected["levels"][-1]["numbered_nodes"] = {"nodes": len(mesh.points), "checksum": "%016x" % checksum}
json.dump(expected, open(path, "w"), indent=1)
PY
# 22.0: the same ball in gmsh's 2.2 format with its node tags made to skip
# (tag t as 3t + 100), --exact --keep-order: the ids in a node label
# section; recorded as their count and the sum over k of (k + 1) x the
# k-th node's id modulo 2^64, in the file's order (which the stream keeps).
gmsh "$tmp/ball_order2.geo" -3 -order 2 -format msh22 -o "$tmp/ball_order2_22.msh" >/dev/null
/usr/bin/python3 "$here/../gmsh22_node_tags.py" "$tmp/ball_order2_22.msh" "$tmp/ball_order2_labelled.msh" 3t+100 \
  --ids "$here/ball_order2_labelled.ids"
make_one ball_order2_labelled_exact ball_order2_labelled.msh --exact --keep-order
/usr/bin/python3 - "$here/ball_order2_labelled_exact.expected.json" "$here/ball_order2_labelled.ids" <<'PY'
import json, sys
path, ids_path = sys.argv[1:]
ids = [int(v) for v in open(ids_path).read().split()]
expected = json.load(open(path))
checksum = sum((k + 1) * v for k, v in enumerate(ids)) % (1 << 64)
expected["levels"][-1]["node_labels"] = {"nodes": len(ids), "checksum": "%016x" % checksum}
json.dump(expected, open(path, "w"), indent=1)
PY
rm "$here/ball_order2_labelled.ids"
