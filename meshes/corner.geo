// Rounded square: side 10, corner radius 1.5, rotated by 30 degrees counter-clockwise
// about its centre, and translated so that its lowest point is (0, 0), a mesh vertex.
// Centre of the square: (cx, cy) = (3.5 (cos 30 - sin 30), 1.5 + 3.5 (sin 30 + cos 30))
//                                 = (1.75 (sqrt 3 - 1), 1.5 + 1.75 (sqrt 3 + 1))
//                                 = (1.28108891324554, 6.28108891324554).
// Rotation: 30 degrees counter-clockwise about (cx, cy).
// Corners k = 0, 1, 2, 3 (upper right, upper left, lower left, lower right before the
// rotation): arc centres (cx, cy) + 3.5 sqrt(2) (cos, sin)(30 + 45 + 90 k degrees), each
// arc spanning outward normals 30 + 90 k to 120 + 90 k degrees. The lowest point is on
// the lower-left corner's arc (k = 2, centre (0, 1.5)), where the outward normal points
// straight down (270 degrees); that arc is split there.
// Gamma_C = the whole boundary (any part may touch after it rotates): physical label 1.
//   sides: 4 x 14 segments; arcs 0, 1, 3: 5 segments; arc 2: 3 + 2 segments.
// No Gamma_N, no Gamma_D.
// refine (gmsh -setnumber refine k) multiplies every segment count by k.
// Write MSH 2.2 for FreeFEM's gmshload:  gmsh -2 -format msh22 corner.geo -o corner.msh
DefineConstant[ refine = 1 ];
S = 10;  rc = 1.5;  th = Pi / 6;  // side, corner radius, rotation (30 degrees)
a = S / 2 - rc;                   // centre of the square to an arc centre, along each axis
cx = a * (Cos(th) - Sin(th));
cy = rc + a * (Sin(th) + Cos(th));
d = a * Sqrt(2);
nS = Round(14 * refine);          // segments on each straight side (length 7)
nA = Round(5 * refine);           // segments on each corner arc (length 1.5 pi/2)
nA1 = Round(3 * refine);          // lower-left arc: normals 210 to 270 degrees
nA2 = Round(2 * refine);          //                 normals 270 to 300 degrees
lc = (S - 2 * rc) / nS;           // interior size, the sides'

// corner k: arc centre 10 + k, arc start 20 + k (normal 30 + 90 k), arc end 30 + k (normal 120 + 90 k)
For k In {0 : 3}
  If (k == 2)
    Point(10 + k) = {0, rc, 0, lc};                          // exactly above the lowest point
  Else
    Point(10 + k) = {cx + d * Cos(th + Pi / 4 + k * Pi / 2), cy + d * Sin(th + Pi / 4 + k * Pi / 2), 0, lc};
  EndIf
  xk = Point{10 + k};
  Point(20 + k) = {xk[0] + rc * Cos(th + k * Pi / 2), xk[1] + rc * Sin(th + k * Pi / 2), 0, lc};
  Point(30 + k) = {xk[0] + rc * Cos(th + (k + 1) * Pi / 2), xk[1] + rc * Sin(th + (k + 1) * Pi / 2), 0, lc};
EndFor
Point(40) = {0, 0, 0, lc};                                   // lowest point, normal 270 degrees

Circle(1) = {20, 10, 30};         // corner 0
Line(2) = {30, 21};
Circle(3) = {21, 11, 31};         // corner 1
Line(4) = {31, 22};
Circle(5) = {22, 12, 40};         // corner 2, up to the lowest point
Circle(6) = {40, 12, 32};         // corner 2, from the lowest point
Line(7) = {32, 23};
Circle(8) = {23, 13, 33};         // corner 3
Line(9) = {33, 20};
Transfinite Curve{2, 4, 7, 9} = nS + 1;
Transfinite Curve{1, 3, 8} = nA + 1;
Transfinite Curve{5} = nA1 + 1;
Transfinite Curve{6} = nA2 + 1;

Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8, 9};
Plane Surface(1) = {1};
Physical Curve("contact", 1) = {1, 2, 3, 4, 5, 6, 7, 8, 9};
Physical Surface("body", 1) = {1};
Field[1] = MathEval;
Field[1].F = Sprintf("%g", lc);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm = 6;
