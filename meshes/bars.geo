// Two bars L x 1 end to end, touching at X1 = 0 (docs/bodies.md): body 1 on [-L, 0] x [0, 1], body 2 on
// [0, L2] x [0, 1], each with its own points (Geometry.AutoCoherence = 0: the touching ends are not merged, so the
// bodies share no node). The whole boundary is label 2, traction-free (Gamma_N; no Gamma_C, no foundation), and
// may touch the other body. Element size 0.5 / refine.
// Write MSH 2.2 for FreeFEM's gmshload:  gmsh -2 -format msh22 bars.geo -o bars.msh
DefineConstant[ refine = 1, L = 10, L2 = 10 ];
size = 0.5 / refine;
Geometry.AutoCoherence = 0;
Point(1) = {-L, 0, 0, size};  Point(2) = {0, 0, 0, size};  Point(3) = {0, 1, 0, size};  Point(4) = {-L, 1, 0, size};
Point(5) = {0, 0, 0, size};   Point(6) = {L2, 0, 0, size}; Point(7) = {L2, 1, 0, size}; Point(8) = {0, 1, 0, size};
Line(1) = {1, 2};  Line(2) = {2, 3};  Line(3) = {3, 4};  Line(4) = {4, 1};
Line(5) = {5, 6};  Line(6) = {6, 7};  Line(7) = {7, 8};  Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4};  Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8};  Plane Surface(2) = {2};
Transfinite Curve{2, 4, 6, 8} = Round(1 / size) + 1;
Transfinite Curve{1, 3} = Round(L / size) + 1;
Transfinite Curve{5, 7} = Round(L2 / size) + 1;
Physical Curve("free", 2) = {1, 2, 3, 4, 5, 6, 7, 8};
Physical Surface("bar1", 1) = {1};
Physical Surface("bar2", 2) = {2};
