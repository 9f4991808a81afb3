#!/usr/bin/env bash
# bench/node_order.sh [BUILD_DIR] -- what keeping a second-order mesh's node
# numbering costs (meshenc --exact --keep-order, format 21.0,
# spec/FORMAT.md §3.13), on the meshes of bench/edge_nodes.sh as gmsh and
# Netgen number them (run it first, or this makes them): the gmsh part of
# data/two_materials.geo at three sizes, a gmsh ball and Netgen's pin part.
# Per mesh: vertices, edge nodes, the runs of vertices and of edge nodes in
# the file's numbering, the vertex order and node order sections' bytes
# (bits per vertex and per edge node), the share of edge nodes on a cell
# around the one numbered before them (what the section codes cheaply), a
# random numbering's bound, the exact stream without and with
# --keep-order; and whether meshdec's .msh of the stream has every node at
# the input's number (meshio, within half a grid step) and the same 10-node
# tetrahedra; then what the file's own node ids cost (format 22.0). Writes
# bench/results/NODE_ORDER.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
enc=$build/tools/meshenc
dec=$build/tools/meshdec
info=$build/tools/meshinfo
py=/usr/bin/python3
work=$build/edge-nodes-data
[ -f "$work/netgen_2.vol" ] && [ -f "$work/part_finer_2.msh" ] || "$root/bench/edge_nodes.sh" "$build" >/dev/null
cd "$work"
rows=()
for m in two_materials_2.msh part_fine_2.msh part_finer_2.msh ball_2.msh netgen_2.vol; do
  base=${m%.*}
  "$enc" $m --exact -q -o $base.plain.dtm --report $base.plain.json >/dev/null
  "$enc" $m --exact --keep-order -q -o $base.numbered.dtm --report $base.numbered.json >/dev/null
  "$dec" $base.numbered.dtm -q -o $base.numbered.out.msh >/dev/null
  xz_bytes=$(xz -9 -T1 -c $m | wc -c)
  rows+=("$("$py" - "$m" "$base" "$("$info" $base.numbered.dtm --json)" "$xz_bytes" <<'PY'
import contextlib, io, json, math, sys
import meshio, numpy as np
m, base, info, xz = sys.argv[1], sys.argv[2], json.loads(sys.argv[3]), int(sys.argv[4])
plain, numbered = json.load(open(base + ".plain.json")), json.load(open(base + ".numbered.json"))
with contextlib.redirect_stdout(io.StringIO()):
    a, b = meshio.read(m), meshio.read(base + ".numbered.out.msh")
t = np.concatenate([c.data for c in a.cells if c.type == "tetra10"])
u = np.concatenate([c.data for c in b.cells if c.type == "tetra10"])
n_all = len(a.points)
corner = np.zeros(n_all, bool)
corner[t[:, :4].ravel()] = True
runs = 1 + int(np.count_nonzero(np.diff(corner.astype(int))))
# Edge nodes on a cell around the edge of the node numbered before them.
pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]  # meshio's (VTK's) order of the six
cells_of = {}
for ci, c in enumerate(t):
    for k in range(6):
        cells_of.setdefault(int(c[4 + k]), []).append(ci)
nodes = sorted(cells_of)
near = sum(1 for p, q in zip(nodes, nodes[1:]) if any(q in t[ci][4:] for ci in cells_of[p]))
E = len(nodes)
same_points = len(b.points) == n_all and np.abs(a.points - b.points).max() <= 0.5 * info["step"] * (1 + 1e-9)
def cells(t):
    return {(frozenset(c[:4]), frozenset((frozenset((c[i], c[j])), c[4 + k]) for k, (i, j) in enumerate(pairs)))
            for c in t.tolist()}
same = same_points and cells(t) == cells(u)
v = numbered["input_points"]
print("| %s | %d | %d | %d | %d (%.2f) | %d (%.2f) | %.0f%% | %.2f | %d | %d | %.0f%% | %d (%.2fx) | %s |" % (
    m, v, E, runs, numbered["order_bytes"], 8.0 * numbered["order_bytes"] / v, numbered["node_order_bytes"],
    8.0 * numbered["node_order_bytes"] / E, 100.0 * near / (E - 1), math.log2(E) - 1.44, plain["stream_bytes"],
    numbered["stream_bytes"], 100.0 * (numbered["stream_bytes"] / plain["stream_bytes"] - 1),
    xz, numbered["stream_bytes"] / xz, "yes" if same else "NO"))
PY
)")
done
# The node ids (format 22.0): part_finer_2.msh's nodes given ids as files
# number them otherwise than 1 to n (gmsh 2.2 files written by meshio,
# then each node tag t made: parts of 5,000 from their own offsets, every
# tenth id, random ids below 10^9), each with --exact --keep-order.
"$py" -c 'import meshio; meshio.write("ids_plain.msh", meshio.read("part_finer_2.msh"), file_format="gmsh22", binary=False)'
for m in offsets stride random; do "$py" "$root/tests/gmsh22_node_tags.py" ids_plain.msh ids_$m.msh $m; done
id_rows=()
for m in ids_plain ids_offsets ids_stride ids_random; do
  "$enc" $m.msh --exact --keep-order -q -o $m.dtm --report $m.json >/dev/null
  id_rows+=("$("$py" -c "
import json
r = json.load(open('$m.json'))
lines = open('$m.msh').read().split('\\n')
nodes = int(lines[lines.index('\$Nodes') + 1])
b = r.get('node_label_bytes', 0)
print('| %s | %d | %d | %.3f | %d |' % ('$m'.replace('ids_', ''), nodes, b, 8.0 * b / nodes, r['stream_bytes']))
")")
done
out=$root/bench/results/NODE_ORDER.md
notes=$(sed -n '/^## What it shows/,$p' "$out" 2>/dev/null || true)
{
  echo "# --exact --keep-order of second-order meshes: the edge nodes where the input numbered them"
  echo
  echo "Made by \`bench/node_order.sh\` (one run each, this project's 2-core machine; the meshes of \`bench/edge_nodes.sh\`, made by Debian's gmsh 4.8.4 and Netgen 6.2 in their own numbering). Per mesh: *runs*: the stretches of vertices and of edge nodes in the file's numbering (gmsh numbers each geometric entity's nodes together, Netgen its vertices first); the vertex order section (format 10.0, §3.9) and the node order section (21.0, §3.13) in bytes (bits per vertex, per edge node); *near*: the edge nodes on a cell around the edge of the node numbered before them, which the section codes as an index among a few; a random numbering's bound, log2(E) - 1.44 bits an edge node; the exact stream without and with \`--keep-order\`; the file under \`xz -9\` (and the stream with \`--keep-order\` over it); *same numbering*: meshdec's \`.msh\` of the stream has every node at the input's number, within half a grid step, and the same 10-node tetrahedra, each naming the same nodes (meshio)."
  echo
  echo "| mesh | vertices | edge nodes | runs | vertex order bytes (bits/vertex) | node order bytes (bits/edge node) | near | random bound | exact stream | with --keep-order | increase | xz -9 of the file (stream / it) | same numbering |"
  echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"
  printf '%s\n' "${rows[@]}"
  echo
  echo "The node ids (format 22.0): part_finer_2.msh written by meshio as gmsh 2.2 (its nodes numbered 1 to n: *plain*, no section), then each node tag t made t + 100000 x floor(t / 5000) (*offsets*: parts numbered from their own offsets), 10t (*stride*) and a random id below 10^9 (*random*); --exact --keep-order of each: the node label section's bytes and bits per node, and the whole stream."
  echo
  echo "| ids | nodes | node label bytes | bits per node | stream |"
  echo "|---|---:|---:|---:|---:|"
  printf '%s\n' "${id_rows[@]}"
  if [ -n "$notes" ]; then echo; echo "$notes"; fi
} >"$out"
cat "$out"
