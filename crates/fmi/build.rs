//! Sets `RELNAV_GENERATION_DATE`, the FMUs' `generationDateAndTime` (see
//! [`generation_date`]).

use std::env;
use std::path::PathBuf;
use std::process::Command;

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
}
