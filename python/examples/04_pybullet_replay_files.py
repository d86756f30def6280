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

import sys

import numpy as np

from exported_folder import folder_from, interpolator, read_rows, report, twist_swing

try:
    import pybullet as p
except ImportError:
    print("pyBullet is not installed (pip install pybullet): nothing to replay")
    sys.exit(0)

KP, KD = 200.0, 20.0  # the PD's stiffness (N·m/rad) and damping (N·m·s/rad), as in the README
DT = 1e-5  # s; first order, so the twist's error is proportional to it

folder = folder_from(sys.argv)
S = read_rows(folder)
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


def rotation_vector(xyzw):
    """The rotation vector of a unit quaternion (x, y, z, w), its shorter way round."""
    v, w = np.array(xyzw[:3]), xyzw[3]
    if w < 0:
        v, w = -v, -w
    s = np.linalg.norm(v)
    return v * (2 * np.arctan2(s, w) / s) if s > 1e-15 else 2 * v


worst_relative_twist = 0.0
for k in range(round(T[-1] / DT)):
    at = interpolator(S, k * DT)
    if ball:
        now, rate_now = p.getJointStateMultiDof(cat, 0)[:2]  # (x, y, z, w); B's frame
        goal = np.array([at(c) for c in ("rel_qx", "rel_qy", "rel_qz", "rel_qw")])
        goal /= np.linalg.norm(goal)
        # The error rotation in B's frame: now · exp(error) = goal.
        _, inverse = p.invertTransform([0, 0, 0], now)
        error = rotation_vector(p.multiplyTransforms([0, 0, 0], inverse, [0, 0, 0], goal.tolist())[1])
        couple = np.array([at(c) for c in ("tau1_nm", "tau2_nm", "tauz_nm")])
        rate = np.array([at(c) for c in ("rel_wx_rad_s", "rel_wy_rad_s", "rel_wz_rad_s")])
        turn = np.array(p.getMatrixFromQuaternion(now)).reshape(3, 3)  # B's axes in A's frame
        force = turn.T @ couple + KP * error + KD * (rate - np.array(rate_now))
        p.setJointMotorControlMultiDof(cat, 0, p.TORQUE_CONTROL, force=force.tolist())
        worst_relative_twist = max(worst_relative_twist, abs(twist_swing(now[3], *now[:3])[0]))
    else:
        js = p.getJointStates(cat, [0, 1])
        tau = [at(f"tau{j}_nm") + KP * (at(f"q{j}_rad") - js[j - 1][0]) + KD * (at(f"qd{j}_rad_s") - js[j - 1][1])
               for j in (1, 2)]
        p.setJointMotorControlArray(cat, [0, 1], p.TORQUE_CONTROL, forces=tau)
    p.stepSimulation()

x, y, z, w = p.getBasePositionAndOrientation(cat)[1]  # A's orientation; pyBullet: (x, y, z, w)
twist, swing = twist_swing(w, x, y, z)
if ball:
    print(f"largest relative twist of the halves during the replay: {worst_relative_twist:.2e}°")
report(folder, "spherical (no-twist)" if ball else "universal", f"pyBullet {p.getAPIVersion()}", twist, swing, S, k + 1,
       DT, 0.2)
