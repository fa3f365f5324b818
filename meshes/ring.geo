// Thin ring (annulus): centre (0, 10), outer radius 10, inner radius 9 (thickness 1);
// the lowest outer point is (0, 0), a mesh vertex. Element size about 0.35 at refine 1
// (about 3 elements across the thickness).
// Gamma_C = outer arc s in (7pi/6, 11pi/6), split at (0, 0): 2 x 30 segments, physical label 1.
// Gamma_N = the rest of the outer circle (2 x 60 segments) and the whole inner circle
//           (4 x 40 segments), traction free:                   physical label 2.
// refine (gmsh -setnumber refine k) multiplies every segment count by k.
// Write MSH 2.2 for FreeFEM's gmshload:  gmsh -2 -format msh22 ring.geo -o ring.msh
DefineConstant[ refine = 1 ];
R = 10;  r = 9;                   // outer and inner radius; centre (0, R)
nC = Round(30 * refine);          // segments on each half of Gamma_C (outer arc of length 10 pi/6)
nN = Round(60 * refine);          // segments on each outer Gamma_N arc (length 10 * 2pi/3)
nI = Round(40 * refine);          // segments on each quarter of the inner circle (length 9 pi/2)
lc = 2 * Pi * R / (2 * nC + 2 * nN);   // interior size, the outer boundary's

Point(1) = {0, R, 0, lc};                                    // centre
Point(2) = {R * Cos(7 * Pi / 6), R + R * Sin(7 * Pi / 6), 0, lc};
Point(3) = {0, 0, 0, lc};                                    // lowest point, s = 3pi/2
Point(4) = {R * Cos(11 * Pi / 6), R + R * Sin(11 * Pi / 6), 0, lc};
Point(5) = {0, 2 * R, 0, lc};                                // top, s = pi/2
Point(6) = {r, R, 0, lc};                                    // inner circle, s = 0, pi/2, pi, 3pi/2
Point(7) = {0, R + r, 0, lc};
Point(8) = {-r, R, 0, lc};
Point(9) = {0, R - r, 0, lc};

Circle(1) = {2, 1, 3};            // outer: Gamma_C
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};            // outer: Gamma_N
Circle(4) = {5, 1, 2};
Circle(5) = {6, 1, 7};            // inner: Gamma_N
Circle(6) = {7, 1, 8};
Circle(7) = {8, 1, 9};
Circle(8) = {9, 1, 6};
Transfinite Curve{1, 2} = nC + 1;
Transfinite Curve{3, 4} = nN + 1;
Transfinite Curve{5, 6, 7, 8} = nI + 1;

Curve Loop(1) = {1, 2, 3, 4};
Curve Loop(2) = {5, 6, 7, 8};
Plane Surface(1) = {1, 2};
Physical Curve("contact", 1) = {1, 2};
Physical Curve("neumann", 2) = {3, 4, 5, 6, 7, 8};
Physical Surface("body", 1) = {1};
Field[1] = MathEval;
Field[1].F = Sprintf("%g", lc);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm = 6;
