//! [`PetscSolver`]: one PETSc linear solver for a problem's fixed pattern,
//! behind cfe's seam ([`Analyse`], [`LinearSolver`]).
//!
//! **The matrix.** PETSc's matrix holds every DOF of the model, node after node
//! (`D::N` a node: block size 2 or 3, so that GAMG aggregates nodes and the
//! rigid-body modes line up with its blocks); a prescribed DOF's row and column
//! are empty but for a diagonal entry (the mean of the free diagonal, so it
//! does not spoil the scaling), its right-hand side and solution zero. The free
//! equations' entries are cfe's own assembly of `K(states)` (the parts and the
//! coupling elements in their states: [`Stiffness::assemble`], as the other
//! back ends), scattered into a fixed compressed-row layout built once from
//! the lower pattern, which PETSc is given exactly as its preallocation.
//!
//! **CG + GAMG** (`petsc`). Conjugate gradients on the unpreconditioned
//! residual (so the tolerance is `‖b − K x‖ ≤ rtol ‖b‖`, checked again on the
//! true residual after each solve), GAMG with the rigid-body modes of the node
//! coordinates as near-null space (`MatNullSpaceCreateRigidBody`). A solve
//! starts from the caller's guess (the last pattern's solution). The
//! preconditioner is built with the first states and kept across the active-set
//! and Coulomb iterations while it works: **it is rebuilt at the next
//! preparation once a solve with the kept preconditioner took more than twice
//! the iterations of the first solve after it was built (and more than 10), and
//! at once — the solve repeated — when a solve with a kept preconditioner did
//! not converge**.
//!
//! **MUMPS** (`petsc-mumps`). KSPPREONLY + PCCHOLESKY with MUMPS: a numeric
//! factorization for each new set of states.
//!
//! User options (`-ksp_*`, `-pc_*`, `-mat_mumps_*`, an options file) are read
//! by `KSPSetFromOptions` after these defaults, from the back end's own
//! database, so they override them.

use crate::ffi::{self, PetscInt};
use crate::{Error, Petsc, Result, comm, session};
use cfe::assembly::{FIXED, NodeGraph, Stiffness};
use cfe::coupling::{PairState, PairStates};
use cfe::dim::D2;
use cfe::fem::ElementFamily;
use cfe::solve::backend::{
    Analyse, Iterations, LinearFailure, LinearSolver, Outcome, Problem, Statistics,
};
use cfe::solve::system::Method;
use std::ffi::{CStr, CString, c_char};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// The relative residual `‖b − K x‖ / ‖b‖` CG stops at unless told otherwise.
/// Measured on the seed example (c_n = 1e9 against E = 2.1e5) refined 1 to 8
/// times: at 1e-8 every run ends on the direct solver's pair states, with pair
/// forces within 1.4e-8 of its and an equilibrium error below 1e-10; 1e-10 (the
/// `cg` back end's) is below the true residual the penalty lets CG reach
/// (1.0e-10 to 2.5e-10 once refined), so those runs fail.
pub const DEFAULT_TOLERANCE: f64 = 1e-8;

/// Restarts from the iterate allowed when the true residual is above the
/// tolerance the recursively updated one met.
const MAX_RESTARTS: usize = 2;

/// Which PETSc solver.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// KSPCG + PCGAMG with the rigid-body near-null space.
    CgGamg,
    /// KSPPREONLY + PCCHOLESKY by MUMPS.
    Mumps,
}

/// The PETSc objects of a solver, destroyed together under the lock.
struct Objects {
    mat: ffi::Mat,
    ksp: ffi::KSP,
    b: ffi::Vec,
    x: ffi::Vec,
    work: ffi::Vec,
    near_null: ffi::MatNullSpace,
    options: ffi::PetscOptions,
}

impl Objects {
    fn null() -> Objects {
        let null = std::ptr::null_mut();
        Objects {
            mat: null,
            ksp: null,
            b: null,
            x: null,
            work: null,
            near_null: null,
            options: null,
        }
    }
}

impl Drop for Objects {
    fn drop(&mut self) {
        let Ok(_s) = session() else { return };
        // SAFETY: each object is null or made by this solver, destroyed once
        // (PETSc's destroy functions accept null and null the handle).
        unsafe {
            ffi::KSPDestroy(&mut self.ksp);
            ffi::MatNullSpaceDestroy(&mut self.near_null);
            ffi::MatDestroy(&mut self.mat);
            ffi::VecDestroy(&mut self.b);
            ffi::VecDestroy(&mut self.x);
            ffi::VecDestroy(&mut self.work);
            if !self.options.is_null() {
                ffi::PetscOptionsDestroy(&mut self.options);
            }
        }
    }
}

/// A PETSc solver of `K(states)` for one problem's pattern.
pub struct PetscSolver<'a, D: ElementFamily = D2> {
    problem: Problem<'a, D>,
    kind: Kind,
    /// The lower pattern over the free equations (cfe's assembly fills it).
    lower: Stiffness,
    /// The whole matrix over every DOF, compressed rows (sorted columns).
    row_ptr: Vec<usize>,
    cols: Vec<PetscInt>,
    values: Vec<f64>,
    /// Position in `values` of each stored lower entry, and of its mirror
    /// (`usize::MAX` on the diagonal).
    at: Vec<usize>,
    mirror: Vec<usize>,
    /// Position in `values` of each prescribed DOF's diagonal entry.
    fixed_diagonal: Vec<usize>,
    /// The DOF of each free equation.
    eq_dof: Vec<usize>,
    objects: Objects,
    /// The states the matrix holds.
    prepared: Option<PairStates>,
    /// Whether a preconditioner (or factorization) has been built.
    built: bool,
    /// Iterations of the first solve after the preconditioner was built.
    fresh_iterations: Option<usize>,
    /// Rebuild the preconditioner at the next preparation.
    rebuild: bool,
    tolerance: f64,
    stop: Option<&'a AtomicUsize>,
    stats: Statistics,
}

/// `n` as a `PetscInt`, or [`Error::TooLarge`] naming `what`.
fn petsc_int(n: usize, what: &str) -> Result<PetscInt> {
    PetscInt::try_from(n).map_err(|_| {
        Error::TooLarge(format!(
            "{n} {what} do not fit the 32-bit indices of this PETSc (at most {}); use a PETSc built with 64-bit indices",
            PetscInt::MAX
        ))
    })
}

/// `name` as a C string (a fixed type name, without NUL).
fn c(name: &str) -> CString {
    CString::new(name).expect("no NUL in a PETSc type name")
}

/// The failure of a PETSc call during a solve, for the seam (the message is in
/// [`PetscSolver::last_error`]).
fn failure(e: &Error) -> LinearFailure {
    match e {
        Error::Call { function, code, .. } => LinearFailure::BackEnd {
            function,
            code: *code,
        },
        _ => LinearFailure::BackEnd {
            function: "cfe-petsc",
            code: -1,
        },
    }
}

impl<'a, D: ElementFamily> PetscSolver<'a, D> {
    /// The solver `kind` for `problem`'s pattern with `config`'s options: the
    /// layout of the whole matrix, the matrix preallocated exactly, the
    /// near-null space (CG + GAMG) and the KSP set up from the defaults and then
    /// the options.
    pub fn new(problem: Problem<'a, D>, kind: Kind, config: &Petsc) -> Result<Self> {
        let Problem {
            parts,
            interfaces,
            dofs,
        } = problem;
        let graph = NodeGraph::new(parts, interfaces, dofs);
        let lower = Stiffness::new(parts, dofs, &graph);
        drop(graph);
        let n_dofs = dofs.eq.len();
        let n = petsc_int(n_dofs, "DOFs")?;
        let mut eq_dof = vec![0usize; dofs.n_eq];
        for (d, &e) in dofs.eq.iter().enumerate() {
            if e != FIXED {
                eq_dof[e] = d;
            }
        }
        // Row counts: each lower entry in its row and its mirror's; a
        // prescribed DOF its diagonal.
        let nnz = lower.row_idx.len();
        let mut count = vec![0usize; n_dofs + 1];
        for j in 0..dofs.n_eq {
            for &i in &lower.row_idx[lower.col_ptr[j]..lower.col_ptr[j + 1]] {
                count[eq_dof[j] + 1] += 1;
                if i as usize != j {
                    count[eq_dof[i as usize] + 1] += 1;
                }
            }
        }
        for (d, &e) in dofs.eq.iter().enumerate() {
            if e == FIXED {
                count[d + 1] += 1;
            }
        }
        let per_row: Vec<PetscInt> = count[1..]
            .iter()
            .map(|&c| petsc_int(c, "entries in a row"))
            .collect::<Result<_>>()?;
        for d in 0..n_dofs {
            count[d + 1] += count[d];
        }
        petsc_int(count[n_dofs], "matrix entries")?;
        let row_ptr = count;
        let mut next = row_ptr[..n_dofs].to_vec();
        let mut cols = vec![0 as PetscInt; row_ptr[n_dofs]];
        let (mut at, mut mirror) = (vec![0usize; nnz], vec![usize::MAX; nnz]);
        let mut fixed_diagonal = Vec::with_capacity(dofs.fixed.len());
        // Equations follow the DOFs' order: row r of the whole matrix gets the
        // columns of the rows before it (ascending) before its own lower ones
        // (ascending), its diagonal first among those: sorted.
        for (d, &e) in dofs.eq.iter().enumerate() {
            if e == FIXED {
                fixed_diagonal.push(next[d]);
                cols[next[d]] = d as PetscInt;
                next[d] += 1;
                continue;
            }
            let j = e;
            for p in lower.col_ptr[j]..lower.col_ptr[j + 1] {
                let i = lower.row_idx[p] as usize;
                let di = eq_dof[i];
                at[p] = next[d];
                cols[next[d]] = di as PetscInt;
                next[d] += 1;
                if i != j {
                    mirror[p] = next[di];
                    cols[next[di]] = d as PetscInt;
                    next[di] += 1;
                }
            }
        }
        let mut solver = PetscSolver {
            problem,
            kind,
            lower,
            values: vec![0.0; row_ptr[n_dofs]],
            row_ptr,
            cols,
            at,
            mirror,
            fixed_diagonal,
            eq_dof,
            objects: Objects::null(),
            prepared: None,
            built: false,
            fresh_iterations: None,
            rebuild: false,
            tolerance: config.tolerance,
            stop: None,
            stats: Statistics {
                matrix_nnz: nnz,
                ..Statistics::default()
            },
        };
        solver.create(n, &per_row, config)?;
        Ok(solver)
    }

    /// The PETSc objects: matrix, vectors, near-null space, KSP.
    fn create(&mut self, n: PetscInt, per_row: &[PetscInt], config: &Petsc) -> Result<()> {
        let mut s = session()?;
        let o = &mut self.objects;
        o.options = crate::options_database(&s, &config.options, config.options_file.as_ref())?;
        s.push(o.options)?;
        let bs = D::N as PetscInt;
        call!(MatCreate(comm(), &mut o.mat))?;
        call!(MatSetSizes(o.mat, n, n, n, n))?;
        call!(MatSetType(o.mat, c("seqaij").as_ptr()))?;
        call!(MatSetBlockSize(o.mat, bs))?;
        call!(MatSeqAIJSetPreallocation(o.mat, 0, per_row.as_ptr()))?;
        for v in [&mut o.b, &mut o.x, &mut o.work] {
            call!(VecCreateSeq(comm(), n, v))?;
            call!(VecSetBlockSize(*v, bs))?;
        }
        // The rigid-body modes of the node coordinates (in `work`, then zeroed
        // by its next use).
        {
            let Problem { parts, dofs, .. } = self.problem;
            let mut a: *mut f64 = std::ptr::null_mut();
            call!(VecGetArray(o.work, &mut a))?;
            // SAFETY: PETSc's array of the vector's n entries.
            let coords = unsafe { std::slice::from_raw_parts_mut(a, n as usize) };
            for (p, part) in parts.iter().enumerate() {
                for (i, x) in part.mesh.nodes.iter().enumerate() {
                    let g = dofs.node_offset[p] + i;
                    coords[D::dof(g, 0)..D::dof(g, 0) + D::N].copy_from_slice(x.as_ref());
                }
            }
            call!(VecRestoreArray(o.work, &mut a))?;
            call!(MatNullSpaceCreateRigidBody(o.work, &mut o.near_null))?;
            call!(MatSetNearNullSpace(o.mat, o.near_null))?;
        }
        call!(KSPCreate(comm(), &mut o.ksp))?;
        call!(KSPSetOperators(o.ksp, o.mat, o.mat))?;
        let mut pc = std::ptr::null_mut();
        call!(KSPGetPC(o.ksp, &mut pc))?;
        match self.kind {
            Kind::CgGamg => {
                call!(KSPSetType(o.ksp, c("cg").as_ptr()))?;
                call!(PCSetType(pc, c("gamg").as_ptr()))?;
                call!(KSPSetNormType(o.ksp, ffi::KSP_NORM_UNPRECONDITIONED))?;
                let default = ffi::PETSC_DEFAULT as f64;
                call!(KSPSetTolerances(
                    o.ksp,
                    self.tolerance,
                    default,
                    default,
                    ffi::PETSC_DEFAULT
                ))?;
            }
            Kind::Mumps => {
                call!(KSPSetType(o.ksp, c("preonly").as_ptr()))?;
                call!(PCSetType(pc, c("cholesky").as_ptr()))?;
                call!(PCFactorSetMatSolverType(pc, c("mumps").as_ptr()))?;
            }
        }
        call!(KSPSetFromOptions(o.ksp))?;
        let (mut rtol, mut abstol, mut dtol, mut maxits) = (0.0, 0.0, 0.0, 0);
        call!(KSPGetTolerances(
            o.ksp,
            &mut rtol,
            &mut abstol,
            &mut dtol,
            &mut maxits
        ))?;
        self.tolerance = rtol;
        Ok(())
    }

    /// The relative residual CG stops at (after the options).
    pub fn tolerance(&self) -> f64 {
        self.tolerance
    }

    /// The preconditioner's PETSc type (`gamg`, `cholesky`; another if the
    /// options chose it), with MUMPS named.
    pub fn preconditioner_name(&self) -> String {
        let Ok(_s) = session() else {
            return String::new();
        };
        let mut pc = std::ptr::null_mut();
        let mut name: *const c_char = std::ptr::null();
        if call!(KSPGetPC(self.objects.ksp, &mut pc)).is_err()
            || call!(PCGetType(pc, &mut name)).is_err()
            || name.is_null()
        {
            return String::new();
        }
        // SAFETY: PETSc's static type name.
        let name = unsafe { CStr::from_ptr(name) }
            .to_string_lossy()
            .into_owned();
        match self.kind {
            Kind::Mumps => format!("{name} (mumps)"),
            Kind::CgGamg => name,
        }
    }

    /// `Err(Stopped)` once the stop flag is nonzero.
    fn check_stop(&self) -> std::result::Result<(), LinearFailure> {
        match self.stop.map_or(0, |s| s.load(Ordering::Relaxed)) {
            0 => Ok(()),
            signal => Err(LinearFailure::Stopped(signal)),
        }
    }

    /// Assembles `K(states)` into PETSc's matrix (cfe's assembly, scattered
    /// into the whole matrix's layout, handed over row by row).
    fn assemble(&mut self, states: &[Vec<PairState>]) -> Result<()> {
        let Problem {
            parts,
            interfaces,
            dofs,
        } = self.problem;
        self.lower.assemble(parts, interfaces, states, dofs);
        let lower = self.lower.take_values();
        for (p, &v) in lower.iter().enumerate() {
            self.values[self.at[p]] = v;
            if self.mirror[p] != usize::MAX {
                self.values[self.mirror[p]] = v;
            }
        }
        // The prescribed DOFs' diagonal: the mean of the free one.
        let free: f64 = (0..dofs.n_eq)
            .map(|e| lower[self.lower.col_ptr[e]])
            .sum::<f64>();
        let mean = if dofs.n_eq > 0 {
            free / dofs.n_eq as f64
        } else {
            1.0
        };
        drop(lower);
        for &p in &self.fixed_diagonal {
            self.values[p] = mean;
        }
        let _s = session()?;
        let mat = self.objects.mat;
        for r in 0..self.row_ptr.len() - 1 {
            let (start, end) = (self.row_ptr[r], self.row_ptr[r + 1]);
            let row = r as PetscInt;
            call!(MatSetValues(
                mat,
                1,
                &row,
                (end - start) as PetscInt,
                self.cols[start..end].as_ptr(),
                self.values[start..end].as_ptr(),
                ffi::INSERT_VALUES
            ))?;
        }
        call!(MatAssemblyBegin(mat, ffi::MAT_FINAL_ASSEMBLY))?;
        call!(MatAssemblyEnd(mat, ffi::MAT_FINAL_ASSEMBLY))?;
        Ok(())
    }

    /// The preconditioner (or factorization) for the assembled matrix: built
    /// anew (`rebuild`) or kept.
    fn set_up(&mut self, rebuild: bool) -> Result<()> {
        let mut s = session()?;
        s.push(self.objects.options)?;
        let keep = if rebuild {
            ffi::PETSC_FALSE
        } else {
            ffi::PETSC_TRUE
        };
        call!(KSPSetReusePreconditioner(self.objects.ksp, keep))?;
        call!(KSPSetUp(self.objects.ksp))
    }

    /// One KSP solve of `rhs` (free equations) from `guess`, into `rhs`'s
    /// place in `x`: the iterations, PETSc's converged reason and the true
    /// relative residual.
    fn ksp_solve(&mut self, rhs: &[f64], guess: Option<&[f64]>) -> Result<(usize, i32, f64)> {
        let mut s = session()?;
        s.push(self.objects.options)?;
        let o = &self.objects;
        let n = self.row_ptr.len() - 1;
        let scatter = |v: ffi::Vec, from: Option<&[f64]>| -> Result<()> {
            let mut a: *mut f64 = std::ptr::null_mut();
            call!(VecGetArray(v, &mut a))?;
            // SAFETY: PETSc's array of the vector's n entries.
            let all = unsafe { std::slice::from_raw_parts_mut(a, n) };
            all.fill(0.0);
            if let Some(from) = from {
                for (e, &d) in self.eq_dof.iter().enumerate() {
                    all[d] = from[e];
                }
            }
            call!(VecRestoreArray(v, &mut a))
        };
        scatter(o.b, Some(rhs))?;
        let warm = guess.is_some() && self.kind == Kind::CgGamg;
        scatter(o.x, guess.filter(|_| warm))?;
        let nonzero = if warm {
            ffi::PETSC_TRUE
        } else {
            ffi::PETSC_FALSE
        };
        call!(KSPSetInitialGuessNonzero(o.ksp, nonzero))?;
        call!(KSPSolve(o.ksp, o.b, o.x))?;
        let (mut its, mut reason) = (0, 0);
        call!(KSPGetIterationNumber(o.ksp, &mut its))?;
        call!(KSPGetConvergedReason(o.ksp, &mut reason))?;
        // The true residual b − K x.
        call!(MatMult(o.mat, o.x, o.work))?;
        let (mut kx, mut b): (*const f64, *const f64) = (std::ptr::null(), std::ptr::null());
        call!(VecGetArrayRead(o.work, &mut kx))?;
        call!(VecGetArrayRead(o.b, &mut b))?;
        // SAFETY: PETSc's arrays of the vectors' n entries, read only.
        let (kx_s, b_s) = unsafe {
            (
                std::slice::from_raw_parts(kx, n),
                std::slice::from_raw_parts(b, n),
            )
        };
        let (mut r2, mut b2) = (0.0, 0.0);
        for (k, b) in kx_s.iter().zip(b_s) {
            r2 += (b - k) * (b - k);
            b2 += b * b;
        }
        call!(VecRestoreArrayRead(o.work, &mut kx))?;
        call!(VecRestoreArrayRead(o.b, &mut b))?;
        let relative = if b2 > 0.0 {
            (r2 / b2).sqrt()
        } else {
            r2.sqrt()
        };
        Ok((its.max(0) as usize, reason, relative))
    }

    /// The solution in `x` at the free equations, into `out`.
    fn gather(&self, out: &mut [f64]) -> Result<()> {
        let _s = session()?;
        let n = self.row_ptr.len() - 1;
        let mut a: *const f64 = std::ptr::null();
        call!(VecGetArrayRead(self.objects.x, &mut a))?;
        // SAFETY: PETSc's array of the vector's n entries, read only.
        let all = unsafe { std::slice::from_raw_parts(a, n) };
        for (e, &d) in self.eq_dof.iter().enumerate() {
            out[e] = all[d];
        }
        call!(VecRestoreArrayRead(self.objects.x, &mut a))
    }

    /// For each vector of the near-null space GAMG is given (the rigid-body
    /// modes: 3 in 2D, 6 in 3D), `‖K r‖ / (‖K‖_F ‖r‖)` with `K = K(states)`
    /// assembled: zero to round-off when the modes are exact rigid motions of
    /// the model (no DOF prescribed).
    pub fn rigid_mode_residuals(&mut self, states: &[Vec<PairState>]) -> Result<Vec<f64>> {
        self.assemble(states)?;
        self.prepared = None;
        let norm_k = self.values.iter().map(|v| v * v).sum::<f64>().sqrt();
        let _s = session()?;
        let o = &self.objects;
        let n = self.row_ptr.len() - 1;
        let (mut has_const, mut count, mut vecs) = (0, 0, std::ptr::null());
        call!(MatNullSpaceGetVecs(
            o.near_null,
            &mut has_const,
            &mut count,
            &mut vecs
        ))?;
        // SAFETY: PETSc's array of the space's `count` vectors.
        let vecs = unsafe { std::slice::from_raw_parts(vecs, count as usize) };
        let mut out = Vec::with_capacity(vecs.len());
        for &r in vecs {
            call!(MatMult(o.mat, r, o.work))?;
            let norm = |v: ffi::Vec| -> Result<f64> {
                let mut a: *const f64 = std::ptr::null();
                call!(VecGetArrayRead(v, &mut a))?;
                // SAFETY: as above, n entries, read only.
                let s = unsafe { std::slice::from_raw_parts(a, n) };
                let norm = s.iter().map(|x| x * x).sum::<f64>().sqrt();
                call!(VecRestoreArrayRead(v, &mut a))?;
                Ok(norm)
            };
            out.push(norm(o.work)? / (norm_k * norm(r)?));
        }
        Ok(out)
    }

    /// The failure of a solve whose KSP ended with `reason` < 0.
    fn diverged(&self, reason: i32, its: usize, relative: f64) -> LinearFailure {
        match reason {
            ffi::KSP_DIVERGED_INDEFINITE_PC
            | ffi::KSP_DIVERGED_INDEFINITE_MAT
            | ffi::KSP_DIVERGED_PC_FAILED => LinearFailure::NotPositiveDefinite { equation: None },
            _ => LinearFailure::NotConverged {
                iterations: its,
                relative_residual: relative,
                tolerance: self.tolerance,
            },
        }
    }
}

impl<'a, D: ElementFamily> Analyse<'a, D> for PetscSolver<'a, D> {
    /// CG + GAMG without options ([`Petsc::default`]).
    fn analyse(problem: Problem<'a, D>) -> cfe::Result<Self> {
        Ok(PetscSolver::new(problem, Kind::CgGamg, &Petsc::default())?)
    }
}

impl<'a, D: ElementFamily> LinearSolver<'a> for PetscSolver<'a, D> {
    /// Assembles `K(states)`; builds the preconditioner (MUMPS: factorizes)
    /// when there is none, when the rule of the module says so, or always
    /// (MUMPS): [`Method::Factorization`]; else keeps it ([`Method::Reuse`]).
    fn prepare(&mut self, states: &[Vec<PairState>]) -> std::result::Result<Method, LinearFailure> {
        if self.prepared.as_deref() == Some(states) {
            return Ok(Method::Reuse);
        }
        self.check_stop()?;
        let t = Instant::now();
        self.prepared = None;
        self.assemble(states).map_err(|e| failure(&e))?;
        let rebuild = self.kind == Kind::Mumps || !self.built || self.rebuild;
        self.set_up(rebuild).map_err(|e| failure(&e))?;
        self.prepared = Some(states.to_vec());
        let dt = t.elapsed().as_secs_f64();
        self.stats.prepare_seconds += dt;
        if rebuild {
            self.built = true;
            self.rebuild = false;
            self.fresh_iterations = None;
            self.stats.preparations += 1;
            self.stats.first_prepare_seconds.get_or_insert(dt);
            Ok(Method::Factorization)
        } else {
            Ok(Method::Reuse)
        }
    }

    fn solve_in_place(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        guess: Option<&[f64]>,
    ) -> std::result::Result<Outcome, LinearFailure> {
        assert_eq!(
            rhs.len(),
            self.eq_dof.len(),
            "right-hand side of another size"
        );
        let mut method = self.prepare(states)?;
        self.check_stop()?;
        let t = Instant::now();
        let b = rhs.to_vec();
        let mut start: Option<Vec<f64>> = guess.map(<[f64]>::to_vec);
        let (mut total, mut restarts, mut retried) = (0usize, 0usize, false);
        let result = loop {
            let fresh = self.fresh_iterations.is_none();
            let (its, reason, relative) = self
                .ksp_solve(&b, start.as_deref())
                .map_err(|e| failure(&e))?;
            total += its;
            if fresh {
                self.fresh_iterations = Some(its);
            }
            if self.kind == Kind::Mumps {
                break if reason < 0 {
                    Err(self.diverged(reason, total, relative))
                } else {
                    Ok(None)
                };
            }
            if reason < 0 {
                if reason == ffi::KSP_DIVERGED_ITS && !fresh && !retried {
                    // A kept preconditioner that no longer serves: build it
                    // for these states and solve again from the guess.
                    retried = true;
                    self.rebuild = true;
                    self.prepared = None;
                    method = self.prepare(states)?;
                    continue;
                }
                break Err(self.diverged(reason, total, relative));
            }
            if relative <= self.tolerance {
                break Ok(Some(relative));
            }
            if restarts == MAX_RESTARTS {
                break Err(LinearFailure::NotConverged {
                    iterations: total,
                    relative_residual: relative,
                    tolerance: self.tolerance,
                });
            }
            // The recursive residual met the tolerance, the true one did not:
            // go on from the iterate.
            restarts += 1;
            let mut x = vec![0.0; b.len()];
            self.gather(&mut x).map_err(|e| failure(&e))?;
            start = Some(x);
        };
        if let Some(fresh) = self.fresh_iterations
            && total > (2 * fresh).max(10)
        {
            self.rebuild = true;
        }
        self.stats.iterations += total;
        self.stats.solve_seconds += t.elapsed().as_secs_f64();
        let relative = result?;
        self.gather(rhs).map_err(|e| failure(&e))?;
        Ok(Outcome {
            method,
            iterations: relative.map(|relative_residual| Iterations {
                count: total,
                relative_residual,
            }),
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
    }

    fn is_prepared(&self) -> bool {
        self.prepared.is_some()
    }

    fn starts_from_guess(&self) -> bool {
        self.kind == Kind::CgGamg
    }

    fn statistics(&self) -> Statistics {
        self.stats
    }
}
