"""Paper 000's example through the relnav FMU with FMPy: 100 s of EKF navigation."""
from pathlib import Path

import numpy as np
from fmpy import simulate_fmu

fmu = Path(__file__).resolve().parents[1] / "target" / "fmu" / "relnav.fmu"
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

names = ["thrust_x", "thrust_y", "thrust_z", "range", "azimuth", "elevation"]
# the camera and relative-GNSS inputs stay zero and unflagged: the radio alone
others = ["camera_azimuth", "camera_elevation", "gnss_x", "gnss_y", "gnss_z", "gnss_vx", "gnss_vy", "gnss_vz"]
flags = ["measurement_valid", "camera_valid", "gnss_valid", "gnss_velocity_valid"]
columns = [("time", float)] + [(v, float) for v in names + others] + [(f, bool) for f in flags]
inputs = np.zeros(100, dtype=columns)
inputs["time"] = t[:-1]  # the row of time t holds the measurement taken at t
inputs["range"], inputs["azimuth"], inputs["elevation"] = meas.T
inputs["measurement_valid"] = True

# parameters default to paper 000's set-up; filter 1 = EKF, 2 = UKF
result = simulate_fmu(fmu, stop_time=100.0, output_interval=1.0, input=inputs,
                      start_values={"filter": 1})
final = result[-1]
state = ["x", "y", "z", "vx", "vy", "vz"]
print(f"t = {final['time']:.0f} s, truth (x, y, z) = ({x[-1]:.3f}, {y[-1]:.3f}, {z[-1]:.3f}) m")
print("estimate:", ", ".join(f"{v} = {final[v]:.3f}" for v in state))
print("1-sigma: ", ", ".join(f"{v} = {final[f'sigma_{v}']:.3f}" for v in state))
