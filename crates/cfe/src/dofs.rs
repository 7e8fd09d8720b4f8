//! DOF numbering: global nodes and degrees of freedom across parts, with the
//! Dirichlet DOFs eliminated. Below the elements: the part elements and the coupling
//! elements find their global DOFs here.

use crate::domain::{Part, Support};
use crate::fem::element::MAX_DOFS;

/// Marks a DOF that is prescribed (eliminated from the system).
pub const FIXED: usize = usize::MAX;

/// Numbering of nodes and degrees of freedom across parts: global node
/// `g = node_offset[part] + local`, DOFs `2g` (x) and `2g + 1` (y).
#[derive(Debug, Clone)]
pub struct DofMap {
    /// First global node of each part (length parts + 1).
    pub node_offset: Vec<usize>,
    /// Equation number of each DOF, or `FIXED` (`usize::MAX`).
    pub eq: Vec<usize>,
    /// Number of equations (free DOFs): the unknowns.
    pub n_eq: usize,
    /// Prescribed value of each DOF at full load (0 where free).
    pub prescribed: Vec<f64>,
    /// Each fixed DOF, ascending, with the index of the support that fixes it
    /// (the first one listed wins). A list rather than an entry per DOF: a
    /// structure's supports fix a boundary, a small share of its DOFs.
    pub fixed: Vec<(usize, usize)>,
}

impl DofMap {
    /// Numbers the DOFs of `parts`, eliminating those fixed by `supports`.
    pub fn new(parts: &[Part], supports: &[Support]) -> DofMap {
        let mut node_offset = Vec::with_capacity(parts.len() + 1);
        let mut n = 0;
        for p in parts {
            node_offset.push(n);
            n += p.mesh.nodes.len();
        }
        node_offset.push(n);
        let mut prescribed = vec![0.0; 2 * n];
        // `eq` marks the fixed DOFs first (free: 0), then numbers the free ones.
        let mut eq = vec![0; 2 * n];
        let mut fixed = Vec::new();
        for (s, sup) in supports.iter().enumerate() {
            for &node in &sup.nodes {
                let g = node_offset[sup.part] + node;
                for c in 0..2 {
                    if sup.fix[c] && eq[2 * g + c] != FIXED {
                        eq[2 * g + c] = FIXED;
                        fixed.push((2 * g + c, s));
                        prescribed[2 * g + c] = sup.value[c];
                    }
                }
            }
        }
        fixed.sort_unstable();
        let mut n_eq = 0;
        for e in eq.iter_mut().filter(|e| **e != FIXED) {
            *e = n_eq;
            n_eq += 1;
        }
        DofMap {
            node_offset,
            eq,
            n_eq,
            prescribed,
            fixed,
        }
    }

    /// Number of global nodes.
    pub fn n_nodes(&self) -> usize {
        *self.node_offset.last().unwrap_or(&0)
    }

    /// Global node of `node` in `part`.
    pub fn node(&self, part: usize, node: usize) -> usize {
        self.node_offset[part] + node
    }

    /// The reaction (x, y) of each of `count` supports: the out-of-balance force
    /// `F_int − λ F_ext` summed over the DOFs each fixes (`f_ext` at full load).
    pub fn reactions(
        &self,
        count: usize,
        f_int: &[f64],
        f_ext: &[f64],
        lambda: f64,
    ) -> Vec<[f64; 2]> {
        let mut r = vec![[0.0; 2]; count];
        for &(d, k) in &self.fixed {
            r[k][d % 2] += f_int[d] - lambda * f_ext[d];
        }
        r
    }

    /// The number of supports that fix at least one DOF (one more than the largest
    /// support index).
    pub fn support_count(&self) -> usize {
        self.fixed.iter().map(|&(_, k)| k + 1).max().unwrap_or(0)
    }

    /// The part and local node of a global node.
    pub fn locate(&self, g: usize) -> (usize, usize) {
        let p = self.node_offset.partition_point(|&o| o <= g) - 1;
        (p, g - self.node_offset[p])
    }

    /// The global DOFs of element `e` of `part` (the first 2n entries, n its node
    /// count) and their number.
    pub fn element_dofs(
        &self,
        parts: &[Part],
        part: usize,
        e: usize,
    ) -> ([usize; MAX_DOFS], usize) {
        let nodes = parts[part].mesh.elements[e].nodes();
        let mut g = [0; MAX_DOFS];
        for (a, &n) in nodes.iter().enumerate() {
            let gn = self.node(part, n);
            g[2 * a] = 2 * gn;
            g[2 * a + 1] = 2 * gn + 1;
        }
        (g, 2 * nodes.len())
    }
}
