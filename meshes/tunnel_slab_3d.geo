// 3D slab of the 2D tunnel geometry (tunnel axis z), thickness H, all
// hexahedra. Physical ids: 1 far field (r = R), 3 tunnel wall (r = a),
// 4 the faces z = 0 and z = H (rollers u_z = 0: plane-strain slab).
// Generate: gmsh -3 -format msh2 tunnel_slab_3d.geo -o tunnel_slab_3d.msh
a  = 1.0;
R  = 30.0;
H  = 1.0;
nz = 2;
nt = 8;
nr = 17;
q  = (R / a)^(1.0 / nr);

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

// Extrude returns: [0] top, [1] volume, [2..] lateral surfaces in the order
// of the curve loop: radial line, outer arc, radial line, inner arc.
For k In {1:4}
  ex[] = Extrude {0, 0, H} { Surface{k}; Layers{nz}; Recombine; };
  top[] += ex[0];
  vol[] += ex[1];
  outer[] += ex[3];
  inner[] += ex[5];
EndFor
Physical Surface(1) = {outer[]};
Physical Surface(3) = {inner[]};
Physical Surface(4) = {top[], 1, 2, 3, 4};
Physical Volume(1) = {vol[]};
