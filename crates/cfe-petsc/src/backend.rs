//! [`PetscSolver`]: one PETSc linear solver for a problem's fixed pattern,
//! behind cfe's seam ([`Analyse`], [`LinearSolver`]).
//!
//! **The matrix.** PETSc's matrix (AIJ: sequential on one rank, MPIAIJ on
//! several) holds every DOF of the model, node after node (`D::N` a node:
//! block size 2 or 3, so that GAMG aggregates nodes and the rigid-body modes
//! line up with its blocks), in the node order of a [`Partition`]: each rank
//! owns the rows of a contiguous range of nodes. A prescribed DOF's row and
//! column hold zeros but for a diagonal entry (the mean of the free diagonal,
//! so it does not spoil the scaling), its right-hand side and solution zero.
//! Each rank adds the stiffness of its own part elements and coupling
//! elements (cfe's element routines, [`ElementSource::stiffness`]) with
//! `MatSetValues(ADD_VALUES)`; entries of rows another rank owns travel in
//! PETSc's assembly. The pattern — every node pair an element or a coupling
//! element in any state joins, from cfe's [`NodeGraph`] — is preallocated
//! exactly and inserted (as zeros) once, so it never changes. The parts'
//! stiffness is assembled once into a second matrix of that pattern; each new
//! set of pair states copies it (`MatCopy`) and adds the coupling elements.
//!
//! **The solution on every rank.** Every rank runs the same contact scheme on
//! the whole model (replicated), so each needs the whole solution: the
//! right-hand side's owned entries are set from the caller's (replicated)
//! vector, and after the solve the distributed solution is gathered on every
//! rank (`VecScatterCreateToAll`: the whole vector, 8 bytes per DOF, to every
//! rank, once per solve).
//!
//! **CG + GAMG** (`petsc`). Conjugate gradients on the unpreconditioned
//! residual (so the tolerance is `‖b − K x‖ ≤ rtol ‖b‖`, checked again on the
//! true residual after each solve), GAMG with the rigid-body modes of the node
//! coordinates as near-null space (`MatNullSpaceCreateRigidBody`). A solve
//! starts from the caller's guess (the last pattern's solution) unless its
//! residual is larger than the right-hand side's norm (then from zero). The
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
//! CG + GAMG's options database starts with [`DEFAULT_GAMG_OPTIONS`] (more
//! smoothing on GAMG's levels: about 40 % fewer CG iterations, measured). User options
//! (`-ksp_*`, `-pc_*`, `-mg_*`, `-mat_mumps_*`, an options file) are inserted
//! after them and read by `KSPSetFromOptions` after the defaults set in code,
//! from the back end's own database, so they override both.

use crate::ffi::{self, PetscInt};
use crate::partition::{Partition, node_coordinates};
use crate::{Error, Petsc, Result, comm, session};
use cfe::assembly::{
    CouplingElements, ElementSource, FIXED, NodeGraph, PartElements, SomeElements,
};
use cfe::coupling::{PairState, PairStates};
use cfe::dim::D2;
use cfe::dofs::DofMap;
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

/// The PETSc options cfe gives CG + GAMG before the user's (which, read
/// later, override them): four Chebyshev–Jacobi smoothing steps on each level
/// of GAMG's V-cycle instead of PETSc's two, over a wider part of the
/// spectrum (from 0.05 of the largest eigenvalue estimate instead of 0.1).
/// Measured on one rank (README, "PETSc back end"): about 40 % fewer CG
/// iterations per solve on the seed example refined 4 times (357 → 210) and
/// on the 3D plate on a base (274 → 167 at 1 500 unknowns), the same pair
/// states and about the same CPU time in all (each iteration smooths twice as
/// much): 40 % fewer of CG's global reductions, which bound it across many
/// ranks. A graph threshold (`-pc_gamg_threshold 0.02`) lowers the 2D
/// iterations more (96) but makes the 3D iterations far costlier (coarse
/// grids that barely shrink); SOR smoothing fails on the 2D stick law.
pub const DEFAULT_GAMG_OPTIONS: &str =
    "-mg_levels_ksp_max_it 4 -mg_levels_ksp_chebyshev_esteig 0,0.05,0,1.1";

/// The options of `kind` cfe sets before the user's: [`DEFAULT_GAMG_OPTIONS`]
/// for CG + GAMG, none for MUMPS.
pub fn default_options(kind: Kind) -> &'static str {
    match kind {
        Kind::CgGamg => DEFAULT_GAMG_OPTIONS,
        Kind::Mumps => "",
    }
}

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
    /// `K(states)`, what KSP solves.
    mat: ffi::Mat,
    /// The parts' stiffness alone, in the same pattern.
    parts: ffi::Mat,
    ksp: ffi::KSP,
    b: ffi::Vec,
    x: ffi::Vec,
    work: ffi::Vec,
    /// The whole solution on this rank (sequential) and the scatter filling it.
    all: ffi::Vec,
    to_all: ffi::VecScatter,
    near_null: ffi::MatNullSpace,
    options: ffi::PetscOptions,
}

impl Objects {
    fn null() -> Objects {
        let null = std::ptr::null_mut();
        Objects {
            mat: null,
            parts: null,
            ksp: null,
            b: null,
            x: null,
            work: null,
            all: null,
            to_all: null,
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
            ffi::MatDestroy(&mut self.parts);
            ffi::VecScatterDestroy(&mut self.to_all);
            ffi::VecDestroy(&mut self.all);
            ffi::VecDestroy(&mut self.b);
            ffi::VecDestroy(&mut self.x);
            ffi::VecDestroy(&mut self.work);
            if !self.options.is_null() {
                ffi::PetscOptionsDestroy(&mut self.options);
            }
        }
    }
}

/// A PETSc solver of `K(states)` for one problem's pattern, on every rank of
/// `PETSC_COMM_WORLD` (one without `mpirun`).
pub struct PetscSolver<'a, D: ElementFamily = D2> {
    problem: Problem<'a, D>,
    kind: Kind,
    /// This rank and the number of ranks.
    rank: usize,
    ranks: usize,
    /// The PETSc row of each DOF (`D::N` per node, in the partition's node
    /// order).
    dof_row: Vec<PetscInt>,
    /// The PETSc row of each free equation.
    eq_row: Vec<PetscInt>,
    /// The free equation (or [`FIXED`]) of each row this rank owns, in order.
    local_eq: Vec<usize>,
    /// The coupling elements this rank assembles.
    my_couplings: Vec<usize>,
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

/// The failure of a PETSc call during a solve, for the seam (the function and
/// its error code; the seam's failure carries no message).
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

/// The `n` entries PETSc's `VecGetArray` gave at `a`, as a slice (empty for a
/// rank that owns no rows, whatever the pointer).
///
/// # Safety
/// `a` must point to `n` entries of a vector held by `VecGetArray` until the
/// slice is dropped.
unsafe fn local_array<'x>(a: *mut f64, n: usize) -> &'x mut [f64] {
    if n == 0 || a.is_null() {
        return &mut [];
    }
    // SAFETY: as the caller promises, n > 0 entries at a non-null `a`.
    unsafe { std::slice::from_raw_parts_mut(a, n) }
}

/// Adds the stiffness of the elements of `source` into `mat` at the rows of
/// `dof_row` (free DOFs only: a prescribed DOF's row and column take none),
/// each element matrix made exactly symmetric from its entries `(a, b)` with
/// `eq(a) ≥ eq(b)` (the triangle cfe's own assembly reads).
fn add_elements<D: ElementFamily>(
    mat: ffi::Mat,
    source: &dyn ElementSource,
    dofs: &DofMap<D>,
    dof_row: &[PetscInt],
) -> Result<()> {
    let mut result = Ok(());
    let (mut free, mut rows, mut values) = (Vec::new(), Vec::new(), Vec::new());
    source.for_each_stiffness(&mut |g, k, stride| {
        if result.is_err() {
            return;
        }
        free.clear();
        free.extend((0..g.len()).filter(|&a| dofs.eq[g[a]] != FIXED));
        let m = free.len();
        rows.clear();
        rows.extend(free.iter().map(|&a| dof_row[g[a]]));
        values.clear();
        for &a in &free {
            for &b in &free {
                let v = if dofs.eq[g[a]] >= dofs.eq[g[b]] {
                    k[a * stride + b]
                } else {
                    k[b * stride + a]
                };
                values.push(v);
            }
        }
        result = call!(MatSetValues(
            mat,
            m as PetscInt,
            rows.as_ptr(),
            m as PetscInt,
            rows.as_ptr(),
            values.as_ptr(),
            ffi::ADD_VALUES
        ));
    });
    result
}

/// The stored entries of the lower triangle of K over the free equations
/// (what cfe's own assembly stores), from the node graph.
fn lower_entries<D: ElementFamily>(graph: &NodeGraph, dofs: &DofMap<D>) -> usize {
    let mut count = 0;
    for g in 0..dofs.n_nodes() {
        for &h in graph.neighbours(g) {
            for a in 0..D::N {
                let ea = dofs.eq[D::dof(g, a)];
                if ea == FIXED {
                    continue;
                }
                for b in 0..D::N {
                    let eb = dofs.eq[D::dof(h, b)];
                    count += usize::from(eb != FIXED && eb <= ea);
                }
            }
        }
    }
    count
}

impl<'a, D: ElementFamily> PetscSolver<'a, D> {
    /// The solver `kind` for `problem`'s pattern with `config`'s options, on
    /// every rank: the partition, the matrix preallocated exactly with the
    /// parts' stiffness assembled, the near-null space (CG + GAMG) and the KSP
    /// set up from the defaults and then the options. Collective: every rank
    /// makes it for the same problem.
    pub fn new(problem: Problem<'a, D>, kind: Kind, config: &Petsc) -> Result<Self> {
        let Problem {
            parts,
            interfaces,
            dofs,
        } = problem;
        let (rank, ranks) = crate::world()?;
        let n_dofs = dofs.eq.len();
        petsc_int(n_dofs, "DOFs")?;
        let partition = Partition::new(parts, interfaces, dofs, ranks);
        let dof_row: Vec<PetscInt> = (0..n_dofs)
            .map(|d| (D::N * partition.node_index[d / D::N] + d % D::N) as PetscInt)
            .collect();
        let mut eq_row = vec![0 as PetscInt; dofs.n_eq];
        for (d, &e) in dofs.eq.iter().enumerate() {
            if e != FIXED {
                eq_row[e] = dof_row[d];
            }
        }
        let my_nodes = partition.nodes_of(rank);
        let local_eq: Vec<usize> = my_nodes
            .iter()
            .flat_map(|&g| (0..D::N).map(move |c| D::dof(g, c)))
            .map(|d| dofs.eq[d])
            .collect();
        let my_couplings = Partition::elements_of(&partition.coupling_owner, rank);
        let mut solver = PetscSolver {
            problem,
            kind,
            rank,
            ranks,
            dof_row,
            eq_row,
            local_eq,
            my_couplings,
            objects: Objects::null(),
            prepared: None,
            built: false,
            fresh_iterations: None,
            rebuild: false,
            tolerance: config.tolerance,
            stop: None,
            stats: Statistics::default(),
        };
        solver.create(&partition, &my_nodes, config)?;
        Ok(solver)
    }

    /// This rank and the number of ranks the solver runs on.
    pub fn ranks(&self) -> (usize, usize) {
        (self.rank, self.ranks)
    }

    /// The PETSc objects: the matrices (pattern, then the parts' stiffness),
    /// vectors, near-null space, KSP.
    fn create(&mut self, partition: &Partition, my_nodes: &[usize], config: &Petsc) -> Result<()> {
        let Problem {
            parts,
            interfaces,
            dofs,
        } = self.problem;
        let n = petsc_int(dofs.eq.len(), "DOFs")?;
        let n_local = petsc_int(my_nodes.len() * D::N, "DOFs of a rank")?;
        let (first, end) = (
            partition.node_start[self.rank],
            partition.node_start[self.rank + 1],
        );
        // The pattern: each owned node's row block against its neighbours'.
        let graph = NodeGraph::new(parts, interfaces, dofs);
        self.stats.matrix_nnz = lower_entries(&graph, dofs);
        let (mut d_nnz, mut o_nnz) = (Vec::new(), Vec::new());
        for &g in my_nodes {
            let nb = graph.neighbours(g);
            let inside = nb
                .iter()
                .filter(|&&h| (first..end).contains(&partition.node_index[h]))
                .count();
            for _ in 0..D::N {
                d_nnz.push(petsc_int(D::N * inside, "entries in a row")?);
                o_nnz.push(petsc_int(D::N * (nb.len() - inside), "entries in a row")?);
            }
        }
        let mut s = session()?;
        let o = &mut self.objects;
        let options = format!("{} {}", default_options(self.kind), config.options);
        o.options = crate::options_database(&s, &options, config.options_file.as_ref())?;
        s.push(o.options)?;
        let bs = D::N as PetscInt;
        call!(MatCreate(comm(), &mut o.parts))?;
        call!(MatSetSizes(o.parts, n_local, n_local, n, n))?;
        call!(MatSetType(o.parts, c("aij").as_ptr()))?;
        call!(MatSetBlockSize(o.parts, bs))?;
        call!(MatSeqAIJSetPreallocation(o.parts, 0, d_nnz.as_ptr()))?;
        call!(MatMPIAIJSetPreallocation(
            o.parts,
            0,
            d_nnz.as_ptr(),
            0,
            o_nnz.as_ptr()
        ))?;
        drop((d_nnz, o_nnz));
        let (mut cols, mut zeros) = (Vec::new(), Vec::new());
        for &g in my_nodes {
            cols.clear();
            for &h in graph.neighbours(g) {
                cols.extend((0..D::N).map(|c| self.dof_row[D::dof(h, c)]));
            }
            zeros.clear();
            zeros.resize(D::N * cols.len(), 0.0);
            let rows: Vec<PetscInt> = (0..D::N).map(|c| self.dof_row[D::dof(g, c)]).collect();
            call!(MatSetValues(
                o.parts,
                bs,
                rows.as_ptr(),
                cols.len() as PetscInt,
                cols.as_ptr(),
                zeros.as_ptr(),
                ffi::ADD_VALUES
            ))?;
        }
        drop(graph);
        let mine = Partition::elements_of(&partition.part_owner, self.rank);
        let elements = PartElements::new(parts, dofs);
        add_elements(
            o.parts,
            &SomeElements::new(&elements, &mine),
            dofs,
            &self.dof_row,
        )?;
        drop(mine);
        call!(MatAssemblyBegin(o.parts, ffi::MAT_FINAL_ASSEMBLY))?;
        call!(MatAssemblyEnd(o.parts, ffi::MAT_FINAL_ASSEMBLY))?;
        call!(MatSetOption(
            o.parts,
            ffi::MAT_NEW_NONZERO_LOCATION_ERR,
            ffi::PETSC_TRUE
        ))?;
        call!(MatDuplicate(o.parts, ffi::MAT_COPY_VALUES, &mut o.mat))?;
        call!(MatSetOption(
            o.mat,
            ffi::MAT_NEW_NONZERO_LOCATION_ERR,
            ffi::PETSC_TRUE
        ))?;
        for v in [&mut o.b, &mut o.x, &mut o.work] {
            call!(VecCreateMPI(comm(), n_local, n, v))?;
            call!(VecSetBlockSize(*v, bs))?;
        }
        call!(VecScatterCreateToAll(o.x, &mut o.to_all, &mut o.all))?;
        // The rigid-body modes of the node coordinates (in `work`, then zeroed
        // by its next use).
        {
            let coords = node_coordinates(parts, dofs);
            let mut a: *mut f64 = std::ptr::null_mut();
            call!(VecGetArray(o.work, &mut a))?;
            // SAFETY: PETSc's array of the vector's n_local entries.
            let local = unsafe { local_array(a, n_local as usize) };
            for (l, &g) in my_nodes.iter().enumerate() {
                local[l * D::N..(l + 1) * D::N]
                    .copy_from_slice(&coords[D::dof(g, 0)..D::dof(g, 0) + D::N]);
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

    /// Assembles `K(states)` into PETSc's matrix: the parts' stiffness copied,
    /// this rank's coupling elements in their states added, then the
    /// prescribed DOFs' diagonal set to the mean of the free one (collective).
    fn assemble(&mut self, states: &[Vec<PairState>]) -> Result<()> {
        let Problem {
            interfaces, dofs, ..
        } = self.problem;
        let _s = session()?;
        let o = &self.objects;
        call!(MatCopy(o.parts, o.mat, ffi::SAME_NONZERO_PATTERN))?;
        let couplings = CouplingElements::new(interfaces, Some(states), dofs);
        add_elements(
            o.mat,
            &SomeElements::new(&couplings, &self.my_couplings),
            dofs,
            &self.dof_row,
        )?;
        call!(MatAssemblyBegin(o.mat, ffi::MAT_FINAL_ASSEMBLY))?;
        call!(MatAssemblyEnd(o.mat, ffi::MAT_FINAL_ASSEMBLY))?;
        // The prescribed rows' diagonal (zero until now): the mean of the free.
        call!(MatGetDiagonal(o.mat, o.work))?;
        let mut free = 0.0;
        call!(VecSum(o.work, &mut free))?;
        let mean = if dofs.n_eq > 0 {
            free / dofs.n_eq as f64
        } else {
            1.0
        };
        let mut a: *mut f64 = std::ptr::null_mut();
        call!(VecGetArray(o.work, &mut a))?;
        // SAFETY: PETSc's array of the vector's local entries.
        let local = unsafe { local_array(a, self.local_eq.len()) };
        for (v, &e) in local.iter_mut().zip(&self.local_eq) {
            *v = if e == FIXED { mean } else { 0.0 };
        }
        call!(VecRestoreArray(o.work, &mut a))?;
        call!(MatDiagonalSet(o.mat, o.work, ffi::ADD_VALUES))?;
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

    /// Sets this rank's entries of `v` from `from` (free equations; zero at
    /// the prescribed DOFs, everywhere without `from`).
    fn set_local(&self, v: ffi::Vec, from: Option<&[f64]>) -> Result<()> {
        let mut a: *mut f64 = std::ptr::null_mut();
        call!(VecGetArray(v, &mut a))?;
        // SAFETY: PETSc's array of the vector's local entries.
        let local = unsafe { local_array(a, self.local_eq.len()) };
        for (v, &e) in local.iter_mut().zip(&self.local_eq) {
            *v = match from {
                Some(from) if e != FIXED => from[e],
                _ => 0.0,
            };
        }
        call!(VecRestoreArray(v, &mut a))
    }

    /// One KSP solve of `rhs` (free equations) from `guess`: the iterations,
    /// PETSc's converged reason and the true relative residual (collective).
    fn ksp_solve(&mut self, rhs: &[f64], guess: Option<&[f64]>) -> Result<(usize, i32, f64)> {
        let mut s = session()?;
        s.push(self.objects.options)?;
        let o = &self.objects;
        self.set_local(o.b, Some(rhs))?;
        let mut warm = guess.is_some() && self.kind == Kind::CgGamg;
        self.set_local(o.x, guess.filter(|_| warm))?;
        if warm {
            // A guess farther from the solution than zero (a pair closed
            // across a gap: the penalty times the gap) starts from zero
            // instead: CG would have to undo it, and PETSc's divergence test
            // (‖r‖ > 1e5 ‖b‖) can stop it before its first iteration.
            call!(MatMult(o.mat, o.x, o.work))?;
            call!(VecAYPX(o.work, -1.0, o.b))?;
            let (mut r0, mut b) = (0.0, 0.0);
            call!(VecNorm(o.work, ffi::NORM_2, &mut r0))?;
            call!(VecNorm(o.b, ffi::NORM_2, &mut b))?;
            if r0 > b {
                warm = false;
                self.set_local(o.x, None)?;
            }
        }
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
        call!(VecAYPX(o.work, -1.0, o.b))?;
        let (mut r, mut b) = (0.0, 0.0);
        call!(VecNorm(o.work, ffi::NORM_2, &mut r))?;
        call!(VecNorm(o.b, ffi::NORM_2, &mut b))?;
        let relative = if b > 0.0 { r / b } else { r };
        Ok((its.max(0) as usize, reason, relative))
    }

    /// The solution in `x` at the free equations, into `out`, on every rank
    /// (collective: the whole vector gathered on each).
    fn gather(&self, out: &mut [f64]) -> Result<()> {
        let _s = session()?;
        let o = &self.objects;
        call!(VecScatterBegin(
            o.to_all,
            o.x,
            o.all,
            ffi::INSERT_VALUES,
            ffi::SCATTER_FORWARD
        ))?;
        call!(VecScatterEnd(
            o.to_all,
            o.x,
            o.all,
            ffi::INSERT_VALUES,
            ffi::SCATTER_FORWARD
        ))?;
        let mut a: *const f64 = std::ptr::null();
        call!(VecGetArrayRead(o.all, &mut a))?;
        // SAFETY: PETSc's array of the sequential vector's n entries, read only.
        let all = unsafe { std::slice::from_raw_parts(a, self.dof_row.len()) };
        for (e, &r) in self.eq_row.iter().enumerate() {
            out[e] = all[r as usize];
        }
        call!(VecRestoreArrayRead(o.all, &mut a))
    }

    /// For each vector of the near-null space GAMG is given (the rigid-body
    /// modes: 3 in 2D, 6 in 3D), `‖K r‖ / (‖K‖_F ‖r‖)` with `K = K(states)`
    /// assembled: zero to round-off when the modes are exact rigid motions of
    /// the model (no DOF prescribed). Collective.
    pub fn rigid_mode_residuals(&mut self, states: &[Vec<PairState>]) -> Result<Vec<f64>> {
        self.assemble(states)?;
        self.prepared = None;
        let _s = session()?;
        let o = &self.objects;
        let mut norm_k = 0.0;
        call!(MatNorm(o.mat, ffi::NORM_FROBENIUS, &mut norm_k))?;
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
            let (mut kr, mut nr) = (0.0, 0.0);
            call!(VecNorm(o.work, ffi::NORM_2, &mut kr))?;
            call!(VecNorm(r, ffi::NORM_2, &mut nr))?;
            out.push(kr / (norm_k * nr));
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
            self.eq_row.len(),
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
