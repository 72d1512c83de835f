//! Monte Carlo campaigns: runs in parallel (rayon), results independent of the thread
//! count, a progress bar for anything longer than a second, and Ctrl-C to stop early.
//!
//! Determinism: run `i` draws everything from `ChaCha8Rng::seed_from_u64(run_seed(base,
//! i))` (SplitMix64 of the base seed and the run index), so a run's numbers do not depend
//! on which thread does it. Runs are reduced in fixed chunks of [`CHUNK`] in run order and
//! the chunks are combined in order, so even the floating-point sums are identical for
//! any thread count.
//!
//! The same chunks can run anywhere: [`Campaign`] runs one chunk into a [`Partial`]
//! (serialisable bytes) and a [`Reducer`] adds them in chunk order — [`run`] is exactly
//! that on this machine's threads, and the Python package's Dask campaigns the same on a
//! cluster, so both give bit-identical results.

use crate::pcrlb;
use crate::results::{FilterStats, McResult};
use crate::scenario::{Scenario, Thrust};
use crate::sim::{run_filter, Prepared, Score};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use relnav_core::types::Mat6;
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
    /// squared range error and reported range variance
    range: Vec<[f64; 2]>,
    ok_runs: u32,
    failed: u32,
    failures: Vec<String>,
    nanos: u128,
    /// a particle filter's moves over the ok runs: tried, accepted
    moves: [u64; 2],
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
            range: vec![[0.0; 2]; n],
            ok_runs: 0,
            failed: 0,
            failures: Vec::new(),
            nanos: 0,
            moves: [0; 2],
        }
    }
    fn add_run(&mut self, s: &[Score], (tried, accepted): (u64, u64)) {
        self.moves[0] += tried;
        self.moves[1] += accepted;
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
            self.range[k][0] += v[10];
            self.range[k][1] += v[11];
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
            self.range[k][0] += o.range[k][0];
            self.range[k][1] += o.range[k][1];
        }
        self.ok_runs += o.ok_runs;
        self.failed += o.failed;
        self.failures.extend(o.failures.iter().cloned());
        self.nanos += o.nanos;
        self.moves[0] += o.moves[0];
        self.moves[1] += o.moves[1];
    }
}

/// Sums of one chunk: per filter, plus the PCRLB's measurement information and the sum of
/// the runs' own bounds (diagonal, I/O frame; and the range's, along each run's own line
/// of sight) with the number of runs in it.
#[derive(Clone)]
struct Chunk {
    filters: Vec<Acc>,
    info: Vec<Mat6>,
    run_bound: Vec<[f64; 6]>,
    run_range_bound: Vec<f64>,
    bound_runs: u32,
    runs: u32,
}

impl Chunk {
    /// Add another chunk's sums (the order of calls fixes the floating-point result).
    fn merge(&mut self, o: &Chunk) {
        for (a, b) in self.filters.iter_mut().zip(&o.filters) {
            a.merge(b);
        }
        for (a, b) in self.info.iter_mut().zip(&o.info) {
            *a += b;
        }
        for (a, b) in self.run_bound.iter_mut().zip(&o.run_bound) {
            for (x, y) in a.iter_mut().zip(b) {
                *x += y;
            }
        }
        for (a, b) in self.run_range_bound.iter_mut().zip(&o.run_range_bound) {
            *a += b;
        }
        self.bound_runs += o.bound_runs;
        self.runs += o.runs;
    }
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
        run_bound: if want_info {
            vec![[0.0; 6]; n]
        } else {
            Vec::new()
        },
        run_range_bound: if want_info { vec![0.0; n] } else { Vec::new() },
        bound_runs: 0,
        runs: 0,
    };
    let mut run_info = Vec::with_capacity(if want_info { n } else { 0 });
    let mut scores = Vec::with_capacity(n);
    for i in runs {
        if cancel.load(Ordering::Relaxed) {
            break;
        }
        let mut rng = ChaCha8Rng::seed_from_u64(run_seed(base, i));
        let run = prep.simulate_truth(&mut rng);
        if want_info {
            run_info.clear();
            for (k, x) in run.states.iter().enumerate() {
                let mut info = Mat6::zeros();
                if prep.primary_measures(k, x) {
                    info += pcrlb::measurement_information(prep, x);
                }
                for (i, s) in prep.sensors.iter().enumerate() {
                    if run.extra[i][k].is_some() {
                        info += pcrlb::sensor_information(s, x);
                    }
                }
                c.info[k] += info;
                run_info.push(info);
            }
            // (a run whose own recursion fails numerically is left out of the mean)
            if let Ok(b) = pcrlb::bounds(prep, &run_info) {
                let frame = prep.scenario.io_frame();
                for (k, jinv) in b.iter().enumerate() {
                    let io = frame.cov_from_canonical(jinv);
                    for (i, x) in c.run_bound[k].iter_mut().enumerate() {
                        *x += io[(i, i)];
                    }
                    let r = run.states[k].fixed_rows::<3>(0);
                    let u = r / r.norm();
                    c.run_range_bound[k] +=
                        (u.transpose() * jinv.fixed_view::<3, 3>(0, 0) * u)[(0, 0)];
                }
                c.bound_runs += 1;
            }
        }
        for (fi, f) in prep.filters.iter().enumerate() {
            let t0 = Instant::now();
            let filter_seed = run_seed(base ^ 0x5046_5F53_4545_4453, i * 64 + fi as u64);
            let r = run_filter(prep, f, &run, filter_seed, &mut scores);
            c.filters[fi].nanos += t0.elapsed().as_nanos();
            match r {
                Ok(moves) => c.filters[fi].add_run(&scores, moves),
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

/// A campaign ready to run: the prepared scenario, the run count, the base seed and the
/// fixed chunks of [`CHUNK`] runs, in run order.
///
/// This is the engine behind [`run`] and the entry point for running a campaign
/// elsewhere (the Python package's Dask campaigns): [`Campaign::run_chunk`] computes one
/// chunk's sums ([`Partial`], serialisable with [`Partial::to_bytes`]) on any machine,
/// and a [`Reducer`] adds them **in chunk order**, so the floating-point sums — and the
/// result — are bit-identical to [`run`]'s for any number of threads or machines.
pub struct Campaign {
    prep: Prepared,
    base: u64,
    runs: u64,
    want_info: bool,
    chunks: Vec<std::ops::Range<u64>>,
}

impl Campaign {
    /// Prepare `scenario` for `runs` runs (default: the scenario's own count, at least 1).
    pub fn new(scenario: &Scenario, runs: Option<u32>) -> Result<Self, String> {
        let prep = Prepared::new(scenario)?;
        let runs = runs.unwrap_or(scenario.simulation.runs).max(1) as u64;
        let want_info = pcrlb::undefined_reason(&prep).is_none();
        let chunks = (0..runs)
            .step_by(CHUNK)
            .map(|s| s..(s + CHUNK as u64).min(runs))
            .collect();
        Ok(Self {
            base: scenario.simulation.seed,
            prep,
            runs,
            want_info,
            chunks,
        })
    }

    /// Requested number of runs.
    pub fn runs(&self) -> u64 {
        self.runs
    }

    /// The chunks (ranges of run indices), in the order they are reduced.
    pub fn chunks(&self) -> &[std::ops::Range<u64>] {
        &self.chunks
    }

    /// The prepared scenario.
    pub fn prepared(&self) -> &Prepared {
        &self.prep
    }

    /// Run chunk `index` (runs `chunks()[index]`, each seeded from its run index alone).
    /// `done` counts finished runs; when `cancel` is set, the chunk stops before its next
    /// run and the partial sums hold fewer runs.
    pub fn run_chunk(
        &self,
        index: usize,
        done: &AtomicU64,
        cancel: &AtomicBool,
    ) -> Result<Partial, String> {
        let range = self.chunks.get(index).cloned().ok_or_else(|| {
            format!(
                "chunk {index} does not exist (the campaign has {} chunks)",
                self.chunks.len()
            )
        })?;
        Ok(Partial {
            index: index as u64,
            range: range.clone(),
            base: self.base,
            chunk: run_chunk(&self.prep, self.base, range, self.want_info, done, cancel),
        })
    }

    /// An empty reducer for this campaign's partial sums.
    pub fn reducer(&self) -> Reducer {
        let n = self.prep.steps + 1;
        Reducer {
            total: Chunk {
                filters: vec![Acc::new(n); self.prep.filters.len()],
                info: vec![Mat6::zeros(); if self.want_info { n } else { 0 }],
                run_bound: vec![[0.0; 6]; if self.want_info { n } else { 0 }],
                run_range_bound: vec![0.0; if self.want_info { n } else { 0 }],
                bound_runs: 0,
                runs: 0,
            },
            next: 0,
        }
    }

    /// Check that `p` is chunk `reducer.next_index()` of this campaign.
    fn check(&self, p: &Partial, next: usize) -> Result<(), String> {
        let n = self.prep.steps + 1;
        let want = self.chunks.get(next);
        if p.index != next as u64 || want != Some(&p.range) || p.base != self.base {
            return Err(format!(
                "partial sums out of order or from another campaign: expected chunk {next} \
                 (runs {want:?}, seed {}), got chunk {} (runs {:?}, seed {})",
                self.base, p.index, p.range, p.base
            ));
        }
        let dims_ok = p.chunk.filters.len() == self.prep.filters.len()
            && p.chunk.filters.iter().all(|a| a.sum.len() == n)
            && p.chunk.info.len() == if self.want_info { n } else { 0 };
        if !dims_ok {
            return Err(format!(
                "partial sums of chunk {next} do not fit this campaign (filters or steps differ)"
            ));
        }
        Ok(())
    }

    /// The campaign's result from the reduced sums (chunks not added count as not run:
    /// the result is then marked interrupted).
    pub fn finish(&self, reducer: Reducer) -> McResult {
        summarize_total(&self.prep, self.runs, self.want_info, &reducer.total)
    }
}

/// Adds partial sums in chunk order (see [`Campaign`]).
pub struct Reducer {
    total: Chunk,
    next: usize,
}

impl Reducer {
    /// Add the next chunk's sums; refused (nothing changes) unless `p` is chunk
    /// [`Reducer::next_index`] of `campaign`.
    pub fn add(&mut self, campaign: &Campaign, p: &Partial) -> Result<(), String> {
        campaign.check(p, self.next)?;
        self.total.merge(&p.chunk);
        self.next += 1;
        Ok(())
    }

    /// Index of the chunk [`Reducer::add`] expects next (= chunks added so far).
    pub fn next_index(&self) -> usize {
        self.next
    }

    /// Runs added so far.
    pub fn runs(&self) -> u32 {
        self.total.runs
    }
}

/// The sums of one chunk of runs ([`Campaign::run_chunk`]), with the chunk it belongs to.
#[derive(Clone)]
pub struct Partial {
    index: u64,
    range: std::ops::Range<u64>,
    base: u64,
    chunk: Chunk,
}

/// First bytes of [`Partial::to_bytes`] (format name and version).
const PARTIAL_MAGIC: &[u8; 8] = b"RNPART04";

impl Partial {
    /// Index of the chunk.
    pub fn index(&self) -> usize {
        self.index as usize
    }

    /// Runs completed in this chunk.
    pub fn runs(&self) -> u32 {
        self.chunk.runs
    }

    /// A self-describing little-endian encoding (every `f64` by its bit pattern, so
    /// [`Partial::from_bytes`] gives back exactly the same sums).
    pub fn to_bytes(&self) -> Vec<u8> {
        let c = &self.chunk;
        let n = c.filters.first().map_or(c.info.len(), |a| a.sum.len());
        let mut w = Vec::with_capacity(64 + c.filters.len() * n * 14 * 8 + c.info.len() * 296);
        w.extend_from_slice(PARTIAL_MAGIC);
        for v in [self.index, self.range.start, self.range.end, self.base] {
            w.extend_from_slice(&v.to_le_bytes());
        }
        for v in [
            c.runs,
            n as u32,
            c.filters.len() as u32,
            c.info.len() as u32,
            c.bound_runs,
        ] {
            w.extend_from_slice(&v.to_le_bytes());
        }
        let f64s = |w: &mut Vec<u8>, v: &mut dyn Iterator<Item = f64>| {
            for x in v {
                w.extend_from_slice(&x.to_le_bytes());
            }
        };
        for a in &c.filters {
            f64s(&mut w, &mut a.sum.iter().flatten().copied());
            f64s(&mut w, &mut a.nees.iter().copied());
            f64s(&mut w, &mut a.nis.iter().copied());
            for x in &a.nis_n {
                w.extend_from_slice(&x.to_le_bytes());
            }
            f64s(&mut w, &mut a.max_pos.iter().copied());
            f64s(&mut w, &mut a.max_vel.iter().copied());
            f64s(&mut w, &mut a.range.iter().flatten().copied());
            for x in [a.ok_runs, a.failed, a.failures.len() as u32] {
                w.extend_from_slice(&x.to_le_bytes());
            }
            w.extend_from_slice(&a.nanos.to_le_bytes());
            for x in a.moves {
                w.extend_from_slice(&x.to_le_bytes());
            }
            for f in &a.failures {
                w.extend_from_slice(&(f.len() as u32).to_le_bytes());
                w.extend_from_slice(f.as_bytes());
            }
        }
        for m in &c.info {
            f64s(&mut w, &mut m.iter().copied());
        }
        f64s(&mut w, &mut c.run_bound.iter().flatten().copied());
        f64s(&mut w, &mut c.run_range_bound.iter().copied());
        w
    }

    /// Decode [`Partial::to_bytes`]; the error says what does not fit.
    pub fn from_bytes(bytes: &[u8]) -> Result<Self, String> {
        let mut r = ByteReader { bytes, pos: 0 };
        if r.take(8)? != PARTIAL_MAGIC {
            return Err("not relnav partial sums (bad magic or another format version)".into());
        }
        let (index, start, end, base) = (r.u64()?, r.u64()?, r.u64()?, r.u64()?);
        let (runs, n, nf, ni) = (r.u32()?, r.u32()? as usize, r.u32()?, r.u32()? as usize);
        let bound_runs = r.u32()?;
        if ni != 0 && ni != n {
            return Err(format!(
                "partial sums: {ni} information matrices for {n} times"
            ));
        }
        // every filter needs at least 14 n values: refuse sizes the input cannot hold
        if (nf as usize).saturating_mul(n).saturating_mul(14 * 4) > bytes.len() {
            return Err("partial sums: truncated".into());
        }
        let mut filters = Vec::with_capacity(nf as usize);
        for _ in 0..nf {
            let mut a = Acc::new(n);
            for s in a.sum.iter_mut().flatten() {
                *s = r.f64()?;
            }
            for v in [&mut a.nees, &mut a.nis] {
                for x in v.iter_mut() {
                    *x = r.f64()?;
                }
            }
            for x in a.nis_n.iter_mut() {
                *x = r.u32()?;
            }
            for v in [&mut a.max_pos, &mut a.max_vel] {
                for x in v.iter_mut() {
                    *x = r.f64()?;
                }
            }
            for x in a.range.iter_mut().flatten() {
                *x = r.f64()?;
            }
            let (ok, failed, nfail) = (r.u32()?, r.u32()?, r.u32()?);
            a.ok_runs = ok;
            a.failed = failed;
            a.nanos = u128::from_le_bytes(r.array()?);
            a.moves = [r.u64()?, r.u64()?];
            for _ in 0..nfail {
                let len = r.u32()? as usize;
                a.failures
                    .push(String::from_utf8_lossy(r.take(len)?).into_owned());
            }
            filters.push(a);
        }
        let mut info = Vec::with_capacity(ni);
        for _ in 0..ni {
            let mut m = Mat6::zeros();
            for x in m.iter_mut() {
                *x = r.f64()?;
            }
            info.push(m);
        }
        let mut run_bound = vec![[0.0; 6]; ni];
        for x in run_bound.iter_mut().flatten() {
            *x = r.f64()?;
        }
        let mut run_range_bound = vec![0.0; ni];
        for x in run_range_bound.iter_mut() {
            *x = r.f64()?;
        }
        if r.pos != bytes.len() {
            return Err(format!(
                "partial sums: {} trailing bytes",
                bytes.len() - r.pos
            ));
        }
        Ok(Partial {
            index,
            range: start..end,
            base,
            chunk: Chunk {
                filters,
                info,
                run_bound,
                run_range_bound,
                bound_runs,
                runs,
            },
        })
    }
}

/// Cursor over the bytes of [`Partial::from_bytes`].
struct ByteReader<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> ByteReader<'a> {
    fn take(&mut self, k: usize) -> Result<&'a [u8], String> {
        let s = self
            .pos
            .checked_add(k)
            .and_then(|e| self.bytes.get(self.pos..e))
            .ok_or("partial sums: truncated")?;
        self.pos += k;
        Ok(s)
    }
    fn array<const K: usize>(&mut self) -> Result<[u8; K], String> {
        let mut a = [0u8; K];
        a.copy_from_slice(self.take(K)?);
        Ok(a)
    }
    fn u32(&mut self) -> Result<u32, String> {
        Ok(u32::from_le_bytes(self.array()?))
    }
    fn u64(&mut self) -> Result<u64, String> {
        Ok(u64::from_le_bytes(self.array()?))
    }
    fn f64(&mut self) -> Result<f64, String> {
        Ok(f64::from_le_bytes(self.array()?))
    }
}

/// Run a scenario's campaign on this machine's threads: [`Campaign::run_chunk`] for every
/// chunk in parallel (rayon), then a [`Reducer`] in chunk order.
pub fn run(scenario: &Scenario, opts: &Options) -> Result<McResult, String> {
    let campaign = Campaign::new(scenario, opts.runs)?;
    let runs = campaign.runs();
    let done = Arc::new(AtomicU64::new(0));
    let cancel = opts
        .cancel
        .clone()
        .unwrap_or_else(|| Arc::new(AtomicBool::new(false)));
    let work = || -> Result<Vec<Partial>, String> {
        (0..campaign.chunks().len())
            .into_par_iter()
            .map(|i| campaign.run_chunk(i, &done, &cancel))
            .collect()
    };
    let results = std::thread::scope(|scope| -> Result<Vec<Partial>, String> {
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
                .map_err(|e| format!("thread pool: {e}"))
                .and_then(|pool| pool.install(work))
        } else {
            work()
        };
        finished.store(true, Ordering::Relaxed);
        out
    })?;
    // reduce in chunk order: deterministic whatever the thread count
    let mut reducer = campaign.reducer();
    for p in &results {
        reducer.add(&campaign, p)?;
    }
    Ok(campaign.finish(reducer))
}

/// The campaign's statistics from the sums over all runs.
fn summarize_total(prep: &Prepared, runs: u64, want_info: bool, total: &Chunk) -> McResult {
    let scenario = &prep.scenario;
    let n = prep.steps + 1;
    let m = f64::from(total.runs.max(1));
    let mean_info: Vec<Mat6> = total.info.iter().map(|i| i / m).collect();
    let pcrlb = if want_info {
        pcrlb::recursion(prep, &mean_info)
    } else {
        Err(pcrlb::undefined_reason(prep).unwrap_or_default())
    };
    let pcrlb_runs = match (&pcrlb, total.bound_runs) {
        (Err(e), _) => Err(e.clone()),
        (Ok(_), 0) => Err("no run's own recursion succeeded".into()),
        (Ok(_), b) => {
            let b = f64::from(b);
            Ok(total.run_bound.iter().map(|v| v.map(|x| x / b)).collect())
        }
    };
    let range_bound_runs = match (&pcrlb_runs, total.bound_runs) {
        (Ok(_), b) if b > 0 => total
            .run_range_bound
            .iter()
            .map(|v| v / f64::from(b))
            .collect(),
        _ => Vec::new(),
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
                range_mse: a.range.iter().map(|v| v[0] / r).collect(),
                range_var: a.range.iter().map(|v| v[1] / r).collect(),
                failed_runs: a.failed,
                us_per_step: a.nanos as f64 / 1e3 / steps_total,
                move_acceptance: if a.moves[0] > 0 {
                    a.moves[1] as f64 / a.moves[0] as f64
                } else {
                    f64::NAN
                },
            }
        })
        .collect();
    McResult {
        nis_dof: prep.nis_dof() as u32,
        scenario: scenario.name.clone(),
        title: scenario.title.clone(),
        t: prep.times(),
        runs: total.runs,
        interrupted: u64::from(total.runs) < runs,
        filters,
        pcrlb,
        pcrlb_runs,
        range_bound_runs,
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
    }
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
