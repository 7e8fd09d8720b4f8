//! Support check: is every part held against rigid-body motion by its Dirichlet
//! conditions and its bonded coupling pairs? Each part is treated as a rigid body
//! with three motions (two translations, one rotation); every fixed DOF and every
//! bonded pair is a constraint row on those motions. The assembly is supported when
//! the constraint rows have full rank; otherwise the null space names the parts that
//! can move freely. This turns a singular stiffness into an error a user can act on.

use crate::assembly::{DofMap, FIXED};
use crate::coupling::{Interface, Law, PairState};
use crate::domain::Part;
use crate::error::{Error, Result};
use faer::{Mat, Side};

/// The constant part of the support check, computed once per model: each part's
/// frame (centre and size, so the rotation column is scaled like the others) and
/// the constraint rows of the fixed DOFs, summed into the Gram matrix `Σ r rᵀ`
/// (one pass over the nodes). [`SupportCheck::check`] then adds only the closed
/// pairs, so a check costs O(pairs) however fine the meshes.
pub struct SupportCheck {
    /// Per part: centre and size.
    frames: Vec<([f64; 2], f64)>,
    /// `Σ r rᵀ` over the fixed DOFs (3 rows and columns per part).
    supports: Mat<f64>,
}

const AXES: [[f64; 2]; 2] = [[1.0, 0.0], [0.0, 1.0]];

impl SupportCheck {
    /// The frames and the supports' rows of `parts` under the DOF map `dofs`.
    pub fn new(parts: &[Part], dofs: &DofMap) -> Self {
        let frames: Vec<([f64; 2], f64)> = parts
            .iter()
            .map(|p| {
                let n = p.mesh.nodes.len() as f64;
                let c = p
                    .mesh
                    .nodes
                    .iter()
                    .fold([0.0, 0.0], |a, x| [a[0] + x[0] / n, a[1] + x[1] / n]);
                let size = p
                    .mesh
                    .nodes
                    .iter()
                    .map(|x| crate::mesh::dist(*x, c))
                    .fold(0.0, f64::max)
                    .max(1e-300);
                (c, size)
            })
            .collect();
        let np = parts.len();
        let mut check = SupportCheck {
            frames,
            supports: Mat::<f64>::zeros(3 * np, 3 * np),
        };
        let mut g = Mat::<f64>::zeros(3 * np, 3 * np);
        for (p, part) in parts.iter().enumerate() {
            for (n, x) in part.mesh.nodes.iter().enumerate() {
                let gn = dofs.node(p, n);
                for (c, axis) in AXES.iter().enumerate() {
                    if dofs.eq[2 * gn + c] == FIXED {
                        let r = check.row(p, *x, *axis);
                        add(&mut g, &[(3 * p, r[0]), (3 * p + 1, r[1]), (3 * p + 2, r[2])]);
                    }
                }
            }
        }
        check.supports = g;
        check
    }

    /// Rigid-body row of part `p` for a motion component along `d` at point `x`.
    fn row(&self, p: usize, x: [f64; 2], d: [f64; 2]) -> [f64; 3] {
        let (c, s) = self.frames[p];
        let (rx, ry) = ((x[0] - c[0]) / s, (x[1] - c[1]) / s);
        [d[0], d[1], -ry * d[0] + rx * d[1]]
    }

    /// Checks that the parts cannot move as rigid bodies under the supports and
    /// the closed pairs in `states` (each along the directions its law
    /// stiffens). Returns an error naming every part that can.
    pub fn check(
        &self,
        parts: &[Part],
        interfaces: &[Interface],
        states: &[Vec<PairState>],
    ) -> Result<()> {
        let np = parts.len();
        let mut g = self.supports.clone();
        for (iface, st) in interfaces.iter().zip(states) {
            let (h, q) = (iface.host, iface.node_part);
            let law = iface.params();
            for (c, &s) in iface.elements.iter().zip(st) {
                // A pair constrains the directions its penalties act in: both when
                // bonded or slipping (x and y: a slipping pair keeps its stabilising
                // spring), the normal only when frictionless.
                let [k_n, k_s] = law.penalties(s);
                let directions: &[[f64; 2]] = match (k_n > 0.0, k_s > 0.0) {
                    (true, true) => &AXES,
                    (true, false) => &[c.normal],
                    (false, true) => &[[-c.normal[1], c.normal[0]]],
                    (false, false) => &[],
                };
                for &axis in directions {
                    let (rh, rq) = (self.row(h, c.position, axis), self.row(q, c.position, axis));
                    add(&mut g, &[
                        (3 * q, rq[0]),
                        (3 * q + 1, rq[1]),
                        (3 * q + 2, rq[2]),
                        (3 * h, -rh[0]),
                        (3 * h + 1, -rh[1]),
                        (3 * h + 2, -rh[2]),
                    ]);
                }
            }
        }
        let eig = g
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| Error::Singular(format!("support check failed: {e:?}")))?;
        let s = eig.S();
        let u = eig.U();
        let lmax = (0..3 * np).map(|i| s[i].abs()).fold(1.0, f64::max);
        let mut free = vec![false; np];
        for k in 0..3 * np {
            if s[k] > 1e-10 * lmax {
                continue;
            }
            for (p, f) in free.iter_mut().enumerate() {
                let w: f64 = (0..3).map(|c| u[(3 * p + c, k)].powi(2)).sum();
                if w > 1e-6 {
                    *f = true;
                }
            }
        }
        if free.iter().any(|&f| f) {
            Err(unsupported(parts, interfaces, states, &free))
        } else {
            Ok(())
        }
    }
}

/// Adds the outer product `Σ a b` of the sparse row `entries` to `g`.
fn add(g: &mut Mat<f64>, entries: &[(usize, f64)]) {
    for &(i, a) in entries {
        for &(j, b) in entries {
            g[(i, j)] += a * b;
        }
    }
}

/// The error naming the parts that are `free` to move, each with how many of its
/// coupling pairs are open in `states`.
fn unsupported(
    parts: &[Part],
    interfaces: &[Interface],
    states: &[Vec<PairState>],
    free: &[bool],
) -> Error {
    let names: Vec<String> = (0..parts.len())
        .filter(|&p| free[p])
        .map(|p| {
            let pairs: usize = interfaces
                .iter()
                .zip(states)
                .filter(|(i, _)| i.host == p || i.node_part == p)
                .map(|(_, st)| st.len())
                .sum();
            let open: usize = interfaces
                .iter()
                .zip(states)
                .filter(|(i, _)| i.host == p || i.node_part == p)
                .map(|(_, st)| st.iter().filter(|&&s| s == PairState::Open).count())
                .sum();
            // Closed pairs with no tangential stiffness: frictionless.
            let sliding: usize = interfaces
                .iter()
                .zip(states)
                .filter(|(i, _)| i.host == p || i.node_part == p)
                .map(|(i, st)| {
                    let law = i.params();
                    st.iter()
                        .filter(|&&s| s != PairState::Open && law.penalties(s)[1] == 0.0)
                        .count()
                })
                .sum();
            // Its Coulomb interfaces' slipping pairs.
            let coulomb = interfaces
                .iter()
                .zip(states)
                .filter(|(i, _)| (i.host == p || i.node_part == p) && i.law == Law::Coulomb);
            let (mut frictional, mut slipping) = (false, 0);
            for (_, st) in coulomb {
                frictional = true;
                slipping += st.iter().filter(|&&s| s == PairState::Slip).count();
            }
            if sliding > 0 {
                format!(
                    "'{}' ({open} of its {pairs} coupling pairs open, {sliding} closed but sliding freely: frictionless pairs carry no tangential force, so hold the part tangentially with a [[support]])",
                    parts[p].name
                )
            } else if frictional && open < pairs {
                // Free though touching on a frictional face: friction does not
                // hold it. (With every pair open it was pulled away: the plain
                // message, which says the loads should press the parts together.)
                format!(
                    "'{}' ({open} of its {pairs} coupling pairs open, {slipping} slipping: a part pushed along its faces harder than friction holds it, more than μ × the force pressing them together, has no position of rest)",
                    parts[p].name
                )
            } else {
                format!(
                    "'{}' ({open} of its {pairs} coupling pairs open)",
                    parts[p].name
                )
            }
        })
        .collect();
    Error::Unsupported {
        parts: (0..parts.len())
            .filter(|&p| free[p])
            .map(|p| parts[p].name.clone())
            .collect(),
        message: format!(
            "part(s) {} left without support: they can move as rigid bodies. Add a [[support]], or check that the loads press the parts together",
            names.join(", ")
        ),
    }
}
