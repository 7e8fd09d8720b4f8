//! Incremental solution with contact interfaces. The load (and any prescribed
//! displacement) grows linearly over the increments; every increment solves total
//! equilibrium `K(D̂) u = λ F` (the law is secant, so a lagged state leaves no
//! accumulated error). Two schemes decide the pair states D̂:
//!
//! - `active-set`: solve, recompute every pair's state from the new [[u_n]], repeat
//!   until no state changes. A cycle (a state pattern seen before in the same
//!   increment) is settled by keeping the flipping pairs bonded — no
//!   interpenetration, a small tensile force — and iterating on; those pairs are
//!   reported as *settled*.
//! - `implex` (the seed's): the states of increment n come from [[u_n]] of increment
//!   n − 1 (all bonded before the first); one solve per increment.

use super::linear::CholeskySolver;
use super::support;
use crate::assembly::{self, DofMap, FIXED, Stiffness};
use crate::coupling::{Interface, PairState, element as cfe};
use crate::error::{Error, Result};
use crate::model::{Part, Scheme, Settings};
use std::collections::HashSet;
use std::time::Instant;

/// Seconds spent in each phase of the solution.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct SolveTimings {
    /// Sparsity pattern and symbolic factorization (once).
    pub pattern_and_symbolic: f64,
    /// Assembly of K values and right-hand sides.
    pub assembly: f64,
    /// Numeric factorizations.
    pub factorization: f64,
    /// Triangular solves.
    pub solve: f64,
    /// State updates, support checks, internal forces.
    pub contact_update: f64,
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

/// The incremental solver for one model.
pub struct Solver<'a> {
    parts: &'a [Part],
    interfaces: &'a [Interface],
    dofs: &'a DofMap,
    settings: &'a Settings,
    f_ext: Vec<f64>,
    k: Stiffness,
    chol: CholeskySolver,
    /// Phase timings.
    pub timings: SolveTimings,
}

impl<'a> Solver<'a> {
    /// Builds the fixed sparsity pattern and the symbolic factorization.
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
        let k = Stiffness::new(parts, interfaces, dofs);
        let chol = CholeskySolver::new(k.matrix())?;
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
            k,
            chol,
            timings,
        })
    }

    /// Number of nonzeros in the lower triangle of K.
    pub fn matrix_nnz(&self) -> usize {
        self.k.row_idx.len()
    }

    /// Number of nonzeros of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.chol.factor_nnz()
    }

    /// Runs all increments; `on_increment` receives each converged increment (to
    /// write it out) before the next starts. Returns the last increment.
    pub fn run(
        &mut self,
        mut on_increment: impl FnMut(&IncrementResult) -> Result<()>,
    ) -> Result<IncrementResult> {
        let n_inc = self.settings.increments;
        let mut states: Vec<Vec<PairState>> = self
            .interfaces
            .iter()
            .map(|i| vec![PairState::Bonded; i.elements.len()])
            .collect();
        let mut last = None;
        for inc in 1..=n_inc {
            let lambda = inc as f64 / n_inc as f64;
            let result = match self.settings.scheme {
                Scheme::ActiveSet => self.active_set_increment(inc, lambda, states.clone())?,
                Scheme::Implex => {
                    let (u, f_int) = self.solve_states(lambda, &states, inc)?;
                    let r = self.finish(inc, lambda, 1, u, f_int, states.clone(), Vec::new());
                    // States for the next increment from this increment's jumps.
                    states = self.states_from(&r.u, &states, &HashSet::new());
                    r
                }
            };
            if self.settings.scheme == Scheme::ActiveSet {
                states = result.states.clone();
            }
            on_increment(&result)?;
            last = Some(result);
        }
        Ok(last.expect("at least one increment"))
    }

    fn active_set_increment(
        &mut self,
        inc: usize,
        lambda: f64,
        mut states: Vec<Vec<PairState>>,
    ) -> Result<IncrementResult> {
        let mut history: Vec<Vec<Vec<PairState>>> = vec![states.clone()];
        let mut locked: HashSet<(usize, usize)> = HashSet::new();
        for it in 1..=self.settings.max_iterations {
            let (u, f_int) = self.solve_states(lambda, &states, inc)?;
            let mut next = self.states_from(&u, &states, &locked);
            if next == states {
                let mut settled: Vec<_> = locked.into_iter().collect();
                settled.sort_unstable();
                return Ok(self.finish(inc, lambda, it, u, f_int, states, settled));
            }
            if let Some(pos) = history.iter().position(|h| *h == next) {
                // A cycle: every pair whose state differs somewhere along it flips.
                let cycle = &history[pos..];
                for (i, st) in next.iter().enumerate() {
                    for (k, &s) in st.iter().enumerate() {
                        if cycle.iter().any(|h| h[i][k] != s) {
                            locked.insert((i, k));
                        }
                    }
                }
                for &(i, k) in &locked {
                    next[i][k] = PairState::Bonded;
                }
                if next == states {
                    let mut settled: Vec<_> = locked.into_iter().collect();
                    settled.sort_unstable();
                    return Ok(self.finish(inc, lambda, it, u, f_int, states, settled));
                }
            }
            history.push(next.clone());
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
    fn states_from(
        &self,
        u: &[f64],
        _prev: &[Vec<PairState>],
        locked: &HashSet<(usize, usize)>,
    ) -> Vec<Vec<PairState>> {
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
                        let g = self.dofs.cfe_dofs(iface, c);
                        let d = g.map(|j| u[j]);
                        let gap = cfe::local_jump(c.normal, cfe::jump(&c.shape, &d))[0];
                        iface.law.state(gap, self.gap_tolerance(&d))
                    })
                    .collect()
            })
            .collect()
    }

    /// The open/closed tolerance of a pair: `gap_tolerance` × the largest
    /// displacement magnitude among its four nodes.
    fn gap_tolerance(&self, d: &[f64; 8]) -> f64 {
        let scale = (0..4)
            .map(|a| d[2 * a].hypot(d[2 * a + 1]))
            .fold(0.0, f64::max);
        self.settings.gap_tolerance * scale
    }

    /// One linear solve at load factor `lambda` with the given states. Returns the
    /// displacements of all DOFs and the internal force.
    fn solve_states(
        &mut self,
        lambda: f64,
        states: &[Vec<PairState>],
        inc: usize,
    ) -> Result<(Vec<f64>, Vec<f64>)> {
        let t = Instant::now();
        support::check(self.parts, self.interfaces, states, self.dofs)?;
        self.timings.contact_update += t.elapsed().as_secs_f64();

        let t = Instant::now();
        self.k.assemble(self.interfaces, states, self.dofs);
        let mut u: Vec<f64> = self.dofs.prescribed.iter().map(|v| lambda * v).collect();
        let mut rhs = vec![0.0; self.dofs.n_eq];
        let has_prescribed = u.iter().any(|&v| v != 0.0);
        let f_p = if has_prescribed {
            assembly::internal_force(self.parts, self.interfaces, states, self.dofs, &u)
        } else {
            Vec::new()
        };
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            if e != FIXED {
                rhs[e] = lambda * self.f_ext[d] - if has_prescribed { f_p[d] } else { 0.0 };
            }
        }
        self.timings.assembly += t.elapsed().as_secs_f64();

        let t = Instant::now();
        if let Err(eq) = self.chol.factorize(self.k.matrix()) {
            let d = self.dofs.eq.iter().position(|&e| e == eq).unwrap_or(0);
            let (p, n) = self.dofs.locate(d / 2);
            return Err(Error::Singular(format!(
                "increment {inc}: the stiffness matrix is not positive definite (pivot at part '{}', node {n}, {} displacement); check for a mechanism or an unsupported part",
                self.parts[p].name,
                if d % 2 == 0 { "x" } else { "y" }
            )));
        }
        self.timings.factorization += t.elapsed().as_secs_f64();

        let t = Instant::now();
        self.chol.solve_in_place(&mut rhs);
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            if e != FIXED {
                u[d] = rhs[e];
            }
        }
        self.timings.solve += t.elapsed().as_secs_f64();

        let t = Instant::now();
        let f_int = assembly::internal_force(self.parts, self.interfaces, states, self.dofs, &u);
        self.timings.contact_update += t.elapsed().as_secs_f64();
        if u.iter().any(|v| !v.is_finite()) {
            return Err(Error::Singular(format!(
                "increment {inc}: the solution is not finite"
            )));
        }
        Ok((u, f_int))
    }

    #[allow(clippy::too_many_arguments)]
    fn finish(
        &self,
        index: usize,
        lambda: f64,
        iterations: usize,
        u: Vec<f64>,
        f_int: Vec<f64>,
        states: Vec<Vec<PairState>>,
        settled: Vec<(usize, usize)>,
    ) -> IncrementResult {
        let f_ext: Vec<f64> = self.f_ext.iter().map(|f| lambda * f).collect();
        let mut scale: f64 = f_ext.iter().fold(0.0, |a, f| a.max(f.abs()));
        let mut res: f64 = 0.0;
        for (d, &e) in self.dofs.eq.iter().enumerate() {
            if e == FIXED {
                scale = scale.max((f_int[d] - f_ext[d]).abs());
            } else {
                res = res.max((f_int[d] - f_ext[d]).abs());
            }
        }
        IncrementResult {
            index,
            lambda,
            iterations,
            u,
            states,
            settled,
            f_int,
            f_ext,
            residual: if scale > 0.0 { res / scale } else { res },
        }
    }
}
