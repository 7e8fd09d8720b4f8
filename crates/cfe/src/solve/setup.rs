//! The setup of a solve: the node graph, the fill-reducing ordering, the fixed
//! sparsity pattern, the parts' constant stiffness and the symbolic factorization,
//! with the independent steps side by side on two threads: the ordering beside
//! the pattern (both read the graph only), then faer's symbolic analysis (one
//! thread, the pattern only) beside the assembly of the parts' values.

use super::linear::CholeskySolver;
use super::ordering;
use crate::assembly::{DofMap, NodeGraph, PartElements, Stiffness};
use crate::coupling::Interface;
use crate::domain::Part;
use crate::error::Result;

/// The stiffness (pattern of every part and coupling element, values of the
/// parts) and its Cholesky solver after the symbolic analysis in the
/// nested-dissection order.
pub fn pattern_and_symbolic(
    parts: &[Part],
    interfaces: &[Interface],
    dofs: &DofMap,
) -> Result<(Stiffness, CholeskySolver)> {
    let graph = NodeGraph::new(parts, interfaces, dofs);
    let coords: Vec<[f64; 2]> = parts
        .iter()
        .flat_map(|p| p.mesh.nodes.iter().copied())
        .collect();
    let (order, mut k) = rayon::join(
        || ordering::nested_dissection(&coords, &graph, dofs),
        || Stiffness::pattern(dofs, &graph),
    );
    drop(graph);
    let part_elements = PartElements::new(parts, dofs);
    let (chol, base) = rayon::join(
        || CholeskySolver::new(k.matrix(), Some(&order)),
        || k.base_values(&[&part_elements], dofs),
    );
    k.base = base;
    Ok((k, chol?))
}
