//! The boundary faces of a 3D host and the geometry of a point against one: the
//! closest point of a face (exact on a triangle; on a bilinear quadrangle Newton's
//! projection, with the closest edge point as the fallback), the host face's shape
//! values N̄ᵢ there (barycentric on a triangle, the bilinear functions at the
//! natural coordinates of the projection on a quadrangle), the outward unit normal
//! there, and which feature of the face (inside, an edge, a vertex) the point is
//! on. Pure functions of coordinates: the pair search ([`super::search3d`]) puts
//! the faces in an R-tree and chooses among them.
//!
//! A face is the mesh's [`BoundaryFace`]: its corners counter-clockwise seen from
//! outside its element, so `(b − a) × (c − a)` (a triangle) and `x_ξ × x_η` (a
//! quadrangle, corners at the natural coordinates (−1, −1), (1, −1), (1, 1),
//! (−1, 1) of its bilinear map) point outward.

pub use crate::mesh::{BoundaryFace, FaceNodes};
use rstar::{AABB, PointDistance, RTreeObject};

/// A point of a face closer than this fraction of the face's parameter range to
/// an edge (a barycentric coordinate, or `(1 ∓ ξ)/2` on a quadrangle, at most
/// this) is *on* that edge; on two edges, at their vertex. There the normal is
/// averaged over the boundary faces sharing the edge or the vertex
/// ([`super::search3d`]).
pub const FEATURE_TOLERANCE: f64 = 1e-6;

/// Newton's projection on a bilinear quadrangle stops when its step in the
/// natural coordinates (ξ, η ∈ [−1, 1]) is below this.
pub const NEWTON_TOLERANCE: f64 = 1e-13;

/// Which part of a face a point of it lies on (local corner indices).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Feature {
    /// Strictly inside the face.
    Inside,
    /// On the edge between corners `a` and `b` (`a < b`).
    Edge(usize, usize),
    /// At corner `a`.
    Vertex(usize),
}

/// The closest point of a face to a point, with everything the coupling element
/// reads there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FacePoint {
    /// The closest point X_C.
    pub point: [f64; 3],
    /// Its distance from the point projected.
    pub distance: f64,
    /// The face's shape values N̄ᵢ at X_C, one per corner (the first 3 for a
    /// triangle; they sum to 1, none negative).
    pub shape: [f64; 4],
    /// The face's outward unit normal at X_C.
    pub normal: [f64; 3],
    /// Where on the face X_C lies.
    pub feature: Feature,
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
pub fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The Euclidean length of `a`.
pub fn norm(a: [f64; 3]) -> f64 {
    a[0].hypot(a[1]).hypot(a[2])
}

/// `a / |a|` (`a` itself when it is zero).
pub fn unit(a: [f64; 3]) -> [f64; 3] {
    let l = norm(a);
    if l > 0.0 { a.map(|x| x / l) } else { a }
}

/// `Σ wᵢ xᵢ` over the corners.
fn combine(x: &[[f64; 3]], w: &[f64]) -> [f64; 3] {
    std::array::from_fn(|c| x.iter().zip(w).map(|(p, wi)| wi * p[c]).sum())
}

/// The closest point of the triangle `x` to `p`, as its barycentric coordinates
/// (λ₀, λ₁, λ₂) (exact: the Voronoi region of `p` decides the vertex, the edge or
/// the inside; Ericson, *Real-Time Collision Detection*, 2005, §5.1.5).
pub fn closest_on_triangle(x: [[f64; 3]; 3], p: [f64; 3]) -> [f64; 3] {
    let [a, b, c] = x;
    let ab = sub(b, a);
    let ac = sub(c, a);
    let ap = sub(p, a);
    let (d1, d2) = (dot(ab, ap), dot(ac, ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return [1.0, 0.0, 0.0];
    }
    let bp = sub(p, b);
    let (d3, d4) = (dot(ab, bp), dot(ac, bp));
    if d3 >= 0.0 && d4 <= d3 {
        return [0.0, 1.0, 0.0];
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let t = d1 / (d1 - d3);
        return [1.0 - t, t, 0.0];
    }
    let cp = sub(p, c);
    let (d5, d6) = (dot(ab, cp), dot(ac, cp));
    if d6 >= 0.0 && d5 <= d6 {
        return [0.0, 0.0, 1.0];
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let t = d2 / (d2 - d6);
        return [1.0 - t, 0.0, t];
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0 {
        let t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return [0.0, 1.0 - t, t];
    }
    let s = 1.0 / (va + vb + vc);
    let (v, w) = (vb * s, vc * s);
    [1.0 - v - w, v, w]
}

/// The closest point of segment `a`–`b` to `p`: its parameter t ∈ [0, 1] from a.
fn closest_on_segment(a: [f64; 3], b: [f64; 3], p: [f64; 3]) -> f64 {
    let ab = sub(b, a);
    let l2 = dot(ab, ab);
    if l2 > 0.0 {
        (dot(sub(p, a), ab) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    }
}

/// The bilinear shape functions of a quadrangle at natural coordinates (ξ, η),
/// corners at (−1, −1), (1, −1), (1, 1), (−1, 1).
pub fn quad_shape([s, t]: [f64; 2]) -> [f64; 4] {
    [
        0.25 * (1.0 - s) * (1.0 - t),
        0.25 * (1.0 + s) * (1.0 - t),
        0.25 * (1.0 + s) * (1.0 + t),
        0.25 * (1.0 - s) * (1.0 + t),
    ]
}

/// The tangents `(x_ξ, x_η)` of the bilinear quadrangle `x` at (ξ, η).
fn quad_tangents(x: &[[f64; 3]; 4], [s, t]: [f64; 2]) -> ([f64; 3], [f64; 3]) {
    let ds = [-(1.0 - t), 1.0 - t, 1.0 + t, -(1.0 + t)].map(|v| 0.25 * v);
    let dt = [-(1.0 - s), -(1.0 + s), 1.0 + s, 1.0 - s].map(|v| 0.25 * v);
    (combine(x, &ds), combine(x, &dt))
}

/// The outward unit normal of the bilinear quadrangle `x` at (ξ, η): `x_ξ × x_η`
/// normalised.
pub fn quad_normal(x: &[[f64; 3]; 4], xi: [f64; 2]) -> [f64; 3] {
    let (a, b) = quad_tangents(x, xi);
    unit(cross(a, b))
}

/// Newton's projection of `p` on the bilinear quadrangle `x`: the natural
/// coordinates (ξ, η) where `(x(ξ, η) − p)` is normal to both tangents — the
/// stationary point of the squared distance, its Hessian
/// `[[x_ξ·x_ξ, x_ξ·x_η + x_ξη·r], [·, x_η·x_η]]` (x_ξξ = x_ηη = 0 on a bilinear
/// map; its Gauss–Newton part where that is not positive definite) — from the
/// centre, until the step is below [`NEWTON_TOLERANCE`]. `None` when it does not
/// converge in 100 steps or lands outside the face (beyond 1e-12
/// of [−1, 1]²): then the closest point is on an edge.
pub fn project_on_quad(x: &[[f64; 3]; 4], p: [f64; 3]) -> Option<[f64; 2]> {
    let twist = combine(x, &[0.25, -0.25, 0.25, -0.25]);
    let mut xi = [0.0f64; 2];
    for _ in 0..100 {
        let r = sub(combine(x, &quad_shape(xi)), p);
        let (a, b) = quad_tangents(x, xi);
        let g = [dot(a, r), dot(b, r)];
        let (aa, bb) = (dot(a, a), dot(b, b));
        // The Hessian, or where it is not positive definite (far from a
        // strongly warped face) its Gauss–Newton part, which is.
        let mut ab = dot(a, b) + dot(twist, r);
        if (aa * bb - ab * ab).is_nan() || aa * bb - ab * ab <= 0.0 {
            ab = dot(a, b);
        }
        let det = aa * bb - ab * ab;
        if !(det.is_finite() && det > 0.0) {
            return None;
        }
        let step = [-(bb * g[0] - ab * g[1]) / det, -(aa * g[1] - ab * g[0]) / det];
        xi = [xi[0] + step[0], xi[1] + step[1]];
        if xi.iter().any(|v| !v.is_finite() || v.abs() > 10.0) {
            return None;
        }
        if step[0].hypot(step[1]) < NEWTON_TOLERANCE {
            let inside = xi.iter().all(|v| v.abs() <= 1.0 + 1e-12);
            return inside.then(|| xi.map(|v| v.clamp(-1.0, 1.0)));
        }
    }
    None
}

/// The feature of a point whose "distance to each edge" in the face's parameters
/// is `edge_params[k]` for the edges `edges[k]` (corner pairs).
fn feature_of(edge_params: &[f64], edges: &[(usize, usize)]) -> Feature {
    let on: Vec<usize> = (0..edges.len())
        .filter(|&k| edge_params[k] <= FEATURE_TOLERANCE)
        .collect();
    match on.as_slice() {
        [] => Feature::Inside,
        [k] => Feature::Edge(edges[*k].0, edges[*k].1),
        [k, l, ..] => {
            let (a, b) = edges[*k];
            let (c, d) = edges[*l];
            let v = if a == c || a == d { a } else { b };
            Feature::Vertex(v)
        }
    }
}

/// The closest point of the face with corner coordinates `x` (3 or 4 of them) to
/// `p`. On a triangle it is exact ([`closest_on_triangle`]); on a quadrangle it
/// is the nearer of Newton's projection ([`project_on_quad`], when it converges
/// inside) and the closest points of the four straight edges (the fallback, and
/// the answer whenever the closest point is on the boundary).
pub fn closest_point(x: &[[f64; 3]], p: [f64; 3]) -> FacePoint {
    if x.len() == 3 {
        let tri = [x[0], x[1], x[2]];
        let l = closest_on_triangle(tri, p);
        let point = combine(x, &l);
        // Edge k is opposite corner k.
        let feature = feature_of(&l, &[(1, 2), (0, 2), (0, 1)]);
        FacePoint {
            point,
            distance: norm(sub(p, point)),
            shape: [l[0], l[1], l[2], 0.0],
            normal: unit(cross(sub(x[1], x[0]), sub(x[2], x[0]))),
            feature,
        }
    } else {
        let q = [x[0], x[1], x[2], x[3]];
        let mut best: Option<([f64; 2], [f64; 3], f64)> = project_on_quad(&q, p).map(|xi| {
            let point = combine(x, &quad_shape(xi));
            (xi, point, norm(sub(p, point)))
        });
        // Edge k from corner k to corner k + 1, as natural coordinates.
        let ends = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];
        for k in 0..4 {
            let (a, b) = (q[k], q[(k + 1) % 4]);
            let t = closest_on_segment(a, b, p);
            let (ea, eb) = (ends[k], ends[(k + 1) % 4]);
            let xi = [ea[0] + t * (eb[0] - ea[0]), ea[1] + t * (eb[1] - ea[1])];
            let point = combine(x, &quad_shape(xi));
            let d = norm(sub(p, point));
            if best.is_none_or(|(_, _, bd)| d < bd) {
                best = Some((xi, point, d));
            }
        }
        let (xi, point, distance) = best.expect("a quadrangle has edges");
        let params = [
            0.5 * (1.0 + xi[1]),
            0.5 * (1.0 - xi[0]),
            0.5 * (1.0 - xi[1]),
            0.5 * (1.0 + xi[0]),
        ];
        let feature = feature_of(&params, &[(0, 1), (1, 2), (2, 3), (0, 3)]);
        FacePoint {
            point,
            distance,
            shape: quad_shape(xi),
            normal: quad_normal(&q, xi),
            feature,
        }
    }
}

/// The size of a face: its longest edge (the scale of its projection tolerance).
pub fn face_size(x: &[[f64; 3]]) -> f64 {
    (0..x.len())
        .map(|k| norm(sub(x[(k + 1) % x.len()], x[k])))
        .fold(0.0, f64::max)
}

/// The share of the face `x` of each corner, `∫ Nᵢ dA`: a third of the area on a
/// triangle; on a quadrangle by the 2 × 2 Gauss rule on its bilinear map (exact
/// for a flat parallelogram: a quarter of the area each).
pub fn corner_areas(x: &[[f64; 3]]) -> [f64; 4] {
    if x.len() == 3 {
        let a = 0.5 * norm(cross(sub(x[1], x[0]), sub(x[2], x[0])));
        [a / 3.0, a / 3.0, a / 3.0, 0.0]
    } else {
        let q = [x[0], x[1], x[2], x[3]];
        let g = 1.0 / 3.0f64.sqrt();
        let mut out = [0.0; 4];
        for s in [-g, g] {
            for t in [-g, g] {
                let (a, b) = quad_tangents(&q, [s, t]);
                let j = norm(cross(a, b));
                for (o, n) in out.iter_mut().zip(quad_shape([s, t])) {
                    *o += n * j;
                }
            }
        }
        out
    }
}

/// A face as the R-tree holds it: its corners' coordinates and its index in the
/// list of boundary faces. Its distance to a point is the exact distance to its
/// closest point ([`closest_point`]), so `locate_within_distance` and
/// `nearest_neighbor` are exact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceObject {
    corners: [[f64; 3]; 4],
    count: usize,
    /// Index of the face in the list the tree was built from.
    pub index: usize,
}

impl FaceObject {
    /// The face of corners `x` (3 or 4), number `index` of its list.
    pub fn new(x: &[[f64; 3]], index: usize) -> Self {
        let mut corners = [[0.0; 3]; 4];
        corners[..x.len()].copy_from_slice(x);
        Self {
            corners,
            count: x.len(),
            index,
        }
    }

    /// The corners' coordinates.
    pub fn corners(&self) -> &[[f64; 3]] {
        &self.corners[..self.count]
    }
}

impl RTreeObject for FaceObject {
    type Envelope = AABB<[f64; 3]>;

    fn envelope(&self) -> Self::Envelope {
        AABB::from_points(self.corners().iter())
    }
}

impl PointDistance for FaceObject {
    fn distance_2(&self, p: &[f64; 3]) -> f64 {
        let d = closest_point(self.corners(), *p).distance;
        d * d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        norm(sub(a, b)) <= tol
    }

    /// A triangle tilted 45° (in the plane z = y): a point 0.3 off it along its
    /// normal (0, −1, 1)/√2 above (0.5, 0.5, 0.5) projects there, with the
    /// barycentric values (0.5, 0.25, 0.25) and distance 0.3, inside; a point
    /// beyond the edge a–c projects on the edge at t = 1/4 (shape (3/4, 0, 1/4),
    /// distance √1.04); one beyond corner b projects on b.
    #[test]
    fn projection_on_a_tilted_triangle() {
        let x = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 2.0]];
        let n = [0.0, -(0.5f64.sqrt()), 0.5f64.sqrt()];
        let on = |q: [f64; 3], s: f64| [q[0] + s * n[0], q[1] + s * n[1], q[2] + s * n[2]];
        let f = closest_point(&x, on([0.5, 0.5, 0.5], 0.3));
        assert!(close(f.point, [0.5, 0.5, 0.5], 1e-15), "{f:?}");
        assert!((f.distance - 0.3).abs() < 1e-15);
        assert!(close([f.shape[0], f.shape[1], f.shape[2]], [0.5, 0.25, 0.25], 1e-15));
        assert!(close(f.normal, n, 1e-15));
        assert_eq!(f.feature, Feature::Inside);
        let f = closest_point(&x, on([-1.0, 0.5, 0.5], 0.2));
        assert!(close(f.point, [0.0, 0.5, 0.5], 1e-15), "{f:?}");
        assert!((f.distance - 1.04f64.sqrt()).abs() < 1e-15);
        let want = [0.75, 0.0, 0.25, 0.0];
        assert!((0..4).all(|i| (f.shape[i] - want[i]).abs() < 1e-15), "{:?}", f.shape);
        assert_eq!(f.feature, Feature::Edge(0, 2));
        let f = closest_point(&x, [3.0, -1.0, 0.0]);
        assert_eq!((f.shape, f.feature), ([0.0, 1.0, 0.0, 0.0], Feature::Vertex(1)));
        assert!((f.distance - 2.0f64.sqrt()).abs() < 1e-15);
    }

    /// A warped quadrangle, the saddle z = −w x y over [−1, 1]² (w = 0.2): a point
    /// 0.1 along the surface normal (wη, wξ, 1)/|…| above x(0.3, −0.5) projects
    /// there — Newton's projection gives the bilinear values (0.2625, 0.4875,
    /// 0.1625, 0.0875) and distance 0.1 — and a point beyond the edge ξ = 1 falls
    /// back to the edge's closest point.
    #[test]
    fn projection_on_a_warped_quadrangle() {
        let w = 0.2;
        let x = [
            [-1.0, -1.0, -w],
            [1.0, -1.0, w],
            [1.0, 1.0, -w],
            [-1.0, 1.0, w],
        ];
        let (s, t) = (0.3, -0.5);
        let foot = [s, t, -w * s * t];
        let n = unit([w * t, w * s, 1.0]);
        let p = [foot[0] + 0.1 * n[0], foot[1] + 0.1 * n[1], foot[2] + 0.1 * n[2]];
        let f = closest_point(&x, p);
        assert!(close(f.point, foot, 1e-14), "{f:?}");
        assert!((f.distance - 0.1).abs() < 1e-14);
        let want = [0.2625, 0.4875, 0.1625, 0.0875];
        assert!((0..4).all(|i| (f.shape[i] - want[i]).abs() < 1e-14), "{:?}", f.shape);
        assert!(close(f.normal, n, 1e-14));
        assert_eq!(f.feature, Feature::Inside);
        // Beyond the edge ξ = 1 (corners 1–2, the straight segment x = 1, z = −w y):
        // the closest point is on that segment.
        let f = closest_point(&x, [2.0, 0.25, -w * 0.25]);
        assert!(close(f.point, [1.0, 0.25, -w * 0.25], 1e-14), "{f:?}");
        assert_eq!(f.feature, Feature::Edge(1, 2));
        assert!((f.shape[0] + f.shape[3]).abs() < 1e-15);
    }

    /// The corner shares of a face sum to its area: a right triangle of legs 3, 4
    /// (area 6, 2 each) and a flat parallelogram (a quarter each).
    #[test]
    fn corner_areas_sum_to_the_area() {
        let t = corner_areas(&[[0.0, 0.0, 1.0], [3.0, 0.0, 1.0], [0.0, 4.0, 1.0]]);
        assert!(t[..3].iter().all(|&a| (a - 2.0).abs() < 1e-14));
        let q = corner_areas(&[[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 1.0, 1.0], [1.0, 1.0, 1.0]]);
        let area = norm(cross([2.0, 0.0, 0.0], [1.0, 1.0, 1.0]));
        assert!(q.iter().all(|&a| (a - area / 4.0).abs() < 1e-14), "{q:?}");
    }
}
