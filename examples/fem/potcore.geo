// Pot-core electromagnet with an armature plate: an axisymmetric (r, z) cross-section in mm.
// x = r, y = z. Regenerate the mesh with:  gmsh -2 -format msh22 potcore.geo -o potcore.msh
// Physical groups: 1 steel (pot + plate), 2 coil, 3 air; curve 10 = outer circle (open boundary),
// curve 11 = symmetry axis.
lc_gap = 0.5;   // in the 1 mm gap between pot and plate
lc_steel = 1.5;
lc_far = 8.0;

Point(1) = {0, -20, 0, lc_steel};
Point(2) = {30, -20, 0, lc_steel};
Point(3) = {30, 15, 0, lc_gap};
Point(4) = {25, 15, 0, lc_gap};
Point(5) = {25, -15, 0, lc_steel};
Point(6) = {10, -15, 0, lc_steel};
Point(7) = {10, 15, 0, lc_gap};
Point(8) = {0, 15, 0, lc_gap};
Point(9) = {0, 16, 0, lc_gap};
Point(10) = {30, 16, 0, lc_gap};
Point(11) = {30, 21, 0, lc_steel};
Point(12) = {0, 21, 0, lc_steel};
Point(13) = {12, -13, 0, lc_steel};
Point(14) = {23, -13, 0, lc_steel};
Point(15) = {23, 13, 0, lc_steel};
Point(16) = {12, 13, 0, lc_steel};
Point(20) = {0, 0, 0, lc_far};
Point(21) = {0, -80, 0, lc_far};
Point(22) = {80, 0, 0, lc_far};
Point(23) = {0, 80, 0, lc_far};

// Pot outline.
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 6};
Line(6) = {6, 7};
Line(7) = {7, 8};
Line(8) = {8, 1};
// Plate.
Line(9) = {9, 10};
Line(10) = {10, 11};
Line(11) = {11, 12};
Line(12) = {12, 9};
// Coil.
Line(13) = {13, 14};
Line(14) = {14, 15};
Line(15) = {15, 16};
Line(16) = {16, 13};
// Outer circle and axis pieces in the air.
Circle(17) = {21, 20, 22};
Circle(18) = {22, 20, 23};
Line(19) = {23, 12};
Line(20) = {9, 8};
Line(21) = {1, 21};

Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
Plane Surface(1) = {1};
Curve Loop(2) = {9, 10, 11, 12};
Plane Surface(2) = {2};
Curve Loop(3) = {13, 14, 15, 16};
Plane Surface(3) = {3};
Curve Loop(4) = {17, 18, 19, -11, -10, -9, 20, -7, -6, -5, -4, -3, -2, -1, 21};
Plane Surface(4) = {4, 3};

Physical Surface(1) = {1, 2};
Physical Surface(2) = {3};
Physical Surface(3) = {4};
Physical Curve(10) = {17, 18};
Physical Curve(11) = {8, 12, 19, 20, 21};
