//! A deliberately simple second back end behind the linear-solver seam
//! ([`super::backend`]): conjugate gradients preconditioned by the inverse
//! diagonal of `K(states)` (Jacobi), on the assembled sparse matrix, by faer's
//! operator traits and its `conjugate_gradient`. It proves the seam; it is not
//! fast (its iterations grow with the penalty's conditioning).
//!
//! The matrix is stored whole (both triangles, in the equations' order: the
//! operator faer's sparse matrix applies); its pattern is laid out once and its
//! values scattered from the assembled lower triangle at each preparation. The
//! preconditioner is rebuilt with the values (one pass over the diagonal): a
//! preparation is needed exactly when the states change. A solve starts from
//! the caller's guess (warm start), stops when `‖b − K x‖ ≤ tolerance · ‖b‖` —
//! checked on the true residual, and restarted from the iterate when the
//! recursively updated one drifted below it — and returns a typed error when
//! the iteration cap is reached first.

use super::backend::{
    Analyse, Iterations, LinearFailure, LinearSolver, Outcome, Problem, Statistics,
};
use super::system::Method;
use crate::assembly::{NodeGraph, Stiffness};
use crate::coupling::{PairState, PairStates};
use crate::dim::{D2, Dim};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::matrix_free::InitialGuessStatus;
use faer::matrix_free::LinOp;
use faer::matrix_free::conjugate_gradient::{
    CgError, CgParams, conjugate_gradient, conjugate_gradient_scratch,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{ColRef, MatMut, MatRef, Par};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// Relative residual a solve stops at unless told otherwise
/// ([`ConjugateGradients::tolerance`]).
pub const DEFAULT_TOLERANCE: f64 = 1e-10;

/// Restarts from the iterate allowed when the true residual is above the
/// tolerance that the recursively updated one met.
const MAX_RESTARTS: usize = 4;

/// Jacobi-preconditioned conjugate gradients on the assembled `K(states)`.
pub struct ConjugateGradients<'a, D: Dim = D2> {
    problem: Problem<'a, D>,
    /// The lower triangle's pattern (equations' order); values only while a
    /// preparation scatters them.
    lower: Stiffness,
    /// The whole matrix's pattern.
    full: SymbolicSparseColMat<usize>,
    /// Position in the whole matrix of each stored lower entry `(i, j)`, and of
    /// its mirror `(j, i)` (`usize::MAX` on the diagonal).
    at: Vec<usize>,
    mirror: Vec<usize>,
    /// Position of each diagonal entry in the whole matrix (`usize::MAX`: not
    /// in the pattern).
    diagonal: Vec<usize>,
    /// The whole matrix's values for the prepared states.
    values: Vec<f64>,
    /// `1 / K_ii` (the Jacobi preconditioner).
    inverse_diagonal: Vec<f64>,
    /// The states `values` are of.
    prepared: Option<PairStates>,
    stop: Option<&'a AtomicUsize>,
    /// Relative residual `‖b − K x‖ / ‖b‖` a solve stops at.
    pub tolerance: f64,
    /// Iteration cap of one solve (restarts included); `None`: ten times the
    /// number of equations.
    pub max_iterations: Option<usize>,
    stats: Statistics,
}

impl<'a, D: Dim> Analyse<'a, D> for ConjugateGradients<'a, D> {
    /// The node graph, the lower pattern (the parts' stiffness assembled into
    /// it) and the whole matrix's pattern.
    fn analyse(problem: Problem<'a, D>) -> crate::error::Result<Self> {
        let Problem {
            parts,
            interfaces,
            dofs,
        } = problem;
        let graph = NodeGraph::new(parts, interfaces, dofs);
        let lower = Stiffness::new(parts, dofs, &graph);
        drop(graph);
        let n = lower.n();
        let nnz = lower.row_idx.len();
        // Each off-diagonal entry twice: fewer than 2·nnz entries, whose
        // 16 bytes each are already held, so the count fits a usize.
        let mut count = vec![0usize; n + 1];
        for j in 0..n {
            for &i in &lower.row_idx[lower.col_ptr[j]..lower.col_ptr[j + 1]] {
                count[j + 1] += 1;
                if i as usize != j {
                    count[i as usize + 1] += 1;
                }
            }
        }
        for j in 0..n {
            count[j + 1] += count[j];
        }
        let col_ptr = count;
        let mut next = col_ptr[..n].to_vec();
        let mut rows = vec![0usize; col_ptr[n]];
        let (mut at, mut mirror) = (vec![0usize; nnz], vec![usize::MAX; nnz]);
        let mut diagonal = vec![usize::MAX; n];
        // Column j of the whole matrix gets the rows of the columns before it
        // (its upper part, ascending) before its own lower rows (ascending):
        // its rows come out sorted.
        for j in 0..n {
            for p in lower.col_ptr[j]..lower.col_ptr[j + 1] {
                let i = lower.row_idx[p] as usize;
                at[p] = next[j];
                rows[next[j]] = i;
                next[j] += 1;
                if i == j {
                    diagonal[j] = at[p];
                } else {
                    mirror[p] = next[i];
                    rows[next[i]] = j;
                    next[i] += 1;
                }
            }
        }
        let full = SymbolicSparseColMat::new_checked(n, n, col_ptr, None, rows);
        Ok(ConjugateGradients {
            problem,
            lower,
            full,
            at,
            mirror,
            diagonal,
            values: Vec::new(),
            inverse_diagonal: Vec::new(),
            prepared: None,
            stop: None,
            tolerance: DEFAULT_TOLERANCE,
            max_iterations: None,
            stats: Statistics {
                matrix_nnz: nnz,
                ..Statistics::default()
            },
        })
    }
}

impl<D: Dim> ConjugateGradients<'_, D> {
    /// The prepared matrix (both triangles) as faer's sparse operator.
    fn matrix(&self) -> SparseColMatRef<'_, usize, f64> {
        SparseColMatRef::new(self.full.as_ref(), &self.values)
    }

    /// `Err(Stopped)` once the stop flag is nonzero.
    fn check_stop(&self) -> Result<(), LinearFailure> {
        match self.stop.map_or(0, |s| s.load(Ordering::Relaxed)) {
            0 => Ok(()),
            signal => Err(LinearFailure::Stopped(signal)),
        }
    }

    /// Conjugate gradients from `x` for `K x = b` at most `cap` iterations in
    /// all (`done` counts them), restarted from the iterate while the true
    /// residual is above the tolerance the recursive one met.
    fn iterate(
        &self,
        b: &[f64],
        x: &mut [f64],
        cap: usize,
        done: &mut usize,
    ) -> Result<Iterations, LinearFailure> {
        let n = b.len();
        let precond = ColRef::from_slice(&self.inverse_diagonal).as_diagonal();
        let a = self.matrix();
        let mut buffer = MemBuffer::new(conjugate_gradient_scratch(precond, a, 1, Par::Seq));
        let mut restarts = 0usize;
        let result = loop {
            // Always "maybe nonzero" (the zero guess too): faer 0.24's
            // `InitialGuessStatus::Zero` leaves its residual vector unset.
            let params = CgParams {
                initial_guess: InitialGuessStatus::MaybeNonZero,
                abs_tolerance: 0.0,
                rel_tolerance: self.tolerance,
                max_iters: cap - *done,
                ..CgParams::default()
            };
            let solved = conjugate_gradient(
                MatMut::from_column_major_slice_mut(x, n, 1),
                precond,
                a,
                MatRef::from_column_major_slice(b, n, 1),
                params,
                |_| {},
                Par::Seq,
                MemStack::new(&mut buffer),
            );
            match solved {
                Ok(info) => {
                    *done += info.iter_count;
                    // The recursively updated residual met the tolerance: the
                    // true one decides.
                    let relative_residual = self.relative_residual(b, x);
                    if relative_residual <= self.tolerance {
                        break Ok(Iterations {
                            count: *done,
                            relative_residual,
                        });
                    }
                    if *done >= cap || restarts == MAX_RESTARTS || info.iter_count == 0 {
                        break Err(LinearFailure::NotConverged {
                            iterations: *done,
                            relative_residual,
                            tolerance: self.tolerance,
                        });
                    }
                    restarts += 1;
                    self.check_stop()?;
                }
                Err(CgError::NoConvergence { .. }) => {
                    break Err(LinearFailure::NotConverged {
                        iterations: cap,
                        relative_residual: self.relative_residual(b, x),
                        tolerance: self.tolerance,
                    });
                }
                Err(
                    CgError::NonPositiveDefiniteOperator
                    | CgError::NonPositiveDefinitePreconditioner,
                ) => break Err(LinearFailure::NotPositiveDefinite { equation: None }),
            }
        };
        drop(buffer);
        result
    }

    /// `‖b − K x‖ / ‖b‖` (0 for `b = 0` and `x = 0`).
    fn relative_residual(&self, b: &[f64], x: &[f64]) -> f64 {
        let n = b.len();
        let mut kx = vec![0.0; n];
        let a = self.matrix();
        let mut scratch = MemBuffer::new(a.apply_scratch(1, Par::Seq));
        a.apply(
            MatMut::from_column_major_slice_mut(&mut kx, n, 1),
            MatRef::from_column_major_slice(x, n, 1),
            Par::Seq,
            MemStack::new(&mut scratch),
        );
        let r = b
            .iter()
            .zip(&kx)
            .map(|(b, k)| (b - k) * (b - k))
            .sum::<f64>()
            .sqrt();
        let norm = b.iter().map(|b| b * b).sum::<f64>().sqrt();
        if norm == 0.0 { r } else { r / norm }
    }
}

impl<'a, D: Dim> LinearSolver<'a> for ConjugateGradients<'a, D> {
    /// Assembles `K(states)` into the whole matrix and inverts its diagonal;
    /// a diagonal entry that is not positive and finite is
    /// [`LinearFailure::NotPositiveDefinite`] at its equation.
    fn prepare(&mut self, states: &[Vec<PairState>]) -> Result<Method, LinearFailure> {
        if self.prepared.as_deref() == Some(states) {
            return Ok(Method::Reuse);
        }
        self.check_stop()?;
        let t = Instant::now();
        self.prepared = None;
        let Problem {
            parts,
            interfaces,
            dofs,
        } = self.problem;
        self.lower.assemble(parts, interfaces, states, dofs);
        let lower = self.lower.take_values();
        self.values.clear();
        self.values.resize(self.full.row_idx().len(), 0.0);
        for (p, &v) in lower.iter().enumerate() {
            self.values[self.at[p]] = v;
            if self.mirror[p] != usize::MAX {
                self.values[self.mirror[p]] = v;
            }
        }
        drop(lower);
        self.inverse_diagonal.clear();
        for (e, &d) in self.diagonal.iter().enumerate() {
            let k = if d == usize::MAX { 0.0 } else { self.values[d] };
            if !(k > 0.0 && k.is_finite()) {
                return Err(LinearFailure::NotPositiveDefinite { equation: Some(e) });
            }
            self.inverse_diagonal.push(1.0 / k);
        }
        self.prepared = Some(states.to_vec());
        let dt = t.elapsed().as_secs_f64();
        self.stats.preparations += 1;
        self.stats.prepare_seconds += dt;
        self.stats.first_prepare_seconds.get_or_insert(dt);
        Ok(Method::Factorization)
    }

    fn solve_in_place(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        guess: Option<&[f64]>,
    ) -> Result<Outcome, LinearFailure> {
        let method = self.prepare(states)?;
        self.check_stop()?;
        let t = Instant::now();
        let n = rhs.len();
        assert_eq!(n, self.inverse_diagonal.len(), "right-hand side of another size");
        let b = rhs.to_vec();
        let mut x = match guess {
            Some(g) => {
                assert_eq!(g.len(), n, "initial guess of another size");
                g.to_vec()
            }
            None => vec![0.0; n],
        };
        let cap = self
            .max_iterations
            .unwrap_or_else(|| n.saturating_mul(10).max(100));
        let mut done = 0usize;
        let result = self.iterate(&b, &mut x, cap, &mut done);
        self.stats.solve_seconds += t.elapsed().as_secs_f64();
        // The cost model: per iteration one product with the matrix and a few
        // vector operations.
        let per_iteration = 2.0 * self.values.len() as f64 + 12.0 * n as f64;
        let iterations = match &result {
            Ok(it) => it.count,
            Err(LinearFailure::NotConverged { iterations, .. }) => *iterations,
            Err(_) => done,
        };
        self.stats.iterations += iterations;
        self.stats.flops += per_iteration * iterations as f64;
        let iterations = result?;
        rhs.copy_from_slice(&x);
        Ok(Outcome {
            method,
            iterations: Some(iterations),
            complete: true,
        })
    }

    fn set_stop(&mut self, stop: &'a AtomicUsize) {
        self.stop = Some(stop);
    }

    fn forget(&mut self) {
        self.prepared = None;
    }

    fn release(&mut self) {
        self.prepared = None;
        self.values = Vec::new();
        self.inverse_diagonal = Vec::new();
    }

    fn is_prepared(&self) -> bool {
        self.prepared.is_some()
    }

    fn starts_from_guess(&self) -> bool {
        true
    }

    fn statistics(&self) -> Statistics {
        self.stats
    }
}
