//! Links BLAS/LAPACK statically for the `hinf` feature (Clarabel's SDP support), and
//! sets `RELNAV_GENERATION_DATE`, the FMU's `generationDateAndTime` (see
//! [`generation_date`]).
//!
//! Clarabel's `sdp` feature calls BLAS/LAPACK through the `blas`/`lapack` crates; we select
//! no `blas-src`/`lapack-src` backend and link Debian's static OpenBLAS here instead
//! (`libopenblas-dev`), with the static Fortran runtime it needs (`libgfortran.a`,
//! `libquadmath.a` from `libgfortran-12-dev`). The cdylib, and with it the FMU, then
//! depends on the system C runtime only (`tests/fmu.rs` checks its NEEDED entries).
//! `scripts/setup.sh` installs both packages. `RELNAV_OPENBLAS_DIR` / `RELNAV_GFORTRAN_DIR`
//! override the search directories.
//!
//! Size: OpenBLAS's run-time CPU dispatch pulls in its kernels for every CPU type (~25 MB
//! of the library). Debian's static reference BLAS/LAPACK (`libblas-dev`,
//! `liblapack-dev`) would pull only the routines Clarabel calls, but it is not compiled
//! as position-independent code and cannot go into the cdylib (rust-lld: "relocation
//! R_X86_64_PC32 ... recompile with -fPIC"); tried and dropped.

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

/// Days since 1970-01-01 -> (year, month, day), proleptic Gregorian (the civil-from-days
/// algorithm of H. Hinnant's "chrono-Compatible Low-Level Date Algorithms").
fn civil_from_days(z: i64) -> (i64, i64, i64) {
    let z = z + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

fn git(args: &[&str]) -> Option<String> {
    let dir = env::var_os("CARGO_MANIFEST_DIR")?;
    let out = Command::new("git")
        .args(args)
        .current_dir(dir)
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    let s = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!s.is_empty()).then_some(s)
}

/// The FMU's `generationDateAndTime`, deterministic so that the XML and with it the GUID
/// (UUID v5 of the XML) are the same for every build of one source: `SOURCE_DATE_EPOCH`
/// when set (the reproducible-builds convention), else the commit date of `HEAD`, else
/// 1970-01-01T00:00:00Z (no git). Never the build time.
fn generation_date() -> String {
    println!("cargo:rerun-if-env-changed=SOURCE_DATE_EPOCH");
    // rebuild when HEAD moves (a commit, a checkout); only files that exist, or cargo
    // would rerun this script (and rebuild the crate) on every build
    let mut watch = Vec::new();
    if let Some(head) = git(&["rev-parse", "--git-path", "HEAD"]) {
        watch.push(head);
    }
    if let Some(r) = git(&["symbolic-ref", "-q", "HEAD"]) {
        if let Some(p) = git(&["rev-parse", "--git-path", &r]) {
            watch.push(p);
        }
    }
    if let Some(p) = git(&["rev-parse", "--git-path", "packed-refs"]) {
        watch.push(p);
    }
    let root = env::var_os("CARGO_MANIFEST_DIR").map(PathBuf::from);
    for w in watch {
        let p = match &root {
            Some(r) => r.join(&w),
            None => PathBuf::from(&w),
        };
        if p.exists() {
            println!("cargo:rerun-if-changed={}", p.display());
        }
    }
    let epoch = env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.trim().parse::<i64>().ok())
        .or_else(|| git(&["log", "-1", "--format=%ct"]).and_then(|s| s.parse().ok()))
        .unwrap_or(0);
    let (days, secs) = (epoch.div_euclid(86_400), epoch.rem_euclid(86_400));
    let (y, m, d) = civil_from_days(days);
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        secs / 3600,
        secs % 3600 / 60,
        secs % 60
    )
}

fn main() {
    println!("cargo:rerun-if-changed=build.rs");
    println!(
        "cargo:rustc-env=RELNAV_GENERATION_DATE={}",
        generation_date()
    );
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
    // lets the design switch OpenBLAS to one thread (src/ffi.rs)
    println!("cargo:rustc-cfg=relnav_openblas");
    println!("cargo:rustc-link-lib=static:+verbatim=libgfortran.a");
    println!("cargo:rustc-link-lib=static:+verbatim=libquadmath.a");
}
