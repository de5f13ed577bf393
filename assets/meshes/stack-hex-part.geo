// The upper part of `stack-mixed-msh`: a steel block 40 x 40 x 20 mm meshed on its own with
// hexahedra of 4 mm (a transfinite square of 10 x 10 quadrangles extruded in 5 recombined
// layers), standing on z = 20 mm. Written to stack-hex-part.msh by
//   gmsh -3 -format msh41 stack-hex-part.geo -o stack-hex-part.msh
Point(1) = {0, 0, 0.02};
Point(2) = {0.04, 0, 0.02};
Point(3) = {0.04, 0.04, 0.02};
Point(4) = {0, 0.04, 0.02};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 11;
Transfinite Surface{1};
Recombine Surface{1};
a[] = Extrude {0, 0, 0.02} { Surface{1}; Layers{5}; Recombine; };
Physical Volume("A") = {a[1]};
Physical Surface("underside") = {1};
Physical Surface("top") = {a[0]};
