// A two-material part for the golden 9.0 stream (data/README.md): an
// aluminium block with a steel pin through it, meshed by gmsh 4.8.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 10, 6, 4};
Cylinder(2) = {5, 3, -1, 0, 0, 6, 1.5};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
// The pin's ends outside the block are not saved.
Physical Volume("aluminium", 1) = {2};
Physical Volume("steel", 2) = {3};
Mesh.CharacteristicLengthMax = 0.7;
