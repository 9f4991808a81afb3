// A two-material part for the golden 9.0 stream (data/README.md): an
// aluminium block with a steel pin through it, two tagged surfaces,
// meshed by gmsh 4.8 (gmsh -3 two_materials.geo -format msh41).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 10, 6, 4};
Cylinder(2) = {5, 3, -1, 0, 0, 6, 1.5};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
// Volumes: 1 the block, 2 the pin inside it, 3 and 4 its ends outside,
// which are not saved.
Physical Volume("aluminium", 1) = {1};
Physical Volume("steel", 2) = {2};
// Tagged faces, where a simulation sets its boundary conditions: the base
// (the block's and the pin's, z = 0) and the loaded end (x = 10).
Physical Surface("base", 3) = Surface In BoundingBox{-0.1, -0.1, -0.1, 10.1, 6.1, 0.1};
Physical Surface("load", 4) = Surface In BoundingBox{9.9, -0.1, -0.1, 10.1, 6.1, 4.1};
Mesh.CharacteristicLengthMax = 0.7;
