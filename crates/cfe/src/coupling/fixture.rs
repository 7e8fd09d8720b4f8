//! A hand-built interface for the unit tests of the law check and the history
//! rules: one T3 host element (nodes (0, 0), (1, 0), (0, 1), part 0) whose edge
//! on y = 0 (outward normal (0, −1)) carries `n` coupling nodes of a node part
//! (part 1) at x = (j + 1) / (n + 1). With the host at rest, node j displaced by
//! (a, b) has the local jump ([[u_n]], [[u_s]]) = (−b, a): [`displaced`] sets the
//! pairs' gaps and tangential jumps directly.

use super::element::CouplingElement;
use super::law::{Enforcement, Law};
use super::{Coupling, Interface};
use crate::dim::{D2, Dim};
use crate::dofs::DofMap;

/// An interface of `law` with `n` node CFEs on the fixture's host edge (penalties
/// c_n = 10, c_s = 4, c_slip = 0.4 for Coulomb, friction μ).
pub fn interface(law: Law, n: usize, friction: f64) -> Interface {
    let elements = (0..n)
        .map(|j| {
            let x = (j + 1) as f64 / (n + 1) as f64;
            CouplingElement {
                node: j,
                host_element: 0,
                host_nodes: vec![0, 1, 2],
                shape: vec![1.0 - x, x, 0.0],
                normal: [0.0, -1.0],
                frame: D2::frame([0.0, -1.0]),
                position: [x, 0.0],
                distance: 0.0,
                gap0: 0.0,
                tributary: 1.0,
                edge_length: 1.0,
                ring: 1.0,
                segment: None,
            }
        })
        .collect();
    Interface {
        name: "fixture".into(),
        host: 0,
        node_part: 1,
        law,
        c_n: 10.0,
        c_s: 4.0,
        c_slip: if law == Law::Coulomb { 0.4 } else { 0.0 },
        elements,
        max_projection_distance: 0.0,
        friction,
        enforcement: Enforcement::Penalty,
        penetration_tolerance: 0.0,
        unpaired: 0,
        coupling: Coupling::Node,
        form: super::CouplingForm::Face,
    }
}

/// The DOF map of the host's 3 nodes and `n` node-part nodes, all free.
pub fn dofs(n: usize) -> DofMap {
    let nodes = 3 + n;
    DofMap {
        node_offset: vec![0, 3, nodes],
        eq: (0..2 * nodes).collect(),
        n_eq: 2 * nodes,
        prescribed: vec![0.0; 2 * nodes],
        fixed: Vec::new(),
        dim: std::marker::PhantomData,
    }
}

/// Displacements (all DOFs) giving node j the normal gap `jumps[j][0]` and the
/// tangential jump `jumps[j][1]`, the host at rest.
pub fn displaced(jumps: &[[f64; 2]]) -> Vec<f64> {
    let mut u = vec![0.0; 6];
    for &[g, s] in jumps {
        u.extend([s, -g]);
    }
    u
}
