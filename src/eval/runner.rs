//! Monte Carlo campaigns: runs in parallel (rayon), results independent of the thread
//! count, a progress bar for anything longer than a second, and Ctrl-C to stop early.
//!
//! Determinism: run `i` draws everything from `ChaCha8Rng::seed_from_u64(run_seed(base,
//! i))` (SplitMix64 of the base seed and the run index), so a run's numbers do not depend
//! on which thread does it. Runs are reduced in fixed chunks of [`CHUNK`] in run order and
//! the chunks are combined in order, so even the floating-point sums are identical for
//! any thread count.

use super::pcrlb;
use super::results::{FilterStats, McResult};
use super::scenario::{Scenario, Thrust};
use super::sim::{run_filter, Prepared, Score};
use crate::types::Mat6;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Runs per reduction chunk.
pub const CHUNK: usize = 4;

/// Seed of run `i`: SplitMix64 of `base + i * golden` (independent streams per run).
pub fn run_seed(base: u64, i: u64) -> u64 {
    let mut z = base.wrapping_add(i.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Options of a campaign.
#[derive(Debug, Clone, Default)]
pub struct Options {
    /// Override the scenario's run count.
    pub runs: Option<u32>,
    /// Worker threads (0: rayon's default, one per core).
    pub threads: usize,
    /// Show a progress bar (after one second) on stderr.
    pub progress: bool,
    /// Set to stop early (e.g. by Ctrl-C): finished runs are kept and reported.
    pub cancel: Option<Arc<AtomicBool>>,
}

/// Sums over runs for one filter.
#[derive(Clone)]
struct Acc {
    sum: Vec<[f64; 6]>,
    nees: Vec<f64>,
    nis: Vec<f64>,
    nis_n: Vec<u32>,
    max_pos: Vec<f64>,
    max_vel: Vec<f64>,
    ok_runs: u32,
    failed: u32,
    failures: Vec<String>,
    nanos: u128,
}

impl Acc {
    fn new(n: usize) -> Self {
        Self {
            sum: vec![[0.0; 6]; n],
            nees: vec![0.0; n],
            nis: vec![0.0; n],
            nis_n: vec![0; n],
            max_pos: vec![0.0; n],
            max_vel: vec![0.0; n],
            ok_runs: 0,
            failed: 0,
            failures: Vec::new(),
            nanos: 0,
        }
    }
    fn add_run(&mut self, s: &[Score]) {
        for (k, v) in s.iter().enumerate() {
            for (acc, x) in self.sum[k].iter_mut().zip(v.iter()) {
                *acc += x;
            }
            self.nees[k] += v[6];
            if v[7].is_finite() {
                self.nis[k] += v[7];
                self.nis_n[k] += 1;
            }
            self.max_pos[k] = self.max_pos[k].max(v[8]);
            self.max_vel[k] = self.max_vel[k].max(v[9]);
        }
        self.ok_runs += 1;
    }
    fn merge(&mut self, o: &Acc) {
        for k in 0..self.sum.len() {
            for i in 0..6 {
                self.sum[k][i] += o.sum[k][i];
            }
            self.nees[k] += o.nees[k];
            self.nis[k] += o.nis[k];
            self.nis_n[k] += o.nis_n[k];
            self.max_pos[k] = self.max_pos[k].max(o.max_pos[k]);
            self.max_vel[k] = self.max_vel[k].max(o.max_vel[k]);
        }
        self.ok_runs += o.ok_runs;
        self.failed += o.failed;
        self.failures.extend(o.failures.iter().cloned());
        self.nanos += o.nanos;
    }
}

/// Sums of one chunk: per filter, plus the PCRLB's measurement information.
#[derive(Clone)]
struct Chunk {
    filters: Vec<Acc>,
    info: Vec<Mat6>,
    runs: u32,
}

fn run_chunk(
    prep: &Prepared,
    base: u64,
    runs: std::ops::Range<u64>,
    want_info: bool,
    done: &AtomicU64,
    cancel: &AtomicBool,
) -> Chunk {
    let n = prep.steps + 1;
    let mut c = Chunk {
        filters: vec![Acc::new(n); prep.filters.len()],
        info: if want_info {
            vec![Mat6::zeros(); n]
        } else {
            Vec::new()
        },
        runs: 0,
    };
    let mut scores = Vec::with_capacity(n);
    for i in runs {
        if cancel.load(Ordering::Relaxed) {
            break;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(run_seed(base, i));
        let (truth, meas) = prep.simulate_truth(&mut rng);
        if want_info {
            for (k, x) in truth.iter().enumerate() {
                if prep.measured[k] {
                    c.info[k] += pcrlb::measurement_information(prep, x);
                }
            }
        }
        for (fi, f) in prep.filters.iter().enumerate() {
            let t0 = Instant::now();
            let filter_seed = run_seed(base ^ 0x5046_5F53_4545_4453, i * 64 + fi as u64);
            let r = run_filter(prep, f, &truth, &meas, filter_seed, &mut scores);
            c.filters[fi].nanos += t0.elapsed().as_nanos();
            match r {
                Ok(()) => c.filters[fi].add_run(&scores),
                Err(e) => {
                    c.filters[fi].failed += 1;
                    c.filters[fi].failures.push(format!("run {i}: {e}"));
                }
            }
        }
        c.runs += 1;
        done.fetch_add(1, Ordering::Relaxed);
    }
    c
}

/// Run a scenario's campaign.
pub fn run(scenario: &Scenario, opts: &Options) -> Result<McResult, String> {
    let prep = Prepared::new(scenario)?;
    let runs = opts.runs.unwrap_or(scenario.simulation.runs).max(1) as u64;
    let base = scenario.simulation.seed;
    let want_info = pcrlb::undefined_reason(&prep).is_none();
    let done = Arc::new(AtomicU64::new(0));
    let cancel = opts
        .cancel
        .clone()
        .unwrap_or_else(|| Arc::new(AtomicBool::new(false)));
    let chunks: Vec<std::ops::Range<u64>> = (0..runs)
        .step_by(CHUNK)
        .map(|s| s..(s + CHUNK as u64).min(runs))
        .collect();
    let work = || -> Vec<Chunk> {
        chunks
            .par_iter()
            .map(|r| run_chunk(&prep, base, r.clone(), want_info, &done, &cancel))
            .collect()
    };
    let results = std::thread::scope(|scope| -> Result<Vec<Chunk>, String> {
        let finished = Arc::new(AtomicBool::new(false));
        if opts.progress {
            let (done, finished) = (done.clone(), finished.clone());
            let label = scenario.name.clone();
            scope.spawn(move || progress(&label, runs, &done, &finished));
        }
        let out = if opts.threads > 0 {
            rayon::ThreadPoolBuilder::new()
                .num_threads(opts.threads)
                .build()
                .map_err(|e| format!("thread pool: {e}"))?
                .install(work)
        } else {
            work()
        };
        finished.store(true, Ordering::Relaxed);
        Ok(out)
    })?;
    // reduce in chunk order: deterministic whatever the thread count
    let n = prep.steps + 1;
    let mut total = Chunk {
        filters: vec![Acc::new(n); prep.filters.len()],
        info: vec![Mat6::zeros(); if want_info { n } else { 0 }],
        runs: 0,
    };
    for c in &results {
        for (a, b) in total.filters.iter_mut().zip(&c.filters) {
            a.merge(b);
        }
        for (a, b) in total.info.iter_mut().zip(&c.info) {
            *a += b;
        }
        total.runs += c.runs;
    }
    let m = f64::from(total.runs.max(1));
    let mean_info: Vec<Mat6> = total.info.iter().map(|i| i / m).collect();
    let pcrlb = if want_info {
        pcrlb::recursion(&prep, &mean_info)
    } else {
        Err(pcrlb::undefined_reason(&prep).unwrap_or_default())
    };
    let filters = prep
        .filters
        .iter()
        .zip(&total.filters)
        .map(|(f, a)| {
            let r = f64::from(a.ok_runs.max(1));
            let steps_total = (a.ok_runs + a.failed).max(1) as f64 * n as f64;
            FilterStats {
                label: f.label.clone(),
                kind: f.kind.clone(),
                mse: a.sum.iter().map(|s| s.map(|v| v / r)).collect(),
                nees: a.nees.iter().map(|v| v / r).collect(),
                nis: a
                    .nis
                    .iter()
                    .zip(&a.nis_n)
                    .map(|(s, c)| if *c > 0 { s / f64::from(*c) } else { f64::NAN })
                    .collect(),
                nis_count: a.nis_n.clone(),
                max_pos_err: a.max_pos.clone(),
                max_vel_err: a.max_vel.clone(),
                failed_runs: a.failed,
                us_per_step: a.nanos as f64 / 1e3 / steps_total,
            }
        })
        .collect();
    Ok(McResult {
        scenario: scenario.name.clone(),
        title: scenario.title.clone(),
        t: prep.times(),
        runs: total.runs,
        interrupted: u64::from(total.runs) < runs,
        filters,
        pcrlb,
        convergence_time: scenario.simulation.convergence_time,
        convergence_threshold: (
            scenario.simulation.convergence_threshold[0],
            scenario.simulation.convergence_threshold[1],
        ),
        published: scenario
            .published
            .iter()
            .map(|p| (p.filter.clone(), p.figure.clone()))
            .collect(),
        unreported_burns: match &scenario.thrust {
            Thrust::Burns {
                burns,
                reported: false,
            } => {
                let mut w: Vec<(f64, f64)> = burns.iter().map(|b| (b.start, b.stop)).collect();
                w.sort_by(|a, b| a.0.total_cmp(&b.0));
                w
            }
            _ => Vec::new(),
        },
    })
}

/// A progress bar that appears only once the campaign has lasted a second.
fn progress(label: &str, total: u64, done: &AtomicU64, finished: &AtomicBool) {
    let start = Instant::now();
    let mut bar: Option<indicatif::ProgressBar> = None;
    while !finished.load(Ordering::Relaxed) {
        std::thread::sleep(std::time::Duration::from_millis(100));
        if bar.is_none() && start.elapsed().as_secs_f64() > 1.0 {
            let b = indicatif::ProgressBar::new(total);
            if let Ok(style) = indicatif::ProgressStyle::with_template(
                "{prefix} [{bar:40}] {pos}/{len} runs, {elapsed} elapsed, eta {eta}",
            ) {
                b.set_style(style.progress_chars("=> "));
            }
            b.set_prefix(label.to_string());
            bar = Some(b);
        }
        if let Some(b) = &bar {
            b.set_position(done.load(Ordering::Relaxed));
        }
    }
    if let Some(b) = bar {
        b.finish_and_clear();
    }
}
