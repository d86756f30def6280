"""What the replays of an exported folder (``03_mujoco_replay_files.py``,
``04_pybullet_replay_files.py``, and for a cat beyond two motors ``05_mujoco_replay_tree.py``,
``06_pybullet_replay_tree.py``) share: finding the folder, reading its schedule file, the
interpolation between its rows, and twist and swing. Only ``numpy``; run on its own it does
nothing.
"""

import json
import subprocess
import tempfile
from pathlib import Path

import numpy as np


def folder_from(argv):
    """The folder named on the command line, or (from the repository root) Kane and Scher's
    optimum written into a temporary folder by ``catflip optimize … --whole --out``."""
    if len(argv) > 1:
        return Path(argv[1])
    scratch = tempfile.mkdtemp()
    subprocess.run(["cargo", "run", "--release", "--quiet", "--", "optimize", "problems/kane-scher.toml",
                    "--whole", "--quiet", "--out", scratch], check=True, stdout=subprocess.DEVNULL)
    return Path(scratch) / "kane-scher-whole"


def read_rows(folder):
    """The schedule file's rows, one per time (a boundary time is written twice, 'end' and
    'start'; where the rates are continuous the two agree to the jerk, so the 'start' rows alone
    make one grid)."""
    rows = np.genfromtxt(folder / "whole-optimum.csv", delimiter=",", names=True, dtype=None, encoding=None)
    sidecar = json.loads((folder / "whole-optimum.json").read_text())
    sampling = sidecar["sampling"]
    # A truncated or foreign CSV would replay to its own last row and seem to land: refuse it.
    assert rows.size == sampling["rows"], f"whole-optimum.csv holds {rows.size} rows, its sidecar {sampling['rows']}"
    assert abs(rows["t_s"][-1] - sampling["duration_s"]) <= 1e-9 * sampling["duration_s"], \
        f"whole-optimum.csv ends at {rows['t_s'][-1]} s, its sidecar's fall at {sampling['duration_s']} s"
    assert not sidecar["jumps"], "this recipe replays a file whose rates do not jump"
    return rows[rows["boundary"] != "end"]


def interpolator(rows, t):
    """Column name → its value at time ``t``: cubic (four-row Lagrange) interpolation, O(h⁴),
    where a straight line between rows a few milliseconds apart would cost the flip about 1e-2°.
    When the piece holding ``t`` (from its 'start' row to the next) has four rows or more, the
    four are taken inside it: across a piece boundary the torques kink (a spline's knot, where
    the jerk jumps), and a cubic through rows on both sides would smear the kink."""
    times = rows["t_s"]
    i = min(max(np.searchsorted(times, t, side="right") - 2, 0), len(times) - 4)
    starts = np.flatnonzero(rows["boundary"] == "start")  # the 'end' rows are gone (read_rows)
    k = np.searchsorted(times[starts], t, side="right")
    lo = starts[k - 1] if k > 0 else 0
    hi = starts[k] if k < len(starts) else len(times) - 1
    if hi - lo >= 3:
        i = min(max(i, lo), hi - 3)
    x = times[i:i + 4]
    weights = [np.prod([(t - x[b]) / (x[a] - x[b]) for b in range(4) if b != a]) for a in range(4)]
    return lambda column: np.dot(weights, rows[column][i:i + 4])


def rotation_vector(xyzw):
    """The rotation vector of a unit quaternion (x, y, z, w), its shorter way round."""
    v, w = np.array(xyzw[:3]), xyzw[3]
    if w < 0:
        v, w = -v, -w
    s = np.linalg.norm(v)
    return v * (2 * np.arctan2(s, w) / s) if s > 1e-15 else 2 * v


def twist_swing(w, x, y, z):
    """Twist about +z and swing of the z axis, degrees, of a unit quaternion."""
    return np.degrees(2 * np.arctan2(z, w)), np.degrees(2 * np.arctan2(np.hypot(x, y), np.hypot(w, z)))


def report(folder, joint, engine, twist, swing, rows, steps, dt, tolerance):
    """Prints the replay against catflip's last row and fails beyond ``tolerance`` degrees."""
    print(f"{folder}: {joint} joint")
    print(f"{engine}: twist {twist:+.9f}°, swing {swing:.9f}° after {steps} steps of {dt} s")
    print(f"catflip (exact engine):  twist {rows['twist_deg'][-1]:+.9f}°, swing {rows['swing_deg'][-1]:.9f}°")
    gap = abs((twist - rows["twist_deg"][-1] + 180.0) % 360.0 - 180.0)
    print(f"twist gap {gap:.2e}°, swing gap {abs(swing - rows['swing_deg'][-1]):.2e}°")
    assert gap < tolerance and abs(swing - rows["swing_deg"][-1]) < tolerance, \
        f"{engine}'s replay does not land where catflip says"
