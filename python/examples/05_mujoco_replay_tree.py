"""The whole optimum of a cat beyond two motors (the spherical joint's three motors, a tail)
replayed in MuJoCo from its exported files alone: no catflip package, only ``mujoco`` and
``numpy`` (without MuJoCo the script says so and exits 0).

    cargo run --release -- compare-models problems/tail.toml --out results-scratch
    python python/examples/05_mujoco_replay_tree.py results-scratch/tail-models/no-twist-tail

Without a folder (from the repository root) it replays every such folder of the committed
results (``results/*-models/*/``, the ``compare-models`` rows beyond two motors).

A folder holds ``model.xml`` (MJCF) and ``whole-optimum.csv`` with its sidecar
``whole-optimum.json`` (format ``catflip-tree-schedule/1``: every column, body and joint
described). Each joint is replayed as the model file builds it (README, "Replay elsewhere"):

- a universal joint (two hinges through a tiny cross): the CSV's motor torques ``tau<k>_nm`` plus
  a stiff PD on ``q<k>_rad``;
- a ball (the spherical joint, or the no-twist joint, which MuJoCo lacks): the joint's whole couple
  on the child in the child's frame, ``<child>_couple_x_nm …`` (on the no-twist joint its third
  part holds the relative twist at zero), plus a stiff PD on the relative rotation towards
  ``<child>_rel_qw …`` at the rate ``<child>_rel_wx_rad_s …``.

The cat's final orientation in MuJoCo is compared with the CSV's last row (catflip's exact
engine on the tree of bodies). The PD's correction is printed too: what the feedback adds to the
torques catflip computed (the file's rows are four to a span of the optimum's spline, and the
interpolation stays inside a span, where every column is smooth).
"""

import json
import sys
from pathlib import Path

import numpy as np

from exported_folder import interpolator, read_rows, report, twist_swing

try:
    import mujoco
except ImportError:
    print("MuJoCo is not installed (pip install mujoco): nothing to replay")
    sys.exit(0)

KP, KD = 200.0, 20.0  # the PD's stiffness (N·m/rad) and damping (N·m·s/rad), as in the README
# A ball's PD acts between its two bodies, and the command is held over each step: the damping
# alone multiplies their relative rate by 1 − KD·dt·(1/I_parent + 1/I_child) per step (the joint
# can only lower that mobility), which overshoots beyond 1 and blows up beyond 2. On a small
# cat's halves (a real cat's: 9e-4 and 1.3e-3 kg·m² about the spine) the gains above would
# make it 3.8, so a ball's gains are scaled down until the product is at most 1, with each body's
# least principal moment (the paper's halves, 5e-3 kg·m², and every committed folder but the
# real cat's stay at 0.83 or below, their gains unscaled).
FORMAT = "catflip-tree-schedule/1"


def folders(argv):
    """The folders named, or every exported tree of the committed results."""
    if len(argv) > 1:
        return [Path(a) for a in argv[1:]]
    found = sorted(p.parent for p in Path("results").glob("*-models/*/whole-optimum.json"))
    assert found, "no folder results/*-models/*/ with a whole-optimum.json: run from the repository root"
    return found


def rotation(quat):
    """The rotation matrix of a unit quaternion (w, x, y, z)."""
    out = np.zeros(9)
    mujoco.mju_quat2Mat(out, quat)
    return out.reshape(3, 3)


def replay(folder):
    """Replays one folder; fails when MuJoCo does not land where catflip says."""
    sidecar = json.loads((folder / "whole-optimum.json").read_text())
    assert sidecar["format"] == FORMAT, f"{folder}: not a tree's schedule file ({sidecar['format']})"
    rows = read_rows(folder)
    m = mujoco.MjModel.from_xml_path(str(folder / sidecar["model"]["mjcf"]))  # g = 0, RK4
    d = mujoco.MjData(m)
    dt = m.opt.timestep
    # Per joint of the sidecar: how its motors are driven.
    drives = []
    for link in sidecar["model"]["links"]:
        motors = [m.actuator(name).id for name in link["mjcf_motors"]]
        joints = [m.joint(name) for name in link["mjcf_joints"]]
        if len(joints) == 1 and m.jnt_type[joints[0].id] == mujoco.mjtJoint.mjJNT_BALL:
            mobility = sum(1.0 / float(np.min(m.body_inertia[m.body(link[b]).id])) for b in ("parent", "child"))
            gain = min(1.0, 1.0 / (KD * dt * mobility))
            drives.append(("ball", (link["child"], gain), motors, joints[0].qposadr[0], joints[0].dofadr[0]))
        else:
            hinges = [(k, j.qposadr[0], j.dofadr[0]) for k, j in zip(link["coordinates"], joints)]
            drives.append(("hinges", hinges, motors, None, None))
    worst_pd, square_sum = 0.0, 0.0
    steps = round(rows["t_s"][-1] / dt)
    for step in range(steps):
        at = interpolator(rows, step * dt)
        # The torques are held over the step: those of its midpoint (second order in dt).
        mid = interpolator(rows, (step + 0.5) * dt)
        for kind, what, motors, qadr, vadr in drives:
            if kind == "ball":
                c, gain = what
                now = d.qpos[qadr:qadr + 4].copy()
                goal = np.array([at(f"{c}_rel_q{p}") for p in "wxyz"])
                goal /= np.linalg.norm(goal)
                error = np.zeros(3)
                mujoco.mju_subQuat(error, goal, now)  # now · exp(error) = goal, in the child's frame
                rate = np.array([at(f"{c}_rel_w{p}_rad_s") for p in "xyz"])
                feedback = gain * (KP * error + KD * (rate - d.qvel[vadr:vadr + 3]))
                d.ctrl[motors] = np.array([mid(f"{c}_couple_{p}_nm") for p in "xyz"]) + feedback
            else:
                feedback = np.array([KP * (at(f"q{k}_rad") - d.qpos[qa]) + KD * (at(f"qd{k}_rad_s") - d.qvel[va])
                                     for k, qa, va in what])
                d.ctrl[motors] = np.array([mid(f"tau{k}_nm") for k, _, _ in what]) + feedback
            worst_pd = max(worst_pd, float(np.max(np.abs(feedback))))
            square_sum += float(np.sum(feedback ** 2))
        mujoco.mj_step(m, d)
    twist, swing = twist_swing(*d.qpos[3:7])  # A's orientation, (w, x, y, z)
    peak = max(p["value"] for p in sidecar["peak_torque_nm"])
    rms = np.sqrt(square_sum / (steps * sum(len(drive[2]) for drive in drives)))
    print(f"the PD's correction to catflip's torques: largest {worst_pd:.2e} N·m, rms {rms:.2e} N·m "
          f"(the peak motor torque is {peak:.6f} N·m)")
    joints = ", ".join(f"{link['child']} on {link['parent']}: {link['joint']}" for link in sidecar["model"]["links"])
    report(folder, joints, f"MuJoCo {mujoco.__version__}", twist, swing, rows, steps, dt, 1e-3)


for folder in folders(sys.argv):
    replay(folder)
