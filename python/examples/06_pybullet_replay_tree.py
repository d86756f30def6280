"""The whole optimum of a cat beyond two motors replayed in pyBullet from its exported
``model.urdf`` and ``whole-optimum.csv`` alone (``pip install pybullet numpy``; without pyBullet the
script says so and exits 0): the URDF twin of ``05_mujoco_replay_tree.py``.

    cargo run --release -- compare-models problems/tail.toml --out results-scratch
    python python/examples/06_pybullet_replay_tree.py results-scratch/tail-models/no-twist-tail

Without a folder (from the repository root) it replays the committed
``results/tail-models/no-twist-tail`` (a ball for the halves, two hinges for the tail).

Each joint as the URDF builds it: a universal joint's two ``continuous`` joints get ``tau<k>_nm``
plus a stiff PD on ``q<k>_rad``; a ball (pyBullet's non-standard ``spherical`` joint, whose
``TORQUE_CONTROL`` couple acts about the child's axes and whose velocity is the child's relative
rate in its own frame: ``04_pybullet_replay_files.py`` checks both) gets the couple
``<child>_couple_x_nm …`` plus a PD on the relative rotation. pyBullet's integrator is first order:
the flip's error falls in proportion to the step (1e-5 s here).
"""

import json
import sys
from pathlib import Path

import numpy as np

from exported_folder import interpolator, read_rows, report, rotation_vector, twist_swing

try:
    import pybullet as p
except ImportError:
    print("pyBullet is not installed (pip install pybullet): nothing to replay")
    sys.exit(0)

KP, KD = 200.0, 20.0  # the PD's stiffness (N·m/rad) and damping (N·m·s/rad), as in the README
DT = 1e-5  # s; first order, so the twist's error is proportional to it
FORMAT = "catflip-tree-schedule/1"


def replay(folder):
    sidecar = json.loads((folder / "whole-optimum.json").read_text())
    assert sidecar["format"] == FORMAT, f"{folder}: not a tree's schedule file ({sidecar['format']})"
    rows = read_rows(folder)
    p.connect(p.DIRECT)
    p.setGravity(0, 0, 0)  # the falling frame
    p.setTimeStep(DT)
    cat = p.loadURDF(str(folder / sidecar["model"]["urdf"]), useFixedBase=False, flags=p.URDF_USE_INERTIA_FROM_FILE)
    index = {p.getJointInfo(cat, j)[1].decode(): j for j in range(p.getNumJoints(cat))}
    for link in range(-1, p.getNumJoints(cat)):
        p.changeDynamics(cat, link, linearDamping=0, angularDamping=0)
    drives = []
    for link in sidecar["model"]["links"]:
        # The URDF names its joints as the MJCF does (the sidecar's mjcf_joints): one ball, or two hinges.
        names = link["mjcf_joints"]
        if p.getJointInfo(cat, index[names[0]])[2] == p.JOINT_SPHERICAL:
            j = index[names[0]]
            # Free the joint: pyBullet's default motor would hold it.
            p.setJointMotorControlMultiDof(cat, j, p.POSITION_CONTROL, targetPosition=[0, 0, 0, 1],
                                           targetVelocity=[0, 0, 0], force=[0, 0, 0])
            drives.append(("ball", link["child"], j))
        else:
            hinges = [(k, index[name]) for k, name in zip(link["coordinates"], names)]
            p.setJointMotorControlArray(cat, [j for _, j in hinges], p.VELOCITY_CONTROL, forces=[0] * len(hinges))
            drives.append(("hinges", hinges, None))
    steps = round(rows["t_s"][-1] / DT)
    for step in range(steps):
        at = interpolator(rows, step * DT)
        for kind, what, j in drives:
            if kind == "ball":
                c = what
                now, rate_now = p.getJointStateMultiDof(cat, j)[:2]  # (x, y, z, w); the child's frame
                goal = np.array([at(f"{c}_rel_q{q}") for q in "xyzw"])
                goal /= np.linalg.norm(goal)
                _, inverse = p.invertTransform([0, 0, 0], now)
                error = rotation_vector(p.multiplyTransforms([0, 0, 0], inverse, [0, 0, 0], goal.tolist())[1])
                couple = np.array([at(f"{c}_couple_{q}_nm") for q in "xyz"])
                rate = np.array([at(f"{c}_rel_w{q}_rad_s") for q in "xyz"])
                force = couple + KP * error + KD * (rate - np.array(rate_now))
                p.setJointMotorControlMultiDof(cat, j, p.TORQUE_CONTROL, force=force.tolist())
            else:
                ids = [i for _, i in what]
                states = p.getJointStates(cat, ids)
                tau = [at(f"tau{k}_nm") + KP * (at(f"q{k}_rad") - s[0]) + KD * (at(f"qd{k}_rad_s") - s[1])
                       for (k, _), s in zip(what, states)]
                p.setJointMotorControlArray(cat, ids, p.TORQUE_CONTROL, forces=tau)
        p.stepSimulation()
    x, y, z, w = p.getBasePositionAndOrientation(cat)[1]  # A's orientation; pyBullet: (x, y, z, w)
    p.disconnect()
    twist, swing = twist_swing(w, x, y, z)
    joints = ", ".join(f"{link['child']} on {link['parent']}: {link['joint']}" for link in sidecar["model"]["links"])
    report(folder, joints, f"pyBullet {p.getAPIVersion()}", twist, swing, rows, steps, DT, 0.2)


folders = [Path(a) for a in sys.argv[1:]] or [Path("results/tail-models/no-twist-tail")]
for folder in folders:
    replay(folder)
