"""Paper 000's example with the relnav Python package: 100 s of UKF navigation, step by
step and in one batch call."""
import numpy as np

import relnav

n = 2 * np.pi / 7200  # mean motion of the target's orbit [rad/s]
t = np.arange(101.0)  # measurements at t = 0 .. 99 s, estimate at 100 s

# truth in paper 000's frame (x along-track, y radial, z minus normal), at rest at t = 0
x = 400 + 3000 * (np.sin(n * t) - n * t)
y = 500 * (4 - 3 * np.cos(n * t))
z = 200 * np.cos(n * t)

# radio measurements: range, azimuth atan2(y, x), elevation asin(z / range), with noise
rho = np.sqrt(x**2 + y**2 + z**2)
meas = np.column_stack([rho, np.arctan2(y, x) % (2 * np.pi), np.arcsin(z / rho)])[:-1]
meas += np.random.default_rng(0).normal(0.0, [0.5, np.radians(0.01), np.radians(0.01)], meas.shape)
thrust = np.zeros((100, 3))  # [N], held over each step

# keyword arguments are the FMU's parameters (defaults: paper 000's set-up)
est = relnav.Estimator(filter="ukf", mean_motion=n)
for k in range(100):  # measurement taken at t_k applied first, then predicted to t_k + 1
    est.step(thrust[k], meas[k], dt=1.0)

# the same 100 steps in one call (no Python loop, the GIL released): rows = t_1 .. t_100
batch = relnav.Estimator(filter="ukf", mean_motion=n)
estimates, sigmas = batch.run(thrust, meas, valid=np.ones(100, bool), dt=1.0)
assert np.array_equal(estimates[-1], est.state)  # bit for bit

error = np.linalg.norm(est.state[:3] - [x[-1], y[-1], z[-1]])
print(f"estimate at t = 100 s: {np.round(est.state, 3)}")
print(f"1-sigma:               {np.round(est.sigma, 3)}")
print(f"position error after 100 s: {error:.3f} m")
