//! [`Partition`]: which rank assembles which elements and owns which rows of
//! PETSc's matrix, computed alike on every rank from the replicated model.
//!
//! The part elements are split by recursive coordinate bisection of their
//! centroids (each cut across the widest extent of the elements it splits, at
//! the count proportional to the ranks on either side), so each rank gets a
//! compact block of elements. A node belongs to the lowest rank among the part
//! elements holding it (rank 0 if none does); a coupling element belongs to
//! the rank of its first node, so every coupling element is assembled by one
//! rank. The nodes are then renumbered rank after rank (in their global order
//! within a rank), so each rank's rows — `D::N` per node, node after node —
//! are one contiguous range, as PETSc's MPIAIJ layout wants.
//!
//! On one rank the renumbering is the identity.

use cfe::assembly::{CouplingElements, ElementSource, PartElements};
use cfe::coupling::Interface;
use cfe::dofs::DofMap;
use cfe::domain::Part;
use cfe::fem::ElementFamily;

/// The split of a model over `ranks` ranks (see the module).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Partition {
    /// The number of ranks.
    pub ranks: usize,
    /// The rank of each part element (in [`PartElements`]' numbering).
    pub part_owner: Vec<u32>,
    /// The rank of each coupling element (in [`CouplingElements`]' numbering).
    pub coupling_owner: Vec<u32>,
    /// The rank of each global node.
    pub node_owner: Vec<u32>,
    /// The PETSc node number of each global node (its rows are
    /// `D::N · index + c`).
    pub node_index: Vec<usize>,
    /// The first PETSc node of each rank (length `ranks + 1`).
    pub node_start: Vec<usize>,
}

/// The coordinates of every global node, `D::N` each, node after node.
pub fn node_coordinates<D: ElementFamily>(parts: &[Part<D>], dofs: &DofMap<D>) -> Vec<f64> {
    let mut coords = vec![0.0; dofs.eq.len()];
    for (p, part) in parts.iter().enumerate() {
        for (i, x) in part.mesh.nodes.iter().enumerate() {
            let g = dofs.node_offset[p] + i;
            coords[D::dof(g, 0)..D::dof(g, 0) + D::N].copy_from_slice(x.as_ref());
        }
    }
    coords
}

/// Gives the elements of `items` (centroids `c`, `n` coordinates each) the
/// ranks `first..first + ranks` by recursive coordinate bisection.
fn bisect(items: &mut [usize], c: &[f64], n: usize, first: u32, ranks: usize, owner: &mut [u32]) {
    if ranks <= 1 || items.len() <= 1 {
        for &e in items.iter() {
            owner[e] = first;
        }
        return;
    }
    // The axis of the widest extent.
    let mut axis = 0;
    let mut widest = f64::NEG_INFINITY;
    for a in 0..n {
        let (lo, hi) = items
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &e| {
                (lo.min(c[e * n + a]), hi.max(c[e * n + a]))
            });
        if hi - lo > widest {
            widest = hi - lo;
            axis = a;
        }
    }
    let left = ranks / 2;
    // Elements in proportion to the ranks (u128: no overflow of the product).
    let k = (items.len() as u128 * left as u128 / ranks as u128) as usize;
    let key = |e: &usize| (c[e * n + axis], *e);
    if k > 0 && k < items.len() {
        items.select_nth_unstable_by(k, |a, b| {
            let (ka, kb) = (key(a), key(b));
            ka.0.total_cmp(&kb.0).then(ka.1.cmp(&kb.1))
        });
    }
    let (lower, upper) = items.split_at_mut(k);
    bisect(lower, c, n, first, left, owner);
    bisect(upper, c, n, first + left as u32, ranks - left, owner);
}

impl Partition {
    /// The partition of the model `parts` + `interfaces` over `ranks` (≥ 1)
    /// ranks.
    pub fn new<D: ElementFamily>(
        parts: &[Part<D>],
        interfaces: &[Interface<D>],
        dofs: &DofMap<D>,
        ranks: usize,
    ) -> Partition {
        let ranks = ranks.max(1);
        let n = D::N;
        let n_nodes = dofs.n_nodes();
        let coords = node_coordinates(parts, dofs);
        let elements = PartElements::new(parts, dofs);
        let couplings = CouplingElements::new(interfaces, None, dofs);
        // Centroids of the part elements.
        let mut centroids = vec![0.0; elements.len() * n];
        for e in 0..elements.len() {
            elements.nodes(e, &mut |g| {
                let w = 1.0 / g.len().max(1) as f64;
                for &node in g {
                    for a in 0..n {
                        centroids[e * n + a] += w * coords[node * n + a];
                    }
                }
            });
        }
        let mut part_owner = vec![0u32; elements.len()];
        let mut items: Vec<usize> = (0..elements.len()).collect();
        bisect(&mut items, &centroids, n, 0, ranks, &mut part_owner);
        drop(items);
        drop(centroids);
        let mut node_owner = vec![u32::MAX; n_nodes];
        for (e, &r) in part_owner.iter().enumerate() {
            elements.nodes(e, &mut |g| {
                for &node in g {
                    node_owner[node] = node_owner[node].min(r);
                }
            });
        }
        for o in &mut node_owner {
            if *o == u32::MAX {
                *o = 0;
            }
        }
        let mut coupling_owner = vec![0u32; couplings.len()];
        for (e, owner) in coupling_owner.iter_mut().enumerate() {
            couplings.nodes(e, &mut |g| {
                if let Some(&first) = g.first() {
                    *owner = node_owner[first];
                }
            });
        }
        // Nodes rank after rank, in their global order within a rank.
        let mut node_start = vec![0usize; ranks + 1];
        for &o in &node_owner {
            node_start[o as usize + 1] += 1;
        }
        for r in 0..ranks {
            node_start[r + 1] += node_start[r];
        }
        let mut next = node_start[..ranks].to_vec();
        let mut node_index = vec![0usize; n_nodes];
        for (g, &o) in node_owner.iter().enumerate() {
            node_index[g] = next[o as usize];
            next[o as usize] += 1;
        }
        Partition {
            ranks,
            part_owner,
            coupling_owner,
            node_owner,
            node_index,
            node_start,
        }
    }

    /// The global nodes `rank` owns, in PETSc's order.
    pub fn nodes_of(&self, rank: usize) -> Vec<usize> {
        let mut nodes = vec![0usize; self.node_start[rank + 1] - self.node_start[rank]];
        for (g, &o) in self.node_owner.iter().enumerate() {
            if o as usize == rank {
                nodes[self.node_index[g] - self.node_start[rank]] = g;
            }
        }
        nodes
    }

    /// The elements of `owner` that `rank` assembles.
    pub fn elements_of(owner: &[u32], rank: usize) -> Vec<usize> {
        (0..owner.len())
            .filter(|&e| owner[e] as usize == rank)
            .collect()
    }
}
