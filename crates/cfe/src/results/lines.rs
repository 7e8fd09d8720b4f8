//! Line probes (`[[line]]`): a straight line through the parts, sampled at
//! evenly spaced points for the displacement and the stresses there, as
//! `lines/<name>.csv` and `lines/<name>.png` are written and Python's
//! `result.lines[name]` reads them.
//!
//! Each point is located in the element that contains it (the first, in part
//! and element order, for a point on a shared edge), once, from the reference
//! mesh: only elements whose bounding box meets the line's are tested, so a
//! line costs O(elements) once and O(points × elements along it). The
//! displacement is the element's interpolation at the point (its shape
//! functions); the stress is the element's own there — constant in a T3,
//! B(ξ, η) u in a Q4 — never an average across elements or parts.

use crate::domain::Part;
use crate::fem::{axisymmetric, element, q4};
use crate::mesh::Element;

/// A line probe as the model holds it: checked (a nonzero length, at least
/// two points, its part, if any, known), its points located in the parts.
#[derive(Debug, Clone, PartialEq)]
pub struct LineProbe {
    /// Its name (letters, digits, `-`, `_`): the file names `lines/<name>.*`.
    pub name: String,
    /// Start point.
    pub from: [f64; 2],
    /// End point.
    pub to: [f64; 2],
    /// The sample points' locations, in order from `from` to `to`: the
    /// distance s from `from`, the point, and where it lies (none: outside
    /// every part searched, left out of the outputs).
    pub points: Vec<(f64, [f64; 2], Option<Located>)>,
}

/// Where a sample point lies: its part, element, and the element's shape
/// functions and (Q4) natural coordinates there.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Located {
    /// The part (index in the model).
    pub part: usize,
    /// The element (index in the part's mesh).
    pub element: usize,
    /// The shape functions at the point, one per element node (T3: the first
    /// three).
    pub shape: [f64; 4],
    /// The Q4's natural coordinates (0 for a T3).
    pub xi: [f64; 2],
}

/// One sample of a line at a solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LineSample {
    /// Distance from the line's start.
    pub s: f64,
    /// The point.
    pub x: [f64; 2],
    /// The part it lies in.
    pub part: usize,
    /// Displacement (ux, uy).
    pub u: [f64; 2],
    /// Stress (σxx, σyy, σxy).
    pub stress: [f64; 3],
    /// Von Mises stress (the part's plane condition; with σθθ in an
    /// axisymmetric part, whose (σxx, σyy, σxy) are (σrr, σzz, σrz) with the
    /// hoop strain).
    pub von_mises: f64,
}

/// Relative slack of the inside tests (of a natural or barycentric
/// coordinate): a point on an edge is inside both elements that share it.
const INSIDE: f64 = 1e-9;

/// The `n` (≥ 2) evenly spaced points from `from` to `to` located in `parts`
/// (only part `only` when given).
pub fn locate(
    parts: &[Part],
    only: Option<usize>,
    name: &str,
    from: [f64; 2],
    to: [f64; 2],
    n: usize,
) -> LineProbe {
    let length = (to[0] - from[0]).hypot(to[1] - from[1]);
    let at = |k: usize| {
        let t = k as f64 / (n - 1) as f64;
        (
            t * length,
            [
                from[0] + t * (to[0] - from[0]),
                from[1] + t * (to[1] - from[1]),
            ],
        )
    };
    let (lo, hi) = (
        [from[0].min(to[0]), from[1].min(to[1])],
        [from[0].max(to[0]), from[1].max(to[1])],
    );
    // Candidate elements: those whose bounding box (grown by the slack) meets
    // the line's.
    let mut candidates: Vec<(usize, usize, [f64; 2], [f64; 2])> = Vec::new();
    for (p, part) in parts.iter().enumerate() {
        if only.is_some_and(|o| o != p) {
            continue;
        }
        let mesh = &part.mesh;
        for (e, el) in mesh.elements.iter().enumerate() {
            let x = element::coordinates(mesh, el);
            let m = el.nodes().len();
            let (mut a, mut b) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
            for xi in &x[..m] {
                for c in 0..2 {
                    a[c] = a[c].min(xi[c]);
                    b[c] = b[c].max(xi[c]);
                }
            }
            let slack = INSIDE * (b[0] - a[0]).max(b[1] - a[1]);
            let (a, b) = ([a[0] - slack, a[1] - slack], [b[0] + slack, b[1] + slack]);
            if a[0] <= hi[0] && b[0] >= lo[0] && a[1] <= hi[1] && b[1] >= lo[1] {
                candidates.push((p, e, a, b));
            }
        }
    }
    let points = (0..n)
        .map(|k| {
            let (s, x) = at(k);
            let found = candidates
                .iter()
                .filter(|(_, _, a, b)| x[0] >= a[0] && x[0] <= b[0] && x[1] >= a[1] && x[1] <= b[1])
                .find_map(|&(p, e, _, _)| inside(&parts[p], p, e, x));
            (s, x, found)
        })
        .collect();
    LineProbe {
        name: name.to_string(),
        from,
        to,
        points,
    }
}

/// The first element of `part` (index `p`, in element order) that contains
/// `x`, and where (`None`: outside the part).
pub fn locate_point(part: &Part, p: usize, x: [f64; 2]) -> Option<Located> {
    (0..part.mesh.elements.len()).find_map(|e| inside(part, p, e, x))
}

/// Whether `x` lies in element `e` of `part` (index `p`), and where.
fn inside(part: &Part, p: usize, e: usize, x: [f64; 2]) -> Option<Located> {
    let mesh = &part.mesh;
    let el = &mesh.elements[e];
    let c = element::coordinates(mesh, el);
    match el {
        Element::T3(_) => {
            let [a, b, d] = [c[0], c[1], c[2]];
            let det = (b[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (b[1] - a[1]);
            if det == 0.0 || !det.is_finite() {
                return None;
            }
            let l1 = ((x[0] - a[0]) * (d[1] - a[1]) - (d[0] - a[0]) * (x[1] - a[1])) / det;
            let l2 = ((b[0] - a[0]) * (x[1] - a[1]) - (x[0] - a[0]) * (b[1] - a[1])) / det;
            let l0 = 1.0 - l1 - l2;
            [l0, l1, l2]
                .iter()
                .all(|&l| l >= -INSIDE)
                .then_some(Located {
                    part: p,
                    element: e,
                    shape: [l0, l1, l2, 0.0],
                    xi: [0.0; 2],
                })
        }
        Element::Q4(_) => {
            let xi = q4::natural_coordinates(&[c[0], c[1], c[2], c[3]], x)?;
            (xi[0].abs() <= 1.0 + INSIDE && xi[1].abs() <= 1.0 + INSIDE).then(|| Located {
                part: p,
                element: e,
                shape: q4::shape(xi),
                xi,
            })
        }
    }
}

/// The samples of `line` at the displacements `u` (2 per global node, the
/// parts' nodes numbered from `node_offset[p]`): the points that lie in a part.
pub fn sample(
    line: &LineProbe,
    parts: &[Part],
    node_offset: &[usize],
    u: &[f64],
) -> Vec<LineSample> {
    line.points
        .iter()
        .filter_map(|&(s, x, at)| {
            let at = at?;
            let part = &parts[at.part];
            let mesh = &part.mesh;
            let el = &mesh.elements[at.element];
            let base = node_offset[at.part];
            let nodes = el.nodes();
            let mut ue = [0.0; element::MAX_DOFS];
            for (i, &n) in nodes.iter().enumerate() {
                let g = base + n;
                ue[2 * i] = u[2 * g];
                ue[2 * i + 1] = u[2 * g + 1];
            }
            let disp: [f64; 2] = std::array::from_fn(|c| {
                (0..nodes.len()).map(|i| at.shape[i] * ue[2 * i + c]).sum()
            });
            let xe = element::coordinates(mesh, el);
            if part.material.is_axisymmetric() {
                // (σrr, σzz, σrz) with the hoop strain; von Mises with σθθ.
                let d = part.material.d_axisymmetric();
                let [rr, zz, rz, hoop] =
                    axisymmetric::stress_at(el, &xe, &d, &ue, &at.shape, at.xi);
                return Some(LineSample {
                    s,
                    x,
                    part: at.part,
                    u: disp,
                    stress: [rr, zz, rz],
                    von_mises: part.material.von_mises_with([rr, zz, rz], Some(hoop)),
                });
            }
            let d = part.material.d_matrix();
            let stress = match el {
                Element::T3(_) => element::stresses(el, &xe, &d, &ue).element,
                Element::Q4(_) => {
                    let u8: [f64; 8] = std::array::from_fn(|i| ue[i]);
                    q4::stress_at(&[xe[0], xe[1], xe[2], xe[3]], &d, &u8, at.xi)
                }
            };
            Some(LineSample {
                s,
                x,
                part: at.part,
                u: disp,
                stress,
                von_mises: part.material.von_mises(stress),
            })
        })
        .collect()
}
