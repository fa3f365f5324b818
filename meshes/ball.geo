// a ball of radius 20 centred at (0, 0, 20); Gamma_C (label 1) its surface below X3 = 10, label 2 the rest
SetFactory("OpenCASCADE");
refine = DefineNumber[1, Name "refine"];
Sphere(1) = {0, 0, 20, 20};
Box(2) = {-25, -25, -1, 50, 50, 11};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Recursive Delete { Volume{3}; }
lower() = Surface In BoundingBox{-21, -21, -1, 21, 21, 10.001};
disk() = Surface In BoundingBox{-21, -21, 9.999, 21, 21, 10.001};
lower() -= disk();
upper() = Surface In BoundingBox{-21, -21, 9.999, 21, 21, 41};
upper() -= disk();
Physical Surface(1) = {lower()};
Physical Surface(2) = {upper()};
Physical Volume(1) = {1, 2};
Mesh.CharacteristicLengthMax = 8 / refine;
