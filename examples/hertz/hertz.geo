// Hertz contact of a cylinder on a block (units: mm), plane strain.
//
// The cylinder (radius R = 10, centre (0, R)) is modelled by its lower half: the
// half disk below its horizontal diameter y = R, which carries the load. It touches
// the block (x in [-W, W], y in [-H, 0]) at the origin. With a contact half-width
// a of about 1 (hertz.toml: P' = 4000 N/mm), both bodies are many a in size, as the
// half-plane theory of Hertz assumes.
//
//            load (uniform on y = R, "load")
//     ______________________________
//     \              |             /      cylinder: two quarter disks sharing the
//      \   cylinder  | axis       /       axis x = 0 (so that nodes lie on it, and
//       '-._         |        _.-'        the mesh is nearly symmetric); its arc is "arc"
//   ________'-.______|____.-'________  y = 0: the block's top ("face")
//  |                                 |
//  |              block              |    block: "sides" x = +-W, "base" y = -H
//  |_________________________________|
//
// Both parts are in this one file, as the physical surfaces "cylinder" and "block";
// they are meshed independently (their nodes on the contact do not coincide, apart
// from the first point of contact, the origin, which both have as a vertex).
//
// Element size: h = a0 / n (a0 = 1, n = the number of elements per contact
// half-width; default 10, set with `gmsh -setnumber n 20 ...`) within a distance
// of 1.6 a0 from the origin, growing at 0.3 per unit distance beyond, up to hFar.
// The block is meshed 1.25 times coarser than the cylinder (the host is the
// coarser part).
//
// Regenerate with make_meshes.sh.

If (!Exists(n))
  n = 10;
EndIf
R = 10;              // cylinder radius
W = 20;              // block half width
H = 20;              // block height
a0 = 1;              // the contact half-width the mesh is designed for
h = a0 / n;          // element size in the contact zone (cylinder)
hFar = 2.5;          // element size far from the contact

// Cylinder.
Point(1) = {0, 0, 0, h};        // bottom of the cylinder: first point of contact
Point(2) = {R, R, 0, hFar};     // right end of the diameter
Point(3) = {0, R, 0, hFar};     // centre
Point(4) = {-R, R, 0, hFar};    // left end of the diameter
Circle(1) = {4, 3, 1};          // arc, left quarter
Circle(2) = {1, 3, 2};          // arc, right quarter
Line(3) = {2, 3};               // load, right half
Line(4) = {3, 4};               // load, left half
Line(5) = {1, 3};               // axis
Curve Loop(1) = {1, 5, 4};
Plane Surface(1) = {1};         // left quarter disk
Curve Loop(2) = {2, 3, -5};
Plane Surface(2) = {2};         // right quarter disk

// Block.
Point(11) = {-W, -H, 0, hFar};
Point(12) = { W, -H, 0, hFar};
Point(13) = { W,  0, 0, hFar};
Point(14) = {-W,  0, 0, hFar};
Point(15) = { 0,  0, 0, h};     // the block's own vertex at the origin
Line(11) = {11, 12};            // base
Line(12) = {12, 13};            // right side
Line(13) = {13, 15};            // face, right half
Line(14) = {15, 14};            // face, left half
Line(15) = {14, 11};            // left side
Curve Loop(11) = {11, 12, 13, 14, 15};
Plane Surface(11) = {11};

// Size fields: h (cylinder) or 1.25 h (block) within 1.6 a0 of the origin,
// growing by 0.3 per unit distance beyond, at most hFar.
Field[1] = Distance;
Field[1].PointsList = {1};
Field[2] = MathEval;
Field[2].F = Sprintf("Min(%g, %g + 0.3 * Max(0, F1 - %g))", hFar, h, 1.6 * a0);
Field[3] = MathEval;
Field[3].F = Sprintf("Min(%g, %g + 0.3 * Max(0, F1 - %g))", hFar, 1.25 * h, 1.6 * a0);
Field[4] = Restrict;
Field[4].InField = 2;
Field[4].SurfacesList = {1, 2};
Field[4].CurvesList = {1, 2, 3, 4, 5};
Field[5] = Restrict;
Field[5].InField = 3;
Field[5].SurfacesList = {11};
Field[5].CurvesList = {11, 12, 13, 14, 15};
Field[6] = Min;
Field[6].FieldsList = {4, 5};
Background Field = 6;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm = 6;             // Frontal-Delaunay

Physical Surface("cylinder", 1) = {1, 2};
Physical Surface("block", 2) = {11};
Physical Curve("arc", 11) = {1, 2};
Physical Curve("load", 12) = {3, 4};
Physical Curve("face", 21) = {13, 14};
Physical Curve("base", 22) = {11};
Physical Curve("sides", 23) = {12, 15};
