// Cantilever beam [0, 10] x [1, 2]: length 10, height 1; its bottom side lies 1 above
// the foundation X2 = 0. Structured mesh: transfinite surface, alternating diagonals,
// 40 x 4 segments at refine 1 (element size 0.25), triangles only.
// Gamma_D = left end x = 0 (clamped):                        physical label 3.
// Gamma_C = right half of the bottom, [5, 10] x {1}:          physical label 1.
// Gamma_N = left half of the bottom, [0, 5] x {1}, top side
//           y = 2 and right end x = 10 (traction free):        physical label 2.
// refine (gmsh -setnumber refine k) multiplies every segment count by k.
// Write MSH 2.2 for FreeFEM's gmshload:  gmsh -2 -format msh22 cantilever.geo -o cantilever.msh
DefineConstant[ refine = 1 ];
L = 10;  H = 1;  y0 = 1;          // length, height, height of the bottom side
nL = Round(20 * refine);          // segments on each half of the bottom (the top has 2 nL)
nH = Round(4 * refine);           // segments across the height
lc = L / (2 * nL);

Point(1) = {0,     y0,     0, lc};
Point(2) = {L / 2, y0,     0, lc};                           // start of Gamma_C
Point(3) = {L,     y0,     0, lc};
Point(4) = {L,     y0 + H, 0, lc};
Point(5) = {0,     y0 + H, 0, lc};

Line(1) = {1, 2};                 // bottom, left half:  Gamma_N
Line(2) = {2, 3};                 // bottom, right half: Gamma_C
Line(3) = {3, 4};                 // right end:          Gamma_N
Line(4) = {4, 5};                 // top:                Gamma_N
Line(5) = {5, 1};                 // left end:           Gamma_D
Transfinite Curve{1, 2} = nL + 1;
Transfinite Curve{4} = 2 * nL + 1;
Transfinite Curve{3, 5} = nH + 1;

Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Transfinite Surface{1} = {1, 3, 4, 5} Alternate;   // corners: the bottom is two curves
Physical Curve("contact", 1) = {2};
Physical Curve("neumann", 2) = {1, 3, 4};
Physical Curve("dirichlet", 3) = {5};
Physical Surface("body", 1) = {1};
Mesh.Algorithm = 6;
