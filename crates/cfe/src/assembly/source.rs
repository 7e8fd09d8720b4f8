//! Element sources: the families of elements the assembly iterates over (the
//! element-provider pattern of fenris). A source numbers its elements `0..len()`
//! and gives, per element, its global nodes (for the sparsity pattern), its
//! stiffness and its internal force over its global DOFs. The part elements (T3,
//! Q4) and the coupling elements are the two implementations here; a new family —
//! a 3D element, another coupling formulation — is a new implementation, and
//! [`crate::assembly`] (pattern, values, internal force) does not change.

use crate::coupling::element::MAX_DOFS;
use crate::coupling::{Interface, PairHistory, PairState};
use crate::dim::{D2, Dim};
use crate::dofs::DofMap;
use crate::domain::Part;
use crate::fem::ElementFamily;
use crate::mesh::MeshCell;

/// Most nodes a part element of any dimension has (HEX8).
const MAX_PART_NODES: usize = 8;

/// Receives one element matrix: its global DOFs `g` and its entries, row-major with
/// row stride `stride` (entry `(a, b)` at `k[a * stride + b]`, a, b < g.len()).
pub type MatrixSink<'s> = dyn FnMut(&[usize], &[f64], usize) + 's;
/// Receives one element vector: its global DOFs and its values over them.
pub type VectorSink<'s> = dyn FnMut(&[usize], &[f64]) + 's;

/// A family of elements contributing to the global stiffness and internal force.
pub trait ElementSource: Sync {
    /// Number of elements.
    fn len(&self) -> usize;

    /// Whether the source has no element.
    fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Calls `f` with the global nodes of element `e` (every node it couples,
    /// whatever its current state: the pattern never changes).
    fn nodes(&self, e: usize, f: &mut dyn FnMut(&[usize]));

    /// Gives `sink` the stiffness `K_e` of element `e` (nothing when it is zero,
    /// e.g. an open pair).
    fn stiffness(&self, e: usize, sink: &mut MatrixSink<'_>);

    /// Calls `f` with the global nodes of every element, in order. The default
    /// asks [`nodes`](Self::nodes) element by element.
    fn for_each_nodes(&self, f: &mut dyn FnMut(&[usize])) {
        for e in 0..self.len() {
            self.nodes(e, f);
        }
    }

    /// Gives `sink` the stiffness of every element, in order. The default asks
    /// [`stiffness`](Self::stiffness) element by element.
    fn for_each_stiffness(&self, sink: &mut MatrixSink<'_>) {
        for e in 0..self.len() {
            self.stiffness(e, sink);
        }
    }

    /// Gives `sink` the internal force `F_e` of element `e` for the displacements
    /// `u` of all DOFs.
    fn internal_force(&self, e: usize, u: &[f64], sink: &mut VectorSink<'_>);

    /// Adds the internal forces of the elements in `range` into `f`, which holds
    /// the DOFs from `first` on (`f[d − first]` for DOF `d`: all of them when
    /// `first` is 0 and `f` as long as `u`; at least those of
    /// [`dof_span`](Self::dof_span) otherwise), for the displacements `u` of all
    /// DOFs. The default gives each element's to `f` in turn; a source with many
    /// elements may do the same in one loop.
    fn add_internal_forces(
        &self,
        range: std::ops::Range<usize>,
        u: &[f64],
        f: &mut [f64],
        first: usize,
    ) {
        for e in range {
            self.internal_force(e, u, &mut |g, fe| {
                for (&ga, v) in g.iter().zip(fe) {
                    f[ga - first] += v;
                }
            });
        }
    }

    /// The DOFs the elements of `range` touch, as one range holding every DOF of
    /// their nodes, or `None` when the source does not tell (all DOFs).
    fn dof_span(&self, range: std::ops::Range<usize>) -> Option<std::ops::Range<usize>> {
        let _ = range;
        None
    }

    /// Whether the assembly should sum this source's internal forces in parallel
    /// chunks (many, independent elements) rather than in element order.
    fn parallel(&self) -> bool {
        false
    }
}

/// The elements of every part (T3 and Q4 in a plane model, TET4 and HEX8 in a
/// solid one: the dimension's [`ElementFamily`]), numbered part after part.
pub struct PartElements<'a, D: ElementFamily = D2> {
    parts: &'a [Part<D>],
    dofs: &'a DofMap<D>,
    /// First element of each part in the source's numbering (length parts + 1).
    offset: Vec<usize>,
    /// The constitutive data of each part.
    c: Vec<D::Constitutive>,
}

impl<'a, D: ElementFamily> PartElements<'a, D> {
    /// The elements of `parts`, numbered with `dofs`.
    pub fn new(parts: &'a [Part<D>], dofs: &'a DofMap<D>) -> Self {
        let mut offset = Vec::with_capacity(parts.len() + 1);
        let mut n = 0;
        for p in parts {
            offset.push(n);
            n += p.mesh.elements.len();
        }
        offset.push(n);
        let c = parts.iter().map(|p| D::constitutive(&p.material)).collect();
        PartElements {
            parts,
            dofs,
            offset,
            c,
        }
    }

    /// The source elements (this numbering) with a node for which `node` is
    /// true, given its global node number; in order.
    pub fn touching(&self, node: impl Fn(usize) -> bool) -> Vec<usize> {
        let mut elements = Vec::new();
        for (p, _, all) in self.by_part(0..self.len()) {
            for (e, el) in all.iter().enumerate() {
                if el.nodes().iter().any(|&n| node(self.dofs.node(p, n))) {
                    elements.push(self.offset[p] + e);
                }
            }
        }
        elements
    }

    /// The part and the element within it of source element `e`.
    #[inline(always)]
    fn locate(&self, e: usize) -> (usize, usize) {
        let p = self.offset.partition_point(|&o| o <= e) - 1;
        (p, e - self.offset[p])
    }

    /// The elements of `range` part by part: each part with some, its index and
    /// those of its elements (no search per element).
    fn by_part(
        &self,
        range: std::ops::Range<usize>,
    ) -> impl Iterator<Item = (usize, &'a Part<D>, &'a [D::Cell])> + '_ {
        self.parts.iter().enumerate().filter_map(move |(p, part)| {
            let (first, last) = (
                range.start.max(self.offset[p]),
                range.end.min(self.offset[p + 1]),
            );
            (first < last).then(|| {
                (p, part, &part.mesh.elements[first - self.offset[p]..last - self.offset[p]])
            })
        })
    }

    /// The element stiffness and global DOFs of source element `e`.
    #[inline(always)]
    fn element(&self, e: usize) -> (D::ElementMatrix, D::ElementDofs, usize) {
        let (p, e) = self.locate(e);
        let part = &self.parts[p];
        let ke = D::stiffness(&part.mesh, &part.mesh.elements[e], &self.c[p]);
        let (g, n) = self.dofs.element_dofs(self.parts, p, e);
        (ke, g, n)
    }

    /// The internal force `K_e u_e` and global DOFs of source element `e` for the
    /// displacements `u` of all DOFs (without forming `K_e`).
    #[inline(always)]
    fn element_force(&self, e: usize, u: &[f64]) -> (D::ElementVector, D::ElementDofs, usize) {
        let (p, e) = self.locate(e);
        let part = &self.parts[p];
        let (g, n) = self.dofs.element_dofs(self.parts, p, e);
        let mut ue = D::zero_vector();
        for (v, &gi) in ue.as_mut().iter_mut().zip(&g.as_ref()[..n]) {
            *v = u[gi];
        }
        let fe = D::internal_force(&part.mesh, &part.mesh.elements[e], &self.c[p], &ue);
        (fe, g, n)
    }
}

impl<D: ElementFamily> ElementSource for PartElements<'_, D> {
    fn len(&self) -> usize {
        *self.offset.last().unwrap_or(&0)
    }

    fn nodes(&self, e: usize, f: &mut dyn FnMut(&[usize])) {
        let (p, e) = self.locate(e);
        let nodes = self.parts[p].mesh.elements[e].nodes();
        let mut g = [0usize; MAX_PART_NODES];
        for (gi, &n) in g.iter_mut().zip(nodes) {
            *gi = self.dofs.node(p, n);
        }
        f(&g[..nodes.len()]);
    }

    fn stiffness(&self, e: usize, sink: &mut MatrixSink<'_>) {
        let (ke, g, n) = self.element(e);
        sink(&g.as_ref()[..n], D::flat(&ke), D::STRIDE);
    }

    fn internal_force(&self, e: usize, u: &[f64], sink: &mut VectorSink<'_>) {
        let (fe, g, n) = self.element_force(e, u);
        sink(&g.as_ref()[..n], &fe.as_ref()[..n]);
    }

    fn for_each_nodes(&self, f: &mut dyn FnMut(&[usize])) {
        let mut g = [0usize; MAX_PART_NODES];
        for (p, part) in self.parts.iter().enumerate() {
            for el in &part.mesh.elements {
                let nodes = el.nodes();
                for (gi, &n) in g.iter_mut().zip(nodes) {
                    *gi = self.dofs.node(p, n);
                }
                f(&g[..nodes.len()]);
            }
        }
    }

    fn for_each_stiffness(&self, sink: &mut MatrixSink<'_>) {
        for (p, part) in self.parts.iter().enumerate() {
            for (e, el) in part.mesh.elements.iter().enumerate() {
                let ke = D::stiffness(&part.mesh, el, &self.c[p]);
                let (g, n) = self.dofs.element_dofs(self.parts, p, e);
                sink(&g.as_ref()[..n], D::flat(&ke), D::STRIDE);
            }
        }
    }

    fn add_internal_forces(
        &self,
        range: std::ops::Range<usize>,
        u: &[f64],
        f: &mut [f64],
        first_dof: usize,
    ) {
        for (p, part, elements) in self.by_part(range) {
            let base = self.dofs.dof(self.dofs.node(p, 0), 0);
            // The part's DOFs in `f` (from `first_dof` on).
            let fp = &mut f[base.saturating_sub(first_dof)..];
            let shift = first_dof.saturating_sub(base);
            for el in elements {
                let nodes = el.nodes();
                let mut ue = D::zero_vector();
                let dof = |a: usize, c: usize| self.dofs.dof(a, c);
                let uem = ue.as_mut();
                for (a, &n) in nodes.iter().enumerate() {
                    for c in 0..self.dofs.per_node() {
                        uem[dof(a, c)] = u[base + dof(n, c)];
                    }
                }
                let fe = D::internal_force(&part.mesh, el, &self.c[p], &ue);
                let fe = fe.as_ref();
                for (a, &n) in nodes.iter().enumerate() {
                    for c in 0..self.dofs.per_node() {
                        fp[dof(n, c) - shift] += fe[dof(a, c)];
                    }
                }
            }
        }
    }

    fn dof_span(&self, range: std::ops::Range<usize>) -> Option<std::ops::Range<usize>> {
        let (mut lo, mut hi) = (usize::MAX, 0);
        for (p, _, elements) in self.by_part(range) {
            for &n in elements.iter().flat_map(|el| el.nodes()) {
                let g = self.dofs.node(p, n);
                lo = lo.min(self.dofs.dof(g, 0));
                hi = hi.max(self.dofs.dof(g + 1, 0));
            }
        }
        (lo < hi).then_some(lo..hi)
    }

    fn parallel(&self) -> bool {
        true
    }
}

/// Some elements of another source, numbered `0..len()` in the order given: a
/// few elements out of many, such as the part elements around the coupling
/// nodes, whose internal forces sum to the complete force at those nodes' DOFs.
pub struct SomeElements<'a> {
    source: &'a dyn ElementSource,
    elements: &'a [usize],
}

impl<'a> SomeElements<'a> {
    /// The elements `elements` (in `source`'s numbering, each below its `len()`)
    /// of `source`.
    pub fn new(source: &'a dyn ElementSource, elements: &'a [usize]) -> Self {
        SomeElements { source, elements }
    }
}

impl ElementSource for SomeElements<'_> {
    fn len(&self) -> usize {
        self.elements.len()
    }

    fn nodes(&self, e: usize, f: &mut dyn FnMut(&[usize])) {
        self.source.nodes(self.elements[e], f);
    }

    fn stiffness(&self, e: usize, sink: &mut MatrixSink<'_>) {
        self.source.stiffness(self.elements[e], sink);
    }

    fn internal_force(&self, e: usize, u: &[f64], sink: &mut VectorSink<'_>) {
        self.source.internal_force(self.elements[e], u, sink);
    }
}

/// The coupling elements of every interface, numbered interface after interface,
/// in given pair states (`None`: for the pattern only, every pair counted).
pub struct CouplingElements<'a, D: Dim = D2> {
    interfaces: &'a [Interface<D>],
    states: Option<&'a [Vec<PairState>]>,
    history: Option<&'a [Vec<PairHistory<D>>]>,
    dofs: &'a DofMap<D>,
    /// First pair of each interface in the source's numbering (length interfaces + 1).
    offset: Vec<usize>,
}

impl<'a, D: Dim> CouplingElements<'a, D> {
    /// The coupling elements of `interfaces` in `states` (`states[i][k]` for pair k
    /// of interface i; `None` when only the pattern is wanted).
    pub fn new(
        interfaces: &'a [Interface<D>],
        states: Option<&'a [Vec<PairState>]>,
        dofs: &'a DofMap<D>,
    ) -> Self {
        let mut offset = Vec::with_capacity(interfaces.len() + 1);
        let mut n = 0;
        for i in interfaces {
            offset.push(n);
            n += i.elements.len();
        }
        offset.push(n);
        CouplingElements {
            interfaces,
            states,
            history: None,
            dofs,
            offset,
        }
    }

    /// The same elements with the pairs' histories (slip, slip force, multipliers:
    /// `history[i][k]` for pair k of interface i), which enter their internal
    /// forces; without, every history is zero.
    pub fn with_history(mut self, history: Option<&'a [Vec<PairHistory<D>>]>) -> Self {
        self.history = history;
        self
    }

    /// The interface, the pair and its state of source element `e`.
    fn locate(&self, e: usize) -> (&Interface<D>, usize, PairState) {
        let i = self.offset.partition_point(|&o| o <= e) - 1;
        let k = e - self.offset[i];
        let state = self.states.map_or(PairState::Bonded, |s| s[i][k]);
        (&self.interfaces[i], k, state)
    }
}

impl<D: Dim> ElementSource for CouplingElements<'_, D> {
    fn len(&self) -> usize {
        *self.offset.last().unwrap_or(&0)
    }

    fn nodes(&self, e: usize, f: &mut dyn FnMut(&[usize])) {
        let (iface, k, _) = self.locate(e);
        let (g, n) = iface.elements[k].global_nodes(self.dofs, iface.host, iface.node_part);
        f(&g[..n]);
    }

    fn stiffness(&self, e: usize, sink: &mut MatrixSink<'_>) {
        let (iface, k, state) = self.locate(e);
        if state == PairState::Open {
            return;
        }
        let c = &iface.elements[k];
        // The penalties the law puts in the stiffness of this state (the
        // tangential one is 0 for a frictionless or slipping pair).
        let [c_n, c_s] = iface.params().penalties(state);
        let ke = c.stiffness(c_n, c_s, PairState::Bonded);
        let g = c.dofs(self.dofs, iface.host, iface.node_part);
        let n = g.as_slice().len();
        let mut k = [0.0; MAX_DOFS * MAX_DOFS];
        for a in 0..n {
            for b in 0..n {
                k[a * MAX_DOFS + b] = ke.get(a, b);
            }
        }
        sink(g.as_slice(), &k, MAX_DOFS);
    }

    fn internal_force(&self, e: usize, u: &[f64], sink: &mut VectorSink<'_>) {
        let (iface, k, state) = self.locate(e);
        let c = &iface.elements[k];
        let i = self.offset.partition_point(|&o| o <= e) - 1;
        let h = self.history.map_or(PairHistory::default(), |h| h[i][k]);
        let p = iface.pair_at(k, self.dofs, u, state, &h);
        let fe = c.nodal_force(p.force);
        sink(p.dofs.as_slice(), &fe[..c.n_dofs()]);
    }
}
