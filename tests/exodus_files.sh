#!/usr/bin/env bash
# tests/exodus_files.sh MESHENC -- Exodus II files as ParaView and meshio
# write them, made here from a two-material gmsh part, read by meshenc; and
# meshdec's own, read by ParaView's Exodus reader (blocks, side set, 10-node
# tetrahedra) and by meshenc back to the stream that meshdec's .msh gives.
# Needs gmsh, python3-meshio, python3-netcdf4 and pvpython (scripts/setup.sh
# --all).
set -u
meshenc=$1
meshdec=$(dirname "$meshenc")/meshdec
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
failed=0
cat > part.geo <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Box(2) = {1, 0, 0, 1, 1, 1};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume("aluminium", 1) = {1};
Physical Volume("steel", 2) = {2};
Physical Surface("base", 3) = {5};
Mesh.MeshSizeMax = 0.2;
GEO
gmsh part.geo -3 -format msh41 -o a.msh >/dev/null && gmsh part.geo -3 -order 2 -format msh41 -o q.msh >/dev/null ||
  { echo "gmsh failed"; exit 1; }

# The part with a temperature, a vector and a cell value per material, as
# a .vtu (its blocks' ids the ObjectId array, as ParaView's Exodus writer
# takes them) and as meshio's Exodus file.
/usr/bin/python3 - <<'PY' || { echo "meshio failed"; exit 1; }
import meshio, numpy as np
m = meshio.read("a.msh")
k = [i for i, c in enumerate(m.cells) if c.type == "tetra"]
tets = np.concatenate([m.cells[i].data for i in k])
phys = np.concatenate([m.cell_data["gmsh:physical"][i] for i in k]).astype(np.int32)
p = m.points
mesh = meshio.Mesh(p, [("tetra", tets)], point_data={"T": p[:, 0] ** 2 + p[:, 1], "u": 0.5 * p},
                   cell_data={"ObjectId": [phys], "p": [1.5 * phys]})
mesh.write("part.vtu")
meshio.write("meshio.e", mesh, file_format="exodus")
open("counts", "w").write("%d %d %d\n" % (len(tets), (phys == 1).sum(), (phys == 2).sum()))
PY
read -r tets ones twos < counts
pvpython - <<'PY' >/dev/null 2>&1 || { echo "pvpython cannot write an Exodus file"; exit 1; }
from paraview.simple import *
SaveData("paraview.e", proxy=XMLUnstructuredGridReader(FileName=["part.vtu"]))
PY

# ParaView's file: its blocks the regions, its variables the fields; the
# stream is the one the .vtu gives with ObjectId as the regions.
"$meshenc" paraview.e -o paraview.dtm > paraview.log 2>&1 || { cat paraview.log; failed=1; }
"$meshenc" part.vtu --region-array ObjectId -o vtu.dtm > vtu.log 2>&1 || { cat vtu.log; failed=1; }
grep -q "regions (element blocks), 2: 1 ($ones tetrahedra), 2 ($twos tetrahedra)" paraview.log &&
  grep -q "fields coded: 'T' (float64, lossless), 'u' (float64 x 3, lossless)" paraview.log &&
  grep -q "cell data (level 0's cells): 'p' (float64, lossless)" paraview.log ||
  { echo "paraview.e: not its blocks and variables"; cat paraview.log; failed=1; }
cmp -s paraview.dtm vtu.dtm || { echo "paraview.e: not the .vtu's stream"; failed=1; }

# meshio's file: its tetrahedra; its variable, which libexodusii 6.02 does
# not find there, named.
"$meshenc" meshio.e -o meshio.dtm > meshio.log 2>&1 || { cat meshio.log; failed=1; }
grep -q "the input's $tets tetrahedra" meshio.log && grep -q "variables 'T', 'u': named, but libexodusii 6.02 finds no values" meshio.log ||
  { echo "meshio.e: not its tetrahedra, or its variables unnamed"; cat meshio.log; failed=1; }

# meshdec's files: linear, and second-order with --exact; meshenc reads
# each back to the stream meshdec's .msh gives.
"$meshenc" a.msh -o a.dtm >/dev/null 2>&1 && "$meshenc" q.msh --exact -o q.dtm >/dev/null 2>&1 ||
  { echo "meshenc failed on gmsh's part"; exit 1; }
for s in a q; do
  exact=$([ $s = q ] && echo --exact)
  "$meshdec" $s.dtm -o $s.out.e >/dev/null 2>&1 && "$meshdec" $s.dtm -o $s.out.msh >/dev/null 2>&1 ||
    { echo "meshdec failed on $s.dtm"; failed=1; continue; }
  "$meshenc" $s.out.e $exact -o $s.e.dtm >/dev/null 2>&1 && "$meshenc" $s.out.msh $exact -o $s.msh.dtm >/dev/null 2>&1 ||
    { echo "meshenc failed on $s.out.e or $s.out.msh"; failed=1; continue; }
  cmp -s $s.e.dtm $s.msh.dtm || { echo "$s.out.e: not the stream of meshdec's .msh"; failed=1; }
done
# (Without --exact, the TETRA10 blocks' edge nodes named as left out, as
# the tetrahedra's, no other kind of element named.)
"$meshenc" q.out.e -o q.linear.dtm > q.linear.log 2>&1 || { cat q.linear.log; failed=1; }
grep -q "nodes on the edges of second-order elements ([0-9]* second-order tetrahedra)" q.linear.log ||
  { echo "q.out.e: the TETRA10 nodes' note names other elements"; cat q.linear.log; failed=1; }
faces=$(/usr/bin/python3 -c "
import meshio
m = meshio.read('a.msh')
print(sum(int((d == 3).sum()) for c, d in zip(m.cells, m.cell_data['gmsh:physical']) if c.type == 'triangle'))")
pvpython - "$faces" <<'PY' > pv.log 2>&1 || { echo "ParaView does not read meshdec's .e files as written"; cat pv.log; failed=1; }
import sys
from paraview.simple import ExodusIIReader
from paraview import servermanager as sm
faces = int(sys.argv[1])
for path, cell_type in (("a.out.e", 10), ("q.out.e", 24)):
    r = ExodusIIReader(FileName=[path])
    r.UpdatePipelineInformation()
    r.SideSetArrayStatus = list(r.SideSetArrayStatus.Available)
    r.PointVariables = list(r.PointVariables.Available)
    r.UpdatePipeline()
    data = sm.Fetch(r)
    blocks = {}
    it = data.NewIterator()
    it.InitTraversal()
    while not it.IsDoneWithTraversal():
        b = it.GetCurrentDataObject()
        blocks[it.GetCurrentMetaData().Get(data.NAME())] = (
            b.GetNumberOfCells(), {b.GetCellType(i) for i in range(b.GetNumberOfCells())},
            {b.GetPointData().GetArrayName(i) for i in range(b.GetPointData().GetNumberOfArrays())})
        it.GoToNextItem()
    assert set(blocks) == {"aluminium", "steel", "base"}, (path, blocks)
    assert blocks["aluminium"][1] == {cell_type} and blocks["steel"][1] == {cell_type}, (path, blocks)
    assert {"level", "boundary"} <= blocks["steel"][2], (path, blocks)
    assert blocks["base"][0] == faces, (path, blocks["base"], faces)
PY
# meshio reads meshdec's files too: its two blocks' cells, its variables
# by name (no stale bytes in them).
/usr/bin/python3 - <<'PY' || { echo "meshio does not read meshdec's .e files as written"; failed=1; }
import meshio
for path, kind in (("a.out.e", "tetra"), ("q.out.e", "tetra10")):
    m = meshio.read(path)
    assert [c.type for c in m.cells] == [kind, kind], (path, m.cells)
    assert {"level", "boundary"} <= set(m.point_data), (path, list(m.point_data))
PY
[ $failed -eq 0 ] && echo "exodus_files: ok"
exit $failed
