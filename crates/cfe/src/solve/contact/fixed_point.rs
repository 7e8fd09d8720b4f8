//! The fixed point on a pattern's right-hand-side terms: within one pattern of
//! states (K fixed), the slip forces of slipping Coulomb pairs, their spring
//! anchors and the augmented-Lagrangian multipliers are iterated until they
//! are consistent with the solution they give, Anderson-accelerated
//! ([`iterate`], generic over a [`FixedPoint`]); a fixed point whose coupling
//! nodes drifted further than a state of rest moves them is not converged.

use super::scale::largest_off;
use super::solver::Solver;
use crate::assembly::{self, FIXED};
use crate::coupling::{PairHistories, PairHistory, PairSet, PairState, history};
use crate::dim::Tangent;
use crate::error::Result;
use crate::fem::ElementFamily;
use crate::solve::anderson::Anderson;
use crate::solve::backend::{Request, Solve};
use std::time::Instant;

/// The fixed point on the slip forces stops when none changes by more than this
/// fraction of the load scale (far below the law's force tolerance, so a converged
/// slip force is μ |f_n| to round-off as the law check sees it).
pub const FIXED_POINT_TOLERANCE: f64 = 1e-10;

/// Most fixed-point solves (slip forces, Uzawa steps) per pattern. With the
/// Anderson acceleration a pattern that has a fixed point reaches it in far fewer
/// (typically 5–10); one that does not is left: its unsettled slipping pairs stick.
pub const MAX_FIXED_POINT: usize = 60;

/// How many previous fixed-point steps the Anderson acceleration of the pairs'
/// right-hand-side terms mixes (`Anderson`, in `solve::anderson`).
pub const ANDERSON_DEPTH: usize = 8;

/// A right-hand-side term of a pair that the fixed point iterates: one
/// component of a tangential term (the index: 0 ≤ j < `Tangent::COMPONENTS`),
/// or the normal multiplier.
#[derive(Debug, Clone, Copy)]
pub(super) enum Term {
    SlipForce(usize),
    Anchor(usize),
    NormalMultiplier,
    TangentMultiplier(usize),
}

/// The load scale a fixed point's tolerance is taken from.
#[derive(Clone, Copy)]
pub(super) enum FixedPointScale<'f> {
    /// From the internal force of the pattern's first solution and the current
    /// displacements, at this load factor ([`Solver::load_scale`]).
    Forces(f64, &'f [f64]),
    /// A given scale (a trial solution, which has no internal force).
    Given(f64),
}

/// A fixed-point iteration on right-hand-side terms, as [`iterate`] drives it.
pub(super) trait FixedPoint {
    /// Starts a step: the largest displacement of a coupling node now (what
    /// the drift guard reads), or the error that ends the iteration (a stop
    /// request).
    fn moved(&mut self) -> Result<f64>;
    /// One step on the terms, the plain step mixed by `anderson`, given the
    /// largest coupling-node displacement `moved`: `true` when the terms were
    /// already at their fixed point (then they are left as they are).
    fn update(&mut self, moved: f64, anderson: &mut Anderson) -> bool;
    /// Whether a fixed point whose coupling nodes moved by `moved` has drifted
    /// (is no state of rest, so not converged).
    fn drifted(&self, moved: f64) -> bool;
    /// Moves the solution by the change of the terms' forces.
    fn solve(&mut self) -> Result<()>;
}

/// Iterates `terms` to their fixed point, at most `max` steps, Anderson-
/// accelerated with depth [`ANDERSON_DEPTH`]. Returns whether it converged:
/// the terms reached their fixed point and it has not drifted.
pub(super) fn iterate(terms: &mut impl FixedPoint, max: usize) -> Result<bool> {
    let mut anderson = Anderson::new(ANDERSON_DEPTH);
    for _ in 0..max {
        let moved = terms.moved()?;
        if terms.update(moved, &mut anderson) {
            return Ok(!terms.drifted(moved));
        }
        terms.solve()?;
    }
    Ok(false)
}

/// The pairs' terms of one pattern `states`, iterated from the solution `u`
/// (valid at the coupling elements' DOFs at least): what the steps of
/// [`Solver::fixed_point`] read and keep.
struct PairTerms<'s, 'a, D: ElementFamily> {
    solver: &'s mut Solver<'a, D>,
    states: &'s [Vec<PairState>],
    inc: usize,
    u: &'s mut [f64],
    scale: FixedPointScale<'s>,
    /// The summed change at the coupling DOFs (in their order).
    total: Option<Vec<f64>>,
    /// A step's right-hand side: zero off the coupling equations.
    du: Vec<f64>,
    /// The displacements at zero, at which the pairs' constant terms are read.
    zero: Vec<f64>,
    /// The coupling nodes (sorted).
    coupling_nodes: Vec<usize>,
    /// The largest nodal displacement off the coupling nodes (the load scale's
    /// floor reads the largest of all): fixed until a step solves in full.
    u_rest: f64,
    /// The histories before the last update.
    before: PairHistories<D>,
}

impl<D: ElementFamily> FixedPoint for PairTerms<'_, '_, D> {
    fn moved(&mut self) -> Result<f64> {
        self.solver.check_stop(self.inc)?;
        // The largest displacement of a coupling node.
        let u = &*self.u;
        Ok(self
            .coupling_nodes
            .iter()
            .map(|&n| D::length(&u[D::dof(n, 0)..D::dof(n + 1, 0)]))
            .fold(0.0, f64::max))
    }

    fn update(&mut self, moved: f64, anderson: &mut Anderson) -> bool {
        let load = match self.scale {
            FixedPointScale::Forces(lambda, f) => {
                self.solver
                    .load_scale_with(lambda, f, moved.max(self.u_rest))
            }
            FixedPointScale::Given(s) => s,
        };
        self.before = self.solver.history.clone();
        self.solver
            .update_right_hand_side(self.states, self.u, FIXED_POINT_TOLERANCE * load, anderson)
    }

    fn drifted(&self, moved: f64) -> bool {
        self.solver.scales.drifted(moved)
    }

    fn solve(&mut self) -> Result<()> {
        let s = &mut *self.solver;
        s.fixed_point += 1;
        let t = Instant::now();
        let change = s.pair_term_change(self.states, &self.before, &self.zero);
        let total = self
            .total
            .get_or_insert_with(|| vec![0.0; s.coupling_dofs.len()]);
        if self.du.is_empty() {
            self.du = vec![0.0; s.dofs.n_eq];
        }
        for ((&d, c), sum) in s.coupling_dofs.iter().zip(&change).zip(total.iter_mut()) {
            let e = s.dofs.eq[d];
            if e != FIXED {
                self.du[e] = -c;
                *sum -= c;
            }
        }
        s.timings.contact_update += t.elapsed().as_secs_f64();
        // The change of the solution: at the coupling equations (restricted),
        // or in full (its right-hand side lives there).
        let request = Request::new(self.states).interface_only().rhs_on_interface();
        let outcome = s
            .linear
            .solve_pattern(request, &mut self.du)
            .map_err(|f| s.linear_error(f, self.inc))?;
        s.record(&outcome);
        if outcome.complete {
            for (d, &e) in s.dofs.eq.iter().enumerate() {
                if e != FIXED {
                    self.u[d] += self.du[e];
                }
            }
            // Solved in full: zero off the coupling equations again.
            self.du.fill(0.0);
            if let FixedPointScale::Forces(..) = self.scale {
                self.u_rest = largest_off::<D>(self.u, &self.coupling_nodes);
            }
        } else {
            for &d in &s.coupling_dofs {
                let e = s.dofs.eq[d];
                if e != FIXED {
                    self.u[d] += self.du[e];
                }
            }
        }
        Ok(())
    }
}

impl<'a, D: ElementFamily> Solver<'a, D> {
    /// Iterates the pairs' right-hand-side terms of `states` to their fixed point
    /// from the solution `u` (valid at the coupling elements' DOFs at least),
    /// Anderson-accelerated. K is the pattern's: only the pairs' constant terms
    /// change, so each step moves `u` by K⁻¹ of their change, a right-hand side on
    /// the pairs' DOFs solved on the interface's tree paths (`u` moves at the
    /// coupling DOFs only, all the pairs' forces read). A step's work is the
    /// pairs' and that solve's: the change, its sum and the load scale's largest
    /// displacement are kept on the coupling DOFs (the rest of `u` does not move
    /// unless a refactorization solves in full). Returns the summed force change
    /// (free equations) for one complete solve, or `None` when the terms were
    /// already at their fixed point.
    pub(super) fn fixed_point(
        &mut self,
        states: &[Vec<PairState>],
        inc: usize,
        u: &mut [f64],
        scale: FixedPointScale<'_>,
    ) -> Result<Option<Vec<f64>>> {
        self.fixed_point_converged = false;
        // The largest nodal displacement off the coupling nodes (the load scale's
        // floor reads the largest of all): fixed until a step solves in full.
        let coupling_nodes: Vec<usize> = {
            let mut nodes: Vec<usize> =
                self.coupling_dofs.iter().map(|&d| d / D::N).collect();
            nodes.dedup();
            nodes
        };
        let u_rest = match scale {
            FixedPointScale::Forces(..) => largest_off::<D>(u, &coupling_nodes),
            FixedPointScale::Given(_) => 0.0,
        };
        // With `friction_solve = "newton"`, the slip forces solved in one shot
        // first: the fixed point's first step moves `u` by their change.
        let newton = self.newton_slip_terms(states, inc, u)?;
        let mut terms = PairTerms {
            zero: vec![0.0; u.len()],
            solver: self,
            states,
            inc,
            u,
            scale,
            total: None,
            du: Vec::new(),
            coupling_nodes,
            u_rest,
            before: Vec::new(),
        };
        let (converged, settled) = match newton {
            Some((before, settled)) => {
                terms.before = before;
                terms.solve()?;
                // The pattern solved exactly at the directions its pairs slip
                // along: where those did not settle, the law check reports the
                // pairs that turn (the search's next pattern), with nothing
                // for the fixed point to iterate. A solution that moved a
                // coupling node further than a state of rest can is the
                // numerically singular system's (a part held along its faces
                // by slipping pairs alone under a load along them): no state
                // of rest in the pattern, as the fixed point's drift says.
                let moved = terms.moved()?;
                let drifted = terms.drifted(moved);
                (!drifted, settled)
            }
            None => (iterate(&mut terms, MAX_FIXED_POINT)?, true),
        };
        let total = terms.total;
        self.fixed_point_converged = converged;
        self.slip_directions_settled = settled;
        Ok(total.map(|sum| self.on_free_equations(&sum)))
    }

    /// The summed change `sum` at the coupling DOFs (in their order) as a vector
    /// of the free equations (zero off the coupling ones).
    fn on_free_equations(&self, sum: &[f64]) -> Vec<f64> {
        let mut full = vec![0.0; self.dofs.n_eq];
        for (&d, &v) in self.coupling_dofs.iter().zip(sum) {
            let e = self.dofs.eq[d];
            if e != FIXED {
                full[e] = v;
            }
        }
        full
    }

    /// The change of the pairs' internal force at zero displacement `zero` (their
    /// constant terms: slip forces, spring anchors, multipliers) from the
    /// histories `before` to the current ones, at the coupling DOFs (in their
    /// order; the pairs act nowhere else). Each side is summed element by element
    /// as the assembled force would be.
    pub(super) fn pair_term_change(
        &self,
        states: &[Vec<PairState>],
        before: &PairHistories<D>,
        zero: &[f64],
    ) -> Vec<f64> {
        let force = |h: &[Vec<PairHistory<D>>]| {
            let pairs = assembly::CouplingElements::new(self.interfaces, Some(states), self.dofs)
                .with_history(Some(h));
            assembly::internal_force_at(&pairs, zero, &self.coupling_dofs)
        };
        let (now, was) = (force(&self.history), force(before));
        now.iter().zip(&was).map(|(a, b)| a - b).collect()
    }

    /// One fixed-point step on the pairs' right-hand-side terms for the solution
    /// `u` of `states`: sets every closed Coulomb pair's slip force to
    /// `μ |f_n|` along its trial force and its spring anchor to its tangential
    /// jump, the multipliers of augmented interfaces to the pairs' forces (zero
    /// when open), and returns whether nothing changed by more than the tolerances
    /// (force `tol`; each interface's `penetration_tolerance`) — then the history
    /// is left as it was, consistent with `u`. Otherwise the terms that act on the
    /// solution go through `anderson` (the plain step mixed with the previous ones).
    pub(super) fn update_right_hand_side(
        &mut self,
        states: &[Vec<PairState>],
        u: &[f64],
        tol: f64,
        anderson: &mut Anderson,
    ) -> bool {
        let mut next = self.history.clone();
        let laws = self.laws();
        let (converged, augmented_error) =
            history::step_terms(&self.pairs(), &laws, states, u, &mut next, tol);
        self.augmented_error = augmented_error;
        self.take_step(states, next, converged, anderson);
        converged
    }

    /// Ends a fixed-point step on `states` whose plain step gives the histories
    /// `next`: when `converged`, the history the solution was computed with is
    /// kept, but for a stick pair's slip force and anchor (unused while it
    /// sticks, they are its start should it slip); otherwise the terms that
    /// act on the solution are `anderson`'s mix of the plain step with the
    /// previous ones.
    fn take_step(
        &mut self,
        states: &[Vec<PairState>],
        mut next: PairHistories<D>,
        converged: bool,
        anderson: &mut Anderson,
    ) {
        if converged {
            // Keep the history the solution was computed with; a stick pair's slip
            // force and anchor (unused while it sticks) are its start should it slip.
            for ((h, n), st) in self.history.iter_mut().zip(&next).zip(states) {
                for ((h, n), s) in h.iter_mut().zip(n).zip(st) {
                    if *s == PairState::Bonded {
                        h.slip_force = n.slip_force;
                        h.anchor = n.anchor;
                    }
                }
            }
        } else {
            let x = self.active_terms(states, &self.history);
            let g = self.active_terms(states, &next);
            let mixed = anderson.step(&x, &g);
            self.set_active_terms(states, &mut next, &mixed);
            self.history = next;
        }
    }

    /// The right-hand-side terms of `history` that act on the solution of
    /// `states`, each as a force: a slipping Coulomb pair's slip force and
    /// `c_slip` × its anchor; an augmented closed pair's normal multiplier, and
    /// its tangential one when it sticks.
    pub(super) fn active_terms(&self, states: &[Vec<PairState>], history: &PairHistories<D>) -> Vec<f64> {
        let mut x = Vec::new();
        self.visit_active_terms(states, |i, k, field, c_slip| {
            let h = &history[i][k];
            x.push(match field {
                Term::SlipForce(j) => h.slip_force.component(j),
                Term::Anchor(j) => c_slip * h.anchor.component(j),
                Term::NormalMultiplier => h.multiplier.0,
                Term::TangentMultiplier(j) => h.multiplier.1.component(j),
            });
        });
        x
    }

    /// Writes `x` (as [`Self::active_terms`] orders it) into `history`.
    pub(super) fn set_active_terms(&self, states: &[Vec<PairState>], history: &mut PairHistories<D>, x: &[f64]) {
        let mut it = x.iter();
        self.visit_active_terms(states, |i, k, field, c_slip| {
            let v = *it.next().expect("as many terms as active_terms gives");
            let h = &mut history[i][k];
            match field {
                Term::SlipForce(j) => h.slip_force.set_component(j, v),
                Term::Anchor(j) => h.anchor.set_component(j, v / c_slip),
                Term::NormalMultiplier => h.multiplier.0 = v,
                Term::TangentMultiplier(j) => h.multiplier.1.set_component(j, v),
            }
        });
    }

    /// Calls `f(interface, pair, term, c_slip)` for each right-hand-side term that
    /// acts on the solution of `states`, in a fixed order (per pair: the slip
    /// force's components, the anchor's, the normal multiplier, the tangential
    /// multiplier's; one component each in 2D).
    pub(super) fn visit_active_terms(
        &self,
        states: &[Vec<PairState>],
        mut f: impl FnMut(usize, usize, Term, f64),
    ) {
        let pairs = self.pairs();
        let components = <D::Tangent as Tangent>::COMPONENTS;
        for (i, st) in states.iter().enumerate().take(pairs.interface_count()) {
            let base = pairs.law(i);
            let augmented = pairs.augmented(i).is_some();
            for (k, &state) in st.iter().enumerate().take(pairs.pair_count(i)) {
                let law = pairs.pair_law(i, k, &base);
                if state == PairState::Slip && law.c_slip > 0.0 {
                    for j in 0..components {
                        f(i, k, Term::SlipForce(j), law.c_slip);
                    }
                    for j in 0..components {
                        f(i, k, Term::Anchor(j), law.c_slip);
                    }
                }
                if augmented && state.is_closed() {
                    f(i, k, Term::NormalMultiplier, law.c_slip);
                    if state == PairState::Bonded && law.penalties(state)[1] > 0.0 {
                        for j in 0..components {
                            f(i, k, Term::TangentMultiplier(j), law.c_slip);
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The map x ← a x + b on one term, which is also the one coupling-node
    /// displacement; the drift guard's reach is `reach`.
    struct Affine {
        x: f64,
        a: f64,
        b: f64,
        reach: f64,
        solves: usize,
    }

    impl FixedPoint for Affine {
        fn moved(&mut self) -> Result<f64> {
            Ok(self.x.abs())
        }
        fn update(&mut self, _: f64, anderson: &mut Anderson) -> bool {
            let g = self.a * self.x + self.b;
            if (g - self.x).abs() <= 1e-12 {
                return true;
            }
            self.x = anderson.step(&[self.x], &[g])[0];
            false
        }
        fn drifted(&self, moved: f64) -> bool {
            moved > self.reach
        }
        fn solve(&mut self) -> Result<()> {
            self.solves += 1;
            Ok(())
        }
    }

    fn affine(a: f64, b: f64, reach: f64) -> Affine {
        Affine {
            x: 0.0,
            a,
            b,
            reach,
            solves: 0,
        }
    }

    /// A contraction x ← 0.9 x + 1 (slow for the plain step: 0.9ᵏ) reaches its
    /// closed-form fixed point b / (1 − a) = 10 in a few accelerated steps.
    #[test]
    fn a_contraction_converges_to_its_fixed_point() {
        let mut t = affine(0.9, 1.0, 100.0);
        assert!(iterate(&mut t, MAX_FIXED_POINT).unwrap());
        assert!((t.x - 10.0).abs() <= 1e-10, "x = {}", t.x);
        assert!(t.solves <= 3, "{} solves", t.solves);
    }

    /// The drift guard: the same fixed point (10) beyond the reach 5 a state
    /// of rest may move a node is found but not converged.
    #[test]
    fn a_drifted_fixed_point_is_not_converged() {
        let mut t = affine(0.9, 1.0, 5.0);
        assert!(!iterate(&mut t, MAX_FIXED_POINT).unwrap());
        assert!((t.x - 10.0).abs() <= 1e-10, "x = {}", t.x);
    }

    /// x ← x + 1 has no fixed point: every step solves, and after `max` steps
    /// the iteration gives up unconverged.
    #[test]
    fn a_map_without_fixed_point_stops_at_the_limit() {
        let mut t = affine(1.0, 1.0, f64::INFINITY);
        assert!(!iterate(&mut t, MAX_FIXED_POINT).unwrap());
        assert_eq!(t.solves, MAX_FIXED_POINT);
    }
}
