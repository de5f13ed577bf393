// The `two-blocks` scene meshed with hexahedra by gmsh: a transfinite square of 10 x 10
// quadrangles extruded twice by 5 recombined layers (the box scene's 10 x 10 x 5 hexahedra per
// block). The extrusions share their middle surface, so the contact face is conforming.
Point(1) = {0, 0, 0};
Point(2) = {0.04, 0, 0};
Point(3) = {0.04, 0.04, 0};
Point(4) = {0, 0.04, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 11;
Transfinite Surface{1};
Recombine Surface{1};
b[] = Extrude {0, 0, 0.02} { Surface{1}; Layers{5}; Recombine; };
a[] = Extrude {0, 0, 0.02} { Surface{b[0]}; Layers{5}; Recombine; };
Physical Volume("B") = {b[1]};
Physical Volume("A") = {a[1]};
Physical Surface("bottom") = {1};
Physical Surface("top") = {a[0]};
