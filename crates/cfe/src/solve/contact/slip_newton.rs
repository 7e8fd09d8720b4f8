//! The Newton step of a pattern's slip forces in a run (`[analysis]
//! friction_solve = "newton"`, docs/method.md §2.1): the slipping pairs' columns
//! (read from the interface's condensed operator the low-rank machinery caches,
//! [`crate::solve::backend::PairFlexibility`], or solved for on their paths), the
//! small non-symmetric system of their slip terms solved by Newton steps against
//! the radial return ([`super::friction::return_map_derivative`]), and a
//! pattern's exact solve. The fixed point on the slip forces starts from it and
//! remains the fallback.

use super::friction::return_map_derivative;
use super::increment::{IncrementResult, Iteration, NewtonCounts, count_changes};
use super::solver::Solver;
use crate::assembly::FIXED;
use crate::coupling::{Enforcement, Law, PairHistories, PairState};
use crate::dim::Tangent;
use crate::domain::FrictionSolve;
use crate::error::Result;
use crate::fem::ElementFamily;
use crate::solve::backend::{Request, Solve as _};
use faer::Mat;
use faer::linalg::solvers::{PartialPivLu, Solve};
use std::collections::HashSet;
use std::time::Instant;

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
    /// (they would cost more solves than the fixed point's steps), or the
    /// small system is singular (no state of rest in the pattern). With it,
    /// whether the directions settled: where they did not, the terms are the
    /// pattern's exact solution at the directions last solved for, and the
    /// law check reports the pairs whose slip turns.
    pub(super) fn newton_slip_terms(
        &mut self,
        states: &[Vec<PairState>],
        inc: usize,
        u: &[f64],
    ) -> Result<Option<(PairHistories<D>, bool)>> {
        let augmented = self
            .interfaces
            .iter()
            .any(|i| i.enforcement == Enforcement::Augmented);
        if self.friction_solve != FrictionSolve::Newton || augmented {
            return Ok(None);
        }
        let mut slips = self.slipping(states, u);
        if slips.is_empty() {
            return Ok(None);
        }
        let Some(cols) = self.slip_columns(states, inc, &slips, MAX_NEWTON_SLIPPING)? else {
            return Ok(None);
        };
        let Some((dz, settled)) = solve_slip_terms(&mut slips, &cols) else {
            self.newton.fallbacks += 1;
            return Ok(None);
        };
        self.newton.solved += 1;
        let before = self.history.clone();
        self.set_slip_terms(&slips, &cols, &dz);
        Ok(Some((before, settled)))
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
    /// `return_map_derivative`). Its solution is the fixed point the
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
            // The directions `dz` was solved for, should the turn not settle.
            let solved: Vec<T> = slips.iter().map(|s| s.xi).collect();
            let mut turned = false;
            for (s, &(f_n, _, trial)) in slips.iter_mut().zip(&at) {
                // In 3D a pair whose trial force reversed (turned by more than
                // 90° from the direction solved for) keeps that direction: the
                // reversal passes through the cone, so the pair sticks next
                // (the law check's semi-smooth step); turning it round would
                // send its neighbours' directions off too, and the turn of
                // the others would not settle.
                let reversed = T::COMPONENTS > 1 && trial.dot(s.xi) < 0.0;
                if trial.norm() > s.mu * (-f_n).max(0.0) && !reversed {
                    let xi = trial.direction();
                    // A turn beyond round-off (a 3D direction converges).
                    turned |= xi.sub(s.xi).norm() > 1e-13;
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
                // The exact solution of the pattern at the directions last
                // solved for: the law check sees the pairs that turn.
                for (s, xi) in slips.iter_mut().zip(solved) {
                    s.xi = xi;
                }
                return Some((dz, false));
            }
        }
        seen.insert(key(slips));
        // The Newton system J δ = −R.
        let mut jac = Mat::<f64>::zeros(n, n);
        for (p, (s, &(f_n, _, trial))) in slips.iter().zip(&at).enumerate() {
            // A reversed 3D pair slides along its fixed direction (above).
            let reversed = T::COMPONENTS > 1 && trial.dot(s.xi) < 0.0;
            let beyond = trial.norm() > s.mu * (-f_n).max(0.0) && !reversed;
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
