//! Tests across the particle filter's modules: the dispatched (AVX2) loops against the
//! baseline path, the fused update pass against the two-pass weights and moments, and the
//! transposed particle copy.

use super::likelihood::Likelihood;
use super::moments::{exp_moments, exp_moments_soa};
use super::resample::{self, normalize_log_weights};
use super::rng::PfRng;
use super::transition::{CwBlocks, Transition};
use super::{ParticleFilter, PfKind, PfParams, N};
use crate::dynamics::{CwModel, Discretization};
use crate::estimators::Estimator;
use crate::noise::NoiseModel;
use crate::numerics::cholesky::chol;
use crate::numerics::moments::{moments, weighted_sum, Moments};
use crate::numerics::soa::{transpose_into, BLOCK};
use crate::sensors::MeasurementModel;
use crate::types::{Mat3, Mat6, State, Vec3};
use rand::SeedableRng;

/// 1003 states (a short last block) around `c`, with the zero-range and far-off states
/// the block paths must hand to their scalar fallbacks.
pub(super) fn test_cloud(c: &Vec3) -> Vec<State> {
    (0..1003)
        .map(|k| {
            let f = |i: usize| ((i * 7 + k * 13) as f64).sin();
            match k % 11 {
                0 => State::zeros(),
                1 => State::new(f(0) * 900.0, f(1) * 900.0, f(2) * 900.0, 0.0, 0.0, 0.0),
                _ => State::new(c.x + f(0), c.y + f(1), c.z + f(2), f(3), f(4), f(5)),
            }
        })
        .collect()
}

/// The hot loops run through `simd::dispatch` (AVX2 where the CPU has it) give the
/// same bits as the baseline path: the transition (particles, means, generator), the
/// block likelihood, the moments, the weighted sum and the normalised weights.
#[test]
fn dispatched_loops_equal_baseline_bitwise() {
    use crate::numerics::simd::with_baseline;
    use crate::sensors::RadioSensor;
    let bits = |v: &[State]| -> Vec<u64> {
        v.iter()
            .flat_map(|s| s.iter().map(|x| x.to_bits()))
            .collect()
    };
    let fbits = |v: &[f64]| -> Vec<u64> { v.iter().map(|x| x.to_bits()).collect() };
    let m = CwModel::new(2.0 * core::f64::consts::PI / 5400.0);
    let mut d = m.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    d.q += Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
    let l = chol(&d.q).expect("pd");
    let c = Vec3::new(400.0, 500.0, -200.0);
    // 1003: a short last block
    let x = test_cloud(&c);
    let w: Vec<f64> = (0..x.len()).map(|k| 1.0 + (k as f64).cos()).collect();
    let s = RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1e-4);
    let z = s.predict(&c).expect("defined") + Vec3::new(0.2, -1e-4, 3e-4);
    let run = || {
        let mut out = Vec::new();
        for diag in [true, false] {
            let tr = Transition {
                blocks: CwBlocks::of(&d.phi),
                phi: d.phi,
                u: State::new(1e-3, 0.0, -2e-3, 0.0, 1e-6, 0.0),
                diag: diag.then(|| l.diagonal()),
                l,
            };
            let mut rng = PfRng::seed_from_u64(3);
            let (mut xn, mut xb) = (vec![State::zeros(); x.len()], vec![State::zeros(); x.len()]);
            let (bad, _) = tr.run(&x, None, &mut xn, &mut xb, None, false, &mut rng);
            out.push((bits(&xn), bits(&xb), bad.to_bits(), rng));
        }
        let lik = Likelihood::new(&s, &z, &NoiseModel::Gaussian, &[0.5, 1e-4, 1e-4]);
        let mut ll = vec![0.0; x.len()];
        lik.log_many(&x, &mut ll);
        let mom = moments(&State::from_element(0.1), &x, &w);
        let (ws, wsum) = weighted_sum(&x, &w);
        let mut wn = vec![0.0; x.len()];
        let lm = normalize_log_weights(&ll, &mut wn);
        // the update pass and the normalisation's exponentials with the moments
        let lw: Vec<f64> = w.iter().map(|v| -v).collect();
        let (mut lwn, mut ll2) = (vec![0.0; x.len()], vec![0.0; x.len()]);
        let max = lik.weigh_many(&x, None, &lw, &mut lwn, &mut ll2);
        let mut ew = vec![0.0; x.len()];
        let (esum, emom) = exp_moments(&State::from_element(0.1), &x, &lwn, max, &mut ew);
        let upd = (fbits(&lwn), fbits(&ll2), max.to_bits(), fbits(&ew));
        let mut soa = vec![[[0.0; BLOCK]; N]; x.len().div_ceil(BLOCK)];
        transpose_into(&x, &mut soa);
        let (ssum, smom) = exp_moments_soa(&State::from_element(0.1), &soa, &lwn, max, &mut ew);
        let em = [esum, emom.wsum, ssum, smom.wsum]
            .into_iter()
            .chain(emom.s1.iter().copied())
            .chain(emom.s2)
            .chain(smom.s1.iter().copied())
            .chain(smom.s2)
            .chain(ew.iter().copied())
            .collect::<Vec<_>>();
        (
            out,
            upd,
            fbits(&em),
            fbits(&ll),
            fbits(mom.s1.as_slice()),
            fbits(&mom.s2),
            mom.wsum.to_bits(),
            fbits(ws.as_slice()),
            wsum.to_bits(),
            fbits(&wn),
            lm.map(f64::to_bits),
        )
    };
    let fast = run();
    let base = with_baseline(run);
    assert!(fast == base);
}

/// The update pass and [`exp_moments`] give the weights of [`normalize_log_weights`]
/// bit for bit (and the same log mean likelihood through
/// [`ParticleFilter::normalise`]'s formula), and the weighted moments of the two-pass
/// form (about the weighted mean) to rounding; merged chunk sums equal them too.
#[test]
fn one_pass_weights_and_moments_equal_the_two_pass_ones() {
    use crate::sensors::RadioSensor;
    let s = RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1e-3);
    let c = Vec3::new(400.0, 500.0, -200.0);
    let z = s.predict(&c).expect("defined") + Vec3::new(0.2, -1e-3, 3e-3);
    let lik = Likelihood::new(&s, &z, &NoiseModel::Gaussian, &[0.5, 1e-3, 1e-3]);
    let x = test_cloud(&c);
    let n = x.len();
    let logw: Vec<f64> = (0..n).map(|k| -((k % 7) as f64) * 0.1).collect();
    let (mut lwn, mut ll) = (vec![0.0; n], vec![0.0; n]);
    let max = lik.weigh_many(&x, None, &logw, &mut lwn, &mut ll);
    assert_eq!(max.to_bits(), resample::max_ignoring_nan(&lwn).to_bits());
    for i in 0..n {
        assert_eq!(ll[i].to_bits(), lik.log(&x[i]).to_bits());
        assert_eq!(lwn[i].to_bits(), (logw[i] + ll[i]).to_bits());
    }
    let mut want = vec![0.0; n];
    let lm = normalize_log_weights(&lwn, &mut want).expect("weights");
    let reference = State::new(c.x + 0.3, c.y - 0.2, c.z + 0.1, 0.0, 0.0, 0.0);
    let mut w = vec![0.0; n];
    let (sum, mom) = exp_moments(&reference, &x, &lwn, max, &mut w);
    let inv = 1.0 / sum;
    w.iter_mut().for_each(|v| *v *= inv);
    assert!(w.iter().zip(&want).all(|(a, b)| a.to_bits() == b.to_bits()));
    assert_eq!((sum.ln() + max - (n as f64).ln()).to_bits(), lm.to_bits());
    // the two-pass moments of the normalised weights about their weighted mean
    let (ms, ws) = weighted_sum(&x, &want);
    let m2 = ms / ws;
    let (_, p2) = moments(&m2, &x, &want).finish();
    let (m1, p1) = mom.mean_cov().expect("finite");
    let scale = p2.abs().max();
    assert!((m1 - m2).abs().max() <= 1e-12 * m2.abs().max(), "{m1} {m2}");
    assert!((p1 - p2).abs().max() <= 1e-12 * scale, "{p1} {p2}");
    // chunk sums merged in order (the parallel path's form)
    let mut acc = Moments::new(reference);
    let mut sum2 = 0.0;
    for ((xs, ls), ws) in x.chunks(100).zip(lwn.chunks(100)).zip(w.chunks_mut(100)) {
        let (s, m) = exp_moments(&reference, xs, ls, max, ws);
        sum2 += s;
        acc.merge(&m);
    }
    let (m3, p3) = acc.mean_cov().expect("finite");
    assert!((sum2 - sum).abs() <= 1e-12 * sum);
    assert!((m3 - m2).abs().max() <= 1e-12 * m2.abs().max());
    assert!((p3 - p2).abs().max() <= 1e-12 * scale);
    // from the transposed copy (lane sums; a short last block whose padding holds
    // garbage): the same weights and sum bit for bit, the moments to rounding
    let mut soa = vec![[[f64::NAN; BLOCK]; N]; n.div_ceil(BLOCK)];
    transpose_into(&x, &mut soa);
    let mut w4 = vec![0.0; n];
    let (sum4, mom4) = exp_moments_soa(&reference, &soa, &lwn, max, &mut w4);
    assert_eq!(sum4.to_bits(), sum.to_bits());
    assert_eq!(mom4.wsum.to_bits(), sum.to_bits());
    w4.iter_mut().for_each(|v| *v *= inv);
    assert!(w4
        .iter()
        .zip(&want)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    let (m4, p4) = mom4.mean_cov().expect("finite");
    assert!((m4 - m2).abs().max() <= 1e-12 * m2.abs().max(), "{m4} {m2}");
    assert!((p4 - p2).abs().max() <= 1e-12 * scale, "{p4} {p2}");
}

/// The particles kept transposed beside `x` (`soa`: read by the next weighting and
/// transition instead of transposing `x`) change no bit: a filter that never reads them
/// (its `soa_fresh` cleared before every step) draws the same particles and weights, on
/// the literal transition kinds and with moves, with a short last block.
#[test]
fn transposed_particles_change_no_bit() {
    use crate::sensors::RadioSensor;
    let m = CwModel::new(2.0 * core::f64::consts::PI / 5400.0);
    let mut d = m.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    d.q += Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
    let s = RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1e-3);
    let truth = State::new(400.0, 500.0, -200.0, 0.1, -0.05, 0.02);
    let p0 = Mat6::from_diagonal(&State::new(100.0, 100.0, 100.0, 0.01, 0.01, 0.01));
    for (kind, moves) in [
        (PfKind::Sir, false),
        (PfKind::Rpf, false),
        (PfKind::Gapf, false),
        (PfKind::Sir, true),
    ] {
        let params = PfParams {
            particles: 100,
            seed: 11,
            moves,
            ..PfParams::new(kind)
        };
        let mut a = ParticleFilter::new(truth, p0, params);
        let mut b = ParticleFilter::new(truth, p0, params);
        let mut x = truth;
        for _ in 0..12 {
            x = d.phi * x;
            let z = s
                .predict(&x.fixed_rows::<3>(0).into_owned())
                .expect("a measurement");
            a.predict(&d, &Vec3::zeros()).expect("predict");
            b.soa_fresh = false;
            b.predict(&d, &Vec3::zeros()).expect("predict");
            a.update(&s, &z).expect("update");
            b.soa_fresh = false;
            b.update(&s, &z).expect("update");
            assert!(a.state() == b.state(), "{kind:?} moves {moves}");
        }
        let (pa, wa) = a.particles();
        let (pa, wa) = (pa.to_vec(), wa.to_vec());
        let (pb, wb) = b.particles();
        assert!(pa == pb && wa == wb, "{kind:?} moves {moves}");
        assert!(a.resample_count() > 0, "{kind:?} moves {moves}");
    }
}
