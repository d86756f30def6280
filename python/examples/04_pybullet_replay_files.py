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

from exported_folder import folder_from, interpolator, read_rows, report, rotation_vector, twist_swing

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


def matrix(xyzw):
    """The rotation matrix of a unit quaternion (x, y, z, w)."""
    return np.array(p.getMatrixFromQuaternion(xyzw)).reshape(3, 3)


def check_spherical_readings():
    """The conventions the recipe relies on, checked on this model (a second copy of it, at a
    random state): the joint's position is B's rotation relative to A, its velocity B's angular
    velocity relative to A in B's frame, and a TORQUE_CONTROL couple acts about B's axes: over
    2000 steps from rest its work equals the change of kinetic energy to 1e-4 (the first-order
    step's error; about A's axes it would not)."""
    probe = p.loadURDF(str(folder / "model.urdf"), basePosition=[10, 0, 0], useFixedBase=False,
                       flags=p.URDF_USE_INERTIA_FROM_FILE)
    for link in (-1, 0):
        p.changeDynamics(probe, link, linearDamping=0, angularDamping=0)
    p.setJointMotorControlMultiDof(probe, 0, p.POSITION_CONTROL, targetPosition=[0, 0, 0, 1],
                                   targetVelocity=[0, 0, 0], force=[0, 0, 0])
    rng = np.random.default_rng(22)
    relative = rng.normal(size=4)
    relative /= np.linalg.norm(relative)
    p.resetJointStateMultiDof(probe, 0, targetValue=relative.tolist(), targetVelocity=rng.normal(size=3).tolist())
    inertia = [np.diag(p.getDynamicsInfo(probe, link)[2]) for link in (-1, 0)]

    def frames():
        base = p.getBasePositionAndOrientation(probe)[1]
        link = p.getLinkState(probe, 0, computeLinkVelocity=1, computeForwardKinematics=1)
        return matrix(base), matrix(link[1]), np.array(p.getBaseVelocity(probe)[1]), np.array(link[7])

    def energy():
        (v_a, w_a), link = p.getBaseVelocity(probe), p.getLinkState(probe, 0, computeLinkVelocity=1)
        r_a, r_b, _, w_b = frames()
        masses = [p.getDynamicsInfo(probe, link)[0] for link in (-1, 0)]
        return sum(0.5 * m * np.dot(v, v) + 0.5 * (r.T @ w) @ i @ (r.T @ w) for m, v, w, r, i in
                   zip(masses, (np.array(v_a), np.array(link[6])), (np.array(w_a), w_b), (r_a, r_b), inertia))

    position, velocity = p.getJointStateMultiDof(probe, 0)[:2]
    r_a, r_b, w_a, w_b = frames()
    assert np.allclose(r_a.T @ r_b, matrix(position), atol=1e-6)  # pyBullet hands link frames as floats
    assert np.allclose(r_b.T @ (w_b - w_a), velocity, atol=1e-6)
    # From rest, so that what moves the energy is the couple alone.
    p.resetJointStateMultiDof(probe, 0, targetValue=relative.tolist(), targetVelocity=[0, 0, 0])
    p.resetBaseVelocity(probe, [0, 0, 0], [0, 0, 0])
    couple, start = np.array([0.3, -0.2, 0.1]), energy()
    work_b = work_a = 0.0
    for _ in range(2000):
        position, before = p.getJointStateMultiDof(probe, 0)[:2]
        p.setJointMotorControlMultiDof(probe, 0, p.TORQUE_CONTROL, force=couple.tolist())
        p.stepSimulation()
        mean = (np.array(before) + np.array(p.getJointStateMultiDof(probe, 0)[1])) / 2
        work_b += couple @ mean * DT
        work_a += couple @ (matrix(position) @ mean) * DT
    change = energy() - start
    print(f"pyBullet's spherical joint: work about B's axes {work_b:.6e} J, about A's {work_a:.6e} J, "
          f"kinetic energy {change:+.6e} J")
    assert abs(work_b - change) <= 1e-4 * abs(change) < abs(work_a - change)
    p.removeBody(probe)


if ball:
    check_spherical_readings()
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
        force = matrix(now).T @ couple + KP * error + KD * (rate - np.array(rate_now))
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
