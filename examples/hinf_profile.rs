//! Runs one H-infinity design (argument: `paper`, `paper_full` (the same SDP posed with the
//! filter matrices as variables), `observer`, `observer_full`, `mixed` or `mixed_quiet`) and
//! prints gamma, H2 norm, interior-point iterations and wall time: the workload for
//! `valgrind --tool=callgrind` instruction counts beside the criterion medians
//! (`cargo run --release --example hinf_profile -- paper`).
#![allow(clippy::unwrap_used, clippy::expect_used, clippy::panic)]

use relnav::hinf::design::{
    design_observer_full, design_open_loop, design_open_loop_mixed, design_paper_full,
    design_paper_spec, DesignOptions,
};
use relnav::hinf::HinfSpec;

fn main() {
    let which = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "paper".to_string());
    let reps: usize = std::env::args()
        .nth(2)
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    let opts = DesignOptions::default();
    let spec = HinfSpec::paper();
    let quiet = relnav::nav::NavConfig {
        filter: relnav::nav::FilterKind::Hinf,
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
                let plant = relnav::hinf::HinfPlant::paper_closed_loop(
                    &spec,
                    &relnav::hinf::PAPER_K,
                    relnav::hinf::PAPER_MASS,
                );
                let d = design_paper_full(&plant, spec.period, &opts).expect("paper design");
                (d.gamma, d.h2_norm, format!("{}", d.iterations))
            }
            "observer_full" => {
                let plant = relnav::hinf::HinfPlant::open_loop(&spec);
                let d = design_observer_full(&plant, spec.period, &opts).expect("observer");
                (d.gamma, d.h2_norm, format!("{}", d.iterations))
            }
            "observer" => {
                let d = design_open_loop(&spec, &opts).expect("observer design");
                (d.gamma, d.h2_norm, format!("{}", d.iterations))
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
