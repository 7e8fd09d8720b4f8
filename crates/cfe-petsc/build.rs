//! Finds the system PETSc through pkg-config (`PETSc.pc`, or `petsc.pc`) and
//! links it. A machine without it stops here with a message naming the Debian
//! packages, not with a link error. The hand-written declarations of
//! `src/ffi.rs` assume a PETSc of 32-bit `PetscInt`, real double `PetscScalar`
//! and Open MPI (`MPI_Comm` a pointer): read from the installed `petscconf.h`
//! and checked here.

use std::process::Command;

const INSTALL: &str = "install PETSc and Open MPI, e.g. on Debian or Ubuntu: `sudo apt-get install libpetsc-real-dev openmpi-bin libopenmpi-dev pkg-config` (or set PKG_CONFIG_PATH to the folder of a PETSc build's PETSc.pc)";

fn pkg_config(args: &[&str]) -> Option<String> {
    let out = Command::new("pkg-config").args(args).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn main() {
    println!("cargo:rerun-if-env-changed=PKG_CONFIG_PATH");
    println!("cargo:rerun-if-changed=build.rs");
    let Some(name) = ["PETSc", "petsc"]
        .into_iter()
        .find(|n| pkg_config(&["--exists", n]).is_some())
    else {
        panic!("cfe-petsc: PETSc was not found by pkg-config (no PETSc.pc or petsc.pc): {INSTALL}");
    };
    let version = pkg_config(&["--modversion", name]).unwrap_or_default();
    let include = pkg_config(&["--variable=includedir", name]).unwrap_or_else(|| {
        panic!("cfe-petsc: pkg-config gives no includedir for {name}: {INSTALL}")
    });
    let conf_path = std::path::Path::new(&include).join("petscconf.h");
    let conf = std::fs::read_to_string(&conf_path).unwrap_or_else(|e| {
        panic!(
            "cfe-petsc: cannot read {} ({e}): the PETSc headers are missing; {INSTALL}",
            conf_path.display()
        )
    });
    println!("cargo:rerun-if-changed={}", conf_path.display());
    let defined = |key: &str| {
        conf.lines()
            .any(|l| l.split_whitespace().take(2).eq(["#define", key]))
    };
    let value = |key: &str| {
        conf.lines().find_map(|l| {
            let mut w = l.split_whitespace();
            (w.next() == Some("#define") && w.next() == Some(key))
                .then(|| w.next().map(str::to_string))?
        })
    };
    let fail = |what: &str| -> ! {
        panic!(
            "cfe-petsc: PETSc {version} at {include} is {what}; its bindings (src/ffi.rs) need PetscInt of 32 bits, a real double PetscScalar and Open MPI: install the Debian package libpetsc-real-dev (not libpetsc-complex-dev or a 64-bit-index build)"
        )
    };
    if defined("PETSC_USE_64BIT_INDICES") {
        fail("built with 64-bit indices");
    }
    if defined("PETSC_USE_COMPLEX") || !defined("PETSC_USE_REAL_DOUBLE") {
        fail("not built for real double scalars");
    }
    if value("PETSC_SIZEOF_INT").as_deref() != Some("4") {
        fail("built where an int is not 4 bytes");
    }
    if !defined("PETSC_HAVE_OMPI_MAJOR_VERSION") {
        fail("not built with Open MPI");
    }
    println!(
        "cargo:rustc-env=CFE_PETSC_MUMPS={}",
        if defined("PETSC_HAVE_MUMPS") {
            "1"
        } else {
            "0"
        }
    );
    println!("cargo:rustc-env=CFE_PETSC_VERSION={version}");
    let libs = pkg_config(&["--libs", name]).unwrap_or_else(|| {
        panic!("cfe-petsc: pkg-config gives no libraries for {name}: {INSTALL}")
    });
    // Open MPI itself, for the ranks' agreement on a failure (src/ranks.rs
    // calls MPI_Allreduce, MPI_Bcast and MPI_Abort): `ompi.pc` of
    // libopenmpi-dev, else the `mpi` library PETSc was linked with.
    let mpi = pkg_config(&["--libs", "ompi"]).unwrap_or_else(|| "-lmpi".into());
    for flag in libs.split_whitespace().chain(mpi.split_whitespace()) {
        if let Some(dir) = flag.strip_prefix("-L") {
            println!("cargo:rustc-link-search=native={dir}");
        } else if let Some(lib) = flag.strip_prefix("-l") {
            println!("cargo:rustc-link-lib=dylib={lib}");
        }
    }
}
