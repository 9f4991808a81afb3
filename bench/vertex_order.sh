#!/usr/bin/env bash
# bench/vertex_order.sh [BUILD_DIR] -- what keeping the input's vertex
# numbering costs (meshenc --keep-order, spec/FORMAT.md §3.9), on meshes in
# the numbering their mesher gave them: the Netgen and gmsh parts of
# bench/quality_cap.sh (run it first, or this makes them), bunny_100k
# (TetGen's), and bunny_100k with its nodes shuffled (a random numbering,
# the worst case: about log2(n) - 1.44 bits a vertex). Per mesh: the order
# section's bytes and bits per vertex, the stream with and without it, and
# how many nodes are a Delaunay neighbour of the one before. Writes
# bench/results/VERTEX_ORDER.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
enc=$build/tools/meshenc
py=/usr/bin/python3
work=$build/regions-data
mkdir -p "$work"
cd "$work"
[ -f netgen_fine.msh ] && [ -f gmsh_part.msh ] || "$root/bench/quality_cap.sh" "$build" > /dev/null
for ext in node ele; do xz -dc "$root/data/bunny_100k.$ext.xz" > bunny_100k.$ext; done
"$py" - <<'PY'
import numpy as np
# bunny_100k with its nodes in a random order (the same mesh).
lines = [l for l in open("bunny_100k.node").read().split("\n") if l.strip() and not l.startswith("#")]
head, rows = lines[0], lines[1:]
n = int(head.split()[0])
perm = np.random.default_rng(1).permutation(n)  # new k = old perm[k]
new_of_old = np.empty(n, np.int64)
new_of_old[perm] = np.arange(n)
with open("bunny_shuffled.node", "w") as f:
    f.write(head + "\n")
    for k in range(n):
        f.write(" ".join([str(k)] + rows[perm[k]].split()[1:]) + "\n")
ele = [l for l in open("bunny_100k.ele").read().split("\n") if l.strip() and not l.startswith("#")]
with open("bunny_shuffled.ele", "w") as f:
    f.write(ele[0] + "\n")
    for l in ele[1:]:
        v = l.split()
        f.write(" ".join([v[0]] + [str(new_of_old[int(x)]) for x in v[1:5]] + v[5:]) + "\n")
PY
for m in netgen_fine.msh gmsh_part.msh bunny_100k.node bunny_shuffled.node; do
  base=${m%.*}
  extra=()
  case $m in bunny*) extra=(--box 256 --dmax 2) ;; esac
  "$enc" $m -q -o $base.order.dtm --report $base.order.json --keep-order "${extra[@]}"
  "$enc" $m -q -o $base.plain.dtm --report $base.plain.json "${extra[@]}"
done
"$py" - <<'PY'
import json, math
import meshio, numpy as np
from scipy.spatial import Delaunay
def local_share(points):
    tri = Delaunay(points)
    indptr, idx = tri.vertex_neighbor_vertices
    near = sum(1 for k in range(1, len(points)) if k - 1 in idx[indptr[k]:indptr[k + 1]])
    return near / (len(points) - 1)
def node_points(path):
    rows = [l.split() for l in open(path).read().split("\n") if l.strip() and not l.startswith("#")][1:]
    return np.array([[float(x) for x in r[1:4]] for r in rows])
out = ["# The input's vertex numbering: what --keep-order costs", "",
       "Made by `bench/vertex_order.sh` (meshes made by Debian's Netgen 6.2 and gmsh 4.8.4, and the corpus's "
       "bunny_100k as TetGen numbered it and shuffled; one run each). *Local* = the share of nodes that are "
       "a Delaunay neighbour of the node numbered before them (what the section codes cheaply). A random "
       "numbering's bound is log2(n!) / n = about log2(n) - 1.44 bits a vertex.", "",
       "| mesh | vertices | local | order bytes | bits per vertex | log2(n) - 1.44 | stream without | with | increase |",
       "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
for base, what, points in (("netgen_fine", "Netgen part (its numbering)", lambda: meshio.read("netgen_fine.msh").points),
                           ("gmsh_part", "gmsh part (its numbering)", lambda: meshio.read("gmsh_part.msh").points),
                           ("bunny_100k", "bunny_100k (TetGen's numbering)", lambda: node_points("bunny_100k.node")),
                           ("bunny_shuffled", "bunny_100k, shuffled", lambda: node_points("bunny_shuffled.node"))):
    o, p = json.load(open(base + ".order.json")), json.load(open(base + ".plain.json"))
    n = o["input_points"]
    out.append("| %s | %d | %.0f%% | %d | %.2f | %.2f | %d | %d | %.0f%% |" % (
        what, n, 100 * local_share(points()), o["order_bytes"], 8.0 * o["order_bytes"] / n, math.log2(n) - 1.44,
        p["stream_bytes"], o["stream_bytes"], 100.0 * (o["stream_bytes"] / p["stream_bytes"] - 1)))
open("VERTEX_ORDER.md", "w").write("\n".join(out) + "\n")
print("\n".join(out))
PY
cp VERTEX_ORDER.md "$root/bench/results/VERTEX_ORDER.md"
