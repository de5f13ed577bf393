// A curved non-matching interface: a steel core (cylinder, radius 15 mm, height 30 mm,
// tetrahedra of 3 mm) in an aluminium sleeve (outer radius 25 mm, tetrahedra of 4 mm), meshed
// independently (no BooleanFragments): the two facetings of the cylindrical face differ.
SetFactory("OpenCASCADE");
Cylinder(1) = {0, 0, 0, 0, 0, 0.03, 0.015};
Cylinder(2) = {0, 0, 0, 0, 0, 0.03, 0.025};
Cylinder(3) = {0, 0, 0, 0, 0, 0.03, 0.015};
BooleanDifference(4) = { Volume{2}; Delete; }{ Volume{3}; Delete; };
MeshSize{ PointsOf{ Volume{1}; } } = 0.003;
MeshSize{ PointsOf{ Volume{4}; } } = 0.004;
Physical Volume("core") = {1};
Physical Volume("sleeve") = {4};
Physical Surface("core_top") = {2};
Physical Surface("sleeve_bottom") = {6};
