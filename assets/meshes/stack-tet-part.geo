// The lower part of `stack-mixed-msh`: an aluminium block 40 x 40 x 20 mm meshed on its own with
// tetrahedra of about 3 mm, its top face at z = 20 mm. Written to stack-tet-part.msh by
//   gmsh -3 -format msh41 stack-tet-part.geo -o stack-tet-part.msh
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.04, 0.04, 0.02};
Mesh.MeshSizeMin = 0.003;
Mesh.MeshSizeMax = 0.003;
Physical Volume("B") = {1};
Physical Surface("bottom") = {5};
Physical Surface("lid") = {6};
