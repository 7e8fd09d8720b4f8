//! DOF numbering: global nodes and degrees of freedom across parts, with the
//! Dirichlet DOFs eliminated. Below the elements: the part elements and the coupling
//! elements find their global DOFs here.

use crate::dim::{D2, Dim};
use crate::domain::{Part, Support};
use crate::fem::element::MAX_DOFS;
use std::marker::PhantomData;

/// Marks a DOF that is prescribed (eliminated from the system).
pub const FIXED: usize = usize::MAX;

/// Numbering of nodes and degrees of freedom across parts: global node
/// `g = node_offset[part] + local`, its DOFs `N g + c` for its components c
/// ([`Dim::dof`] of the model's dimension `D`; `2g` (x) and `2g + 1` (y) in 2D).
#[derive(Debug, Clone)]
pub struct DofMap<D: Dim = D2> {
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
    /// The dimension the DOFs are numbered in (`D::N` a node).
    pub dim: PhantomData<D>,
}

impl DofMap {
    /// Numbers the DOFs of the plane `parts`, eliminating those fixed by
    /// `supports` (x and y) ([`DofMap::numbered`] in 2D).
    pub fn new(parts: &[Part], supports: &[Support]) -> DofMap {
        let nodes: Vec<usize> = parts.iter().map(|p| p.mesh.nodes.len()).collect();
        DofMap::numbered(&nodes, supports)
    }
}

impl<D: Dim> DofMap<D> {
    /// Numbers the DOFs of parts of `nodes[p]` nodes each (`D::N` a node),
    /// eliminating the first `D::N` components of each support's `fix`
    /// (the first support listed wins a DOF) with their prescribed values.
    pub fn numbered(nodes: &[usize], supports: &[Support]) -> Self {
        let mut node_offset = Vec::with_capacity(nodes.len() + 1);
        let mut n = 0;
        for &count in nodes {
            node_offset.push(n);
            n += count;
        }
        node_offset.push(n);
        let mut prescribed = vec![0.0; D::dof(n, 0)];
        // `eq` marks the fixed DOFs first (free: 0), then numbers the free ones.
        let mut eq = vec![0; D::dof(n, 0)];
        let mut fixed = Vec::new();
        for (s, sup) in supports.iter().enumerate() {
            for &node in &sup.nodes {
                let g = node_offset[sup.part] + node;
                for c in 0..D::N {
                    let d = D::dof(g, c);
                    if sup.fix[c] && eq[d] != FIXED {
                        eq[d] = FIXED;
                        fixed.push((d, s));
                        prescribed[d] = sup.value[c];
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
            dim: PhantomData,
        }
    }
}

impl<D: Dim> DofMap<D> {
    /// DOFs per node (`D::N`).
    pub fn per_node(&self) -> usize {
        D::N
    }

    /// The DOF of component `c` of global node `g` ([`Dim::dof`]).
    pub fn dof(&self, g: usize, c: usize) -> usize {
        D::dof(g, c)
    }

    /// The position of every global node of `parts` (numbered by this map), in
    /// the dimension's vector: the components its part's mesh gives, in order
    /// (a plane mesh gives x and y), the others 0.
    pub fn positions(&self, parts: &[Part]) -> Vec<D::Vector> {
        parts
            .iter()
            .flat_map(|p| p.mesh.nodes.iter())
            .map(|x| {
                let mut v = D::Vector::default();
                let n = x.len().min(D::N);
                v.as_mut()[..n].copy_from_slice(&x[..n]);
                v
            })
            .collect()
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
    ) -> Vec<D::Vector> {
        let mut r = vec![D::Vector::default(); count];
        for &(d, k) in &self.fixed {
            r[k].as_mut()[d % D::N] += f_int[d] - lambda * f_ext[d];
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

    /// The global DOFs of element `e` of `part` (the first N n entries, n its
    /// node count) and their number.
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
            for c in 0..D::N {
                g[D::N * a + c] = D::dof(gn, c);
            }
        }
        (g, D::N * nodes.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::{Material, PlaneKind};
    use crate::mesh::{ElementKind, Mesh};

    /// The plane numbering through the dimension: node g's components are DOFs
    /// 2g and 2g + 1 (`dof`, `per_node`), an element's DOFs are its nodes' in
    /// order, a support's fixed DOF gets its prescribed value and no equation,
    /// and a reaction sums F_int − λ F_ext over the DOFs its support fixes, per
    /// component.
    #[test]
    fn plane_numbering_through_the_dimension() {
        let parts = vec![Part {
            name: "p".into(),
            mesh: Mesh::rectangle([0.0, 1.0], [0.0, 1.0], [2, 1], ElementKind::Q4),
            material: Material::new(1.0, 0.3, PlaneKind::Stress, 1.0, "p").unwrap(),
        }];
        let bottom = parts[0].mesh.boundary_nodes("bottom").unwrap();
        let supports = vec![Support {
            name: "s".into(),
            part: 0,
            nodes: bottom.clone(),
            fix: [false, true, false],
            value: [0.0, -0.5, 0.0],
            step: 0,
        }];
        let dofs = DofMap::new(&parts, &supports);
        assert_eq!(dofs.per_node(), 2);
        assert_eq!((dofs.dof(4, 0), dofs.dof(4, 1)), (8, 9));
        let n = dofs.n_nodes();
        assert_eq!(dofs.eq.len(), 2 * n);
        for &g in &bottom {
            assert_eq!(dofs.eq[dofs.dof(g, 1)], FIXED);
            assert_eq!(dofs.prescribed[dofs.dof(g, 1)], -0.5);
            assert_ne!(dofs.eq[dofs.dof(g, 0)], FIXED);
        }
        assert_eq!(dofs.n_eq, 2 * n - bottom.len());
        let (g, len) = dofs.element_dofs(&parts, 0, 1);
        let nodes = parts[0].mesh.elements[1].nodes();
        let expected: Vec<usize> = nodes.iter().flat_map(|&a| [2 * a, 2 * a + 1]).collect();
        assert_eq!(&g[..len], &expected[..]);
        // F_int = 1 at every DOF, F_ext = 2 at every DOF, λ = 0.25: each fixed
        // DOF contributes 0.5 to the y reaction.
        let (f_int, f_ext) = (vec![1.0; 2 * n], vec![2.0; 2 * n]);
        let r = dofs.reactions(1, &f_int, &f_ext, 0.25);
        assert_eq!(r, vec![[0.0, 0.5 * bottom.len() as f64]]);
    }

    /// A tiny solid numbering: node g's components are DOFs 3g, 3g + 1 and
    /// 3g + 2, a support fixes its z (and only the components it names), every
    /// other DOF gets an equation in order, and a reaction has three components.
    #[test]
    fn solid_numbering_through_the_dimension() {
        use crate::dim::D3;
        let supports = vec![Support {
            name: "s".into(),
            part: 1,
            nodes: vec![0, 2],
            fix: [false, false, true],
            value: [0.0, 0.0, 0.25],
            step: 0,
        }];
        // Two parts of 2 and 3 nodes: part 1's nodes 0 and 2 are global 2 and 4.
        let dofs = DofMap::<D3>::numbered(&[2, 3], &supports);
        assert_eq!((dofs.per_node(), dofs.n_nodes()), (3, 5));
        assert_eq!(dofs.eq.len(), 15);
        assert_eq!(dofs.fixed, vec![(8, 0), (14, 0)]);
        assert_eq!((dofs.prescribed[8], dofs.prescribed[14]), (0.25, 0.25));
        assert_eq!(dofs.n_eq, 13);
        let free: Vec<usize> = dofs.eq.iter().copied().filter(|&e| e != FIXED).collect();
        assert_eq!(free, (0..13).collect::<Vec<_>>());
        assert_eq!(dofs.locate(4), (1, 2));
        let r = dofs.reactions(1, &[1.0; 15], &[0.0; 15], 1.0);
        assert_eq!(r, vec![[0.0, 0.0, 2.0]]);
    }
}
