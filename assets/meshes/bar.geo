// The `bar` scene's steel bar (0.1 x 0.01 x 0.01 m) meshed with tetrahedra by gmsh: the example
// of README "Your own geometry". One physical volume (the body) and the six faces of the box as
// physical surfaces, which a scene's [[boundary]] names with `surface = "..."`.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.01, 0.01};
e = 1e-6;
Physical Volume("bar") = {1};
Physical Surface("x-") = Surface In BoundingBox{-e, -e, -e, e, 0.01 + e, 0.01 + e};
Physical Surface("x+") = Surface In BoundingBox{0.1 - e, -e, -e, 0.1 + e, 0.01 + e, 0.01 + e};
// element size: 2.5 mm (four across the section)
Mesh.CharacteristicLengthMax = 0.0025;
Mesh.CharacteristicLengthMin = 0.0025;
