// dimension 3
// Ball of the 3D scenes (issue 25): radius R = 20, centre (0, 0, 20), lowest point (0, 0, 0),
// a mesh vertex (the pole S, where four patches meet). Tetrahedra; the sphere is eight patches of
// gmsh's built-in kernel on the sphere: four below the circle X3 = 10 (from S to it), four above
// (from it to the top (0, 0, 40)); their curves are great-circle arcs through S or the top, and the
// circle X3 = 10 itself (radius sqrt(300)), so that the labels split exactly there.
// Gamma_C = the sphere where X3 < 10 (the 3D twin of the paper's arc):  physical label 1.
// Gamma_N = the rest of the sphere, traction free:                     physical label 2.
// Physical Volume 1 = the ball. Boundary triangles are oriented outward.
// Uniform size lc = 4 / refine. Measured (gmsh 4.8.4, -nt 1): refine 0.5: 132 vertices,
// 373 tetrahedra; refine 1: 667 vertices, 2674 tetrahedra; refine 2: 3995 vertices, 19815 tetrahedra.
// refine (gmsh -setnumber refine k) divides the element size by k.
// The first line, "// dimension 3", tells the Makefile to mesh with gmsh -3.
// Write MSH 2.2 for FreeFEM's gmshload3:  gmsh -3 -format msh22 ball.geo -o ball.msh
DefineConstant[ refine = 1 ];
R = 20;
zC = 10;                          // Gamma_C is the sphere below X3 = zC
rC = Sqrt(R^2 - (R - zC)^2);      // radius of the circle X3 = zC
lc = 4 / refine;

Point(1) = {0, 0, R, lc};                                    // centre
Point(2) = {0, 0, 0, lc};                                    // lowest point S
Point(3) = {0, 0, 2 * R, lc};                                // top
Point(4) = {rC, 0, zC, lc};                                  // the circle X3 = zC, at 0, 90, 180, 270 degrees
Point(5) = {0, rC, zC, lc};
Point(6) = {-rC, 0, zC, lc};
Point(7) = {0, -rC, zC, lc};
Point(8) = {0, 0, zC, lc};                                   // centre of that circle

// quarter k (k = 0..3): 1 + k the circle X3 = zC from point 4 + k to the next, 5 + k the arc from S
// up to point 4 + k (60 degrees), 9 + k the arc from point 4 + k up to the top (120 degrees)
For k In {0 : 3}
  Circle(1 + k) = {4 + k, 8, 4 + (k + 1) % 4};
  Circle(5 + k) = {2, 1, 4 + k};
  Circle(9 + k) = {4 + k, 1, 3};
EndFor
// patches 1..4 below X3 = zC, 5..8 above; each loop runs counter-clockwise seen from outside
For k In {0 : 3}
  Curve Loop(1 + k) = {5 + (k + 1) % 4, -(1 + k), -(5 + k)};
  Surface(1 + k) = {1 + k} In Sphere {1};
  Curve Loop(5 + k) = {1 + k, 9 + (k + 1) % 4, -(9 + k)};
  Surface(5 + k) = {5 + k} In Sphere {1};
EndFor
Surface Loop(1) = {1 : 8};
Volume(1) = {1};
Physical Surface("contact", 1) = {1 : 4};
Physical Surface("neumann", 2) = {5 : 8};
Physical Volume("ball", 1) = {1};
// the element size: field 1 (hertz.geo includes this file and sets its own graded field instead)
Field[1] = MathEval;
Field[1].F = Sprintf("%g", lc);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
