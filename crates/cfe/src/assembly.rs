//! Assembly: numbers the degrees of freedom of all parts (Dirichlet DOFs eliminated),
//! builds the sparsity pattern of the global stiffness once — including every coupling
//! element's couplings, so a pair changing state changes values, never the pattern —
//! and fills the lower triangle of K, the internal force vector and the external loads.

use crate::coupling::{Interface, PairState, element::MAX_NODES};
pub use crate::dofs::{DofMap, FIXED};
use crate::domain::{Load, Part};
use crate::fem::element::{self, MAX_DOFS};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};

/// The node adjacency graph of the whole model (CSR, each row sorted, self
/// included): two nodes are adjacent when an element — a part element or a coupling
/// element — contains both. It gives the sparsity pattern and the fill-reducing
/// ordering.
#[derive(Debug, Clone)]
pub struct NodeGraph {
    /// Row pointers (length nodes + 1).
    pub ptr: Vec<usize>,
    /// Neighbours of each node, sorted.
    pub adj: Vec<usize>,
}

impl NodeGraph {
    /// The graph of all part elements and all coupling elements (whatever their state).
    pub fn new(parts: &[Part], interfaces: &[Interface], dofs: &DofMap) -> NodeGraph {
        let n_nodes = dofs.n_nodes();
        // Two passes (count, fill), then sort and dedup each row.
        let mut count = vec![0usize; n_nodes + 1];
        let each_element = |f: &mut dyn FnMut(&[usize])| {
            let mut g = [0usize; MAX_NODES];
            for (p, part) in parts.iter().enumerate() {
                for el in &part.mesh.elements {
                    let nodes = el.nodes();
                    for (gi, &n) in g.iter_mut().zip(nodes) {
                        *gi = dofs.node(p, n);
                    }
                    f(&g[..nodes.len()]);
                }
            }
            for iface in interfaces {
                for c in &iface.elements {
                    let (g, n) = c.global_nodes(dofs, iface.host, iface.node_part);
                    f(&g[..n]);
                }
            }
        };
        each_element(&mut |nodes| {
            for &a in nodes {
                count[a + 1] += nodes.len();
            }
        });
        for i in 0..n_nodes {
            count[i + 1] += count[i];
        }
        let mut adj = vec![0usize; count[n_nodes]];
        let mut fill = count.clone();
        each_element(&mut |nodes| {
            for &a in nodes {
                for &b in nodes {
                    adj[fill[a]] = b;
                    fill[a] += 1;
                }
            }
        });
        let mut ptr = vec![0usize; n_nodes + 1];
        let mut out = Vec::with_capacity(adj.len() / 2);
        for a in 0..n_nodes {
            let row = &mut adj[count[a]..count[a + 1]];
            row.sort_unstable();
            let mut last = usize::MAX;
            for &b in row.iter() {
                if b != last {
                    out.push(b);
                    last = b;
                }
            }
            ptr[a + 1] = out.len();
        }
        NodeGraph { ptr, adj: out }
    }

    /// The neighbours of node `a` (including itself).
    pub fn neighbours(&self, a: usize) -> &[usize] {
        &self.adj[self.ptr[a]..self.ptr[a + 1]]
    }
}

/// The global stiffness matrix K (lower triangle, compressed sparse columns over the
/// free DOFs) with a fixed pattern. `base` holds the parts' contribution, assembled
/// once; [`Stiffness::assemble`] adds the coupling elements for a set of pair states.
#[derive(Debug, Clone)]
pub struct Stiffness {
    /// Column pointers (length n_eq + 1).
    pub col_ptr: Vec<usize>,
    /// Row indices, sorted within each column, all ≥ the column.
    pub row_idx: Vec<usize>,
    /// The parts' contribution to the values.
    pub base: Vec<f64>,
    /// Current values: base + coupling elements.
    pub values: Vec<f64>,
}

impl Stiffness {
    /// Builds the pattern from the node graph of every part element and every
    /// coupling element, and assembles the parts' stiffness.
    pub fn new(parts: &[Part], dofs: &DofMap, graph: &NodeGraph) -> Stiffness {
        let n_nodes = dofs.n_nodes();
        let (nbr_ptr, nbr) = (&graph.ptr, &graph.adj);
        // DOF-level lower-triangular CSC over equations. Equation numbers increase with
        // DOF index, so rows come out sorted.
        let mut col_ptr = Vec::with_capacity(dofs.n_eq + 1);
        col_ptr.push(0);
        let mut row_idx = Vec::with_capacity(nbr.len() * 2);
        for a in 0..n_nodes {
            for ca in 0..2 {
                let j = dofs.eq[2 * a + ca];
                if j == FIXED {
                    continue;
                }
                for &b in &nbr[nbr_ptr[a]..nbr_ptr[a + 1]] {
                    for cb in 0..2 {
                        let i = dofs.eq[2 * b + cb];
                        if i != FIXED && i >= j {
                            row_idx.push(i);
                        }
                    }
                }
                col_ptr.push(row_idx.len());
            }
        }
        let nnz = row_idx.len();
        let mut k = Stiffness {
            col_ptr,
            row_idx,
            base: vec![0.0; nnz],
            values: vec![0.0; nnz],
        };
        let mut base = std::mem::take(&mut k.base);
        for (p, part) in parts.iter().enumerate() {
            let d = part.material.d_matrix();
            for (e, el) in part.mesh.elements.iter().enumerate() {
                let x = element::coordinates(&part.mesh, el);
                let ke = element::stiffness(el, &x, &d, part.material.thickness);
                let (g, n) = dofs.element_dofs(parts, p, e);
                k.scatter(&mut base, dofs, &g[..n], |a, b| ke[a][b]);
            }
        }
        k.base = base;
        k
    }

    /// Number of equations.
    pub fn n(&self) -> usize {
        self.col_ptr.len() - 1
    }

    /// Position of entry (row i, column j), i ≥ j, in the value array.
    fn position(&self, i: usize, j: usize) -> usize {
        let (s, e) = (self.col_ptr[j], self.col_ptr[j + 1]);
        s + self.row_idx[s..e]
            .binary_search(&i)
            .expect("entry is in the sparsity pattern")
    }

    /// Adds an element matrix (given by `k(a, b)` over local DOFs `g`) into `values`,
    /// lower triangle, free DOFs only.
    fn scatter(
        &self,
        values: &mut [f64],
        dofs: &DofMap,
        g: &[usize],
        k: impl Fn(usize, usize) -> f64,
    ) {
        for (b, &gb) in g.iter().enumerate() {
            let j = dofs.eq[gb];
            if j == FIXED {
                continue;
            }
            for (a, &ga) in g.iter().enumerate() {
                let i = dofs.eq[ga];
                if i == FIXED || i < j {
                    continue;
                }
                let pos = self.position(i, j);
                values[pos] += k(a, b);
            }
        }
    }

    /// Sets `values` = parts + the coupling elements in their `states`
    /// (`states[i][k]` for pair k of interface i).
    pub fn assemble(&mut self, interfaces: &[Interface], states: &[Vec<PairState>], dofs: &DofMap) {
        let mut values = std::mem::take(&mut self.values);
        values.copy_from_slice(&self.base);
        for (iface, st) in interfaces.iter().zip(states) {
            for (c, &s) in iface.elements.iter().zip(st) {
                if s == PairState::Open {
                    continue;
                }
                let ke = c.stiffness(iface.c_n, iface.c_s, s);
                let g = c.dofs(dofs, iface.host, iface.node_part);
                self.scatter(&mut values, dofs, g.as_slice(), |a, b| ke.get(a, b));
            }
        }
        self.values = values;
    }

    /// The current matrix as a faer sparse view (lower triangle).
    pub fn matrix(&self) -> SparseColMatRef<'_, usize, f64> {
        let n = self.n();
        let symbolic =
            SymbolicSparseColMatRef::new_checked(n, n, &self.col_ptr, None, &self.row_idx);
        SparseColMatRef::new(symbolic, &self.values)
    }
}

/// The internal force vector over all DOFs, `F_int = Σ_parts K_e u_e + Σ_CFE B_eᵀ Rᵀ f`
/// (seed eq. 1), for the full displacement vector `u` (free and prescribed DOFs).
pub fn internal_force(
    parts: &[Part],
    interfaces: &[Interface],
    states: &[Vec<PairState>],
    dofs: &DofMap,
    u: &[f64],
) -> Vec<f64> {
    use rayon::prelude::*;
    // Part elements in one chunk per thread, each summed into its own vector.
    let elements: Vec<(usize, usize)> = parts
        .iter()
        .enumerate()
        .flat_map(|(p, part)| (0..part.mesh.elements.len()).map(move |e| (p, e)))
        .collect();
    let threads = rayon::current_num_threads().max(1);
    let chunk = elements.len().div_ceil(threads).max(1);
    let materials: Vec<[[f64; 3]; 3]> = parts.iter().map(|p| p.material.d_matrix()).collect();
    let mut f = elements
        .par_chunks(chunk)
        .map(|chunk| {
            let mut f = vec![0.0; u.len()];
            for &(p, e) in chunk {
                let part = &parts[p];
                let el = &part.mesh.elements[e];
                let x = element::coordinates(&part.mesh, el);
                let ke = element::stiffness(el, &x, &materials[p], part.material.thickness);
                let (g, n) = dofs.element_dofs(parts, p, e);
                let ue: [f64; MAX_DOFS] =
                    std::array::from_fn(|i| if i < n { u[g[i]] } else { 0.0 });
                let fe = element::mul(&ke, &ue, n);
                for (a, &ga) in g[..n].iter().enumerate() {
                    f[ga] += fe[a];
                }
            }
            f
        })
        .reduce_with(|mut a, b| {
            for (x, y) in a.iter_mut().zip(&b) {
                *x += y;
            }
            a
        })
        .unwrap_or_else(|| vec![0.0; u.len()]);
    for (iface, st) in interfaces.iter().zip(states) {
        for (c, &s) in iface.elements.iter().zip(st) {
            let g = c.dofs(dofs, iface.host, iface.node_part);
            let (fe, _) = c.internal_force(iface.c_n, iface.c_s, s, &g.gather(u));
            for (a, &ga) in g.as_slice().iter().enumerate() {
                f[ga] += fe[a];
            }
        }
    }
    f
}

/// The external force vector over all DOFs at full load.
pub fn external_force(loads: &[Load], dofs: &DofMap) -> Vec<f64> {
    let mut f = vec![0.0; 2 * dofs.n_nodes()];
    for load in loads {
        for &(n, v) in &load.nodal {
            let g = dofs.node(load.part, n);
            f[2 * g] += v[0];
            f[2 * g + 1] += v[1];
        }
    }
    f
}
