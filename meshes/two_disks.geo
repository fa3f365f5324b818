// Two of the paper's disks (disk.geo: R = 20), one above the other (docs/bodies.md): body 1 centred at (0, R), its
// lowest point at (0, 0); body 2 centred at (0, 3R + gap), gap = 2 above body 1's top. Each has its own points. Labels:
// each disk's bottom arc s in (7pi/6, 11pi/6) is Gamma_C (label 1, for a foundation), the rest of its circle label 2;
// every boundary may touch the other disk. refine (gmsh -setnumber refine k) multiplies every segment count by k.
DefineConstant[ refine = 1, lcfac = 1.142 ];
R = 20;
gap = 2;
nC = Round(24 * refine);
nN = Round(32 * refine);
lc = lcfac * 2 * Pi * R / (2 * nC + 2 * nN);
Geometry.AutoCoherence = 0;
For k In {0 : 1}
  yc = R + k * (2 * R + gap);
  p = 10 * k;
  Point(p + 1) = {0, yc, 0, lc};
  Point(p + 2) = {R * Cos(7 * Pi / 6), yc + R * Sin(7 * Pi / 6), 0, lc};
  Point(p + 3) = {0, yc - R, 0, lc};
  Point(p + 4) = {R * Cos(11 * Pi / 6), yc + R * Sin(11 * Pi / 6), 0, lc};
  Point(p + 5) = {0, yc + R, 0, lc};
  Circle(p + 1) = {p + 2, p + 1, p + 3};
  Circle(p + 2) = {p + 3, p + 1, p + 4};
  Circle(p + 3) = {p + 4, p + 1, p + 5};
  Circle(p + 4) = {p + 5, p + 1, p + 2};
  Transfinite Curve{p + 1, p + 2} = nC + 1;
  Transfinite Curve{p + 3, p + 4} = nN + 1;
  Curve Loop(k + 1) = {p + 1, p + 2, p + 3, p + 4};
  Plane Surface(k + 1) = {k + 1};
EndFor
Physical Curve("contact", 1) = {1, 2, 11, 12};
Physical Curve("free", 2) = {3, 4, 13, 14};
Physical Surface("lower", 1) = {1};
Physical Surface("upper", 2) = {2};
Field[1] = MathEval;
Field[1].F = Sprintf("%g", lc);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.Algorithm = 6;
