// A steel sphere pressed on an aluminium block (Hertz), a quarter model (units: mm).
//
// The sphere (radius R = 10, centre (0, 0, R)) is modelled by the quarter of its
// lower half with x ≥ 0, y ≥ 0: it touches the block's top z = 0 at the origin.
// The block is [0, W] × [0, W] × [−H, 0]. The planes x = 0 and y = 0 are planes of
// symmetry of the full model (sphere_on_block.toml holds them as rollers).
//
//          z
//          |  ____  sphere's flat top z = R ("ball_top": the load)
//          | |    `-.
//          | | ball   \   the curved face ("ball_face": the coupling nodes)
//          |  `-._     |
//   _______|______`-.__/__________ z = 0  block's top ("block_top")
//  |       |                      |
//  |       |     block            |   bottom z = −H ("block_bottom")
//  |_______|______________________|
//          x = 0 ("symmetry_x"; y = 0: "symmetry_y")
//
// Both parts are in one file, as the physical volumes "ball" and "block", meshed
// independently in tetrahedra (their nodes on the contact do not coincide apart
// from the first point of contact, the origin).
//
// Element size h = a0 / n on the sphere within 1.6 a0 of the origin (a0 = 1 mm,
// the contact radius the mesh is designed for; n = 8 by default, set with
// `gmsh -setnumber n 8 ...`), 1.25 h on the block (the host is the coarser part),
// growing by 0.35 per unit distance beyond, up to hFar.
//
// Regenerate with make_meshes.sh.

SetFactory("OpenCASCADE");

If (!Exists(n))
  n = 8;
EndIf
R = 10;              // sphere radius
W = 10;              // block: quarter width
H = 10;              // block height
a0 = 1;              // the contact radius the mesh is designed for
h = a0 / n;          // element size in the contact zone (sphere)
hFar = 3;            // element size far from the contact
e = 1e-6;            // bounding-box slack

// Sphere: latitude from −90° (the south pole, the origin) to 0° (the equator
// z = R), longitude from 0 to 90°: the quarter of the lower hemisphere.
Sphere(1) = {0, 0, R, R, -Pi/2, 0, Pi/2};
Box(2) = {0, 0, -H, W, W, H};

// Size field: h (sphere) or 1.25 h (block) within 1.6 a0 of the origin,
// growing by 0.35 per unit distance beyond, at most hFar.
Point(100) = {0, 0, 0};
Field[1] = Distance;
Field[1].PointsList = {100};
Field[2] = MathEval;
Field[2].F = Sprintf("Min(%g, %g + 0.35 * Max(0, F1 - %g))", hFar, h, 1.6 * a0);
Field[3] = MathEval;
Field[3].F = Sprintf("Min(%g, %g + 0.35 * Max(0, F1 - %g))", hFar, 1.25 * h, 1.6 * a0);
Field[4] = Restrict;
Field[4].InField = 2;
Field[4].VolumesList = {1};
Field[5] = Restrict;
Field[5].InField = 3;
Field[5].VolumesList = {2};
Field[6] = Min;
Field[6].FieldsList = {4, 5};
Background Field = 6;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

// The sphere's faces.
ballTop() = Surface In BoundingBox{-e, -e, R - e, R + e, R + e, R + e};
ballX() = Surface In BoundingBox{-e, -e, -e, e, R + e, R + e};
ballY() = Surface In BoundingBox{-e, -e, -e, R + e, e, R + e};
ballAll() = Abs(Boundary{ Volume{1}; });
ballFace() = ballAll();
ballFace() -= {ballTop(), ballX(), ballY()};
// The block's faces.
blockTop() = Surface In BoundingBox{-e, -e, -e, W + e, W + e, e};
blockBottom() = Surface In BoundingBox{-e, -e, -H - e, W + e, W + e, -H + e};
blockX() = Surface In BoundingBox{-e, -e, -H - e, e, W + e, e};
blockY() = Surface In BoundingBox{-e, -e, -H - e, W + e, e, e};

Physical Volume("ball", 1) = {1};
Physical Volume("block", 2) = {2};
Physical Surface("ball_face", 11) = {ballFace()};
Physical Surface("ball_top", 12) = {ballTop()};
Physical Surface("block_top", 21) = {blockTop()};
Physical Surface("block_bottom", 22) = {blockBottom()};
Physical Surface("symmetry_x", 31) = {ballX(), blockX()};
Physical Surface("symmetry_y", 32) = {ballY(), blockY()};
