//! Support check: is every part held against rigid-body motion by its Dirichlet
//! conditions and its bonded coupling pairs? Each part is treated as a rigid body
//! with `D::RIGID_MODES` motions ([`Dim::rigid_mode`]: in 2D two translations
//! and one rotation, in 3D three of each); every fixed DOF and every bonded pair
//! is a constraint row on those motions. The assembly is supported when the
//! constraint rows have full rank; otherwise the null space names the parts that
//! can move freely. This turns a singular stiffness into an error a user can act
//! on.
//!
//! [`super::friction_hold::FrictionHold`] asks the question before any solve
//! for a part (or parts taken together) held along its faces by friction alone.

use crate::assembly::{DofMap, FIXED};
use crate::coupling::{Interface, Law, PairState};
use crate::dim::{D2, Dim, Tangent};
use crate::domain::Part;
use crate::error::{Error, Result};
use faer::{Mat, Side};

/// Most rigid-body modes of a part in any dimension (6 in 3D).
const MAX_MODES: usize = 6;

/// The constant part of the support check, computed once per model: each part's
/// frame (centre and size, so the rotation columns are scaled like the others) and
/// the constraint rows of the fixed DOFs, summed into the Gram matrix `Σ r rᵀ`
/// (one pass over the nodes). [`SupportCheck::check`] then adds only the closed
/// pairs, so a check costs O(pairs) however fine the meshes.
pub struct SupportCheck<D: Dim = D2> {
    /// Per part: centre and size.
    frames: Vec<(D::Vector, f64)>,
    /// `Σ r rᵀ` over the fixed DOFs (`D::RIGID_MODES` rows and columns per part).
    supports: Mat<f64>,
    /// Per part: whether a support fixes any of its DOFs.
    supported: Vec<bool>,
}

/// The entries of part `p`'s rigid-body row `r` in the Gram matrix:
/// `(M p + m, r[m])` for the part's M = `D::RIGID_MODES` modes m.
fn entries<D: Dim>(p: usize, r: &[f64; MAX_MODES]) -> [(usize, f64); MAX_MODES] {
    let m = D::RIGID_MODES;
    std::array::from_fn(|k| if k < m { (m * p + k, r[k]) } else { (0, 0.0) })
}

impl<D: Dim> SupportCheck<D> {
    /// The frames and the supports' rows of `parts` under the DOF map `dofs`.
    pub fn new(parts: &[Part], dofs: &DofMap<D>) -> Self {
        let axisymmetric: Vec<bool> = parts.iter().map(|p| p.material.is_axisymmetric()).collect();
        SupportCheck::from_positions(&dofs.positions(parts), dofs, &axisymmetric)
    }

    /// The check of parts whose global nodes (numbered by `dofs`) are at
    /// `positions`, `axisymmetric[p]` telling whether part p is an axisymmetric
    /// (plane) one.
    pub fn from_positions(positions: &[D::Vector], dofs: &DofMap<D>, axisymmetric: &[bool]) -> Self {
        let np = axisymmetric.len();
        let mut check = SupportCheck {
            frames: (0..np).map(|p| frame::<D>(&positions[nodes_of(dofs, p)])).collect(),
            supports: Mat::<f64>::zeros(D::RIGID_MODES * np, D::RIGID_MODES * np),
            supported: (0..np).map(|p| has_support(dofs, p)).collect(),
        };
        check.supports = check.supports_gram(positions, dofs, axisymmetric);
        check
    }

    /// `Σ r rᵀ` over the DOFs `dofs` fixes (node g at `positions[g]`), and for
    /// each axisymmetric part the rows that hold its radial translation and its
    /// in-plane rotation.
    fn supports_gram(&self, positions: &[D::Vector], dofs: &DofMap<D>, axisymmetric: &[bool]) -> Mat<f64> {
        let m = D::RIGID_MODES;
        let mut g = Mat::<f64>::zeros(m * self.frames.len(), m * self.frames.len());
        for p in 0..self.frames.len() {
            for gn in nodes_of(dofs, p) {
                for c in 0..D::N {
                    if dofs.eq[D::dof(gn, c)] == FIXED {
                        let r = self.row(p, positions[gn], unit::<D>(c));
                        add(&mut g, &entries::<D>(p, &r)[..m]);
                    }
                }
            }
        }
        // An axisymmetric part's only rigid motion is along the axis: a radial
        // translation (mode 0) or an in-plane rotation (mode 2) strains its
        // rings (the hoop strain u_r / r), so they are held whatever its
        // supports. (Axisymmetric parts are plane ones.)
        for (p, _) in axisymmetric.iter().enumerate().filter(|(_, a)| **a) {
            add(&mut g, &[(m * p, 1.0)]);
            add(&mut g, &[(m * p + 2, 1.0)]);
        }
        g
    }

    /// Rigid-body row of part `p` for a motion component along `d` at point
    /// `x`: `d · v_k((x − c) / size)` for each rigid mode `v_k`.
    fn row(&self, p: usize, x: D::Vector, d: D::Vector) -> [f64; MAX_MODES] {
        let (c, s) = self.frames[p];
        let mut r = D::Vector::default();
        for i in 0..D::N {
            r.as_mut()[i] = (x.as_ref()[i] - c.as_ref()[i]) / s;
        }
        let mut row = [0.0; MAX_MODES];
        for (k, v) in row.iter_mut().enumerate().take(D::RIGID_MODES) {
            *v = D::dot(d.as_ref(), D::rigid_mode(k, r).as_ref());
        }
        row
    }

    /// Checks that the parts cannot move as rigid bodies under the supports and
    /// the closed pairs in `states` (each along the directions its law
    /// stiffens). Returns an error naming every part that can.
    pub fn check(
        &self,
        parts: &[Part],
        interfaces: &[Interface<D>],
        states: &[Vec<PairState>],
    ) -> Result<()> {
        let free = self.free_parts(interfaces, states)?;
        if free.iter().any(|&f| f) {
            Err(unsupported(parts, interfaces, states, &free, &self.supported))
        } else {
            Ok(())
        }
    }

    /// Per part, whether it can move as a rigid body under the supports and
    /// the closed pairs of `interfaces` in `states`: the null space of the
    /// Gram matrix of their rows.
    pub fn free_parts(&self, interfaces: &[Interface<D>], states: &[Vec<PairState>]) -> Result<Vec<bool>> {
        let m = D::RIGID_MODES;
        let np = self.frames.len();
        let mut g = self.supports.clone();
        for (iface, st) in interfaces.iter().zip(states) {
            self.add_pairs(&mut g, iface, st);
        }
        let eig = g
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| Error::Singular(format!("support check failed: {e:?}")))?;
        let s = eig.S();
        let u = eig.U();
        let lmax = (0..m * np).map(|i| s[i].abs()).fold(1.0, f64::max);
        let mut free = vec![false; np];
        for k in 0..m * np {
            if s[k] > 1e-10 * lmax {
                continue;
            }
            for (p, f) in free.iter_mut().enumerate() {
                let w: f64 = (0..m).map(|c| u[(m * p + c, k)].powi(2)).sum();
                if w > 1e-6 {
                    *f = true;
                }
            }
        }
        Ok(free)
    }

    /// Adds to `g` the rows of the closed pairs of `iface` in `states`: a pair
    /// constrains the directions its penalties act in — every axis when bonded
    /// or slipping (a slipping pair keeps its stabilising spring), the normal
    /// only when frictionless — between its node part and its host.
    fn add_pairs(&self, g: &mut Mat<f64>, iface: &Interface<D>, states: &[PairState]) {
        let m = D::RIGID_MODES;
        let (h, q) = (iface.host, iface.node_part);
        let law = iface.params();
        for (c, &s) in iface.elements.iter().zip(states) {
            let [k_n, k_s] = law.penalties(s);
            let frame = D::frame(c.normal);
            let axes = match (k_n > 0.0, k_s > 0.0) {
                (true, true) => 0..D::N,
                (true, false) => 0..1,
                (false, true) => 1..1 + <D::Tangent as Tangent>::COMPONENTS,
                (false, false) => 0..0,
            };
            for k in axes {
                // Both in global axes when bonded (x, y, …), else the frame's.
                let axis = if k_s > 0.0 && k_n > 0.0 { unit::<D>(k) } else { D::axis(&frame, k) };
                let (rh, rq) = (self.row(h, c.position, axis), self.row(q, c.position, axis));
                let (eq, eh) = (entries::<D>(q, &rq), entries::<D>(h, &rh.map(|v| -v)));
                let both: [(usize, f64); 2 * MAX_MODES] =
                    std::array::from_fn(|j| if j < m { eq[j] } else if j < 2 * m { eh[j - m] } else { (0, 0.0) });
                add(g, &both[..2 * m]);
            }
        }
    }
}

/// The unit vector along axis `c`.
fn unit<D: Dim>(c: usize) -> D::Vector {
    let mut e = D::Vector::default();
    e.as_mut()[c] = 1.0;
    e
}

/// The global nodes of part `p`.
pub(super) fn nodes_of<D: Dim>(dofs: &DofMap<D>, p: usize) -> std::ops::Range<usize> {
    dofs.node_offset[p]..dofs.node_offset[p + 1]
}

/// The centre of the points `x` and their largest distance from it (at least
/// 1e-300): a part's frame.
fn frame<D: Dim>(x: &[D::Vector]) -> (D::Vector, f64) {
    let n = x.len() as f64;
    let c = x.iter().fold(D::Vector::default(), |mut a, x| {
        for i in 0..D::N {
            a.as_mut()[i] += x.as_ref()[i] / n;
        }
        a
    });
    let size = x
        .iter()
        .map(|x| {
            let mut d = D::Vector::default();
            for i in 0..D::N {
                d.as_mut()[i] = c.as_ref()[i] - x.as_ref()[i];
            }
            D::length(d.as_ref())
        })
        .fold(0.0, f64::max)
        .max(1e-300);
    (c, size)
}

/// Adds the outer product `Σ a b` of the sparse row `entries` to `g`.
fn add(g: &mut Mat<f64>, entries: &[(usize, f64)]) {
    for &(i, a) in entries {
        for &(j, b) in entries {
            g[(i, j)] += a * b;
        }
    }
}

/// Whether a support fixes any DOF of part `p`.
pub(super) fn has_support<D: Dim>(dofs: &DofMap<D>, p: usize) -> bool {
    let nodes = nodes_of(dofs, p);
    dofs.eq[D::dof(nodes.start, 0)..D::dof(nodes.end, 0)].contains(&FIXED)
}

/// The groups of parts linked by any interface in which no part has a support
/// (`supported` per part): whatever the pairs do, each moves as one rigid body.
pub(super) fn unheld_groups<D: Dim>(
    n: usize,
    interfaces: &[Interface<D>],
    supported: &[bool],
) -> Vec<Vec<usize>> {
    groups(n, interfaces.iter().map(|i| (i.host, i.node_part)))
        .into_iter()
        .filter(|g| g.iter().all(|&p| !supported[p]))
        .collect()
}

/// The error naming the parts that are `free` to move. First the groups of
/// parts with no support at all (`supported` per part), whose interfaces cannot
/// help: the whole assembly, or the parts named; then every other free part
/// with how many of its coupling pairs are open in `states` (and, on a
/// frictional or frictionless face, why its pairs do not hold it).
fn unsupported<D: Dim>(
    parts: &[Part],
    interfaces: &[Interface<D>],
    states: &[Vec<PairState>],
    free: &[bool],
    supported: &[bool],
) -> Error {
    let unheld = unheld_groups(parts.len(), interfaces, supported);
    let mut clauses = unheld_clauses(parts, interfaces, &unheld);
    let names: Vec<String> = (0..parts.len())
        .filter(|&p| free[p] && !unheld.iter().any(|g| g.contains(&p)))
        .map(|p| free_part(parts, interfaces, states, p))
        .collect();
    if !names.is_empty() {
        clauses.push(format!(
            "part(s) {} left without support: they can move as rigid bodies. Add a [[support]], or check that the loads press the parts together",
            names.join(", ")
        ));
    }
    Error::Unsupported {
        parts: (0..parts.len())
            .filter(|&p| free[p])
            .map(|p| parts[p].name.clone())
            .collect(),
        message: clauses.join("; "),
    }
}

/// The parts of `g` quoted and listed.
fn quote(parts: &[Part], g: &[usize]) -> String {
    g.iter()
        .map(|&p| format!("'{}'", parts[p].name))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A clause per group of parts with no support at all (`unheld`): the whole
/// assembly, a part alone, or parts linked only to each other.
fn unheld_clauses<D: Dim>(parts: &[Part], interfaces: &[Interface<D>], unheld: &[Vec<usize>]) -> Vec<String> {
    if unheld.len() == 1 && unheld[0].len() == parts.len() {
        return vec![format!(
            "the assembly has no support: no [[support]] fixes any part ({}), so it moves as a rigid body whatever its interfaces do. Add a [[support]] that holds it (x, y and a rotation)",
            quote(parts, &unheld[0])
        )];
    }
    unheld
        .iter()
        .map(|g| {
            let linked = interfaces
                .iter()
                .any(|i| g.contains(&i.host) || g.contains(&i.node_part));
            match (g.len(), linked) {
                (1, false) => format!(
                    "part {} has no support and no interface: nothing holds it; add a [[support]] or an [[interface]] to a supported part",
                    quote(parts, g)
                ),
                (1, true) => format!(
                    "part {} has no support, and its interfaces link it to no supported part: add a [[support]]",
                    quote(parts, g)
                ),
                _ => format!(
                    "parts {} have no support, and their interfaces link them to no supported part, so they move together as a rigid body: add a [[support]] to one of them",
                    quote(parts, g)
                ),
            }
        })
        .collect()
}

/// Free part `p` described by its coupling pairs in `states`: how many are
/// open, and, on a frictionless or frictional face, why they do not hold it.
fn free_part<D: Dim>(parts: &[Part], interfaces: &[Interface<D>], states: &[Vec<PairState>], p: usize) -> String {
    // Its pairs, open ones, closed ones with no tangential stiffness
    // (frictionless: sliding freely), and its Coulomb interfaces' slipping pairs.
    let (mut pairs, mut open, mut sliding, mut slipping) = (0, 0, 0, 0);
    let mut frictional = false;
    let touching = interfaces
        .iter()
        .zip(states)
        .filter(|(i, _)| i.host == p || i.node_part == p);
    for (i, st) in touching {
        let law = i.params();
        frictional |= i.law == Law::Coulomb;
        pairs += st.len();
        for &s in st {
            match s {
                PairState::Open => open += 1,
                PairState::Slip => slipping += 1,
                PairState::Bonded => {}
            }
            if s != PairState::Open && law.penalties(s)[1] == 0.0 {
                sliding += 1;
            }
        }
    }
    if sliding > 0 {
        format!(
            "'{}' ({open} of its {pairs} coupling pairs open, {sliding} closed but sliding freely: frictionless pairs carry no tangential force, so hold the part tangentially with a [[support]])",
            parts[p].name
        )
    } else if frictional && open < pairs {
        // Free though touching on a frictional face: friction does not hold
        // it. (With every pair open it was pulled away: the plain message,
        // which says the loads should press the parts together.)
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
}

/// The connected groups of `n` parts under the `links` (pairs of parts: an
/// interface's host and node part), each sorted, in the order of their smallest
/// part.
pub(super) fn groups(n: usize, links: impl Iterator<Item = (usize, usize)>) -> Vec<Vec<usize>> {
    let mut root: Vec<usize> = (0..n).collect();
    fn find(root: &mut [usize], mut p: usize) -> usize {
        while root[p] != p {
            root[p] = root[root[p]];
            p = root[p];
        }
        p
    }
    for (a, b) in links {
        let (a, b) = (find(&mut root, a), find(&mut root, b));
        root[a.max(b)] = a.min(b);
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut index = vec![usize::MAX; n];
    for p in 0..n {
        let r = find(&mut root, p);
        if index[r] == usize::MAX {
            index[r] = groups.len();
            groups.push(Vec::new());
        }
        groups[index[r]].push(p);
    }
    groups
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dim::D3;

    /// The groups of parts linked by interfaces: 0–1–2 and 3–4 linked, 5 alone.
    #[test]
    fn groups_are_the_connected_parts() {
        let links = [(2, 1), (4, 3), (0, 1)];
        assert_eq!(groups(6, links.into_iter()), vec![vec![0, 1, 2], vec![3, 4], vec![5]]);
        assert_eq!(groups(2, std::iter::empty()), vec![vec![0], vec![1]]);
    }

    /// A solid body (the 8 corners of a box) is free with no support, still
    /// free with 3 collinear points fixed in x, y, z (it turns about their
    /// line), and held when 3 non-collinear points are fixed in every
    /// component — and held with fewer components: the 3-2-1 rule (one point
    /// in x, y, z, one in y, z, one in z, none on a common line) fixes the 6
    /// rigid modes exactly.
    #[test]
    fn a_solid_body_is_held_by_three_non_collinear_points() {
        let corners: Vec<[f64; 3]> = (0..8)
            .map(|i| [(i & 1) as f64 * 2.0, ((i >> 1) & 1) as f64, ((i >> 2) & 1) as f64 * 0.5])
            .collect();
        let support = |fixes: &[(usize, [bool; 3])]| -> Vec<crate::domain::Support> {
            fixes
                .iter()
                .map(|&(node, fix)| crate::domain::Support {
                    name: format!("n{node}"),
                    part: 0,
                    nodes: vec![node],
                    fix,
                    value: [0.0; 3],
                    step: 0,
                })
                .collect()
        };
        let free = |fixes: &[(usize, [bool; 3])]| {
            let dofs = DofMap::<D3>::numbered(&[8], &support(fixes));
            let check = SupportCheck::<D3>::from_positions(&corners, &dofs, &[false]);
            check.free_parts(&[], &[]).unwrap()[0]
        };
        let all = [true; 3];
        assert!(free(&[]));
        // Nodes 0, 1 (and its mirror along x): on the line y = z = 0.
        assert!(free(&[(0, all), (1, all)]));
        // 0, 1, 2 are not collinear: held.
        assert!(!free(&[(0, all), (1, all), (2, all)]));
        // 3-2-1: node 0 in x, y, z; node 1 in y, z; node 2 in z.
        assert!(!free(&[(0, all), (1, [false, true, true]), (2, [false, false, true])]));
        // Without node 2's z the body turns about the x axis through 0 and 1.
        assert!(free(&[(0, all), (1, [false, true, true])]));
    }

    /// The plane check through the same code: a square fixed at one corner in
    /// x and y turns about it; a second corner fixed in y holds it.
    #[test]
    fn a_plane_body_is_held_by_a_pin_and_a_roller() {
        let corners = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        let support = |node: usize, fix: [bool; 3]| crate::domain::Support {
            name: "s".into(),
            part: 0,
            nodes: vec![node],
            fix,
            value: [0.0; 3],
            step: 0,
        };
        let pin = support(0, [true, true, false]);
        let dofs = DofMap::<D2>::numbered(&[4], std::slice::from_ref(&pin));
        let check = SupportCheck::<D2>::from_positions(&corners, &dofs, &[false]);
        assert_eq!(check.free_parts(&[], &[]).unwrap(), vec![true]);
        let dofs = DofMap::<D2>::numbered(&[4], &[pin, support(1, [false, true, false])]);
        let check = SupportCheck::<D2>::from_positions(&corners, &dofs, &[false]);
        assert_eq!(check.free_parts(&[], &[]).unwrap(), vec![false]);
    }
}
