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
use crate::fem::element;

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

/// The elements of every part (T3 and Q4), numbered part after part.
pub struct PartElements<'a, D: Dim = D2> {
    parts: &'a [Part],
    dofs: &'a DofMap<D>,
    /// First element of each part in the source's numbering (length parts + 1).
    offset: Vec<usize>,
    /// The constitutive matrix of each part.
    d: Vec<[[f64; 3]; 3]>,
    /// The 4×4 D of each axisymmetric part (`None` for a plane part).
    axi: Vec<Option<[[f64; 4]; 4]>>,
}

impl<'a, D: Dim> PartElements<'a, D> {
    /// The elements of `parts`, numbered with `dofs`.
    pub fn new(parts: &'a [Part], dofs: &'a DofMap<D>) -> Self {
        let mut offset = Vec::with_capacity(parts.len() + 1);
        let mut n = 0;
        for p in parts {
            offset.push(n);
            n += p.mesh.elements.len();
        }
        offset.push(n);
        let d = parts.iter().map(|p| p.material.d_matrix()).collect();
        let axi = parts
            .iter()
            .map(|p| p.material.is_axisymmetric().then(|| p.material.d_axisymmetric()))
            .collect();
        PartElements {
            parts,
            dofs,
            offset,
            d,
            axi,
        }
    }

    /// The stiffness of element `el` (corners `x`) of part `p`: the plane
    /// element's, or the axisymmetric one's ([`crate::fem::axisymmetric`]).
    #[inline(always)]
    fn stiffness_of(
        &self,
        p: usize,
        el: &crate::mesh::Element,
        x: &[[f64; 2]; element::MAX_NODES],
    ) -> element::ElementMatrix {
        match &self.axi[p] {
            None => element::stiffness(el, x, &self.d[p], self.parts[p].material.thickness),
            Some(d) => crate::fem::axisymmetric::stiffness(el, x, d),
        }
    }

    /// The internal force `K_e u_e` of element `el` of part `p`, as
    /// [`Self::stiffness_of`] chooses.
    #[inline(always)]
    fn force_of(
        &self,
        p: usize,
        el: &crate::mesh::Element,
        x: &[[f64; 2]; element::MAX_NODES],
        ue: &[f64; element::MAX_DOFS],
    ) -> [f64; element::MAX_DOFS] {
        match &self.axi[p] {
            None => element::internal_force(el, x, &self.d[p], self.parts[p].material.thickness, ue),
            Some(d) => crate::fem::axisymmetric::internal_force(el, x, d, ue),
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
    ) -> impl Iterator<Item = (usize, &'a Part, &'a [crate::mesh::Element])> + '_ {
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
    fn element(&self, e: usize) -> (element::ElementMatrix, [usize; element::MAX_DOFS], usize) {
        let (p, e) = self.locate(e);
        let part = &self.parts[p];
        let el = &part.mesh.elements[e];
        let x = element::coordinates(&part.mesh, el);
        let ke = self.stiffness_of(p, el, &x);
        let (g, n) = self.dofs.element_dofs(self.parts, p, e);
        (ke, g, n)
    }

    /// The internal force `K_e u_e` and global DOFs of source element `e` for the
    /// displacements `u` of all DOFs (without forming `K_e`).
    #[inline(always)]
    fn element_force(
        &self,
        e: usize,
        u: &[f64],
    ) -> ([f64; element::MAX_DOFS], [usize; element::MAX_DOFS], usize) {
        let (p, e) = self.locate(e);
        let part = &self.parts[p];
        let el = &part.mesh.elements[e];
        let x = element::coordinates(&part.mesh, el);
        let (g, n) = self.dofs.element_dofs(self.parts, p, e);
        let ue: [f64; element::MAX_DOFS] =
            std::array::from_fn(|i| if i < n { u[g[i]] } else { 0.0 });
        let fe = self.force_of(p, el, &x, &ue);
        (fe, g, n)
    }
}

impl<D: Dim> ElementSource for PartElements<'_, D> {
    fn len(&self) -> usize {
        *self.offset.last().unwrap_or(&0)
    }

    fn nodes(&self, e: usize, f: &mut dyn FnMut(&[usize])) {
        let (p, e) = self.locate(e);
        let nodes = self.parts[p].mesh.elements[e].nodes();
        let mut g = [0usize; element::MAX_NODES];
        for (gi, &n) in g.iter_mut().zip(nodes) {
            *gi = self.dofs.node(p, n);
        }
        f(&g[..nodes.len()]);
    }

    fn stiffness(&self, e: usize, sink: &mut MatrixSink<'_>) {
        let (ke, g, n) = self.element(e);
        sink(&g[..n], ke.as_flattened(), element::MAX_DOFS);
    }

    fn internal_force(&self, e: usize, u: &[f64], sink: &mut VectorSink<'_>) {
        let (fe, g, n) = self.element_force(e, u);
        sink(&g[..n], &fe[..n]);
    }

    fn for_each_nodes(&self, f: &mut dyn FnMut(&[usize])) {
        let mut g = [0usize; element::MAX_NODES];
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
                let x = element::coordinates(&part.mesh, el);
                let ke = self.stiffness_of(p, el, &x);
                let (g, n) = self.dofs.element_dofs(self.parts, p, e);
                sink(&g[..n], ke.as_flattened(), element::MAX_DOFS);
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
                let x = element::coordinates(&part.mesh, el);
                let mut ue = [0.0; element::MAX_DOFS];
                let dof = |a: usize, c: usize| self.dofs.dof(a, c);
                for (a, &n) in nodes.iter().enumerate() {
                    for c in 0..self.dofs.per_node() {
                        ue[dof(a, c)] = u[base + dof(n, c)];
                    }
                }
                let fe = self.force_of(p, el, &x, &ue);
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
