// Roller of the "roller in cradle" example (units: mm).
//
// A steel roller: the disk of radius R = 20 centred at (0, 40), in the plane z = 0.
// It is the COARSER part, meshed with quadrilaterals (recombined triangles).
// The cradle (cradle.geo) is meshed on its own: the two meshes do not share nodes.
//
// The circle is split into four arcs so that nodes sit at the angles 100, 140, 210
// and 330 degrees (measured from the +x axis about the centre):
//   seat  210 -> 330 deg (through the bottom point, 270 deg): sits in the cradle
//   top   100 -> 140 deg: where the load is applied. It is centred on 120 deg,
//         the direction opposite to the load (30 deg from the vertical, down and
//         to the right), so the load's line of action passes through the centre
//         and does not turn the roller.
//   free  140 -> 210 deg and 330 -> 100 deg
// Every arc gets the same element size: 36 equal edges around the whole circle,
// h = 2 pi R / 36 = 3.49 (transfinite curves: one edge per 10 deg).
//
// Regenerate roller.msh with make_meshes.sh.

R  = 20;             // roller radius
yc = 40;             // centre (0, yc)

Point(1) = {0, yc, 0, 3.5};   // centre (not meshed)
Point(2) = {R*Cos(100*Pi/180), yc + R*Sin(100*Pi/180), 0, 3.5};
Point(3) = {R*Cos(140*Pi/180), yc + R*Sin(140*Pi/180), 0, 3.5};
Point(4) = {R*Cos(210*Pi/180), yc + R*Sin(210*Pi/180), 0, 3.5};
Point(5) = {R*Cos(330*Pi/180), yc + R*Sin(330*Pi/180), 0, 3.5};

// Circle(tag) = {start, centre, end}: every arc is shorter than 180 deg.
Circle(1) = {2, 1, 3};   // 100 -> 140 deg: top
Circle(2) = {3, 1, 4};   // 140 -> 210 deg: free
Circle(3) = {4, 1, 5};   // 210 -> 330 deg: seat
Circle(4) = {5, 1, 2};   // 330 -> 100 deg: free

// Same edge length on every arc: (arc angle / 10 deg) edges, evenly spaced.
Transfinite Curve{1} = 4 + 1;     //  40 deg:  4 edges
Transfinite Curve{2} = 7 + 1;     //  70 deg:  7 edges
Transfinite Curve{3} = 12 + 1;    // 120 deg: 12 edges
Transfinite Curve{4} = 13 + 1;    // 130 deg: 13 edges

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

// Physical groups: only these are saved (Mesh.SaveAll = 0).
Physical Surface("roller", 1) = {1};
Physical Curve("seat", 11) = {3};
Physical Curve("top", 12)  = {1};
Physical Curve("free", 13) = {2, 4};

// Quadrilaterals: Delaunay triangles, recombined into quads by the blossom matching
// (all-quad). The interior size is capped at 3.4 (just under the boundary's 3.49).
// Why not Frontal-Delaunay for quads (Algorithm 8), also all-quad here: it leaves
// quads that span two boundary edges (an angle of 170 deg at the middle node,
// minSICN = sin(10 deg) = 0.17); Delaunay (5) with this cap gives minSICN about 0.66.
Mesh.Algorithm = 5;                 // Delaunay
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 1;    // blossom
Mesh.Smoothing = 10;
Mesh.MeshSizeMax = 3.4;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 1;
Mesh.MshFileVersion = 4.1;
Mesh.Binary = 0;
Mesh.SaveAll = 0;
