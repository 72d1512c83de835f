"""tools/phase_rmse.py: a phase's RMSE is the root of the time average of the per-time
squared RMSE, over `from <= t < to` alone (checked on a CSV written here by hand)."""

import math
import subprocess
import sys

from conftest import REPO_ROOT


def test_phase_rmse_averages_the_window_alone(tmp_path):
    cols = ["rmse_pos", "rmse_vel", "nees"]
    header = ["t"] + [f"{f}_{c}" for f in ("A", "B bank") for c in cols]
    rows = [
        (0.0, [100.0, 1.0, 50.0], [100.0, 1.0, 50.0]),  # before the window
        (1.0, [3.0, 0.1, 4.0], [1.0, 0.3, 8.0]),
        (2.0, [4.0, 0.2, 6.0], [1.0, 0.4, 10.0]),
        (3.0, [100.0, 1.0, 50.0], [100.0, 1.0, 50.0]),  # at the window's end: left out
    ]
    csv = tmp_path / "timeseries.csv"
    csv.write_text(",".join(header) + "\n" + "".join(
        ",".join(str(v) for v in [t, *a, *b]) + "\n" for t, a, b in rows))
    out = subprocess.run([sys.executable, str(REPO_ROOT / "tools" / "phase_rmse.py"), str(csv),
                          "--from", "1", "--to", "3"], capture_output=True, text=True, check=True).stdout
    lines = {line.split("|")[1].strip(): line.split("|")[2:5] for line in out.splitlines()[2:]}
    assert set(lines) == {"A", "B bank"}
    pos, vel, nees = (float(v) for v in lines["A"])
    assert math.isclose(pos, math.sqrt((9 + 16) / 2), abs_tol=0.05)
    assert math.isclose(vel, math.sqrt((0.01 + 0.04) / 2), abs_tol=5e-6)
    assert math.isclose(nees, 5.0, abs_tol=0.005)
    pos, vel, nees = (float(v) for v in lines["B bank"])
    assert math.isclose(pos, 1.0, abs_tol=0.05)
    assert math.isclose(nees, 9.0, abs_tol=0.005)
    assert "2 times in [1, 3)" in out
