//! Links BLAS/LAPACK statically for the `hinf` feature (Clarabel's SDP support).
//!
//! Clarabel's `sdp` feature calls BLAS/LAPACK through the `blas`/`lapack` crates; we select
//! no `blas-src`/`lapack-src` backend and link Debian's static OpenBLAS here instead
//! (`libopenblas-dev`), with the static Fortran runtime it needs (`libgfortran.a`,
//! `libquadmath.a` from `libgfortran-12-dev`). A shared library that links relnav-core
//! (`librelnav.so`, every FMU) then depends on the system C runtime only
//! (`tests/python/test_binary.py` checks the FMU's NEEDED entries). `scripts/setup.sh`
//! installs both packages. `RELNAV_OPENBLAS_DIR` / `RELNAV_GFORTRAN_DIR` override the
//! search directories.
//!
//! Size: OpenBLAS's run-time CPU dispatch pulls in its kernels for every CPU type (~25 MB
//! of the library). Debian's static reference BLAS/LAPACK (`libblas-dev`,
//! `liblapack-dev`) would pull only the routines Clarabel calls, but it is not compiled
//! as position-independent code and cannot go into a cdylib (rust-lld: "relocation
//! R_X86_64_PC32 ... recompile with -fPIC").

use std::env;
use std::path::{Path, PathBuf};
use std::process::Command;

fn gcc_lib_dir(file: &str) -> Option<PathBuf> {
    let out = Command::new("gcc")
        .arg(format!("-print-file-name={file}"))
        .output()
        .ok()?;
    let p = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    if p.is_absolute() && p.exists() {
        p.parent().map(Path::to_path_buf)
    } else {
        None
    }
}

fn find(file: &str, env_var: &str, candidates: &[&str]) -> PathBuf {
    if let Ok(d) = env::var(env_var) {
        return PathBuf::from(d);
    }
    for c in candidates {
        if Path::new(c).join(file).exists() {
            return PathBuf::from(c);
        }
    }
    if let Some(d) = gcc_lib_dir(file) {
        return d;
    }
    println!(
        "cargo:warning={file} not found (set {env_var}); install libopenblas-dev and \
         libgfortran-12-dev (scripts/setup.sh)"
    );
    PathBuf::from(candidates.first().copied().unwrap_or("/usr/lib"))
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=RELNAV_OPENBLAS_DIR");
    println!("cargo:rerun-if-env-changed=RELNAV_GFORTRAN_DIR");
    println!("cargo::rustc-check-cfg=cfg(relnav_openblas)");
    if env::var_os("CARGO_FEATURE_HINF").is_none() {
        return;
    }
    let blas = find(
        "libopenblas.a",
        "RELNAV_OPENBLAS_DIR",
        &[
            "/usr/lib/x86_64-linux-gnu/openblas-pthread",
            "/usr/lib/x86_64-linux-gnu",
            "/usr/lib64",
            "/usr/lib",
        ],
    );
    let fortran = find(
        "libgfortran.a",
        "RELNAV_GFORTRAN_DIR",
        &[
            "/usr/lib/gcc/x86_64-linux-gnu/12",
            "/usr/lib/gcc/x86_64-linux-gnu/13",
            "/usr/lib/gcc/x86_64-linux-gnu/14",
        ],
    );
    println!("cargo:rustc-link-search=native={}", fortran.display());
    println!("cargo:rustc-link-search=native={}", blas.display());
    println!("cargo:rustc-link-lib=static:+verbatim=libopenblas.a");
    // lets the design switch OpenBLAS to one thread (src/numerics/blas.rs)
    println!("cargo:rustc-cfg=relnav_openblas");
    println!("cargo:rustc-link-lib=static:+verbatim=libgfortran.a");
    println!("cargo:rustc-link-lib=static:+verbatim=libquadmath.a");
}
