#!/usr/bin/env bash
# tests/reader_variants.sh MESHENC -- the variants of their files that gmsh,
# meshio, ParaView (VTK) and TetGen write, made here, read as the plain
# file is or with what they add named as left out:
# gmsh 4.1 and 2.2 with a volume in two physical groups (2.2 repeats the
# element: the same stream, the second group named), with physical names
# holding runs of blanks, with Mesh.SaveParametric (2.2's $ParametricNodes,
# ASCII and binary), without physical groups (2.2's elementary entities as
# 4.1's volume entities), with a view of two time steps ($NodeData of one
# name); meshio's and ParaView's legacy .vtk (VTK 9's vtktype names, the
# arrays' METADATA) as their .vtu; a .pvtu of ghost cells (read from their
# own pieces); a .vtu's string array and FieldData, values on its
# triangles; TetGen's .face beside its .node and .ele (its markers the
# tagged faces, but TetGen's default), a tetrahedron naming a point twice.
set -euo pipefail
meshenc=$1
meshdec=$(dirname "$meshenc")/meshdec
py=/usr/bin/python3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
failed=0
cat > two.geo <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Box(2) = {1, 0, 0, 1, 1, 1};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume("left   part  x", 10) = {1};
Physical Volume("right", 20) = {2};
Physical Volume("both", 30) = {1, 2};
Physical Surface("base", 5) = {5};
Mesh.MeshSizeMax = 0.3;
GEO
gmsh two.geo -3 -format msh41 -o two41.msh >/dev/null
gmsh two.geo -3 -format msh22 -o two22.msh >/dev/null
gmsh two.geo -3 -format msh22 -setnumber Mesh.SaveParametric 1 -o par22.msh >/dev/null
gmsh two.geo -3 -format msh22 -bin -setnumber Mesh.SaveParametric 1 -o parb22.msh >/dev/null
for f in two41 two22 par22 parb22; do "$meshenc" $f.msh -o $f.dtm >$f.out 2>&1 || { cat $f.out; failed=1; }; done
for f in two22 par22 parb22; do
  cmp -s two41.dtm $f.dtm || { echo "$f.msh: not the stream of two41.msh"; cat $f.out; failed=1; }
done
for f in two41 two22; do
  grep -q 'regions (physical [a-z]*), 2: 10 "left   part  x" ([0-9]* tetrahedra), 20 "right"' $f.out ||
    { echo "$f.msh: not its two regions, the name's blanks kept"; cat $f.out; failed=1; }
  grep -q 'left out.*physical volumes.*: 30 "both"' $f.out ||
    { echo "$f.msh: the second physical group not named as left out"; cat $f.out; failed=1; }
done
# (Without physical groups: the elementary entities, 2.2's second tag.)
grep -v Physical two.geo >plain.geo
gmsh plain.geo -3 -format msh41 -o plain41.msh >/dev/null
gmsh plain.geo -3 -format msh22 -o plain22.msh >/dev/null
for f in plain41 plain22; do "$meshenc" $f.msh -o $f.dtm >$f.out 2>&1 || { cat $f.out; failed=1; }; done
cmp -s plain41.dtm plain22.dtm || { echo "plain22.msh: not the stream of plain41.msh"; cat plain22.out; failed=1; }
grep -q "regions (volume entities), 2: 1 " plain22.out || { echo "plain22.msh: no volume entities"; cat plain22.out; failed=1; }
# (A view of two time steps: a field a step.)
"$py" - <<'PY'
text = open("two41.msh").read()
lines = text.split("\n")
nodes = int(lines[lines.index("$Nodes") + 1].split()[1])
def view(step):
    return ("$NodeData\n1\n\"T\"\n1\n%d.0\n3\n%d\n1\n%d\n" % (step, step, nodes) +
            "".join("%d %g\n" % (i, i * (step + 1)) for i in range(1, nodes + 1)) + "$EndNodeData\n")
open("steps.msh", "w").write(text + view(0) + view(1))
PY
"$meshenc" steps.msh -o steps.dtm >steps.out 2>&1 || { cat steps.out; failed=1; }
grep -q "fields coded: 'T' (float64, lossless), 'T (step 1)' (float64, lossless)" steps.out ||
  { echo "steps.msh: not a field a time step"; cat steps.out; failed=1; }

# meshio's .vtk and .vtu of the part (its regions, an integer point array,
# cell data on the tetrahedra and the triangles), and ParaView's .vtk of
# the .vtu (ASCII and binary: each array's METADATA after it): one stream.
"$py" - <<'PY'
import meshio
import numpy as np
m = meshio.read("two41.msh")
tets, tris = m.get_cells_type("tetra"), m.get_cells_type("triangle")
physical = [m.get_cell_data("gmsh:physical", "tetra").astype(np.int32),
            m.get_cell_data("gmsh:physical", "triangle").astype(np.int32)]
mesh = meshio.Mesh(m.points, [("tetra", tets), ("triangle", tris)],
                   point_data={"T": m.points[:, 0], "id": np.arange(len(m.points), dtype=np.int32)},
                   cell_data={"gmsh:physical": physical,
                              "stress": [np.arange(len(tets)) * 1.0, np.arange(len(tris)) + 7.0]})
meshio.write("mio.vtu", mesh)
meshio.write("mio.vtk", mesh)
PY
pvpython - >pv.log 2>&1 <<'PY' || { echo "ParaView could not write the .vtk files"; cat pv.log; failed=1; }
from paraview.simple import SaveData, XMLUnstructuredGridReader
r = XMLUnstructuredGridReader(FileName=["mio.vtu"])
SaveData("pv_ascii.vtk", proxy=r, FileType="Ascii")
SaveData("pv_binary.vtk", proxy=r, FileType="Binary")
from vtkmodules.vtkCommonCore import vtkDoubleArray, vtkStringArray
from vtkmodules.vtkFiltersParallel import vtkExtractUnstructuredGridPiece
from vtkmodules.vtkIOLegacy import vtkUnstructuredGridWriter
from vtkmodules.vtkIOParallelXML import vtkXMLPUnstructuredGridWriter
from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter
x = vtkXMLUnstructuredGridReader()
x.SetFileName("mio.vtu")
x.Update()
g = x.GetOutput()
t = vtkDoubleArray()
t.SetName("TimeValue")
t.InsertNextValue(3.5)
g.GetFieldData().AddArray(t)
s = vtkStringArray()
s.SetName("labels")
s.SetNumberOfValues(g.GetNumberOfCells())
for i in range(g.GetNumberOfCells()):
    s.SetValue(i, "cell %d" % i)
g.GetCellData().AddArray(s)
for writer, name in ((vtkXMLUnstructuredGridWriter(), "extra.vtu"), (vtkUnstructuredGridWriter(), "extra.vtk")):
    writer.SetFileName(name)
    writer.SetInputData(g)
    writer.Write()
# Two pieces with a layer of ghost cells, as VTK's parallel writer makes them.
e = vtkExtractUnstructuredGridPiece()
e.SetInputConnection(x.GetOutputPort())
e.CreateGhostCellsOn()
w = vtkXMLPUnstructuredGridWriter()
w.SetInputConnection(e.GetOutputPort())
w.SetFileName("ghosts.pvtu")
w.SetNumberOfPieces(2)
w.SetStartPiece(0)
w.SetEndPiece(1)
w.SetGhostLevel(1)
w.Write()
PY
for f in mio.vtu mio.vtk pv_ascii.vtk pv_binary.vtk extra.vtu extra.vtk ghosts.pvtu; do
  "$meshenc" $f -o $f.dtm >$f.out 2>&1 || { echo "$f: not read"; cat $f.out; failed=1; }
done
for f in mio.vtk pv_binary.vtk; do
  cmp -s mio.vtu.dtm $f.dtm || { echo "$f: not the stream of mio.vtu"; cat $f.out; failed=1; }
done
# (ParaView's ASCII .vtk rounds the values to 6 digits: the same regions
# and tags, and as many fields and cell data.)
for what in "regions (" "tagged faces (" "per-vertex fields coded" "cell data (level 0"; do
  [ "$(grep "$what" mio.vtu.out | cut -d: -f2-)" = "$(grep "$what" pv_ascii.vtk.out | cut -d: -f2-)" ] ||
    { echo "pv_ascii.vtk: its $what differ from mio.vtu's"; cat pv_ascii.vtk.out; failed=1; }
done
grep -q "left out.*the values of the cell arrays 'stress' on the triangles" mio.vtu.out ||
  { echo "mio.vtu: the triangles' cell data not named as left out"; cat mio.vtu.out; failed=1; }
for f in extra.vtu extra.vtk; do
  grep -q "left out.*'TimeValue'" $f.out && grep -q "left out.*'labels'" $f.out ||
    { echo "$f: its FieldData or string array not named as left out"; cat $f.out; failed=1; }
done
grep -q "left out.*ghost cells (vtkGhostType" ghosts.pvtu.out ||
  { echo "ghosts.pvtu: its ghost cells not named"; cat ghosts.pvtu.out; failed=1; }
"$meshdec" ghosts.pvtu.dtm -q -o ghosts.out.vtu && "$meshdec" mio.vtu.dtm -q -o mio.out.vtu || failed=1
"$py" - <<'PY' || failed=1
import sys
import meshio
import numpy as np
def cells(path):
    m = meshio.read(path)
    return {tuple(sorted(map(tuple, np.round(m.points[t], 6)))) for t in m.cells_dict["tetra"]}
if cells("ghosts.out.vtu") != cells("mio.out.vtu"):
    sys.exit("ghosts.pvtu: level 0 is not the .vtu's (its ghost cells read as cells)")
PY

# TetGen: its .face's boundary markers (a .poly's facet markers) are the
# tagged faces; a tetrahedron naming a point twice named.
cat > box.poly <<'POLY'
8 3 0 0
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 0 0 1
6 1 0 1
7 1 1 1
8 0 1 1
6 1
1 0 1
4 1 2 3 4
1 0 2
4 5 6 7 8
1 0 3
4 1 2 6 5
1 0 3
4 2 3 7 6
1 0 3
4 3 4 8 7
1 0 3
4 4 1 5 8
0
0
POLY
tetgen -pq1.2a0.01Q box.poly >/dev/null
"$meshenc" box.1.node -o box.dtm >box.out 2>&1 || { cat box.out; failed=1; }
grep -q "tagged faces (the .face's boundary markers), 3: 1 ([0-9]* triangles), 2 ([0-9]* triangles), 3 " box.out ||
  { echo "box.1.node: its .face's markers are not the tagged faces"; cat box.out; failed=1; }
# (Every face marked 1, TetGen's default without facet markers: none.)
sed 's/^1 0 [23]$/1 0 1/' box.poly >plain.poly
tetgen -pq1.2a0.01Q plain.poly >/dev/null
"$meshenc" plain.1.node -o plain_box.dtm >plain_box.out 2>&1 || { cat plain_box.out; failed=1; }
grep -q "tagged faces\|left out" plain_box.out && { echo "plain.1.node: TetGen's default markers kept"; cat plain_box.out; failed=1; }
# (One facet marked 1, the others 0: the 1s are the user's, kept.)
sed 's/^1 0 [23]$/1 0 0/' box.poly >one.poly
tetgen -pq1.2a0.01Q one.poly >/dev/null
"$meshenc" one.1.node -o one_box.dtm >one_box.out 2>&1 || { cat one_box.out; failed=1; }
grep -q "tagged faces (the .face's boundary markers), 1: 1 " one_box.out ||
  { echo "one.1.node: the one facet marked 1 not kept"; cat one_box.out; failed=1; }
cp box.1.node flat.node
awk 'NR == 2 { $3 = $2 } { print }' box.1.ele >flat.ele
"$meshenc" flat.node -o flat.dtm >flat.out 2>&1 || { cat flat.out; failed=1; }
grep -q "left out.*1 tetrahedron naming a point twice" flat.out ||
  { echo "flat.ele: the tetrahedron naming a point twice not named"; cat flat.out; failed=1; }

[ $failed -eq 0 ] && echo "reader_variants: ok"
exit $failed
