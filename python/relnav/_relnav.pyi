"""Type stubs of the extension module relnav._relnav (Rust, PyO3)."""

from __future__ import annotations

from os import PathLike
from typing import Any, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

_Vec3 = Union[Sequence[float], npt.ArrayLike]
_FloatArray = npt.NDArray[np.float64]

class Estimator:
    """A relative-navigation estimator: one filter of the library behind the FMU's step
    semantics, in the configured frame and SI units (angles in radians). Keyword
    arguments are the FMU's parameters (``relnav.parameters()``)."""

    # --- parameters: begin (generated from relnav.parameters() by tests/python/test_package_api.py; regenerate: RELNAV_BLESS_STUBS=1 pytest tests/python/test_package_api.py) ---
    def __init__(
        self,
        *,
        filter: Union[int, str] = 'ekf',
        frame: Union[int, str] = 'along_radial_antinormal',
        discretization: Union[int, str] = 'exact',
        mean_motion: float = 0.0008726646259971648,
        chaser_mass: float = 1000.0,
        sigma_range: float = 0.5,
        sigma_angle: float = 0.00017453292519943296,
        x0: float = 405.0,
        y0: float = 505.0,
        z0: float = 205.0,
        vx0: float = 0.1,
        vy0: float = 0.1,
        vz0: float = 0.1,
        sigma_pos0: float = 50.0,
        sigma_vel0: float = 1.0,
        accel_psd: float = 0.0,
        q_pos_x: float = 0.09,
        q_pos_y: float = 0.000625,
        q_pos_z: float = 0.0025,
        q_vel_x: float = 1e-06,
        q_vel_y: float = 1e-06,
        q_vel_z: float = 1e-06,
        ukf_alpha: float = 1.0,
        ukf_beta: float = 2.0,
        ukf_kappa: float = 0.0,
        seed: int = 0,
        particles: int = 1500,
        resampler: Union[int, str] = 'auto',
        resample_threshold: float = 0.6666666666666666,
        noise_model: Union[int, str] = 'gaussian',
        noise_zeta: float = 0.2,
        noise_scale: float = 10.0,
        noise_dof: float = 4.0,
        window: int = 10,
        hinf_period: float = 1.0,
        hinf_delta_bar: float = 0.05,
        hinf_b_pos: float = 0.0,
        hinf_b_vel: float = 0.0,
        hinf_d: float = 0.0,
        hinf_design: Union[int, str] = 'mixed',
        hinf_gamma_factor: float = 1.5,
        hinf_acquisition: bool = True,
        aq_law: Union[int, str] = 'gated',
        aq_gate_window: int = 10,
        aq_gate_quantile: float = 0.999,
        imm_modes: int = 3,
        imm_accel_psd_1: float = 0.0,
        imm_accel_psd_2: float = 1e-06,
        imm_accel_psd_3: float = 0.001,
        imm_p_stay_1: float = 0.999999,
        imm_p_stay_2: float = 0.9,
        imm_p_stay_3: float = 0.9,
        pf_move: bool = True,
        pf_threads: int = 0,
        eccentricity: float = 0.0,
        true_anomaly0: float = 0.0,
        sigma_camera: float = 0.001,
        sigma_gnss: float = 0.05,
        sigma_gnss_velocity: float = 0.0005,
        range_bank: int = 1,
        sigma_range0: float = 0.0,
        camera_noise_model: Union[int, str] = 'gaussian',
        camera_noise_zeta: float = 0.2,
        camera_noise_scale: float = 10.0,
        camera_noise_dof: float = 4.0,
        gnss_noise_model: Union[int, str] = 'gaussian',
        gnss_noise_zeta: float = 0.2,
        gnss_noise_scale: float = 10.0,
        gnss_noise_dof: float = 4.0,
        hinf_sensors: int = 1,
        pf_prior: Union[int, str] = 'particle',
    ) -> None:
        """Keyword arguments are the FMU's parameters (names, types, defaults):

            filter: Estimator (codes 1-11: 1-3 Kalman (EKF, UKF, AQUKF), 4-8 particle filters, 9 robust H-infinity, 10 IMM, 11 robust EKF). One of: 1 ekf, 2 ukf, 3 aqukf, 4 pf, 5 rpf, 6 upf, 7 gapf, 8 cgapf, 9 hinf, 10 imm, 11 rekf.
            frame: Hill-frame convention of every input and output vector and angle. One of: 1 radial_along_normal, 2 along_radial_antinormal, 3 along_antinormal_nadir.
            discretization: Discretisation of the CW model. One of: 1 exact, 2 euler.
            mean_motion [rad/s]: Mean motion of the target's orbit, 2 pi / period (> 0).
            chaser_mass [kg]: Chaser mass: thrust / mass = acceleration (> 0).
            sigma_range [m]: Range measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0).
            sigma_angle [rad]: Azimuth and elevation measurement noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0).
            x0 [m]: Initial estimate of x.
            y0 [m]: Initial estimate of y.
            z0 [m]: Initial estimate of z.
            vx0 [m/s]: Initial estimate of vx.
            vy0 [m/s]: Initial estimate of vy.
            vz0 [m/s]: Initial estimate of vz.
            sigma_pos0 [m]: Initial position uncertainty per axis, 1 sigma (> 0).
            sigma_vel0 [m/s]: Initial velocity uncertainty per axis, 1 sigma (> 0).
            accel_psd [m2/s3]: Process noise: spectral density of a continuous white acceleration per axis (Van Loan discretisation; >= 0).
            q_pos_x [m2/s]: Process noise: x position variance added per second (discrete Q = q h; >= 0).
            q_pos_y [m2/s]: Process noise: y position variance added per second (>= 0).
            q_pos_z [m2/s]: Process noise: z position variance added per second (>= 0).
            q_vel_x [m2/s3]: Process noise: vx variance added per second (>= 0).
            q_vel_y [m2/s3]: Process noise: vy variance added per second (>= 0).
            q_vel_z [m2/s3]: Process noise: vz variance added per second (>= 0).
            ukf_alpha: UKF sigma-point spread alpha (> 0); also the unscented proposal of upf and cgapf.
            ukf_beta: UKF beta (2 for Gaussian priors).
            ukf_kappa: UKF kappa.
            seed: Seed of the filters that draw random numbers (identical seeds give identical outputs).
            particles: Number of particles of the particle filters (codes 4-8; 1..2000000).
            resampler: Resampling scheme of the particle filters (auto: multinomial with pf_move = false, systematic with the moves). One of: 1 multinomial, 2 systematic, 3 stratified, 4 residual, 5 auto.
            resample_threshold: The particle filters resample when the effective sample size drops below resample_threshold * particles (in (0, 1]; paper 000: 2/3).
            noise_model: Measurement-noise density scaled by sigma_range and sigma_angle: the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance. One of: 1 gaussian, 2 mixture, 3 student_t.
            noise_zeta: Mixture noise: weight of the wide component (in [0, 1)).
            noise_scale: Mixture noise: sigma of the wide component over the nominal sigma (>= 1).
            noise_dof: Student-t noise: degrees of freedom (> 2).
            window: AQUKF (filter 3): sliding-window width N of the adaptive process noise (1..512; paper 001: 10). For the AQUKF, q_vel_* is the initial adaptive density.
            hinf_period [s]: H-infinity filter (code 9): sampling period of its discrete design; fmi2DoStep with another step size is refused (set it to the communication step).
            hinf_delta_bar: H-infinity filter: bound of the orbit-rate uncertainty, w = w0 (1 + delta), |delta| <= hinf_delta_bar (paper 002: 0.05).
            hinf_b_pos [m]: H-infinity filter: process-noise scaling on positions (paper 002 B: 0.05); 0 with hinf_b_vel = 0 (default): derived from accel_psd, q_pos_*, q_vel_* (the noise every other filter uses).
            hinf_b_vel [m/s]: H-infinity filter: process-noise scaling on velocities (paper 002 B: 0.001); 0 with hinf_b_pos = 0 (default): derived.
            hinf_d [m]: H-infinity filter: scaling of the indirect position measurement noise (paper 002 D: 0.1); 0 (default): derived from sigma_range, sigma_angle and the noise model at the initial estimate's position.
            hinf_design: H-infinity filter: the LMI design (mixed H2/H-infinity by default; gamma_optimal is the pure worst-case design). One of: 1 gamma_optimal, 3 mixed.
            hinf_gamma_factor: H-infinity filter, mixed design: bound on the certified gamma (hinf_gamma) as a multiple of the gamma-optimal design's (> 1).
            hinf_acquisition: H-infinity filter: start with the Kalman gain of the design's noise model and hand over to the designed gain once that is no worse (track initiation); false: the designed gain from the first step.
            aq_law: AQUKF (filter 3): adaptation law of the velocity process noise (1 window: paper 001 at every update; 2 gated: only while the windowed NIS exceeds its chi-square bound). One of: 1 window, 2 gated.
            aq_gate_window: AQUKF, gated law: number of measurement updates in the windowed NIS (1..128).
            aq_gate_quantile: AQUKF, gated law: the gate opens when the windowed NIS exceeds its chi-square quantile at this probability (in (0, 1)).
            imm_modes: IMM (filter 10): number of modes (2 or 3).
            imm_accel_psd_1 [m2/s3]: IMM: white-acceleration density added to the process noise in mode 1 (the quiet mode; >= 0).
            imm_accel_psd_2 [m2/s3]: IMM: white-acceleration density added to the process noise in mode 2 (>= 0).
            imm_accel_psd_3 [m2/s3]: IMM: white-acceleration density added to the process noise in mode 3 (>= 0; unused with 2 modes).
            imm_p_stay_1: IMM: probability of staying in mode 1 over one second (in (0, 1)).
            imm_p_stay_2: IMM: probability of staying in mode 2 over one second (in (0, 1)).
            imm_p_stay_3: IMM: probability of staying in mode 3 over one second (in (0, 1)).
            pf_move: Particle filters (codes 4-8) with pf_prior = 1 (points; false needs it): after every update, Metropolis-Hastings moves whose target is the likelihood times the Gaussian of the predictive moments (Gaussian-prior moves, not invariant for the exact posterior; as accurate as the EKF on Gaussian noise, also with small process noise); false: the papers' filters as written (particles drawn from the prior N(x0, P0), multinomial resampling with resampler = auto, paper 000's SIR, the plain RPF, van der Merwe's UPF, and the GA-PF's and CGA-PF's operators accepted on the likelihood ratio as paper 003 writes), which degenerate with small process noise.
            pf_threads: Particle filters with pf_prior = 1 (points): worker threads of the particle loops from 32768 particles on (0: one per core; 1: the calling thread; <= 1024); results do not depend on it.
            eccentricity: Eccentricity of the target's orbit (0 <= e <= 0.99): 0 the Clohessy-Wiltshire model, > 0 the linearised elliptic model of Yamanaka and Ankersen; mean_motion stays 2 pi / period.
            true_anomaly0 [rad]: True anomaly of the target at the start time (unused at eccentricity 0).
            sigma_camera [rad]: Camera (angles-only) azimuth and elevation noise, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0): the readings camera_azimuth, camera_elevation.
            sigma_gnss [m]: Relative GNSS position noise per axis, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0): the readings gnss_x, gnss_y, gnss_z.
            sigma_gnss_velocity [m/s]: Relative GNSS velocity noise per axis, 1 sigma of the Gaussian (nominal sigma of the other noise models; > 0): the readings gnss_vx, gnss_vy, gnss_vz.
            range_bank: Kalman-type filters (codes 1-3, 10): number of members of a range-parameterised bank (1: the filter alone; 2..9: the prior split along its line of sight into a Gaussian sum, one filter per term, weighted by its measurements; for angles-only acquisition, where one filter's range collapses early).
            sigma_range0 [m]: Initial position uncertainty along the line of sight of x0 (the range), 1 sigma (>= 0; 0: sigma_pos0, the same on every axis); sigma_pos0 is then the uncertainty across it.
            camera_noise_model: Camera: density of the angle noise scaled by sigma_camera (the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance). One of: 1 gaussian, 2 mixture, 3 student_t.
            camera_noise_zeta: Camera, mixture noise: weight of the wide component (in [0, 1)).
            camera_noise_scale: Camera, mixture noise: sigma of the wide component over sigma_camera (>= 1).
            camera_noise_dof: Camera, Student-t noise: degrees of freedom (> 2).
            gnss_noise_model: Relative GNSS: density of the position and velocity noise scaled by sigma_gnss and sigma_gnss_velocity (the particle filters weigh with it, the Kalman filters assume the Gaussian of its variance). One of: 1 gaussian, 2 mixture, 3 student_t.
            gnss_noise_zeta: Relative GNSS, mixture noise: weight of the wide component (in [0, 1)).
            gnss_noise_scale: Relative GNSS, mixture noise: sigma of the wide component over the nominal sigma (>= 1).
            gnss_noise_dof: Relative GNSS, Student-t noise: degrees of freedom (> 2).
            hinf_sensors: H-infinity filter: the measurement set its design is for, the sum of 1 radio, 2 camera, 4 relative GNSS position, 8 relative GNSS velocity (it must hold the radio or the GNSS position: a camera or a velocity alone leaves the position unobservable to a linear observer); the design's noise is each sensor's at the initial estimate.
            pf_prior: Particle filters (codes 4-8): what a particle carries (2 particle, the default: a Gaussian, updated by its own EKF step, by its UKF step for the UPF and CGA-PF, with the noise density's robust update under heavy tails, the set a Gaussian sum resampled and, except for the SIR, its duplicates separated by the kind's step; pf_move and pf_threads do not apply: the terms run on the calling thread; <= 100000 particles. 1 gaussian: a point, moved as pf_move says). One of: 1 gaussian, 2 particle.
        """
    # --- parameters: end ---
    def step(
        self,
        thrust: _Vec3,
        measurement: Optional[_Vec3] = None,
        dt: float = 1.0,
        *,
        camera: Optional[Sequence[float]] = None,
        gnss_position: Optional[_Vec3] = None,
        gnss_velocity: Optional[_Vec3] = None,
    ) -> None:
        """Update with ``measurement`` = (range [m], azimuth [rad], elevation [rad]) taken
        at the step's start (``None``: no measurement), then with the declared sensors'
        readings that are given, in this order: ``camera`` = (azimuth, elevation) [rad],
        ``gnss_position`` = (x, y, z) [m], ``gnss_velocity`` = (vx, vy, vz) [m/s] (I/O
        frame), then predict over ``dt`` [s] with ``thrust`` (x, y, z) [N] held constant.
        A failed step changes nothing and raises the library's error."""
    def predict(self, thrust: _Vec3, dt: float = 1.0) -> None:
        """Time update only: predict over ``dt`` [s] with ``thrust`` [N] held."""
    def update(self, measurement: _Vec3) -> None:
        """Measurement update only, with (range [m], azimuth [rad], elevation [rad])."""
    def reset(self) -> None:
        """Back to the initial estimate (a particle filter redraws from its seed)."""
    def run(
        self,
        thrust: npt.ArrayLike,
        measurements: Optional[npt.ArrayLike] = None,
        valid: Optional[npt.ArrayLike] = None,
        dt: Union[float, npt.ArrayLike, None] = None,
        *,
        camera: Optional[npt.ArrayLike] = None,
        camera_valid: Optional[npt.ArrayLike] = None,
        gnss_position: Optional[npt.ArrayLike] = None,
        gnss_valid: Optional[npt.ArrayLike] = None,
        gnss_velocity: Optional[npt.ArrayLike] = None,
        gnss_velocity_valid: Optional[npt.ArrayLike] = None,
    ) -> Tuple[_FloatArray, _FloatArray]:
        """K steps in one call without the GIL: thrust K x 3 [N], measurements K x 3 or
        None, valid K booleans (default: every row when measurements are given), dt one
        number or K numbers (default 1 s). Row k is ``step(thrust[k], measurements[k] if
        valid[k] else None, dt[k])``; returns (estimates, sigmas), each K x 6, row k after
        step k. The declared sensors the same way, each with its flags: camera K x 2 with
        camera_valid, gnss_position K x 3 with gnss_valid, gnss_velocity K x 3 with
        gnss_velocity_valid."""
    @property
    def state(self) -> _FloatArray:
        """The estimate (x, y, z [m], vx, vy, vz [m/s]) in the configured frame."""
    @property
    def covariance(self) -> _FloatArray:
        """The 6 x 6 covariance (NaN for the H-infinity filter)."""
    @property
    def sigma(self) -> _FloatArray:
        """1-sigma per state component (NaN for the H-infinity filter)."""
    @property
    def range_sigma(self) -> float:
        """1-sigma of the estimated range [m] (NaN for the H-infinity filter)."""
    @property
    def step_nis(self) -> _FloatArray:
        """NIS of the last step's radio, camera, GNSS position and GNSS velocity updates
        (NaN for a sensor that gave no reading then, for the particle and H-infinity
        filters, and after a restore)."""
    @property
    def ess(self) -> float:
        """Effective sample size of a particle filter (NaN for the others)."""
    @property
    def pf_acceptance(self) -> float:
        """Fraction of a particle filter's moves accepted in the last step (NaN when it made none, and for the other filters)."""
    @property
    def q_vv(self) -> _FloatArray:
        """The AQUKF's adaptive velocity process-noise density per axis [m^2/s^3] (NaN
        for the other filters)."""
    @property
    def hinf_gamma(self) -> float:
        """The H-infinity design's certified gamma (NaN for the other filters)."""
    @property
    def hinf_certified(self) -> Optional[bool]:
        """Whether the H-infinity filter runs its certified gain (False during its track
        initiation; None for the other filters)."""
    @property
    def hinf_matrices(self) -> Optional[Dict[str, Union[_FloatArray, float]]]:
        """The H-infinity filter's designed matrices, canonical frame: ``a_f`` (6x6),
        ``b_f`` (6x3), ``c_f`` (6x6), ``e_f`` (6x3), ``b_v`` (6x3) and ``period`` [s]; the
        data the C ABI's runtime filter loads (``relnav_hinf_filter_init``, also in the
        flight library). None for the other filters; ValueError for an eccentric orbit's
        scheduled design."""
    @property
    def params(self) -> Dict[str, Union[float, int, bool, str]]:
        """Every parameter's value (enumerations by name)."""

class CampaignResult:
    """The result of :func:`relnav.campaign`."""

    @property
    def scenario(self) -> str: ...
    @property
    def title(self) -> str: ...
    @property
    def runs(self) -> int:
        """Completed runs."""
    @property
    def interrupted(self) -> bool: ...
    @property
    def t(self) -> _FloatArray:
        """Times [s]."""
    @property
    def filters(self) -> List[str]:
        """Filter labels in scenario order."""
    @property
    def summary(self) -> List[Dict[str, Union[str, int, float]]]:
        """One dict per filter with the columns and numbers of ``summary.csv``."""
    @property
    def timeseries(self) -> Dict[str, _FloatArray]:
        """The columns of ``timeseries.csv``."""
    @property
    def pcrlb(self) -> Optional[_FloatArray]:
        """The PCRLB's diagonal (K x 6 variances) or None where undefined."""
    @property
    def pcrlb_runs(self) -> Optional[_FloatArray]:
        """The bound along each run's own truth (the same recursion, each run's own
        information; its inverse's diagonal averaged over the runs, K x 6 variances) or None
        where the PCRLB is undefined."""
    @property
    def pcrlb_reason(self) -> Optional[str]: ...
    def markdown(self) -> str:
        """The CLI's Markdown table."""
    def write_csv(self, dir: Union[str, PathLike[str]]) -> List[str]:
        """Write ``timeseries.csv`` and ``summary.csv`` into ``dir``."""
    def write_plots(self, dir: Union[str, PathLike[str]]) -> List[str]:
        """Write the CLI's PNG plots into ``dir``."""

class _Campaign:
    def __init__(self, scenario: Union[str, Mapping[str, Any]], runs: Optional[int] = None) -> None: ...
    @property
    def name(self) -> str: ...
    @property
    def runs(self) -> int: ...
    @property
    def chunks(self) -> List[Tuple[int, int]]: ...
    def run_chunk(self, index: int) -> bytes: ...
    def reducer(self) -> _Reducer: ...

class _Reducer:
    def add(self, partial: bytes) -> None: ...
    @property
    def next_index(self) -> int: ...
    @property
    def runs(self) -> int: ...
    def finish(self) -> CampaignResult: ...

def parameters_table() -> List[Dict[str, Any]]: ...
def scenario_toml(source: Union[str, Mapping[str, Any]]) -> str: ...
def builtin_scenario(name: str) -> Optional[str]: ...
def builtin_scenarios() -> List[str]: ...
