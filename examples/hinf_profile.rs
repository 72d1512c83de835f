//! Runs one H-infinity design (argument: `paper`, `paper_full` (the same SDP posed with the
//! filter matrices as variables), `observer` (the Riccati route, SDP fallback),
//! `observer_sdp` (the eliminated SDP), `observer_full`, `observer_quiet`,
//! `observer_sdp_quiet` (filter 9's quiet-truth noise), `mixed` or `mixed_quiet`) and
//! prints gamma, H2 norm, interior-point iterations and wall time: the workload for
//! `valgrind --tool=callgrind` instruction counts beside the criterion medians
//! (`cargo run --release --example hinf_profile -- paper [repetitions [bound]]`). For the
//! observer designs, `RELNAV_PRINT_CERTIFICATE=1` prints the Riccati route's bracket,
//! trials and the eigenvalue range of its certificate `P = g2 X^-1`, and
//! `RELNAV_SDP_TAU=<tau>` also runs the eliminated SDP in the coordinates `diag(I, tau I)
//! e`: on the quiet noise the SDP posed in metres and m/s stops above the infimum, posed
//! in balanced units it agrees (`tests/hinf.rs`, `riccati_route_matches_the_sdp`).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use relnav_core::hinf::design::{
    design_observer, design_observer_full, design_observer_sdp, design_open_loop_mixed,
    design_paper_full, design_paper_spec, DesignOptions,
};
use relnav_core::hinf::HinfSpec;

fn main() {
    let which = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "paper".to_string());
    let reps: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    // optional third argument: the certificate bound rho of the SDPs (default 1e4)
    let mut opts = DesignOptions::default();
    if let Some(rho) = std::env::args().nth(3).and_then(|s| s.parse().ok()) {
        opts.bound = rho;
    }
    let spec = HinfSpec::paper();
    let quiet = relnav_core::nav::NavConfig {
        filter: relnav_core::nav::FilterKind::Hinf,
        accel_psd: 1e-10,
        q_pos: [0.0; 3],
        q_vel: [0.0; 3],
        ..Default::default()
    }
    .hinf_spec()
    .expect("quiet spec");
    for _ in 0..reps {
        let t0 = std::time::Instant::now();
        let (gamma, h2, iters) = match which.as_str() {
            "paper" => {
                let d = design_paper_spec(&spec, &opts).expect("paper design");
                (d.gamma, d.h2_norm, format!("{}", d.iterations))
            }
            "paper_full" => {
                let plant = relnav_core::hinf::HinfPlant::paper_closed_loop(
                    &spec,
                    &relnav_core::hinf::PAPER_K,
                    relnav_core::hinf::PAPER_MASS,
                );
                let d = design_paper_full(&plant, spec.period, &opts).expect("paper design");
                (d.gamma, d.h2_norm, format!("{}", d.iterations))
            }
            "observer_full" => {
                let plant = relnav_core::hinf::HinfPlant::open_loop(&spec);
                let d = design_observer_full(&plant, spec.period, &opts).expect("observer");
                (d.gamma, d.h2_norm, format!("{}", d.iterations))
            }
            "observer" | "observer_quiet" | "observer_sdp" | "observer_sdp_quiet" => {
                let sp = if which.ends_with("quiet") {
                    &quiet
                } else {
                    &spec
                };
                let plant = relnav_core::hinf::HinfPlant::open_loop(sp);
                if std::env::var_os("RELNAV_PRINT_CERTIFICATE").is_some() {
                    let r = relnav_core::hinf::riccati::observer(&plant).expect("riccati");
                    let p = r.x.try_inverse().expect("X invertible") * (r.gamma * r.gamma);
                    let ev = p.symmetric_eigenvalues();
                    println!(
                        "Riccati certificate P = g2 X^-1: eigenvalues {:.3e} .. {:.3e}; \
                         bracket [{}, {}], {} trials, {} doublings",
                        ev.min(),
                        ev.max(),
                        r.gamma_lower,
                        r.gamma,
                        r.steps,
                        r.doublings
                    );
                }
                if let Some(tau) = std::env::var("RELNAV_SDP_TAU")
                    .ok()
                    .and_then(|s| s.parse::<f64>().ok())
                {
                    // the same SDP in the coordinates e' = diag(I, tau I) e
                    let (sp, _) = relnav_core::hinf::design::scaled_plant(&plant, tau);
                    let d = design_observer_sdp(&sp, 1.0, &opts).expect("scaled SDP");
                    println!(
                        "SDP at tau {tau}: gamma {:.8} ({} iterations)",
                        d.gamma, d.iterations
                    );
                }
                let d = if which.starts_with("observer_sdp") {
                    design_observer_sdp(&plant, sp.period, &opts).expect("observer SDP")
                } else {
                    design_observer(&plant, sp.period, &opts).expect("observer design")
                };
                (
                    d.gamma,
                    d.h2_norm,
                    format!(
                        "{} ({:?}, {} Riccati trials, fallback {:?})",
                        d.iterations, d.route, d.riccati_steps, d.riccati_failure
                    ),
                )
            }
            "mixed" | "mixed_quiet" => {
                let sp = if which == "mixed" { &spec } else { &quiet };
                let m = design_open_loop_mixed(sp, 1.5, &opts).expect("mixed design");
                (
                    m.mixed.gamma,
                    m.mixed.h2_norm,
                    format!("{}+{}", m.pure.iterations, m.mixed.iterations),
                )
            }
            other => panic!("unknown design {other}"),
        };
        println!(
            "{which}: gamma {gamma:.8} h2 {h2:.8} iterations {iters} time {:.2} ms",
            t0.elapsed().as_secs_f64() * 1e3
        );
    }
}
