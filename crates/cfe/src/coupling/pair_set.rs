//! The pair set: how the contact scheme reaches the coupling pairs of a model —
//! as assembly reaches elements through `ElementSource` — without knowing what a
//! pair is made of or the dimension it lives in.
//!
//! A [`PairSet`] is a list of interfaces, each a list of pairs. Of an interface
//! it tells the law (its parameters, and the augmented-Lagrangian tolerance when
//! it is so enforced); of a pair its DOFs, its initial gap, where it is (for
//! messages), its rank-one stiffness terms (one per local component: the normal
//! and each tangent), its penalties scaled by its own weight, and — the one
//! evaluation of a pair at u — its local jump, normal gap and force under its
//! law in a state with a history ([`PairSet::at`]). Everything the law sweep
//! ([`super::check_law`]), the history rules ([`super::history`]) and the
//! contact scheme read of a pair comes through here, typed by the set's
//! dimension ([`PairSet::Dim`]: the tangent of the jump, the force and the
//! history, the point type). The trait splits what a set is (its dimension) from
//! what an evaluation is given (displacements, state, history), after fenris's
//! `Operator { type SolutionDim; type Parameters }`.
//!
//! [`InterfacePairs`] is the set of a model's interfaces and DOF map; a 3D model
//! gives its interfaces of 3D coupling elements the same way (`Dim = D3`), and a
//! test can give a pair set of its own (see this file's tests: a set with a
//! two-component tangent driven through the law sweep and the history rules).

use super::Interface;
use super::element::{CfeDofs, PairAt};
use super::law::{Enforcement, LawParams, PairHistory, PairState};
use crate::dim::{D2, Dim};
use crate::dofs::DofMap;

/// The coupling pairs of a model, as the contact scheme reads them: interface
/// `i` (0 ≤ i < [`interface_count`](Self::interface_count)) has pairs `k` (0 ≤ k
/// < [`pair_count`](Self::pair_count)`(i)`).
pub trait PairSet {
    /// The dimension of the pairs: their tangent, point and frame types.
    type Dim: Dim;

    /// Number of interfaces.
    fn interface_count(&self) -> usize;

    /// Number of pairs of interface `i`.
    fn pair_count(&self, i: usize) -> usize;

    /// The law of interface `i` with its own parameters.
    fn law(&self, i: usize) -> LawParams;

    /// The largest penetration (and stick error) accepted on interface `i` when
    /// it is enforced by the augmented Lagrangian; `None` under the penalty.
    fn augmented(&self, i: usize) -> Option<f64>;

    /// The law `base` (interface `i`'s, or its friction scaled by a continuation)
    /// with pair `k`'s own penalties: scaled by its weight (1 but for a
    /// segment-coupling point).
    fn pair_law(&self, i: usize, k: usize, base: &LawParams) -> LawParams;

    /// The global DOFs of pair `k` of interface `i`, in the pair's local order.
    fn pair_dofs(&self, i: usize, k: usize) -> CfeDofs;

    /// The initial normal gap g₀ of pair `k` of interface `i` (0 for a node moved
    /// onto its host face).
    fn initial_gap(&self, i: usize, k: usize) -> f64;

    /// Where pair `k` of interface `i` is, for messages: the interface's name,
    /// the coupling node (in the node part) and its reference position.
    fn label(&self, i: usize, k: usize) -> (&str, usize, <Self::Dim as Dim>::Vector);

    /// Pair `k` of interface `i` evaluated at the displacements `u` (all DOFs)
    /// in `state` with history `h`: its DOFs and element displacements, its local
    /// jump, its normal gap g₀ + \[\[u_n\]\] and its local force under the
    /// interface's law. The one evaluation of a pair at u.
    fn at(
        &self,
        i: usize,
        k: usize,
        u: &[f64],
        state: PairState,
        h: &PairHistory<Self::Dim>,
    ) -> PairAt<Self::Dim>;

    /// The bonded stiffness of pair `k` of interface `i` in rank-one terms,
    /// `K_e = Σ_j c_j w_j w_jᵀ` over its local components j (the normal, then each
    /// tangent: 1 + `Tangent::COMPONENTS` terms), each given to `f(j, c_j, w_j)`
    /// with `w_j` over the pair's DOFs ([`pair_dofs`](Self::pair_dofs) order).
    fn stiffness_terms(&self, i: usize, k: usize, f: &mut dyn FnMut(usize, f64, &[f64]));
}

/// The pairs of a model's interfaces (of coupling elements of dimension `D`),
/// their DOFs numbered by a DOF map: the [`PairSet`] the contact scheme solves
/// with.
#[derive(Debug)]
pub struct InterfacePairs<'a, D: Dim = D2> {
    interfaces: &'a [Interface<D>],
    dofs: &'a DofMap<D>,
}

impl<D: Dim> Clone for InterfacePairs<'_, D> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<D: Dim> Copy for InterfacePairs<'_, D> {}

impl<'a, D: Dim> InterfacePairs<'a, D> {
    /// The pairs of `interfaces`, DOFs numbered by `dofs`.
    pub fn new(interfaces: &'a [Interface<D>], dofs: &'a DofMap<D>) -> Self {
        Self { interfaces, dofs }
    }
}

impl<D: Dim> PairSet for InterfacePairs<'_, D> {
    type Dim = D;

    fn interface_count(&self) -> usize {
        self.interfaces.len()
    }

    fn pair_count(&self, i: usize) -> usize {
        self.interfaces[i].elements.len()
    }

    fn law(&self, i: usize) -> LawParams {
        self.interfaces[i].params()
    }

    fn augmented(&self, i: usize) -> Option<f64> {
        let iface = &self.interfaces[i];
        (iface.enforcement == Enforcement::Augmented).then_some(iface.penetration_tolerance)
    }

    fn pair_law(&self, i: usize, k: usize, base: &LawParams) -> LawParams {
        self.interfaces[i].elements[k].params(base)
    }

    fn pair_dofs(&self, i: usize, k: usize) -> CfeDofs {
        let iface = &self.interfaces[i];
        iface.elements[k].dofs(self.dofs, iface.host, iface.node_part)
    }

    fn initial_gap(&self, i: usize, k: usize) -> f64 {
        self.interfaces[i].elements[k].gap0
    }

    fn label(&self, i: usize, k: usize) -> (&str, usize, D::Vector) {
        let iface = &self.interfaces[i];
        let c = &iface.elements[k];
        (&iface.name, c.node, c.position)
    }

    fn at(&self, i: usize, k: usize, u: &[f64], state: PairState, h: &PairHistory<D>) -> PairAt<D> {
        self.interfaces[i].pair_at(k, self.dofs, u, state, h)
    }

    fn stiffness_terms(&self, i: usize, k: usize, f: &mut dyn FnMut(usize, f64, &[f64])) {
        let iface = &self.interfaces[i];
        let c = &iface.elements[k];
        let n = c.n_dofs();
        c.for_each_stiffness_term(iface.c_n, iface.c_s, |j, c_j, w| f(j, c_j, &w[..n]));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::coupling::fixture::{displaced, dofs, interface};
    use crate::coupling::law::Law;

    /// The interface pairs read what their interface and elements hold: counts,
    /// law, augmented tolerance, weight-scaled law, DOFs, initial gap, label, and
    /// the evaluation is `Interface::pair_at`'s.
    #[test]
    fn interface_pairs_read_their_interfaces() {
        let mut a = interface(Law::Coulomb, 3, 0.5);
        a.elements[1].gap0 = 0.25;
        let mut b = interface(Law::Contact, 2, 0.0);
        b.enforcement = Enforcement::Augmented;
        b.penetration_tolerance = 1e-3;
        let ifaces = [a, b];
        let d = dofs(3);
        let pairs = InterfacePairs::new(&ifaces, &d);
        assert_eq!(pairs.interface_count(), 2);
        assert_eq!((pairs.pair_count(0), pairs.pair_count(1)), (3, 2));
        assert_eq!(pairs.law(0), ifaces[0].params());
        assert_eq!((pairs.augmented(0), pairs.augmented(1)), (None, Some(1e-3)));
        assert_eq!(pairs.pair_law(0, 0, &pairs.law(0)), ifaces[0].params());
        // Pair 2 reads the host's 3 nodes, then node 2 of the node part (global 5).
        assert_eq!(pairs.pair_dofs(0, 2).as_slice(), [0, 1, 2, 3, 4, 5, 10, 11]);
        assert_eq!((pairs.initial_gap(0, 1), pairs.initial_gap(0, 0)), (0.25, 0.0));
        assert_eq!(pairs.label(0, 1), ("fixture", 1, [0.5, 0.0]));
        let u = displaced(&[[-0.1, 0.2], [0.0, 0.3], [0.1, 0.0]]);
        let h = PairHistory::default();
        let p = pairs.at(0, 0, &u, PairState::Bonded, &h);
        assert_eq!(p, ifaces[0].pair_at(0, &d, &u, PairState::Bonded, &h));
        assert_eq!(p.jump, (-0.1, 0.2));
        assert_eq!(p.force, (10.0 * -0.1, 4.0 * 0.2));
    }

    /// The stiffness terms are one per local component (normal, tangent), and
    /// their sum Σ c_j w_j w_jᵀ is the element's stiffness.
    #[test]
    fn stiffness_terms_sum_to_the_element_stiffness() {
        let ifaces = [interface(Law::Contact, 2, 0.0)];
        let d = dofs(2);
        let pairs = InterfacePairs::new(&ifaces, &d);
        let ke = ifaces[0].elements[1].stiffness(10.0, 4.0, PairState::Bonded);
        let n = pairs.pair_dofs(0, 1).as_slice().len();
        let mut sum = vec![0.0; n * n];
        let mut components = Vec::new();
        pairs.stiffness_terms(0, 1, &mut |j, c, w| {
            components.push((j, c));
            for a in 0..n {
                for b in 0..n {
                    sum[a * n + b] += c * w[a] * w[b];
                }
            }
        });
        assert_eq!(components, [(0, 10.0), (1, 4.0)]);
        for a in 0..n {
            for b in 0..n {
                assert!((sum[a * n + b] - ke.get(a, b)).abs() < 1e-13);
            }
        }
    }
}
