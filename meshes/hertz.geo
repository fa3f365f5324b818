// dimension 3
// The ball of ball.geo (R = 20, centre (0, 0, 20), the same patches and labels: Gamma_C = the sphere
// below X3 = 10, label 1; the rest label 2; the ball, volume 1), graded towards its lowest point
// (0, 0, 0), a vertex, for Hertz's impact (scene hertz, make hertz, docs/hertz.md). Element size at
// distance d from (0, 0, 0):
//   h(d) = min(far_size, pole_size + growth * max(0, d - pole_radius)) / refine
// pole_size within pole_radius of the pole, growing by growth per unit length up to far_size.
// Options (gmsh -setnumber NAME VALUE): pole_size (0.15), far_size (3), pole_radius (1), growth (0.13),
// refine (1). The contact radius of Hertz's impact, a* = sqrt(R delta*), is 4.16, 1.66 and 0.661 at
// v0/c* = 1e-2, 1e-3 and 1e-4 (lambda = mu = 30, rho = 1; postprocess/hertz.py); h below is the mean
// length of the Gamma_C triangles' edges within a* of the pole.
// Measured (gmsh 4.8.4, -nt 1), vertices, tetrahedra, a*/h at v0/c* = 1e-2, 1e-3, 1e-4:
//   refine 1 (meshes/hertz.msh):          6979 vertices, 36985 tetrahedra, a*/h = 15.9, 10.1, 4.6
//   refine 0.5:                           1119 vertices,  5120 tetrahedra, a*/h =  8.4,  5.2, 2.5
//   refine 0.3 (meshes/hertz_coarse.msh):  366 vertices,  1367 tetrahedra, a*/h =  5.4,  3.3, 1.5
// The first line, "// dimension 3", tells the Makefile to mesh with gmsh -3.
// Write MSH 2.2 for FreeFEM's gmshload3:  gmsh -3 -format msh22 hertz.geo -o hertz.msh
DefineConstant[ refine = 1, pole_size = 0.15, far_size = 3, pole_radius = 1, growth = 0.13 ];
Include "ball.geo";

Field[2] = Distance;
Field[2].PointsList = {2};                                   // the lowest point (ball.geo's point 2)
Field[3] = MathEval;
Field[3].F = Sprintf("Min(%g, %g + %g * Max(0, F2 - %g)) / %g", far_size, pole_size, growth, pole_radius, refine);
Background Field = 3;
