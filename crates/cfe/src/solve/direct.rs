//! The supernodal Cholesky behind the linear-solver seam ([`super::backend`]):
//! [`Cholesky`] is the [`ContactSystem`] (factorization, low-rank updates,
//! restricted and refined solves) with the problem it solves, so that each
//! call of the seam forwards to the same call of the system, nothing copied.

use super::backend::{
    Analyse, LinearFailure, LinearSolver, LowRankUpdate, Outcome, PairFlexibility, Problem, RefinedSolve,
    Residual, RestrictedSolve, Statistics,
};
use super::system::{ContactSystem, Method, Solve, UpdatePolicy};
use crate::coupling::PairState;
use crate::dim::D2;
use crate::fem::ElementFamily;
use std::sync::atomic::AtomicUsize;

/// The direct back end: today's supernodal Cholesky with its low-rank updates,
/// restricted solves and refinement, for one problem.
pub struct Cholesky<'a, D: ElementFamily = D2> {
    problem: Problem<'a, D>,
    system: ContactSystem<'a, D>,
}

impl<'a, D: ElementFamily> Cholesky<'a, D> {
    /// The back end of `problem` around an existing contact system (built for
    /// the same parts, interfaces and DOFs).
    pub fn with_system(problem: Problem<'a, D>, system: ContactSystem<'a, D>) -> Self {
        Cholesky { problem, system }
    }

    /// The contact system (its counters and tuning).
    pub fn system(&self) -> &ContactSystem<'a, D> {
        &self.system
    }

    /// The contact system, to tune it.
    pub fn system_mut(&mut self) -> &mut ContactSystem<'a, D> {
        &mut self.system
    }
}

impl<'a, D: ElementFamily> Analyse<'a, D> for Cholesky<'a, D> {
    /// The node graph, the nested-dissection ordering, the pattern in the
    /// elimination order and the symbolic factorization
    /// (`super::setup::pattern_and_symbolic`).
    fn analyse(problem: Problem<'a, D>) -> crate::error::Result<Self> {
        let (k, chol) =
            super::setup::pattern_and_symbolic(problem.parts, problem.interfaces, problem.dofs, None)?;
        Ok(Cholesky {
            problem,
            system: ContactSystem::new(problem.parts, k, chol),
        })
    }
}

impl<'a, D: ElementFamily> LinearSolver<'a> for Cholesky<'a, D> {
    fn prepare(&mut self, states: &[Vec<PairState>]) -> Result<Method, LinearFailure> {
        let Problem {
            interfaces, dofs, ..
        } = self.problem;
        Ok(self.system.factorize(interfaces, dofs, states)?)
    }

    fn solve_in_place(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        _guess: Option<&[f64]>,
    ) -> Result<Outcome, LinearFailure> {
        let Problem {
            interfaces, dofs, ..
        } = self.problem;
        let method = self.system.solve(interfaces, dofs, states, rhs)?;
        Ok(Outcome::direct(method))
    }

    fn set_stop(&mut self, stop: &'a AtomicUsize) {
        self.system.set_stop(stop);
    }

    fn forget(&mut self) {
        self.system.invalidate();
    }

    fn forget_right_hand_side(&mut self) {
        self.system.forget_right_hand_side();
    }

    fn release(&mut self) {
        self.system.release();
    }

    fn is_prepared(&self) -> bool {
        self.system.has_factor()
    }

    fn keep_pattern(&mut self, keep: bool) {
        self.system.keep_pattern = keep;
    }

    fn statistics(&self) -> Statistics {
        let s = &self.system;
        Statistics {
            matrix_nnz: s.matrix_nnz(),
            factor_nnz: s.factor_nnz(),
            factor_flops: s.factor_flops(),
            preparations: s.factorizations,
            updates: s.updates,
            iterations: 0,
            flops: s.flops,
            prepare_seconds: s.factor_seconds,
            first_prepare_seconds: s.first_factor_seconds,
            solve_seconds: s.solve_seconds,
        }
    }

    fn take_pattern_seconds(&mut self) -> f64 {
        std::mem::take(&mut self.system.pattern_seconds)
    }

    fn restricted(&mut self) -> Option<&mut dyn RestrictedSolve> {
        Some(self)
    }

    fn refinement(&mut self) -> Option<&mut dyn RefinedSolve> {
        Some(self)
    }

    fn low_rank(&mut self) -> Option<&mut dyn LowRankUpdate> {
        Some(self)
    }

    fn flexibility(&mut self) -> Option<&mut dyn PairFlexibility> {
        Some(self)
    }
}

impl<D: ElementFamily> PairFlexibility for Cholesky<'_, D> {
    /// [`ContactSystem::pair_flexibility`].
    fn pair_flexibility(&mut self, states: &[Vec<PairState>], pairs: &[(usize, usize)]) -> Option<Vec<f64>> {
        let Problem {
            interfaces, dofs, ..
        } = self.problem;
        self.system.pair_flexibility(interfaces, dofs, states, pairs)
    }
}

impl<D: ElementFamily> RestrictedSolve for Cholesky<'_, D> {
    fn solve_interface(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        rhs_on_interface: bool,
    ) -> Result<Outcome, LinearFailure> {
        let Problem {
            interfaces, dofs, ..
        } = self.problem;
        let (method, complete) =
            self.system
                .solve_interface(interfaces, dofs, states, rhs, rhs_on_interface)?;
        Ok(Outcome {
            method,
            iterations: None,
            complete,
        })
    }

    fn solve_pair_forces(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
    ) -> Result<Outcome, LinearFailure> {
        let Problem {
            interfaces, dofs, ..
        } = self.problem;
        let method = self
            .system
            .solve_pair_forces(interfaces, dofs, states, rhs)?;
        Ok(Outcome::direct(method))
    }
}

impl<D: ElementFamily> RefinedSolve for Cholesky<'_, D> {
    /// [`ContactSystem::solve_unrefined`], and for a low-rank update the
    /// residual at the coupling equations and [`ContactSystem::refine`].
    fn solve_refined(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        read: &[usize],
        residual: Residual<'_>,
    ) -> Result<Outcome, LinearFailure> {
        let Problem {
            interfaces, dofs, ..
        } = self.problem;
        let method = match self
            .system
            .solve_unrefined(interfaces, dofs, states, rhs, read)?
        {
            Solve::Complete(method) => method,
            Solve::Unrefined(unrefined) => {
                residual(rhs);
                self.system.refine(unrefined, rhs)
            }
        };
        Ok(Outcome::direct(method))
    }
}

impl<D: ElementFamily> LowRankUpdate for Cholesky<'_, D> {
    fn set_policy(&mut self, policy: UpdatePolicy) {
        self.system.policy = policy;
    }
}
