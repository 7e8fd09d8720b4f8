// Cradle of the "roller in cradle" example (units: mm).
//
// A block x in [-40, 40], y in [0, 30] with a circular seat: the block minus the
// disk of radius R = 20 centred at (0, 40) (the roller, roller.geo), in the plane
// z = 0. Its top is y = 30 for |x| >= sqrt(300) = 17.3205..., and between them the
// seat arc runs from (-sqrt(300), 30) down through (0, 20) to (sqrt(300), 30)
// (angles 210 -> 330 deg about the centre, the same as the roller's seat).
// It is the FINER part, meshed with triangles; it is meshed on its own, so its seat
// nodes do not coincide with the roller's.
//
// Element size: hSeat = 1.0 along the seat, growing smoothly (linearly in the
// distance from the seat) to hFar = 4 at distance 20 and beyond, i.e. at the base
// (which is 20 below the seat's bottom) and at the outer sides.
//
// Physical names: surface "cradle"; curves "seat", "base" (y = 0), "left" (x = -40),
// "right" (x = 40) and "top" (both flat pieces of y = 30).
//
// Regenerate cradle.msh with make_meshes.sh.

R  = 20;             // seat radius (= roller radius)
yc = 40;             // seat centre (0, yc)
W  = 40;             // half width of the block
H  = 30;             // height of the block
hSeat = 1.0;         // element size along the seat
hFar  = 4.0;         // element size at the base and the outer sides
dFar  = 20;          // distance from the seat over which the size grows
a = Sqrt(R*R - (yc - H)*(yc - H));   // = sqrt(300): half width of the seat opening

Point(1) = {-W, 0, 0, hFar};
Point(2) = { W, 0, 0, hFar};
Point(3) = { W, H, 0, hFar};
Point(4) = { a, H, 0, hSeat};        // right end of the seat (330 deg)
Point(5) = {-a, H, 0, hSeat};        // left end of the seat (210 deg)
Point(6) = {-W, H, 0, hFar};
Point(7) = { 0, yc, 0, hFar};        // seat centre (not meshed)

Line(1) = {1, 2};                    // base
Line(2) = {2, 3};                    // right
Line(3) = {3, 4};                    // top, right piece
Circle(4) = {4, 7, 5};               // seat: 330 -> 210 deg, through (0, 20)
Line(5) = {5, 6};                    // top, left piece
Line(6) = {6, 1};                    // left

Curve Loop(1) = {1, 2, 3, 4, 5, 6};
Plane Surface(1) = {1};

// Size field: hSeat within distance 0 of the seat, hFar beyond dFar, linear between.
Field[1] = Distance;
Field[1].CurvesList = {4};
Field[1].Sampling = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hSeat;
Field[2].SizeMax = hFar;
Field[2].DistMin = 0;
Field[2].DistMax = dFar;
Background Field = 2;
Mesh.MeshSizeFromPoints = 0;         // the field alone sets the size
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 0;

// Physical groups: only these are saved (Mesh.SaveAll = 0).
Physical Surface("cradle", 1) = {1};
Physical Curve("seat", 11)  = {4};
Physical Curve("base", 12)  = {1};
Physical Curve("left", 13)  = {6};
Physical Curve("right", 14) = {2};
Physical Curve("top", 15)   = {3, 5};

// Triangles (no recombination).
Mesh.Algorithm = 6;                  // Frontal-Delaunay
Mesh.RecombineAll = 0;
Mesh.MshFileVersion = 4.1;
Mesh.Binary = 0;
Mesh.SaveAll = 0;
