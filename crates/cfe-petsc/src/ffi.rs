//! The PETSc calls this crate makes, declared by hand from the headers of
//! PETSc 3.18 (Debian's `libpetsc-real-dev`): `PetscInt` is 32 bits,
//! `PetscScalar` and `PetscReal` are `f64`, `PetscErrorCode` and the enums are
//! C `int`s, and `MPI_Comm` is Open MPI's pointer. `build.rs` checks the
//! installed `petscconf.h` for exactly that; the `types_match_petscconf`
//! test checks the sizes here.

#![allow(non_camel_case_types, non_snake_case, dead_code)]

use std::ffi::{c_char, c_int, c_void};

/// `PetscInt` (no `PETSC_USE_64BIT_INDICES`).
pub type PetscInt = i32;
/// `PetscScalar` (real double).
pub type PetscScalar = f64;
/// `PetscReal`.
pub type PetscReal = f64;
/// `PetscErrorCode` (0: success).
pub type PetscErrorCode = c_int;
/// `PetscBool` (an enum: `PETSC_FALSE`, `PETSC_TRUE`).
pub type PetscBool = c_int;
pub const PETSC_FALSE: PetscBool = 0;
pub const PETSC_TRUE: PetscBool = 1;
/// `PETSC_DEFAULT` for a tolerance or an iteration count.
pub const PETSC_DEFAULT: PetscInt = -2;
/// `MPI_Comm` in Open MPI: a pointer to its communicator structure.
pub type MPI_Comm = *mut c_void;

/// Opaque PETSc objects (pointers to their private structures).
pub type Mat = *mut c_void;
pub type Vec = *mut c_void;
pub type KSP = *mut c_void;
pub type PC = *mut c_void;
pub type MatNullSpace = *mut c_void;
pub type PetscOptions = *mut c_void;
pub type VecScatter = *mut c_void;
pub type IS = *mut c_void;
/// `PETSC_COPY_VALUES` (`PetscCopyMode`).
pub const PETSC_COPY_VALUES: c_int = 0;
/// `PetscMPIInt`.
pub type PetscMPIInt = c_int;

/// `InsertMode`.
pub const INSERT_VALUES: c_int = 1;
pub const ADD_VALUES: c_int = 2;
/// `MatAssemblyType`.
pub const MAT_FINAL_ASSEMBLY: c_int = 0;
/// `MatOption`: a new nonzero location is an error.
pub const MAT_NEW_NONZERO_LOCATION_ERR: c_int = 11;
/// `MatStructure`.
pub const SAME_NONZERO_PATTERN: c_int = 2;
/// `MatDuplicateOption`.
pub const MAT_COPY_VALUES: c_int = 1;
/// `NormType`.
pub const NORM_2: c_int = 1;
pub const NORM_FROBENIUS: c_int = 2;
/// `ScatterMode`.
pub const SCATTER_FORWARD: c_int = 0;
/// `KSPNormType`.
pub const KSP_NORM_UNPRECONDITIONED: c_int = 2;
/// `KSPConvergedReason` values this crate tells apart.
pub const KSP_DIVERGED_ITS: c_int = -3;
pub const KSP_DIVERGED_INDEFINITE_PC: c_int = -8;
pub const KSP_DIVERGED_INDEFINITE_MAT: c_int = -10;
pub const KSP_DIVERGED_PC_FAILED: c_int = -11;

/// `PetscErrorHandler`: (comm, line, function, file, error, how, message, context).
pub type PetscErrorHandler = unsafe extern "C" fn(
    MPI_Comm,
    c_int,
    *const c_char,
    *const c_char,
    PetscErrorCode,
    c_int,
    *const c_char,
    *mut c_void,
) -> PetscErrorCode;

/// An Open MPI predefined object (`MPI_INT`, `MPI_MAX`, ...): only its
/// address is used, as `mpi.h`'s macros take it.
#[repr(C)]
pub struct OmpiPredefined {
    _opaque: [u8; 0],
}

/// Open MPI's `MPI_Datatype` and `MPI_Op` (pointers).
pub type MPI_Datatype = *const OmpiPredefined;
pub type MPI_Op = *const OmpiPredefined;

unsafe extern "C" {
    /// Open MPI's `MPI_INT`, `MPI_CHAR` and `MPI_MAX` (their addresses).
    pub static ompi_mpi_int: OmpiPredefined;
    pub static ompi_mpi_char: OmpiPredefined;
    pub static ompi_mpi_op_max: OmpiPredefined;
    /// Open MPI's `MPI_COMM_SELF` (`PETSC_COMM_SELF`), by its address.
    pub static ompi_mpi_comm_self: OmpiPredefined;

    pub fn MPI_Allreduce(
        sendbuf: *const c_void,
        recvbuf: *mut c_void,
        count: c_int,
        datatype: MPI_Datatype,
        op: MPI_Op,
        comm: MPI_Comm,
    ) -> c_int;
    pub fn MPI_Bcast(
        buffer: *mut c_void,
        count: c_int,
        datatype: MPI_Datatype,
        root: c_int,
        comm: MPI_Comm,
    ) -> c_int;
    pub fn MPI_Abort(comm: MPI_Comm, errorcode: c_int) -> c_int;
}

unsafe extern "C" {
    /// The communicator of all ranks PETSc runs on (one in a serial run).
    pub static PETSC_COMM_WORLD: MPI_Comm;
    /// This process's rank in `MPI_COMM_WORLD`, set by `PetscInitialize`.
    pub static PetscGlobalRank: PetscMPIInt;
    /// The number of ranks of `MPI_COMM_WORLD`, set by `PetscInitialize`.
    pub static PetscGlobalSize: PetscMPIInt;

    pub fn PetscInitialize(
        argc: *mut c_int,
        args: *mut *mut *mut c_char,
        file: *const c_char,
        help: *const c_char,
    ) -> PetscErrorCode;
    pub fn PetscInitialized(isInitialized: *mut PetscBool) -> PetscErrorCode;
    pub fn PetscFinalize() -> PetscErrorCode;
    pub fn PetscPushErrorHandler(handler: PetscErrorHandler, ctx: *mut c_void) -> PetscErrorCode;
    pub fn PetscReturnErrorHandler(
        comm: MPI_Comm,
        line: c_int,
        fun: *const c_char,
        file: *const c_char,
        n: PetscErrorCode,
        p: c_int,
        mess: *const c_char,
        ctx: *mut c_void,
    ) -> PetscErrorCode;
    pub fn PetscErrorMessage(
        errnum: PetscErrorCode,
        text: *mut *const c_char,
        specific: *mut *mut c_char,
    ) -> PetscErrorCode;

    pub fn PetscOptionsCreate(options: *mut PetscOptions) -> PetscErrorCode;
    pub fn PetscOptionsDestroy(options: *mut PetscOptions) -> PetscErrorCode;
    pub fn PetscOptionsInsertString(options: PetscOptions, s: *const c_char) -> PetscErrorCode;
    pub fn PetscOptionsInsertFile(
        comm: MPI_Comm,
        options: PetscOptions,
        file: *const c_char,
        require: PetscBool,
    ) -> PetscErrorCode;
    pub fn PetscOptionsPush(options: PetscOptions) -> PetscErrorCode;
    pub fn PetscOptionsPop() -> PetscErrorCode;

    pub fn MatCreate(comm: MPI_Comm, a: *mut Mat) -> PetscErrorCode;
    pub fn MatSetSizes(
        a: Mat,
        m: PetscInt,
        n: PetscInt,
        big_m: PetscInt,
        big_n: PetscInt,
    ) -> PetscErrorCode;
    pub fn MatSetType(a: Mat, kind: *const c_char) -> PetscErrorCode;
    pub fn MatSetBlockSize(a: Mat, bs: PetscInt) -> PetscErrorCode;
    pub fn MatSeqAIJSetPreallocation(a: Mat, nz: PetscInt, nnz: *const PetscInt) -> PetscErrorCode;
    pub fn MatMPIAIJSetPreallocation(
        a: Mat,
        d_nz: PetscInt,
        d_nnz: *const PetscInt,
        o_nz: PetscInt,
        o_nnz: *const PetscInt,
    ) -> PetscErrorCode;
    pub fn MatSetOption(a: Mat, op: c_int, flg: PetscBool) -> PetscErrorCode;
    pub fn MatDuplicate(a: Mat, op: c_int, m: *mut Mat) -> PetscErrorCode;
    pub fn MatCopy(a: Mat, b: Mat, s: c_int) -> PetscErrorCode;
    pub fn MatGetDiagonal(a: Mat, v: Vec) -> PetscErrorCode;
    pub fn MatDiagonalSet(a: Mat, d: Vec, mode: c_int) -> PetscErrorCode;
    pub fn MatNorm(a: Mat, kind: c_int, nrm: *mut PetscReal) -> PetscErrorCode;
    pub fn MatGetOwnershipRange(a: Mat, m: *mut PetscInt, n: *mut PetscInt) -> PetscErrorCode;
    pub fn MatSetValues(
        a: Mat,
        m: PetscInt,
        idxm: *const PetscInt,
        n: PetscInt,
        idxn: *const PetscInt,
        v: *const PetscScalar,
        mode: c_int,
    ) -> PetscErrorCode;
    pub fn MatAssemblyBegin(a: Mat, kind: c_int) -> PetscErrorCode;
    pub fn MatAssemblyEnd(a: Mat, kind: c_int) -> PetscErrorCode;
    pub fn MatMult(a: Mat, x: Vec, y: Vec) -> PetscErrorCode;
    pub fn MatSetNearNullSpace(a: Mat, nullsp: MatNullSpace) -> PetscErrorCode;
    pub fn MatDestroy(a: *mut Mat) -> PetscErrorCode;

    pub fn MatNullSpaceCreateRigidBody(coords: Vec, sp: *mut MatNullSpace) -> PetscErrorCode;
    pub fn MatNullSpaceGetVecs(
        sp: MatNullSpace,
        has_const: *mut PetscBool,
        n: *mut PetscInt,
        vecs: *mut *const Vec,
    ) -> PetscErrorCode;
    pub fn MatNullSpaceDestroy(sp: *mut MatNullSpace) -> PetscErrorCode;

    pub fn VecCreateSeq(comm: MPI_Comm, n: PetscInt, v: *mut Vec) -> PetscErrorCode;
    pub fn VecCreateMPI(
        comm: MPI_Comm,
        n: PetscInt,
        big_n: PetscInt,
        v: *mut Vec,
    ) -> PetscErrorCode;
    pub fn VecGetLocalSize(v: Vec, n: *mut PetscInt) -> PetscErrorCode;
    pub fn VecSum(v: Vec, sum: *mut PetscScalar) -> PetscErrorCode;
    pub fn VecNorm(v: Vec, kind: c_int, val: *mut PetscReal) -> PetscErrorCode;
    /// `y = x + beta y`.
    pub fn VecAYPX(y: Vec, beta: PetscScalar, x: Vec) -> PetscErrorCode;
    pub fn VecScatterCreateToAll(v: Vec, ctx: *mut VecScatter, all: *mut Vec) -> PetscErrorCode;
    pub fn VecScatterBegin(
        ctx: VecScatter,
        x: Vec,
        y: Vec,
        addv: c_int,
        mode: c_int,
    ) -> PetscErrorCode;
    pub fn VecScatterEnd(
        ctx: VecScatter,
        x: Vec,
        y: Vec,
        addv: c_int,
        mode: c_int,
    ) -> PetscErrorCode;
    pub fn VecScatterDestroy(ctx: *mut VecScatter) -> PetscErrorCode;
    pub fn VecScatterCreate(x: Vec, ix: IS, y: Vec, iy: IS, ctx: *mut VecScatter)
    -> PetscErrorCode;
    pub fn ISCreateGeneral(
        comm: MPI_Comm,
        n: PetscInt,
        idx: *const PetscInt,
        mode: c_int,
        is: *mut IS,
    ) -> PetscErrorCode;
    pub fn ISDestroy(is: *mut IS) -> PetscErrorCode;
    pub fn VecSetBlockSize(v: Vec, bs: PetscInt) -> PetscErrorCode;
    pub fn VecGetArray(v: Vec, a: *mut *mut PetscScalar) -> PetscErrorCode;
    pub fn VecRestoreArray(v: Vec, a: *mut *mut PetscScalar) -> PetscErrorCode;
    pub fn VecGetArrayRead(v: Vec, a: *mut *const PetscScalar) -> PetscErrorCode;
    pub fn VecRestoreArrayRead(v: Vec, a: *mut *const PetscScalar) -> PetscErrorCode;
    pub fn VecDestroy(v: *mut Vec) -> PetscErrorCode;

    pub fn KSPCreate(comm: MPI_Comm, ksp: *mut KSP) -> PetscErrorCode;
    pub fn KSPSetOperators(ksp: KSP, amat: Mat, pmat: Mat) -> PetscErrorCode;
    pub fn KSPSetType(ksp: KSP, kind: *const c_char) -> PetscErrorCode;
    pub fn KSPGetPC(ksp: KSP, pc: *mut PC) -> PetscErrorCode;
    pub fn KSPSetTolerances(
        ksp: KSP,
        rtol: PetscReal,
        abstol: PetscReal,
        dtol: PetscReal,
        maxits: PetscInt,
    ) -> PetscErrorCode;
    pub fn KSPGetTolerances(
        ksp: KSP,
        rtol: *mut PetscReal,
        abstol: *mut PetscReal,
        dtol: *mut PetscReal,
        maxits: *mut PetscInt,
    ) -> PetscErrorCode;
    pub fn KSPSetNormType(ksp: KSP, normtype: c_int) -> PetscErrorCode;
    pub fn KSPSetInitialGuessNonzero(ksp: KSP, flg: PetscBool) -> PetscErrorCode;
    pub fn KSPSetReusePreconditioner(ksp: KSP, flg: PetscBool) -> PetscErrorCode;
    pub fn KSPSetFromOptions(ksp: KSP) -> PetscErrorCode;
    pub fn KSPSetUp(ksp: KSP) -> PetscErrorCode;
    pub fn KSPSolve(ksp: KSP, b: Vec, x: Vec) -> PetscErrorCode;
    pub fn KSPGetIterationNumber(ksp: KSP, its: *mut PetscInt) -> PetscErrorCode;
    pub fn KSPGetConvergedReason(ksp: KSP, reason: *mut c_int) -> PetscErrorCode;
    pub fn KSPDestroy(ksp: *mut KSP) -> PetscErrorCode;

    pub fn PCSetType(pc: PC, kind: *const c_char) -> PetscErrorCode;
    pub fn PCFactorSetMatSolverType(pc: PC, kind: *const c_char) -> PetscErrorCode;
}

unsafe extern "C" {
    pub fn PCGetType(pc: PC, kind: *mut *const c_char) -> PetscErrorCode;
    pub fn KSPGetType(ksp: KSP, kind: *mut *const c_char) -> PetscErrorCode;
}
