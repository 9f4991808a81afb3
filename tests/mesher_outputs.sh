#!/usr/bin/env bash
# tests/mesher_outputs.sh MESHENC -- meshes as gmsh and Netgen write them,
# made here by Debian's gmsh and python3-netgen, read by meshenc: a
# two-material gmsh part in .msh 2.2 and 4.1, ASCII and binary, gives one
# stream from all four, and meshenc names what the stream does not hold (its
# physical tags and names, its boundary triangles); a Netgen CSG part
# exported as gmsh 2.0 ("2.000000") is read.
set -euo pipefail
meshenc=$1
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
  for kind in a b; do "$meshenc" $kind$v.msh -o $kind$v.dtm >$kind$v.out; done
done
for f in b22 a41 b41; do
  cmp -s a22.dtm $f.dtm || { echo "$f.msh: a stream other than a22.msh's"; failed=1; }
done
for f in a22 b22; do
  grep -q "left out (the stream does not hold it): the tetrahedra's physical tags (1, 2)" $f.out ||
    { echo "$f.msh: physical tags not named"; cat $f.out; failed=1; }
done
for f in a22 b22 a41 b41; do
  grep -q 'PhysicalNames (2:3 "base", 3:1 "aluminium", 3:2 "steel")' $f.out &&
    grep -q "elements other than tetrahedra ([0-9]* triangles" $f.out ||
    { echo "$f.msh: physical names or triangles not named"; cat $f.out; failed=1; }
done
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
[ $failed -eq 0 ] && echo "mesher_outputs: ok"
exit $failed
