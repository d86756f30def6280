"""An exported whole optimum replayed in pyBullet from its files alone: no catflip package, only
``pybullet`` and ``numpy`` (``pip install pybullet numpy``; without pyBullet the script says so and
exits 0).

    cargo run --release -- optimize problems/kane-scher.toml --whole --out results-scratch
    python python/examples/04_pybullet_replay_files.py results-scratch/kane-scher-whole

Without a folder (from the repository root) it runs that ``optimize`` command itself, into a
temporary folder, with ``cargo``.

The folder's ``model.urdf`` and ``whole-optimum.csv`` (the sidecar ``whole-optimum.json`` says what
every column means) drive either joint (README, "Replay elsewhere"):

- the universal joint (two continuous joints and a light cross): the CSV's torques ``tau1_nm,
  tau2_nm`` plus a stiff PD on ``q1_rad, q2_rad``;
- the no-twist joint (pyBullet's non-standard ``spherical`` joint; URDF has no ball joint): the
  joint's whole couple on B in A's frame, ``(tau1_nm, tau2_nm, tauz_nm)``, turned into B's frame
  (pyBullet applies a spherical joint's ``TORQUE_CONTROL`` couple about B's axes and reports its
  velocity in B's frame), plus a stiff PD on the relative rotation towards ``rel_qw … rel_qz``.

pyBullet's integrator is first order: the flip's error falls in proportion to the step (1e-5 s
here). The cat's final orientation is compared with the CSV's last row (catflip's exact engine).
"""

import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

try:
    import pybullet as p
except ImportError:
    print("pyBullet is not installed (pip install pybullet): nothing to replay")
    sys.exit(0)

KP, KD = 200.0, 20.0  # the PD's stiffness (N·m/rad) and damping (N·m·s/rad), as in the README
DT = 1e-5  # s; first order, so the twist's error is proportional to it

if len(sys.argv) > 1:
    folder = Path(sys.argv[1])
else:
    scratch = tempfile.mkdtemp()
    subprocess.run(["cargo", "run", "--release", "--quiet", "--", "optimize", "problems/kane-scher.toml",
                    "--whole", "--quiet", "--out", scratch], check=True, stdout=subprocess.DEVNULL)
    folder = Path(scratch) / "kane-scher-whole"
S = np.genfromtxt(folder / "whole-optimum.csv", delimiter=",", names=True, dtype=None, encoding=None)
sidecar = json.loads((folder / "whole-optimum.json").read_text())
assert not sidecar["jumps"], "this recipe replays a file whose rates do not jump"
S = S[S["boundary"] != "end"]  # a boundary time is written twice; keep one row per time
T = S["t_s"]

p.connect(p.DIRECT)
p.setGravity(0, 0, 0)  # the falling frame: gravity exerts no torque about the centre of mass
p.setTimeStep(DT)
cat = p.loadURDF(str(folder / "model.urdf"), useFixedBase=False, flags=p.URDF_USE_INERTIA_FROM_FILE)
ball = p.getJointInfo(cat, 0)[2] == p.JOINT_SPHERICAL
for link in range(-1, p.getNumJoints(cat)):
    p.changeDynamics(cat, link, linearDamping=0, angularDamping=0)
if ball:
    # Free the joint: pyBullet's default motor would hold it.
    p.setJointMotorControlMultiDof(cat, 0, p.POSITION_CONTROL, targetPosition=[0, 0, 0, 1],
                                   targetVelocity=[0, 0, 0], force=[0, 0, 0])
else:
    p.setJointMotorControlArray(cat, [0, 1], p.VELOCITY_CONTROL, forces=[0, 0])


def matrix(xyzw):
    return np.array(p.getMatrixFromQuaternion(xyzw)).reshape(3, 3)


def twist_swing(x, y, z, w):
    """Twist about +z and swing of the z axis, degrees."""
    return np.degrees(2 * np.arctan2(z, w)), np.degrees(2 * np.arctan2(np.hypot(x, y), np.hypot(w, z)))


def rotation_vector(xyzw):
    """The rotation vector of a unit quaternion (x, y, z, w), its shorter way round."""
    v, w = np.array(xyzw[:3]), xyzw[3]
    if w < 0:
        v, w = -v, -w
    s = np.linalg.norm(v)
    return v * (2 * np.arctan2(s, w) / s) if s > 1e-15 else 2 * v


worst_relative_twist = 0.0
for k in range(round(T[-1] / DT)):
    t = k * DT
    # Cubic (four-row Lagrange) interpolation between rows a few milliseconds apart.
    i = min(max(np.searchsorted(T, t, side="right") - 2, 0), len(T) - 4)
    x = T[i:i + 4]
    weights = [np.prod([(t - x[b]) / (x[a] - x[b]) for b in range(4) if b != a]) for a in range(4)]
    at = lambda c: np.dot(weights, S[c][i:i + 4])
    if ball:
        now, rate_now = p.getJointStateMultiDof(cat, 0)[:2]  # (x, y, z, w); B's frame
        goal = np.array([at(c) for c in ("rel_qx", "rel_qy", "rel_qz", "rel_qw")])
        goal /= np.linalg.norm(goal)
        # The error rotation in B's frame: now · exp(error) = goal.
        _, inverse = p.invertTransform([0, 0, 0], now)
        error = rotation_vector(p.multiplyTransforms([0, 0, 0], inverse, [0, 0, 0], goal.tolist())[1])
        couple = np.array([at(c) for c in ("tau1_nm", "tau2_nm", "tauz_nm")])
        rate = np.array([at(c) for c in ("rel_wx_rad_s", "rel_wy_rad_s", "rel_wz_rad_s")])
        force = matrix(now).T @ couple + KP * error + KD * (rate - np.array(rate_now))
        p.setJointMotorControlMultiDof(cat, 0, p.TORQUE_CONTROL, force=force.tolist())
        worst_relative_twist = max(worst_relative_twist, abs(twist_swing(*now)[0]))
    else:
        js = p.getJointStates(cat, [0, 1])
        tau = [at(f"tau{j}_nm") + KP * (at(f"q{j}_rad") - js[j - 1][0]) + KD * (at(f"qd{j}_rad_s") - js[j - 1][1])
               for j in (1, 2)]
        p.setJointMotorControlArray(cat, [0, 1], p.TORQUE_CONTROL, forces=tau)
    p.stepSimulation()

twist, swing = twist_swing(*p.getBasePositionAndOrientation(cat)[1])  # A's orientation, (x, y, z, w)
print(f"{folder}: {'spherical (no-twist)' if ball else 'universal'} joint")
print(f"pyBullet {p.getAPIVersion()}: twist {twist:+.6f}°, swing {swing:.6f}° after {k + 1} steps of {DT} s")
print(f"catflip (exact engine):  twist {S['twist_deg'][-1]:+.6f}°, swing {S['swing_deg'][-1]:.6f}°")
gap = abs((twist - S["twist_deg"][-1] + 180.0) % 360.0 - 180.0)
print(f"twist gap {gap:.2e}°, swing gap {abs(swing - S['swing_deg'][-1]):.2e}°")
if ball:
    print(f"largest relative twist of the halves during the replay: {worst_relative_twist:.2e}°")
assert gap < 0.2 and abs(swing - S["swing_deg"][-1]) < 0.2, "pyBullet's replay does not land where catflip says"
