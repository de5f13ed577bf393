// The `two-blocks` scene (a steel block A on an aluminium block B, each 0.04 x 0.04 x 0.02 m)
// meshed with tetrahedra by gmsh. The two boxes are fragmented so that their common face is
// conforming: its nodes are shared in the file, and Lopin copies them into each body.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.04, 0.04, 0.02};
Box(2) = {0, 0, 0.02, 0.04, 0.04, 0.02};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
e = 1e-6;
Physical Volume("B") = Volume In BoundingBox{-e, -e, -e, 0.04 + e, 0.04 + e, 0.02 + e};
Physical Volume("A") = Volume In BoundingBox{-e, -e, 0.02 - e, 0.04 + e, 0.04 + e, 0.04 + e};
Physical Surface("bottom") = Surface In BoundingBox{-e, -e, -e, 0.04 + e, 0.04 + e, e};
Physical Surface("top") = Surface In BoundingBox{-e, -e, 0.04 - e, 0.04 + e, 0.04 + e, 0.04 + e};
// element size: 4 mm, the box scene's hexahedron size
Mesh.CharacteristicLengthMax = 0.004;
Mesh.CharacteristicLengthMin = 0.004;
