//! Coulomb friction as a semi-smooth Newton (primal–dual active set) on the
//! pairs, with each pattern solved exactly (docs/method.md §2.1, "A Newton
//! solve of Coulomb friction").
//!
//! For a fixed *pattern* — every pair open, stick, or slipping along a fixed unit
//! direction ξ — the penalty problem is linear: a slipping pair's tangential force
//! is `μ ξ (−f_n)` with `f_n = c_n g_n` affine in the displacements, a rank-one,
//! non-symmetric coupling of the pair's tangential row to its normal row. So a
//! pattern has one solution, found in one shot ([`solve_pattern_linear`] on a
//! condensed interface, [`Solver::solve_pattern_exact`] on a model: the
//! symmetric factorization of the pattern's K plus a dense correction of rank
//! the number of slipping pairs), with no fixed point. The outer loop over
//! patterns is the Newton step of the complementarity function
//! ([`next_active`]: the radial return of the trial force onto the cone, the
//! normal law's gap and tension), globalised by taking one flip at a time once a
//! pattern repeats ([`newton_condensed`]).
//!
//! Everything per pair is written on [`Tangent`], so the 3D law (a two-component
//! tangent, the radial return and its consistent tangent
//! `μ (−f_n)/|trial| (I − ξ⊗ξ)`, [`return_map_derivative`]) uses it unchanged.
//!
//! In a run, `[analysis] friction_solve = "newton"` (off by default) starts
//! every pattern's fixed point on the slip forces with their Newton step
//! ([`Solver::newton_slip_terms`]), its columns read from the interface's
//! condensed operator the low-rank machinery caches
//! ([`crate::solve::backend::PairFlexibility`]); the fixed point confirms them
//! and remains the fallback. The search over patterns is still the active
//! set's, not [`newton_condensed`]; docs/method.md gives what remains and why.

use super::increment::{IncrementResult, Iteration, NewtonCounts, count_changes};
use super::solver::Solver;
use crate::assembly::FIXED;
use crate::coupling::{Enforcement, Law, PairHistories, PairState};
use crate::dim::Tangent;
use crate::domain::FrictionSolve;
use crate::fem::ElementFamily;
use crate::error::Result;
use crate::solve::backend::{Request, Solve as _};
use faer::Mat;
use faer::linalg::solvers::{PartialPivLu, Solve};
use std::collections::HashSet;
use std::time::Instant;

/// A pair's place in a Newton pattern: open, stick, or slipping along the unit
/// direction ξ (fixed for the pattern).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Active<T: Tangent> {
    /// No force.
    Open,
    /// Closed, sticking: `f_s = c_s ([[u_s]] − s_p)`.
    Stick,
    /// Closed, slipping along ξ: `f_s = μ (−f_n) ξ`.
    Slip(T),
}

/// The tolerances of the complementarity rule: a force (tension of a closed
/// pair, a trial force beyond the cone) and a length (penetration of an open
/// pair).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerance {
    /// Force tolerance.
    pub force: f64,
    /// Length tolerance.
    pub gap: f64,
}

/// The Newton update of one pair: its place in the next pattern from its
/// solution in this one. `closed` says whether it is closed now, `gap` is its
/// normal gap `g₀ + [[u_n]]`, `f_n` the normal force it carries if closed
/// (`c_n g_n`, negative in compression), `trial` its trial tangential force
/// `c_s ([[u_s]] − s_p)` and `mu` the friction coefficient. A closed pair in
/// tension beyond the tolerance opens, an open pair penetrating beyond it
/// closes; a closed pair sticks when its trial force is inside the cone
/// `μ (−f_n)` (with the tolerance) and slips along the trial force otherwise —
/// the radial return, in any number of tangent components. This is the
/// active-set form of the semi-smooth Newton step on the complementarity
/// function `C(f, u) = max(μ(−f_n), |f_t + c_s u_t|) f_t − μ(−f_n)(f_t + c_s u_t)`
/// (with its normal part `min(−f_n, −c_n g_n)`).
pub fn next_active<T: Tangent>(
    closed: bool,
    gap: f64,
    f_n: f64,
    trial: T,
    mu: f64,
    tol: Tolerance,
) -> Active<T> {
    let stays_open = if closed {
        f_n > tol.force
    } else {
        gap >= -tol.gap
    };
    if stays_open {
        return Active::Open;
    }
    let limit = mu * (-f_n).max(0.0);
    if trial.norm() <= limit + tol.force {
        Active::Stick
    } else {
        Active::Slip(trial.direction())
    }
}

/// The derivative of the radial return `f_t = μ (−f_n) trial/|trial|` of a
/// slipping pair applied to a change `(d_fn, d_trial)`: `μ (−d_fn) ξ +
/// μ (−f_n)/|trial| (I − ξ⊗ξ) d_trial`, ξ the trial's direction. In one
/// tangent component the second term is zero (the direction does not turn):
/// the 2D pattern's coupling is the rank-one `μ ξ c_n` of the normal row alone;
/// in two it is the consistent tangent of the 3D return map (symmetric, so it
/// joins K).
pub fn return_map_derivative<T: Tangent>(trial: T, f_n: f64, mu: f64, d_fn: f64, d_trial: T) -> T {
    let xi = trial.direction();
    let along = xi.scale(-mu * d_fn);
    let norm = trial.norm();
    if norm == 0.0 {
        return along;
    }
    let turn = d_trial.sub(xi.scale(xi.dot(d_trial)));
    along.add(turn.scale(mu * (-f_n).max(0.0) / norm))
}

/// One pair of a condensed interface (2D: one tangent component): penalties,
/// friction coefficient, initial gap and plastic slip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CondensedPair {
    /// Normal penalty.
    pub c_n: f64,
    /// Tangential penalty.
    pub c_s: f64,
    /// Friction coefficient.
    pub mu: f64,
    /// Initial normal gap g₀.
    pub gap0: f64,
    /// Plastic slip s_p.
    pub slip: f64,
}

impl CondensedPair {
    /// The local force `(f_n, f_s)` of the pair at jump `(j_n, j_s)` in `place`.
    pub fn force(&self, place: Active<f64>, j: [f64; 2]) -> [f64; 2] {
        let f_n = self.c_n * (self.gap0 + j[0]);
        match place {
            Active::Open => [0.0, 0.0],
            Active::Stick => [f_n, self.c_s * (j[1] - self.slip)],
            Active::Slip(xi) => [f_n, -self.mu * xi * f_n],
        }
    }
}

/// An interface condensed onto its pairs: the local jumps `j` (2 per pair,
/// normal then tangential) of the model under its loads are `j = free − F f`,
/// `f` the pairs' local forces, `F` the interface's flexibility (2m × 2m, the
/// Schur complement's inverse: `R B K⁻¹ Bᵀ Rᵀ` of the parts alone).
#[derive(Debug, Clone)]
pub struct Condensed {
    /// The flexibility F, row-major.
    pub flex: Vec<f64>,
    /// The jumps with no pair force.
    pub free: Vec<f64>,
    /// The pairs.
    pub pairs: Vec<CondensedPair>,
}

/// The exact solution of one pattern of a condensed interface: the jumps `j`
/// solving `(I + F L) j = free − F l₀`, `f = L j + l₀` the pattern's (affine)
/// pair forces. `None` when the pattern's system is singular (no state of rest
/// in it, e.g. every pair of a part slipping one way under a load along the
/// faces).
pub fn solve_pattern_linear(c: &Condensed, pattern: &[Active<f64>]) -> Option<Vec<f64>> {
    let n = 2 * c.pairs.len();
    // L (block-diagonal 2×2 per pair) and l₀.
    let mut l = vec![[[0.0; 2]; 2]; c.pairs.len()];
    let mut l0 = vec![0.0; n];
    for (p, (pair, place)) in c.pairs.iter().zip(pattern).enumerate() {
        let at_zero = pair.force(*place, [0.0, 0.0]);
        l0[2 * p] = at_zero[0];
        l0[2 * p + 1] = at_zero[1];
        for a in 0..2 {
            let mut e = [0.0; 2];
            e[a] = 1.0;
            let f = pair.force(*place, e);
            l[p][0][a] = f[0] - at_zero[0];
            l[p][1][a] = f[1] - at_zero[1];
        }
    }
    let a = Mat::<f64>::from_fn(n, n, |r, col| {
        let (q, b) = (col / 2, col % 2);
        let fl: f64 = (0..2).map(|k| c.flex[r * n + 2 * q + k] * l[q][k][b]).sum();
        fl + if r == col { 1.0 } else { 0.0 }
    });
    let rhs = Mat::<f64>::from_fn(n, 1, |r, _| {
        c.free[r] - (0..n).map(|k| c.flex[r * n + k] * l0[k]).sum::<f64>()
    });
    let j = PartialPivLu::new(a.as_ref()).solve(rhs.as_ref());
    let j: Vec<f64> = (0..n).map(|r| j[(r, 0)]).collect();
    j.iter().all(|v| v.is_finite()).then_some(j)
}

/// What [`newton_condensed`] did: the patterns it solved, in order, and the
/// jumps of the last.
#[derive(Debug, Clone)]
pub struct NewtonRun {
    /// Every pattern solved, the first the start.
    pub patterns: Vec<Vec<Active<f64>>>,
    /// The jumps of the consistent pattern.
    pub jumps: Vec<f64>,
}

/// The semi-smooth Newton on a condensed interface from `start`: solve the
/// pattern exactly ([`solve_pattern_linear`]), update every pair
/// ([`next_active`]), repeat until no pair changes. Damping: once the update
/// leads back to a pattern already solved (a cycle of the full step), only the
/// pair with the largest complementarity residual changes — the least step that
/// leaves the cycle. `None` when a pattern is singular, or `max` patterns pass,
/// or a repeated pattern has no single change left: no state of rest is within
/// reach.
pub fn newton_condensed(
    c: &Condensed,
    start: Vec<Active<f64>>,
    tol: Tolerance,
    max: usize,
) -> Option<NewtonRun> {
    let mut seen: HashSet<Vec<u8>> = HashSet::new();
    let key = |p: &[Active<f64>]| -> Vec<u8> {
        p.iter()
            .map(|a| match a {
                Active::Open => 0,
                Active::Stick => 1,
                Active::Slip(x) if *x > 0.0 => 2,
                Active::Slip(_) => 3,
            })
            .collect()
    };
    let mut pattern = start;
    let mut patterns = Vec::new();
    for _ in 0..max {
        seen.insert(key(&pattern));
        patterns.push(pattern.clone());
        let j = solve_pattern_linear(c, &pattern)?;
        let mut next = Vec::with_capacity(pattern.len());
        let mut residual = Vec::with_capacity(pattern.len());
        for (p, (pair, place)) in c.pairs.iter().zip(&pattern).enumerate() {
            let jp = [j[2 * p], j[2 * p + 1]];
            let gap = pair.gap0 + jp[0];
            let f_n = pair.c_n * gap;
            let trial = pair.c_s * (jp[1] - pair.slip);
            let closed = *place != Active::Open;
            let n = next_active(closed, gap, f_n, trial, pair.mu, tol);
            let f = pair.force(*place, jp);
            // The residual of the law in this pattern: how far the pair's force
            // is from what the law gives it.
            let r = if n == *place {
                0.0
            } else {
                let law = pair.force(n, jp);
                (law[0] - f[0]).abs().max((law[1] - f[1]).abs()).max(tol.force)
            };
            next.push(n);
            residual.push(r);
        }
        if next == pattern {
            return Some(NewtonRun { patterns, jumps: j });
        }
        if seen.contains(&key(&next)) {
            // Damped: the single worst change, if it leads somewhere new.
            let mut order: Vec<usize> = (0..next.len()).filter(|&p| next[p] != pattern[p]).collect();
            order.sort_by(|&a, &b| residual[b].total_cmp(&residual[a]).then(a.cmp(&b)));
            let step = order.into_iter().find_map(|p| {
                let mut one = pattern.clone();
                one[p] = next[p];
                (!seen.contains(&key(&one))).then_some(one)
            })?;
            pattern = step;
        } else {
            pattern = next;
        }
    }
    None
}

/// Most Newton steps within one pattern's solve of its slip forces after the
/// first: each solves the small system again (same columns) at the slip
/// directions of the last solution — a 2D pair whose trial force reversed
/// beyond the cone slides the other way, a 3D pair's direction turns (the
/// radial return's derivative).
pub const MAX_DIRECTION_UPDATES: usize = 8;

/// Most slipping pairs a pattern's Newton step ([`Solver::newton_slip_terms`])
/// takes when its columns must be solved for (a back end without the cached
/// condensed operator, or no factorization kept for the pattern): beyond it the
/// fixed point alone (its Anderson steps, a Krylov method on the same affine
/// map, are then fewer than the columns' solves). Columns read from the cache
/// have no such limit.
pub const MAX_NEWTON_SLIPPING: usize = 60;

/// A slipping Coulomb pair as a pattern's exact solve reads it (tangents `T`:
/// one component in 2D, two in 3D).
#[derive(Debug, Clone, Copy)]
struct Slipping<T: Tangent> {
    i: usize,
    k: usize,
    mu: f64,
    c_n: f64,
    c_s: f64,
    c_slip: f64,
    /// Its plastic slip.
    slip: T,
    /// The unit direction it slides along (±1 in 2D).
    xi: T,
    /// Its normal force and tangential jump at the pattern's first solution.
    f_n: f64,
    u_s: T,
    /// Its constant term there: slip force less the spring's anchor term.
    z: T,
}

/// The columns of a pattern's exact solve: the jumps a unit change of each
/// component of each slipping pair's term causes at every slipping pair. With
/// `C` tangent components and `m` pairs there are `n = m C` terms (pair q's
/// component b at `q C + b`): `pn` is m × n (row the pair's normal jump), `ps`
/// n × n (row `p C + c` pair p's tangential jump component c), row-major.
struct Columns {
    pn: Vec<f64>,
    ps: Vec<f64>,
}

impl Columns {
    /// Pair `p`'s normal jump and tangential jump under the terms' changes `dz`.
    fn jumps<T: Tangent>(&self, p: usize, dz: &[f64]) -> (f64, T) {
        let n = dz.len();
        let c = T::COMPONENTS;
        let dn: f64 = (0..n).map(|a| self.pn[p * n + a] * dz[a]).sum();
        let mut ds = T::default();
        for j in 0..c {
            let row = (p * c + j) * n;
            ds.set_component(j, (0..n).map(|a| self.ps[row + a] * dz[a]).sum());
        }
        (dn, ds)
    }
}

impl<D: ElementFamily> Solver<'_, D> {
    /// What the Newton steps of the patterns' slip forces did so far
    /// (`friction_solve = "newton"`; zero otherwise).
    pub fn newton_counts(&self) -> NewtonCounts {
        self.newton
    }

    /// Sets the slip force and spring anchor of every slipping pair of `slips`
    /// to their values at the pattern's solution: the first solution's moved
    /// by the columns `cols` times the terms' changes `dz`, the slip force
    /// `μ (−f_n) ξ` along the direction each pair was solved for.
    fn set_slip_terms(&mut self, slips: &[Slipping<D::Tangent>], cols: &Columns, dz: &[f64]) {
        for (p, s) in slips.iter().enumerate() {
            let (dn, ds) = cols.jumps::<D::Tangent>(p, dz);
            let h = &mut self.history[s.i][s.k];
            h.slip_force = s.xi.scale(s.mu * (-(s.f_n + s.c_n * dn)).max(0.0));
            h.anchor = s.u_s.add(ds);
        }
    }

    /// The Newton step of a pattern's slip forces (`friction_solve =
    /// "newton"`), taken before its fixed point from the solution `u` (valid
    /// at the coupling DOFs): the slipping Coulomb pairs' terms solved in one
    /// shot ([`Solver::solve_pattern_exact`]'s system, directions updated
    /// within the pattern) and written into the history, which is returned as
    /// it was before them; the fixed point then moves the solution by their
    /// change and confirms them (typically at its first check). `None` — the
    /// history untouched, the fixed point alone as by default — when the
    /// setting is off, an interface is augmented (its multipliers are
    /// iterated), no pair slips, the columns cannot be read from the cached
    /// condensed operator and more than [`MAX_NEWTON_SLIPPING`] pairs slip
    /// (they would cost more solves than the fixed point's steps), the
    /// small system is singular (no state of rest in the pattern), or its
    /// directions do not settle.
    pub(super) fn newton_slip_terms(
        &mut self,
        states: &[Vec<PairState>],
        inc: usize,
        u: &[f64],
    ) -> Result<Option<PairHistories<D>>> {
        let augmented = self
            .interfaces
            .iter()
            .any(|i| i.enforcement == Enforcement::Augmented);
        if self.settings.friction_solve != FrictionSolve::Newton || augmented {
            return Ok(None);
        }
        let mut slips = self.slipping(states, u);
        if slips.is_empty() {
            return Ok(None);
        }
        let Some(cols) = self.slip_columns(states, inc, &slips, MAX_NEWTON_SLIPPING)? else {
            return Ok(None);
        };
        let Some((dz, true)) = solve_slip_terms(&mut slips, &cols) else {
            self.newton.fallbacks += 1;
            return Ok(None);
        };
        self.newton.solved += 1;
        let before = self.history.clone();
        self.set_slip_terms(&slips, &cols, &dz);
        Ok(Some(before))
    }

    /// The slipping Coulomb pairs of `states` at the solution `u` (valid at the
    /// coupling DOFs), each sliding along its trial force there.
    fn slipping(&self, states: &[Vec<PairState>], u: &[f64]) -> Vec<Slipping<D::Tangent>> {
        let mut slips = Vec::new();
        for (i, iface) in self.interfaces.iter().enumerate() {
            if iface.law != Law::Coulomb {
                continue;
            }
            let base = self.law_params(i);
            for (k, c) in iface.elements.iter().enumerate() {
                let law = c.params(&base);
                if states[i][k] != PairState::Slip || law.c_slip <= 0.0 {
                    continue;
                }
                let h = &self.history[i][k];
                let p = iface.pair_at(k, self.dofs, u, PairState::Slip, h);
                let trial = law.trial_shear::<D>(p.jump.1, h);
                slips.push(Slipping {
                    i,
                    k,
                    mu: law.friction,
                    c_n: law.c_n,
                    c_s: law.c_s,
                    c_slip: law.c_slip,
                    slip: h.slip,
                    xi: trial.direction(),
                    f_n: p.force.0,
                    u_s: p.jump.1,
                    z: h.slip_force.sub(h.anchor.scale(law.c_slip)),
                });
            }
        }
        slips
    }

    /// The columns of the slipping pairs `slips` of `states`: from the
    /// interface's condensed operator when the back end keeps it
    /// ([`Solver::cached_slip_columns`]), else by solves when at most
    /// `most_solved` pairs slip (`None` beyond).
    fn slip_columns(
        &mut self,
        states: &[Vec<PairState>],
        inc: usize,
        slips: &[Slipping<D::Tangent>],
        most_solved: usize,
    ) -> Result<Option<Columns>> {
        if let Some(cols) = self.cached_slip_columns(states, slips) {
            self.newton.cached += 1;
            return Ok(Some(cols));
        }
        if slips.len() > most_solved {
            return Ok(None);
        }
        self.solved_slip_columns(states, inc, slips).map(Some)
    }

    /// The columns of the slipping pairs `slips` of `states` from the pairs'
    /// flexibility under the pattern's K ([`crate::solve::backend::PairFlexibility`]: Gram entries of
    /// the cached correction columns and the kept capacitance, no solve with
    /// the factor). A unit term along tangential axis b of pair q is a local
    /// force on it, so the jumps it causes are minus its flexibility column.
    /// `None` when the back end cannot give it.
    fn cached_slip_columns(
        &mut self,
        states: &[Vec<PairState>],
        slips: &[Slipping<D::Tangent>],
    ) -> Option<Columns> {
        let c = <D::Tangent as Tangent>::COMPONENTS;
        let (m, per) = (slips.len(), c + 1);
        let n = m * c;
        let pairs: Vec<(usize, usize)> = slips.iter().map(|s| (s.i, s.k)).collect();
        let f = self.linear.flexibility()?.pair_flexibility(states, &pairs)?;
        let mut cols = Columns {
            pn: vec![0.0; m * n],
            ps: vec![0.0; n * n],
        };
        for p in 0..m {
            for a in 0..n {
                cols.pn[p * n + a] = -f[(p * per) * n + a];
                for j in 0..c {
                    cols.ps[(p * c + j) * n + a] = -f[(p * per + 1 + j) * n + a];
                }
            }
        }
        Some(cols)
    }

    /// The columns of the slipping pairs `slips` of `states`: each component
    /// of each pair's term raised by 1, its force change solved on the
    /// interface's paths.
    fn solved_slip_columns(
        &mut self,
        states: &[Vec<PairState>],
        inc: usize,
        slips: &[Slipping<D::Tangent>],
    ) -> Result<Columns> {
        let c = <D::Tangent as Tangent>::COMPONENTS;
        let m = slips.len();
        let n = m * c;
        let len = self.dofs.eq.len();
        let zero = vec![0.0; len];
        let mut cols = Columns {
            pn: vec![0.0; m * n],
            ps: vec![0.0; n * n],
        };
        let mut rhs = vec![0.0; self.dofs.n_eq];
        let mut v = vec![0.0; len];
        let before = self.history.clone();
        for (q, s) in slips.iter().enumerate() {
            for b in 0..c {
                let a = q * c + b;
                self.check_stop(inc)?;
                let t = &mut self.history[s.i][s.k].slip_force;
                t.set_component(b, t.component(b) + 1.0);
                let change = self.pair_term_change(states, &before, &zero);
                self.history[s.i][s.k] = before[s.i][s.k];
                rhs.fill(0.0);
                for (&d, ch) in self.coupling_dofs.iter().zip(&change) {
                    let e = self.dofs.eq[d];
                    if e != FIXED {
                        rhs[e] = -ch;
                    }
                }
                let request = Request::new(states).interface_only().rhs_on_interface();
                let outcome = self
                    .linear
                    .solve_pattern(request, &mut rhs)
                    .map_err(|f| self.linear_error(f, inc))?;
                self.record(&outcome);
                self.fixed_point += 1;
                for &d in &self.coupling_dofs {
                    let e = self.dofs.eq[d];
                    v[d] = if e == FIXED { 0.0 } else { rhs[e] };
                }
                for (p, sp) in slips.iter().enumerate() {
                    let iface = &self.interfaces[sp.i];
                    let at = iface.pair_at(sp.k, self.dofs, &v, PairState::Slip, &before[sp.i][sp.k]);
                    cols.pn[p * n + a] = at.jump.0;
                    for j in 0..c {
                        cols.ps[(p * c + j) * n + a] = at.jump.1.component(j);
                    }
                }
            }
        }
        Ok(cols)
    }

    /// Solves the pattern `states` at load factor `lambda` exactly, in one shot,
    /// and checks the law on every pair: the increment a run would end on if this
    /// pattern were its answer, as [`Solver::solve_pattern`] gives it but with the
    /// slip forces of the slipping Coulomb pairs solved for rather than iterated.
    /// Each slipping pair slides along the direction of its trial force in the
    /// pattern's first solution (turned where the solution's trial force turns
    /// beyond the cone, then solved again; directions that do not settle are
    /// left to the law check to report). The slip forces' constant terms
    /// `z = t − c_slip a` (slip force less the stabilising spring's anchor term)
    /// satisfy, with the pattern's K (springs included), the system
    ///
    /// ```text
    ///     (I + diag(μ ξ c_n) P_n + diag(c_slip) P_s) δz = −μ ξ f_n⁰ − c_slip u_s⁰ − z⁰
    /// ```
    ///
    /// `P_n`, `P_s` the normal and tangential jumps of the slipping pairs under a
    /// unit change of each pair's term (one solve on the interface's paths per
    /// slipping pair and tangent component: the columns of the interface's
    /// Schur complement), `f_n⁰`, `u_s⁰`, `z⁰` those of the first solution (in
    /// 3D, the Newton steps add the radial return's turn,
    /// [`return_map_derivative`]). Its solution is the fixed point the
    /// iteration of [`Solver::solve_pattern`] converges to, when it converges;
    /// a singular system (a part free to slide under a load along its faces)
    /// has none and gives `None`. A model with augmented-Lagrangian interfaces
    /// is solved by [`Solver::solve_pattern`] (its multipliers are iterated).
    pub fn solve_pattern_exact(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
    ) -> Result<Option<IncrementResult<D>>> {
        let augmented = self
            .interfaces
            .iter()
            .any(|i| i.enforcement == Enforcement::Augmented);
        if self.proportional || augmented {
            return self.solve_pattern(lambda, states).map(Some);
        }
        let t = Instant::now();
        let inc = 1;
        let (u0, _, _) = self.solve_once(lambda, states, inc)?;
        let mut slips = self.slipping(states, &u0);
        if !slips.is_empty() {
            let cols = self
                .slip_columns(states, inc, &slips, usize::MAX)?
                .expect("columns by solves when not cached");
            let Some((dz, _)) = solve_slip_terms(&mut slips, &cols) else {
                return Ok(None);
            };
            self.set_slip_terms(&slips, &cols, &dz);
        }
        // One complete solve with the solved terms.
        let (u, f_int, method) = self.solve_once(lambda, states, inc)?;
        let check = self.check_law(states, &u, &f_int, lambda);
        let history = vec![Iteration {
            method,
            changed: count_changes(&check.next, states),
            seconds: t.elapsed().as_secs_f64(),
        }];
        Ok(Some(self.finish(inc, lambda, history, u, f_int, states.to_vec(), check, false)))
    }
}

/// Solves the slipping pairs' terms of a pattern by Newton steps on the small
/// system of their columns `cols`: the residual of each pair's term against
/// the radial return, `R = z − (μ (−f_n) ξ − c_slip u_s)`, with ξ the
/// direction of its trial force where that lies beyond the cone (kept
/// otherwise: the law check then makes the pair stick), and its derivative
/// ([`return_map_derivative`]: `μ (−δf_n) ξ` in 2D, which makes one step exact
/// for fixed directions; the turn of ξ in 3D). A 2D pair whose trial force
/// reversed beyond the cone slides the other way at the next step (the
/// semi-smooth step), at most [`MAX_DIRECTION_UPDATES`] times and never back
/// to directions already solved. Returns the changes of the terms, and whether
/// the directions settled with the residual at round-off; `None` when the
/// system is singular (no state of rest in the pattern).
fn solve_slip_terms<T: Tangent>(slips: &mut [Slipping<T>], cols: &Columns) -> Option<(Vec<f64>, bool)> {
    let c = T::COMPONENTS;
    let m = slips.len();
    let n = m * c;
    let key = |slips: &[Slipping<T>]| -> Vec<u64> {
        slips
            .iter()
            .flat_map(|s| (0..c).map(move |j| s.xi.component(j).to_bits()))
            .collect()
    };
    let mut seen: HashSet<Vec<u64>> = HashSet::new();
    let mut dz = vec![0.0; n];
    for step in 0..=MAX_DIRECTION_UPDATES + 1 {
        // The iterate: each pair's normal force, jump and trial force.
        let at: Vec<(f64, T, T)> = (0..m)
            .map(|p| {
                let s = &slips[p];
                let (dn, ds) = cols.jumps::<T>(p, &dz);
                let u_s = s.u_s.add(ds);
                (s.f_n + s.c_n * dn, u_s, u_s.sub(s.slip).scale(s.c_s))
            })
            .collect();
        // The semi-smooth step's directions: the trial force's beyond the cone.
        if step > 0 {
            let mut turned = false;
            for (s, &(f_n, _, trial)) in slips.iter_mut().zip(&at) {
                if trial.norm() > s.mu * (-f_n).max(0.0) {
                    let xi = trial.direction();
                    turned |= xi != s.xi;
                    s.xi = xi;
                }
            }
            let settled = at.iter().zip(slips.iter()).enumerate().all(|(p, (&(f_n, u_s, _), s))| {
                let r = residual(s, p, &dz, f_n, u_s);
                let size = s.mu * f_n.abs() + s.c_slip * u_s.norm() + s.z.norm();
                r.norm() <= 1e-10 * size.max(f64::MIN_POSITIVE)
            });
            if !turned && settled {
                return Some((dz, true));
            }
            if step > MAX_DIRECTION_UPDATES || (turned && seen.contains(&key(slips))) {
                return Some((dz, false));
            }
        }
        seen.insert(key(slips));
        // The Newton system J δ = −R.
        let mut jac = Mat::<f64>::zeros(n, n);
        for (p, (s, &(f_n, _, trial))) in slips.iter().zip(&at).enumerate() {
            let beyond = trial.norm() > s.mu * (-f_n).max(0.0);
            for a in 0..n {
                let d_fn = s.c_n * cols.pn[p * n + a];
                let mut d_us = T::default();
                for j in 0..c {
                    d_us.set_component(j, cols.ps[(p * c + j) * n + a]);
                }
                // A pair pulled apart carries no slip force (the cone is
                // closed): its derivative is zero, the semi-smooth branch.
                let dg = if f_n > 0.0 {
                    T::default()
                } else if beyond {
                    return_map_derivative(trial, f_n, s.mu, d_fn, d_us.scale(s.c_s))
                } else {
                    s.xi.scale(-s.mu * d_fn)
                };
                for j in 0..c {
                    let eye = if p * c + j == a { 1.0 } else { 0.0 };
                    jac[(p * c + j, a)] = eye - dg.component(j) + s.c_slip * d_us.component(j);
                }
            }
        }
        let rhs = Mat::<f64>::from_fn(n, 1, |r, _| {
            let (p, j) = (r / c, r % c);
            let (f_n, u_s, _) = at[p];
            -residual(&slips[p], p, &dz, f_n, u_s).component(j)
        });
        let delta = PartialPivLu::new(jac.as_ref()).solve(rhs.as_ref());
        if (0..n).any(|r| !delta[(r, 0)].is_finite()) {
            return None;
        }
        for (r, v) in dz.iter_mut().enumerate() {
            *v += delta[(r, 0)];
        }
    }
    Some((dz, false))
}

/// Pair `p`'s residual against the radial return at the terms' changes `dz`
/// (its normal force `f_n` and jump `u_s` there): `z − (μ max(−f_n, 0) ξ −
/// c_slip u_s)`.
fn residual<T: Tangent>(s: &Slipping<T>, p: usize, dz: &[f64], f_n: f64, u_s: T) -> T {
    let c = T::COMPONENTS;
    let mut z = s.z;
    for j in 0..c {
        z.set_component(j, z.component(j) + dz[p * c + j]);
    }
    z.sub(s.xi.scale(s.mu * (-f_n).max(0.0)).sub(u_s.scale(s.c_slip)))
}

#[cfg(test)]
mod tests {
    use super::*;

    const TOL: Tolerance = Tolerance {
        force: 1e-9,
        gap: 1e-12,
    };

    /// The complementarity rule: tension opens a closed pair, penetration closes
    /// an open one, a closed pair sticks inside the cone and slips along its trial
    /// force beyond it — in one tangent component and in two (the radial return:
    /// the direction is the trial's, whatever the axes).
    #[test]
    fn the_newton_update_is_the_return_map() {
        assert_eq!(next_active(true, 1e-3, 5.0, 0.0, 0.3, TOL), Active::Open);
        assert_eq!(next_active(false, 1e-3, 0.0, 0.0, 0.3, TOL), Active::Open);
        assert_eq!(next_active(false, -1e-3, -10.0, 2.0, 0.3, TOL), Active::Stick);
        assert_eq!(next_active(true, -1e-3, -10.0, -3.5, 0.3, TOL), Active::Slip(-1.0));
        let t = [3.0, 4.0];
        match next_active(true, -1e-3, -10.0, t, 0.3, TOL) {
            Active::Slip(xi) => {
                let e = xi.sub([0.6, 0.8]).norm();
                assert!(e < 1e-15, "ξ = {xi:?}");
            }
            other => panic!("{other:?}"),
        }
    }

    /// The consistent tangent of the radial return, against central differences
    /// of `μ (−f_n) t/|t|`: in two components it turns with the trial force
    /// (μ f/|t| (I − ξ⊗ξ)); in one it is the normal coupling μ ξ alone.
    #[test]
    fn the_return_maps_derivative_is_its_difference_quotient() {
        let map = |t: [f64; 2], f_n: f64| t.direction().scale(0.4 * -f_n);
        let (t, f_n) = ([3.0, -1.5], -7.0);
        let (d_fn, d_t) = (0.3, [-0.2, 0.5]);
        let h = 1e-6;
        let fd = map(t.add(d_t.scale(h)), f_n + h * d_fn)
            .sub(map(t.sub(d_t.scale(h)), f_n - h * d_fn))
            .scale(0.5 / h);
        let exact = return_map_derivative(t, f_n, 0.4, d_fn, d_t);
        assert!(fd.sub(exact).norm() < 1e-8, "{fd:?} vs {exact:?}");
        // ξ = −1: μ (−d_fn) ξ = 0.4 × 0.3.
        assert_eq!(return_map_derivative(-2.0, -7.0, 0.4, 0.3, 5.0), 0.4 * 0.3);
    }

    /// A tiny condensed model: two pairs on one elastic body (flexibility with
    /// coupling between them), pressed and pushed sideways.
    fn two_pairs(push: f64, mu: f64) -> Condensed {
        let flex = vec![
            1.0, 0.2, 0.3, 0.0, //
            0.2, 2.0, 0.1, 0.4, //
            0.3, 0.1, 1.0, 0.2, //
            0.0, 0.4, 0.2, 2.0,
        ]
        .into_iter()
        .map(|v| v * 1e-3)
        .collect();
        let pair = CondensedPair {
            c_n: 1e6,
            c_s: 1e6,
            mu,
            gap0: 0.0,
            slip: 0.0,
        };
        Condensed {
            flex,
            free: vec![-0.1, push, -0.1, 0.2 * push],
            pairs: vec![pair; 2],
        }
    }

    /// Per-pattern exactness: the one-shot solve of a pattern with both pairs
    /// slipping equals the fixed point of the slip forces (the explicit
    /// right-hand-side iteration with its stabilising spring, run to round-off),
    /// and the solution obeys the pattern's law: |f_s| = μ (−f_n) along ξ.
    #[test]
    fn a_pattern_solved_in_one_shot_is_the_fixed_points_limit() {
        let c = two_pairs(0.3, 0.2);
        let pattern = vec![Active::Slip(1.0); 2];
        let j = solve_pattern_linear(&c, &pattern).unwrap();
        // The fixed point: slip force t and anchor a as right-hand-side terms,
        // a spring c_slip in the pattern's matrix.
        let c_slip = 1e3;
        let (mut t, mut a) = ([0.0; 2], [0.0; 2]);
        let mut jf = vec![0.0; 4];
        for _ in 0..2000 {
            // Solve (I + F L_s) j = free − F l₀ with L_s: c_n normal, c_slip tangential.
            let cs = Condensed {
                pairs: c
                    .pairs
                    .iter()
                    .map(|p| CondensedPair { c_s: c_slip, ..*p })
                    .collect(),
                free: (0..4)
                    .map(|r| {
                        let l0 = [0.0, t[0] - c_slip * a[0], 0.0, t[1] - c_slip * a[1]];
                        c.free[r] - (0..4).map(|k| c.flex[r * 4 + k] * l0[k]).sum::<f64>()
                    })
                    .collect(),
                ..c.clone()
            };
            jf = solve_pattern_linear(&cs, &[Active::Stick, Active::Stick]).unwrap();
            for p in 0..2 {
                t[p] = -0.2 * c.pairs[p].c_n * jf[2 * p];
                a[p] = jf[2 * p + 1];
            }
        }
        for r in 0..4 {
            assert!((j[r] - jf[r]).abs() <= 1e-12 * 0.1, "{j:?} vs {jf:?}");
        }
        // Consistent: each pair in compression, its trial force beyond the cone
        // along ξ.
        for (p, pair) in c.pairs.iter().enumerate() {
            let f = pair.force(pattern[p], [j[2 * p], j[2 * p + 1]]);
            assert!(f[0] < 0.0);
            assert!(pair.c_s * j[2 * p + 1] > 0.2 * -f[0], "pair {p}: {f:?}");
        }
    }

    /// The Newton loop's state changes on the tiny model: from all stick, a
    /// light push stays stuck (one pattern); a push beyond friction slips a
    /// pair (two patterns or more, the last consistent) and the answer obeys
    /// Coulomb's law on both pairs; with μ = 0 both pairs slip.
    #[test]
    fn the_newton_loop_changes_states_until_the_law_holds() {
        let stick = vec![Active::Stick; 2];
        let light = newton_condensed(&two_pairs(0.001, 0.2), stick.clone(), TOL, 20).unwrap();
        assert_eq!(light.patterns.len(), 1);
        let c = two_pairs(0.1, 0.2);
        let run = newton_condensed(&c, stick.clone(), TOL, 20).unwrap();
        let last = run.patterns.last().unwrap();
        assert!(run.patterns.len() >= 2, "{:?}", run.patterns);
        assert!(last.iter().any(|a| matches!(a, Active::Slip(_))), "{last:?}");
        for (p, pair) in c.pairs.iter().enumerate() {
            let j = [run.jumps[2 * p], run.jumps[2 * p + 1]];
            let f = pair.force(last[p], j);
            let cone = pair.mu * (-f[0]).max(0.0);
            assert!(f[0] <= 0.0);
            assert!(f[1].abs() <= cone + 1e-9, "pair {p}: {f:?}");
            if let Active::Slip(xi) = last[p] {
                assert!((f[1] - xi * cone).abs() <= 1e-9);
                assert!(pair.c_s * (j[1] - pair.slip) * xi > cone);
            }
        }
        // μ = 0: the pairs carry no shear, the body (bounded F) takes the push.
        let free = newton_condensed(&two_pairs(0.1, 0.0), stick, TOL, 20).unwrap();
        assert!(free.patterns.last().unwrap().iter().all(|a| matches!(a, Active::Slip(_))));
    }
}
