//! Linearised relative motion about a target on an elliptic (Keplerian) orbit: the
//! Tschauner–Hempel equations, solved in closed form by Yamanaka and Ankersen ("New state
//! transition matrix for relative motion on an arbitrary elliptical orbit", JGCD 25(1),
//! 2002).
//!
//! Continuous model, canonical frame (x along the target's radius vector, y along-track,
//! z along its orbital angular momentum; the velocity is the time derivative of these
//! coordinates), with `w = nu'` the target's true-anomaly rate and `mu / r^3` its gravity
//! gradient:
//!
//! ```text
//! x'' = (w^2 + 2 mu/r^3) x + w' y + 2 w y' + a_x
//! y'' = -w' x + (w^2 - mu/r^3) y - 2 w x' + a_y
//! z'' = -mu/r^3 z + a_z
//! ```
//!
//! Everything follows from the mean motion `n` (`2 pi / period`, as for the CW model) and
//! the eccentricity `e`: with `rho = 1 + e cos nu` and `k^2 = n / (1 - e^2)^(3/2)`,
//! `w = k^2 rho^2`, `w' = -2 k^4 e rho^3 sin nu` and `mu / r^3 = k^4 rho^3` (no
//! gravitational parameter is needed). At `e = 0` these are the CW equations.
//!
//! The step from `t0` to `t1 = t0 + dt`:
//!
//! * `Phi(t1, t0)` in closed form: each coordinate is scaled to `u~ = rho u`, with
//!   derivatives taken with respect to the true anomaly (`u~' = -e sin nu u + u' / (k^2
//!   rho)`), where the in-plane motion has Yamanaka and Ankersen's fundamental matrix
//!   (its `J = k^2 (t - t0)` term carries the along-track drift) and the out-of-plane
//!   motion is `z~'' = -z~`. The true anomaly at `t` comes from Kepler's equation
//!   ([`eccentric_anomaly`], a fixed number of Halley iterations).
//! * `Gamma = integral Phi(t1, s) B ds` (thrust held over the step) and
//!   `Qd = integral Phi(t1, s) B qc B^T Phi(t1, s)^T ds` (white acceleration of density
//!   `qc`) by Gauss–Legendre quadrature in the eccentric anomaly `E`
//!   (`ds = (1 - e cos E) / n dE`, so no Kepler solve per node): six nodes on each of
//!   `ceil(dE / h)` equal panels, `h = min(0.25, 0.4 acosh(1/e))`. The integrands are
//!   analytic in a strip about the real `E` axis of half-width `acosh(1/e)` (where
//!   `1 - e cos E` vanishes), so the quadrature converges geometrically, at the same rate
//!   for every `e` with this `h`. Against the linearised equations integrated numerically
//!   (RK4 in `E`, Richardson-extrapolated), for `e <= 0.95` and steps up to one period,
//!   `Phi` and `Gamma` agree to 1e-11 and `Qd` to [`QUADRATURE_BOUND`] = 1e-9 of each
//!   matrix's largest entry (tests; measured 3.6e-12, 9.2e-13 and 6.5e-10).
//! * A step starts from `t0`'s anomaly advanced from an anchor, the Kepler solve at the
//!   grid point `m0 + i short_dm` of mean anomaly at or below it: Kepler's equation solved
//!   in the increment (two Halley steps from Newton's, the increment's sine and cosine by
//!   their Taylor polynomials). It is a pure function of `t0`, which a caller stepping
//!   forward keeps with its anchor ([`KeplerMemo`]), so the navigator solves Kepler's
//!   equation once per `short_dm` of mean anomaly, not once per step.
//! * A short step (`n dt <= (1 - e) short_span`, its span in `E` at most `short_span =
//!   min(0.02, 0.04 acosh(1/e))`: a navigator's usual step) needs no `sin_cos` beyond its
//!   anchor's and no anomaly inside the step. It runs from `t0` to `t1 = t0 + dt` as the
//!   caller's clock rounds it (`h = t1 - t0`), and its end's anomaly is `t1`'s as a step
//!   starting there takes it, so a caller stepping forward finds it kept: one increment
//!   solve per step. The increment from start to end then carries the rounding of `n t`
//!   (about `1e-16 n t` rad: 1e-13 rad after 10^6 s), a timing error of the order of an
//!   ulp of `t`. It is compiled for AVX2 where the CPU has it (the same bits,
//!   [`crate::numerics::simd`]; tested). `Gamma` and `Qd` come from the quintic
//!   Hermite interpolant in time of the integrand `G(tau) = Phi(t1, t1 - tau) B`, whose
//!   values and first two derivatives at both ends follow from the transition and the
//!   target's rates there: `Gamma` is its integral, `Qd` the five-point Gauss–Lobatto rule
//!   on `G qc G^T`. Within [`SHORT_BOUND`] = 1e-8 of the six-node panels up to `e = 0.95`
//!   (tested); at `e = 0.99` within the order of the closed-form transition's own rounding
//!   near apogee (the same test compares the two; figures in `docs/filters.md`).
//! * A short step whose `w h` (the larger of the ends' true-anomaly rates times the step)
//!   is at most [`CUBIC_SPAN`] = 1.2e-3 (a one-second step in a 2-hour orbit up to e = 0.1;
//!   not a two-second one), for `e <= 0.95`, takes the cubic interpolant (the ends' values
//!   and first derivatives) and the four-point Gauss–Lobatto rule instead: its errors grow
//!   as `(w h)^3`, within [`CUBIC_BOUND`] = 1e-9 of the panels (tested; at `e = 0` about
//!   `(w h)^3 / 360` of the input matrix, larger near perigee at high `e`). In both rules
//!   the end's node, `G(0) = B`, enters by its three entries.
//! * A step of one period or more is split into `k` whole periods and a remainder: over a
//!   whole period the in-plane transition is `I + D` with `D` the along-track drift (the
//!   fundamental matrix is periodic but for its `J` term), so `k` periods of thrust and
//!   noise are sums over `I + i D`, `i < k`, in closed form. The work is bounded for every
//!   input: at most two quadratures of at most `ceil(2 pi / h)` panels (26 up to e = 0.81, 111 at e = 0.99).
//!
//! The model reduces to CW at `e = 0` (tested): the transition to rounding, the input
//! matrix and noise to rounding but for steps of the cubic rule, within its bound; the
//! navigator still builds the [`super::CwModel`] for `e = 0`, whose noise and input
//! matrices are in closed form.

use super::{DiscreteModel, Discretization, RelativeDynamics};
#[cfg(not(feature = "std"))]
use crate::math::Float;
use crate::numerics::lanes::{axpy4, mul4};
use crate::numerics::Owned;
use crate::types::{Mat3, Mat6, Mat63, State, Vec3};
use core::f64::consts::{PI, TAU};
use nalgebra::{Matrix2, Matrix4, Matrix4x2, SMatrix, Vector2, Vector4};

/// Halley iterations of [`eccentric_anomaly`] at eccentricity `e`, fixed per eccentricity
/// band: from Danby's starter every mean anomaly converges to double precision in at most
/// 3 (e <= 0.2), 4 (e <= 0.8) and 6 (e <= 0.99) iterations on a dense grid (the test
/// checks each band at these counts; the first two carry one iteration of margin).
pub fn kepler_iterations(e: f64) -> usize {
    if e <= 0.2 {
        4
    } else if e <= 0.8 {
        5
    } else {
        KEPLER_ITERATIONS
    }
}

/// The most Halley iterations [`eccentric_anomaly`] takes (`e > 0.8`).
pub const KEPLER_ITERATIONS: usize = 6;

/// Gauss–Legendre nodes per quadrature panel.
const NODES: usize = 6;
/// Longest panel, in eccentric anomaly [rad].
const PANEL_E: f64 = 0.25;
/// Longest panel as a fraction of the half-width `acosh(1/e)` of the strip where the
/// integrands are analytic (keeps the quadrature's convergence rate as `e -> 1`).
const PANEL_STRIP: f64 = 0.4;
/// The stated bound of the process noise's error (max over entries, relative to the
/// largest entry of the same matrix) for `0 <= e <= 0.95` and steps up to one period,
/// checked by the tests against the integrated linearised equations (the transition and
/// the input matrix: 1e-11). At high `e` the bound is set by the reference's and this
/// computation's rounding, not by the quadrature: panels four times shorter change the
/// noise by less than 1e-15, and it is linear in the density to 1e-15.
pub const QUADRATURE_BOUND: f64 = 1e-9;

/// Longest short step, in eccentric anomaly [rad]: its end anomaly follows from the start's
/// without a Kepler solve ([`EllipticModel::advanced`]) and its input matrix and noise come
/// from the four Gauss–Lobatto points [`LOBATTO_X`] instead of six-node panels.
const SHORT_SPAN: f64 = 0.02;
/// The same as a fraction of the analytic strip's half-width `acosh(1/e)`.
const SHORT_STRIP: f64 = 0.04;
/// The stated bound of the short step's quadrature error against the six-node panels
/// (relative to each matrix's largest entry), tested for `e <= 0.95` (at `e = 0.99` the
/// transition's own rounding sets it, see the module docs).
pub const SHORT_BOUND: f64 = 1e-8;

/// Gauss–Lobatto nodes and weights on `[-1, 1]` (5 points: the ends, `0` and
/// `+-sqrt(3/7)`; exact for degree 7, with two of the five values free).
const LOBATTO_X: [f64; 5] = [
    -1.0,
    -0.654_653_670_707_977_1,
    0.0,
    0.654_653_670_707_977_1,
    1.0,
];
const LOBATTO_W: [f64; 5] = [0.1, 49.0 / 90.0, 32.0 / 45.0, 49.0 / 90.0, 0.1];

/// The quintic Hermite basis at the interior Lobatto nodes, `s = (1 + x) / 2` of the step
/// from its end (`s = 0`) to its start (`s = 1`): the weights of the value, the first and
/// the second derivative at `s = 0`, then of the second derivative, the first and the value
/// at `s = 1`.
const HERMITE: [[f64; 6]; 3] = [
    hermite((1.0 + LOBATTO_X[1]) / 2.0),
    hermite((1.0 + LOBATTO_X[2]) / 2.0),
    hermite((1.0 + LOBATTO_X[3]) / 2.0),
];

/// Gauss–Lobatto nodes and weights on `[-1, 1]` with 4 points (the ends and
/// `+-1/sqrt(5)`; exact for degree 5): the rule of a step whose `w h` is at most
/// [`CUBIC_SPAN`].
const LOBATTO4_X: [f64; 4] = [-1.0, -0.447_213_595_499_957_9, 0.447_213_595_499_957_9, 1.0];
const LOBATTO4_W: [f64; 4] = [1.0 / 6.0, 5.0 / 6.0, 5.0 / 6.0, 1.0 / 6.0];

/// The cubic Hermite basis (the ends' values and first derivatives) at the interior nodes
/// of [`LOBATTO4_X`], in the order of [`HERMITE`] (its second-derivative weights zero).
const CUBIC: [[f64; 6]; 2] = [
    cubic((1.0 + LOBATTO4_X[1]) / 2.0),
    cubic((1.0 + LOBATTO4_X[2]) / 2.0),
];

const fn cubic(s: f64) -> [f64; 6] {
    let (s2, s3) = (s * s, s * s * s);
    [
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + s,
        0.0,
        0.0,
        s3 - s2,
        3.0 * s2 - 2.0 * s3,
    ]
}

/// The largest `w h` (the target's largest angular rate at the step's ends times the step)
/// for which a short step takes the cubic interpolant and the four-point Gauss–Lobatto
/// rule instead of the quintic one and five points: their errors grow as `(w h)^3` (the
/// interpolant's) and `(w h)^4` (the rule's on the noise), within [`CUBIC_BOUND`] of the
/// six-node panels below it (tested). A one-second step in low orbit has `w h` about 1e-3.
pub const CUBIC_SPAN: f64 = 1.2e-3;
/// The largest eccentricity of the cubic rule (tested up to it; above, the transition's own
/// rounding near apogee is of the order of its bound).
const CUBIC_E: f64 = 0.95;
/// The stated bound of the cubic rule's error against the six-node panels (relative to each
/// matrix's largest entry), tested for `e <= 0.95`.
pub const CUBIC_BOUND: f64 = 1e-9;

const fn hermite(s: f64) -> [f64; 6] {
    let (s2, s3, s4, s5) = (s * s, s * s * s, s * s * s * s, s * s * s * s * s);
    [
        1.0 - 10.0 * s3 + 15.0 * s4 - 6.0 * s5,
        s - 6.0 * s3 + 8.0 * s4 - 3.0 * s5,
        0.5 * s2 - 1.5 * s3 + 1.5 * s4 - 0.5 * s5,
        0.5 * s3 - s4 + 0.5 * s5,
        -4.0 * s3 + 7.0 * s4 - 3.0 * s5,
        10.0 * s3 - 15.0 * s4 + 6.0 * s5,
    ]
}

/// Gauss–Legendre nodes and weights on `[-1, 1]` (6 points).
const GL_X: [f64; NODES] = [
    -0.932_469_514_203_152,
    -0.661_209_386_466_264_5,
    -0.238_619_186_083_196_9,
    0.238_619_186_083_196_9,
    0.661_209_386_466_264_5,
    0.932_469_514_203_152,
];
const GL_W: [f64; NODES] = [
    0.171_324_492_379_170_3,
    0.360_761_573_048_138_6,
    0.467_913_934_572_691,
    0.467_913_934_572_691,
    0.360_761_573_048_138_6,
    0.171_324_492_379_170_3,
];

/// Halley steps of [`EllipticModel::advanced`] after its Newton start: on a dense grid of
/// eccentricities up to 0.99, start anomalies and increments up to the short-step bound the
/// residual is at rounding after two (tested).
const INCREMENT_ITERATIONS: usize = 2;

/// The largest angle [`small_sin_cosm1`] takes (above `short_span`, the largest increment
/// asked of it).
const SMALL_ANGLE: f64 = 0.05;

/// `sin x` and `cos x - 1` for `|x| <=` [`SMALL_ANGLE`] by their Taylor polynomials
/// (through `x^9` and `x^10`): the first terms left out, `|x|^11 / 11!` and `x^12 / 12!`,
/// are below 1e-21 of `|x|` there, far below an ulp. `cos x - 1` keeps the digits `cos x`
/// would round away, which the differences of nearby anomalies need.
#[inline(always)]
fn small_sin_cosm1(x: f64) -> (f64, f64) {
    debug_assert!(x.abs() <= SMALL_ANGLE || !x.is_finite());
    let x2 = x * x;
    let s = x
        * (1.0
            - x2 * (1.0 / 6.0)
                * (1.0
                    - x2 * (1.0 / 20.0) * (1.0 - x2 * (1.0 / 42.0) * (1.0 - x2 * (1.0 / 72.0)))));
    let c = -0.5
        * x2
        * (1.0
            - x2 * (1.0 / 12.0)
                * (1.0
                    - x2 * (1.0 / 30.0) * (1.0 - x2 * (1.0 / 56.0) * (1.0 - x2 * (1.0 / 90.0)))));
    (s, c)
}

/// The eccentric anomaly `E` with `E - e sin E = m`, for any mean anomaly `m` (not reduced:
/// the result carries `m`'s revolutions) and `0 <= e < 1`. Fixed work: the reduction of
/// `m` to `[-pi, pi]`, Danby's starter `E0 = m + 0.85 e` (for `m >= 0`, by symmetry
/// otherwise), [`kepler_iterations`]`(e)` Halley steps (at most [`KEPLER_ITERATIONS`]).
pub fn eccentric_anomaly(m: f64, e: f64) -> f64 {
    kepler(m, e).0
}

/// [`eccentric_anomaly`] with its sine and cosine: one `sin_cos` at the starter, then each
/// Halley step's correction `d` moves them by angle addition with [`small_sin_cosm1`] when
/// `|d| <=` [`SMALL_ANGLE`] (a new `sin_cos` otherwise; from the polynomials of `E` itself
/// for `E <=` [`SMALL_ANGLE`]), so a converging solve costs one.
fn kepler(m: f64, e: f64) -> (f64, f64, f64) {
    let turns = (m / TAU).round();
    let mr = m - turns * TAU;
    let (sign, ma) = if mr < 0.0 { (-1.0, -mr) } else { (1.0, mr) };
    let mut big_e = (ma + 0.85 * e).min(PI);
    let (mut s, mut c) = big_e.sin_cos();
    for _ in 0..kepler_iterations(e) {
        let f = big_e - e * s - ma;
        let fp = 1.0 - e * c;
        let d = f / (fp - 0.5 * f * e * s / fp);
        // a non-finite m stays non-finite; a finite one never divides by zero (fp >= 1 - e)
        big_e -= d;
        if big_e.abs() <= SMALL_ANGLE {
            // near perigee from the polynomials of E itself: relative precision as E -> 0
            let (se, cm) = small_sin_cosm1(big_e);
            (s, c) = (se, 1.0 + cm);
        } else if d.abs() <= SMALL_ANGLE {
            let (sd, cd) = small_sin_cosm1(-d);
            (s, c) = (s + (s * cd + c * sd), c + (c * cd - s * sd));
        } else {
            (s, c) = big_e.sin_cos();
        }
    }
    (sign * big_e + turns * TAU, sign * s, c)
}

/// Where the target is at one instant: the eccentric anomaly with its sine and cosine, and
/// the sine and cosine of the true anomaly (every matrix here needs only those: no `atan2`;
/// a nearby instant follows from these by [`small_sin_cosm1`], without a `sin_cos`).
#[derive(Debug, Clone, Copy)]
struct Anomaly {
    /// eccentric anomaly, with its revolutions
    big_e: f64,
    /// sin E
    se: f64,
    /// cos E
    ce: f64,
    /// sin of the true anomaly
    sn: f64,
    /// cos of the true anomaly
    cn: f64,
    /// `rho = 1 + e cos nu`
    rho: f64,
    /// `1 / rho = (1 - e cos E) / (1 - e^2)`
    ir: f64,
}

/// One quadrature node of a step: where the target is, the time left to the step's end [s]
/// and the node's weight in time [s].
struct Node {
    at: Anomaly,
    to_end: f64,
    weight: f64,
}

/// What the transition, the input matrix and the noise of a step share from its end
/// ([`EllipticModel::end_factor`]).
struct EndFactor {
    /// `U(a1) P^T psi_a(a1)`
    la: Matrix4<f64>,
    /// `U(a1) P^T psi_b(a1)`: the `J` column
    lb: Vector4<f64>,
    /// the normal axis' unscaling at `a1`
    unz: Matrix2<f64>,
}

/// The nonzero entries of a short step's end blocks ([`EllipticModel::hermite_blocks`]),
/// with `c = 2 w`, `g = mu / r^3` and `w'` at the end: `h G'` has `h` and `+-h c`, `h^2 G''`
/// has `+-h^2 c`, `h^2 (2 g - 3 w^2)`, `+-h^2 w'`, `-h^2 (g + 3 w^2)` and `-h^2 g`; `G = B`.
/// Kept as numbers rather than packed: a packed block would mix them with zeros, which the
/// dispatched code builds with a `vmovq` that valgrind 3.19 cannot decode.
struct EndBlocks {
    h: f64,
    hc: f64,
    h2c: f64,
    h2x: f64,
    h2wd: f64,
    h2y: f64,
    h2z: f64,
}

impl EndBlocks {
    /// `p G + v h G' + a h^2 G''` at the end, packed (the products in the order of the
    /// blocks, as a dense sum over them would take them).
    #[inline(always)]
    fn combine(&self, [p, v, a]: [f64; 3]) -> Packed {
        [
            v * self.h,
            a * -self.h2c,
            p + a * self.h2x,
            v * -self.hc + a * self.h2wd,
            a * self.h2c,
            v * self.h,
            v * self.hc + a * -self.h2wd,
            p + a * -self.h2y,
            v * self.h,
            p + a * -self.h2z,
        ]
    }
}

/// The linearised elliptic model (Yamanaka–Ankersen) for one target orbit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EllipticModel {
    /// Mean motion of the target's orbit, `2 pi / period` [rad/s].
    pub n: f64,
    /// Eccentricity of the target's orbit, `0 <= e < 1`.
    pub e: f64,
    /// The target's true anomaly at time 0 [rad].
    pub nu0: f64,
    /// mean anomaly at time 0
    m0: f64,
    /// `k^2 = n / (1 - e^2)^(3/2)`: the true-anomaly rate is `k^2 rho^2`
    k2: f64,
    /// longest quadrature panel [rad of eccentric anomaly]
    panel: f64,
    /// longest short step [rad of eccentric anomaly]
    short_span: f64,
    /// longest short step [rad of mean anomaly], taken from the start's anomaly by
    /// [`EllipticModel::advanced`] and the Lobatto rule: `(1 - e) short_span`, whose
    /// eccentric anomaly is at most `short_span` (`dM/dE = 1 - e cos E >= 1 - e`)
    short_dm: f64,
    /// `sqrt(1 - e^2)`
    sq: f64,
    /// `1 / (1 - e^2)`
    inv_1me2: f64,
    /// `1 / n`
    inv_n: f64,
    /// `1 / k^2`
    inv_k2: f64,
}

/// What [`EllipticModel::start`] keeps between the steps of a caller stepping forward: the
/// last anchor (the Kepler solve at the grid point `m0 + i short_dm` of mean anomaly, a pure
/// function of the index `i`), so that Kepler's equation is solved once per grid interval,
/// and the last anomaly with its time, which is the next step's start when it begins where
/// the last one ended. Both are pure functions of their keys: whether the memo holds them
/// or not changes no result.
#[derive(Debug, Clone, Copy, Default)]
pub struct KeplerMemo {
    anchor: Option<(f64, Anomaly)>,
    last: Option<(u64, Anomaly)>,
}

/// The in-plane scaled coordinates of Yamanaka and Ankersen's frame (x along-track, z
/// toward the Earth) from the canonical ones (x radial, y along-track), both ordered
/// (x~, y~, x~', y~') resp. (x~, z~, x~', z~'): `w = P u` (applied by [`rows_pt`] and
/// [`cols_p`]; the matrix itself checks them in the tests).
#[cfg(test)]
fn ya_from_canonical() -> Matrix4<f64> {
    Matrix4::new(
        0.0, 1.0, 0.0, 0.0, //
        -1.0, 0.0, 0.0, 0.0, //
        0.0, 0.0, 0.0, 1.0, //
        0.0, 0.0, -1.0, 0.0,
    )
}

impl EllipticModel {
    /// The model for mean motion `n` [rad/s], eccentricity `e` and true anomaly `nu0` at
    /// time 0 (callers validate: `n > 0`, `0 <= e < 1`, all finite).
    pub fn new(n: f64, e: f64, nu0: f64) -> Self {
        let (s, c) = (0.5 * nu0).sin_cos();
        let e0 = 2.0 * ((1.0 - e).sqrt() * s).atan2((1.0 + e).sqrt() * c);
        let m0 = e0 - e * e0.sin();
        let k2 = n / (1.0 - e * e).powf(1.5);
        // acosh(1/e) is infinite at e = 0; a NaN e (refused by callers) gives PANEL_E
        let strip = (1.0 / e).acosh();
        let panel = PANEL_E.min(PANEL_STRIP * strip).max(1e-3);
        let short_span = SHORT_SPAN.min(SHORT_STRIP * strip);
        Self {
            n,
            e,
            nu0,
            m0,
            k2,
            panel,
            short_span,
            short_dm: (1.0 - e) * short_span,
            sq: (1.0 - e * e).sqrt(),
            inv_1me2: 1.0 / (1.0 - e * e),
            inv_n: 1.0 / n,
            inv_k2: 1.0 / k2,
        }
    }

    /// The orbital period `2 pi / n` [s].
    pub fn period(&self) -> f64 {
        TAU / self.n
    }

    fn anomaly(&self, t: f64) -> Anomaly {
        let (big_e, se, ce) = kepler(self.m0 + self.n * t, self.e);
        self.with_sin_cos(big_e, se, ce)
    }

    /// `cos nu = (cos E - e) / (1 - e cos E)`, `sin nu = sqrt(1 - e^2) sin E / (1 - e cos E)`.
    fn at_e(&self, big_e: f64) -> Anomaly {
        let (se, ce) = big_e.sin_cos();
        self.with_sin_cos(big_e, se, ce)
    }

    #[inline(always)]
    fn with_sin_cos(&self, big_e: f64, se: f64, ce: f64) -> Anomaly {
        let q = 1.0 - self.e * ce;
        let d = 1.0 / q;
        let cn = (ce - self.e) * d;
        Anomaly {
            big_e,
            se,
            ce,
            sn: self.sq * se * d,
            cn,
            rho: 1.0 + self.e * cn,
            ir: q * self.inv_1me2,
        }
    }

    /// The anomaly at time `t` as every step starts (and a short step ends) at it:
    /// [`EllipticModel::advanced`] from the Kepler solve at the grid point `m0 + i short_dm`
    /// of mean anomaly at or below `m0 + n t` (its increment is within the short step's,
    /// where `advanced` is as accurate as a fresh solve, tested); the anchor and the result
    /// kept in `memo`.
    #[inline(always)]
    fn start(&self, t: f64, memo: &mut KeplerMemo) -> Anomaly {
        if let Some((bits, a)) = memo.last {
            if bits == t.to_bits() {
                return a;
            }
        }
        let x = self.n * t;
        let i = (x / self.short_dm).floor();
        let anchor = match memo.anchor {
            Some((j, a)) if j == i => a,
            _ => {
                let (big_e, se, ce) = kepler(self.m0 + i * self.short_dm, self.e);
                let a = self.with_sin_cos(big_e, se, ce);
                memo.anchor = Some((i, a));
                a
            }
        };
        let a = self.advanced(&anchor, x - i * self.short_dm).0;
        memo.last = Some((t.to_bits(), a));
        a
    }

    /// The anomaly `d` (`|d| <=` [`SMALL_ANGLE`]) of eccentric anomaly after `a`, with
    /// `sin d` and `cos d - 1` (angle addition from `a`'s sine and cosine).
    #[inline(always)]
    fn shifted(&self, a: &Anomaly, d: f64) -> (Anomaly, f64, f64) {
        let (sd, cd) = small_sin_cosm1(d);
        let at = self.with_sin_cos(
            a.big_e + d,
            a.se + (a.se * cd + a.ce * sd),
            a.ce + (a.ce * cd - a.se * sd),
        );
        (at, sd, cd)
    }

    /// The anomaly `dm` of mean anomaly after `a`, for `0 <= dm <=` `short_dm` (so its
    /// eccentric anomaly is at most `short_span` after `a`'s): Kepler's equation in the
    /// increment `d`, `d - e (sin E0 (cos d - 1) + cos E0 sin d) = dm`, from Newton's step at
    /// `d = 0` by [`INCREMENT_ITERATIONS`] Halley steps, the sine and cosine of `d` by
    /// [`small_sin_cosm1`]: no `sin_cos`. Also returns `sin d` and `cos d - 1`.
    #[inline(always)]
    fn advanced(&self, a: &Anomaly, dm: f64) -> (Anomaly, f64, f64) {
        let (s0, c0, e) = (a.se, a.ce, self.e);
        let mut d = dm / (1.0 - e * c0);
        for _ in 0..INCREMENT_ITERATIONS {
            let (sd, cd) = small_sin_cosm1(d);
            let f = d - e * (s0 * cd + c0 * sd) - dm;
            let fp = 1.0 - e * (c0 * (1.0 + cd) - s0 * sd);
            let fpp = e * (s0 * (1.0 + cd) + c0 * sd);
            d -= f / (fp - 0.5 * f * fpp / fp);
        }
        self.shifted(a, d)
    }

    /// The target's mean anomaly at time 0 [rad].
    pub fn mean_anomaly0(&self) -> f64 {
        self.m0
    }

    /// The target's angular rate `nu'` at time `t` [rad/s] (`k^2 rho^2`).
    pub fn angular_rate(&self, t: f64) -> f64 {
        let a = self.anomaly(t);
        self.k2 * a.rho * a.rho
    }

    /// The first time `t >= 0` [s] at which the target is at true anomaly `nu` [rad].
    pub fn time_at_true_anomaly(&self, nu: f64) -> f64 {
        let (s, c) = (0.5 * nu).sin_cos();
        let big_e = 2.0 * ((1.0 - self.e).sqrt() * s).atan2((1.0 + self.e).sqrt() * c);
        let m = big_e - self.e * big_e.sin();
        (m - self.m0).rem_euclid(TAU) / self.n
    }

    /// The target's true anomaly at time `t` [rad, in (-pi, pi]].
    pub fn true_anomaly(&self, t: f64) -> f64 {
        let a = self.anomaly(t);
        a.sn.atan2(a.cn)
    }

    /// Yamanaka and Ankersen's in-plane fundamental matrix at true anomaly `nu`, split as
    /// `Psi = psi_a + J psi_b e_4^T` (only the last column depends on `J`): `(psi_a, psi_b)`.
    #[inline(always)]
    fn psi(&self, a: &Anomaly) -> (Matrix4<f64>, Vector4<f64>) {
        let e = self.e;
        let (sn, cn, rho, ir) = (a.sn, a.cn, a.rho, a.ir);
        let (s, c) = (rho * sn, rho * cn);
        // cos 2 nu, sin 2 nu
        let sp = cn + e * (cn * cn - sn * sn);
        let cp = -(sn + e * (2.0 * sn * cn));
        let a = Matrix4::new(
            1.0,
            -c * (1.0 + ir),
            s * (1.0 + ir),
            0.0,
            0.0,
            s,
            c,
            2.0,
            0.0,
            2.0 * s,
            2.0 * c - e,
            3.0,
            0.0,
            sp,
            cp,
            -3.0 * e * s * ir * ir,
        );
        (
            a,
            Vector4::new(3.0 * rho * rho, -3.0 * e * s, -6.0 * e * s, -3.0 * e * sp),
        )
    }

    /// The closed-form inverse of [`EllipticModel::psi`] at `J = 0`.
    #[inline(always)]
    fn psi_inv(&self, a: &Anomaly) -> Matrix4<f64> {
        let e = self.e;
        let (sn, cn, rho, ir) = (a.sn, a.cn, a.rho, a.ir);
        let (s, c) = (rho * sn, rho * cn);
        let f = self.inv_1me2;
        // the last two columns are the velocity columns (of `psi^-1 P`, unpermuted)
        let v = self.psi_inv_velocity(a);
        Matrix4::from_columns(&[
            Vector4::new(1.0 - e * e, 0.0, 0.0, 0.0) * f,
            Vector4::new(
                3.0 * e * s * (ir + ir * ir),
                -3.0 * s * (ir + e * e * ir * ir),
                -3.0 * (c * ir + e),
                3.0 * rho + e * e - 1.0,
            ) * f,
            v.column(1).owned(),
            -v.column(0),
        ])
    }

    /// The two columns of `psi^-1 P` a velocity input enters by: `(-psi^-1[:, 3],
    /// psi^-1[:, 2])` of [`EllipticModel::psi_inv`], alone.
    #[inline(always)]
    fn psi_inv_velocity(&self, a: &Anomaly) -> Matrix4x2<f64> {
        let e = self.e;
        let (sn, cn, rho, ir) = (a.sn, a.cn, a.rho, a.ir);
        let (s, c) = (rho * sn, rho * cn);
        let f = self.inv_1me2;
        Matrix4x2::new(
            -(2.0 - e * c),
            -e * s * (1.0 + ir),
            -(c - 2.0 * e),
            s * (1.0 + ir),
            s,
            c * (1.0 + ir) + e,
            -e * s,
            -rho * rho,
        ) * f
    }

    /// Per-axis scaling `(u, u') -> (u~, u~')` at true anomaly `nu`.
    #[inline(always)]
    fn scaling(&self, a: &Anomaly) -> Matrix2<f64> {
        Matrix2::new(a.rho, 0.0, -self.e * a.sn, a.ir * self.inv_k2)
    }

    /// Its inverse: `u = u~ / rho`, `u' = k^2 (e sin nu u~ + rho u~')`.
    #[inline(always)]
    fn unscaling(&self, a: &Anomaly) -> Matrix2<f64> {
        Matrix2::new(a.ir, 0.0, self.k2 * self.e * a.sn, self.k2 * a.rho)
    }

    /// `m S` for the in-plane scaling `S` on (x, y, vx, vy) -> (x~, y~, x~', y~') at `a` (the
    /// per-axis [`EllipticModel::scaling`] on both axes), by column operations.
    #[inline(always)]
    fn scale_cols(&self, a: &Anomaly, m: &Matrix4<f64>) -> Matrix4<f64> {
        let s = self.scaling(a);
        let mut out = *m;
        for axis in 0..2 {
            let (p, v) = (m.column(axis), m.column(axis + 2));
            out.set_column(axis, &(p * s[(0, 0)] + v * s[(1, 0)]));
            out.set_column(axis + 2, &(v * s[(1, 1)]));
        }
        out
    }

    /// `U m` for the in-plane unscaling `U` at `a` ([`EllipticModel::unscaling`] on both
    /// axes), by row operations.
    #[inline(always)]
    fn unscale_rows<const C: usize>(
        &self,
        a: &Anomaly,
        m: &SMatrix<f64, 4, C>,
    ) -> SMatrix<f64, 4, C> {
        let u = self.unscaling(a);
        let mut out = *m;
        for axis in 0..2 {
            let (p, v) = (m.row(axis), m.row(axis + 2));
            out.set_row(axis, &(p * u[(0, 0)]));
            out.set_row(axis + 2, &(p * u[(1, 0)] + v * u[(1, 1)]));
        }
        out
    }

    /// The factors every matrix of a step ending at `a1` starts with: the in-plane `U(a1)
    /// P^T psi(a1)` split as `la + J lb e_4^T`, and the normal unscaling.
    #[inline(always)]
    fn end_factor(&self, a1: &Anomaly) -> EndFactor {
        let (pa, pb) = self.psi(a1);
        EndFactor {
            la: self.unscale_rows(a1, &rows_pt(&pa)),
            lb: self.unscale_rows(a1, &Vector4::new(-pb[1], pb[0], -pb[3], pb[2])),
            unz: self.unscaling(a1),
        }
    }

    /// The continuous system matrix `A(t)` (canonical frame).
    pub fn continuous_a(&self, t: f64) -> Mat6 {
        let a = self.anomaly(t);
        let (sn, rho) = (a.sn, a.rho);
        let k4 = self.k2 * self.k2;
        let w = self.k2 * rho * rho;
        let wd = -2.0 * k4 * self.e * rho * rho * rho * sn;
        let g = k4 * rho * rho * rho; // mu / r^3
        let mut a = Mat6::zeros();
        a[(0, 3)] = 1.0;
        a[(1, 4)] = 1.0;
        a[(2, 5)] = 1.0;
        a[(3, 0)] = w * w + 2.0 * g;
        a[(3, 1)] = wd;
        a[(3, 4)] = 2.0 * w;
        a[(4, 0)] = -wd;
        a[(4, 1)] = w * w - g;
        a[(4, 3)] = -2.0 * w;
        a[(5, 2)] = -g;
        a
    }

    /// The transition matrix `Phi(t1, t0)` between two instants given by their anomalies
    /// (`j = k^2 (t1 - t0)`; `end` is [`EllipticModel::end_factor`] at `a1`), written into
    /// the in-plane and normal entries of `phi` ([`assemble`]).
    #[inline(always)]
    fn phi_with(&self, end: &EndFactor, a0: &Anomaly, a1: &Anomaly, j: f64, phi: &mut Mat6) {
        let mut left = end.la;
        left.set_column(3, &(end.la.column(3) + end.lb * j));
        let inplane = left * self.scale_cols(a0, &cols_p(&self.psi_inv(a0)));
        let (sd, cd) = sin_cos_difference(a1, a0);
        let normal = end.unz * Matrix2::new(cd, sd, -sd, cd) * self.scaling(a0);
        assemble(&inplane, &normal, phi);
    }

    fn phi_between(&self, a0: &Anomaly, a1: &Anomaly, j: f64) -> Mat6 {
        let mut phi = Mat6::zeros();
        self.phi_with(&self.end_factor(a1), a0, a1, j, &mut phi);
        phi
    }

    /// `Phi(t0 + dt, t0)`.
    pub fn phi(&self, t0: f64, dt: f64) -> Mat6 {
        let a0 = self.anomaly(t0);
        let a1 = self.anomaly(t0 + dt);
        self.phi_between(&a0, &a1, self.k2 * dt)
    }

    /// The quadrature nodes of the step from `a0` to `a1` (less than one period later,
    /// `a1.big_e >= a0.big_e`) by `sin_cos` at each: six-node panels.
    fn panel_nodes<'a>(&'a self, a0: &Anomaly, a1: &'a Anomaly) -> impl Iterator<Item = Node> + 'a {
        let span = a1.big_e - a0.big_e;
        // ceil of a finite, non-negative number below 2 pi / PANEL_E + 1: bounded
        let panels = if span.is_finite() {
            crate::numerics::clamp((span / self.panel).ceil(), 1.0, (TAU / self.panel).ceil())
                as usize
        } else {
            1
        };
        let h = span / panels as f64;
        let e0 = a0.big_e;
        (0..panels).flat_map(move |k| {
            let mid = e0 + (k as f64 + 0.5) * h;
            GL_X.iter().zip(&GL_W).map(move |(x, &w)| {
                let big_e = mid + 0.5 * h * x;
                // (E1 - E) - e (sin E1 - sin E), without cancellation
                let de = a1.big_e - big_e;
                let dsin = 2.0 * (0.5 * (a1.big_e + big_e)).cos() * (0.5 * de).sin();
                self.node(self.at_e(big_e), de - self.e * dsin, 0.5 * h * w)
            })
        })
    }

    /// The coefficients of the quintic Hermite interpolant of a short step's integrand
    /// `G(tau) = Phi(t1, t1 - tau) B` over `h` [s], in the order of [`HERMITE`]: `G`, `h G'`
    /// and `h^2 G''` at the step's end (`tau = 0`), then `h^2 G''`, `h G'` and `G` at its
    /// start. All six are free: `G = Phi(t1, s) B`, `G' = Phi(t1, s) A(s) B` and `G'' =
    /// Phi(t1, s) (A(s)^2 - A'(s)) B` at `s = t1 - tau`, with `Phi(t1, t1) = I`, the
    /// transition at `s = t0`, and `A B = [I; C]`, `(A^2 - A') B = [C; A_vp + C^2 - C']`
    /// (`C` the Coriolis block) sparse in the target's rates: no interior anomaly and no
    /// fundamental matrix. The end's three are sparse ([`EndBlocks`]); the start's are
    /// packed as [`Packed`].
    #[inline(always)]
    fn hermite_blocks(
        &self,
        a0: &Anomaly,
        a1: &Anomaly,
        phi: &Mat6,
        h: f64,
    ) -> (EndBlocks, [Packed; 3]) {
        let h2 = h * h;
        // per end: 2 w (the Coriolis coefficient), mu / r^3, w' and 3 w^2
        let rates = |a: &Anomaly| {
            let w = self.k2 * a.rho * a.rho;
            let g = self.k2 * self.k2 * a.rho * a.rho * a.rho;
            (2.0 * w, g, -2.0 * g * self.e * a.sn, 3.0 * w * w)
        };
        let (c0, g0, wd0, w3_0) = rates(a0);
        let (c1, g1, wd1, w3_1) = rates(a1);
        let end = EndBlocks {
            h,
            hc: h * c1,
            h2c: h2 * c1,
            h2x: h2 * (2.0 * g1 - w3_1),
            h2wd: h2 * wd1,
            h2y: h2 * (g1 + w3_1),
            h2z: h2 * g1,
        };
        let mut b = [[0.0; 10]; 3];
        for (r, &row) in [0, 1, 3, 4].iter().enumerate() {
            let p = |c: usize| phi[(row, c)];
            b[0][r] = h2 * (-c0 * p(1) + (2.0 * g0 - w3_0) * p(3) + wd0 * p(4));
            b[0][4 + r] = h2 * (c0 * p(0) - wd0 * p(3) - (g0 + w3_0) * p(4));
            b[1][r] = h * (p(0) - c0 * p(4));
            b[1][4 + r] = h * (p(1) + c0 * p(3));
            b[2][r] = p(3);
            b[2][4 + r] = p(4);
        }
        for (r, row) in [2, 5].into_iter().enumerate() {
            b[0][8 + r] = -h2 * g0 * phi[(row, 5)];
            b[1][8 + r] = h * phi[(row, 2)];
            b[2][8 + r] = phi[(row, 5)];
        }
        (end, b)
    }

    /// A short step's input matrix and (with `qc`) noise over `h` [s]:
    /// [`EllipticModel::quadrature`] at the five Gauss–Lobatto nodes in time of the
    /// interpolant of [`EllipticModel::hermite_blocks`], whose two end values are
    /// coefficients and whose three interior ones its sums. The rule is exact to degree 7:
    /// the input matrix is the quintic interpolant's integral, the noise the rule on `G qc
    /// G^T`. Written into `out.gamma` and `out.q` as [`EllipticModel::quadrature`].
    #[inline(always)]
    fn short_gamma_q(
        &self,
        a0: &Anomaly,
        a1: &Anomaly,
        h: f64,
        qc: Option<&Mat3>,
        out: &mut DiscreteModel,
    ) {
        let (end, start) = self.hermite_blocks(a0, a1, &out.phi, h);
        let rho = a0.rho.max(a1.rho);
        if self.k2 * rho * rho * h <= CUBIC_SPAN && self.e <= CUBIC_E {
            Self::lobatto(&end, &start[1..], &CUBIC, &LOBATTO4_W, h, qc, out);
        } else {
            Self::lobatto(&end, &start, &HERMITE, &LOBATTO_W, h, qc, out);
        }
    }

    /// The Lobatto rule of `N` points (`I = N - 2` interior, `basis` the interpolant's
    /// weights there) on the interpolant of the end blocks `end` and the start blocks
    /// `start` (the last ones of [`EllipticModel::hermite_blocks`]'s, as many as the
    /// basis uses): [`EllipticModel::quadrature`] at the start's node and the interior
    /// ones, the end's node (`G(0) = B`) by its entries.
    #[inline(always)]
    fn lobatto<const I: usize, const N: usize>(
        end: &EndBlocks,
        start: &[Packed],
        basis: &[[f64; 6]; I],
        weights: &[f64; N],
        h: f64,
        qc: Option<&Mat3>,
        out: &mut DiscreteModel,
    ) {
        let last = start[start.len() - 1];
        let mut nodes = [last; N];
        for (node, basis) in nodes[1..=I].iter_mut().zip(basis) {
            *node = end.combine([basis[0], basis[1], basis[2]]);
            for (bk, &c) in start.iter().zip(&basis[6 - start.len()..]) {
                for (v, x) in node.iter_mut().zip(bk) {
                    *v += c * x;
                }
            }
        }
        let w = weights.map(|w| 0.5 * h * w);
        let mut wn = w;
        wn[0] = w[N - 1];
        let values = nodes.into_iter().zip(wn).take(I + 1);
        let diagonal = Self::quadrature(values, qc, &mut out.gamma, &mut out.q);
        // the end's node, G(0) = B, by its entries: w0 on the velocity rows of gamma,
        // w0 qc on the velocity block of the noise
        let w0 = w[0];
        for i in 3..6 {
            out.gamma[(i, i - 3)] += w0;
        }
        match (qc, diagonal) {
            (_, Some(d)) => {
                for (i, di) in d.iter().enumerate() {
                    out.q[(3 + i, 3 + i)] += w0 * di;
                }
            }
            (Some(qc), None) => {
                let sym = (qc + qc.transpose()) * 0.5;
                for i in 3..6 {
                    for j in 3..6 {
                        out.q[(i, j)] += w0 * sym[(i - 3, j - 3)];
                    }
                }
            }
            (None, None) => {}
        }
    }

    /// A quadrature weight `w` in the eccentric anomaly at `at` as a weight in time: `ds =
    /// (1 - e cos E) / n dE`, and `1 - e cos E = (1 - e^2) / rho`.
    fn weight(&self, at: &Anomaly, w: f64) -> f64 {
        w * (1.0 - self.e * self.e) * at.ir * self.inv_n
    }

    /// A node at `at`, `dm_to_end` of mean anomaly before the step's end, with quadrature
    /// weight `w` in the eccentric anomaly.
    fn node(&self, at: Anomaly, dm_to_end: f64, w: f64) -> Node {
        Node {
            at,
            to_end: dm_to_end * self.inv_n,
            weight: self.weight(&at, w),
        }
    }

    /// `Phi(t1, s) B` at a node (in-plane and normal blocks), with its weight.
    fn value(&self, end: &EndFactor, a1: &Anomaly, node: Node) -> (Packed, f64) {
        let Node { at, to_end, weight } = node;
        let scale = at.ir * self.inv_k2;
        // unit accelerations along x and y enter as u~' = 1 / (k^2 rho): the velocity
        // columns of psi^-1 P
        let v = self.psi_inv_velocity(&at) * scale;
        let g_in = end.la * v + end.lb * (v.row(3) * (self.k2 * to_end));
        let (sd, cd) = sin_cos_difference(a1, &at);
        let gz = end.unz * Vector2::new(sd, cd) * scale;
        let mut v = [0.0; 10];
        v[..8].copy_from_slice(g_in.as_slice());
        v[8..].copy_from_slice(gz.as_slice());
        (v, weight)
    }

    /// Input matrix and (with `qc`) process noise by the quadrature of the integrand's
    /// `values` ([`Packed`], with their weights in time), written into `gamma`'s in-plane and
    /// normal entries and (with `qc`) `q`'s: for a diagonal `qc` only those, the others,
    /// zero, being the caller's to set.
    #[inline(always)]
    fn quadrature(
        values: impl Iterator<Item = (Packed, f64)>,
        qc: Option<&Mat3>,
        gamma: &mut Mat63,
        q: &mut Mat6,
    ) -> Option<[f64; 3]> {
        // a diagonal density (every caller in relnav) is summed per axis and per block, on
        // four-lane columns (all 16 in-plane entries, `q_in[k][j]`, the lower triangle read)
        let diagonal = qc.map(|m| {
            let m = (m + m.transpose()) * 0.5;
            (m[(0, 1)] == 0.0 && m[(0, 2)] == 0.0 && m[(1, 2)] == 0.0)
                .then(|| [m[(0, 0)], m[(1, 1)], m[(2, 2)]])
        });
        let mut g_sum: Packed = [0.0; 10];
        let (mut q_in, mut q_z) = ([[0.0; 4]; 4], [0.0; 3]);
        let mut q_full = Mat6::zeros();
        for (v, weight) in values {
            for (s, x) in g_sum.iter_mut().zip(&v) {
                *s += x * weight;
            }
            match (qc, diagonal) {
                (Some(_), Some(Some(d))) => {
                    for (c, dj) in [in_column(&v, 0), in_column(&v, 1)].iter().zip(d) {
                        let wc = mul4(*c, [weight * dj; 4]);
                        for (col, &ck) in q_in.iter_mut().zip(c) {
                            axpy4(col, &wc, ck);
                        }
                    }
                    let wz = [v[8] * (weight * d[2]), v[9] * (weight * d[2])];
                    q_z[0] += wz[0] * v[8];
                    q_z[1] += wz[1] * v[8];
                    q_z[2] += wz[1] * v[9];
                }
                (Some(qc), _) => {
                    let mut g = Mat63::zeros();
                    unpack(&v, &mut g);
                    q_full += g * qc * g.transpose() * weight;
                }
                (None, _) => {}
            }
        }
        unpack(&g_sum, gamma);
        if matches!(diagonal, Some(Some(_))) {
            const IDX: [usize; 4] = [0, 1, 3, 4];
            for (j, &r) in IDX.iter().enumerate() {
                for (k, &c) in IDX.iter().enumerate().take(j + 1) {
                    q[(r, c)] = q_in[k][j];
                    q[(c, r)] = q_in[k][j];
                }
            }
            q[(2, 2)] = q_z[0];
            q[(5, 2)] = q_z[1];
            q[(2, 5)] = q_z[1];
            q[(5, 5)] = q_z[2];
        } else if qc.is_some() {
            *q = (q_full + q_full.transpose()) * 0.5;
        }
        diagonal.flatten()
    }

    /// [`EllipticModel::quadrature`] by [`EllipticModel::panel_nodes`] from `a0` to `a1`.
    fn panel_quadrature(&self, a0: &Anomaly, a1: &Anomaly, qc: Option<&Mat3>) -> (Mat63, Mat6) {
        let end = self.end_factor(a1);
        let values = self.panel_nodes(a0, a1).map(|n| self.value(&end, a1, n));
        let (mut gamma, mut q) = (Mat63::zeros(), Mat6::zeros());
        Self::quadrature(values, qc, &mut gamma, &mut q);
        (gamma, q)
    }

    /// The exact step (transition, input matrix, noise) from `t0` over `dt >= 0`.
    fn exact(&self, t0: f64, dt: f64, qc: Option<&Mat3>) -> DiscreteModel {
        let mut out = DiscreteModel::default();
        self.exact_into(&mut KeplerMemo::default(), t0, dt, qc, &mut out);
        out
    }

    /// [`EllipticModel::exact`] into `out`, with the start's anchor kept in `memo` (written
    /// in place: a step's matrices are 90 numbers, which the navigator would otherwise copy
    /// through every layer).
    fn exact_into(
        &self,
        memo: &mut KeplerMemo,
        t0: f64,
        dt: f64,
        qc: Option<&Mat3>,
        out: &mut DiscreteModel,
    ) {
        out.t = t0;
        out.dt = dt;
        let dm = self.n * dt;
        // the step as the caller's clock takes it: from t0 to t1 = t0 + dt, rounded
        // a short step (false for NaN): the end and the nodes from the start, no Kepler
        // solve and no sin_cos beyond the start's; compiled for AVX2 where the CPU has it
        // (the same bits)
        if dm <= self.short_dm {
            // the zeros (the in-plane and normal motions do not couple) set here: packing a
            // number with a zero in the dispatched code takes a `vmovq` that valgrind 3.19
            // cannot decode
            zero_coupling(out, qc.is_some());
            crate::numerics::simd::dispatch(
                #[inline(always)]
                || {
                    let t1 = t0 + dt;
                    let h = t1 - t0;
                    // the end is the next step's start: one increment solve per step
                    let a0 = self.start(t0, memo);
                    let a1 = self.start(t1, memo);
                    let end = self.end_factor(&a1);
                    self.phi_with(&end, &a0, &a1, self.k2 * h, &mut out.phi);
                    self.short_gamma_q(&a0, &a1, h, qc, out);
                },
            );
            return;
        }
        let a0 = self.start(t0, memo);
        (out.phi, out.gamma, out.q) = self.long_parts(a0, t0, dt, qc);
    }

    /// A step longer than the short step's bound.
    fn long_parts(&self, a0: Anomaly, t0: f64, dt: f64, qc: Option<&Mat3>) -> (Mat6, Mat63, Mat6) {
        let period = self.period();
        let whole = (dt / period).floor();
        if whole.is_nan() || whole < 1.0 {
            let a1 = self.anomaly(t0 + dt);
            let phi = self.phi_between(&a0, &a1, self.k2 * dt);
            let (gamma, q) = self.panel_quadrature(&a0, &a1, qc);
            return (phi, gamma, q);
        }
        // k whole periods from t0, then the remainder: Phi(t0 + i P, t0) = I + i D
        let rest = dt - whole * period;
        let a_p = Anomaly {
            big_e: a0.big_e + TAU,
            ..a0
        };
        let (gamma_p, q_p) = self.panel_quadrature(&a0, &a_p, qc);
        let d = self.phi_between(&a0, &a0, self.k2 * period) - Mat6::identity();
        let s1 = whole * (whole - 1.0) / 2.0;
        let s2 = (whole - 1.0) * whole * (2.0 * whole - 1.0) / 6.0;
        let gamma_k = gamma_p * whole + d * gamma_p * s1;
        let dq = d * q_p;
        let q_k = q_p * whole + (dq + dq.transpose()) * s1 + dq * d.transpose() * s2;
        let m_k = Mat6::identity() + d * whole;
        let a1 = self.anomaly(t0 + rest);
        let phi_r = self.phi_between(&a0, &a1, self.k2 * rest);
        let (gamma_r, q_r) = self.panel_quadrature(&a0, &a1, qc);
        let q = phi_r * q_k * phi_r.transpose() + q_r;
        (
            phi_r * m_k,
            phi_r * gamma_k + gamma_r,
            (q + q.transpose()) * 0.5,
        )
    }

    /// Propagate a state exactly from `t0` over `dt` with a constant acceleration.
    pub fn propagate(&self, x: &State, accel: &Vec3, t0: f64, dt: f64) -> State {
        self.exact(t0, dt, None).apply(x, accel)
    }

    /// The zero-order-hold input matrix of the step from `t0` over `dt`.
    pub fn gamma(&self, t0: f64, dt: f64) -> Mat63 {
        self.exact(t0, dt, None).gamma
    }
}

/// `P^T m` for [`ya_from_canonical`]'s signed permutation `P`, without a product.
fn rows_pt(m: &Matrix4<f64>) -> Matrix4<f64> {
    Matrix4::from_rows(&[-m.row(1), m.row(0).owned(), -m.row(3), m.row(2).owned()])
}

/// Sets the entries of a step's matrices that couple the in-plane (x, y) and normal (z)
/// motions, all zero, and without `noise` the whole noise: the short step writes every
/// other entry.
fn zero_coupling(out: &mut DiscreteModel, noise: bool) {
    for p in [0, 1, 3, 4] {
        for z in [2, 5] {
            out.phi[(p, z)] = 0.0;
            out.phi[(z, p)] = 0.0;
            out.q[(p, z)] = 0.0;
            out.q[(z, p)] = 0.0;
        }
        out.gamma[(p, 2)] = 0.0;
    }
    for z in [2, 5] {
        out.gamma[(z, 0)] = 0.0;
        out.gamma[(z, 1)] = 0.0;
    }
    if !noise {
        out.q = Mat6::zeros();
    }
}

/// `m P`, likewise.
fn cols_p(m: &Matrix4<f64>) -> Matrix4<f64> {
    Matrix4::from_columns(&[
        -m.column(1),
        m.column(0).owned(),
        -m.column(3),
        m.column(2).owned(),
    ])
}

/// The 6x3 input-shaped matrix of a [`Packed`] one, written into its in-plane and normal
/// entries of `g`; the others, zero, are the caller's to set.
#[inline(always)]
fn unpack(v: &Packed, g: &mut Mat63) {
    for (row, src) in [(0, 0), (1, 1), (3, 2), (4, 3)] {
        g[(row, 0)] = v[src];
        g[(row, 1)] = v[4 + src];
    }
    g[(2, 2)] = v[8];
    g[(5, 2)] = v[9];
}

/// The in-plane rows of input `axis` (0: x, 1: y) of a [`Packed`] matrix.
#[inline(always)]
fn in_column(v: &Packed, axis: usize) -> [f64; 4] {
    let c = 4 * axis;
    [v[c], v[c + 1], v[c + 2], v[c + 3]]
}

/// A 6x3 input-shaped matrix packed by input column: the x input's in-plane rows (x, y, vx,
/// vy), the y input's, then the z input's normal rows (z, vz); the other entries are zero.
type Packed = [f64; 10];

/// `(sin, cos)` of the true-anomaly difference `nu(a) - nu(b)`.
fn sin_cos_difference(a: &Anomaly, b: &Anomaly) -> (f64, f64) {
    (a.sn * b.cn - a.cn * b.sn, a.cn * b.cn + a.sn * b.sn)
}

/// The 6x6 transition from its in-plane (x, y, vx, vy) and normal (z, vz) blocks, written
/// into those entries of `m`; the others, zero, are the caller's to set.
#[inline(always)]
fn assemble(inplane: &Matrix4<f64>, normal: &Matrix2<f64>, m: &mut Mat6) {
    const IDX: [usize; 4] = [0, 1, 3, 4];
    for (i, &r) in IDX.iter().enumerate() {
        for (j, &c) in IDX.iter().enumerate() {
            m[(r, c)] = inplane[(i, j)];
        }
    }
    m[(2, 2)] = normal[(0, 0)];
    m[(2, 5)] = normal[(0, 1)];
    m[(5, 2)] = normal[(1, 0)];
    m[(5, 5)] = normal[(1, 1)];
}

impl EllipticModel {
    /// [`RelativeDynamics::step`] into `out`, with the start's Kepler anchor kept in `memo`
    /// (the same result, bit for bit; a caller stepping forward solves Kepler's equation once per
    /// `short_dm` of mean anomaly instead of once per step).
    pub fn step_into(
        &self,
        memo: &mut KeplerMemo,
        t: f64,
        dt: f64,
        qc: &Mat3,
        method: Discretization,
        out: &mut DiscreteModel,
    ) {
        match method {
            Discretization::Exact => self.exact_into(memo, t, dt, Some(qc), out),
            Discretization::Euler => *out = self.step(t, dt, qc, method),
        }
    }
}

impl RelativeDynamics for EllipticModel {
    fn step(&self, t: f64, dt: f64, qc: &Mat3, method: Discretization) -> DiscreteModel {
        match method {
            Discretization::Exact => self.exact(t, dt, Some(qc)),
            Discretization::Euler => {
                let b = super::CwModel::continuous_b();
                DiscreteModel {
                    t,
                    dt,
                    phi: Mat6::identity() + self.continuous_a(t) * dt,
                    gamma: b * dt,
                    q: b * qc * b.transpose() * dt,
                }
            }
        }
    }
    fn step_noise(&self, t: f64, dt: f64, qc: &Mat3) -> Mat6 {
        self.exact(t, dt, Some(qc)).q
    }
    fn system_matrix(&self, t: f64) -> Mat6 {
        self.continuous_a(t)
    }
    fn time_invariant(&self) -> bool {
        false
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dynamics::CwModel;

    const MU: f64 = 3.986_004_418e14;

    /// Kepler's equation by bisection (the test's own solver).
    fn kepler_bisect(m: f64, e: f64) -> f64 {
        let (mut lo, mut hi) = (m - 1.0, m + 1.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if mid - e * mid.sin() < m {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }

    /// The linearised equations' system matrix at eccentric anomaly `big_e`, written from
    /// the orbit's geometry (radius, radial rate, angular rate), not from the model's
    /// scaled variables.
    fn a_of(n: f64, e: f64, big_e: f64) -> Mat6 {
        let a = (MU / (n * n)).cbrt();
        let r = a * (1.0 - e * big_e.cos());
        let p = a * (1.0 - e * e);
        let h = (MU * p).sqrt();
        let w = h / (r * r);
        let rdot = (MU * a).sqrt() * e * big_e.sin() / r;
        let wd = -2.0 * rdot * w / r;
        let g = MU / (r * r * r);
        let mut m = Mat6::zeros();
        m[(0, 3)] = 1.0;
        m[(1, 4)] = 1.0;
        m[(2, 5)] = 1.0;
        m[(3, 0)] = w * w + 2.0 * g;
        m[(3, 1)] = wd;
        m[(3, 4)] = 2.0 * w;
        m[(4, 0)] = -wd;
        m[(4, 1)] = w * w - g;
        m[(4, 3)] = -2.0 * w;
        m[(5, 2)] = -g;
        m
    }

    /// `Phi`, `Gamma` and `Qd` of the step from mean anomaly `m0` over `dt` by RK4 on
    /// `Phi' = A Phi`, `Gamma' = A Gamma + B`, `Q' = A Q + Q A^T + B qc B^T`, integrated in
    /// the eccentric anomaly (`dt/dE = (1 - e cos E) / n`) with `steps` steps.
    fn integrated(
        n: f64,
        e: f64,
        m0: f64,
        dt: f64,
        qc: &Mat3,
        steps: usize,
    ) -> (Mat6, Mat63, Mat6) {
        let e0 = kepler_bisect(m0, e);
        let e1 = kepler_bisect(m0 + n * dt, e);
        let b = CwModel::continuous_b();
        let bqb = b * qc * b.transpose();
        type Y = (Mat6, Mat63, Mat6);
        let f = |big_e: f64, y: &Y| -> Y {
            let a = a_of(n, e, big_e);
            let k = (1.0 - e * big_e.cos()) / n;
            (
                a * y.0 * k,
                (a * y.1 + b) * k,
                (a * y.2 + y.2 * a.transpose() + bqb) * k,
            )
        };
        let add = |y: &Y, d: &Y, s: f64| -> Y { (y.0 + d.0 * s, y.1 + d.1 * s, y.2 + d.2 * s) };
        let h = (e1 - e0) / steps as f64;
        let mut y: Y = (Mat6::identity(), Mat63::zeros(), Mat6::zeros());
        for i in 0..steps {
            let x = e0 + i as f64 * h;
            let k1 = f(x, &y);
            let k2 = f(x + 0.5 * h, &add(&y, &k1, 0.5 * h));
            let k3 = f(x + 0.5 * h, &add(&y, &k2, 0.5 * h));
            let k4 = f(x + h, &add(&y, &k3, h));
            y = (
                y.0 + (k1.0 + k2.0 * 2.0 + k3.0 * 2.0 + k4.0) * (h / 6.0),
                y.1 + (k1.1 + k2.1 * 2.0 + k3.1 * 2.0 + k4.1) * (h / 6.0),
                y.2 + (k1.2 + k2.2 * 2.0 + k3.2 * 2.0 + k4.2) * (h / 6.0),
            );
        }
        y
    }

    /// Largest entry difference over the reference's largest entry.
    fn rel<const R: usize, const C: usize>(
        a: &nalgebra::SMatrix<f64, R, C>,
        b: &nalgebra::SMatrix<f64, R, C>,
    ) -> f64 {
        (a - b).abs().max() / b.abs().max()
    }

    /// The fixed Halley iterations reach double precision for every `e <= 0.99` and every
    /// mean anomaly, with revolutions, and agree with bisection.
    #[test]
    fn kepler_converges_to_double_precision_in_fixed_iterations() {
        let (mut worst, mut worst_sc) = (0.0f64, 0.0f64);
        for ie in 0..=99 {
            let e = ie as f64 * 0.01;
            let small = (0..60).map(|k| 10f64.powf(-12.0 + 0.2 * k as f64));
            let grid = (0..=2000).map(|k| -PI + TAU * k as f64 / 2000.0);
            for m in grid.chain(small.clone()).chain(small.map(|m| -m)) {
                let big_e = eccentric_anomaly(m, e);
                // one more Newton step moves E by no more than its conditioning allows
                let step = (big_e - e * big_e.sin() - m) / (1.0 - e * big_e.cos());
                // relative to E, or 1e-30 rad absolute at m = 0 (where E = 0)
                let tol = 4.0 * f64::EPSILON * big_e.abs().max(1e-30) / (1.0 - e * big_e.cos());
                let err = if step.abs() <= 1e-30 {
                    0.0
                } else {
                    step.abs() / tol
                };
                worst = worst.max(err);
                assert!(err <= 1.0, "e {e} m {m}: E {big_e}, Newton step {step:e}");
                // the sine and cosine carried by angle addition are those of E, to the
                // rounding of up to six additions
                let (_, s, c) = kepler(m, e);
                let (s_ref, c_ref) = big_e.sin_cos();
                let tol = 8.0 * f64::EPSILON;
                worst_sc = worst_sc.max((s - s_ref).abs().max((c - c_ref).abs()) / f64::EPSILON);
                assert!(
                    (s - s_ref).abs() <= tol && (c - c_ref).abs() <= tol,
                    "e {e} m {m}: {} {}",
                    s - s_ref,
                    c - c_ref
                );
                for turns in [-3.0, 5.0] {
                    let shifted = eccentric_anomaly(m + turns * TAU, e);
                    assert!(
                        (shifted - big_e - turns * TAU).abs() <= 1e-12,
                        "e {e} m {m}"
                    );
                }
            }
            let b = kepler_bisect(1.234, e);
            assert!(
                (eccentric_anomaly(1.234, e) - b).abs() <= 4.0 * f64::EPSILON * 4.0 / (1.0 - e)
            );
        }
        eprintln!(
            "kepler: worst step / tolerance {worst:.3}; sine and cosine within {worst_sc:.1} ulps"
        );
    }

    /// The permutation helpers are the products with `P`, and the velocity columns are
    /// those of `psi^-1 P`.
    #[test]
    fn permutations_and_velocity_columns() {
        let p = ya_from_canonical();
        let m = Matrix4::from_fn(|i, j| (1 + i * 4 + j) as f64);
        assert_eq!(rows_pt(&m), p.transpose() * m);
        assert_eq!(cols_p(&m), m * p);
        let model = EllipticModel::new(1e-3, 0.4, 0.3);
        let a = model.at_e(1.1);
        let full = model.psi_inv(&a) * p;
        let v = model.psi_inv_velocity(&a);
        assert_eq!(v.column(0), full.column(2));
        assert_eq!(v.column(1), full.column(3));
        // and psi_inv is the inverse of psi at J = 0
        let (pa, _) = model.psi(&a);
        assert!((model.psi_inv(&a) * pa - Matrix4::identity()).abs().max() < 1e-14);
    }

    /// At e = 0 the elliptic model is the CW model, to rounding.
    #[test]
    fn circular_orbit_is_cw() {
        let n = TAU / 5400.0;
        let qc = Mat3::from_diagonal(&Vec3::new(1e-6, 2e-6, 3e-6));
        let ell = EllipticModel::new(n, 0.0, 0.7);
        let cw = CwModel::new(n);
        for (t0, dt) in [
            (0.0, 1.0),
            (0.0, 2.0),
            (100.0, 60.0),
            (1e4, 1000.0),
            (3.0, 5400.0),
            (7.0, 3.5 * 5400.0),
        ] {
            let s = ell.step(t0, dt, &qc, Discretization::Exact);
            let c = cw.discretize(dt, &qc, Discretization::Exact);
            let (ep, eg, eq) = (
                rel(&s.phi, &c.phi),
                rel(&s.gamma, &c.gamma),
                rel(&s.q, &c.q),
            );
            eprintln!("e = 0, dt {dt}: phi {ep:.1e} gamma {eg:.1e} q {eq:.1e}");
            // the transition in closed form: to rounding; the input matrix and noise too,
            // but for a step short enough for the cubic rule (dt 1 here), within its bound
            let quadrature = if n * dt <= CUBIC_SPAN {
                CUBIC_BOUND
            } else {
                1e-12
            };
            assert!(
                ep < 1e-12 && eg < quadrature && eq < quadrature,
                "dt {dt}: {ep:e} {eg:e} {eq:e}"
            );
            assert_eq!(ell.continuous_a(t0), {
                let mut a = cw.continuous_a();
                a[(3, 0)] = ell.continuous_a(t0)[(3, 0)];
                a[(4, 1)] = ell.continuous_a(t0)[(4, 1)];
                a[(5, 2)] = ell.continuous_a(t0)[(5, 2)];
                a
            });
            assert!(rel(&ell.continuous_a(t0), &cw.continuous_a()) < 1e-14);
        }
    }

    /// Transition, input matrix and noise against the integrated linearised equations, for
    /// eccentricities up to 0.95 and steps up to one period (several start anomalies,
    /// perigee passes included; diagonal and correlated densities); the quadrature stays
    /// within [`QUADRATURE_BOUND`].
    #[test]
    fn step_matches_the_integrated_linearised_equations() {
        let n = TAU / 7200.0;
        let diagonal = Mat3::from_diagonal(&Vec3::new(1e-8, 4e-8, 2e-8));
        // a correlated density takes the general path of the noise sum
        let mut full = diagonal;
        for (i, j, v) in [(0, 1, 1e-8), (0, 2, -5e-9), (1, 2, 8e-9)] {
            full[(i, j)] = v;
            full[(j, i)] = v;
        }
        let mut worst = [0.0f64; 3];
        for e in [0.005, 0.1, 0.5, 0.81, 0.95] {
            let qc = if e > 0.3 { full } else { diagonal };
            for (m0, frac) in [(-0.3, 0.002), (2.0, 0.05), (-1.0, 0.3), (0.4, 0.999)] {
                let dt = frac * 7200.0;
                // the model's epoch at true anomaly 0 (mean anomaly 0): start at m0
                let model = EllipticModel::new(n, e, 0.0);
                let t0 = m0 / n;
                let s = model.step(t0, dt, &qc, Discretization::Exact);
                // RK4 at N and 2N steps, Richardson-extrapolated (its h^4 term removed)
                let steps = ((frac * 64000.0) as usize).max(1600);
                let (p1, g1, q1) = integrated(n, e, m0, dt, &qc, steps);
                let (p2, g2, q2) = integrated(n, e, m0, dt, &qc, 2 * steps);
                let x = |a: f64, b: f64| (16.0 * b - a) / 15.0;
                let (phi, gamma, q) = (p1.zip_map(&p2, x), g1.zip_map(&g2, x), q1.zip_map(&q2, x));
                let errs = [rel(&s.phi, &phi), rel(&s.gamma, &gamma), rel(&s.q, &q)];
                for (w, v) in worst.iter_mut().zip(errs) {
                    *w = w.max(v);
                }
                assert!(
                    errs[0] < 1e-11 && errs[1] < 1e-11 && errs[2] < QUADRATURE_BOUND,
                    "e {e} m0 {m0} dt {dt}: {errs:?}"
                );
            }
        }
        eprintln!(
            "elliptic step vs integration: phi {:.1e} gamma {:.1e} q {:.1e}",
            worst[0], worst[1], worst[2]
        );
    }

    /// The short step (its end by Kepler's equation in the increment, the quintic Hermite
    /// rule from the transition) against Kepler's equation solved afresh and the six-node
    /// panels, at the longest step it takes and fractions of it, for every eccentricity up to
    /// 0.99 and start anomalies around the orbit (perigee passes, where the integrands vary
    /// fastest, included). At `e = 0.99` the rule inherits the rounding of the closed-form
    /// transition near apogee (measured here as the transition against the product of its
    /// halves), so its bound there is that rounding's order, not [`SHORT_BOUND`].
    #[test]
    fn short_steps_match_kepler_and_the_panels() {
        let n = TAU / 7200.0;
        let qc = Mat3::from_diagonal(&Vec3::new(1e-8, 4e-8, 2e-8));
        let mut worst = [0.0f64; 3];
        // at e = 0.99: the rule against the panels, the transition against its halves
        let mut near_one = [0.0f64; 2];
        // the cubic rule's steps (w h <= CUBIC_SPAN): their worst error, their count
        let (mut cubic, mut cubic_steps) = (0.0f64, 0);
        for e in [0.001, 0.005, 0.1, 0.3, 0.5, 0.7, 0.81, 0.9, 0.95, 0.99] {
            let short = EllipticModel::new(n, e, 0.0);
            for k in 0..240 {
                let e0 = -PI + TAU * k as f64 / 240.0;
                let a0 = short.at_e(e0);
                // steps at the cubic rule's bound (w h just below and just above it)
                let w0 = short.k2 * a0.rho * a0.rho;
                let at_bound = [0.99, 1.01].map(|f| f * CUBIC_SPAN / w0 * n / short.short_dm);
                for frac in [0.001, 0.005, 0.01, 0.03, 0.1, 0.25, 1.0]
                    .into_iter()
                    .chain(at_bound.into_iter().filter(|&f| f <= 1.0))
                {
                    let dm = frac * short.short_dm;
                    let a1 = short.advanced(&a0, dm).0;
                    // against the full solve of the same mean anomaly, in ulps of E scaled
                    // by 1 / (1 - e cos E) as the Kepler test
                    let m1 = (e0 - e * e0.sin()) + dm;
                    let fresh = short.at_e(eccentric_anomaly(m1, e));
                    let ulps = (a1.big_e - fresh.big_e).abs() * (1.0 - e * fresh.ce)
                        / (f64::EPSILON * 4.0);
                    worst[0] = worst[0].max(ulps);
                    // sine and cosine by angle addition: within the anomaly's own difference
                    let tol = (a1.big_e - fresh.big_e).abs() + 4.0 * f64::EPSILON;
                    assert!(
                        (a1.se - fresh.se).abs() <= tol && (a1.ce - fresh.ce).abs() <= tol,
                        "{e} {e0} {dm}: {} {}",
                        a1.se - fresh.se,
                        a1.ce - fresh.ce
                    );
                    let d = a1.big_e - a0.big_e;
                    assert!((0.0..=short.short_span).contains(&d), "{e} {e0} {d}");
                    let end = short.end_factor(&a1);
                    let mut step = DiscreteModel::default();
                    short.phi_with(&end, &a0, &a1, short.k2 * dm / n, &mut step.phi);
                    short.short_gamma_q(&a0, &a1, dm / n, Some(&qc), &mut step);
                    let DiscreteModel {
                        phi, gamma: g, q, ..
                    } = step;
                    let (gr, qr) = short.panel_quadrature(&a0, &a1, Some(&qc));
                    let err = rel(&g, &gr).max(rel(&q, &qr));
                    let rho = a0.rho.max(a1.rho);
                    if short.k2 * rho * rho * dm / n <= CUBIC_SPAN && e <= CUBIC_E {
                        cubic = cubic.max(err);
                        cubic_steps += 1;
                    }
                    if e < 0.99 {
                        worst[1] = worst[1].max(rel(&g, &gr));
                        worst[2] = worst[2].max(rel(&q, &qr));
                    } else {
                        let am = short.advanced(&a0, 0.5 * dm).0;
                        let j = 0.5 * short.k2 * dm / n;
                        let halves =
                            short.phi_between(&am, &a1, j) * short.phi_between(&a0, &am, j);
                        near_one[0] = near_one[0].max(err);
                        near_one[1] = near_one[1].max(rel(&phi, &halves));
                    }
                }
            }
        }
        eprintln!(
            "short steps: end anomaly {:.2} x 4 ulps (scaled); Hermite rule vs six-node panels: \
             gamma {:.1e} q {:.1e}; at e = 0.99 {:.1e}, the transition against its halves \
             {:.1e}; the cubic rule's {cubic_steps} steps {cubic:.1e}",
            worst[0], worst[1], worst[2], near_one[0], near_one[1]
        );
        assert!(
            cubic < CUBIC_BOUND && cubic_steps > 1000,
            "{cubic} {cubic_steps}"
        );
        assert!(worst[0] < 2.0, "{worst:?}");
        assert!(
            near_one[0] < 1e-7 && near_one[1] > 0.25 * near_one[0],
            "{near_one:?}"
        );
        assert!(
            worst[1] < SHORT_BOUND && worst[2] < SHORT_BOUND,
            "{worst:?}"
        );
    }

    /// A step's start anomaly, advanced from its grid anchor, against Kepler's equation
    /// solved afresh at the same time (times around many orbits, before the epoch and far
    /// after it), and a step taken with a kept anchor equals one taken without, bit for bit.
    /// A caller stepping forward (the memo keeps each step's end as the next one's start)
    /// gets the steps of a fresh model, bit for bit, on the dispatched (AVX2 where present)
    /// and the baseline instruction set alike; a non-diagonal density takes the general sum
    /// and agrees with the diagonal one's to rounding.
    #[test]
    fn forward_steps_are_fresh_steps_on_either_instruction_set() {
        use crate::numerics::simd::with_baseline;
        let n = TAU / 5400.0;
        let qc = Mat3::from_diagonal(&Vec3::new(1e-8, 4e-8, 2e-8));
        for e in [0.005, 0.3, 0.81, 0.95] {
            let m = EllipticModel::new(n, e, 2.0);
            let run = || {
                let mut memo = KeplerMemo::default();
                let (mut t, mut steps) = (0.0, Vec::new());
                for k in 0..400 {
                    let dt = if k % 50 == 49 {
                        0.25
                    } else {
                        1.0 + 0.5 * (k % 3) as f64
                    };
                    let mut kept = DiscreteModel::default();
                    m.step_into(&mut memo, t, dt, &qc, Discretization::Exact, &mut kept);
                    assert_eq!(kept, m.step(t, dt, &qc, Discretization::Exact), "{e} {t}");
                    steps.push(kept);
                    t += dt;
                }
                steps
            };
            assert_eq!(run(), with_baseline(run), "{e}");
            // the general density's sum (a density with a vanishing off-diagonal entry is
            // summed as diagonal: the test perturbs one)
            let mut full = qc;
            full[(0, 1)] = 1e-30;
            full[(1, 0)] = 1e-30;
            let a = m.step(123.0, 1.0, &qc, Discretization::Exact);
            let b = m.step(123.0, 1.0, &full, Discretization::Exact);
            assert!(rel(&a.q, &b.q) < 1e-14, "{e} {}", rel(&a.q, &b.q));
            assert_eq!(a.gamma, b.gamma);
        }
    }

    #[test]
    fn anchored_starts_match_kepler_and_do_not_depend_on_the_memo() {
        let n = TAU / 7200.0;
        let qc = Mat3::from_diagonal(&Vec3::new(1e-8, 4e-8, 2e-8));
        let mut worst = 0.0f64;
        for e in [0.001, 0.1, 0.5, 0.81, 0.99] {
            let m = EllipticModel::new(n, e, 0.7);
            let mut memo = KeplerMemo::default();
            for k in -3000..3000 {
                let t = 0.37 * k as f64 + if k > 0 { 1e6 } else { 0.0 };
                let a = m.start(t, &mut memo);
                let fresh = m.anomaly(t);
                let ulps = (a.big_e - fresh.big_e).abs() * (1.0 - e * fresh.ce)
                    / (f64::EPSILON * 4.0 * fresh.big_e.abs().max(1.0));
                worst = worst.max(ulps);
                // sine and cosine: within the anomaly's own difference and its rounding (two
                // chains of angle additions: the anchor's solve and the advance)
                let tol =
                    (a.big_e - fresh.big_e).abs() + 8.0 * f64::EPSILON * fresh.big_e.abs().max(1.0);
                assert!((a.se - fresh.se).abs() <= tol, "{e} {t}");
                assert!((a.ce - fresh.ce).abs() <= tol, "{e} {t}");
                if k % 97 == 0 {
                    let mut kept = DiscreteModel::default();
                    m.step_into(&mut memo, t, 1.3, &qc, Discretization::Exact, &mut kept);
                    assert_eq!(kept, m.step(t, 1.3, &qc, Discretization::Exact), "{e} {t}");
                }
            }
        }
        eprintln!("anchored start anomalies: {worst:.2} x 4 ulps (scaled, relative)");
        assert!(worst < 2.0, "{worst}");
    }

    /// The small-angle polynomials against the library's sine and cosine.
    #[test]
    fn small_angles() {
        for k in -1000..=1000 {
            let x = SMALL_ANGLE * k as f64 / 1000.0;
            let (s, c) = small_sin_cosm1(x);
            assert!((s - x.sin()).abs() <= f64::EPSILON * x.abs(), "{x}");
            // cos x - 1 = -2 sin^2(x / 2), to a few ulps of itself
            let reference = -2.0 * (0.5 * x).sin().powi(2);
            assert!(
                (c - reference).abs() <= 4.0 * f64::EPSILON * reference.abs(),
                "{x}"
            );
        }
    }

    /// Steps of several periods (split into whole periods and a remainder) equal the
    /// composition of shorter steps.
    #[test]
    fn long_steps_compose() {
        let n = TAU / 7200.0;
        let qc = Mat3::from_diagonal(&Vec3::new(1e-8, 4e-8, 2e-8));
        for e in [0.1, 0.81] {
            let model = EllipticModel::new(n, e, 1.0);
            let (t0, dt) = (123.0, 3.4 * 7200.0);
            let long = model.step(t0, dt, &qc, Discretization::Exact);
            let composed = |parts: usize| {
                let mut phi = Mat6::identity();
                let mut gamma = Mat63::zeros();
                let mut q = Mat6::zeros();
                for i in 0..parts {
                    let h = dt / parts as f64;
                    let s = model.step(t0 + i as f64 * h, h, &qc, Discretization::Exact);
                    phi = s.phi * phi;
                    gamma = s.phi * gamma + s.gamma;
                    q = s.phi * q * s.phi.transpose() + s.q;
                }
                (phi, gamma, q)
            };
            let (phi, gamma, q) = composed(17);
            let errs = nalgebra::Vector3::new(
                rel(&long.phi, &phi),
                rel(&long.gamma, &gamma),
                rel(&long.q, &q),
            );
            eprintln!(
                "e {e}: 3.4 periods in one step vs 17: {:.1e} {:.1e} {:.1e}",
                errs[0], errs[1], errs[2]
            );
            // composing 17 steps of a transition conditioned like 1 / (1 - e^2)^2 costs
            // digits: two compositions (17 and 340 steps) differ among themselves as much
            assert!(errs.iter().all(|&v| v < 1e-9), "e {e}: {errs:?}");
        }
    }

    /// Huge or non-finite steps give numbers or NaN, never a hang or a panic.
    #[test]
    fn huge_steps_are_bounded_work() {
        let model = EllipticModel::new(1e-3, 0.5, 0.0);
        let qc = Mat3::identity();
        for dt in [1e12, 1e300, f64::INFINITY, f64::NAN] {
            let _ = model.step(0.0, dt, &qc, Discretization::Exact);
        }
        let s = model.step(0.0, 1000.0 * model.period(), &qc, Discretization::Exact);
        assert!(s.phi.iter().all(|v| v.is_finite()));
    }

    /// Euler is first order in the step: halving it quarters the one-step error.
    #[test]
    fn euler_is_first_order() {
        let model = EllipticModel::new(TAU / 7200.0, 0.3, 0.5);
        let qc = Mat3::zeros();
        let err = |dt: f64| {
            let x = model.step(10.0, dt, &qc, Discretization::Euler).phi;
            (x - model.phi(10.0, dt)).abs().max()
        };
        let ratio = err(20.0) / err(10.0);
        assert!((ratio - 4.0).abs() < 0.2, "ratio {ratio}");
    }
}
