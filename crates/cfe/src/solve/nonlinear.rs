//! Incremental solution with contact interfaces. The load (and any prescribed
//! displacement) grows linearly over the increments; every increment solves total
//! equilibrium `K(D̂) u = λ F` (the law is secant, so a lagged state leaves no
//! accumulated error). Two schemes decide the pair states D̂:
//!
//! - `active-set`: solve, recompute every pair's state from the new `[[u_n]]`, repeat
//!   until no state changes. A cycle (a state pattern seen before in the same
//!   increment, or a pair about to change state for the second time in it) is
//!   settled by keeping the flipping pairs bonded — no interpenetration, a small
//!   tensile force — and iterating on; those pairs are
//!   reported as *settled* and stay bonded in the following increments (the loads
//!   are proportional, so the same cycle would recur at every load level).
//! - `implex` (the seed's): the states of increment n come from `[[u_n]]` of increment
//!   n − 1 (all bonded before the first); one solve per increment.
//!
//! Linear solves go through [`ContactSystem`], which refactorizes or corrects the
//! current factorization by a low-rank update, whichever costs less. A state set
//! already solved at another load factor is not solved again: with proportional
//! loads its solution scales with λ exactly.

use super::linear::CholeskySolver;
use super::ordering;
use super::support;
use super::system::{ContactSystem, Method};
use crate::assembly::{self, DofMap, FIXED, NodeGraph, Stiffness};
use crate::coupling::{Interface, PairState};
use crate::domain::{Part, Scheme, Settings};
use crate::error::{Error, Result};
use std::collections::HashSet;
use std::time::Instant;

/// Seconds spent in each phase of the solution.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct SolveTimings {
    /// Node graph, ordering, sparsity pattern and symbolic factorization (once).
    pub pattern_and_symbolic: f64,
    /// Assembly of K values and right-hand sides.
    pub assembly: f64,
    /// Numeric factorizations.
    pub factorization: f64,
    /// Triangular solves, including low-rank update columns.
    pub solve: f64,
    /// State updates, support checks, internal forces.
    pub contact_update: f64,
}

/// One linear solve of an increment.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Iteration {
    /// How the system was solved (or `None` when the solution of the same states
    /// at another load factor was scaled).
    pub method: Option<Method>,
    /// Pairs whose state the law changed after this solve.
    pub changed: usize,
    /// Seconds spent on this iteration (solve, internal forces, state update).
    pub seconds: f64,
}

/// The converged result of one increment.
#[derive(Debug, Clone)]
pub struct IncrementResult {
    /// 1-based increment number.
    pub index: usize,
    /// Load factor λ (1 at the last increment).
    pub lambda: f64,
    /// Linear solves in this increment.
    pub iterations: usize,
    /// What each solve did.
    pub history: Vec<Iteration>,
    /// Displacements of all DOFs.
    pub u: Vec<f64>,
    /// Pair states used in the final solve, per interface.
    pub states: Vec<Vec<PairState>>,
    /// Pairs kept bonded to settle a cycle: (interface, pair).
    pub settled: Vec<(usize, usize)>,
    /// Internal force of all DOFs (reactions are F_int − F_ext at fixed DOFs).
    pub f_int: Vec<f64>,
    /// External force of all DOFs at this λ.
    pub f_ext: Vec<f64>,
    /// Largest out-of-balance force at free DOFs relative to the largest external or reaction force.
    pub residual: f64,
}

/// The solution of one state set, kept to answer the same states at another λ.
struct Solved {
    states: Vec<Vec<PairState>>,
    lambda: f64,
    u: Vec<f64>,
    f_int: Vec<f64>,
}

/// The incremental solver for one model.
pub struct Solver<'a> {
    parts: &'a [Part],
    interfaces: &'a [Interface],
    dofs: &'a DofMap,
    settings: &'a Settings,
    f_ext: Vec<f64>,
    system: ContactSystem,
    last: Option<Solved>,
    initial: Option<Vec<Vec<PairState>>>,
    /// Phase timings.
    pub timings: SolveTimings,
}

/// Out-of-balance tolerance above which a low-rank solution is redone by factorization.
const UPDATE_RESIDUAL_LIMIT: f64 = 1e-8;

impl<'a> Solver<'a> {
    /// Builds the node graph, the nested-dissection ordering, the fixed sparsity
    /// pattern and the symbolic factorization.
    pub fn new(
        parts: &'a [Part],
        interfaces: &'a [Interface],
        dofs: &'a DofMap,
        f_ext: Vec<f64>,
        settings: &'a Settings,
    ) -> Result<Self> {
        if dofs.n_eq == 0 {
            return Err(Error::Model(
                "every degree of freedom is prescribed: nothing to solve".into(),
            ));
        }
        let t = Instant::now();
        let graph = NodeGraph::new(parts, interfaces, dofs);
        let coords: Vec<[f64; 2]> = parts
            .iter()
            .flat_map(|p| p.mesh.nodes.iter().copied())
            .collect();
        let order = ordering::nested_dissection(&coords, &graph, dofs);
        let k = Stiffness::new(parts, dofs, &graph);
        drop(graph);
        let chol = CholeskySolver::new(k.matrix(), Some(&order))?;
        let timings = SolveTimings {
            pattern_and_symbolic: t.elapsed().as_secs_f64(),
            ..Default::default()
        };
        Ok(Solver {
            parts,
            interfaces,
            dofs,
            settings,
            f_ext,
            system: ContactSystem::new(k, chol),
            last: None,
            initial: None,
            timings,
        })
    }

    /// Number of nonzeros in the lower triangle of K.
    pub fn matrix_nnz(&self) -> usize {
        self.system.k.row_idx.len()
    }

    /// Number of nonzeros of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.system.factor_nnz()
    }

    /// Seconds of the first numeric factorization (None before it).
    pub fn first_factorization_seconds(&self) -> Option<f64> {
        self.system.first_factor_seconds
    }

    /// Numeric factorizations and low-rank updates performed so far.
    pub fn solve_counts(&self) -> (usize, usize) {
        (self.system.factorizations, self.system.updates)
    }

    /// Starts the `active-set` iteration of the first increment from these states
    /// instead of all bonded (e.g. the pattern found on a coarser mesh). The converged
    /// result does not depend on it; the number of iterations does.
    pub fn set_initial_states(&mut self, states: Vec<Vec<PairState>>) {
        if states.len() == self.interfaces.len()
            && states
                .iter()
                .zip(self.interfaces)
                .all(|(s, i)| s.len() == i.elements.len())
        {
            self.initial = Some(states);
        }
    }

    /// Runs all increments; `on_increment` receives each converged increment (to
    /// write it out) before the next starts. Returns the last increment.
    pub fn run(
        &mut self,
        mut on_increment: impl FnMut(&IncrementResult) -> Result<()>,
    ) -> Result<IncrementResult> {
        let n_inc = self.settings.increments;
        let all_bonded: Vec<Vec<PairState>> = self
            .interfaces
            .iter()
            .map(|i| vec![PairState::Bonded; i.elements.len()])
            .collect();
        let mut states = match (self.settings.scheme, self.initial.take()) {
            (Scheme::ActiveSet, Some(s)) => s,
            _ => all_bonded,
        };
        let mut locked: HashSet<(usize, usize)> = HashSet::new();
        let mut last = None;
        for inc in 1..=n_inc {
            let lambda = inc as f64 / n_inc as f64;
            let result = match self.settings.scheme {
                Scheme::ActiveSet => {
                    let r = self.active_set_increment(inc, lambda, states.clone(), &mut locked)?;
                    states = r.states.clone();
                    r
                }
                Scheme::Implex => {
                    let t = Instant::now();
                    let (u, f_int, method) = self.solve_states(lambda, &states, inc)?;
                    // States for the next increment from this increment's jumps.
                    let next = self.states_from(&u, &HashSet::new());
                    let changed = count_changes(&next, &states);
                    let seconds = t.elapsed().as_secs_f64();
                    let history = vec![Iteration {
                        method,
                        changed,
                        seconds,
                    }];
                    let r = self.finish(inc, lambda, history, u, f_int, states, Vec::new());
                    states = next;
                    r
                }
            };
            on_increment(&result)?;
            last = Some(result);
        }
        let t = &mut self.timings;
        t.factorization = self.system.factor_seconds;
        t.solve = self.system.solve_seconds;
        Ok(last.expect("at least one increment"))
    }

    fn active_set_increment(
        &mut self,
        inc: usize,
        lambda: f64,
        mut states: Vec<Vec<PairState>>,
        locked: &mut HashSet<(usize, usize)>,
    ) -> Result<IncrementResult> {
        let mut seen: Vec<Vec<Vec<PairState>>> = vec![states.clone()];
        let mut flips: std::collections::HashMap<(usize, usize), u32> =
            std::collections::HashMap::new();
        let mut history = Vec::new();
        for _ in 1..=self.settings.max_iterations {
            let t = Instant::now();
            let (u, f_int, method) = self.solve_states(lambda, &states, inc)?;
            let mut next = self.states_from(&u, locked);
            if let Some(pos) = seen.iter().position(|h| *h == next)
                && next != states
            {
                // A cycle: every pair whose state differs somewhere along it flips.
                let cycle = &seen[pos..];
                for (i, st) in next.iter().enumerate() {
                    for (k, &s) in st.iter().enumerate() {
                        if cycle.iter().any(|h| h[i][k] != s) {
                            locked.insert((i, k));
                        }
                    }
                }
                for &(i, k) in locked.iter() {
                    next[i][k] = PairState::Bonded;
                }
            }
            // A pair about to change state a second time in this increment returns to
            // a state it already had: it oscillates (a cycle of its own, whatever the
            // other pairs do). Settle it at once.
            for (i, (n, s)) in next.iter_mut().zip(&states).enumerate() {
                for (k, (nk, sk)) in n.iter_mut().zip(s).enumerate() {
                    if nk != sk {
                        let count = flips.entry((i, k)).or_insert(0u32);
                        *count += 1;
                        if *count >= 2 {
                            locked.insert((i, k));
                            *nk = PairState::Bonded;
                        }
                    }
                }
            }
            history.push(Iteration {
                method,
                changed: count_changes(&next, &states),
                seconds: t.elapsed().as_secs_f64(),
            });
            if next == states {
                let mut settled: Vec<_> = locked.iter().copied().collect();
                settled.sort_unstable();
                return Ok(self.finish(inc, lambda, history, u, f_int, states, settled));
            }
            seen.push(next.clone());
            states = next;
        }
        let open: usize = states
            .iter()
            .flatten()
            .filter(|&&s| s == PairState::Open)
            .count();
        Err(Error::NoConvergence(format!(
            "increment {inc} (load factor {lambda:.4}): the contact states did not settle within {} iterations ({open} pairs open at the last one, {} pairs kept bonded to break cycles). Raise [analysis] max_iterations or use more increments",
            self.settings.max_iterations,
            locked.len()
        )))
    }

    /// The pair states the law assigns to displacements `u`; `locked` pairs stay bonded.
    fn states_from(&self, u: &[f64], locked: &HashSet<(usize, usize)>) -> Vec<Vec<PairState>> {
        self.interfaces
            .iter()
            .enumerate()
            .map(|(i, iface)| {
                iface
                    .elements
                    .iter()
                    .enumerate()
                    .map(|(k, c)| {
                        if locked.contains(&(i, k)) {
                            return PairState::Bonded;
                        }
                        let d = c.dofs(self.dofs, iface.host, iface.node_part).gather(u);
                        let d = &d[..c.n_dofs()];
                        iface.law.state(c.gap_n(d), self.gap_tolerance(d))
                    })
                    .collect()
            })
            .collect()
    }

    /// The open/closed tolerance of a pair: `gap_tolerance` × the largest
    /// displacement magnitude among its nodes (element displacements `d`).
    fn gap_tolerance(&self, d: &[f64]) -> f64 {
        let scale = d
            .chunks_exact(2)
            .map(|v| v[0].hypot(v[1]))
            .fold(0.0, f64::max);
        self.settings.gap_tolerance * scale
    }

    /// Displacements (all DOFs), internal force and solve method for the given
    /// states at load factor `lambda`.
    fn solve_states(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        inc: usize,
    ) -> Result<(Vec<f64>, Vec<f64>, Option<Method>)> {
        if let Some(s) = &self.last
            && s.states == states
            && s.lambda != 0.0
        {
            // Loads and prescribed values are proportional: same states, scaled solution.
            let f = lambda / s.lambda;
            let u = s.u.iter().map(|v| f * v).collect();
            let f_int = s.f_int.iter().map(|v| f * v).collect();
            return Ok((u, f_int, None));
        }
        let t = Instant::now();
        support::check(self.parts, self.interfaces, states, self.dofs)?;
        self.timings.contact_update += t.elapsed().as_secs_f64();

        let t = Instant::now();
        let mut u: Vec<f64> = self.dofs.prescribed.iter().map(|v| lambda * v).collect();
        let has_prescribed = u.iter().any(|&v| v != 0.0);
        let f_p = if has_prescribed {
            assembly::internal_force(self.parts, self.interfaces, states, self.dofs, &u)
        } else {
            Vec::new()
        };
        let mut rhs = vec![0.0; self.dofs.n_eq];
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            if e != FIXED {
                rhs[e] = lambda * self.f_ext[d] - if has_prescribed { f_p[d] } else { 0.0 };
            }
        }
        self.timings.assembly += t.elapsed().as_secs_f64();

        let mut refactored = false;
        loop {
            let mut x = rhs.clone();
            let method = self
                .system
                .solve(self.interfaces, self.dofs, states, &mut x)
                .map_err(|eq| self.pivot_error(eq, inc))?;
            for (d, &e) in self.dofs.eq.iter().enumerate() {
                if e != FIXED {
                    u[d] = x[e];
                }
            }
            if u.iter().any(|v| !v.is_finite()) {
                return Err(Error::Singular(format!(
                    "increment {inc}: the solution is not finite"
                )));
            }
            let t = Instant::now();
            let f_int =
                assembly::internal_force(self.parts, self.interfaces, states, self.dofs, &u);
            self.timings.contact_update += t.elapsed().as_secs_f64();
            let residual = self.residual(lambda, &f_int);
            if residual > UPDATE_RESIDUAL_LIMIT
                && matches!(method, Method::LowRank { .. })
                && !refactored
            {
                // The update lost accuracy: solve again with a fresh factorization.
                self.system.invalidate();
                refactored = true;
                continue;
            }
            self.last = Some(Solved {
                states: states.to_vec(),
                lambda,
                u: u.clone(),
                f_int: f_int.clone(),
            });
            return Ok((u, f_int, Some(method)));
        }
    }

    fn pivot_error(&self, eq: usize, inc: usize) -> Error {
        let d = self.dofs.eq.iter().position(|&e| e == eq).unwrap_or(0);
        let (p, n) = self.dofs.locate(d / 2);
        Error::NotPositiveDefinite {
            increment: inc,
            part: self.parts[p].name.clone(),
            node: n,
            component: d % 2,
            message: format!(
                "increment {inc}: the stiffness matrix is not positive definite (pivot at part '{}', node {n}, {} displacement); check for a mechanism or an unsupported part",
                self.parts[p].name,
                if d % 2 == 0 { "x" } else { "y" }
            ),
        }
    }

    /// Largest out-of-balance force at free DOFs relative to the largest external
    /// force or reaction.
    fn residual(&self, lambda: f64, f_int: &[f64]) -> f64 {
        let mut scale: f64 = 0.0;
        let mut res: f64 = 0.0;
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            let r = f_int[d] - lambda * self.f_ext[d];
            if e == FIXED {
                scale = scale.max(r.abs());
            } else {
                scale = scale.max((lambda * self.f_ext[d]).abs());
                res = res.max(r.abs());
            }
        }
        if scale > 0.0 { res / scale } else { res }
    }

    #[allow(clippy::too_many_arguments)]
    fn finish(
        &self,
        index: usize,
        lambda: f64,
        history: Vec<Iteration>,
        u: Vec<f64>,
        f_int: Vec<f64>,
        states: Vec<Vec<PairState>>,
        settled: Vec<(usize, usize)>,
    ) -> IncrementResult {
        let f_ext: Vec<f64> = self.f_ext.iter().map(|f| lambda * f).collect();
        let residual = self.residual(lambda, &f_int);
        IncrementResult {
            index,
            lambda,
            iterations: history.len(),
            history,
            u,
            states,
            settled,
            f_int,
            f_ext,
            residual,
        }
    }
}

fn count_changes(a: &[Vec<PairState>], b: &[Vec<PairState>]) -> usize {
    a.iter()
        .zip(b)
        .map(|(x, y)| x.iter().zip(y).filter(|(p, q)| p != q).count())
        .sum()
}
