// Solid of the Turek-Hron FSI benchmark (CSM1-3): an elastic bar of length 0.35 and height
// 0.02 attached to the fixed cylinder of centre C = (0.2, 0.2), radius 0.05. The bar is
// y in [0.19, 0.21], from the cylinder surface to x = 0.6; its left end is the cylinder arc
// between (x0, 0.19) and (x0, 0.21), x0 = 0.2 + sqrt(0.05^2 - 0.01^2) = 0.24898979485566356.
// The point A = (0.6, 0.2), middle of the right end, is a mesh vertex (the right end is split there).
// Gamma_D = the cylinder arc (clamped):                          physical label 3.
// Gamma_N = bottom, top and right end (two halves), traction free: physical label 2.
// No Gamma_C. Structured mesh: transfinite surface, alternating diagonals, triangles,
// nx segments along the bar and ny (even) across it: nx = 60, ny = 4 at refine 1.
// refine (gmsh -setnumber refine k) multiplies every segment count by k (ny stays even).
// Write MSH 2.2 for FreeFEM's gmshload:  gmsh -2 -format msh22 csm3.geo -o csm3.msh
DefineConstant[ refine = 1 ];
xc = 0.2;  yc = 0.2;  rC = 0.05;  // the cylinder
h = 0.01;                         // half the bar's height
xe = 0.6;                         // the bar's right end
x0 = xc + Sqrt(rC^2 - h^2);
nx = Round(60 * refine);          // segments along the bar
ny = 2 * Max(1, Round(2 * refine));   // segments across the bar, even so that A is a node
lc = (xe - x0) / nx;

Point(1) = {xc, yc, 0, lc};                                  // centre of the cylinder
Point(2) = {x0, yc - h, 0, lc};
Point(3) = {xe, yc - h, 0, lc};
Point(4) = {xe, yc, 0, lc};                                  // A
Point(5) = {xe, yc + h, 0, lc};
Point(6) = {x0, yc + h, 0, lc};

Line(1) = {2, 3};                 // bottom:               Gamma_N
Line(2) = {3, 4};                 // right end, lower half: Gamma_N
Line(3) = {4, 5};                 // right end, upper half: Gamma_N
Line(4) = {5, 6};                 // top:                  Gamma_N
Circle(5) = {6, 1, 2};            // cylinder arc:         Gamma_D
Transfinite Curve{1, 4} = nx + 1;
Transfinite Curve{2, 3} = ny / 2 + 1;
Transfinite Curve{5} = ny + 1;

Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Transfinite Surface{1} = {2, 3, 5, 6} Alternate;   // corners: the right end is two curves
Physical Curve("neumann", 2) = {1, 2, 3, 4};
Physical Curve("dirichlet", 3) = {5};
Physical Surface("body", 1) = {1};
Mesh.Algorithm = 6;
