// Newton's cradle in the plane (docs/bodies.md): a row of `bodies` disks of radius 1 (default 3), centres (2k, 0),
// each touching the next at (2k + 1, 0); each disk its own points (Geometry.AutoCoherence = 0), a point at each pole
// where it touches, and its whole circle label 2 (traction-free; it may touch the next disk). Element size
// 0.1 / refine on the boundary, graded to 0.025 / refine at the touching poles.
// Write MSH 2.2 for FreeFEM's gmshload:  gmsh -2 -format msh22 [-setnumber bodies 5] cradle.geo -o cradle.msh
DefineConstant[ refine = 1, bodies = 3 ];
lc = 0.1 / refine;
lcPole = 0.025 / refine;
Geometry.AutoCoherence = 0;
For k In {0 : bodies - 1}
  xc = 2 * k;
  p = 10 * k;
  Point(p + 1) = {xc, 0, 0, lc};
  Point(p + 2) = {xc + 1, 0, 0, lcPole};
  Point(p + 3) = {xc, 1, 0, lc};
  Point(p + 4) = {xc - 1, 0, 0, lcPole};
  Point(p + 5) = {xc, -1, 0, lc};
  Circle(p + 1) = {p + 2, p + 1, p + 3};
  Circle(p + 2) = {p + 3, p + 1, p + 4};
  Circle(p + 3) = {p + 4, p + 1, p + 5};
  Circle(p + 4) = {p + 5, p + 1, p + 2};
  Curve Loop(k + 1) = {p + 1, p + 2, p + 3, p + 4};
  Plane Surface(k + 1) = {k + 1};
  Physical Surface(k + 1) = {k + 1};
EndFor
Physical Curve(2) = {};
For k In {0 : bodies - 1}
  Physical Curve(2) += {10 * k + 1, 10 * k + 2, 10 * k + 3, 10 * k + 4};
EndFor
Mesh.Algorithm = 6;
