"""The whole-manoeuvre optimum handed to MuJoCo and replayed (when MuJoCo is installed:
``pip install mujoco``; without it the script says so and exits 0).

    python python/examples/02_mujoco_replay.py [PROBLEM.toml]   # from the repository root

The problem defaults to ``problems/paper.toml``; any cat on the universal joint replays
(``problems/unequal-halves.toml``: each half its own link in the MJCF).

catflip gives the model (MJCF: true inertias, zero gravity, the falling frame) and the optimum's
time series as numpy arrays; MuJoCo drives its two joint motors with catflip's exact torques plus
a stiff PD on catflip's angles (the README's "Replay elsewhere" recipe) and integrates the free
fall. The cat's final orientation in MuJoCo is compared with the exact engine's.
"""

import sys
import warnings

import numpy as np

import catflip

try:
    import mujoco
except ImportError:
    print("MuJoCo is not installed (pip install mujoco): nothing to replay")
    sys.exit(0)

warnings.simplefilter("ignore", catflip.CatflipWarning)
problem = catflip.load(sys.argv[1] if len(sys.argv) > 1 else "problems/paper.toml")
whole = catflip.optimize_whole(problem, rate_hz=1000.0)
assert whole.solved, whole.report["status"]
s = whole.series
model = mujoco.MjModel.from_xml_string(catflip.model_files(problem)["model.xml"])
data = mujoco.MjData(model)
dt = model.opt.timestep
for k in range(round(s.t[-1] / dt)):
    t = k * dt
    i = min(np.searchsorted(s.t, t, side="right"), len(s.t) - 1) - 1  # boundary rows are one-sided
    w = (t - s.t[i]) / (s.t[i + 1] - s.t[i])
    tau = (1 - w) * s.tau[i] + w * s.tau[i + 1]
    q = (1 - w) * s.q[i] + w * s.q[i + 1]
    qd = (1 - w) * s.qd[i] + w * s.qd[i + 1]
    data.ctrl[:] = tau + 200.0 * (q - data.qpos[7:9]) + 20.0 * (qd - data.qvel[6:8])
    mujoco.mj_step(model, data)
qw, qx, qy, qz = data.qpos[3:7]  # A's orientation, (w, x, y, z)
twist = np.degrees(2 * np.arctan2(qz, qw))
swing = np.degrees(2 * np.arctan2(np.hypot(qx, qy), np.hypot(qw, qz)))
print(f"MuJoCo {mujoco.__version__}: twist {twist:+.6f}°, swing {swing:.6f}° after {k + 1} steps of {dt} s")
print(f"catflip (exact engine):  twist {s.twist_deg[-1]:+.6f}°, swing {s.swing_deg[-1]:.6f}°")
gap = abs((twist - s.twist_deg[-1] + 180.0) % 360.0 - 180.0)
print(f"twist gap {gap:.2e}°")
assert gap < 0.01 and abs(swing - s.swing_deg[-1]) < 0.01, "MuJoCo's replay does not land where catflip says"
