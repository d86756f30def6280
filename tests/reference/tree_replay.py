#!/usr/bin/env python3
"""Independent replay of catflip's exported whole optimum on a cat of several rigid bodies.

Reads FOLDER/whole-optimum.json (sidecar "catflip-tree-schedule/1") and FOLDER/whole-optimum.csv
and checks them from the physics contract alone (written without catflip's dynamics source,
2026-12-05; numpy + scipy, no catflip imports):
 1. torques: at every row, from (q, q', q'') by Newton-Euler on each joint's subtree, with A's
    rate Omega from zero momentum and Omega' from its time derivative (checked against central
    differences of Omega), against the CSV's tau<k>; action = reaction from the rest of the tree;
 2. the flip: A's quaternion by DOP853 (rtol = atol = 1e-12) piece by piece, q(t) by quintic
    Hermite between consecutive rows of a piece (exact on its cubic), against the sidecar's final
    twist and swing and the CSV's qw..qz, twist_deg, swing_deg at every row;
 3. the peak |tau| per motor over the rows.

Conventions: every body frame at its centre of mass; a link hangs child c from parent p at the
joint point a (in p) = b (in c): x_c = x_p + R_p a - R_c b, R_c = R_p J(q); universal
J = Rx(q1) Ry(q2), no-twist J = exp([q1, q2, 0]x), spherical J = exp([q1, q2, 0]x) Rz(q3), hinge
(an appendage's, e.g. legs) J = Rx(q1). A torque is the joint's couple on the child's subtree
about the joint point, projected on the motor axes: universal p's x and Rx(q1) y; no-twist p's
x, y; spherical p's x, y and c's z; hinge p's x.
Kinematics are in A's frame; the dynamics use the inertial frame that coincides with A's frame
at the instant and falls with the centre of mass.

Run from the repository root: python3 tests/reference/tree_replay.py FOLDER [...] (numpy, scipy)
Exits 1 if a check fails.
"""
import csv
import json
import math
import os
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

TAU_REL_TOL = 1e-8      # torques, relative to the largest |tau|
ANGLE_TOL_DEG = 1e-8    # final twist and swing
ROW_TOL = 1e-8          # quaternion components, twist and swing (deg) at the rows
EX, EY, EZ = np.eye(3)


# ----------------------------------------------------------------------------- small algebra
def hat(v):
    z = np.zeros(v.shape[:-1])
    return np.stack([np.stack([z, -v[..., 2], v[..., 1]], -1),
                     np.stack([v[..., 2], z, -v[..., 0]], -1),
                     np.stack([-v[..., 1], v[..., 0], z], -1)], -2)


def vee_skew(M):
    return 0.5 * np.stack([M[..., 2, 1] - M[..., 1, 2], M[..., 0, 2] - M[..., 2, 0],
                           M[..., 1, 0] - M[..., 0, 1]], -1)


tr = lambda M: np.swapaxes(M, -1, -2)
MM = np.matmul
MV = lambda A, v: np.einsum("nij,nj->ni", A, v)


# A jet is (x, x', x'') in time, arrays with a leading row axis.
def jmul(A, B, f=MM):
    return (f(A[0], B[0]), f(A[1], B[0]) + f(A[0], B[1]),
            f(A[2], B[0]) + 2 * f(A[1], B[1]) + f(A[0], B[2]))


def chain(f0, f1, f2, x):
    """jet of f(x) from f, f', f'' at x (x a scalar jet); f's may be matrices per row."""
    e = lambda s: s.reshape(s.shape + (1,) * (f0.ndim - s.ndim))
    return f0, f1 * e(x[1]), f2 * e(x[1] ** 2) + f1 * e(x[2])


def axis_rotation(e, th):
    """jet of the rotation by the angle jet th about the fixed unit axis e."""
    K = hat(e)
    c, s = np.cos(th[0])[:, None, None], np.sin(th[0])[:, None, None]
    return chain(np.eye(3) + s * K + (1 - c) * K @ K, c * K + s * K @ K, -s * K + c * K @ K, th)


# sin(r)/r and (1 - cos r)/r^2 as power series in s = r^2 (no singularity at r = 0)
_SIN_C = np.array([(-1.0) ** k / math.factorial(2 * k + 1) for k in range(30)])
_COS_C = np.array([(-1.0) ** k / math.factorial(2 * k + 2) for k in range(30)])


def _series_jet(c, s):
    P = np.polynomial.polynomial
    return chain(P.polyval(s[0], c), P.polyval(s[0], P.polyder(c)), P.polyval(s[0], P.polyder(c, 2)), s)


def rotvec_exp(v):
    """jet of exp([v]x) by Rodrigues, v a jet of rotation vectors (N, 3)."""
    s = jmul(v, v, lambda a, b: np.sum(a * b, -1))
    K = tuple(hat(x) for x in v)
    a, b = (tuple(x[:, None, None] for x in _series_jet(c, s)) for c in (_SIN_C, _COS_C))
    aK, bKK = jmul(a, K, np.multiply), jmul(b, jmul(K, K), np.multiply)
    return (np.eye(3) + aK[0] + bKK[0], aK[1] + bKK[1], aK[2] + bKK[2])


def joint_rotation(joint, q):
    """J(q) as a jet; q a jet of the link's own coordinates (N, n)."""
    if joint == "universal":
        return jmul(axis_rotation(EX, [x[:, 0] for x in q]), axis_rotation(EY, [x[:, 1] for x in q]))
    if joint == "hinge":                            # an appendage's: Rx(q1)
        return axis_rotation(EX, [x[:, 0] for x in q])
    bend = rotvec_exp(tuple(np.stack([x[:, 0], x[:, 1], 0 * x[:, 0]], -1) for x in q))
    if joint == "no-twist":
        return bend
    if joint == "spherical":
        return jmul(bend, axis_rotation(EZ, [x[:, 2] for x in q]))
    raise ValueError(joint)


# ----------------------------------------------------------------------------- the tree
def load_model(side):
    bodies = side["model"]["bodies"]
    index = {b["name"]: k for k, b in enumerate(bodies)}
    assert index[bodies[0]["name"]] == 0
    links = [dict(p=index[l["parent"]], c=index[l["child"]], joint=l["joint"],
                  cols=[k - 1 for k in l["coordinates"]],
                  a=np.array(l["joint_point_in_parent_m"]), b=np.array(l["joint_point_in_child_m"]))
             for l in side["model"]["links"]]
    done, ordered = {0}, []
    while len(ordered) < len(links):               # parents before children
        for l in links:
            if l["c"] not in done and l["p"] in done:
                ordered.append(l)
                done.add(l["c"])
    for l in reversed(ordered):                     # each link's subtree
        l["sub"] = {l["c"]}.union(*[m["sub"] for m in ordered if m["p"] == l["c"]])
    return dict(m=np.array([b["mass_kg"] for b in bodies]),
                I=[np.diag(b["inertia_kg_m2"]) for b in bodies], links=ordered,
                n=sum(len(l["cols"]) for l in links))


def kinematics(model, q, qd, qdd):
    """every body's attitude Q and centre p relative to A (in A's frame), as jets."""
    N = len(q)
    Q = {0: (np.broadcast_to(np.eye(3), (N, 3, 3)), np.zeros((N, 3, 3)), np.zeros((N, 3, 3)))}
    p = {0: (np.zeros((N, 3)),) * 3}
    for l in model["links"]:
        J = joint_rotation(l["joint"], tuple(x[:, l["cols"]] for x in (q, qd, qdd)))
        Q[l["c"]] = jmul(Q[l["p"]], J)
        p[l["c"]] = tuple(pp + Qp @ l["a"] - Qc @ l["b"] for pp, Qp, Qc in zip(p[l["p"]], Q[l["p"]], Q[l["c"]]))
    return Q, p


def motion(model, Q, p, Om, Omd):
    """inertial rates of every body: (R, I_world, omega, alpha, r, v, a), r about the centre of mass."""
    W, m, out = hat(Om), model["m"], []
    for k in range(len(m)):
        (Q0, Q1, Q2), (p0, p1, p2) = Q[k], p[k]
        R1 = W @ Q0 + Q1                                        # world = A's frame at the instant
        R2 = (hat(Omd) + W @ W) @ Q0 + 2 * W @ Q1 + Q2
        v = np.cross(Om, p0) + p1
        a = np.cross(Omd, p0) + np.cross(Om, np.cross(Om, p0)) + 2 * np.cross(Om, p1) + p2
        out.append([Q0, Q0 @ model["I"][k] @ tr(Q0), vee_skew(R1 @ tr(Q0)), vee_skew(R2 @ tr(Q0)), p0, v, a])
    for j in (4, 5, 6):                                         # about the centre of mass
        c = sum(m[k] * out[k][j] for k in range(len(m))) / m.sum()
        for o in out:
            o[j] = o[j] - c
    return out


def rate_of_change(model, b):
    """each body's d/dt of its angular momentum about the origin (inertial), per body."""
    return [MV(Iw, al) + np.cross(w, MV(Iw, w)) + model["m"][k] * np.cross(r, a)
            for k, (R, Iw, w, al, r, v, a) in enumerate(b)]


def base(model, q, qd, qdd, rate=True):
    """A's rate Omega from H = 0 and its rate Omega' from H' = 0 (both linear in the unknown)."""
    Q, p = kinematics(model, q, qd, qdd)
    Z = np.zeros((len(q), 3))
    b = motion(model, Q, p, Z, Z)
    Ilock = sum(Iw + m * (np.sum(r * r, -1)[:, None, None] * np.eye(3) - r[:, :, None] * r[:, None, :])
                for m, (R, Iw, w, al, r, v, a) in zip(model["m"], b))
    h = sum(MV(Iw, w) + m * np.cross(r, v) for m, (R, Iw, w, al, r, v, a) in zip(model["m"], b))
    Om = -np.linalg.solve(Ilock, h[..., None])[..., 0]
    if not rate:
        return Om, None, Q, p
    hd = sum(rate_of_change(model, motion(model, Q, p, Om, Z)))
    Omd = -np.linalg.solve(Ilock, hd[..., None])[..., 0]
    return Om, Omd, Q, p


def torques(model, q, qd, qdd):
    Om, Omd, Q, p = base(model, q, qd, qdd)
    b = motion(model, Q, p, Om, Omd)
    L = rate_of_change(model, b)
    tau, reaction = np.zeros((len(q), model["n"])), 0.0
    for l in model["links"]:
        Qp = Q[l["p"]][0]
        rP = b[l["p"]][4] + Qp @ l["a"]              # the joint point about the centre of mass
        moment = lambda k: L[k] - model["m"][k] * np.cross(rP, b[k][6])
        T = sum(moment(k) for k in l["sub"])
        rest = sum(moment(k) for k in range(len(L)) if k not in l["sub"])
        reaction = max(reaction, np.max(np.abs(T + rest)))
        qj = q[:, l["cols"]]
        axes = [Qp @ EX] if l["joint"] == "hinge" else [Qp @ EX, Qp @ EY]
        if l["joint"] == "universal":
            axes[1] = MV(Qp, np.stack([0 * qj[:, 0], np.cos(qj[:, 0]), np.sin(qj[:, 0])], -1))
        if l["joint"] == "spherical":
            axes.append(Q[l["c"]][0] @ EZ)
        for col, ax in zip(l["cols"], axes):
            tau[:, col] = np.sum(T * ax, -1)
    return tau, reaction, np.max(np.abs(sum(L)))


# ----------------------------------------------------------------------------- the flip
def quintic(t, X, Xd, Xdd):
    """coefficients (rows-1, 6, n) of the quintic Hermite pieces between consecutive rows."""
    h = np.diff(t)
    c0, c1, c2, H = X[:-1], Xd[:-1], Xdd[:-1] / 2, h[:, None]
    rhs = np.stack([X[1:] - c0 - c1 * H - c2 * H * H, Xd[1:] - c1 - 2 * c2 * H, Xdd[1:] - 2 * c2], 1)
    M = np.moveaxis(np.array([[h ** 3, h ** 4, h ** 5], [3 * h ** 2, 4 * h ** 3, 5 * h ** 4],
                              [6 * h, 12 * h ** 2, 20 * h ** 3]]), -1, 0)
    return np.concatenate([np.stack([c0, c1, c2], 1), np.linalg.solve(M, rhs)], 1)


def qmul(p, q):
    w1, x1, y1, z1 = p
    w2, x2, y2, z2 = q
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def flip(model, side, t, X, Xd, Xdd):
    """A's quaternion (world from A) at every row, piece by piece."""
    quat, y0, nfev = np.zeros((len(t), 4)), np.array([1.0, 0, 0, 0]), 0
    k = np.arange(6)
    for piece in side["pieces"]:
        i0, i1 = piece["first_row"], piece["last_row"]
        ts, C = t[i0:i1 + 1], quintic(t[i0:i1 + 1], X[i0:i1 + 1], Xd[i0:i1 + 1], Xdd[i0:i1 + 1])

        def rhs(tt, y):
            j = min(max(np.searchsorted(ts, tt) - 1, 0), len(C) - 1)
            s = tt - ts[j]
            q = (s ** k) @ C[j]
            qd = (k[1:] * s ** (k[1:] - 1)) @ C[j][1:]
            Om = base(model, q[None], qd[None], 0 * qd[None], rate=False)[0][0]
            return 0.5 * qmul(y, np.array([0.0, *Om]))
        sol = solve_ivp(rhs, (ts[0], ts[-1]), y0, method="DOP853", rtol=1e-12, atol=1e-12, t_eval=ts)
        nfev += sol.nfev
        quat[i0:i1 + 1] = sol.y.T
        y0 = sol.y[:, -1] / np.linalg.norm(sol.y[:, -1])
    twist = 2 * np.degrees(np.unwrap(np.arctan2(quat[:, 3], quat[:, 0])))
    swing = 2 * np.degrees(np.arctan2(np.hypot(quat[:, 1], quat[:, 2]), np.hypot(quat[:, 0], quat[:, 3])))
    return quat, twist, swing, nfev


# ----------------------------------------------------------------------------- the report
def check(folder):
    start = time.time()
    side = json.load(open(os.path.join(folder, "whole-optimum.json")))
    assert side["format"] == "catflip-tree-schedule/1", side["format"]
    model = load_model(side)
    rows = list(csv.DictReader(open(os.path.join(folder, side["csv"]))))
    col = lambda name: np.array([float(r[name]) for r in rows])
    assert all(r["phase"] == pc["name"] for pc in side["pieces"] for r in rows[pc["first_row"]:pc["last_row"] + 1])
    n = model["n"]
    t = col("t_s")
    X, Xd, Xdd, tau_csv = (np.stack([col(f"{p}{k}_{u}") for k in range(1, n + 1)], -1)
                           for p, u in (("q", "rad"), ("qd", "rad_s"), ("qdd", "rad_s2"), ("tau", "nm")))
    names = "+".join(l["joint"] for l in model["links"])
    print(f"== {folder}: {len(model['m'])} bodies ({names}), {n} motors, {len(rows)} rows, {len(side['pieces'])} pieces")

    tau, reaction, hdot = torques(model, X, Xd, Xdd)
    scale = np.max(np.abs(tau_csv))
    diff = np.abs(tau - tau_csv)
    rel = np.max(diff) / scale
    i, j = np.unravel_index(np.argmax(diff), diff.shape)
    print(f"1. torques: max |tau - tau_csv| = {np.max(diff):.3e} N·m = {rel:.3e} of max |tau| {scale:.6f} "
          f"(row {i}, motor {j + 1}); per motor " + ", ".join(f"{x:.1e}" for x in diff.max(0) / scale))
    Omd = base(model, X, Xd, Xdd)[1]                         # Omega' against central differences
    step = lambda s: base(model, X + s * Xd + s * s / 2 * Xdd, Xd + s * Xdd, Xdd, rate=False)[0]
    fd = (step(1e-6) - step(-1e-6)) / 2e-6
    print(f"   action = reaction {reaction:.1e} N·m; momentum rate residual {hdot:.1e}; "
          f"Omega' vs central differences {np.max(np.abs(fd - Omd)) / np.max(np.abs(Omd)):.1e} relative")
    ok = rel <= TAU_REL_TOL

    quat, twist, swing, nfev = flip(model, side, t, X, Xd, Xdd)
    ori = side["orientation"]
    dtw, dsw = twist[-1] - ori["final_twist_deg"], swing[-1] - ori["final_swing_deg"]
    print(f"2. flip: twist {twist[-1]:.13f} deg (sidecar {ori['final_twist_deg']:.13f}, diff {dtw:.1e}), "
          f"swing {swing[-1]:.2e} deg (sidecar {ori['final_swing_deg']:.2e}, diff {dsw:.1e}); {nfev} evaluations")
    qcsv = np.stack([col(c) for c in ("qw", "qx", "qy", "qz")], -1)
    sign = np.sign(np.sum(quat * qcsv, -1))[:, None]
    dq = np.max(np.abs(quat - sign * qcsv))
    dtr, dsr = np.max(np.abs(twist - col("twist_deg"))), np.max(np.abs(swing - col("swing_deg")))
    print(f"   at all rows: quaternion {dq:.1e}, twist {dtr:.1e} deg, swing {dsr:.1e} deg")
    ok &= max(abs(dtw), abs(dsw)) <= ANGLE_TOL_DEG and max(dq, dtr, dsr) <= ROW_TOL

    peak = np.max(np.abs(tau), 0)
    listed = [p["value"] for p in side.get("peak_torque_nm", [])]
    print("3. peak |tau| per motor over the rows: " + ", ".join(f"{x:.10f}" for x in peak)
          + (f"  (sidecar's peaks {', '.join(f'{x:.10f}' for x in listed)})" if listed else ""))
    print(f"   {'ok' if ok else 'FAILED'} in {time.time() - start:.1f} s")
    return ok


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    results = [check(f) for f in sys.argv[1:]]
    sys.exit(0 if all(results) else 1)
