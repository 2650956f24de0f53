// 3D tunnel (radius a, axis z) with a face at z = 0 for staged advance:
// excavated for z < 0, unexcavated rock (core r < a) for z > 0. Domain
// r <= R = 20a, -L <= z <= L, all hexahedra (O-grid core), graded towards
// the face and the wall. Physical ids: 1 far field (r = R), 3 tunnel wall
// and face (excavated boundary), 4 end planes z = +-L (rollers u_z = 0).
// Generate: gmsh -3 -format msh2 tunnel_face_3d.geo -o tunnel_face_3d.msh
a  = 1.0;
R  = 20.0;
nt = 6;     // cells per quarter circle (24 around)
nr = 11;    // radial cells in the rock ring a..R
nc = 3;     // radial cells between the core square and the wall
s  = 0.5 * a;  // half width of the core square
q  = (R / a)^(1.0 / nr);
nz = 12;    // element layers on each side of the face, growing by gz
gz = 1.25;
h0 = 0.25 * a;

Point(1) = {0, 0, 0};
Point(2) = {a, 0, 0};  Point(3) = {0, a, 0};  Point(4) = {-a, 0, 0};  Point(5) = {0, -a, 0};
Point(6) = {R, 0, 0};  Point(7) = {0, R, 0};  Point(8) = {-R, 0, 0};  Point(9) = {0, -R, 0};
// Core square corners, on the diagonals; O-grid blocks connect them to the
// wall points at 45 degrees.
c = a / Sqrt(2);
Point(10) = {s, 0, 0}; Point(11) = {0, s, 0}; Point(12) = {-s, 0, 0}; Point(13) = {0, -s, 0};
Point(14) = {c, c, 0}; Point(15) = {-c, c, 0}; Point(16) = {-c, -c, 0}; Point(17) = {c, -c, 0};
Point(18) = {s, s, 0}; Point(19) = {-s, s, 0}; Point(20) = {-s, -s, 0}; Point(21) = {s, -s, 0};

// Wall circle split at 0, 45, 90, ... degrees.
Circle(1) = {2, 1, 14};  Circle(2) = {14, 1, 3};  Circle(3) = {3, 1, 15};  Circle(4) = {15, 1, 4};
Circle(5) = {4, 1, 16};  Circle(6) = {16, 1, 5};  Circle(7) = {5, 1, 17};  Circle(8) = {17, 1, 2};
// Outer circle: quarter arcs split at 45 degrees too, so the ring sectors
// match the wall arcs.
Point(22) = {R / Sqrt(2), R / Sqrt(2), 0};  Point(23) = {-R / Sqrt(2), R / Sqrt(2), 0};
Point(24) = {-R / Sqrt(2), -R / Sqrt(2), 0}; Point(25) = {R / Sqrt(2), -R / Sqrt(2), 0};
Circle(11) = {6, 1, 22};  Circle(12) = {22, 1, 7};  Circle(13) = {7, 1, 23};  Circle(14) = {23, 1, 8};
Circle(15) = {8, 1, 24};  Circle(16) = {24, 1, 9};  Circle(17) = {9, 1, 25};  Circle(18) = {25, 1, 6};
// Radial lines of the ring.
Line(21) = {2, 6};   Line(22) = {14, 22}; Line(23) = {3, 7};   Line(24) = {15, 23};
Line(25) = {4, 8};   Line(26) = {16, 24}; Line(27) = {5, 9};   Line(28) = {17, 25};
// Core: square edges and spokes to the wall.
Line(31) = {10, 18}; Line(32) = {18, 11}; Line(33) = {11, 19}; Line(34) = {19, 12};
Line(35) = {12, 20}; Line(36) = {20, 13}; Line(37) = {13, 21}; Line(38) = {21, 10};
Line(41) = {10, 2};  Line(42) = {18, 14}; Line(43) = {11, 3};  Line(44) = {19, 15};
Line(45) = {12, 4};  Line(46) = {20, 16}; Line(47) = {13, 5};  Line(48) = {21, 17};
// Core square in four quarters through the centre.
Line(51) = {1, 10}; Line(52) = {1, 11}; Line(53) = {1, 12}; Line(54) = {1, 13};

// Ring sectors (8 surfaces).
ring[] = {};
For k In {0:7}
  Curve Loop(100 + k) = {21 + k, 11 + k, -(21 + (k + 1) % 8), -(1 + k)};
  Plane Surface(100 + k) = {100 + k};
  ring[] += 100 + k;
EndFor
// Core spokes blocks (8 surfaces between the square boundary and the wall).
core[] = {};
For k In {0:7}
  Curve Loop(200 + k) = {31 + k, 41 + (k + 1) % 8, -(1 + k), -(41 + k)};
  Plane Surface(200 + k) = {200 + k};
  core[] += 200 + k;
EndFor
// Core square quarters.
Curve Loop(300) = {51, 31, 32, -52}; Plane Surface(300) = {300};
Curve Loop(301) = {52, 33, 34, -53}; Plane Surface(301) = {301};
Curve Loop(302) = {53, 35, 36, -54}; Plane Surface(302) = {302};
Curve Loop(303) = {54, 37, 38, -51}; Plane Surface(303) = {303};
core[] += {300:303};

nh = nt / 2;  // cells per 45-degree arc
Transfinite Curve{1:8, 11:18, 31:38} = nh + 1;
Transfinite Curve{51:54} = nh + 1;
Transfinite Curve{21:28} = nr + 1 Using Progression q;
Transfinite Curve{41:48} = nc + 1;
Transfinite Surface{ring[], core[]};
Recombine Surface{ring[], core[]};

// Graded layers: heights h0 gz^i, cumulative, normalized.
L = h0 * (gz^nz - 1) / (gz - 1);
n[] = {}; t[] = {};
z = 0;
For i In {0:nz-1}
  z += h0 * gz^i;
  n[] += 1;
  t[] += z / L;
EndFor

// Excavated part z in [-L, 0]: rock ring only. Lateral order: radial line,
// outer arc, radial line, wall arc.
wall[] = {}; far[] = {}; ends[] = {}; vol[] = {};
For k In {0:7}
  ex[] = Extrude {0, 0, -L} { Surface{100 + k}; Layers{n[], t[]}; Recombine; };
  ends[] += ex[0]; vol[] += ex[1]; far[] += ex[3]; wall[] += ex[5];
EndFor
// Unexcavated part z in [0, L]: ring and core.
For k In {0:7}
  ex[] = Extrude {0, 0, L} { Surface{100 + k}; Layers{n[], t[]}; Recombine; };
  ends[] += ex[0]; vol[] += ex[1]; far[] += ex[3];
EndFor
For k In {0:#core[]-1}
  ex[] = Extrude {0, 0, L} { Surface{core[k]}; Layers{n[], t[]}; Recombine; };
  ends[] += ex[0]; vol[] += ex[1];
EndFor

Physical Surface(1) = {far[]};
Physical Surface(3) = {wall[], core[]};  // wall (z < 0) and face (z = 0)
Physical Surface(4) = {ends[]};
Physical Volume(1) = {vol[]};
