//! The setup of a solve: the node graph, the fill-reducing ordering, the fixed
//! sparsity pattern, the parts' constant stiffness and the symbolic factorization,
//! the independent steps side by side on two threads (three `rayon::join`s):
//!
//! 1. the ordering beside the pattern (both read the node graph only);
//! 2. the upper triangle of `P K Pᵀ` and its elimination tree beside the
//!    pattern's copy in the elimination order (the lower triangle, which the
//!    stiffness keeps and the column counts read);
//! 3. the column counts and faer's supernodes beside the assembly of the parts'
//!    values into that copy.

use super::linear::CholeskySolver;
use super::ordering;
use super::symbolic;
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
    let (order, k) = rayon::join(
        || ordering::nested_dissection(&coords, &graph, dofs),
        || Stiffness::pattern(dofs, &graph),
    );
    drop(graph);
    // The order and its inverse in 4 bytes an equation (held beside the factor;
    // `n_eq ≤ MAX_EQUATIONS` is checked above).
    let order: Vec<u32> = order.into_iter().map(|e| e as u32).collect();
    let mut inverse = vec![0u32; order.len()];
    for (new, &old) in order.iter().enumerate() {
        inverse[old as usize] = new as u32;
    }
    // The elimination tree (from the upper triangle of P K Pᵀ) beside the lower
    // triangle in the elimination order (the stiffness's storage, also what the
    // column counts read).
    let ((upper, etree, post), mut ordered) = rayon::join(
        || {
            let upper = symbolic::permuted_upper(&k.col_ptr, &k.row_idx, &inverse);
            let etree = symbolic::elimination_tree(&upper.col_ptr, &upper.row_idx);
            let post = symbolic::postorder(&etree);
            (upper, etree, post)
        },
        || k.in_order_pattern(&order, &inverse),
    );
    drop(k);
    // The column counts and faer's supernodes beside the parts' values.
    let part_elements = PartElements::new(parts, dofs);
    let (chol, values) = rayon::join(
        || {
            let counts =
                symbolic::column_counts(&ordered.col_ptr, &ordered.row_idx, &etree, &post);
            CholeskySolver::from_symbolic(order, inverse, &upper, &etree, &counts)
        },
        || ordered.values_of(&[&part_elements], dofs),
    );
    ordered.set_parts_values(values);
    // The graph, the permuted copies and the tree are freed: their pages go back
    // before the factorization allocates the factor.
    drop((upper, etree, post));
    super::heap::return_free_memory();
    Ok((ordered, chol?))
}

/// The stiffness's pattern (every part and coupling element) in the elimination
/// order `order` (`inverse` its inverse) of a solver from [`pattern_and_symbolic`],
/// built again without values: what a factorization needs when the pattern was
/// freed after the last one ([`super::system::ContactSystem::keep_pattern`]).
pub fn pattern_in_order(
    parts: &[Part],
    interfaces: &[Interface],
    dofs: &DofMap,
    order: &[u32],
    inverse: &[u32],
) -> Stiffness {
    let graph = NodeGraph::new(parts, interfaces, dofs);
    let k = Stiffness::pattern(dofs, &graph);
    drop(graph);
    k.in_order_pattern(order, inverse)
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
            fixed: Vec::new(),
        };
        match pattern_and_symbolic(&[], &[], &dofs) {
            Err(Error::TooLarge { unknowns, .. }) => assert_eq!(unknowns, MAX_EQUATIONS as u64 + 1),
            other => panic!("expected TooLarge, got {:?}", other.map(|_| ())),
        }
    }
}
