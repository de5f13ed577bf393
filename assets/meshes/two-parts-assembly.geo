// An assembly of two parts meshed independently, with no BooleanFragments: a steel block
// 40 x 40 x 20 mm (tetrahedra of 4 mm) on an aluminium block of the same footprint (tetrahedra
// of 3 mm). The parts touch on z = 20 mm but share no surface, so their contact faces do not
// match: Lopin couples them as a non-matching interface.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0.02, 0.04, 0.04, 0.02};
Box(2) = {0, 0, 0, 0.04, 0.04, 0.02};
MeshSize{ PointsOf{ Volume{1}; } } = 0.004;
MeshSize{ PointsOf{ Volume{2}; } } = 0.003;
Physical Volume("A") = {1};
Physical Volume("B") = {2};
Physical Surface("top") = {6};
Physical Surface("bottom") = {11};
