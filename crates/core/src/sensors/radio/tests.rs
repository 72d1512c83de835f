use super::*;
use core::f64::consts::TAU;
use rand::SeedableRng;

#[test]
fn definitions_in_each_frame() {
    // paper 000 frame: (400, 500, 200) m
    let s = RadioSensor::new(Frame::AlongRadialAntinormal, 0.5, 1e-4);
    let r = Frame::AlongRadialAntinormal.vec_to_canonical(&Vec3::new(400.0, 500.0, 200.0));
    let z = s.h(&r).unwrap_or_default();
    let rho = (400.0f64 * 400.0 + 500.0 * 500.0 + 200.0 * 200.0).sqrt();
    assert!((z.x - rho).abs() < 1e-12);
    assert!((z.y - (500.0f64).atan2(400.0)).abs() < 1e-15);
    assert!((z.z - (200.0 / rho).asin()).abs() < 1e-15);
    // azimuth in the third and fourth quadrant is in [pi, 2 pi)
    let s1 = RadioSensor::new(Frame::RadialAlongNormal, 0.5, 1e-4);
    let z = s1.h(&Vec3::new(1.0, -1.0, 0.0)).unwrap_or_default();
    assert!((z.y - 1.75 * PI).abs() < 1e-15);
    let z = s1.h(&Vec3::new(-1.0, -1.0, 0.0)).unwrap_or_default();
    assert!((z.y - 1.25 * PI).abs() < 1e-15);
}

#[test]
fn jacobian_matches_finite_differences() {
    let pts = [
        Vec3::new(400.0, 500.0, 200.0),
        Vec3::new(-30.0, 7.0, -900.0),
        Vec3::new(1.0, -2.0, 0.5),
        Vec3::new(-250.0, -0.3, 10.0), // near the azimuth wrap in some frames
    ];
    for f in Frame::ALL {
        let s = RadioSensor::new(f, 1.0, 1.0);
        for r in pts {
            let g = s.geometry(&r).unwrap_or_else(|_| Geometry {
                z: Vec3::zeros(),
                h: Mat36::zeros(),
                azimuth_usable: false,
            });
            assert!(g.azimuth_usable);
            for j in 0..3 {
                let eps = 1e-6 * r.norm();
                let mut rp = r;
                rp[j] += eps;
                let mut rm = r;
                rm[j] -= eps;
                let zp = s.h(&rp).unwrap_or_default();
                let zm = s.h(&rm).unwrap_or_default();
                let fd = RadioSensor::residual(&zp, &zm) / (2.0 * eps);
                for i in 0..3 {
                    let an = g.h[(i, j)];
                    assert!(
                        (an - fd[i]).abs() < 1e-6 * (1.0 + an.abs()),
                        "{f:?} r={r:?} ({i},{j}): {an} vs {}",
                        fd[i]
                    );
                }
                assert_eq!(g.h[(0, j + 3)], 0.0);
            }
        }
    }
}

/// The particle filters' residual (asin of the angle residuals' sines where they are
/// small) equals `diff(z, predict(r))` everywhere: every frame, azimuths across 0 / 2 pi,
/// residuals beyond 60 degrees (the atan2 fallback), near the poles.
/// The block form equals `residual_at` lane by lane, bit for bit, near the
/// measurement (the vectorised series), off it by up to 0.09 rad (sines beyond the
/// series': `asin_small` afterwards) and far from it, on the pole and at zero range
/// (the lanes redone by `residual_at`), in every frame; the last block is short.
#[test]
#[allow(clippy::needless_range_loop)]
fn residuals_at_equal_residual_at_bitwise() {
    use rand::Rng;
    const B: usize = 16;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(4);
    for frame in [
        Frame::RadialAlongNormal,
        Frame::AlongRadialAntinormal,
        Frame::AlongAntinormalNadir,
    ] {
        let s = RadioSensor::new(frame, 0.5, 1e-4);
        let centre = Vec3::new(400.0, -500.0, 200.0);
        let z = s.predict(&centre).unwrap() + Vec3::new(0.3, 1e-4, -2e-4);
        let trig = AngleTrig::of(&z);
        for k in 0..400 {
            let n = if k % 7 == 6 { 5 } else { B };
            let mut r = [[0.0; B]; 3];
            for i in 0..B {
                let p = match (k + i) % 9 {
                    0 => Vec3::from_fn(|_, _| rng.random_range(-1000.0..1000.0)),
                    1 => Vec3::zeros(),
                    2 => frame.vec_to_canonical(&Vec3::new(0.0, 0.0, 300.0)),
                    3 => centre * rng.random_range(0.5..1.5),
                    // off the measurement by up to 0.09 rad (sines beyond the series')
                    4 => {
                        let across = centre.cross(&Vec3::new(0.2, 0.3, 1.0)).normalize();
                        centre + across * rng.random_range(-60.0..60.0)
                    }
                    _ => centre + Vec3::from_fn(|_, _| rng.random_range(-2.0..2.0)),
                };
                (r[0][i], r[1][i], r[2][i]) = (p.x, p.y, p.z);
            }
            let mut d = [[f64::NAN; B]; 3];
            let mut ok = [false; B];
            s.residuals_at(&z, &trig, &r, n, &mut d, &mut ok);
            for i in 0..n {
                let ri = Vec3::new(r[0][i], r[1][i], r[2][i]);
                match s.residual_at(&z, &trig, &ri) {
                    Some(v) => {
                        assert!(ok[i], "{ri:?}");
                        for c in 0..3 {
                            assert_eq!(d[c][i].to_bits(), v[c].to_bits(), "{ri:?} {c}");
                        }
                    }
                    None => assert!(!ok[i], "{ri:?}"),
                }
            }
        }
    }
}

#[test]
fn residual_at_equals_diff_of_predict() {
    use rand::Rng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(3);
    for frame in [
        Frame::RadialAlongNormal,
        Frame::AlongRadialAntinormal,
        Frame::AlongAntinormalNadir,
    ] {
        let s = RadioSensor::new(frame, 0.5, 1e-4);
        for k in 0..20_000 {
            let r = Vec3::from_fn(|_, _| rng.random_range(-1000.0..1000.0));
            let r = if k % 50 == 0 {
                Vec3::new(1e-9, -1e-9, 700.0)
            } else {
                r
            };
            let zh = s.predict(&r).unwrap();
            // measurements near the prediction, and anywhere
            let z = if k % 2 == 0 {
                Vec3::new(
                    zh.x + rng.random_range(-5.0..5.0),
                    wrap_2pi(zh.y + rng.random_range(-0.3..0.3)),
                    (zh.z + rng.random_range(-0.3..0.3)).clamp(-FRAC_PI_2, FRAC_PI_2),
                )
            } else {
                Vec3::new(
                    rng.random_range(0.0..2000.0),
                    rng.random_range(0.0..TAU),
                    rng.random_range(-FRAC_PI_2..FRAC_PI_2),
                )
            };
            let want = s.diff(&z, &zh);
            let got = s.residual_at(&z, &AngleTrig::of(&z), &r).unwrap();
            assert!(
                (got - want).abs().max() < 1e-9,
                "{frame:?} r {r:?} z {z:?}: {got:?} vs {want:?}"
            );
        }
        assert!(s
            .residual_at(
                &Vec3::new(1.0, 0.0, 0.0),
                &AngleTrig::of(&Vec3::new(1.0, 0.0, 0.0)),
                &Vec3::zeros()
            )
            .is_none());
    }
}

/// The radio sensor's unscented transform (no `atan2` per point) equals the default
/// one (`predict`, circular `weighted_mean`, wrapped `diff`) to rounding: clouds of 13
/// points near and far, across the azimuth's 0 / 2 pi cut, spreads beyond 60 degrees
/// (the `atan2` path), a point on the pole, with the UKF's default weights and with a
/// negative centre weight; and whether the azimuth is usable, as `geometry` says.
/// `unscented_seven_block` equals `unscented_seven` bit for bit on every lane it marks
/// fast, on the dispatched and the baseline path, and marks fast every lane whose
/// centre and points are well inside the series' domain, innovation angles beyond it
/// included (measurements off the cloud by up to 0.1 rad); far-off lanes, the pole and
/// zero range are left to the caller.
#[test]
#[allow(clippy::needless_range_loop)]
fn seven_block_equals_unscented_seven_bitwise() {
    use crate::numerics::simd::{dispatch, with_baseline};
    use rand::Rng;
    const B: usize = 16;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(8);
    let (mut fast_lanes, mut lanes, mut wide_lanes) = (0, 0, 0);
    for frame in Frame::ALL {
        let s = RadioSensor::new(frame, 0.5, 1e-3);
        let truth = frame.vec_to_canonical(&Vec3::new(400.0, 500.0, -200.0));
        for k in 0..200 {
            let spread = [0.3, 3.0, 30.0][k % 3];
            let o: [Vec3; 3] =
                core::array::from_fn(|_| Vec3::from_fn(|_, _| rng.random_range(-spread..spread)));
            let wm = [(0.0, 1.0 / 6.0), (-2.0, 0.5)][k % 2];
            // every fourth measurement off the cloud by up to 0.1 rad (innovation
            // angles beyond the series' 2^-5: `libm`'s `asin` in both forms)
            let da = if k % 4 == 3 { 0.1 } else { 3e-3 };
            let z = s.predict(&truth).unwrap()
                + Vec3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-da..da),
                    rng.random_range(-da..da),
                );
            let trig = AngleTrig::of(&z);
            let c: [[f64; B]; 3] = {
                let mut c = [[0.0; B]; 3];
                for i in 0..B {
                    let p = match (k + i) % 23 {
                        0 => Vec3::zeros(),
                        1 => frame.vec_to_canonical(&Vec3::new(0.0, 0.0, 300.0)),
                        2 => truth * 1.5,
                        _ => truth + Vec3::from_fn(|_, _| rng.random_range(-5.0..5.0)),
                    };
                    (c[0][i], c[1][i], c[2][i]) = (p.x, p.y, p.z);
                }
                c
            };
            let run = || {
                let mut out = SevenBlock::<B>::default();
                dispatch(
                    #[inline(always)]
                    || s.unscented_seven_block(&z, &trig, &c, &o, wm, &mut out),
                );
                out
            };
            let (a, b) = (run(), with_baseline(run));
            for i in 0..B {
                assert_eq!(a.fast[i], b.fast[i]);
                lanes += 1;
                if !a.fast[i] {
                    continue;
                }
                fast_lanes += 1;
                let ci = Vec3::new(c[0][i], c[1][i], c[2][i]);
                let mut dz = [Vec3::zeros(); 7];
                let (nu, usable) = s.unscented_seven(&z, &trig, &ci, &o, wm, &mut dz).unwrap();
                assert!(usable);
                if nu.y.abs().max(nu.z.abs()) > 0.04 {
                    wide_lanes += 1;
                }
                for out in [&a, &b] {
                    for kk in 0..3 {
                        assert_eq!(
                            out.nu[kk][i].to_bits(),
                            nu[kk].to_bits(),
                            "{frame:?} {k} {i}"
                        );
                        for (p, d) in dz.iter().enumerate() {
                            assert_eq!(
                                out.dz[p][kk][i].to_bits(),
                                d[kk].to_bits(),
                                "{frame:?} {k} {i} {p}"
                            );
                        }
                    }
                }
            }
        }
    }
    // the pole, zero range and the far-off lanes (3 in 23) and the widest spreads fall back
    assert!(
        fast_lanes > lanes / 2 && fast_lanes < lanes,
        "{fast_lanes} of {lanes}"
    );
    // and innovation angles beyond the series' domain do not (about half the lanes of
    // the measurements off by up to 0.1 rad)
    assert!(wide_lanes > fast_lanes / 10, "{wide_lanes} of {fast_lanes}");
}

#[test]
fn unscented_transform_equals_the_default() {
    use rand::Rng;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    let weights = [
        [1.0 / 12.0; 13],
        core::array::from_fn(|i| if i == 0 { -2.0 } else { 0.25 }),
    ];
    for frame in [
        Frame::RadialAlongNormal,
        Frame::AlongRadialAntinormal,
        Frame::AlongAntinormalNadir,
    ] {
        let s = RadioSensor::new(frame, 0.5, 1e-4);
        for k in 0..4000 {
            let wm = &weights[k % 2];
            let c = match k % 4 {
                // on the azimuth cut (sensor x axis) and near it
                0 => frame.vec_to_canonical(&Vec3::new(500.0, 0.0, 100.0)),
                _ => Vec3::from_fn(|_, _| rng.random_range(-1000.0..1000.0)),
            };
            let spread = [1.0, 50.0, 2000.0][k % 3];
            let mut r: [Vec3; 13] = core::array::from_fn(|_| {
                c + Vec3::from_fn(|_, _| rng.random_range(-spread..spread))
            });
            if k % 97 == 0 {
                r[3] = frame.vec_to_canonical(&Vec3::new(0.0, 0.0, 300.0));
            }
            let zs: Vec<Vec3> = r.iter().map(|ri| s.predict(ri).unwrap()).collect();
            let want_hat = s.weighted_mean(wm, &zs);
            let mut got = [Vec3::zeros(); 13];
            let got_hat = s.unscented(&r, wm, &mut got).unwrap();
            let scale = 1.0 + want_hat.x.abs();
            assert!((got_hat.x - want_hat.x).abs() < 1e-12 * scale);
            assert!(wrap_pi(got_hat.y - want_hat.y).abs() < 1e-9);
            assert!((got_hat.z - want_hat.z).abs() < 1e-12);
            for (zi, gi) in zs.iter().zip(&got) {
                let want = s.diff(zi, &want_hat);
                assert!(
                    (gi.x - want.x).abs() < 1e-12 * scale
                        && wrap_pi(gi.y - want.y).abs() < 1e-9
                        && (gi.z - want.z).abs() < 1e-12,
                    "{frame:?} {k}: {gi:?} vs {want:?}"
                );
            }
            assert_eq!(
                s.azimuth_usable(&c).unwrap(),
                s.geometry(&c).unwrap().azimuth_usable
            );
        }
        let mut dz = [Vec3::zeros(); 2];
        assert!(s
            .unscented(&[Vec3::x(), Vec3::zeros()], &[0.5, 0.5], &mut dz)
            .is_none());
        assert!(s.azimuth_usable(&Vec3::zeros()).is_err());
    }
}

#[test]
fn singular_geometry() {
    let s = RadioSensor::new(Frame::RadialAlongNormal, 1.0, 1.0);
    assert_eq!(s.geometry(&Vec3::zeros()), Err(GeometryError::ZeroRange));
    assert!(s.h(&Vec3::new(f64::NAN, 0.0, 0.0)).is_none());
    let g = s.geometry(&Vec3::new(1e-9, 0.0, 100.0));
    assert!(
        matches!(g, Ok(g) if !g.azimuth_usable && g.h.row(1).norm() == 0.0
        && g.h.row(2).iter().all(|v| v.is_finite()))
    );
}

#[test]
fn noise_is_seeded_and_has_the_stated_spread() {
    let s = RadioSensor::new(Frame::AlongRadialAntinormal, 0.5, 1.745e-4);
    let r = Vec3::new(500.0, 400.0, -200.0);
    let z0 = s.h(&r).unwrap_or_default();
    let mut a = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    let mut b = rand_chacha::ChaCha8Rng::seed_from_u64(7);
    assert_eq!(s.measure(&r, &mut a), s.measure(&r, &mut b));
    let k = 20_000;
    let mut sum = Vec3::zeros();
    let mut sq = Vec3::zeros();
    for _ in 0..k {
        let d = RadioSensor::residual(&s.measure(&r, &mut a).unwrap_or_default(), &z0);
        sum += d;
        sq += d.component_mul(&d);
    }
    let sd = (sq / k as f64).map(f64::sqrt);
    // sample sd of a Gaussian: relative standard error 1/sqrt(2k) = 0.5 %; allow 4 sigma
    assert!((sd.x / 0.5 - 1.0).abs() < 0.02);
    assert!((sd.y / 1.745e-4 - 1.0).abs() < 0.02);
    assert!((sd.z / 1.745e-4 - 1.0).abs() < 0.02);
    assert!((sum.x / k as f64).abs() < 4.0 * 0.5 / (k as f64).sqrt());
}
