#!/usr/bin/env bash
# bench/exodus.sh [BUILD_DIR] -- a simulation's Exodus II file against the
# stream: the two-material gmsh part of data/two_materials.geo (a block and
# a cylinder, its base and load faces tagged) at two sizes, linear and
# second-order, with a temperature and a displacement at every node and a
# stress in every element, written by ParaView's Exodus writer as its users
# make such files (its blocks from the regions). Per file: its bytes, xz -9
# and zstd -19 of it, meshenc's stream (lossless; second-order: --exact,
# every node and cell kept), and a check that meshdec's .e of the stream
# reads back to the same stream. Writes bench/results/EXODUS.md.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=${1:-build}
case $build in /*) ;; *) build=$root/$build ;; esac
enc=$build/tools/meshenc
dec=$build/tools/meshdec
work=$build/exodus-data
mkdir -p "$work"
cd "$work"
sed 's/Mesh.CharacteristicLengthMax = 0.7;/Mesh.CharacteristicLengthMax = 0.35;/' "$root/data/two_materials.geo" >part_a.geo
sed 's/Mesh.CharacteristicLengthMax = 0.7;/Mesh.CharacteristicLengthMax = 0.15;/' "$root/data/two_materials.geo" >part_b.geo
rows=""
for g in part_a part_b; do
  gmsh $g.geo -3 -nt 1 -format msh41 -o $g.msh >/dev/null
  gmsh $g.geo -3 -nt 1 -order 2 -format msh41 -o ${g}_2.msh >/dev/null
  for m in $g ${g}_2; do
    /usr/bin/python3 - "$m" <<'PY'
import sys
import meshio, numpy as np
name = sys.argv[1]
m = meshio.read(name + ".msh")
kind = "tetra10" if name.endswith("_2") else "tetra"
k = [i for i, c in enumerate(m.cells) if c.type == kind]
cells = np.concatenate([m.cells[i].data for i in k])
phys = np.concatenate([m.cell_data["gmsh:physical"][i] for i in k]).astype(np.int32)
p = m.points
used = np.unique(cells)
points = np.zeros_like(p)
points[used] = p[used]
x, y, z = points[:, 0], points[:, 1], points[:, 2]
temperature = 300 + 20 * np.sin(0.3 * x) * np.cos(0.4 * y) + 2 * z
displacement = np.stack([1e-3 * x * x, 2e-4 * x * y, -5e-4 * x * x * (1 + 0.1 * z)], axis=1)
c = p[cells[:, :4]].mean(axis=1)
stress = 1e8 * (1 + 0.5 * np.cos(0.5 * c[:, 0]) * np.sin(0.7 * c[:, 2])) * np.where(phys == 1, 1.0, 2.7)
# (Only the mesh's nodes: gmsh's geometry points off the mesh dropped.)
index = -np.ones(len(p), np.int64)
index[used] = np.arange(len(used))
meshio.Mesh(p[used], [(kind, index[cells])], point_data={"temperature": temperature[used], "displacement": displacement[used]},
            cell_data={"ObjectId": [phys], "stress": [stress]}).write(name + ".vtu")
PY
    pvpython - "$m" >/dev/null 2>&1 <<'PY'
import sys
from paraview.simple import SaveData, XMLUnstructuredGridReader
SaveData(sys.argv[1] + ".e", proxy=XMLUnstructuredGridReader(FileName=[sys.argv[1] + ".vtu"]))
PY
    exact=$([[ $m == *_2 ]] && echo --exact || true)
    "$enc" $m.e $exact -o $m.dtm >$m.log 2>&1
    "$dec" $m.dtm -o $m.out.e >/dev/null 2>&1
    "$enc" $m.out.e $exact -o $m.again.dtm >/dev/null 2>&1
    cmp -s $m.dtm $m.again.dtm && same=yes || same=NO
    xz -9 -k -f -T1 $m.e
    zstd -q -19 -f $m.e -o $m.e.zst
    vertices=$(sed -n 's/.*: \([0-9]*\) points, .*/\1/p' $m.log | head -1)
    cells=$(sed -n "s/.*the input's \([0-9]*\) tetrahedra.*/\1/p" $m.log | head -1)
    nodes=$( [[ -n $exact ]] && sed -n "s/.*level 0's \([0-9]*\) second-order edges.*/\1/p" $m.log | head -1 || echo 0)
    e=$(stat -c %s $m.e) xzs=$(stat -c %s $m.e.xz) zs=$(stat -c %s $m.e.zst) s=$(stat -c %s $m.dtm)
    best=$((xzs < zs ? xzs : zs))
    rows+="| $m | $vertices | ${nodes:-0} | $cells | $e | $xzs | $zs | $s | $(awk -v a=$s -v b=$best 'BEGIN{printf "%.3f", a / b}') | $(awk -v a=$s -v v=$vertices 'BEGIN{printf "%.1f", 8 * a / v}') | $same |
"
  done
done
cat >"$root/bench/results/EXODUS.md" <<EOF
# Exodus II files against the stream

Made by \`bench/exodus.sh\` ($(date -u +%F), this project's 2-core machine): the two-material gmsh part of
data/two_materials.geo (gmsh 4.8.4) at CharacteristicLengthMax 0.35 (part_a) and 0.15 (part_b), linear and
second-order (\`_2\`), each with a float64 temperature and a float64 displacement at every node and a float64
stress in every element, written by ParaView's Exodus writer (netCDF classic, its two blocks the materials).
*Stream*: \`meshenc X.e\` (every level; the values lossless), second-order ones with \`--exact\` (level 0 the
file's 10-node tetrahedra, their edge nodes within half a grid step, the values there lossless). *Same*: meshdec's
\`.e\` of the stream read back by meshenc gives the same stream.

| file | vertices | edge nodes | tetrahedra | .e bytes | xz -9 | zstd -19 | stream | stream / better | stream bits/vertex | same |
|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|
${rows}
The values dominate: a float64 at every node costs what it holds (lossless), where the mesh's connectivity, which
an Exodus file stores as 4 or 10 integers a cell, the stream does not send at all (\`--field-error\` codes values
within a bound instead: [docs/VALUES.md](../../docs/VALUES.md)).
EOF
cat "$root/bench/results/EXODUS.md"
