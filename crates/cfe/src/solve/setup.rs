//! The setup of a solve: the node graph, the fill-reducing ordering, the fixed
//! sparsity pattern, the parts' constant stiffness and the symbolic factorization,
//! with the independent steps side by side on two threads: the ordering beside
//! the pattern and its row indices widened for faer (both read the graph only),
//! then faer's symbolic analysis (one thread, the pattern only) beside the
//! assembly of the parts' values and the copy of the pattern and values in the
//! elimination order.

use super::linear::CholeskySolver;
use super::ordering;
use crate::assembly::{DofMap, MAX_EQUATIONS, NodeGraph, PartElements, Stiffness};
use crate::coupling::Interface;
use crate::domain::Part;
use crate::error::{Error, Result};

/// The stiffness (pattern of every part and coupling element in the
/// nested-dissection elimination order, values of the parts) and its Cholesky
/// solver after the symbolic analysis in that order.
pub fn pattern_and_symbolic(
    parts: &[Part],
    interfaces: &[Interface],
    dofs: &DofMap,
) -> Result<(Stiffness, CholeskySolver)> {
    if dofs.n_eq > MAX_EQUATIONS {
        return Err(Error::TooLarge {
            unknowns: dofs.n_eq as u64,
            bytes: 0,
            available: 0,
            message: format!(
                "{} equations, more than the {MAX_EQUATIONS} a stiffness matrix can index; use a smaller refinement or fewer cells",
                dofs.n_eq
            ),
        });
    }
    let graph = NodeGraph::new(parts, interfaces, dofs);
    let coords: Vec<[f64; 2]> = parts
        .iter()
        .flat_map(|p| p.mesh.nodes.iter().copied())
        .collect();
    let (order, (k, rows)) = rayon::join(
        || ordering::nested_dissection(&coords, &graph, dofs),
        || {
            let k = Stiffness::pattern(dofs, &graph);
            let rows = k.wide_rows();
            (k, rows)
        },
    );
    drop(graph);
    let mut inverse = vec![0usize; order.len()];
    for (new, &old) in order.iter().enumerate() {
        inverse[old] = new;
    }
    let part_elements = PartElements::new(parts, dofs);
    let (chol, k) = rayon::join(
        || k.with_matrix_wide(&rows, |m| CholeskySolver::new(m, Some(&order))),
        || k.in_order_with_parts(&[&part_elements], dofs, &order, &inverse),
    );
    Ok((k, chol?))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A system with more equations than a stiffness can index is refused with
    /// `Error::TooLarge` before anything is built.
    #[test]
    fn too_many_equations_are_refused() {
        let dofs = DofMap {
            node_offset: vec![0],
            eq: Vec::new(),
            n_eq: MAX_EQUATIONS + 1,
            prescribed: Vec::new(),
            support_of: Vec::new(),
        };
        match pattern_and_symbolic(&[], &[], &dofs) {
            Err(Error::TooLarge { unknowns, .. }) => assert_eq!(unknowns, MAX_EQUATIONS as u64 + 1),
            other => panic!("expected TooLarge, got {:?}", other.map(|_| ())),
        }
    }
}
