// 2D circular tunnel (radius a) in a circular domain of radius R = 30a,
// all quadrilaterals, graded geometrically from the wall to the far field.
// Physical ids (docs/architecture.md, "The continuum"): 1 far field, 3 tunnel wall.
// Generate: gmsh -2 -format msh2 tunnel_2d.geo -o tunnel_2d.msh
a  = 1.0;
R  = 30.0;
nt = 8;    // cells per quarter circle (32 around the wall)
nr = 17;   // radial cells; nr ~ 4 nt ln(R/a) / (2 pi) keeps cells square
q  = (R / a)^(1.0 / nr);  // geometric growth of the radial size

Point(1) = {0, 0, 0};
Point(2) = {a, 0, 0};  Point(3) = {0, a, 0};  Point(4) = {-a, 0, 0};  Point(5) = {0, -a, 0};
Point(6) = {R, 0, 0};  Point(7) = {0, R, 0};  Point(8) = {-R, 0, 0};  Point(9) = {0, -R, 0};
Circle(1) = {2, 1, 3}; Circle(2) = {3, 1, 4}; Circle(3) = {4, 1, 5}; Circle(4) = {5, 1, 2};
Circle(5) = {6, 1, 7}; Circle(6) = {7, 1, 8}; Circle(7) = {8, 1, 9}; Circle(8) = {9, 1, 6};
Line(9) = {2, 6}; Line(10) = {3, 7}; Line(11) = {4, 8}; Line(12) = {5, 9};
Curve Loop(1) = {9, 5, -10, -1};  Plane Surface(1) = {1};
Curve Loop(2) = {10, 6, -11, -2}; Plane Surface(2) = {2};
Curve Loop(3) = {11, 7, -12, -3}; Plane Surface(3) = {3};
Curve Loop(4) = {12, 8, -9, -4};  Plane Surface(4) = {4};
Transfinite Curve{1:8} = nt + 1;
Transfinite Curve{9:12} = nr + 1 Using Progression q;
Transfinite Surface{1:4};
Recombine Surface{1:4};

Physical Curve(1) = {5:8};
Physical Curve(3) = {1:4};
Physical Surface(1) = {1:4};
