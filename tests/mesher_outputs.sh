#!/usr/bin/env bash
# tests/mesher_outputs.sh MESHENC -- meshes as gmsh and Netgen write them,
# made here by Debian's gmsh and python3-netgen, read by meshenc: a
# two-material gmsh part in .msh 2.2 and 4.1, ASCII and binary, gives one
# stream from all four, with its two physical volumes as regions and its
# physical surface as tagged faces, nothing left out; meshdec writes them
# back as gmsh physical groups, VTU cell data and Medit refs, which gmsh and
# meshio read; a Netgen
# CSG part exported as gmsh 2.0 ("2.000000") is read with its domain (Netgen
# tags a domain d 100000 + d), and a Netgen .vol (and .vol.gz) with its
# named materials and boundary conditions, which meshdec's .vol gives back
# to Netgen. With --exact both decode cell for cell. A
# graded gmsh mesh encoded in blocks keeps its coarse inside's large cells.
# gmsh -save_all's volumes and surfaces in no physical group join none. A
# partitioned mesh (gmsh -part) gives the stream of the mesh whole.
# Second-order meshes (gmsh -order 2, Netgen's SecondOrder()) give their
# linear mesh's stream (with --exact, their 10-node tetrahedra back, with
# the point data at every node); prisms and hexahedra (gmsh's, VTK's, Netgen's
# boundary layer, Medit's) are read as tetrahedra.
set -euo pipefail
meshenc=$1
meshdec=$(dirname "$meshenc")/meshdec
here=$(cd "$(dirname "$0")" && pwd)
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
Mesh.MeshSizeMax = 0.15;
GEO
for v in 22 41; do
  gmsh part.geo -3 -format msh$v -o a$v.msh >/dev/null
  gmsh part.geo -3 -bin -format msh$v -o b$v.msh >/dev/null
  for kind in a b; do "$meshenc" $kind$v.msh -o $kind$v.dtm >$kind$v.out 2>&1; done
done
for f in b22 a41 b41; do
  cmp -s a22.dtm $f.dtm || { echo "$f.msh: a stream other than a22.msh's"; failed=1; }
done
for f in a22 b22 a41 b41; do
  grep -q 'regions (physical [a-z]*), 2: 1 "aluminium" ([0-9]* tetrahedra), 2 "steel"' $f.out ||
    { echo "$f.msh: the physical volumes are not the regions"; cat $f.out; failed=1; }
  grep -q 'tagged faces (physical [a-z]*), 1: 3 "base" ([0-9]* triangles)' $f.out ||
    { echo "$f.msh: the physical surface is not the tagged faces"; cat $f.out; failed=1; }
  grep -q "left out" $f.out && { echo "$f.msh: something left out"; cat $f.out; failed=1; }
done
# The same part meshed to second order (10-node tetrahedra, 6-node
# triangles) is read as its linear cells: the stream of the linear mesh
# from each .msh flavour, from meshio's .vtu of it (VTK's quadratic
# cells) and from gmsh's Medit .mesh (TetrahedraP2), the regions and
# tagged faces kept, the edge nodes named.
for v in 22 41; do
  gmsh part.geo -3 -order 2 -format msh$v -o q$v.msh >/dev/null
  gmsh part.geo -3 -order 2 -bin -format msh$v -o qb$v.msh >/dev/null
done
# (meshio's .vtu of each, its cells and their physical tags: the same
# stream as each other, the names being gmsh's only.)
/usr/bin/python3 - <<'PY' || { echo "meshio does not convert the .msh files"; failed=1; }
import meshio
for given, written in (("a41.msh", "l.vtu"), ("q41.msh", "q.vtu")):
    m = meshio.read(given)
    meshio.write(written, meshio.Mesh(m.points, m.cells, cell_data={"gmsh:physical": m.cell_data["gmsh:physical"]}))
PY
"$meshenc" l.vtu -o l.vtu.dtm >/dev/null 2>&1 || failed=1
# (And gmsh's Medit .mesh of each: TetrahedraP2 and TrianglesP2, the refs
# gmsh's elementary entities.)
gmsh part.geo -3 -o l.mesh >/dev/null && gmsh part.geo -3 -order 2 -o q.mesh >/dev/null
"$meshenc" l.mesh -o l.mesh.dtm >/dev/null 2>&1 || failed=1
for f in q22.msh qb22.msh q41.msh qb41.msh q.vtu q.mesh; do
  "$meshenc" $f -o $f.dtm >$f.out 2>&1 || { cat $f.out; failed=1; }
  linear=a22.dtm
  [ $f = q.vtu ] && linear=l.vtu.dtm
  [ $f = q.mesh ] && linear=l.mesh.dtm
  cmp -s $linear $f.dtm || { echo "$f: not the linear mesh's stream"; cat $f.out; failed=1; }
  grep -q "left out.*[0-9]* nodes on the edges of second-order elements ([0-9]* second-order tetrahedra)" $f.out ||
    { echo "$f: the edge nodes are not named as left out"; cat $f.out; failed=1; }
done
grep -q 'tagged faces (physical [a-z]*), 1: 3 "base" ([0-9]* triangles)' q41.msh.out ||
  { echo "q41.msh: the 6-node triangles are not the tagged faces"; cat q41.msh.out; failed=1; }
# Cells of other shapes: a boundary layer of prisms (a triangulated surface
# extruded in layers) under a core of tetrahedra, and a block of
# hexahedra. The prisms are read as the solid and regions gmsh's own
# extrusion into tetrahedra gives (the same stream: the levels depend on
# the solid, not on how its cells are cut); with --exact their .vtu
# (meshio's wedges, VTK's other turn) gives the .msh's very tetrahedra; the
# hexahedra's solid (a 1 x 1 x 0.5 block) is level 0's, cell for cell with
# --exact, its quadrangles tagged.
cat > layer.geo <<'GEO'
Point(1) = {0, 0, 0, 0.2}; Point(2) = {1, 0, 0, 0.2}; Point(3) = {1, 1, 0, 0.2}; Point(4) = {0, 1, 0, 0.2};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
layer[] = Extrude {0, 0, 0.2} { Surface{1}; Layers{3}; Recombine; };
core[] = Extrude {0, 0, 0.8} { Surface{layer[0]}; };
Physical Volume("layer", 1) = {layer[1]};
Physical Volume("core", 2) = {core[1]};
Physical Surface("bottom", 3) = {1};
GEO
sed 's/Layers{3}; Recombine; }/Layers{3}; }/' layer.geo > layer_tets.geo
cat > block.geo <<'GEO'
Point(1) = {0, 0, 0, 0.2}; Point(2) = {1, 0, 0, 0.2}; Point(3) = {1, 1, 0, 0.2}; Point(4) = {0, 1, 0, 0.2};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 6; Transfinite Surface{1}; Recombine Surface{1};
block[] = Extrude {0, 0, 0.5} { Surface{1}; Layers{4}; Recombine; };
Physical Volume("block", 1) = {block[1]};
Physical Surface("bottom", 3) = {1};
GEO
for g in layer layer_tets block; do gmsh $g.geo -3 -format msh41 -o $g.msh >/dev/null; done
# (And both made second-order: 18-node prisms, 27-node hexahedra, read
# as the linear ones.)
for g in layer block; do gmsh $g.geo -3 -order 2 -format msh41 -o ${g}_2.msh >/dev/null; done
"$meshenc" layer.msh -o layer.dtm >layer.out 2>&1 || { cat layer.out; failed=1; }
"$meshenc" layer_tets.msh -q -o layer_tets.dtm || failed=1
cmp -s layer.dtm layer_tets.dtm || { echo "layer.msh: its prisms are not gmsh's solid"; cat layer.out; failed=1; }
grep -q "left out.*the shapes of its [0-9]* prisms: each is read as the tetrahedra that split it" layer.out ||
  { echo "layer.msh: the prisms are not named"; cat layer.out; failed=1; }
/usr/bin/python3 - <<'PY' || { echo "meshio does not convert layer.msh"; failed=1; }
import meshio
m = meshio.read("layer.msh")
meshio.write("layer.vtu", meshio.Mesh(m.points, m.cells, cell_data={"gmsh:physical": m.cell_data["gmsh:physical"]}))
PY
"$meshenc" layer.vtu -o layer_vtu.dtm >layer_vtu.out 2>&1 || failed=1
for g in layer block; do
  "$meshenc" $g.msh -q -o $g.linear.dtm && "$meshenc" ${g}_2.msh -o ${g}_2.dtm >${g}_2.out 2>&1 || failed=1
  cmp -s $g.linear.dtm ${g}_2.dtm || { echo "${g}_2.msh: not the linear mesh's stream"; cat ${g}_2.out; failed=1; }
  grep -q "nodes on the edges of second-order elements (.*[0-9]* second-order hexahedra, prisms and pyramids)" ${g}_2.out ||
    { echo "${g}_2.msh: its second-order cells' other nodes are not named"; cat ${g}_2.out; failed=1; }
done
/usr/bin/python3 - <<'PY' || { echo "meshio does not convert block_2.msh"; failed=1; }
import meshio
for given, written in (("block.msh", "block.vtu"), ("block_2.msh", "block_2.vtu")):
    m = meshio.read(given)
    meshio.write(written, meshio.Mesh(m.points, m.cells, cell_data={"gmsh:physical": m.cell_data["gmsh:physical"]}))
PY
"$meshenc" block.vtu -q -o block_vtu.dtm && "$meshenc" block_2.vtu -q -o block_2_vtu.dtm 2>/dev/null || failed=1
cmp -s block_vtu.dtm block_2_vtu.dtm || { echo "block_2.vtu (VTK's 27-node hexahedra): not the linear one's stream"; failed=1; }
for f in layer.msh layer.vtu; do
  "$meshenc" $f --exact -q -o $f.exact.dtm && "$meshdec" $f.exact.dtm -o $f.exact.vtu 2>/dev/null || failed=1
done
/usr/bin/python3 - <<'PY' || failed=1
import sys
import meshio
import numpy as np
def cells(path):
    m = meshio.read(path)
    tets = np.concatenate([c.data for c in m.cells if c.type == "tetra"])
    return {tuple(sorted(map(tuple, np.round(m.points[t], 9)))) for t in tets}
a, b = cells("layer.msh.exact.vtu"), cells("layer.vtu.exact.vtu")
if a != b or len(a) != 1173:
    sys.exit("layer.vtu: its wedges are not split as the .msh's prisms (%d and %d cells, %d differ)" % (len(a), len(b), len(a ^ b)))
PY
"$meshenc" block.msh --exact -o block.dtm >block.out 2>&1 || { cat block.out; failed=1; }
"$meshdec" block.dtm -o block_out.vtu 2>/dev/null || failed=1
/usr/bin/python3 - <<'PY' || failed=1
import sys
import meshio
import numpy as np
m = meshio.read("block_out.vtu")
p = m.points
tets = np.concatenate([c.data for c in m.cells if c.type == "tetra"])
v = np.einsum("ij,ij->i", p[tets[:, 1]] - p[tets[:, 0]], np.cross(p[tets[:, 2]] - p[tets[:, 0]], p[tets[:, 3]] - p[tets[:, 0]])) / 6
# (Within the grid's rounding: a tetrahedron less would take 8e-4.)
faces = sum(len(c.data) for c in m.cells if c.type == "triangle")
if len(tets) != 600 or abs(v.sum() - 0.5) > 2e-4 or (v <= 0).any() or faces != 50:
    sys.exit("block.msh: level 0 is not its 100 hexahedra's 600 tetrahedra (%d cells, volume %g, %d tagged faces)"
             % (len(tets), v.sum(), faces))
PY
# gmsh's Medit .mesh of the block (Hexahedra, Quadrilaterals): the .msh's
# very tetrahedra and tagged triangles with --exact.
gmsh block.geo -3 -o block.mesh >/dev/null
# (And its second-order .mesh, whose 27-node hexahedra and 9-node
# quadrilaterals gmsh writes under the linear keywords: the linear stream.)
gmsh block.geo -3 -order 2 -o block_2.mesh >/dev/null
"$meshenc" block.mesh -q -o block_mesh_linear.dtm && "$meshenc" block_2.mesh -q -o block_2_mesh.dtm 2>/dev/null || failed=1
cmp -s block_mesh_linear.dtm block_2_mesh.dtm || { echo "block_2.mesh (gmsh's second-order Medit): not the linear stream"; failed=1; }
"$meshenc" block.mesh --exact -o block_mesh.dtm >block_mesh.out 2>&1 || { cat block_mesh.out; failed=1; }
"$meshdec" block_mesh.dtm -o block_mesh_out.vtu 2>/dev/null || failed=1
/usr/bin/python3 - <<'PY' || failed=1
import sys
import meshio
import numpy as np
def cells(path, kind):
    m = meshio.read(path)
    return {tuple(sorted(map(tuple, np.round(m.points[t], 9)))) for t in m.cells_dict[kind]}
for kind, n in (("tetra", 600), ("triangle", 50)):
    a, b = cells("block_out.vtu", kind), cells("block_mesh_out.vtu", kind)
    if a != b or len(a) != n:
        sys.exit("block.mesh (gmsh's Medit hexahedra): %d and %d %s cells, %d differ" % (len(a), len(b), kind, len(a ^ b)))
PY
for ext in msh vtu mesh; do "$meshdec" a41.dtm -o out.$ext 2>/dev/null || failed=1; done
gmsh out.msh -0 -format msh22 -o again.msh >/dev/null 2>&1 || { echo "gmsh does not read out.msh"; failed=1; }
grep -A4 '^\$PhysicalNames' again.msh | grep -q '3 2 "steel"' || { echo "gmsh lost the regions"; failed=1; }
grep -A4 '^\$PhysicalNames' again.msh | grep -q '2 3 "base"' || { echo "gmsh lost the tagged faces"; failed=1; }

# A mesh cut for a parallel solver (gmsh -part N; 4.1 puts its elements in
# the partitions' entities, $PartitionedEntities giving their physical
# groups; 2.2 adds each element's partitions to its tags): the same stream
# as the mesh whole, its regions and tagged faces kept; the partitioning,
# the triangles between partitions, the ghost cells and a periodic
# boundary's node pairs named as left out.
for cut in "41 -part 2" "41 -part 3 -bin -part_ghosts" "22 -part 3" "22 -part 2 -bin"; do
  set -- $cut
  name=cut$(echo "$cut" | tr -d ' -')
  # (gmsh 4.8 says "No mesh elements were found" where a partition has no
  # point elements, exits 1, and writes the file whole.)
  gmsh a41.msh -0 -format msh$1 "${@:2}" -o $name.msh >/dev/null 2>&1 || true
  [ -s $name.msh ] || { echo "gmsh -part $3 wrote no $name.msh"; failed=1; continue; }
  "$meshenc" $name.msh -o $name.dtm >$name.out 2>&1 || { cat $name.out; failed=1; continue; }
  cmp -s a22.dtm $name.dtm || { echo "$name.msh (gmsh -part): not the stream of the mesh whole"; cat $name.out; failed=1; }
  grep -q "left out.*the partitioning into $3 partitions" $name.out ||
    { echo "$name.msh: the partitioning not named as left out"; cat $name.out; failed=1; }
  if [ "$1" = 41 ]; then
    grep -q "left out.*triangles of the interfaces between partitions" $name.out ||
      { echo "$name.msh: the interfaces' triangles not named as left out"; cat $name.out; failed=1; }
  fi
done
grep -q 'left out.*sections $GhostElements' cut41part3binpart_ghosts.out ||
  { echo "gmsh -part_ghosts: the ghost cells not named as left out"; cat cut41part3binpart_ghosts.out; failed=1; }
cat > periodic.geo <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Periodic Surface{2} = {1} Translate{1, 0, 0};
Mesh.MeshSizeMax = 0.3;
GEO
gmsh periodic.geo -3 -format msh41 -o periodic.msh >/dev/null
"$meshenc" periodic.msh -o periodic.dtm >periodic.out 2>&1 || { cat periodic.out; failed=1; }
grep -q 'left out.*sections $Periodic' periodic.out || { echo "periodic.msh: its node pairs not named as left out"; cat periodic.out; failed=1; }

# gmsh -save_all writes the volumes and surfaces in no physical group too,
# under their entity numbers, which may be a group's tag: they must not
# join that group. Here volume 2 and every surface but 5 are in none, and
# the groups are tagged 2.
cat > saveall.geo <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Box(2) = {1, 0, 0, 1, 1, 1};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume("left", 2) = {1};
Physical Surface("base", 2) = {5};
Mesh.MeshSizeMax = 0.15;
GEO
gmsh saveall.geo -3 -format msh41 -o grouped.msh >/dev/null
"$meshenc" grouped.msh -o grouped.dtm >grouped.out 2>&1
left=$(grep -o '2 "left" ([0-9]* tetrahedra)' grouped.out | grep -o '([0-9]*' | tr -d '(')
base=$(grep -o '2 "base" ([0-9]* triangles)' grouped.out | grep -o '([0-9]*' | tr -d '(')
# (gmsh 2.2's -save_all drops the groups: every element's physical tag 0.)
for v in 41; do
  gmsh saveall.geo -3 -save_all -format msh$v -o all$v.msh >/dev/null
  "$meshenc" all$v.msh -o all$v.dtm >all$v.out 2>&1 || { cat all$v.out; failed=1; }
  grep -q "2 \"left\" ($left tetrahedra)" all$v.out && grep -q "tagged faces ([^)]*), 1: 2 \"base\" ($base triangles)" all$v.out ||
    { echo "all$v.msh (-save_all): entities in no group joined a group's tag (alone: $left, $base)"; cat all$v.out; failed=1; }
  grep -q "left out.*triangles of surfaces in no physical group" all$v.out ||
    { echo "all$v.msh: the surfaces in no group are not named as left out"; cat all$v.out; failed=1; }
done
grep -q 'regions (physical volumes; [0-9]* tetrahedra of 1 volume in no physical group as region 3), 2: 2 "left" ([0-9]* tetrahedra), 3 "no physical group"' all41.out ||
  { echo "all41.msh: volume 2 is not a region of its own"; cat all41.out; failed=1; }

# Debian's own Python, where python3-netgen is (not a user's pyenv or venv).
py=/usr/bin/python3
[ -x "$py" ] || py=python3
"$py" - <<'PY'
from netgen.csg import CSGeometry, OrthoBrick, Cylinder, Sphere, Pnt
geo = CSGeometry()
geo.Add(OrthoBrick(Pnt(0, 0, 0), Pnt(2, 1, 1)) - Cylinder(Pnt(0.5, 0.5, -1), Pnt(0.5, 0.5, 2), 0.2)
        - Sphere(Pnt(1.4, 0.5, 0.5), 0.25))
geo.GenerateMesh(maxh=0.15).Export("netgen.msh", "Gmsh2 Format")
PY
head -2 netgen.msh | tail -1 | grep -q "^2\.0" || { echo "Netgen no longer writes gmsh 2.0"; failed=1; }
"$meshenc" netgen.msh -o netgen.dtm >netgen.out || { cat netgen.out; failed=1; }
grep -q "netgen.dtm: [0-9]* bytes" netgen.out || { echo "netgen.msh not encoded"; failed=1; }
grep -q "regions (physical tags), 1: 10000[0-9] (" netgen.out || { echo "netgen.msh: its domain is not a region"; cat netgen.out; failed=1; }
# Netgen's own file, as its GUI and Mesh.Save() write it (.vol, and .vol.gz
# gzipped): a part of two named materials with named boundary conditions
# read with them, as regions and tagged faces with their names; the same
# points and tetrahedra as its gmsh 2.0 export (the same levels), the .gz
# the same bytes; what it holds besides (edge segments, the geometry after
# endmesh) named as left out.
"$py" - <<'PY'
from netgen.csg import CSGeometry, OrthoBrick, Cylinder, Pnt
geo = CSGeometry()
box = OrthoBrick(Pnt(0, 0, 0), Pnt(1, 1, 1)).bc("outer")
pin = Cylinder(Pnt(0.5, 0.5, -1), Pnt(0.5, 0.5, 2), 0.2).bc("pin")
geo.Add((box - pin).mat("aluminium"))
geo.Add((box * pin).mat("steel"))
mesh = geo.GenerateMesh(maxh=0.2)
mesh.Save("ng.vol")
mesh.Save("ng.vol.gz")
mesh.Export("ng.msh", "Gmsh2 Format")
mesh.SecondOrder()
mesh.Save("ng2.vol")
PY
"$meshenc" ng.vol -o ng_vol.dtm >ng_vol.out 2>ng_vol.err || { cat ng_vol.out ng_vol.err; failed=1; }
"$meshenc" ng.vol.gz -q -o ng_volgz.dtm 2>/dev/null || failed=1
"$meshenc" ng.msh -o ng_msh.dtm >ng_msh.out 2>/dev/null || failed=1
cmp -s ng_vol.dtm ng_volgz.dtm || { echo "ng.vol.gz: not the bytes of ng.vol"; failed=1; }
# Its second-order mesh (the edge nodes of the pin's curved faces moved
# onto them): the linear mesh's stream, the edge nodes named.
"$meshenc" ng2.vol -o ng2_vol.dtm >ng2_vol.out 2>&1 || { cat ng2_vol.out; failed=1; }
cmp -s ng_vol.dtm ng2_vol.dtm || { echo "ng2.vol: not the linear mesh's stream"; cat ng2_vol.out; failed=1; }
grep -q "nodes on the edges of second-order elements" ng2_vol.out || { echo "ng2.vol: edge nodes not named"; failed=1; }
grep -q 'regions (materials (Netgen domains)), 2: 1 "aluminium" ([0-9]* tetrahedra), 2 "steel" ([0-9]* tetrahedra)' ng_vol.out ||
  { echo "ng.vol: the materials are not its regions"; cat ng_vol.out; failed=1; }
grep -q 'tagged faces (.*Netgen bcnr.*"outer" (.*"pin" (' ng_vol.out || { echo "ng.vol: no named boundary conditions"; cat ng_vol.out; failed=1; }
grep -q "left out.*edgesegmentsgi2" ng_vol.err || { echo "ng.vol: its edge segments are not named as left out"; cat ng_vol.err; failed=1; }
[ "$(grep -E '^ +[0-9]+ +[0-9]+ ' ng_vol.out | cut -c1-70)" = "$(grep -E '^ +[0-9]+ +[0-9]+ ' ng_msh.out | cut -c1-70)" ] ||
  { echo "ng.vol and its gmsh export give other levels"; cat ng_vol.out ng_msh.out; failed=1; }
# meshdec writes a level back as .vol: Netgen loads it with the materials
# and the boundary conditions' names, its tetrahedra turned as its own.
"$meshdec" ng_vol.dtm -o back.vol --level 1 -q || failed=1
"$py" - <<'PY' || failed=1
import sys
from netgen.meshing import Mesh
def names(path):
    m = Mesh()
    m.Load(path)
    els = m.Elements3D()
    def volume(e):
        p = [m.Points()[v].p for v in e.vertices]
        u, v, w = ([p[k][i] - p[0][i] for i in range(3)] for k in (1, 2, 3))
        return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])
    if any(volume(e) >= 0 for e in els):
        sys.exit(path + ": tetrahedra not turned as Netgen's")
    return (sorted(set(m.GetMaterial(e.index) for e in els)),
            sorted(set(m.GetBCName(e.index - 1) for e in m.Elements2D())))
if names("back.vol") != names("ng.vol"):
    sys.exit("back.vol: %s, ng.vol: %s" % (names("back.vol"), names("ng.vol")))
PY
# Netgen's boundary layer (prisms on the sphere, pyramids where they meet
# the tetrahedra), in its .vol and in meshio's .vtu and Medit .mesh of it:
# with --exact the three decode to the same tetrahedra with the same
# regions, 3 a prism and 2 a pyramid; its second-order .vol (Netgen's
# 12-node prisms, 13-node pyramids) gives the linear one's stream.
"$py" - <<'PY'
from netgen.csg import CSGeometry, Sphere, Pnt
import meshio
geo = CSGeometry()
geo.Add(Sphere(Pnt(0, 0, 0), 1).bc("wall").mat("core"))
mesh = geo.GenerateMesh(maxh=0.4)
mesh.BoundaryLayer(1, 0.05, 1, "layer")
mesh.Save("bl.vol")
mesh.SecondOrder()
mesh.Save("bl2.vol")
m = meshio.read("bl.vol")
m.field_data = {}
meshio.write("bl.vtu", m)
meshio.write("bl.mesh", m)
PY
"$meshenc" bl.vol -o bl.dtm >bl.out 2>&1 || { cat bl.out; failed=1; }
grep -q "left out.*the shapes of its [0-9]* pyramids, [0-9]* prisms: each is read as the tetrahedra" bl.out ||
  { echo "bl.vol: its prisms and pyramids are not named"; cat bl.out; failed=1; }
"$meshenc" bl2.vol -q -o bl2.dtm 2>/dev/null || failed=1
cmp -s bl.dtm bl2.dtm || { echo "bl2.vol (Netgen's second-order prisms): not the linear mesh's stream"; failed=1; }
for f in bl.vol bl.vtu bl.mesh; do
  "$meshenc" $f --exact -q -o $f.exact.dtm 2>/dev/null && "$meshdec" $f.exact.dtm -o $f.exact.vtu 2>/dev/null || failed=1
done
"$py" - <<'PY' || failed=1
import sys
import meshio
import numpy as np
given = meshio.read("bl.vol")
count = {c.type: len(c.data) for c in given.cells}
expected = count["tetra"] + 3 * count["wedge"] + 2 * count["pyramid"]
def cells(path):
    m = meshio.read(path)
    return {(tuple(sorted(map(tuple, np.round(m.points[t], 9)))), r)
            for t, r in zip(m.cells_dict["tetra"], m.cell_data_dict["region"]["tetra"])}
a = cells("bl.vol.exact.vtu")
for other in ("bl.vtu", "bl.mesh"):
    b = cells(other + ".exact.vtu")
    if a != b or len(a) != expected or count["wedge"] == 0:
        sys.exit("%s: its prisms and pyramids are not split as the .vol's (%d and %d cells, %d expected, %d differ)"
                 % (other, len(a), len(b), expected, len(a ^ b)))
PY
# A best-shaped mesh (Netgen's, average smallest solid angle 0.34) gets
# coarser levels: the quality floor is 0.85x level 0's but at most 0.25
# (--quality-floor-cap), each level within D_max and above the floor;
# without the cap the floor (0.29) stops it after one coarser level.
"$py" - <<'PY' 2>/dev/null
from netgen.csg import CSGeometry, OrthoBrick, Cylinder, Sphere, Pnt
geo = CSGeometry()
geo.Add(OrthoBrick(Pnt(0, 0, 0), Pnt(2, 1, 1)) - Cylinder(Pnt(0.5, 0.5, -1), Pnt(0.5, 0.5, 2), 0.2)
        - Sphere(Pnt(1.4, 0.5, 0.5), 0.25))
geo.GenerateMesh(maxh=0.06).Export("fine_netgen.msh", "Gmsh2 Format")
PY
"$meshenc" fine_netgen.msh -q -o fine.dtm --report fine.json || failed=1
"$meshenc" fine_netgen.msh -q -o fine_uncapped.dtm --report fine_uncapped.json --quality-floor-cap 0 || failed=1
"$py" - <<'PY' || failed=1
import json, sys
capped, uncapped = json.load(open("fine.json")), json.load(open("fine_uncapped.json"))
levels = capped["levels"]
q0 = levels[0]["avg_min_solid_angle"]
if q0 < 0.3:
    sys.exit("fine_netgen.msh is not a best-shaped mesh (quality %.3f)" % q0)
if len(levels) < 4 or len(uncapped["levels"]) >= len(levels):
    sys.exit("fine_netgen.msh: %d levels with the cap, %d without" % (len(levels), len(uncapped["levels"])))
for l in levels[1:]:
    if l["avg_min_solid_angle"] < min(0.85 * q0, 0.25) - 1e-9 or l["reference_max_error"] > capped["dmax"] * (1 + 1e-9):
        sys.exit("fine_netgen.msh: level %d breaks a bound: %s" % (l["level"], l))
PY
# The regions as gmsh, meshio (VTU cell data, Medit refs) read them back.
"$py" - <<'PY' || failed=1
import sys
import meshio
import numpy as np
counts = {}
for name, key in (("out.msh", "gmsh:physical"), ("out.vtu", "region"), ("out.mesh", "medit:ref")):
    m = meshio.read(name)
    labels = np.concatenate([np.asarray(a) for a, b in zip(m.cell_data[key], m.cells) if b.type == "tetra"])
    counts[name] = dict(zip(*np.unique(labels, return_counts=True)))
if len({str(c) for c in counts.values()}) != 1 or sorted(counts["out.vtu"]) != [1, 2]:
    sys.exit("the writers' regions differ: %s" % counts)
if meshio.read("out.msh").field_data.get("steel", [None])[0] != 2:
    sys.exit("out.msh: the region names are lost")
# The tagged faces: triangles with the tag 3 in every writer.
for name, key in (("out.msh", "gmsh:physical"), ("out.vtu", "region"), ("out.mesh", "medit:ref")):
    m = meshio.read(name)
    tags = [np.asarray(a) for a, b in zip(m.cell_data[key], m.cells) if b.type == "triangle"]
    if not tags or set(np.concatenate(tags).tolist()) != {3}:
        sys.exit("%s: the tagged faces are lost" % name)
PY
# Tagged faces without regions: meshdec's .msh puts the tetrahedra in a
# physical volume of their own ("volume"), so that meshio, which refuses a
# file whose volume entity is in no group beside surfaces in one, reads it.
"$meshenc" a22.msh --no-regions -o faces_only.dtm -q 2>/dev/null
"$meshdec" faces_only.dtm -o faces_only.msh -q
"$py" - <<'PY' || failed=1
import sys
import meshio
import numpy as np
m = meshio.read("faces_only.msh")
tags = {b.type: set(np.asarray(a).tolist()) for a, b in zip(m.cell_data["gmsh:physical"], m.cells)}
if tags != {"triangle": {3}, "tetra": {1}} or m.field_data.get("volume", [None])[0] != 1:
    sys.exit("faces_only.msh: meshio reads %s, %s" % (tags, m.field_data))
PY
# An element result as gmsh writes it: its mesh-quality plugin's view
# (ICN, per tetrahedron) saved as $ElementData. meshenc keeps it as cell
# data, nothing left out; meshdec's .msh and .vtu carry it back, gmsh
# opens the .msh, meshio reads both, and the .msh encodes again to the same
# cell data (every level-0 cell then an input cell).
cat part.geo - > quality.geo <<'GEO'
Mesh 3;
Plugin(AnalyseMeshQuality).ICNMeasure = 1;
Plugin(AnalyseMeshQuality).CreateView = 1;
Plugin(AnalyseMeshQuality).Run;
Save View[0] "quality.msh";
GEO
gmsh quality.geo -0 -format msh41 >/dev/null 2>&1 || { echo "gmsh did not write its quality view"; failed=1; }
grep -q '^\$ElementData' quality.msh || { echo "gmsh's view has no \$ElementData"; failed=1; }
"$meshenc" quality.msh -o quality.dtm --report quality.json >quality.out 2>&1 || { cat quality.out; failed=1; }
grep -q "cell data (level 0's cells): 'ICN 3D' (float64, lossless)" quality.out ||
  { echo "quality.msh: the element data is not the cell data"; cat quality.out; failed=1; }
grep -q "left out" quality.out && { echo "quality.msh: something left out"; cat quality.out; failed=1; }
for ext in msh vtu; do "$meshdec" quality.dtm -o quality_out.$ext 2>/dev/null || failed=1; done
gmsh quality_out.msh -0 -o quality_again.msh >/dev/null 2>&1 || { echo "gmsh does not read quality_out.msh"; failed=1; }
"$meshenc" quality_out.msh -o quality_again.dtm --report quality_again.json >/dev/null 2>&1 || failed=1
"$py" - <<'PY' || failed=1
import json, sys
import meshio
import numpy as np
first, again = json.load(open("quality.json")), json.load(open("quality_again.json"))
if first["cell_fields"][0]["bytes"] != again["cell_fields"][0]["bytes"]:
    sys.exit("quality_out.msh encodes to other cell data: %s, %s" % (first["cell_fields"], again["cell_fields"]))
if again["cells_from_input"] != again["level0_cells"]:
    sys.exit("quality_out.msh: level 0 is not its own input")
values = {}
for name in ("quality_out.msh", "quality_out.vtu"):
    m = meshio.read(name)
    icn = [np.asarray(a) for a, b in zip(m.cell_data["ICN 3D"], m.cells) if b.type == "tetra"]
    values[name] = np.sort(np.concatenate(icn))
    if len(values[name]) != first["level0_cells"] or not np.all((values[name] > 0) & (values[name] <= 1)):
        sys.exit("%s: the cell data read back is not level 0's ICN" % name)
if not np.array_equal(values["quality_out.msh"], values["quality_out.vtu"]):
    sys.exit("the .msh and the .vtu give other values")
PY
# --exact: the gmsh part (regions, tagged faces, the quality view as cell
# data) and the fine Netgen part decode cell for cell, with their regions
# and cell data on the input's own cells, positively oriented (--keep-order:
# the input's numbering, so the cells compare as they are).
"$meshenc" quality.msh -q --exact --keep-order -o exact_gmsh.dtm --report exact_gmsh.json || failed=1
"$meshenc" fine_netgen.msh -q --exact --keep-order -o exact_netgen.dtm --report exact_netgen.json || failed=1
"$meshdec" exact_gmsh.dtm -o exact_gmsh_out.msh 2>/dev/null || failed=1
"$meshdec" exact_netgen.dtm -o exact_netgen_out.msh 2>/dev/null || failed=1
"$py" - <<'PY' || failed=1
import json, sys
import meshio
import numpy as np
def read_msh41(path):
    """gmsh's own .msh 4.1 (meshio cannot read its quality view): the nodes in file order, the
    tetrahedra as indices into them with their physical tag, and the $ElementData per tetrahedron."""
    lines = open(path).read().split("\n")
    at = lambda name: lines.index(name) + 1
    i = at("$Nodes"); blocks = int(lines[i].split()[0]); i += 1; index = {}
    for _ in range(blocks):
        n = int(lines[i].split()[3]); i += 1
        for k in range(n): index[int(lines[i + k])] = len(index)
        i += 2 * n
    physical = {}
    j = at("$Entities"); counts = list(map(int, lines[j].split())); j += 1 + sum(counts[:3])
    for k in range(counts[3]):
        f = lines[j + k].split(); tags = int(f[7]); physical[int(f[0])] = int(f[8]) if tags else 0
    i = at("$Elements"); blocks = int(lines[i].split()[0]); i += 1; tets, tags, region = [], [], []
    for _ in range(blocks):
        dim, entity, kind, n = map(int, lines[i].split()); i += 1
        for k in range(n):
            f = list(map(int, lines[i + k].split()))
            if kind == 4:
                tags.append(f[0]); tets.append([index[v] for v in f[1:5]]); region.append(physical[entity])
        i += n
    data = {}
    if "$ElementData" in lines:
        i = at("$ElementData"); i += 1 + int(lines[i]); i += 1 + int(lines[i]); n = int(lines[i + 3]); i += 1 + int(lines[i])
        data = {int(f[0]): float(f[1]) for f in (lines[i + k].split() for k in range(n))}
    return np.array(tets), np.array(region), np.array([data.get(t, np.nan) for t in tags])
def decoded(path):
    m = meshio.read(path)
    tetra = [k for k, c in enumerate(m.cells) if c.type == "tetra"]
    get = lambda name: np.concatenate([m.cell_data[name][k] for k in tetra]) if name in m.cell_data else None
    return m.points, np.concatenate([m.cells[k].data for k in tetra]), get("gmsh:physical"), get("ICN 3D")
for given, out, report, icn in (("quality.msh", "exact_gmsh_out.msh", "exact_gmsh.json", True),
                                ("fine_netgen.msh", "exact_netgen_out.msh", "exact_netgen.json", False)):
    if icn:
        a, ar, av = read_msh41(given)
    else:
        m = meshio.read(given)
        tetra = [k for k, c in enumerate(m.cells) if c.type == "tetra"]
        a = np.concatenate([m.cells[k].data for k in tetra])
        ar = np.concatenate([m.cell_data["gmsh:physical"][k] for k in tetra])
    p, b, br, bv = decoded(out)
    ka = {tuple(sorted(t)): i for i, t in enumerate(a)}
    kb = {tuple(sorted(t)): i for i, t in enumerate(b)}
    if set(ka) != set(kb):
        sys.exit("%s: level 0 is not the input cell for cell (%d / %d cells, %d differ)"
                 % (given, len(a), len(b), len(set(ka) ^ set(kb))))
    if any(ar[ka[k]] != br[kb[k]] for k in ka):
        sys.exit("%s: a cell's region is not its own" % given)
    if icn and any(av[ka[k]] != bv[kb[k]] for k in ka):
        sys.exit("%s: a cell's ICN is not its own" % given)
    v = np.einsum("ij,ij->i", p[b[:, 1]] - p[b[:, 0]], np.cross(p[b[:, 2]] - p[b[:, 0]], p[b[:, 3]] - p[b[:, 0]]))
    if not (v > 0).all():
        sys.exit("%s: %d cells not positively oriented" % (out, (v <= 0).sum()))
    r = json.load(open(report))["exact"]
    if r["delaunay_cells"] + r["fill_cells"] != len(a) or r["fill_cells"] == 0:
        sys.exit("%s: the report's exact cells do not add up: %s" % (given, r))
PY

# A graded gmsh mesh (cells of 0.06 at a hole's surface, 1.2 far from it)
# encoded in blocks: the kept radius its mean spacing gives would drop its
# coarse inside's large cells (level 0 was 98.8 from the input's surface,
# D_max 2, and the only level); the encoder raises it, so its bricked level
# 0 is as near the input as the whole-level encoder's, with levels under it.
cat > graded.geo <<'GEO'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 10, 6, 4};
Sphere(2) = {3, 3, 2, 0.5};
BooleanDifference{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Field[1] = Distance;
Field[1].SurfacesList = {7};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 0.06;
Field[2].SizeMax = 1.2;
Field[2].DistMin = 0.1;
Field[2].DistMax = 5;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
GEO
gmsh graded.geo -3 -format msh41 -o graded.msh >/dev/null
"$meshenc" graded.msh --box 256 --dmax 2 -q -o graded_whole.dtm --report graded_whole.json 2>/dev/null || failed=1
"$meshenc" graded.msh --box 256 --dmax 2 -q --bricks --block-points 1500 -o graded.dtm --report graded.json \
  2>graded.err || failed=1
grep -q "level 0's surface is up to" graded.err && { echo "graded.msh: bricked level 0 lacks cells"; failed=1; }
"$py" - <<'PY' || failed=1
import json, sys
whole, bricked = json.load(open("graded_whole.json")), json.load(open("graded.json"))
w, b = whole["levels"][0], bricked["levels"][0]
if b["reference_max_error"] > max(w["reference_max_error"], bricked["dmax"]) + 1e-9 or b["tetrahedra"] != w["tetrahedra"]:
    sys.exit("graded.msh: bricked level 0 (%s) is not the whole-level encoder's (%s)" % (b, w))
r = bricked["level0_kept_radius"]
if not r["used"] > 1.5 * r["from_spacing"] or r["cells_of_the_solid_dropped"] != 0:
    sys.exit("graded.msh: level 0's kept radius was not raised: %s" % r)
if len(bricked["levels"]) < 3 or any(l["reference_max_error"] > bricked["dmax"] + 1e-9 for l in bricked["levels"][1:]):
    sys.exit("graded.msh: %d bricked levels, or one beyond D_max" % len(bricked["levels"]))
PY

# --exact keeps a second-order mesh's edge nodes (format 18.0): a gmsh ball
# of 10-node tetrahedra (its boundary's nodes on the sphere, off their
# edges' midpoints) and Netgen's second-order part (the pin's curved faces)
# decode to the same 10-node tetrahedra, each node within half a grid step
# of the input's, in .msh (which gmsh reads back), .vtu and .vtk; a format
# of linear cells says what it does not write.
cat > ball.geo <<'GEO'
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 1};
Mesh.MeshSizeMax = 0.5;
Physical Volume("ball", 1) = {1};
GEO
gmsh ball.geo -3 -order 2 -format msh41 -o ball2.msh >/dev/null
for f in ball2.msh ng2.vol; do
  "$meshenc" $f --exact -o $f.exact.dtm >$f.exact.out 2>&1 || { cat $f.exact.out; failed=1; }
  grep -q "edge nodes: level 0's [0-9]* second-order edges' nodes" $f.exact.out ||
    { echo "$f --exact: its edge nodes are not kept"; cat $f.exact.out; failed=1; }
  grep -q "nodes on the edges of second-order elements" $f.exact.out &&
    { echo "$f --exact: its kept edge nodes are named as left out"; cat $f.exact.out; failed=1; }
  for ext in msh vtu vtk; do "$meshdec" $f.exact.dtm -o $f.out.$ext 2>/dev/null || failed=1; done
  "$meshdec" $f.exact.dtm -o $f.out.mesh 2>$f.mesh.err || failed=1
  grep -q "are not written: meshdec writes this format.s linear cells" $f.mesh.err || { echo "$f: .mesh's linear cells not said"; failed=1; }
done
gmsh ball2.msh.out.msh -0 -format msh22 -o ball_again.msh >/dev/null 2>&1 || { echo "gmsh does not read ball2.msh.out.msh"; failed=1; }
# (--exact-v13, for older decoders: the linear cells, the nodes named.)
"$meshenc" ball2.msh --exact-v13 -o ball_v13.dtm >ball_v13.out 2>&1 || { cat ball_v13.out; failed=1; }
grep -q "left out.*nodes on the edges of second-order elements" ball_v13.out ||
  { echo "ball2.msh --exact-v13: the edge nodes are not named as left out"; cat ball_v13.out; failed=1; }
meshinfo=$(dirname "$meshenc")/meshinfo
# (--exact-v19, for decoders older than 20.0: the same nodes in a 19.0 stream.)
"$meshenc" ng2.vol --exact-v19 -q -o ng_v19.dtm && "$meshdec" ng_v19.dtm -q -o ng_v19.vtu || failed=1
"$meshinfo" ng_v19.dtm | head -1 | grep -q "\.dtm 19\.0" || { echo "ng2.vol --exact-v19: not a 19.0 stream"; failed=1; }
"$meshdec" ng2.vol.exact.dtm -q -o ng_v20.vtu || failed=1
cmp -s <("$py" -c "import meshio; print(meshio.read('ng_v19.vtu').points.tobytes().hex())") \
  <("$py" -c "import meshio; print(meshio.read('ng_v20.vtu').points.tobytes().hex())") ||
  { echo "ng2.vol: the 19.0 and 20.0 streams decode to other nodes"; failed=1; }
"$py" - "$("$meshinfo" ball2.msh.exact.dtm --json)" "$("$meshinfo" ng2.vol.exact.dtm --json)" <<'PY' || failed=1
import json, sys
import meshio
import numpy as np
def tetra10(path):
    m = meshio.read(path)
    return m.points, np.concatenate([c.data for c in m.cells if c.type == "tetra10"])
pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]  # meshio's (VTK's) order
for given, info in (("ball2.msh", sys.argv[1]), ("ng2.vol", sys.argv[2])):
    step = json.loads(info)["step"]
    p, t = tetra10(given)
    corners = np.unique(t[:, :4])
    node = {}
    for c in t:
        for k, (a, b) in enumerate(pairs):
            node[frozenset((c[a], c[b]))] = p[c[4 + k]]
    for ext in ("msh", "vtu", "vtk"):
        q, u = tetra10(given + ".out." + ext)
        if len(u) != len(t):
            sys.exit("%s.out.%s: %d 10-node tetrahedra, the input %d" % (given, ext, len(u), len(t)))
        # Each decoded corner's input corner (the nearest: within half a
        # step), each decoded node against its edge's in the input.
        nearest = {i: corners[np.argmin(np.abs(p[corners] - q[i]).max(axis=1))] for i in np.unique(u[:, :4])}
        worst, moved = 0.0, 0
        for c in u:
            for k, (a, b) in enumerate(pairs):
                x = q[c[4 + k]]
                worst = max(worst, np.abs(x - node[frozenset((nearest[c[a]], nearest[c[b]]))]).max())
                moved += np.abs(x - (q[c[a]] + q[c[b]]) / 2).max() > 1e-6 * step
        if worst > 0.5 * step * (1 + 1e-6):
            sys.exit("%s.out.%s: an edge node %.3g steps from the input's" % (given, ext, worst / step))
        if moved == 0:
            sys.exit("%s.out.%s: no node off its edge's midpoint (the curved boundary's)" % (given, ext))
PY
# With point data at every node (a simulation's results on 10-node
# tetrahedra, as a solver's .msh or .vtu has them: written by meshio),
# --exact keeps the values at the edge nodes too (format 19.0): the decoded
# .msh, .vtu and .vtk give every node its own values, bit for bit.
"$py" - <<'PY' || failed=1
import meshio, numpy as np
m = meshio.read("ball2.msh")
p = m.points
data = {"temperature": np.sin(2 * p[:, 0]) + p[:, 1] * p[:, 2],
        "displacement": np.stack([p[:, 0] ** 2, np.cos(p[:, 1]), p[:, 2]], axis=1)}
fields = meshio.Mesh(p, [c for c in m.cells if c.type == "tetra10"], point_data=data)
fields.write("ball2_fields.vtu")
meshio.write("ball2_fields.msh", fields, file_format="gmsh22", binary=False)
PY
for f in ball2_fields.msh ball2_fields.vtu; do
  "$meshenc" $f --exact -o $f.dtm >$f.out 2>&1 || { cat $f.out; failed=1; }
  grep -q "at the edge nodes, field 'displacement' (float64 x 3)" $f.out ||
    { echo "$f --exact: the fields' values at the edge nodes are not kept"; cat $f.out; failed=1; }
  grep -q "left out" $f.out && { echo "$f --exact: something is left out"; cat $f.out; failed=1; }
  for ext in msh vtu vtk; do "$meshdec" $f.dtm -o $f.out.$ext 2>/dev/null || failed=1; done
done
"$py" - <<'PY' || failed=1
import sys
import meshio, numpy as np
for given in ("ball2_fields.msh", "ball2_fields.vtu"):
    m = meshio.read(given)
    for ext in ("msh", "vtu", "vtk"):
        out = meshio.read(given + ".out." + ext)
        if len(out.points) != len(m.points):
            sys.exit("%s.out.%s: %d points, the input %d" % (given, ext, len(out.points), len(m.points)))
        index = np.array([np.argmin(np.abs(m.points - q).max(axis=1)) for q in out.points])
        for name in ("temperature", "displacement"):
            theirs = np.asarray(m.point_data[name])[index]
            ours = np.asarray(out.point_data[name]).reshape(theirs.shape)
            if not np.array_equal(ours, theirs):
                sys.exit("%s.out.%s: field '%s' differs at %d nodes" % (given, ext, name,
                                                                       int((ours != theirs).any(axis=-1).sum())))
PY
# Abaqus/CalculiX .inp as gmsh writes it (its physical groups as *ELSET,
# its entities as *ELEMENT ELSET=, the physical surface's 2D elements) and
# as meshio writes it (R3D3 triangles, sets of ids like "12.0", a set of
# gmsh:bounding_entities naming no element): the physical volumes are the
# regions and the physical surface the tagged faces, as from the .msh; the
# entities' sets are named as left out. With --exact, meshdec's .inp
# (element sets, an element-based *SURFACE) gives meshio the input's
# tetrahedra, linear and 10-node, each in its set, every node within half
# a grid step.
gmsh part.geo -3 -o g.inp >/dev/null && gmsh part.geo -3 -order 2 -o g2.inp >/dev/null
"$py" - <<'PY' || { echo "meshio does not write the .inp files"; failed=1; }
import meshio
meshio.write("m.inp", meshio.read("a41.msh"))
q = meshio.read("q41.msh")
# (meshio reads no 6-node 2D element back: the 10-node tetrahedra alone.)
keep = [k for k, c in enumerate(q.cells) if c.type == "tetra10"]
sets = {n: [s[k] for k in keep] for n, s in q.cell_sets.items() if n in ("aluminium", "steel")}
meshio.write("m2.inp", meshio.Mesh(q.points, [q.cells[k] for k in keep], cell_sets=sets))
PY
regions=$(grep -o '"aluminium" ([0-9]* tetrahedra), 2 "steel" ([0-9]* tetrahedra)' a41.out) ||
  { echo "a41.msh: no regions to compare the .inp files' with"; failed=1; }
for f in g.inp g2.inp m.inp m2.inp; do
  "$meshenc" $f --exact -o $f.dtm >$f.out 2>&1 || { cat $f.out; failed=1; }
  grep -qF "regions (element sets), 2: 1 $regions" $f.out ||
    { echo "$f: the physical volumes are not the regions (${regions})"; cat $f.out; failed=1; }
  case $f in
    m2.inp) ;;
    *) grep -q 'tagged faces (surfaces and 2D elements.* element sets), 1: 1 "base" ([0-9]* triangles)' $f.out ||
         { echo "$f: the physical surface is not the tagged faces"; cat $f.out; failed=1; } ;;
  esac
  "$meshdec" $f.dtm -o $f.out.inp 2>/dev/null || failed=1
done
grep -q "left out.*element sets Surface5, Volume1, Volume2" g.inp.out || { echo "g.inp: its entities' sets not named"; failed=1; }
grep -q "edge nodes: level 0's [0-9]* second-order edges' nodes" g2.inp.out ||
  { echo "g2.inp --exact: its edge nodes are not kept"; cat g2.inp.out; failed=1; }
"$py" - "$("$meshinfo" m.inp.dtm --json)" <<'PY' || failed=1
import json, sys
import meshio
import numpy as np
step = json.loads(sys.argv[1])["step"]
pairs = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
# (meshio does not read its own .inp back, its sets' "12.0": the .msh it came from.)
for source, given in (("a41.msh", "m.inp"), ("q41.msh", "m2.inp"), ("a41.msh", "g.inp")):
    a, b = meshio.read(source), meshio.read(given + ".out.inp")
    # Each decoded node's input node: the nearest, within half a step.
    index = np.array([np.argmin(np.abs(a.points - q).max(axis=1)) for q in b.points])
    worst = np.abs(a.points[index] - b.points).max()
    if len(b.points) != len(a.points) or len(set(index)) != len(index) or worst > 0.5 * step * (1 + 1e-9):
        sys.exit("%s.out.inp: %d nodes for %d, %g apart (step %g)" % (given, len(b.points), len(a.points), worst, step))
    def cells(m, to):
        out = {}
        for k, c in enumerate(m.cells):
            if c.type not in ("tetra", "tetra10"):
                continue
            member = {n: set(s[k].tolist()) for n, s in m.cell_sets.items() if n in ("aluminium", "steel")}
            for i, t in enumerate(c.data):
                t = to[t]
                edges = frozenset((frozenset((t[x], t[y])), t[4 + e]) for e, (x, y) in enumerate(pairs)) if len(t) > 4 else None
                sets = frozenset(n for n, s in member.items() if i in s)
                out[tuple(sorted(t[:4]))] = (edges, sets)
        return out
    want, got = cells(a, np.arange(len(a.points))), cells(b, index)
    if want != got:
        sys.exit("%s.out.inp: not the input's tetrahedra in their sets (%d / %d, %d differ)"
                 % (given, len(want), len(got), len(set(want.items()) ^ set(got.items()))))
PY

# --exact --keep-order keeps every node's number (format 21.0) and the
# file's own ids (22.0): ball2.msh with its node tags made to skip (tag t
# as 3t + 100, and its nodes listed in reverse) comes back from meshdec's
# .msh and .inp with each node under its id, within half a grid step, and
# each 10-node tetrahedron naming the same ids; a box of it names its
# vertices by their numbers; --exact-v20 writes 20.0; a mesh of second-order
# prisms keeps the numbers of the nodes the stream holds.
"$py" -c 'import meshio; meshio.write("ball22.msh", meshio.read("ball2.msh"), file_format="gmsh22", binary=False)' &&
  "$py" "$here/gmsh22_node_tags.py" ball22.msh ball_ids.msh 3t+100 --reverse ||
  { echo "could not make ball_ids.msh"; failed=1; }
"$meshenc" ball_ids.msh --exact --keep-order -o ball_ids.dtm >ball_ids.out 2>&1 || { cat ball_ids.out; failed=1; }
grep -q "node labels (the input's node ids)" ball_ids.out || { echo "ball_ids.msh: its ids are not kept"; cat ball_ids.out; failed=1; }
grep -q "left out.*node ids" ball_ids.out && { echo "ball_ids.msh: kept ids named as left out"; failed=1; }
"$meshenc" ball_ids.msh --exact -q -o ball_ids_plain.dtm 2>ball_ids_plain.err || failed=1
grep -q "left out.*the node ids" ball_ids_plain.err || { echo "ball_ids.msh without --keep-order: its ids not named"; failed=1; }
"$meshinfo" ball_ids.dtm | head -1 | grep -q "\.dtm 23\.0.*the input's node ids" || { echo "ball_ids.dtm: not 23.0"; failed=1; }
"$meshenc" ball2.msh --exact-v20 --keep-order -q -o ball_v20.dtm || failed=1
"$meshinfo" ball_v20.dtm | head -1 | grep -q "\.dtm 20\.0" || { echo "ball2.msh --exact-v20: not a 20.0 stream"; failed=1; }
for ext in msh inp; do "$meshdec" ball_ids.dtm -q -o ball_ids.out.$ext || failed=1; done
"$meshdec" ball_ids.dtm -q --box -0.5 -0.5 -0.5 0.5 0.5 0.5 -o ball_ids.box.vtu || failed=1
"$py" - "$("$meshinfo" ball_ids.dtm --json)" <<'PY' || failed=1
import json, sys
import numpy as np
step = json.loads(sys.argv[1])["step"]
def nodes_and_tets(path):  # by id, as the file names them
    lines = [l.strip() for l in open(path)]
    nodes, tets = {}, []
    if path.endswith(".inp"):
        mode = None
        for l in lines:
            if l.startswith("*"):
                mode = "n" if l.upper() == "*NODE" else "e" if l.upper().startswith("*ELEMENT, TYPE=C3D10") else None
            elif l and mode == "n":
                f = l.split(","); nodes[int(f[0])] = np.array([float(x) for x in f[1:4]])
            elif l and mode == "e":
                tets.append(frozenset(int(x) for x in l.split(",")[1:]))
        return nodes, set(tets)
    i = lines.index("$Nodes")
    if lines[0:2] == ["$MeshFormat", "2.2 0 8"]:
        n = int(lines[i + 1])
        for l in lines[i + 2:i + 2 + n]:
            f = l.split(); nodes[int(f[0])] = np.array([float(x) for x in f[1:4]])
        j = lines.index("$Elements")
        for l in lines[j + 2:j + 2 + int(lines[j + 1])]:
            f = l.split()
            if f[1] == "11": tets.append(frozenset(int(x) for x in f[3 + int(f[2]):]))
        return nodes, set(tets)
    blocks, k = int(lines[i + 1].split()[0]), i + 2
    for _ in range(blocks):
        c = int(lines[k].split()[3])
        for t, xyz in zip(lines[k + 1:k + 1 + c], lines[k + 1 + c:k + 1 + 2 * c]):
            nodes[int(t)] = np.array([float(x) for x in xyz.split()])
        k += 1 + 2 * c
    j = lines.index("$Elements")
    blocks, k = int(lines[j + 1].split()[0]), j + 2
    for _ in range(blocks):
        d, e, kind, c = map(int, lines[k].split())
        if kind == 11: tets += [frozenset(int(x) for x in l.split()[1:]) for l in lines[k + 1:k + 1 + c]]
        k += 1 + c
    return nodes, set(tets)
given, given_tets = nodes_and_tets("ball_ids.msh")
for out in ("ball_ids.out.msh", "ball_ids.out.inp"):
    nodes, tets = nodes_and_tets(out)
    if set(nodes) != set(given):
        sys.exit("%s: not the input's node ids" % out)
    worst = max(np.abs(nodes[t] - given[t]).max() for t in given)
    if worst > 0.5 * step * (1 + 1e-9):
        sys.exit("%s: a node %g from the input's of its id" % (out, worst))
    if tets != given_tets:
        sys.exit("%s: not the input's 10-node tetrahedra by id" % out)
import meshio
box = meshio.read("ball_ids.box.vtu")
order = list(given)  # the file's order (dicts keep it): vertex_id k is its k-th node
ids = box.point_data["vertex_id"].astype(int)
worst = max(np.abs(box.points[i] - given[order[v]]).max() for i, v in enumerate(ids))
if worst > 0.5 * step * (1 + 1e-9):
    sys.exit("ball_ids.box.vtu: vertex_id is not the input's node number (%g away)" % worst)
PY
# (A mesh of second-order prisms, whose edge nodes the stream does not
# hold: the nodes it holds keep their numbers, as ids.)
"$meshenc" layer_2.msh --exact --keep-order -q -o layer_2.dtm 2>layer_2.err || { cat layer_2.err; failed=1; }
"$meshinfo" layer_2.dtm | head -1 | grep -q "\.dtm 23\.0.*the input's node ids" || { echo "layer_2.msh: its nodes' numbers not kept as ids"; failed=1; }
"$meshdec" layer_2.dtm -q -o layer_2.out.inp || failed=1
"$py" - "$("$meshinfo" layer_2.dtm --json)" <<'PY' || failed=1
import json, sys
import meshio
import numpy as np
step = json.loads(sys.argv[1])["step"]
given = meshio.read("layer_2.msh").points
nodes, mode = {}, False
for line in open("layer_2.out.inp"):
    line = line.strip()
    if line.startswith("*"):
        mode = line.upper() == "*NODE"
    elif mode and line:
        f = line.split(",")
        nodes[int(f[0])] = np.array([float(x) for x in f[1:4]])
worst = max(np.abs(given[i - 1] - p).max() for i, p in nodes.items())
if worst > 0.5 * step * (1 + 1e-9):
    sys.exit("layer_2.out.inp: a node %g from the input's node of its number" % worst)
PY

# meshdec --box of a level in the input's numbering: the same cells as the
# box of the stream without it (a second-order one's nodes on a grid of
# half the step); a linear mesh numbered 1 to n, its nodes named by their
# numbers in the .msh (vertex_id + 1); a box that meets no cell refused,
# nothing written. A region labelled 0 (a Medit ref) is a positive
# physical tag in the .msh, said.
"$meshenc" ball2.msh --exact -q -o ball_plain.dtm 2>/dev/null || failed=1
"$meshdec" ball_plain.dtm -q --box -0.5 -0.5 -0.5 0.5 0.5 0.5 -o ball_plain.box.vtu || failed=1
"$meshenc" a41.msh --keep-order -q -o a41_order.dtm 2>/dev/null || failed=1
"$meshdec" a41_order.dtm -q --box 0.2 0.2 0.2 1.2 0.8 0.8 -o a41_order.box.msh || failed=1
"$py" - <<'PY' || failed=1
import sys
import meshio
import numpy as np
def cells(path):
    m = meshio.read(path)
    return {tuple(sorted(map(tuple, np.round(m.points[t], 6)))) for t in m.cells_dict["tetra"]}
if cells("ball_ids.box.vtu") != cells("ball_plain.box.vtu"):
    sys.exit("ball_ids.box.vtu: not the cells of the same box without the numbering")
given = meshio.read("a41.msh").points  # gmsh's tags 1..n: node k is the point k - 1
lines = open("a41_order.box.msh").read().split("\n")
i = lines.index("$Nodes")
n = int(lines[i + 2].split()[3])
tags = [int(t) for t in lines[i + 3:i + 3 + n]]
xyz = np.array([[float(x) for x in l.split()] for l in lines[i + 3 + n:i + 3 + 2 * n]])
if n == 0 or np.abs(given[np.array(tags) - 1] - xyz).max() > 1e-3:
    sys.exit("a41_order.box.msh: its node tags are not the input's numbers")
PY
if "$meshdec" a41_order.dtm -q --box 5 5 5 6 6 6 -o far.msh 2>far.err || [ -e far.msh ] ||
  ! grep -q "no tetrahedron of level 0 meets the box" far.err; then
  echo "a box meeting no cell: not refused, or a file written"; cat far.err; failed=1
fi
printf 'MeshVersionFormatted 2\nDimension 3\nVertices 5\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 1 0\nTetrahedra 2\n1 2 3 4 0\n2 3 4 5 0\nTriangles 1\n1 2 3 7\nEnd\n' >ref0.mesh
"$meshenc" ref0.mesh -q -o ref0.dtm 2>/dev/null && "$meshdec" ref0.dtm -o ref0.msh 2>ref0.err || failed=1
grep -q "region 0 as physical volume 1" ref0.err && grep -q '^3 1 "region 0"' ref0.msh ||
  { echo "ref0.msh: region 0 not written as a positive physical tag, or not said"; cat ref0.err; failed=1; }

[ $failed -eq 0 ] && echo "mesher_outputs: ok"
exit $failed
