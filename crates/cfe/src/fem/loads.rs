//! Consistent nodal forces of external loads: a resultant force spread uniformly
//! (constant traction) over a boundary segment, integrated exactly over whole and
//! partial edges with the edges' linear shape functions, and a uniform pressure
//! (normal traction) over a boundary; on a solid part, a uniform traction or
//! pressure over boundary faces ([`face_forces`], the integrals of
//! [`super::face3`]).

/// Nodal forces of a uniform traction whose resultant is `force`, spread over the
/// part of `edges` (node coordinate pairs with their node indices) that lies on the
/// straight segment `from`–`to`. An edge counts when both its ends lie on the
/// segment's line within `tol`; the overlap of the edge with the segment is
/// integrated exactly:
///
/// `f_a = q ∫ (1 − ξ) dt`, `f_b = q ∫ ξ dt` over the overlap, `q = force / |to − from|`.
///
/// Returns the nodal forces and the total length of the segment covered by edges.
pub fn segment_forces(
    edges: &[([usize; 2], [[f64; 2]; 2])],
    from: [f64; 2],
    to: [f64; 2],
    force: [f64; 2],
    tol: f64,
) -> (Vec<(usize, [f64; 2])>, f64) {
    let length = (to[0] - from[0]).hypot(to[1] - from[1]);
    let dir = [(to[0] - from[0]) / length, (to[1] - from[1]) / length];
    let q = [force[0] / length, force[1] / length];
    // Coordinate along the segment and distance from its line.
    let along = |p: [f64; 2]| (p[0] - from[0]) * dir[0] + (p[1] - from[1]) * dir[1];
    let off = |p: [f64; 2]| ((p[0] - from[0]) * dir[1] - (p[1] - from[1]) * dir[0]).abs();
    let mut out = Vec::new();
    let mut covered = 0.0;
    for &(nodes, [a, b]) in edges {
        if off(a) > tol || off(b) > tol {
            continue;
        }
        let (ta, tb) = (along(a), along(b));
        if (tb - ta).abs() <= tol {
            continue;
        }
        let t0 = ta.min(tb).max(0.0);
        let t1 = ta.max(tb).min(length);
        if t1 - t0 <= 0.0 {
            continue;
        }
        covered += t1 - t0;
        let xi = |t: f64| (t - ta) / (tb - ta);
        // ∫ ξ dt over [t0, t1] (ξ is linear in t: midpoint rule is exact).
        let int_xi = (t1 - t0) * 0.5 * (xi(t0) + xi(t1));
        let int_1mxi = (t1 - t0) - int_xi;
        out.push((nodes[0], [q[0] * int_1mxi, q[1] * int_1mxi]));
        out.push((nodes[1], [q[0] * int_xi, q[1] * int_xi]));
    }
    (out, covered)
}

/// Nodal forces of a uniform traction with resultant `force` over the whole chain of
/// `edges` (any shape): each edge takes the share of its length, half to each end.
pub fn chain_forces(
    edges: &[([usize; 2], [[f64; 2]; 2])],
    force: [f64; 2],
) -> Vec<(usize, [f64; 2])> {
    let len = |[a, b]: [[f64; 2]; 2]| (b[0] - a[0]).hypot(b[1] - a[1]);
    let total: f64 = edges.iter().map(|e| len(e.1)).sum();
    edges
        .iter()
        .flat_map(|&(nodes, x)| {
            let w = 0.5 * len(x) / total;
            [
                (nodes[0], [force[0] * w, force[1] * w]),
                (nodes[1], [force[0] * w, force[1] * w]),
            ]
        })
        .collect()
}

/// Nodal forces of a uniform pressure `p` (force per unit length of boundary,
/// positive pushing into the part) over `edges`, counter-clockwise with respect
/// to the part (the outward normal n is the edge direction turned −90°): the
/// traction −p n integrated exactly over each straight edge, half to each end,
/// `f_a = f_b = −p n L / 2 = −(p / 2) (y_b − y_a, −(x_b − x_a))`.
pub fn pressure_forces(edges: &[([usize; 2], [[f64; 2]; 2])], p: f64) -> Vec<(usize, [f64; 2])> {
    edges
        .iter()
        .flat_map(|&(nodes, [a, b])| {
            let f = [-0.5 * p * (b[1] - a[1]), 0.5 * p * (b[0] - a[0])];
            [(nodes[0], f), (nodes[1], f)]
        })
        .collect()
}

/// What a uniform load on a solid part's boundary faces is: a traction (force
/// per area, global components) or a pressure (positive pushing against each
/// face's outward normal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FaceLoad {
    /// A uniform traction `t` (force per area).
    Traction([f64; 3]),
    /// A uniform pressure `p` against the outward normal.
    Pressure(f64),
}

/// Consistent nodal forces of a uniform `load` over the boundary `faces` of a
/// solid mesh of node coordinates `nodes` (each face's integral,
/// [`super::face3`], summed per node): one entry per node touched, in the order
/// the faces first reach it. Also returns the resultant (the sum of the forces).
pub fn face_forces(
    nodes: &[[f64; 3]],
    faces: &[crate::mesh::BoundaryFace],
    load: FaceLoad,
) -> (Vec<(usize, [f64; 3])>, [f64; 3]) {
    use super::face3;
    use crate::mesh::FaceNodes;
    let mut index = std::collections::HashMap::new();
    let mut out: Vec<(usize, [f64; 3])> = Vec::new();
    let mut add = |n: usize, f: [f64; 3]| {
        let k = *index.entry(n).or_insert_with(|| {
            out.push((n, [0.0; 3]));
            out.len() - 1
        });
        for (o, f) in out[k].1.iter_mut().zip(f) {
            *o += f;
        }
    };
    for face in faces {
        match &face.nodes {
            FaceNodes::Tri(n) => {
                let x = n.map(|k| nodes[k]);
                let f = match load {
                    FaceLoad::Traction(t) => face3::triangle_traction_forces(&x, t),
                    FaceLoad::Pressure(p) => face3::triangle_pressure_forces(&x, p),
                };
                n.iter().zip(f).for_each(|(&k, f)| add(k, f));
            }
            FaceNodes::Quad(n) => {
                let x = n.map(|k| nodes[k]);
                let f = match load {
                    FaceLoad::Traction(t) => face3::quad_traction_forces(&x, t),
                    FaceLoad::Pressure(p) => face3::quad_pressure_forces(&x, p),
                };
                n.iter().zip(f).for_each(|(&k, f)| add(k, f));
            }
        }
    }
    let mut total = [0.0; 3];
    for (_, f) in &out {
        for (t, f) in total.iter_mut().zip(f) {
            *t += f;
        }
    }
    (out, total)
}

/// The nodal forces of a load on the parts of faces inside a box (one entry
/// per node touched), their resultant and the loaded area
/// ([`clipped_face_forces`]).
pub type ClippedForces = (Vec<(usize, [f64; 3])>, [f64; 3], f64);

/// Consistent nodal forces of a uniform `load` over the parts of the boundary
/// `faces` (plane faces) inside the box `[lo, hi]` along the axes `clip`,
/// each face cut to the box and its shape functions integrated over the cut
/// polygon ([`super::face3::clipped_shape_integrals`]): a traction gives
/// `t ∫ N_i dA`, a pressure `−p n ∫ N_i dA` (n the face's outward unit
/// normal). As [`face_forces`]: one entry per node touched, and the
/// resultant; also the loaded area. `None` for a degenerate face (its
/// index in `faces`).
pub fn clipped_face_forces(
    nodes: &[[f64; 3]],
    faces: &[crate::mesh::BoundaryFace],
    lo: [f64; 3],
    hi: [f64; 3],
    clip: [bool; 3],
    load: FaceLoad,
) -> std::result::Result<ClippedForces, usize> {
    use super::face3;
    let mut index = std::collections::HashMap::new();
    let mut out: Vec<(usize, [f64; 3])> = Vec::new();
    let mut area = 0.0;
    for (i, face) in faces.iter().enumerate() {
        let corners = face.nodes.as_slice();
        let x: Vec<[f64; 3]> = corners.iter().map(|&k| nodes[k]).collect();
        let (w, a) = face3::clipped_shape_integrals(&x, lo, hi, clip).ok_or(i)?;
        if a == 0.0 {
            continue;
        }
        area += a;
        let per_area = match load {
            FaceLoad::Traction(t) => t,
            FaceLoad::Pressure(p) => {
                let v = face.nodes.vector_area(nodes);
                let l = v[0].hypot(v[1]).hypot(v[2]);
                if l.is_nan() || l <= 0.0 {
                    return Err(i);
                }
                v.map(|c| -p * c / l)
            }
        };
        for (&n, wi) in corners.iter().zip(w) {
            let k = *index.entry(n).or_insert_with(|| {
                out.push((n, [0.0; 3]));
                out.len() - 1
            });
            for (o, t) in out[k].1.iter_mut().zip(per_area) {
                *o += t * wi;
            }
        }
    }
    let mut total = [0.0; 3];
    for (_, f) in &out {
        for (t, f) in total.iter_mut().zip(f) {
            *t += f;
        }
    }
    Ok((out, total, area))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A segment from x = 0.5 to x = 2.5 over unit edges [0,1], [1,2], [2,3]:
    /// resultant and first moment are reproduced exactly (uniform load of 2 over
    /// [0.5, 2.5]: total 2, centroid 1.5), with the partial-edge split by hand:
    /// node 0 gets ∫₀.₅¹ (1 − x) dx = 0.125.
    #[test]
    fn partial_edges_integrate_exactly() {
        let x = |i: usize| [i as f64, 0.0];
        let edges: Vec<_> = (0..3).map(|i| ([i, i + 1], [x(i), x(i + 1)])).collect();
        let (f, covered) = segment_forces(&edges, [0.5, 0.0], [2.5, 0.0], [0.0, -2.0], 1e-9);
        assert!((covered - 2.0).abs() < 1e-14);
        let mut nodal = [0.0; 4];
        for (n, v) in f {
            nodal[n] += v[1];
        }
        assert!((nodal.iter().sum::<f64>() + 2.0).abs() < 1e-14);
        let moment: f64 = nodal.iter().enumerate().map(|(i, v)| v * i as f64).sum();
        assert!((moment + 2.0 * 1.5).abs() < 1e-14);
        assert!((nodal[0] + 0.125).abs() < 1e-14);
    }

    /// A pressure on a closed polygon (a unit square, counter-clockwise) has no
    /// resultant, and on one side gives p × length against the outward normal,
    /// split equally between its two nodes.
    #[test]
    fn pressure_is_normal_and_self_balanced_on_a_closed_boundary() {
        let x = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let edges: Vec<_> = (0..4)
            .map(|i| ([i, (i + 1) % 4], [x[i], x[(i + 1) % 4]]))
            .collect();
        let f = pressure_forces(&edges, 3.0);
        let total = f
            .iter()
            .fold([0.0, 0.0], |s, (_, v)| [s[0] + v[0], s[1] + v[1]]);
        assert!(total[0].abs() < 1e-15 && total[1].abs() < 1e-15);
        // The bottom edge (outward normal −y) is pushed up: 1.5 at each end.
        assert_eq!(f[0], (0, [0.0, 1.5]));
        assert_eq!(f[1], (1, [0.0, 1.5]));
        // The right edge (outward normal +x) is pushed to −x.
        assert_eq!(f[2], (1, [-1.5, 0.0]));
    }

    /// Reversed edge orientation and reversed segment give the same nodal forces.
    #[test]
    fn orientation_does_not_matter() {
        let e1 = [([0, 1], [[0.0, 0.0], [1.0, 0.0]])];
        let e2 = [([1, 0], [[1.0, 0.0], [0.0, 0.0]])];
        let (a, _) = segment_forces(&e1, [0.2, 0.0], [0.9, 0.0], [1.0, 0.0], 1e-9);
        let (b, _) = segment_forces(&e2, [0.9, 0.0], [0.2, 0.0], [1.0, 0.0], 1e-9);
        let get = |v: &[(usize, [f64; 2])], n| v.iter().find(|p| p.0 == n).unwrap().1[0];
        assert!((get(&a, 0) - get(&b, 0)).abs() < 1e-15 && (get(&a, 1) - get(&b, 1)).abs() < 1e-15);
    }

    /// A pressure on the top of a box (TET4 triangles and HEX8 quadrangles)
    /// gives nodal forces summing to −p × area along the outward normal +z, a
    /// tangential traction t × area along t; each node appears once.
    #[test]
    fn face_forces_of_a_box_top_sum_to_load_times_area() {
        use super::{FaceLoad, face_forces};
        use crate::dim::D3;
        use crate::mesh::{Mesh, SolidKind};
        for kind in [SolidKind::Tet4, SolidKind::Hex8] {
            let m = Mesh::<D3>::block([0.0, 2.0], [0.0, 3.0], [0.0, 1.0], [2, 3, 1], kind);
            let top = &m.boundaries["top"];
            let (f, total) = face_forces(&m.nodes, top, FaceLoad::Pressure(5.0));
            assert!((total[2] + 5.0 * 6.0).abs() < 1e-12 * 30.0, "{kind:?} {total:?}");
            assert!(total[0].abs() < 1e-12 && total[1].abs() < 1e-12);
            let mut seen: Vec<usize> = f.iter().map(|(n, _)| *n).collect();
            seen.sort_unstable();
            seen.dedup();
            assert_eq!(seen.len(), f.len());
            assert_eq!(seen, m.boundary_nodes("top").unwrap().into_iter().collect::<std::collections::BTreeSet<_>>().into_iter().collect::<Vec<_>>());
            let (_, t) = face_forces(&m.nodes, top, FaceLoad::Traction([1.5, -2.0, 0.0]));
            assert!((t[0] - 9.0).abs() < 1e-12 && (t[1] + 12.0).abs() < 1e-12 && t[2] == 0.0);
        }
    }
}
