//! The coupling finite element (CFE): the host element's nodes plus the coupling
//! node — 4 nodes ("T4") on a T3 host, 5 nodes on a Q4 host (SPEC §2, seed eqs. 3–16).
//!
//! Kinematics: `[[U]] = D_c − Σᵢ N̄ᵢ(X_C) Dᵢ = B_e D_e`,
//! `B_e = [−N̄₁I … −N̄ₙI I]` (2 × 2(n+1), n = 3 or 4 host nodes).
//! Local frame: `R = [[n₁ n₂], [s₁ s₂]]`, s = n turned +90°, `[[u]] = R [[U]]`
//! ([`Dim::frame`] of [`D2`]; this element is still the plane one).
//! Law: `c = diag(c_n, c_s)`, `C = Rᵀ c R`; internal force `F_e = B_eᵀ Rᵀ f` and
//! stiffness `K_e = B_eᵀ (1 − D̂) C B_e` (symmetric).
//!
//! Initial gap: a pair found within a search distance keeps its node where it is
//! meshed and stores its initial normal gap g₀; the law acts on `g_n = g₀ + [[u_n]]`,
//! so `F_e` gains the constant `B_eᵀ Rᵀ (c_n g₀, 0)` (a load term; K_e unchanged).
//!
//! Element DOFs are ordered `[u₁ v₁ … uₙ vₙ u_c v_c]`: host nodes, then the coupling
//! node.
//!
//! The same element serves the segment coupling (`coupling = "segment"`, built in
//! [`super::segment`]): there the jump of coupling node a is the gap integrated
//! over its face segments, `[[U]]_a = Σ_b M̂_ab D_b − Σ_i N̂_ai D_i` (node-part nodes
//! b: a and its face neighbours; host nodes i of every host element under a's
//! segments), so `B_e = [−N̂_a1 I … −N̂_an I  M̂_a1 I … M̂_am I]` with both coefficient
//! rows summing to 1, and the penalties are scaled by the node's weight ω
//! (`c = ω diag(c_n, c_s)`); the node CFE is the case of one node-side node with
//! coefficient 1 and ω = 1.

use super::law::{LawParams, PairHistory, PairState};
use crate::dim::{D2, Dim, Tangent};
use crate::dofs::DofMap;

/// Most nodes a CFE has. The node CFE has a host element's 3 or 4 plus the coupling
/// node; a segment-coupling element has up to 3 node-part nodes and the host nodes
/// of the host elements under them (up to 9: three Q4 or T3 hosts).
pub const MAX_NODES: usize = 12;
/// Most nodes a 3D CFE has: a coupling node inside a HEX8 host (the volume form,
/// overlapping meshes) — 9; on a host face it has 4 (TET4 face: 3 + 1, HEX8
/// face: 4 + 1). The 3D segment coupling does not exist (it needs polygon
/// clipping), so no 3D element has more.
pub const MAX_NODES_3D: usize = 9;
/// Most DOFs a CFE has: 2 × [`MAX_NODES`] = 24 in 2D, 3 × [`MAX_NODES_3D`] = 27
/// in 3D; the larger. Arrays of this size hold any element's DOFs, of which the
/// first [`CouplingElement::n_dofs`] are read.
pub const MAX_DOFS: usize = if 2 * MAX_NODES > 3 * MAX_NODES_3D {
    2 * MAX_NODES
} else {
    3 * MAX_NODES_3D
};

/// One coupling pair: a coupling node of the node part and the host element that
/// contains it, with everything the CFE needs, computed once in the reference
/// configuration.
///
/// Generic over the dimension `D` (DOFs per node, point and frame types; [`D2`]
/// by default): a 3D element is `CouplingElement<D3>` with the same fields.
#[derive(Debug, Clone, PartialEq)]
pub struct CouplingElement<D: Dim = D2> {
    /// The coupling node (index in the node part's mesh).
    pub node: usize,
    /// The host element (index in the host part's mesh).
    pub host_element: usize,
    /// The host element's nodes (indices in the host part's mesh): 3 for a T3 host,
    /// 4 for a Q4 host.
    pub host_nodes: Vec<usize>,
    /// Host shape functions at the coupling node, N̄ᵢ(X_C), one per host node (they
    /// sum to 1).
    pub shape: Vec<f64>,
    /// Unit outward normal n of the host boundary at the coupling node.
    pub normal: D::Vector,
    /// Reference position X_C of the coupling node: its projection on the host
    /// edge, where the node part's node is placed.
    pub position: D::Vector,
    /// Distance from the coupling node, as meshed, to the host edge it was
    /// projected on (how far it was moved, unless it was paired within a search
    /// distance: then it stays and the distance is its gap's magnitude); with
    /// segment coupling, the largest distance of its face segments' Gauss points
    /// from their host edges.
    pub distance: f64,
    /// Initial normal gap g₀ (length, along `normal`: positive apart, negative
    /// overlapping), for a pair found within a search distance; 0 for a node moved
    /// onto its host edge.
    pub gap0: f64,
    /// Tributary length of the coupling node on the node part's face: half the sum
    /// of the lengths of the node part's boundary edges at the node whose both ends
    /// couple in the same interface (for the segment coupling, m_a). Force /
    /// (tributary length × the node part's thickness) = traction
    /// ([`CouplingElement::traction`]). In 3D an area: the node's share ∫ Nᵢ dA of
    /// the node part's faces whose corners all couple (the thickness is then 1).
    pub tributary: f64,
    /// Length of the host edge the node was projected on (the scale of the
    /// geometrically linear limit: slip small against it); in 3D the host face's
    /// size, its longest edge.
    pub edge_length: f64,
    /// The ring the pair stands for in an axisymmetric model, 2π r̄ (r̄ the mean
    /// radius of the node's share of the face, `∫ N_a r ds / ∫ N_a ds`): the
    /// pair's penalties and forces are per unit circumference times it, totals
    /// over the ring. 1 in a plane model.
    pub ring: f64,
    /// `None` for the node CFE; for the segment coupling, the node side of the
    /// coupling node's integrated gap (then `host_nodes` and `shape` are the host
    /// nodes under its face segments and their coefficients N̂_ai).
    pub segment: Option<SegmentSide>,
}

/// The node side of a segment-coupling element of coupling node a (see
/// [`super::segment`]): `[[U]]_a = Σ_b M̂_ab D_b − Σ_i N̂_ai D_i` with
/// `M̂_ab = ∫ N_a N_b ds / m_a`, `N̂_ai = ∫ N_a N̄_i ds / m_a`, `m_a = ∫ N_a ds`.
#[derive(Debug, Clone, PartialEq)]
pub struct SegmentSide {
    /// The node-part nodes b: a and its neighbours along the face (indices in the
    /// node part's mesh), in the order of the element's DOFs.
    pub nodes: Vec<usize>,
    /// Their coefficients M̂_ab (they sum to 1).
    pub shape: Vec<f64>,
    /// The node's share of the face lying over the host, m_a = ∫ N_a ds.
    pub length: f64,
    /// The penalty weight ω = m_a / h̄ (h̄ the mean face-segment length of the
    /// interface): the element's stiffness is ω c_n, ω c_s.
    pub weight: f64,
}

/// The traction (a stress) a pair's force stands for: `force / (length × thickness)`,
/// the force spread over the pair's share of the node part's face — its length
/// there times the node part's out-of-plane thickness t. The one home of the
/// pairs' `pressure` and `shear`. The force is the whole part's (a stiffness is
/// E·t, a penalty force per length over the thickness t), so in plane stress
/// this is the mean traction across t, and in plane strain, whose forces are per
/// unit thickness when t = 1 (the default), the traction too for any t. 0 for a
/// pair with no share of the face (`length` 0).
pub fn traction(force: f64, length: f64, thickness: f64) -> f64 {
    if length > 0.0 {
        force / (length * thickness)
    } else {
        0.0
    }
}

impl<D: Dim> CouplingElement<D> {
    /// The traction of `force` (a force of this pair on the node part, normal or
    /// tangential) on the node part's face: [`traction`] over the pair's tributary
    /// length and the node part's thickness `thickness`. The face belongs to both
    /// parts, but the force crosses it where the node part meets it, over the node
    /// part's thickness; when the host's thickness differs, this is the node part's
    /// side of the interface.
    ///
    /// In an axisymmetric model the force is a total over the ring and crosses
    /// the ring's band of the face, tributary length × 2π r̄ ([`Self::ring`]; the
    /// thickness is 1 there).
    pub fn traction(&self, force: f64, thickness: f64) -> f64 {
        traction(force, self.tributary, thickness * self.ring)
    }

    /// Number of DOFs of the CFE: `D::N` × (host nodes + node-side nodes).
    pub fn n_dofs(&self) -> usize {
        D::N * (self.host_nodes.len() + self.node_shape().len())
    }

    /// The node side's nodes (in the node part): the coupling node, or for the
    /// segment coupling the node and its face neighbours.
    pub fn node_side(&self) -> &[usize] {
        match &self.segment {
            None => std::slice::from_ref(&self.node),
            Some(s) => &s.nodes,
        }
    }

    /// The node side's coefficients: `[1]` for the node CFE, M̂_ab for the segment
    /// coupling.
    pub fn node_shape(&self) -> &[f64] {
        match &self.segment {
            None => &[1.0],
            Some(s) => &s.shape,
        }
    }

    /// The penalty weight ω: 1 for the node CFE, m_a / h̄ for the segment
    /// coupling; times the ring 2π r̄ in an axisymmetric model ([`Self::ring`]).
    pub fn weight(&self) -> f64 {
        self.ring * self.segment.as_ref().map_or(1.0, |s| s.weight)
    }

    /// The global nodes of the CFE in its local order: the host element's nodes
    /// (in part `host`), then the node side's (in part `node_part`); the first
    /// `n + m` entries are used (m = 1 node, or 2 for a segment point).
    pub fn global_nodes(
        &self,
        dofs: &DofMap<D>,
        host: usize,
        node_part: usize,
    ) -> ([usize; MAX_NODES], usize) {
        let n = self.host_nodes.len();
        let mut g = [0; MAX_NODES];
        for (gi, &h) in g.iter_mut().zip(&self.host_nodes) {
            *gi = dofs.node(host, h);
        }
        let side = self.node_side();
        for (gi, &j) in g[n..].iter_mut().zip(side) {
            *gi = dofs.node(node_part, j);
        }
        (g, n + side.len())
    }

    /// The global DOFs of the CFE, `[u₁ v₁ … uₙ vₙ u_c v_c]` in 2D, `D::N` per
    /// node (host nodes in part `host`, then the coupling node in part
    /// `node_part`).
    pub fn dofs(&self, dofs: &DofMap<D>, host: usize, node_part: usize) -> CfeDofs {
        let (g, n) = self.global_nodes(dofs, host, node_part);
        let mut ids = [0; MAX_DOFS];
        for (a, &gn) in g[..n].iter().enumerate() {
            for c in 0..D::N {
                ids[D::N * a + c] = D::dof(gn, c);
            }
        }
        CfeDofs { ids, len: D::N * n }
    }

    /// The global jump `[[U]] = D_c − Σ N̄ᵢ Dᵢ` for element displacements `d`
    /// (as `CfeDofs::gather` orders them; entries past [`n_dofs`](Self::n_dofs) are ignored).
    pub fn jump(&self, d: &[f64]) -> D::Vector {
        jump::<D>(&self.shape, self.node_shape(), &d[..self.n_dofs()])
    }

    /// The local jump `[[u]] = R [[U]] = ([[u_n]], [[u_t]])` for element
    /// displacements `d`: normal and tangential.
    pub fn local_jump(&self, d: &[f64]) -> (f64, D::Tangent) {
        local_jump::<D>(self.normal, self.jump(d))
    }

    /// The normal gap `gap_n = g₀ + [[u_n]]` (positive: the faces are apart) for
    /// element displacements `d`.
    pub fn gap_n(&self, d: &[f64]) -> f64 {
        self.gap(self.local_jump(d))
    }

    /// The normal gap `g₀ + [[u_n]]` for the local jump `jump`.
    pub fn gap(&self, jump: (f64, D::Tangent)) -> f64 {
        if self.gap0 == 0.0 {
            jump.0
        } else {
            self.gap0 + jump.0
        }
    }

    /// The stiffness `K_e = B_eᵀ (1 − D̂) C B_e`, `C = Rᵀ c R`, for penalties
    /// `c_n`, `c_s` and the pair's `state` (zero when open).
    /// For a segment point the penalties are scaled by its weight ω.
    pub fn stiffness(&self, c_n: f64, c_s: f64, state: PairState) -> CfeStiffness<D> {
        let w = self.weight();
        stiffness::<D>(
            &self.shape,
            self.node_shape(),
            self.normal,
            w * c_n,
            w * c_s,
            state,
        )
    }

    /// The bonded stiffness in rank-one terms, `K_e = Σ_k c_k w_k w_kᵀ` over the
    /// local axes k (the normal, then each tangent: 1 + `Tangent::COMPONENTS`),
    /// with `w_k = (R_k B_e)ᵀ`, i.e. `w_k[N a + i] = b_a R_k[i]`: `f(k, c_k, w_k)`
    /// for each, from the same `b` and `R` as [`stiffness`](Self::stiffness).
    /// Bonding a pair adds these terms to K, opening it removes them (the
    /// low-rank update). For a segment point `c_k` includes its weight ω.
    pub fn for_each_stiffness_term(
        &self,
        c_n: f64,
        c_s: f64,
        mut f: impl FnMut(usize, f64, &[f64; MAX_DOFS]),
    ) {
        let r = D::frame(self.normal);
        let b = b_coefficients(&self.shape, self.node_shape());
        let wt = self.weight();
        for k in 0..=<D::Tangent as Tangent>::COMPONENTS {
            let axis = D::axis(&r, k);
            let mut w = [0.0; MAX_DOFS];
            for (p, x) in w.iter_mut().enumerate().take(self.n_dofs()) {
                *x = b[p / D::N] * axis.as_ref()[p % D::N];
            }
            f(k, wt * if k == 0 { c_n } else { c_s }, &w);
        }
    }

    /// The internal force `F_e = B_eᵀ Rᵀ f`, `f = (1 − D̂) c [[u]]`, for element
    /// displacements `d`, and the local force `f` (the force the host side exerts on
    /// the pair, in (n, s)). For a segment point the penalties are scaled by its
    /// weight ω, so `f` is the point's force.
    pub fn internal_force(
        &self,
        c_n: f64,
        c_s: f64,
        state: PairState,
        d: &[f64],
    ) -> ([f64; MAX_DOFS], (f64, D::Tangent)) {
        let w = self.weight();
        internal_force::<D>(
            &self.shape,
            self.node_shape(),
            self.normal,
            w * c_n,
            w * c_s,
            state,
            &d[..self.n_dofs()],
        )
    }
}

impl<D: Dim> CouplingElement<D> {
    /// The pair at element displacements `d` (gathered at `dofs`) under the law
    /// `law` (the interface's; scaled here by the element's weight ω,
    /// [`Self::params`]) in `state` with history `h`: its local jump, its normal gap
    /// g₀ + \[\[u_n\]\] and its local force from [`LawParams::local_force`] (so the
    /// force includes the initial-gap, slip-history, slip-force and multiplier
    /// terms). What `Interface::pair_at` gives for pair k of an interface.
    pub fn at(
        &self,
        dofs: CfeDofs,
        d: [f64; MAX_DOFS],
        law: &LawParams,
        state: PairState,
        h: &PairHistory<D>,
    ) -> PairAt<D> {
        let jump = self.local_jump(&d);
        let gap = self.gap(jump);
        PairAt {
            dofs,
            d,
            jump,
            gap,
            force: self.params(law).local_force(state, gap, jump.1, h),
        }
    }

    /// The internal force `F_e = B_eᵀ Rᵀ f` of the local force `f` (the force the
    /// host side exerts on the pair, in (n, s); the first
    /// [`n_dofs`](Self::n_dofs) entries are the element's).
    pub fn nodal_force(&self, f: (f64, D::Tangent)) -> [f64; MAX_DOFS] {
        nodal_force::<D>(&self.shape, self.node_shape(), self.normal, f)
    }

    /// The interface's law with this element's penalties: `c_n`, `c_s` scaled by its
    /// weight ω (1 for the node CFE, so the parameters are returned unchanged).
    pub fn params(&self, law: &LawParams) -> LawParams {
        let w = self.weight();
        if w == 1.0 {
            *law
        } else {
            LawParams {
                c_n: w * law.c_n,
                c_s: w * law.c_s,
                c_slip: w * law.c_slip,
                ..*law
            }
        }
    }
}

impl CouplingElement<D2> {
    /// The bonded stiffness of a plane element in rank-one form (k = n, s):
    /// [`for_each_stiffness_term`](Self::for_each_stiffness_term)'s two terms
    /// `(c_k, w_k)` as an array.
    pub fn stiffness_terms(&self, c_n: f64, c_s: f64) -> [(f64, [f64; MAX_DOFS]); 2] {
        let mut terms = [(0.0, [0.0; MAX_DOFS]); 2];
        self.for_each_stiffness_term(c_n, c_s, |k, c, w| terms[k] = (c, *w));
        terms
    }
}

/// A coupling pair evaluated at displacements u: its DOFs, its element
/// displacements, its local jump, its normal gap and its force under its law in a
/// state (`Interface::pair_at`, the one evaluation of a pair that the law check,
/// the pair-history rules, the assembly of internal forces and the pair outputs
/// read).
/// In any dimension: the tangential parts are the dimension's tangent
/// ([`Dim::Tangent`]; one component along s in 2D).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairAt<D: Dim = D2> {
    /// The pair's global DOFs.
    pub dofs: CfeDofs,
    /// Its element displacements (zero past its DOFs): see [`Self::d`].
    pub d: [f64; MAX_DOFS],
    /// The local jump `[[u]] = ([[u_n]], [[u_t]])`: normal, tangential.
    pub jump: (f64, D::Tangent),
    /// The normal gap `g₀ + [[u_n]]` (positive: the faces are apart).
    pub gap: f64,
    /// The local force `f = (f_n, f_t)` the host side exerts on the pair.
    pub force: (f64, D::Tangent),
}

impl<D: Dim> PairAt<D> {
    /// The element displacements, as many as the pair has DOFs.
    pub fn d(&self) -> &[f64] {
        &self.d[..self.dofs.len]
    }
}

/// The global DOFs of one coupling element in its local order (host nodes, then the
/// coupling node): see [`CouplingElement::dofs`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CfeDofs {
    ids: [usize; MAX_DOFS],
    len: usize,
}

impl CfeDofs {
    /// The DOFs `ids` (at most [`MAX_DOFS`]), in a pair's local order.
    pub fn new(ids: &[usize]) -> Self {
        let mut all = [0; MAX_DOFS];
        all[..ids.len()].copy_from_slice(ids);
        Self {
            ids: all,
            len: ids.len(),
        }
    }

    /// The DOF numbers, 2 (n + 1) of them.
    pub fn as_slice(&self) -> &[usize] {
        &self.ids[..self.len]
    }

    /// The element displacements: the entries of `u` (all DOFs) at these DOFs
    /// (zero past the element's).
    pub fn gather(&self, u: &[f64]) -> [f64; MAX_DOFS] {
        let mut d = [0.0; MAX_DOFS];
        for (x, &g) in d.iter_mut().zip(self.as_slice()) {
            *x = u[g];
        }
        d
    }
}

/// The global jump `[[U]] = D_c − Σ N̄ᵢ Dᵢ` for element displacements `d`
/// (`D::N` (n + m) values: host nodes, then the node side's m nodes), with
/// `D_c = Σ_j N_j D_j` over the node side (`node_shape`; `[1]` for a coupling node).
fn jump<D: Dim>(shape: &[f64], node_shape: &[f64], d: &[f64]) -> D::Vector {
    let n = shape.len();
    let dim = D::N;
    debug_assert_eq!(d.len(), dim * (n + node_shape.len()));
    let mut out = D::Vector::default();
    for (c, o) in out.as_mut().iter_mut().enumerate() {
        let node = node_shape
            .iter()
            .enumerate()
            .skip(1)
            .fold(node_shape[0] * d[dim * n + c], |acc, (j, nj)| {
                acc + nj * d[dim * (n + j) + c]
            });
        *o = node - (0..n).map(|i| shape[i] * d[dim * i + c]).sum::<f64>();
    }
    out
}

/// The local jump `[[u]] = R [[U]] = ([[u_n]], [[u_t]])` in the frame of the
/// host normal `normal` ([`Dim::frame`]).
fn local_jump<D: Dim>(normal: D::Vector, jump: D::Vector) -> (f64, D::Tangent) {
    D::to_local(&D::frame(normal), jump)
}

/// The coefficients `b` of `B_e` per node, `B_e = [b₁I … b_{n+m}I]` with
/// `b = (−N̄₁, …, −N̄ₙ, N₁, …, N_m)` (the node side's `node_shape`: `[1]` for a
/// coupling node); entries past n + m are zero.
fn b_coefficients(shape: &[f64], node_shape: &[f64]) -> [f64; MAX_NODES] {
    let mut b = [0.0; MAX_NODES];
    for (bi, s) in b.iter_mut().zip(shape) {
        *bi = -s;
    }
    b[shape.len()..shape.len() + node_shape.len()].copy_from_slice(node_shape);
    b
}

/// A CFE stiffness `K_e = B_eᵀ (1 − D̂) C B_e` in factored form: since
/// `B_e = b ⊗ I`, `K_e[N a+i][N b+j] = b_a b_b C_ij` with `C = (1 − D̂) Rᵀ c R`
/// (N = `D::N`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CfeStiffness<D: Dim = D2> {
    /// `b = (−N̄₁, …, −N̄ₙ, 1)` (zero past the element's nodes).
    pub b: [f64; MAX_NODES],
    /// `(1 − D̂) Rᵀ c R` (N×N, symmetric; its first N rows and columns).
    pub c: [[f64; MAX_N]; MAX_N],
    /// Number of DOFs, N (n + 1).
    pub dofs: usize,
    dim: std::marker::PhantomData<D>,
}

/// Most DOFs per node of a dimension ([`CfeStiffness::c`]'s size).
pub const MAX_N: usize = 3;

impl<D: Dim> CfeStiffness<D> {
    /// Entry (p, q), p, q < `dofs`.
    pub fn get(&self, p: usize, q: usize) -> f64 {
        self.b[p / D::N] * self.b[q / D::N] * self.c[p % D::N][q % D::N]
    }

    /// `K_e d` for element displacements `d`.
    pub fn mul(&self, d: &[f64]) -> [f64; MAX_DOFS] {
        let mut out = [0.0; MAX_DOFS];
        for (p, o) in out.iter_mut().enumerate().take(self.dofs) {
            *o = (0..self.dofs).map(|q| self.get(p, q) * d[q]).sum();
        }
        out
    }
}

/// CFE stiffness `K_e = B_eᵀ (1 − D̂) C B_e`, `C = Rᵀ c R` (symmetric, positive
/// semidefinite; zero for an open pair): `C_ij = (1 − D̂) (c_n n_i n_j + c_s Σ_t
/// t_i t_j)` over the frame's axes.
fn stiffness<D: Dim>(
    shape: &[f64],
    node_shape: &[f64],
    normal: D::Vector,
    c_n: f64,
    c_s: f64,
    state: PairState,
) -> CfeStiffness<D> {
    let r = D::frame(normal);
    let k = 1.0 - state.d_hat();
    let n = D::axis(&r, 0);
    let n = n.as_ref();
    let tangents: Vec<D::Vector> = (1..=<D::Tangent as Tangent>::COMPONENTS)
        .map(|t| D::axis(&r, t))
        .collect();
    let mut c = [[0.0; MAX_N]; MAX_N];
    for (i, row) in c.iter_mut().enumerate().take(D::N) {
        for (j, cij) in row.iter_mut().enumerate().take(D::N) {
            let sum = tangents.iter().fold(c_n * n[i] * n[j], |sum, t| {
                sum + c_s * t.as_ref()[i] * t.as_ref()[j]
            });
            *cij = k * sum;
        }
    }
    CfeStiffness {
        b: b_coefficients(shape, node_shape),
        c,
        dofs: D::N * (shape.len() + node_shape.len()),
        dim: std::marker::PhantomData,
    }
}

/// CFE internal force `F_e = B_eᵀ Rᵀ f` with `f = (1 − D̂) c [[u]]`, for element
/// displacements `d` (the first N (n + 1) entries of the result are the element's).
/// Also returns the local force `f` (the force the host side exerts on the pair,
/// normal and tangential).
fn internal_force<D: Dim>(
    shape: &[f64],
    node_shape: &[f64],
    normal: D::Vector,
    c_n: f64,
    c_s: f64,
    state: PairState,
    d: &[f64],
) -> ([f64; MAX_DOFS], (f64, D::Tangent)) {
    let (u_n, u_t) = local_jump::<D>(normal, jump::<D>(shape, node_shape, d));
    let k = 1.0 - state.d_hat();
    let f = (k * c_n * u_n, u_t.scale(k * c_s));
    (nodal_force::<D>(shape, node_shape, normal, f), f)
}

/// `F_e = B_eᵀ Rᵀ f` for the local force `f` (the first N (n + m) entries are the
/// element's).
fn nodal_force<D: Dim>(
    shape: &[f64],
    node_shape: &[f64],
    normal: D::Vector,
    f: (f64, D::Tangent),
) -> [f64; MAX_DOFS] {
    let g = D::to_global(&D::frame(normal), f.0, f.1);
    let g = g.as_ref();
    let b = b_coefficients(shape, node_shape);
    let mut out = [0.0; MAX_DOFS];
    for (p, o) in out
        .iter_mut()
        .enumerate()
        .take(D::N * (shape.len() + node_shape.len()))
    {
        *o = b[p / D::N] * g[p % D::N];
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normal() -> [f64; 2] {
        let a: f64 = 0.4;
        [a.cos(), a.sin()]
    }

    /// The two kinds of host: a T3 with the coupling node on its edge 1–2, and a
    /// distorted Q4 with the node at natural coordinates (0.3, −1) (on its edge 1–2)
    /// and, to exercise all four shape functions, at an interior point (0.3, 0.2):
    /// (host corners, shape functions there, coupling-node position Σ N̄ᵢ Xᵢ).
    type Host = (Vec<[f64; 2]>, Vec<f64>, [f64; 2]);

    fn hosts() -> Vec<Host> {
        let t3 = vec![[0.0, 0.0], [10.0, 1.0], [3.0, 8.0]];
        let q4 = vec![[0.0, 0.0], [10.0, 1.0], [11.0, 9.0], [-1.0, 7.0]];
        let q4_shape = |xi: f64, eta: f64| -> Vec<f64> {
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .iter()
                .map(|(a, b)| 0.25 * (1.0 + a * xi) * (1.0 + b * eta))
                .collect()
        };
        let at = |x: &[[f64; 2]], n: &[f64]| -> [f64; 2] {
            std::array::from_fn(|c| x.iter().zip(n).map(|(p, w)| w * p[c]).sum())
        };
        let mut out = Vec::new();
        for (x, n) in [
            (t3.clone(), vec![0.3, 0.7, 0.0]),
            (q4.clone(), q4_shape(0.3, -1.0)),
            (q4.clone(), q4_shape(0.3, 0.2)),
        ] {
            let c = at(&x, &n);
            out.push((x, n, c));
        }
        out
    }

    fn dense(k: &CfeStiffness) -> Vec<Vec<f64>> {
        (0..k.dofs)
            .map(|p| (0..k.dofs).map(|q| k.get(p, q)).collect())
            .collect()
    }

    /// K_e is symmetric and positive semidefinite (xᵀKx ≥ 0 for many x), of the
    /// size 2 (n + 1), and an open pair has zero stiffness — for T3 and Q4 hosts.
    #[test]
    fn stiffness_symmetric_psd() {
        for (_, shape, _) in hosts() {
            let ks = stiffness::<D2>(&shape, &[1.0], normal(), 1e9, 5e8, PairState::Bonded);
            assert_eq!(ks.dofs, 2 * (shape.len() + 1));
            let k = dense(&ks);
            for (i, row) in k.iter().enumerate() {
                for (j, v) in row.iter().enumerate() {
                    assert_eq!(*v, k[j][i], "K[{i}][{j}] != K[{j}][{i}]");
                }
            }
            let mut seed = 12345u64;
            for _ in 0..200 {
                let x: Vec<f64> = (0..ks.dofs)
                    .map(|_| {
                        seed = seed
                            .wrapping_mul(6364136223846793005)
                            .wrapping_add(1442695040888963407);
                        (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
                    })
                    .collect();
                let e: f64 = (0..ks.dofs)
                    .map(|i| (0..ks.dofs).map(|j| x[i] * k[i][j] * x[j]).sum::<f64>())
                    .sum();
                assert!(e >= -1e-6);
            }
            let open = stiffness::<D2>(&shape, &[1.0], normal(), 1e9, 5e8, PairState::Open);
            assert!(dense(&open).iter().flatten().all(|&v| v == 0.0));
        }
    }

    /// A rigid translation and an infinitesimal rigid rotation of host and coupling
    /// node together produce no jump and no energy: K_e d = 0 (coupling node at
    /// X_C = Σ N̄ᵢ Xᵢ), for the 4-node CFE on a T3 and the 5-node CFE on a Q4.
    #[test]
    fn rigid_body_motion_has_zero_energy() {
        for (x, shape, xc) in hosts() {
            let pts: Vec<[f64; 2]> = x.iter().copied().chain([xc]).collect();
            let m = 2 * pts.len();
            let k = stiffness::<D2>(&shape, &[1.0], normal(), 1e9, 1e9, PairState::Bonded);
            let modes: [Vec<f64>; 3] = [
                (0..m).map(|i| if i % 2 == 0 { 1.0 } else { 0.0 }).collect(),
                (0..m).map(|i| if i % 2 == 1 { 1.0 } else { 0.0 }).collect(),
                (0..m)
                    .map(|i| {
                        if i % 2 == 0 {
                            -pts[i / 2][1]
                        } else {
                            pts[i / 2][0]
                        }
                    })
                    .collect(),
            ];
            for d in modes {
                assert!(jump::<D2>(&shape, &[1.0], &d).iter().all(|v| v.abs() < 1e-12));
                let kd = k.mul(&d);
                assert!(kd.iter().all(|v| v.abs() < 1e-9 * 1e9), "{kd:?}");
            }
        }
    }

    /// The internal force equals K_e d for a bonded pair (the law is linear there),
    /// and its node-by-node sum vanishes (the CFE is self-equilibrated).
    #[test]
    fn internal_force_is_k_times_d_and_balanced() {
        for (_, shape, _) in hosts() {
            let m = 2 * (shape.len() + 1);
            let d: Vec<f64> = (0..m).map(|i| ((i * 7) % 5) as f64 * 0.1 - 0.2).collect();
            let k = stiffness::<D2>(&shape, &[1.0], normal(), 2.0, 3.0, PairState::Bonded);
            let (f, _) = internal_force::<D2>(&shape, &[1.0], normal(), 2.0, 3.0, PairState::Bonded, &d);
            let kd = k.mul(&d);
            for i in 0..m {
                assert!((kd[i] - f[i]).abs() < 1e-12);
            }
            assert!(f[m..].iter().all(|&v| v == 0.0));
            for c in 0..2 {
                assert!((0..m / 2).map(|a| f[2 * a + c]).sum::<f64>().abs() < 1e-12);
            }
        }
    }

    /// The local frame: a coupling node pushed along −n has [[u_n]] < 0 and
    /// [[u_s]] = 0; pushed along s, [[u_s]] equals the push.
    #[test]
    fn local_jump_components() {
        let n = normal();
        let s = [-n[1], n[0]];
        let u = local_jump::<D2>(n, [-2.0 * n[0], -2.0 * n[1]]);
        assert!((u.0 + 2.0).abs() < 1e-15 && u.1.abs() < 1e-15);
        let u = local_jump::<D2>(n, [0.5 * s[0], 0.5 * s[1]]);
        assert!(u.0.abs() < 1e-15 && (u.1 - 0.5).abs() < 1e-15);
    }

    /// The rank-2 form `Σ_k c_k w_k w_kᵀ` is the bonded stiffness, for T3 and Q4 hosts.
    #[test]
    fn stiffness_terms_sum_to_the_stiffness() {
        for (x, shape, position) in hosts() {
            let c = CouplingElement::<D2> {
                node: 0,
                host_element: 0,
                host_nodes: (0..x.len()).collect(),
                shape: shape.clone(),
                normal: normal(),
                position,
                distance: 0.0,
                gap0: 0.0,
                tributary: 1.0,
                edge_length: 1.0,
                ring: 1.0,
                segment: None,
            };
            let k = c.stiffness(1e9, 5e8, PairState::Bonded);
            let terms = c.stiffness_terms(1e9, 5e8);
            for p in 0..c.n_dofs() {
                for q in 0..c.n_dofs() {
                    let sum: f64 = terms.iter().map(|(ck, w)| ck * w[p] * w[q]).sum();
                    assert!((sum - k.get(p, q)).abs() <= 1e-6, "({p}, {q})");
                }
            }
        }
    }

    /// A segment-coupling element (node side: three nodes with coefficients
    /// M̂, weight ω): a rigid translation and rotation of host and node part together
    /// gives no jump and no force when Σ M̂_b X_b = Σ N̂_i X_i; its stiffness is ω ×
    /// the unit-weight one, equals its rank-2 form, and K_e d = F_e.
    #[test]
    fn segment_side_element() {
        for (x, shape, position) in hosts() {
            // Three node-side nodes whose weighted position is the host point.
            let m = [0.2, 0.5, 0.3];
            let off = [[-1.0, 0.5], [0.4, -0.2], [0.0, 0.0]];
            let mut pts: Vec<[f64; 2]> = off
                .iter()
                .map(|o| [position[0] + o[0], position[1] + o[1]])
                .collect();
            let mean: [f64; 2] =
                std::array::from_fn(|c| (0..3).map(|b| m[b] * pts[b][c]).sum::<f64>());
            pts[2] = [
                pts[2][0] + (position[0] - mean[0]) / m[2],
                pts[2][1] + (position[1] - mean[1]) / m[2],
            ];
            let mut c = CouplingElement::<D2> {
                node: 11,
                host_element: 0,
                host_nodes: (0..x.len()).collect(),
                shape: shape.clone(),
                normal: normal(),
                position,
                distance: 0.0,
                gap0: 0.0,
                tributary: 0.5,
                edge_length: 1.0,
                ring: 1.0,
                segment: Some(SegmentSide {
                    nodes: vec![10, 11, 12],
                    shape: m.to_vec(),
                    length: 0.5,
                    weight: 0.25,
                }),
            };
            assert_eq!(c.n_dofs(), 2 * (x.len() + 3));
            let all: Vec<[f64; 2]> = x.iter().copied().chain(pts).collect();
            let n = 2 * all.len();
            for d in [
                (0..n).map(|i| (i % 2) as f64).collect::<Vec<f64>>(),
                (0..n)
                    .map(|i| {
                        if i % 2 == 0 {
                            -all[i / 2][1]
                        } else {
                            all[i / 2][0]
                        }
                    })
                    .collect(),
            ] {
                assert!(
                    c.jump(&d).iter().all(|v| v.abs() < 1e-12),
                    "{:?}",
                    c.jump(&d)
                );
                let (f, _) = c.internal_force(1e9, 1e9, PairState::Bonded, &d);
                assert!(f.iter().all(|v| v.abs() < 1e-3), "{f:?}");
            }
            let k = c.stiffness(2.0, 3.0, PairState::Bonded);
            let terms = c.stiffness_terms(2.0, 3.0);
            let d: Vec<f64> = (0..n).map(|i| ((i * 7) % 5) as f64 * 0.1 - 0.2).collect();
            let (f, _) = c.internal_force(2.0, 3.0, PairState::Bonded, &d);
            let kd = k.mul(&d);
            for p in 0..n {
                assert!((kd[p] - f[p]).abs() < 1e-12);
                for q in 0..n {
                    let sum: f64 = terms.iter().map(|(ck, w)| ck * w[p] * w[q]).sum();
                    assert!((sum - k.get(p, q)).abs() <= 1e-12, "({p}, {q})");
                }
            }
            let unit = {
                c.segment.as_mut().unwrap().weight = 1.0;
                c.stiffness(2.0, 3.0, PairState::Bonded)
            };
            for p in 0..n {
                for q in 0..n {
                    assert!((k.get(p, q) - 0.25 * unit.get(p, q)).abs() < 1e-14);
                }
            }
        }
    }
}
