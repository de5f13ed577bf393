// The `two-blocks` geometry (a steel block A on an aluminium block B, each 0.04 x 0.04 x 0.02 m)
// meshed with tetrahedra by gmsh, its contact face cut in two physical surfaces: `centre` (the
// 0.02 x 0.02 m square in the middle) and `rim` (the rest), so that a scene's zones can give
// each its own friction. The two boxes and the square are fragmented together: the common face
// is conforming and made of the two surfaces.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.04, 0.04, 0.02};
Box(2) = {0, 0, 0.02, 0.04, 0.04, 0.02};
Rectangle(100) = {0.01, 0.01, 0.02, 0.02, 0.02};
BooleanFragments{ Volume{1}; Volume{2}; Delete; }{ Surface{100}; Delete; }
e = 1e-6;
Physical Volume("B") = Volume In BoundingBox{-e, -e, -e, 0.04 + e, 0.04 + e, 0.02 + e};
Physical Volume("A") = Volume In BoundingBox{-e, -e, 0.02 - e, 0.04 + e, 0.04 + e, 0.04 + e};
Physical Surface("bottom") = Surface In BoundingBox{-e, -e, -e, 0.04 + e, 0.04 + e, e};
Physical Surface("top") = Surface In BoundingBox{-e, -e, 0.04 - e, 0.04 + e, 0.04 + e, 0.04 + e};
middle[] = Surface In BoundingBox{-e, -e, 0.02 - e, 0.04 + e, 0.04 + e, 0.02 + e};
centre[] = Surface In BoundingBox{0.01 - e, 0.01 - e, 0.02 - e, 0.03 + e, 0.03 + e, 0.02 + e};
rim[] = middle[];
rim[] -= centre[];
Physical Surface("centre") = centre[];
Physical Surface("rim") = rim[];
// element size: 4 mm, the box scene's hexahedron size
Mesh.CharacteristicLengthMax = 0.004;
Mesh.CharacteristicLengthMin = 0.004;
