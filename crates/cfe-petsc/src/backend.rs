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
//! the whole model (replicated): the right-hand side's owned entries are set
//! from the caller's (replicated) vector, and after a complete solve the
//! distributed solution is gathered on every rank (`VecScatterCreateToAll`:
//! the whole vector, 8 bytes per DOF, to every rank), as the scheme then reads
//! all of it (internal forces, equilibrium). After a restricted solve
//! ([`RestrictedSolve`]: an active-set trial, a correction of the pairs'
//! forces) only the coupling equations' entries are gathered on every rank (a
//! `VecScatter` of those rows), the scheme reading nothing else of it.
//! [`exchanged`] counts the gathers and what they brought this rank.
//!
//! **Failures** are agreed on by the ranks, or end them all
//! ([`ranks`](crate::ranks)): this rank's local work (its elements into the
//! matrix) before the collective calls that follow it, each operation's start
//! (stop flags, another rank's failure); an error of a collective PETSc call
//! on several ranks calls `MPI_Abort`.
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
//! CG + GAMG keeps PETSc's own GAMG settings: more smoothing on GAMG's levels
//! (`-mg_levels_ksp_max_it 4`, a wider Chebyshev band) takes about 40 % fewer
//! CG iterations on one rank (README), but on two ranks it left the 3D plate
//! on a base's true residual 0.2 % above the tolerance its recursive residual
//! met, so it is a user's option, not the default. User options (`-ksp_*`,
//! `-pc_*`, `-mg_*`, `-mat_mumps_*`, an options file) are read by
//! `KSPSetFromOptions` after the defaults set in code, from the back end's own
//! database, so they override them.

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
    Analyse, Iterations, LinearFailure, LinearSolver, Outcome, Problem, RestrictedSolve, Statistics,
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
    /// The solution at the coupling equations on this rank (sequential) and
    /// the scatter filling it (a restricted solve's exchange).
    coupling: ffi::Vec,
    to_coupling: ffi::VecScatter,
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
            coupling: null,
            to_coupling: null,
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
            ffi::VecScatterDestroy(&mut self.to_coupling);
            ffi::VecDestroy(&mut self.coupling);
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

/// Where a KSP solve starts.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Start<'g> {
    /// From zero.
    Zero,
    /// From the caller's guess (free equations).
    Guess(&'g [f64]),
    /// From the solution PETSc's vector holds (the last solve's, or the
    /// iterate of a restart).
    Kept,
}

/// Which entries of a solution every rank receives after a solve.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Exchange {
    /// All of them (the library asked for a complete solve).
    All,
    /// The coupling equations' alone (a restricted solve: an active-set trial,
    /// a correction of the pairs' forces read at the pairs).
    Coupling,
}

/// Counts of the gathers after solves, this process's (every solver's):
/// [`exchanged`].
static RECEIVED: std::sync::Mutex<Received> = std::sync::Mutex::new(Received {
    all: 0,
    coupling: 0,
    doubles: 0,
    coupling_doubles: 0,
    seconds: 0.0,
});

/// Gathers after solves and what they brought a rank.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Received {
    /// Gathers of the whole solution.
    pub all: usize,
    /// Gathers of the coupling equations' entries alone.
    pub coupling: usize,
    /// Doubles received from other ranks (8 bytes each).
    pub doubles: usize,
    /// Of which in the gathers of the coupling equations' entries.
    pub coupling_doubles: usize,
    /// Seconds in the gathers (scatter and copy).
    pub seconds: f64,
}

impl Received {
    fn add(&mut self, exchange: Exchange, doubles: usize, seconds: f64) {
        match exchange {
            Exchange::All => self.all += 1,
            Exchange::Coupling => self.coupling += 1,
        }
        self.doubles += doubles;
        self.seconds += seconds;
        if exchange == Exchange::Coupling {
            self.coupling_doubles += doubles;
        }
        let mut total = RECEIVED.lock().unwrap_or_else(|e| e.into_inner());
        match exchange {
            Exchange::All => total.all += 1,
            Exchange::Coupling => total.coupling += 1,
        }
        total.doubles += doubles;
        total.seconds += seconds;
        if exchange == Exchange::Coupling {
            total.coupling_doubles += doubles;
        }
    }
}

/// The gathers after solves of every PETSc solver of this process (this
/// rank) so far: how many of each kind and the doubles they received.
pub fn exchanged() -> Received {
    *RECEIVED.lock().unwrap_or_else(|e| e.into_inner())
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
    /// The free equations of the coupling elements' DOFs (what a restricted
    /// solve gives every rank).
    coupling_eqs: Vec<usize>,
    /// Doubles this rank received in the gathers after solves.
    received: Received,
    /// The PETSc rows this rank owns (`first..end`).
    owned_rows: (PetscInt, PetscInt),
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
        Error::Rank(f) => LinearFailure::BackEnd {
            function: f.as_static(),
            code: -1,
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

/// This rank's number of rows (`D::N` per node of `my_nodes`) and, per row,
/// its entries in the columns of this rank's nodes and of the others' (the
/// preallocation of MPIAIJ), from the node graph.
#[allow(clippy::type_complexity)]
fn row_counts<D: ElementFamily>(
    graph: &NodeGraph,
    partition: &Partition,
    my_nodes: &[usize],
    rank: usize,
) -> Result<(PetscInt, Vec<PetscInt>, Vec<PetscInt>)> {
    let n_local = petsc_int(my_nodes.len() * D::N, "DOFs of a rank")?;
    let (first, end) = (partition.node_start[rank], partition.node_start[rank + 1]);
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
    Ok((n_local, d_nnz, o_nnz))
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
        // Every rank starts here together, unless one has failed before (rank
        // 0's output folder refused): then every rank ends here.
        if let Some(failure) = crate::ranks::agree(0, None)?.failure {
            return Err(failure.into());
        }
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
        let coupling_eqs: Vec<usize> = cfe::coupling::coupling_dofs(interfaces, dofs)
            .into_iter()
            .map(|d| dofs.eq[d])
            .filter(|&e| e != FIXED)
            .collect();
        let mut solver = PetscSolver {
            problem,
            kind,
            rank,
            ranks,
            dof_row,
            eq_row,
            local_eq,
            my_couplings,
            coupling_eqs,
            received: Received::default(),
            owned_rows: (
                (D::N * partition.node_start[rank]) as PetscInt,
                (D::N * partition.node_start[rank + 1]) as PetscInt,
            ),
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
    /// vectors, near-null space, KSP. This rank's local work (the row counts,
    /// its rows' pattern and elements into PETSc's matrix) is agreed on before
    /// the collective calls that follow it; a collective call's error ends
    /// every rank ([`ranks`](crate::ranks)).
    fn create(&mut self, partition: &Partition, my_nodes: &[usize], config: &Petsc) -> Result<()> {
        let Problem {
            parts,
            interfaces,
            dofs,
        } = self.problem;
        // The pattern: each owned node's row block against its neighbours'.
        let graph = NodeGraph::new(parts, interfaces, dofs);
        self.stats.matrix_nnz = lower_entries(&graph, dofs);
        let counts = row_counts::<D>(&graph, partition, my_nodes, self.rank);
        let mut s = session()?;
        let (n_local, d_nnz, o_nnz) = self.settle(counts)?;
        let made = self.create_matrix(&mut s, n_local, &d_nnz, &o_nnz, config);
        self.collective(made)?;
        drop((d_nnz, o_nnz));
        let filled = self.insert_pattern_and_parts(&graph, partition, my_nodes);
        drop(graph);
        self.settle(filled)?;
        let rest = self.create_rest(my_nodes, n_local);
        self.collective(rest)
    }

    /// Agrees with the other ranks on `local`, this rank's outcome: its value
    /// when no rank failed, else every rank's error is the first failure
    /// ([`Error::Rank`]). Collective; the caller holds the session's lock.
    fn settle<T>(&self, local: Result<T>) -> Result<T> {
        let message = local.as_ref().err().map(Error::to_string);
        match crate::ranks::agree_in_session(0, message.as_deref()).failure {
            Some(failure) => Err(failure.into()),
            None => local,
        }
    }

    /// The result of a collective PETSc call: an error ends every rank when
    /// there are several ([`ranks`](crate::ranks)); on one rank it is returned.
    fn collective<T>(&self, result: Result<T>) -> Result<T> {
        if let Err(e) = &result
            && self.ranks > 1
        {
            crate::ranks::abort(self.rank, &e.to_string());
        }
        result
    }

    /// The parts' matrix made and preallocated (`d_nnz`, `o_nnz`: the row
    /// counts of this rank's `n_local` rows), with the back end's options
    /// database. Collective.
    fn create_matrix(
        &mut self,
        s: &mut crate::Session,
        n_local: PetscInt,
        d_nnz: &[PetscInt],
        o_nnz: &[PetscInt],
        config: &Petsc,
    ) -> Result<()> {
        let n = petsc_int(self.dof_row.len(), "DOFs")?;
        let o = &mut self.objects;
        o.options = crate::options_database(s, &config.options, config.options_file.as_ref())?;
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
        ))
    }

    /// This rank's rows of the pattern (zeros) and its part elements' stiffness
    /// into the parts' matrix (local: entries of other ranks' rows wait in
    /// PETSc's stash for the assembly).
    fn insert_pattern_and_parts(
        &mut self,
        graph: &NodeGraph,
        partition: &Partition,
        my_nodes: &[usize],
    ) -> Result<()> {
        let Problem { parts, dofs, .. } = self.problem;
        let o = &mut self.objects;
        let bs = D::N as PetscInt;
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
        let mine = Partition::elements_of(&partition.part_owner, self.rank);
        let elements = PartElements::new(parts, dofs);
        add_elements(
            o.parts,
            &SomeElements::new(&elements, &mine),
            dofs,
            &self.dof_row,
        )
    }

    /// The rest, collective: the parts' matrix assembled and copied into
    /// `K(states)`'s, the vectors and scatters, the near-null space, the KSP
    /// with the defaults and then the options.
    fn create_rest(&mut self, my_nodes: &[usize], n_local: PetscInt) -> Result<()> {
        let Problem { parts, dofs, .. } = self.problem;
        let n = petsc_int(self.dof_row.len(), "DOFs")?;
        let bs = D::N as PetscInt;
        let o = &mut self.objects;
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
        // The coupling equations' rows, to every rank.
        {
            let rows: Vec<PetscInt> = self.coupling_eqs.iter().map(|&e| self.eq_row[e]).collect();
            let m = petsc_int(rows.len(), "coupling equations")?;
            // SAFETY: Open MPI's MPI_COMM_SELF, by address (PETSC_COMM_SELF).
            let this = (&raw const ffi::ompi_mpi_comm_self).cast_mut().cast();
            let mut is = std::ptr::null_mut();
            call!(ISCreateGeneral(
                this,
                m,
                rows.as_ptr(),
                ffi::PETSC_COPY_VALUES,
                &mut is
            ))?;
            let made = call!(VecCreateSeq(this, m, &mut o.coupling)).and_then(|()| {
                call!(VecScatterCreate(
                    o.x,
                    is,
                    o.coupling,
                    std::ptr::null_mut(),
                    &mut o.to_coupling
                ))
            });
            // SAFETY: the index set made above, destroyed once.
            unsafe { ffi::ISDestroy(&mut is) };
            made?;
        }
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

    /// The start of a back-end operation, on every rank together: the ranks
    /// agree on their stop flags and on a failure one of them met since
    /// ([`ranks`](crate::ranks)): `Err(Stopped)` once a flag is nonzero on
    /// any rank, a failure of another rank as [`LinearFailure::BackEnd`]
    /// naming it and its message.
    fn entry(&self) -> std::result::Result<(), LinearFailure> {
        let stop = self.stop.map_or(0, |s| s.load(Ordering::Relaxed));
        let agreed = {
            let _s = session().map_err(|e| failure(&e))?;
            crate::ranks::agree_in_session(stop, None)
        };
        if agreed.stop != 0 {
            return Err(LinearFailure::Stopped(agreed.stop));
        }
        match agreed.failure {
            Some(f) => Err(LinearFailure::BackEnd {
                function: f.as_static(),
                code: -1,
            }),
            None => Ok(()),
        }
    }

    /// Assembles `K(states)` into PETSc's matrix: the parts' stiffness copied,
    /// this rank's coupling elements in their states added (local, agreed on),
    /// then, collective, the assembly and the prescribed DOFs' diagonal set to
    /// the mean of the free one.
    fn assemble(&mut self, states: &[Vec<PairState>]) -> Result<()> {
        let _s = session()?;
        let local = self.add_couplings(states);
        self.settle(local)?;
        let rest = self.finish_assembly();
        self.collective(rest)
    }

    /// The parts' stiffness copied into `K(states)`'s matrix (the same
    /// pattern: no communication) and this rank's coupling elements in
    /// `states` added (entries of other ranks' rows wait in PETSc's stash).
    fn add_couplings(&self, states: &[Vec<PairState>]) -> Result<()> {
        let Problem {
            interfaces, dofs, ..
        } = self.problem;
        let o = &self.objects;
        call!(MatCopy(o.parts, o.mat, ffi::SAME_NONZERO_PATTERN))?;
        let couplings = CouplingElements::new(interfaces, Some(states), dofs);
        add_elements(
            o.mat,
            &SomeElements::new(&couplings, &self.my_couplings),
            dofs,
            &self.dof_row,
        )
    }

    /// `K(states)`'s assembly (collective) and the prescribed rows' diagonal.
    fn finish_assembly(&self) -> Result<()> {
        let dofs = self.problem.dofs;
        let o = &self.objects;
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

    /// One KSP solve of `rhs` (free equations) from `start`: the iterations,
    /// PETSc's converged reason and the true relative residual (collective).
    fn ksp_solve(&mut self, rhs: &[f64], start: Start<'_>) -> Result<(usize, i32, f64)> {
        let mut s = session()?;
        s.push(self.objects.options)?;
        let o = &self.objects;
        self.set_local(o.b, Some(rhs))?;
        let mut warm = start != Start::Zero && self.kind == Kind::CgGamg;
        match start {
            Start::Guess(guess) if warm => self.set_local(o.x, Some(guess))?,
            Start::Kept if warm => {}
            _ => self.set_local(o.x, None)?,
        }
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

    /// The solution in `x` at the free equations `exchange` names, into `out`,
    /// on every rank (collective): the whole vector gathered on each, or only
    /// its coupling equations' entries.
    fn gather(&mut self, out: &mut [f64], exchange: Exchange) -> Result<()> {
        let t = Instant::now();
        let _s = session()?;
        let o = &self.objects;
        let (to, into, eqs) = match exchange {
            Exchange::All => (o.to_all, o.all, None),
            Exchange::Coupling => (o.to_coupling, o.coupling, Some(&self.coupling_eqs)),
        };
        call!(VecScatterBegin(
            to,
            o.x,
            into,
            ffi::INSERT_VALUES,
            ffi::SCATTER_FORWARD
        ))?;
        call!(VecScatterEnd(
            to,
            o.x,
            into,
            ffi::INSERT_VALUES,
            ffi::SCATTER_FORWARD
        ))?;
        let mut a: *const f64 = std::ptr::null();
        call!(VecGetArrayRead(into, &mut a))?;
        let n = eqs.map_or(self.dof_row.len(), Vec::len);
        let got = if n == 0 || a.is_null() {
            &[][..]
        } else {
            // SAFETY: PETSc's array of the sequential vector's n entries, read only.
            unsafe { std::slice::from_raw_parts(a, n) }
        };
        match eqs {
            None => {
                for (e, &r) in self.eq_row.iter().enumerate() {
                    out[e] = got[r as usize];
                }
            }
            Some(eqs) => {
                for (&e, &v) in eqs.iter().zip(got) {
                    out[e] = v;
                }
            }
        }
        call!(VecRestoreArrayRead(into, &mut a))?;
        // What came from other ranks: the entries of rows this rank does not own.
        let own = self.local_eq.len();
        let (first, end) = self.owned_rows;
        let received = match exchange {
            Exchange::All => self.dof_row.len() - own,
            Exchange::Coupling => self
                .coupling_eqs
                .iter()
                .filter(|&&e| !(first..end).contains(&self.eq_row[e]))
                .count(),
        };
        self.received
            .add(exchange, received, t.elapsed().as_secs_f64());
        Ok(())
    }

    /// Solves `K(states) x = rhs` from `start`, distributed, and writes into
    /// `rhs` on every rank the entries `exchange` says (collective): the
    /// seam's complete and restricted solves.
    fn solve_exchanging(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        mut start: Start<'_>,
        exchange: Exchange,
    ) -> std::result::Result<Outcome, LinearFailure> {
        assert_eq!(
            rhs.len(),
            self.eq_row.len(),
            "right-hand side of another size"
        );
        let mut method = self.prepare(states)?;
        self.entry()?;
        let t = Instant::now();
        let b = rhs.to_vec();
        let (mut total, mut restarts, mut retried) = (0usize, 0usize, false);
        let result = loop {
            let fresh = self.fresh_iterations.is_none();
            let solved = self.ksp_solve(&b, start);
            let (its, reason, relative) = self.collective(solved).map_err(|e| failure(&e))?;
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
            // go on from the iterate (kept in PETSc's vector).
            restarts += 1;
            start = Start::Kept;
        };
        if let Some(fresh) = self.fresh_iterations
            && total > (2 * fresh).max(10)
        {
            self.rebuild = true;
        }
        self.stats.iterations += total;
        self.stats.solve_seconds += t.elapsed().as_secs_f64();
        let relative = result?;
        let gathered = self.gather(rhs, exchange);
        self.collective(gathered).map_err(|e| failure(&e))?;
        Ok(Outcome {
            method,
            iterations: relative.map(|relative_residual| Iterations {
                count: total,
                relative_residual,
            }),
            complete: exchange == Exchange::All,
        })
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
        self.entry()?;
        let t = Instant::now();
        self.prepared = None;
        self.assemble(states).map_err(|e| failure(&e))?;
        let rebuild = self.kind == Kind::Mumps || !self.built || self.rebuild;
        let set_up = self.set_up(rebuild);
        self.collective(set_up).map_err(|e| failure(&e))?;
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
        let start = guess.map_or(Start::Zero, Start::Guess);
        self.solve_exchanging(states, rhs, start, Exchange::All)
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

    fn restricted(&mut self) -> Option<&mut dyn RestrictedSolve> {
        Some(self)
    }
}

/// The restricted solves: distributed as a complete one, but only the
/// coupling equations' entries are gathered on every rank (what the contact
/// scheme reads of an active-set trial or of a correction of the pairs'
/// forces), not the whole solution.
impl<'a, D: ElementFamily> RestrictedSolve for PetscSolver<'a, D> {
    /// Starts CG from the solution PETSc holds (the last solve's: the
    /// restricted solve is given no guess).
    fn solve_interface(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
        _rhs_on_interface: bool,
    ) -> std::result::Result<Outcome, LinearFailure> {
        self.solve_exchanging(states, rhs, Start::Kept, Exchange::Coupling)
    }

    /// A complete solve from zero (a change of the pairs' forces: no guess).
    fn solve_pair_forces(
        &mut self,
        states: &[Vec<PairState>],
        rhs: &mut [f64],
    ) -> std::result::Result<Outcome, LinearFailure> {
        self.solve_exchanging(states, rhs, Start::Zero, Exchange::All)
    }
}
