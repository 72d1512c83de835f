use super::super::{ParticleFilter, PfKind, PfParams};
use crate::dynamics::{CwModel, Discretization};
use crate::estimators::Estimator;
use crate::numerics::simd;
use crate::sensors::RadioSensor;
use crate::types::{Mat3, Mat6, State, Vec3};
use rand::SeedableRng;

/// The particles' bits (and the move counts) after a few steps on a paper-000-like
/// model, with the moves' blocks on whichever path [`simd::dispatch`] takes.
fn run(kind: PfKind, moves: bool) -> (Vec<u64>, f64) {
    let model = CwModel::new(0.001_1);
    let mut d = model.discretize(1.0, &Mat3::zeros(), Discretization::Exact);
    d.q += Mat6::from_diagonal(&State::new(0.09, 6.25e-4, 2.5e-3, 1e-6, 1e-6, 1e-6));
    let f = crate::frames::Frame::AlongRadialAntinormal;
    let sensor = RadioSensor::new(f, 0.5, 1e-3);
    let x0 = State::new(400.0, 500.0, 200.0, 0.0, 0.0, 0.0);
    let params = PfParams {
        particles: 700,
        seed: 3,
        threads: 1,
        moves,
        ..PfParams::new(kind)
    };
    let p0 = Mat6::from_diagonal(&State::new(400.0, 400.0, 400.0, 1e-2, 1e-2, 1e-2));
    let mut pf = ParticleFilter::new(x0 + State::from_element(5.0), p0, params);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    for k in 0..8 {
        let x = model.phi(k as f64) * x0;
        let z = sensor
            .measure(&x.fixed_rows::<3>(0).into_owned(), &mut rng)
            .expect("defined");
        pf.update(&sensor, &z).expect("update");
        pf.predict(&d, &Vec3::zeros()).expect("predict");
    }
    let (x, w) = pf.particles();
    let bits = x
        .iter()
        .flat_map(|xi| xi.iter().map(|v| v.to_bits()).collect::<Vec<_>>())
        .chain(w.iter().map(|v| v.to_bits()))
        .collect();
    (bits, pf.move_acceptance())
}

/// The cloud mutation's Hastings term `q + ln r` of `hastings_cloud` equals the sum of
/// the folded-normal step log-densities it replaces,
/// `sum_k [ln phi_k(s_k / reach_back) - ln reach_back - ln phi_k(s_k / reach) + ln reach]`
/// over the components with `He_k > 0`, for steps drawn as the mutation draws them.
#[test]
#[allow(clippy::needless_range_loop)]
fn hastings_ratio_equals_the_step_densities() {
    use super::{hastings_cloud, Block, B};
    use rand::Rng;
    fn log_step_density(step: f64, reach: f64, en: f64, he: f64) -> f64 {
        let y = step / reach;
        let a = (y - en) / he;
        let b = (y + en) / he;
        ((-0.5 * a * a).exp() + (-0.5 * b * b).exp()).ln() - reach.ln()
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    for case in 0..400 {
        let en: [f64; 6] =
            core::array::from_fn(|k| 10f64.powf(rng.random_range(-3.0..2.0)) * (k + 1) as f64);
        let he: [f64; 6] = core::array::from_fn(|k| {
            if case % 7 == 0 && k == 2 {
                0.0
            } else {
                en[k] / rng.random_range(3.0..5.0)
            }
        });
        let live: [bool; 6] = core::array::from_fn(|k| he[k] > 0.0);
        let mut l = Block::new(B, 0.0, 0.0);
        let mut ln_mu_back = [0.0; B];
        for lane in 0..B {
            let mu: f64 = rng.random_range(0.2..0.95);
            let mu_back: f64 = rng.random_range(0.2..0.95);
            l.aux[lane] = mu.ln();
            l.reach[lane] = (-2.0 * mu.ln()).sqrt();
            ln_mu_back[lane] = mu_back.ln();
            for k in 0..6 {
                let x = rng.random_range(-500.0..500.0);
                let g: f64 = rng.sample(rand_distr::StandardNormal);
                let sign = if rng.random::<bool>() { 1.0 } else { -1.0 };
                l.x[k][lane] = x;
                l.c[k][lane] = x + sign * (en[k] + he[k] * g).abs() * l.reach[lane];
            }
        }
        let (q, r) = hastings_cloud(&l, &ln_mu_back, &en, &he, &live);
        for lane in 0..B {
            let reach_back = (-2.0 * ln_mu_back[lane]).sqrt();
            let mut want = 0.0;
            for k in (0..6).filter(|&k| live[k]) {
                let step = (l.c[k][lane] - l.x[k][lane]).abs();
                want += log_step_density(step, reach_back, en[k], he[k])
                    - log_step_density(step, l.reach[lane], en[k], he[k]);
            }
            let got = q[lane] + r[lane].ln();
            if want.is_finite() {
                assert!(
                    (got - want).abs() <= 1e-9 * (1.0 + want.abs()),
                    "{got} {want}"
                );
            } else {
                // the reverse step's density underflows in the old form: the ratio is 0
                assert!(want == f64::NEG_INFINITY && got < -700.0, "{got} {want}");
            }
        }
    }
}

/// The genetic operators' blocks give the same bits on the dispatched (AVX2) and the
/// baseline path, and they run (some moves tried and accepted).
#[test]
fn dispatched_and_baseline_operators_agree_bit_for_bit() {
    for kind in [PfKind::Gapf, PfKind::Cgapf] {
        for moves in [false, true] {
            let (fast, acc) = run(kind, moves);
            let (base, acc_base) = simd::with_baseline(|| run(kind, moves));
            assert!(acc > 0.0 && acc < 1.0, "{kind:?} {moves}: acceptance {acc}");
            assert_eq!(acc.to_bits(), acc_base.to_bits());
            assert!(fast == base, "{kind:?} moves {moves}: paths differ");
        }
    }
}

/// The literal filters' target is the likelihood alone: its predictive term is zero for
/// every candidate (centred or as a difference), where the moves' Gaussian predictive is
/// not; the likelihood term is the same in both.
#[test]
fn literal_target_is_the_likelihood_alone() {
    use super::target::Target;
    use super::B;
    use crate::estimators::pf::likelihood::Likelihood;
    use crate::noise::NoiseModel;
    let sensor = RadioSensor::new(crate::frames::Frame::AlongRadialAntinormal, 0.5, 1e-3);
    let noise = NoiseModel::Gaussian;
    let z = Vec3::new(640.0, 0.9, 0.3);
    let lik = Likelihood::new(&sensor, &z, &noise, &[1.0; 3]);
    let m = State::new(400.0, 500.0, 200.0, 0.0, 0.0, 0.0);
    let l = Mat6::from_diagonal(&State::new(5.0, 5.0, 5.0, 0.1, 0.1, 0.1));
    let c: [[f64; B]; 6] =
        core::array::from_fn(|k| core::array::from_fn(|i| m[k] + (i * (k + 1)) as f64));
    let (mut u, mut flat, mut gauss) = ([[0.0; B]; 6], [1.0; B], [0.0; B]);
    let literal = Target::<_, 3>::likelihood_only(&lik);
    let moved = Target::<_, 3>::new(&lik, &m, &l);
    literal.log_predictive::<B, true>(&c, &mut u, &mut flat);
    assert!(flat.iter().all(|&v| v == 0.0), "{flat:?}");
    literal.log_predictive::<B, false>(&c, &mut u, &mut flat);
    assert!(flat.iter().all(|&v| v == 0.0), "{flat:?}");
    moved.log_predictive::<B, true>(&c, &mut u, &mut gauss);
    assert!(gauss[1..].iter().all(|&v| v < 0.0), "{gauss:?}");
    let (mut ll_literal, mut ll_moved) = ([0.0; B], [0.0; B]);
    literal.log_likelihood(&c, B, &mut ll_literal);
    moved.log_likelihood(&c, B, &mut ll_moved);
    assert_eq!(ll_literal, ll_moved);
}
