"""An exported whole optimum replayed in MuJoCo from its files alone: no catflip package, only
``mujoco`` and ``numpy`` (``pip install mujoco numpy``; without MuJoCo the script says so and
exits 0).

    cargo run --release -- optimize problems/kane-scher.toml --whole --out results-scratch
    python python/examples/03_mujoco_replay_files.py results-scratch/kane-scher-whole

Without a folder (from the repository root) it runs that ``optimize`` command itself, into a
temporary folder, with ``cargo``.

The folder is what ``optimize --whole --out`` writes: ``model.xml`` (MJCF) and
``whole-optimum.csv`` (the sidecar ``whole-optimum.json`` says what every column means). Both
joints replay (the README's "Replay elsewhere"):

- the universal joint (two hinges): the CSV's torques ``tau1_nm, tau2_nm`` plus a stiff PD on
  ``q1_rad, q2_rad``;
- the no-twist joint (a ball joint; MuJoCo has no no-twist joint): the joint's whole couple on B
  in A's frame, ``(tau1_nm, tau2_nm, tauz_nm)`` (``tauz`` is the constraint's couple that holds the
  relative twist at zero), turned into B's frame by the ball's present rotation, plus a stiff PD
  on the relative rotation towards ``rel_qw … rel_qz`` at the rate ``rel_wx_rad_s …`` (B's frame).

The cat's final orientation in MuJoCo is compared with the CSV's last row (catflip's exact
engine); on the ball joint the largest relative twist met during the replay is printed too.
"""

import sys

import numpy as np

from exported_folder import folder_from, interpolator, read_rows, report, twist_swing

try:
    import mujoco
except ImportError:
    print("MuJoCo is not installed (pip install mujoco): nothing to replay")
    sys.exit(0)

KP, KD = 200.0, 20.0  # the PD's stiffness (N·m/rad) and damping (N·m·s/rad), as in the README

folder = folder_from(sys.argv)
S = read_rows(folder)
T = S["t_s"]
m = mujoco.MjModel.from_xml_path(str(folder / "model.xml"))  # g = 0 (falling frame), RK4
d = mujoco.MjData(m)
ball = m.jnt_type[1] == mujoco.mjtJoint.mjJNT_BALL
dt = m.opt.timestep


def rotation(quat):
    """The rotation matrix of a unit quaternion (w, x, y, z)."""
    out = np.zeros(9)
    mujoco.mju_quat2Mat(out, quat)
    return out.reshape(3, 3)


def check_ball_readings():
    """The readings the recipe relies on, checked on this model at a random state: the ball's
    qpos is B's rotation relative to A, its qvel B's angular velocity relative to A in B's frame."""
    probe = mujoco.MjData(m)
    rng = np.random.default_rng(22)
    probe.qpos[3:7], probe.qpos[7:11] = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 4)))
    probe.qvel[:] = rng.normal(size=m.nv)
    mujoco.mj_forward(m, probe)
    ra, rb = (probe.xmat[m.body(n).id].reshape(3, 3) for n in ("A", "B"))
    wa, wb = (probe.cvel[m.body(n).id][:3] for n in ("A", "B"))  # world frame
    assert np.allclose(ra.T @ rb, rotation(probe.qpos[7:11]), atol=1e-12)
    assert np.allclose(rb.T @ (wb - wa), probe.qvel[6:9], atol=1e-12)


if ball:
    check_ball_readings()
worst_relative_twist = 0.0
for k in range(round(T[-1] / dt)):
    at = interpolator(S, k * dt)
    mid = interpolator(S, (k + 0.5) * dt)  # the torques held over the step: its midpoint's
    if ball:
        # The joint's couple on B in A's frame (motors about x and y, the constraint about z),
        # turned into B's frame.
        couple = np.array([mid(c) for c in ("tau1_nm", "tau2_nm", "tauz_nm")])
        now = d.qpos[7:11].copy()
        goal = np.array([at(c) for c in ("rel_qw", "rel_qx", "rel_qy", "rel_qz")])
        goal /= np.linalg.norm(goal)
        error = np.zeros(3)
        mujoco.mju_subQuat(error, goal, now)  # now · exp(error) = goal, error in B's frame
        rate = np.array([at(c) for c in ("rel_wx_rad_s", "rel_wy_rad_s", "rel_wz_rad_s")])
        # Turned into B's frame by the relative rotation the step's midpoint should have.
        halfway = np.array([mid(c) for c in ("rel_qw", "rel_qx", "rel_qy", "rel_qz")])
        d.ctrl[:] = rotation(halfway / np.linalg.norm(halfway)).T @ couple + KP * error + KD * (rate - d.qvel[6:9])
        worst_relative_twist = max(worst_relative_twist, abs(twist_swing(*now)[0]))
    else:
        d.ctrl[:] = [mid(f"tau{j}_nm")
                     + KP * (at(f"q{j}_rad") - d.qpos[6 + j]) + KD * (at(f"qd{j}_rad_s") - d.qvel[5 + j]) for j in (1, 2)]
    mujoco.mj_step(m, d)

twist, swing = twist_swing(*d.qpos[3:7])  # A's orientation, (w, x, y, z)
if ball:
    print(f"largest relative twist of the halves during the replay: {worst_relative_twist:.2e}°")
report(folder, "ball (no-twist)" if ball else "universal", f"MuJoCo {mujoco.__version__}", twist, swing, S, k + 1, dt,
       1e-3)
