// The contact patch test (Taylor and Papadopoulos 1991; docs/bodies.md): two blocks 4 x 1, one on the other, their
// meshes not matching along the interface X2 = 1 (9 and 7 segments, triangles between), each with its own points.
// Labels: the lower block's base is Gamma_C (1, on the foundation), the upper block's top Gamma_T (4, where the
// pressure acts), every other edge 2. refine (gmsh -setnumber refine k) multiplies every segment count by k.
DefineConstant[ refine = 1 ];
W = 4;
H = 1;
Geometry.AutoCoherence = 0;
For k In {0 : 1}
  p = 10 * k;
  n = (k == 0 ? 9 : 7);
  Point(p + 1) = {-W / 2, k * H, 0};
  Point(p + 2) = {W / 2, k * H, 0};
  Point(p + 3) = {W / 2, (k + 1) * H, 0};
  Point(p + 4) = {-W / 2, (k + 1) * H, 0};
  Line(p + 1) = {p + 1, p + 2};
  Line(p + 2) = {p + 2, p + 3};
  Line(p + 3) = {p + 3, p + 4};
  Line(p + 4) = {p + 4, p + 1};
  Transfinite Curve{p + 1, p + 3} = Round(n * refine) + 1;
  Transfinite Curve{p + 2, p + 4} = Round((k == 0 ? 3 : 2) * refine) + 1;
  Curve Loop(k + 1) = {p + 1, p + 2, p + 3, p + 4};
  Plane Surface(k + 1) = {k + 1};
  Physical Surface(k + 1) = {k + 1};
EndFor
Physical Curve("contact", 1) = {1};
Physical Curve("free", 2) = {2, 3, 4, 11, 12, 14};
Physical Curve("pressed", 4) = {13};
Mesh.Algorithm = 6;
