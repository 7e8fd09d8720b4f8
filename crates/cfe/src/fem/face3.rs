//! Faces of 3D elements for loads and normals: the linear triangle (a TET4 face)
//! and the bilinear quadrangle (a HEX8 face), given by their corner coordinates
//! ordered so that the right-hand rule gives the outward normal. Which corners of
//! which cell form a face is the mesh's topology; these routines take coordinates.
//!
//! ```text
//!   triangle                      quadrangle (η up, ξ right, seen from outside)
//!        2                          3 ─────────── 2
//!        │ ╲                        │             │
//!        │   ╲        n = out       │      n      │     n = a_ξ × a_η / |a_ξ × a_η|
//!        │     ╲      of the page   │   (out)     │     out of the page
//!        0 ───── 1                  0 ─────────── 1
//! ```
//!
//! - **Triangle**: area vector `A n = ½ (x₁ − x₀) × (x₂ − x₀)`; a uniform traction t
//!   gives each corner `t A / 3` and a uniform pressure p (positive pushing into the
//!   body, traction −p n) gives each corner `−p A n / 3` (`∫ N_i dA = A/3`, exact).
//! - **Quadrangle**: `x(ξ, η) = Σ N_i(ξ, η) x_i` with the bilinear
//!   `N_i = ¼ (1 + ξ ξ_i)(1 + η η_i)` of [`super::q4`], tangents `a_ξ = ∂x/∂ξ`,
//!   `a_η = ∂x/∂η`, `dA = |a_ξ × a_η| dξ dη`, unit normal `n = a_ξ × a_η / |a_ξ × a_η|`.
//!   A pressure gives `f_i = −p ∫ N_i (a_ξ × a_η) dξ dη` and a uniform traction
//!   `f_i = t ∫ N_i |a_ξ × a_η| dξ dη`, both by 2×2 Gauss. `a_ξ × a_η` is linear in
//!   (ξ, η) (the twist term crosses itself out), so the pressure forces are exact on
//!   any quadrangle, warped or not; `|a_ξ × a_η|` is linear on a plane quadrangle
//!   (exact there: area and traction forces) and only approximated on a warped one.
//!
//! ```
//! use cfe::fem::face3;
//! // A unit square in the plane z = 2, counter-clockwise seen from +z: normal +z.
//! let x = [[0.0, 0.0, 2.0], [1.0, 0.0, 2.0], [1.0, 1.0, 2.0], [0.0, 1.0, 2.0]];
//! assert_eq!(face3::quad_normal(&x, [0.0, 0.0]), Some([0.0, 0.0, 1.0]));
//! assert!((face3::quad_area(&x) - 1.0).abs() < 1e-15);
//! // A pressure of 8 pushes each corner by a quarter of 8 × 1 against the normal.
//! for f in face3::quad_pressure_forces(&x, 8.0) {
//!     assert!(f[0].abs() < 1e-15 && f[1].abs() < 1e-15 && (f[2] + 2.0).abs() < 1e-14);
//! }
//! ```

use super::q4;

/// `a × b`.
fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `b − a`.
fn sub(b: [f64; 3], a: [f64; 3]) -> [f64; 3] {
    [b[0] - a[0], b[1] - a[1], b[2] - a[2]]
}

/// `|v|`.
fn norm(v: [f64; 3]) -> f64 {
    v[0].hypot(v[1]).hypot(v[2])
}

/// `v / |v|`, `None` when |v| is zero or not finite.
fn unit(v: [f64; 3]) -> Option<[f64; 3]> {
    let l = norm(v);
    (l.is_finite() && l > 0.0).then(|| v.map(|c| c / l))
}

/// Area vector `A n = ½ (x₁ − x₀) × (x₂ − x₀)` of the triangle `x`.
pub fn triangle_area_vector(x: &[[f64; 3]; 3]) -> [f64; 3] {
    cross(sub(x[1], x[0]), sub(x[2], x[0])).map(|c| 0.5 * c)
}

/// Area of the triangle `x`.
pub fn triangle_area(x: &[[f64; 3]; 3]) -> f64 {
    norm(triangle_area_vector(x))
}

/// Unit normal of the triangle `x` (right-hand rule over 0 → 1 → 2); `None` for a
/// degenerate triangle (zero or non-finite area).
pub fn triangle_normal(x: &[[f64; 3]; 3]) -> Option<[f64; 3]> {
    unit(triangle_area_vector(x))
}

/// Consistent nodal forces of a uniform traction `t` (force per area) on the
/// triangle `x`: `t A / 3` at each corner.
pub fn triangle_traction_forces(x: &[[f64; 3]; 3], t: [f64; 3]) -> [[f64; 3]; 3] {
    let w = triangle_area(x) / 3.0;
    [t.map(|c| c * w); 3]
}

/// Consistent nodal forces of a uniform pressure `p` (positive pushing against the
/// outward normal) on the triangle `x`: `−p A n / 3` at each corner.
pub fn triangle_pressure_forces(x: &[[f64; 3]; 3], p: f64) -> [[f64; 3]; 3] {
    let f = triangle_area_vector(x).map(|c| -p * c / 3.0);
    [f; 3]
}

/// The point `x(ξ, η)` and the tangents `a_ξ × a_η` of the quadrangle `x` at natural
/// coordinates `xi`: returns (point, `a_ξ × a_η`).
fn quad_frame(x: &[[f64; 3]; 4], xi: [f64; 2]) -> ([f64; 3], [f64; 3]) {
    let n = q4::shape(xi);
    let dn = q4::shape_derivatives(xi);
    let at = |w: &[f64; 4]| -> [f64; 3] {
        std::array::from_fn(|c| (0..4).map(|i| w[i] * x[i][c]).sum())
    };
    (at(&n), cross(at(&dn[0]), at(&dn[1])))
}

/// The point of the quadrangle `x` at natural coordinates `xi = (ξ, η)`:
/// `Σ N_i(ξ, η) x_i`.
pub fn quad_point(x: &[[f64; 3]; 4], xi: [f64; 2]) -> [f64; 3] {
    quad_frame(x, xi).0
}

/// Area `∫ |a_ξ × a_η| dξ dη` of the quadrangle `x` by 2×2 Gauss (exact for a plane
/// quadrangle).
pub fn quad_area(x: &[[f64; 3]; 4]) -> f64 {
    q4::GAUSS.iter().map(|&g| norm(quad_frame(x, g).1)).sum()
}

/// Unit normal `a_ξ × a_η / |a_ξ × a_η|` of the quadrangle `x` at natural
/// coordinates `xi` (constant on a plane parallelogram, varying on a warped face);
/// `None` where the tangents are parallel (a degenerate corner).
pub fn quad_normal(x: &[[f64; 3]; 4], xi: [f64; 2]) -> Option<[f64; 3]> {
    unit(quad_frame(x, xi).1)
}

/// Consistent nodal forces of a uniform traction `t` (force per area) on the
/// quadrangle `x`: `f_i = t ∫ N_i |a_ξ × a_η| dξ dη` (2×2 Gauss; exact for a plane
/// quadrangle).
pub fn quad_traction_forces(x: &[[f64; 3]; 4], t: [f64; 3]) -> [[f64; 3]; 4] {
    let mut f = [[0.0; 3]; 4];
    for &g in &q4::GAUSS {
        let da = norm(quad_frame(x, g).1);
        for (fi, ni) in f.iter_mut().zip(q4::shape(g)) {
            for c in 0..3 {
                fi[c] += t[c] * ni * da;
            }
        }
    }
    f
}

/// Consistent nodal forces of a uniform pressure `p` (positive pushing against the
/// outward normal) on the quadrangle `x`: `f_i = −p ∫ N_i (a_ξ × a_η) dξ dη`
/// (2×2 Gauss, exact even on a warped face).
pub fn quad_pressure_forces(x: &[[f64; 3]; 4], p: f64) -> [[f64; 3]; 4] {
    let mut f = [[0.0; 3]; 4];
    for &g in &q4::GAUSS {
        let (_, a) = quad_frame(x, g);
        for (fi, ni) in f.iter_mut().zip(q4::shape(g)) {
            for c in 0..3 {
                fi[c] -= p * ni * a[c];
            }
        }
    }
    f
}

/// The part of the plane convex polygon `poly` inside the box `[lo, hi]`
/// along the axes `clip` says (Sutherland–Hodgman: the polygon cut by each
/// plane `x_a = lo_a` and `x_a = hi_a` in turn, its vertices where the edges
/// cross the planes found by linear interpolation). Empty when nothing is
/// inside; the vertices keep the polygon's orientation.
pub fn clip_to_box(
    poly: &[[f64; 3]],
    lo: [f64; 3],
    hi: [f64; 3],
    clip: [bool; 3],
) -> Vec<[f64; 3]> {
    let mut out: Vec<[f64; 3]> = poly.to_vec();
    for a in (0..3).filter(|&a| clip[a]) {
        // Keep s·x_a ≥ s·bound: the side of the box.
        for (bound, s) in [(lo[a], 1.0), (hi[a], -1.0)] {
            if out.is_empty() {
                return out;
            }
            let input = std::mem::take(&mut out);
            let d = |p: &[f64; 3]| s * (p[a] - bound);
            for (k, p) in input.iter().enumerate() {
                let q = input[(k + 1) % input.len()];
                let (dp, dq) = (d(p), d(&q));
                if dp >= 0.0 {
                    out.push(*p);
                }
                if (dp >= 0.0) != (dq >= 0.0) {
                    let t = dp / (dp - dq);
                    let mut x: [f64; 3] = std::array::from_fn(|c| p[c] + t * (q[c] - p[c]));
                    // On the plane exactly, not to round-off.
                    x[a] = bound;
                    out.push(x);
                }
            }
        }
    }
    out
}

/// The shape values of the plane face `x` (3 corners: linear, barycentric; 4:
/// bilinear, at the natural coordinates of the inverse map in the face's
/// plane, [`q4::natural_coordinates`]) at its point `p`; `None` for a
/// degenerate face or an inverse map that fails.
pub fn face_shape_at(x: &[[f64; 3]], p: [f64; 3]) -> Option<Vec<f64>> {
    match x {
        [a, b, c] => {
            let n = cross(sub(*b, *a), sub(*c, *a));
            let nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
            if nn.is_nan() || nn <= 0.0 {
                return None;
            }
            let dot = |u: [f64; 3]| (u[0] * n[0] + u[1] * n[1] + u[2] * n[2]) / nn;
            let l0 = dot(cross(sub(*b, p), sub(*c, p)));
            let l1 = dot(cross(sub(*c, p), sub(*a, p)));
            Some(vec![l0, l1, 1.0 - l0 - l1])
        }
        [_, _, _, _] => {
            // The face's plane: its mean normal and two axes in it.
            let n = unit(cross(sub(x[2], x[0]), sub(x[3], x[1])))?;
            let e1 = unit(sub(x[1], x[0]))?;
            let e2 = cross(n, e1);
            let local = |q: [f64; 3]| {
                let d = sub(q, x[0]);
                let dot = |e: [f64; 3]| d[0] * e[0] + d[1] * e[1] + d[2] * e[2];
                [dot(e1), dot(e2)]
            };
            let x2 = [local(x[0]), local(x[1]), local(x[2]), local(x[3])];
            q4::natural_coordinates(&x2, local(p)).map(|xi| q4::shape(xi).to_vec())
        }
        _ => None,
    }
}

/// The 3-point rule of a triangle exact for quadratics: barycentric points
/// (2/3, 1/6, 1/6) and their permutations, each of weight 1/3 of the area.
const TRIANGLE_RULE: [[f64; 3]; 3] = [
    [2.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0],
    [1.0 / 6.0, 2.0 / 3.0, 1.0 / 6.0],
    [1.0 / 6.0, 1.0 / 6.0, 2.0 / 3.0],
];

/// `∫ N_i dA` over the part of the plane face `x` (3 or 4 corners) inside the
/// box `[lo, hi]` along the axes `clip` ([`clip_to_box`]), and that part's
/// area: the clipped polygon split into a fan of triangles from its first
/// vertex, each integrated by [`TRIANGLE_RULE`] with the face's shape values
/// at the rule's points ([`face_shape_at`]). Exact for a triangle (N linear)
/// and a parallelogram (N quadratic in x); on any plane face `Σ_i ∫ N_i dA`
/// is the clipped area and `Σ_i x_i ∫ N_i dA` its first moment exactly
/// (the shape values sum to 1 and reproduce x). `None` for a degenerate face.
pub fn clipped_shape_integrals(
    x: &[[f64; 3]],
    lo: [f64; 3],
    hi: [f64; 3],
    clip: [bool; 3],
) -> Option<(Vec<f64>, f64)> {
    let poly = clip_to_box(x, lo, hi, clip);
    let mut w = vec![0.0; x.len()];
    let mut area = 0.0;
    for k in 1..poly.len().saturating_sub(1) {
        let t = [poly[0], poly[k], poly[k + 1]];
        let a = triangle_area(&t);
        if a == 0.0 {
            continue;
        }
        area += a;
        for l in TRIANGLE_RULE {
            let p: [f64; 3] = std::array::from_fn(|c| (0..3).map(|j| l[j] * t[j][c]).sum());
            let n = face_shape_at(x, p)?;
            for (wi, ni) in w.iter_mut().zip(n) {
                *wi += ni * a / 3.0;
            }
        }
    }
    Some((w, area))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Σ f and Σ x × f of nodal forces `f` at corners `x`.
    fn resultant_and_moment<const N: usize>(
        x: &[[f64; 3]; N],
        f: &[[f64; 3]; N],
    ) -> ([f64; 3], [f64; 3]) {
        let mut r = [0.0; 3];
        let mut m = [0.0; 3];
        for (xi, fi) in x.iter().zip(f) {
            let mi = cross(*xi, *fi);
            for c in 0..3 {
                r[c] += fi[c];
                m[c] += mi[c];
            }
        }
        (r, m)
    }

    fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
        (0..3).all(|c| (a[c] - b[c]).abs() <= tol)
    }

    /// A triangle (0,0)–(2,0)–(0,2) cut to the unit square: the clipped area
    /// is 1 and `∫ N_i dA` over it is the closed form (N₀ = 1 − x/2 − y/2:
    /// 1/2; N₁ = x/2, N₂ = y/2: 1/4 each), in any plane orientation of the
    /// box's unused axis.
    #[test]
    fn a_clipped_triangle_integrates_its_shape_functions_exactly() {
        let x = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 2.0, 0.0]];
        let (w, area) =
            clipped_shape_integrals(&x, [0.0, 0.0, -1.0], [1.0, 1.0, 1.0], [true, true, false])
                .unwrap();
        assert!((area - 1.0).abs() < 1e-15, "{area}");
        for (wi, want) in w.iter().zip([0.5, 0.25, 0.25]) {
            assert!((wi - want).abs() < 1e-15, "{w:?}");
        }
    }

    /// A parallelogram (0,0)–(2,0)–(3,2)–(1,2) cut at y = 1: the lower half,
    /// area 2, where `∫ N_i dA = ½ (1 − η_i / 2)` (η = y − 1, ξ = x − 1 − y/2,
    /// det J = 1): 3/4 at the corners of y = 0, 1/4 at those of y = 2; a
    /// plane tilted about x gives the same on its own coordinates.
    #[test]
    fn a_clipped_parallelogram_integrates_its_shape_functions_exactly() {
        let x = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [3.0, 2.0, 0.0], [1.0, 2.0, 0.0]];
        let (w, area) =
            clipped_shape_integrals(&x, [-9.0, -9.0, -9.0], [9.0, 1.0, 9.0], [true; 3]).unwrap();
        assert!((area - 2.0).abs() < 1e-14, "{area}");
        for (wi, want) in w.iter().zip([0.75, 0.75, 0.25, 0.25]) {
            assert!((wi - want).abs() < 1e-14, "{w:?}");
        }
        // Tilted: z = y, so the cut at z = 1 keeps y ≤ 1 and dA = √2 dx dy.
        let t = x.map(|p| [p[0], p[1], p[1]]);
        let (w, area) =
            clipped_shape_integrals(&t, [-9.0; 3], [9.0, 9.0, 1.0], [true; 3]).unwrap();
        let r2 = 2f64.sqrt();
        assert!((area - 2.0 * r2).abs() < 1e-14, "{area}");
        for (wi, want) in w.iter().zip([0.75, 0.75, 0.25, 0.25]) {
            assert!((wi - want * r2).abs() < 1e-14, "{w:?}");
        }
        // Outside the box: nothing.
        let (w, area) =
            clipped_shape_integrals(&x, [5.0; 3], [6.0; 3], [true; 3]).unwrap();
        assert_eq!(area, 0.0);
        assert!(w.iter().all(|&v| v == 0.0));
    }

    /// A traction on a tilted triangle sums to t A and its moment about the origin
    /// is A c × t with c the centroid; the pressure sums to −p A n with n ⟂ both
    /// edges and the area equal to Heron's formula.
    #[test]
    fn triangle_loads_give_resultant_and_moment() {
        let x = [[1.0, 0.5, -0.2], [3.2, 1.1, 0.4], [1.7, 2.9, 1.3]];
        let len = |a: [f64; 3], b: [f64; 3]| norm(sub(a, b));
        let (a, b, c) = (len(x[0], x[1]), len(x[1], x[2]), len(x[2], x[0]));
        let s = 0.5 * (a + b + c);
        let heron = (s * (s - a) * (s - b) * (s - c)).sqrt();
        assert!((triangle_area(&x) - heron).abs() < 1e-13 * heron);
        let n = triangle_normal(&x).unwrap();
        for e in [sub(x[1], x[0]), sub(x[2], x[1])] {
            assert!((n[0] * e[0] + n[1] * e[1] + n[2] * e[2]).abs() < 1e-14);
        }
        let t = [0.3, -1.2, 2.5];
        let (r, m) = resultant_and_moment(&x, &triangle_traction_forces(&x, t));
        assert!(close(r, t.map(|v| v * heron), 1e-13));
        let centroid: [f64; 3] = std::array::from_fn(|k| (x[0][k] + x[1][k] + x[2][k]) / 3.0);
        assert!(close(m, cross(centroid, t).map(|v| v * heron), 1e-12));
        let (r, m) = resultant_and_moment(&x, &triangle_pressure_forces(&x, 2.0));
        assert!(close(r, n.map(|v| -2.0 * heron * v), 1e-13));
        assert!(close(m, cross(centroid, n).map(|v| -2.0 * heron * v), 1e-12));
        let flat = [[0.0; 3], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]];
        assert_eq!(triangle_normal(&flat), None);
    }

    /// On a plane, non-parallelogram quadrangle (a trapezoid in a tilted plane) the
    /// area is the sum of its two triangles', the normal is the plane's at every
    /// point, and a traction sums to t A with moment A c × t, c the centroid of the
    /// two triangles (area-weighted).
    #[test]
    fn plane_quad_traction_gives_resultant_and_moment() {
        // Trapezoid in the (e1, e2) plane, placed with an origin o.
        let (o, e1, e2) = ([0.5, -1.0, 2.0], [0.6, 0.8, 0.0], [0.0, 0.0, 1.0]);
        let at = |u: f64, v: f64| -> [f64; 3] { std::array::from_fn(|k| o[k] + u * e1[k] + v * e2[k]) };
        let x = [at(0.0, 0.0), at(4.0, 0.0), at(3.0, 2.0), at(0.5, 2.5)];
        let tri = |a: [f64; 3], b: [f64; 3], c: [f64; 3]| {
            let area = triangle_area(&[a, b, c]);
            let cen: [f64; 3] = std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0);
            (area, cen)
        };
        let (a1, c1) = tri(x[0], x[1], x[2]);
        let (a2, c2) = tri(x[0], x[2], x[3]);
        let area = a1 + a2;
        let centroid: [f64; 3] = std::array::from_fn(|k| (a1 * c1[k] + a2 * c2[k]) / area);
        assert!((quad_area(&x) - area).abs() < 1e-13 * area);
        let plane_n = cross(e1, e2);
        for xi in [[0.0, 0.0], [-1.0, -1.0], [0.7, -0.3], [1.0, 1.0]] {
            assert!(close(quad_normal(&x, xi).unwrap(), plane_n, 1e-14));
        }
        let t = [0.3, -1.2, 2.5];
        let (r, m) = resultant_and_moment(&x, &quad_traction_forces(&x, t));
        assert!(close(r, t.map(|v| v * area), 1e-12));
        assert!(close(m, cross(centroid, t).map(|v| v * area), 1e-11));
        let (r, m) = resultant_and_moment(&x, &quad_pressure_forces(&x, 3.0));
        assert!(close(r, plane_n.map(|v| -3.0 * area * v), 1e-12));
        assert!(close(m, cross(centroid, plane_n).map(|v| -3.0 * area * v), 1e-11));
    }

    /// On a warped quadrangle the pressure's resultant is −p times the vector area
    /// ½ (x₂ − x₀) × (x₃ − x₁) (the area vector of any surface spanning the
    /// boundary), and a closed surface — the six bilinear faces of a distorted
    /// hexahedron, outward — takes no net force nor moment from a uniform pressure.
    #[test]
    fn warped_quad_pressure_is_exact() {
        let x = [[0.0, 0.0, 0.0], [2.0, 0.1, 0.4], [2.2, 1.9, -0.3], [-0.1, 1.7, 0.5]];
        let va = cross(sub(x[2], x[0]), sub(x[3], x[1])).map(|v| 0.5 * v);
        let (r, _) = resultant_and_moment(&x, &quad_pressure_forces(&x, 1.5));
        assert!(close(r, va.map(|v| -1.5 * v), 1e-13));
        let h = [
            [0.0, 0.0, 0.0],
            [2.0, 0.1, -0.2],
            [2.3, 1.8, 0.1],
            [-0.2, 2.1, 0.0],
            [0.1, -0.1, 1.9],
            [1.8, 0.2, 2.4],
            [2.1, 2.2, 1.7],
            [0.2, 1.9, 2.2],
        ];
        let faces = [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]];
        let mut r = [0.0; 3];
        let mut m = [0.0; 3];
        for f in faces {
            let xf = f.map(|i| h[i]);
            let (ri, mi) = resultant_and_moment(&xf, &quad_pressure_forces(&xf, 7.0));
            for c in 0..3 {
                r[c] += ri[c];
                m[c] += mi[c];
            }
        }
        assert!(close(r, [0.0; 3], 1e-13) && close(m, [0.0; 3], 1e-12), "{r:?} {m:?}");
    }
}
