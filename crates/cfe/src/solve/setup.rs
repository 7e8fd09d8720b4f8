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
//!
//! A caller's stop flag is read between these steps and within the long ones
//! (the node graph, the pattern and its copy in the elimination order, the
//! ordering's recursion, the elimination tree, the column counts, the parts'
//! values, each a few thousand rows or elements at a time), and faer's
//! supernodal analysis, which cannot read it, runs on a thread of its own that
//! a stop abandons ([`symbolic::run_until`]): once the flag is nonzero the
//! analysis is abandoned with [`Error::Interrupted`] (no increment solved).

use super::linear::CholeskySolver;
use super::ordering;
use super::symbolic::{self, Stopped, check};
use crate::assembly::{
    DofMap, ElementSource, MAX_EQUATIONS, MatrixSink, NodeGraph, PartElements, Stiffness,
    VectorSink,
};
use crate::coupling::Interface;
use crate::dim::Dim;
use crate::domain::Part;
use crate::error::{Error, Result};
use std::sync::atomic::{AtomicUsize, Ordering};

/// Elements whose stiffness is assembled between two reads of the stop flag.
const STOP_CHECK_ELEMENTS: usize = 16_384;

/// A stop during the analysis, before any increment is solved.
fn interrupted(Stopped(signal): Stopped) -> Error {
    Error::Interrupted {
        increment: 0,
        signal,
    }
}

/// `Ok` when a stiffness matrix can index `n_eq` equations (at most
/// [`MAX_EQUATIONS`]), else [`Error::TooLarge`].
fn indexable(n_eq: usize) -> Result<()> {
    if n_eq > MAX_EQUATIONS {
        return Err(Error::TooLarge {
            unknowns: n_eq as u64,
            bytes: 0,
            available: 0,
            message: format!(
                "{n_eq} equations, more than the {MAX_EQUATIONS} a stiffness matrix can index; use a smaller refinement or fewer cells"
            ),
        });
    }
    Ok(())
}

/// The elimination order (`order[new] = old`) and its inverse in 4 bytes an
/// equation, as they are held beside the factor (the equations are at most
/// `MAX_EQUATIONS`, checked by [`indexable`]).
fn compact_order(order: Vec<usize>) -> (Vec<u32>, Vec<u32>) {
    let order: Vec<u32> = order.into_iter().map(|e| e as u32).collect();
    let mut inverse = vec![0u32; order.len()];
    for (new, &old) in order.iter().enumerate() {
        inverse[old as usize] = new as u32;
    }
    (order, inverse)
}

/// The stiffness (pattern of every part and coupling element in the
/// nested-dissection elimination order, values of the parts) and its Cholesky
/// solver after the symbolic analysis in that order. `stop`, if given, is read
/// between the steps and within the long ones (see the module's text): once it
/// is nonzero the analysis is abandoned with [`Error::Interrupted`].
pub fn pattern_and_symbolic<D: Dim>(
    parts: &[Part],
    interfaces: &[Interface<D>],
    dofs: &DofMap<D>,
    stop: Option<&AtomicUsize>,
) -> Result<(Stiffness, CholeskySolver)> {
    indexable(dofs.n_eq)?;
    check(stop).map_err(interrupted)?;
    let graph = NodeGraph::new_until(parts, interfaces, dofs, stop).map_err(interrupted)?;
    let coords = dofs.positions(parts);
    let (order, k) = rayon::join(
        || ordering::nested_dissection(&coords, &graph, dofs, stop),
        || Stiffness::pattern_until(dofs, &graph, stop),
    );
    drop(graph);
    let order = order.map_err(interrupted)?;
    let k = k.map_err(interrupted)?;
    check(stop).map_err(interrupted)?;
    let (order, inverse) = compact_order(order);
    // The elimination tree (from the upper triangle of P K Pᵀ) beside the lower
    // triangle in the elimination order (the stiffness's storage, also what the
    // column counts read).
    let (tree, ordered) = rayon::join(
        || -> std::result::Result<_, Stopped> {
            let upper = symbolic::permuted_upper(&k.col_ptr, &k.row_idx, &inverse, stop)?;
            let etree = symbolic::elimination_tree_until(&upper.col_ptr, &upper.row_idx, stop)?;
            let post = symbolic::postorder(&etree);
            Ok((upper, etree, post))
        },
        || k.in_order_pattern(&order, &inverse, stop),
    );
    drop(k);
    let (upper, etree, post) = tree.map_err(interrupted)?;
    let mut ordered = ordered.map_err(interrupted)?;
    check(stop).map_err(interrupted)?;
    // The column counts and faer's supernodes beside the parts' values.
    let part_elements = PartElements::new(parts, dofs);
    let part_elements = Until::new(&part_elements, stop);
    let (chol, values) = rayon::join(
        || -> Result<_> {
            let counts = symbolic::column_counts_until(
                &ordered.col_ptr,
                &ordered.row_idx,
                &etree,
                &post,
                stop,
            )
            .map_err(interrupted)?;
            drop(post);
            check(stop).map_err(interrupted)?;
            // The tree and the upper triangle go to faer's supernodal analysis,
            // which frees them (on the thread it may run on).
            CholeskySolver::from_symbolic(order, inverse, upper, etree, counts, stop)
        },
        || ordered.values_of(&[&part_elements], dofs),
    );
    let chol = chol?;
    part_elements.stopped().map_err(interrupted)?;
    check(stop).map_err(interrupted)?;
    ordered.set_parts_values(values);
    // The graph, the permuted copies and the tree are freed: their pages go back
    // before the factorization allocates the factor.
    super::heap::return_free_memory();
    Ok((ordered, chol))
}

/// An element source whose stiffnesses, given all at once
/// ([`ElementSource::for_each_stiffness`]), stop once the caller's stop flag,
/// read every `STOP_CHECK_ELEMENTS` elements, is nonzero (the values are then
/// incomplete: [`Until::stopped`] says so). Element by element it is its
/// source: the same elements in the same order, so the same sums.
struct Until<'s> {
    source: &'s dyn ElementSource,
    stop: Option<&'s AtomicUsize>,
    /// The flag's value when it was read nonzero (0: never).
    halted: AtomicUsize,
}

impl<'s> Until<'s> {
    fn new(source: &'s dyn ElementSource, stop: Option<&'s AtomicUsize>) -> Self {
        Until {
            source,
            stop,
            halted: AtomicUsize::new(0),
        }
    }

    /// `Err(Stopped)` when the stiffnesses were cut short by the stop flag.
    fn stopped(&self) -> std::result::Result<(), Stopped> {
        match self.halted.load(Ordering::Relaxed) {
            0 => Ok(()),
            signal => Err(Stopped(signal)),
        }
    }
}

impl ElementSource for Until<'_> {
    fn len(&self) -> usize {
        self.source.len()
    }

    fn nodes(&self, e: usize, f: &mut dyn FnMut(&[usize])) {
        self.source.nodes(e, f);
    }

    fn stiffness(&self, e: usize, sink: &mut MatrixSink<'_>) {
        self.source.stiffness(e, sink);
    }

    fn internal_force(&self, e: usize, u: &[f64], sink: &mut VectorSink<'_>) {
        self.source.internal_force(e, u, sink);
    }

    fn for_each_stiffness(&self, sink: &mut MatrixSink<'_>) {
        for e in 0..self.len() {
            if e % STOP_CHECK_ELEMENTS == 0
                && let Err(Stopped(signal)) = check(self.stop)
            {
                self.halted.store(signal, Ordering::Relaxed);
                return;
            }
            self.source.stiffness(e, sink);
        }
    }
}

/// The stiffness's pattern (every part and coupling element) in the elimination
/// order `order` (`inverse` its inverse) of a solver from [`pattern_and_symbolic`],
/// built again without values: what a factorization needs when the pattern was
/// freed after the last one ([`super::system::ContactSystem::keep_pattern`]).
/// `stop`, if given, is read within each step: [`Stopped`] once it is nonzero.
pub fn pattern_in_order<D: Dim>(
    parts: &[Part],
    interfaces: &[Interface<D>],
    dofs: &DofMap<D>,
    order: &[u32],
    inverse: &[u32],
    stop: Option<&AtomicUsize>,
) -> std::result::Result<Stiffness, Stopped> {
    let graph = NodeGraph::new_until(parts, interfaces, dofs, stop)?;
    let k = Stiffness::pattern_until(dofs, &graph, stop)?;
    drop(graph);
    k.in_order_pattern(order, inverse, stop)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A system with more equations than a stiffness can index is refused with
    /// `Error::TooLarge` before anything is built.
    #[test]
    fn too_many_equations_are_refused() {
        let dofs: DofMap = DofMap {
            node_offset: vec![0],
            eq: Vec::new(),
            n_eq: MAX_EQUATIONS + 1,
            prescribed: Vec::new(),
            fixed: Vec::new(),
            dim: std::marker::PhantomData,
        };
        match pattern_and_symbolic(&[], &[], &dofs, None) {
            Err(Error::TooLarge { unknowns, .. }) => assert_eq!(unknowns, MAX_EQUATIONS as u64 + 1),
            other => panic!("expected TooLarge, got {:?}", other.map(|_| ())),
        }
    }

    /// A stop flag that stays zero gives the analysis without one (the same
    /// pattern, values and factor size); one already set abandons it with
    /// `Error::Interrupted` carrying its value, before any increment.
    #[test]
    fn stop_flag_abandons_the_analysis() {
        let (parts, dofs) =
            crate::solve::fixture::clamped_rectangle([0.0, 2.0], [0.0, 1.0], [60, 30]);
        let (k, chol) = pattern_and_symbolic(&parts, &[], &dofs, None).unwrap();
        let stop = AtomicUsize::new(0);
        let (flagged, flagged_chol) = pattern_and_symbolic(&parts, &[], &dofs, Some(&stop)).unwrap();
        assert_eq!((&flagged.col_ptr, &flagged.row_idx), (&k.col_ptr, &k.row_idx));
        assert!(flagged.values.iter().zip(&k.values).all(|(a, b)| a.to_bits() == b.to_bits()));
        assert_eq!(flagged_chol.factor_nnz(), chol.factor_nnz());
        stop.store(2, Ordering::Relaxed);
        match pattern_and_symbolic(&parts, &[], &dofs, Some(&stop)) {
            Err(Error::Interrupted { increment: 0, signal: 2 }) => {}
            other => panic!("expected Interrupted, got {:?}", other.map(|_| ())),
        }
    }

    /// The pattern built again for a later factorization and faer's supernodal
    /// analysis read the flag too: left zero, `pattern_in_order` gives the
    /// analysis's pattern and `from_symbolic` a solver with its factor; set,
    /// the first returns `Stopped` and the second `Error::Interrupted` after
    /// increment 0, each carrying the flag's value.
    #[test]
    fn the_pattern_built_again_and_the_supernodes_read_the_flag() {
        let (parts, dofs) =
            crate::solve::fixture::clamped_rectangle([0.0, 2.0], [0.0, 1.0], [60, 30]);
        let (k, chol) = pattern_and_symbolic(&parts, &[], &dofs, None).unwrap();
        let (order, inverse) = chol.order();
        let stop = AtomicUsize::new(0);
        let again = pattern_in_order(&parts, &[], &dofs, order, inverse, Some(&stop)).unwrap();
        assert_eq!((&again.col_ptr, &again.row_idx), (&k.col_ptr, &k.row_idx));
        let plain = Stiffness::pattern(&dofs, &NodeGraph::new(&parts, &[], &dofs));
        let upper = symbolic::permuted_upper(&plain.col_ptr, &plain.row_idx, inverse, None).unwrap();
        let etree = symbolic::elimination_tree_until(&upper.col_ptr, &upper.row_idx, None).unwrap();
        let post = symbolic::postorder(&etree);
        let counts =
            symbolic::column_counts_until(&k.col_ptr, &k.row_idx, &etree, &post, None).unwrap();
        let analyse = |stop: &AtomicUsize| {
            CholeskySolver::from_symbolic(
                order.to_vec(),
                inverse.to_vec(),
                upper.clone(),
                etree.clone(),
                counts.clone(),
                Some(stop),
            )
        };
        assert_eq!(analyse(&stop).unwrap().factor_nnz(), chol.factor_nnz());
        stop.store(15, Ordering::Relaxed);
        assert_eq!(
            pattern_in_order(&parts, &[], &dofs, order, inverse, Some(&stop)).map(|_| ()),
            Err(Stopped(15))
        );
        match analyse(&stop) {
            Err(Error::Interrupted { increment: 0, signal: 15 }) => {}
            other => panic!("expected Interrupted, got {:?}", other.map(|_| ())),
        }
    }

    /// The compact order keeps the permutation and its inverse undoes it:
    /// `inverse[order[new]] = new` for every equation.
    #[test]
    fn compact_order_is_the_permutation_and_its_inverse() {
        let (order, inverse) = compact_order(vec![3, 0, 4, 1, 2]);
        assert_eq!(order, vec![3, 0, 4, 1, 2]);
        assert_eq!(inverse, vec![1, 3, 4, 0, 2]);
        assert!(order.iter().enumerate().all(|(new, &old)| inverse[old as usize] as usize == new));
    }

}
