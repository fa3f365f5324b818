// Disk of the paper, Section 4.1: radius R = 20, centre (0, R), lowest point (0, 0).
// Gamma_C = arc s in (7pi/6, 11pi/6): 48 segments, physical label 1.
// Gamma_N = the rest of the circle:    64 segments, physical label 2.
// refine (gmsh -setnumber refine k) multiplies every segment count by k.
// Write MSH 2.2 for FreeFEM's gmshload:  gmsh -2 -format msh22 disk.geo -o disk.msh
DefineConstant[ refine = 1, lcfac = 1.142 ];
R = 20;
nC = Round(24 * refine);          // segments on each half of Gamma_C
nN = Round(32 * refine);          // segments on each half of Gamma_N
lc = lcfac * 2 * Pi * R / (2 * nC + 2 * nN);   // interior size, tuned so that refine = 1 gives the paper's 989 vertices

Point(1) = {0, R, 0, lc};                                    // centre
Point(2) = {R * Cos(7 * Pi / 6), R + R * Sin(7 * Pi / 6), 0, lc};
Point(3) = {0, 0, 0, lc};                                    // lowest point, s = 3pi/2
Point(4) = {R * Cos(11 * Pi / 6), R + R * Sin(11 * Pi / 6), 0, lc};
Point(5) = {0, 2 * R, 0, lc};                                // top, s = pi/2

Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Transfinite Curve{1, 2} = nC + 1;
Transfinite Curve{3, 4} = nN + 1;

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("contact", 1) = {1, 2};
Physical Curve("neumann", 2) = {3, 4};
Physical Surface("disk", 1) = {1};
Field[1] = MathEval;
Field[1].F = Sprintf("%g", lc);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm = 6;
