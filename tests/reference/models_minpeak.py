#!/usr/bin/env python3
"""Independent cross-check: the minimum-peak-torque zero-momentum flip of four cat models.

Direct collocation + IPOPT (CasADi), written from DESIGN.md §1-3, §10 and the reference scripts
beside it (mintime.py's discretisation, models.py's formulas), without the Rust source.
Needs numpy, scipy, casadi; imports mintime.py (rotations, quaternion steps, the piecewise-cubic path) and,
for `check`, models.py from this directory.

Problem.  Two solid cylinders, front half A and rear half B (axial inertia m r^2/2, transverse
m(3r^2 + l^2)/12), on their axes joined at A's (0,0,-l_A/2) and B's (0,0,+l_B/2); body frames at
the centres, z along the spine towards the head.  Zero total angular momentum, fall time
T = sqrt(2*10/9.8) = 1.4285714 s (the r* cases: their own T, below).  Minimise over joint paths
q(t) the peak motor torque max_{t,j} |tau_j(t)| subject to q = qd = 0 at t = 0 and t = T, A's
attitude R_A(0) = I and R_A(T) = Rz(+pi) or Rz(-pi) (twist +-pi about A's initial spine, swing 0;
quaternion (0, 0, 0, +-1), both signs allowed by constraining w = x = y = 0).

Models (R_AB = B's attitude in A's frame):
  a  equal halves 1.0 kg, 0.9 m, r 0.1 m; universal joint  R_AB = Rx(q1) Ry(q2)
  b  the same halves; Kane and Scher's no-twist joint     R_AB = exp([q1, q2, 0]x)
  c  A 0.8 kg 0.8 m r 0.1, B 1.2 kg 1.0 m r 0.1; universal joint
  d  the halves of c; no-twist joint
  p  (validation only) mintime.py's paper cat: equal halves 1 kg, 1 m, r 0.1, universal
  pu the paper cat on the universal joint (= p; the yardstick of ps)
  ps the paper cat on a spherical joint, R_AB = exp([q1, q2, 0]x) Rz(q3) (the no-twist joint's
     swing, then a relative twist q3 about B's own spine), three motors
  The near-equal halves (a 1 m drop: T = sqrt(2*1.0/9.81) = 0.4515236 s, a case's own fall time):
  rm  the mean half of a real cat, equal halves 1.16385 kg, 0.1979 m, r 0.0432 m; no-twist joint
  r1  halves 1 % apart: A 1.169943 kg 0.198245 m r 0.043275, B 1.157757 kg 0.197555 m r 0.043125;
      no-twist joint (equal halves cannot swing on it by symmetry: is rm a singular case?)
  r1u the halves of r1 on the universal joint
  rmu the mean half of rm on the universal joint
  rn  the real cat's halves: A 1.2857 kg 0.2048 m r 0.0447, B 1.0420 kg 0.1910 m r 0.0417; no-twist
  rnu the halves of rn on the universal joint
Motor torques: the torque the joint transmits to B about the joint point, projected on the motor
axes (universal: A's x and the cross's y = Rx(q1) y; no-twist: A's x and y; spherical: A's x,
A's y and B's spine e = R z).  On the spherical joint w_rel = J_l(v) v' + q3' R z, checked against
vee(R' R^T) by the generic route, against models.py's spherical joint and the reduced Lagrangian.

Dynamics (everything in A's frame; ' = A-frame time derivative; M = mA + mB, mu = mA mB / M):
  d = jA - R jB (B's centre from A's), J = R I_B R^T, w_rel = vee(R' R^T),
  I_lock = I_A + J - mu [d]x^2,  h = J w_rel + mu d x d',  Omega = -I_lock^-1 h  (H = 0),
  Omega' and w_rel' by differentiating those expressions along (q, qd, qdd) (CasADi jacobians);
  Newton-Euler on B: r = (mA/M) d (B's centre from the system's), F = mB (r'' + 2 Om x r' +
  Om' x r + Om x (Om x r)), wB = Om + w_rel, wB_dot = Om' + w_rel' + Om x w_rel,
  tau_J = J wB_dot + wB x J wB - (R jB) x F, motor torques = axes . tau_J.
  The exp of the no-twist joint is I + a(s) K + b(s) K^2, a = sin(sqrt s)/sqrt s,
  b = (1 - cos sqrt s)/s as 16-term power series in s = q1^2 + q2^2 (smooth at q = 0; round-off
  accurate for |q| < 3.5 rad; the bends found stay below 2 rad).
  Checks (`check`): against models.py's Cat.state (Newton-Euler in numpy) at random states, and
  against the generalised forces of the reduced Lagrangian K = 1/2 w_rel.J w_rel + 1/2 mu |d'|^2
  - 1/2 h.I_lock^-1 h (Q = d/dt dK/dqd - dK/dq must equal tau_J . d w_rel/d qd_j; on the
  universal joint that is the motor torque itself).

Discretisation (mintime.py's): N intervals, h = T/N; qdd piecewise linear (node values), so q is
an exact piecewise cubic and the q, qd continuity conditions are exact; the torque bound
-P <= tau_j <= P at every node and every interval midpoint; the attitude by exponential-midpoint
quaternion steps u_{k+1} = u_k (x) exp(h Omega(t_{k+1/2})) (6th-order Taylor exp).  Every
solution is re-checked: the attitude re-integrated with SciPy DOP853 (rtol 1e-10, atol 1e-12,
interval by interval) along the exact piecewise-cubic q(t), the torques evaluated on 10 points
per interval (dense peak).

Starts (peak-torque problems have several local optima): the spine of B on a cone about A's with
bend beta(s) = beta0 sin^2(pi s) (s = t/T) whose direction phi = sign 2 pi turns (s -
sin(2 pi s)/(2 pi)) circulates `turns` times (B's spine (sin b cos phi, sin b sin phi, cos b)
mapped to the joint angles of each joint), beta0 in {30, 45, 60, 90} deg, sign +-, turns in
{0.75, 1, 1.25, 1.5}; phi starts at 0, except that on the universal joint a start bending >= 80 deg
is turned to put its largest bend at phi = pi/2 (mod pi), away from the joint's gimbal lock
(B's spine along joint 1's axis, A's x).  Every start is solved at the first N; each distinct local optimum (peak to
1e-5 N m, twist sign), then every other converged start, is refined on the finer grids from its
interpolated solution.  A case starts no new N0 solve after --budget seconds (default 900) and
refines only the distinct optima after 2 x budget.  IPOPT: tol 1e-9, at most 3000 iterations
and --max-wall seconds (default 300) per solve.

Starts of the spherical joint: the cone starts with q3 = twist sin^2(pi s) (a fifth field of
--starts, rad; 0 by default), and saved solutions (--map-from, refine --warm): a universal-joint
solution is mapped onto the spherical coordinates of the same motion R_AB(t) by its swing-twist
decomposition (e = R z, v = atan2(|z x e|, e_z) (z x e)/|z x e|, q3 = the angle of exp(-[v]x) R
about z, unwrapped), rates by central differences; its attitude is kept.  --mu-init m restarts
IPOPT from a (nearly) optimal point (mu_init m, warm_start_init_point): the min-peak problem at
N >= 400 often hits its wall time from an interpolated start and then converges in under 100
iterations from where it stopped.  --refine-best k refines only the k lowest distinct optima.

Run (outside the repo's build; about 15-30 min per case on one core):
  python3 -m venv /tmp/ipopt-venv && /tmp/ipopt-venv/bin/pip install numpy scipy casadi
  cd tests/reference
  /tmp/ipopt-venv/bin/python models_minpeak.py check
  /tmp/ipopt-venv/bin/python models_minpeak.py solve a b c d --N 100,200 --out /tmp/models_minpeak
  (validation against mintime.py: solve p --starts 45:0.75:1:circle,45:1:1:circle --N 100,200)
  /tmp/ipopt-venv/bin/python models_minpeak.py summary --out /tmp/models_minpeak
  (a finer grid from a saved optimum: refine a --warm OUT/sol_a_N200_0.npz --N 400 --out DIR)
  (the near-equal halves, about 2-8 min per case: solve r1 rm rn r1u --N 100,200 --budget 420
   --refine-best 2 --max-wall 150 --out OUT; a flip of one case as another's start, same joint and
   T: refine r1 --warm OUT/sol_rm_N200_0.npz --N 200 --out DIR)
  (the spherical joint: solve pu --starts 45:0.75:1:circle,60:1:-1 --N 100,200 --out OUT, then
   solve ps --starts 45:0.75:1:cone:0.3,... --map-from OUT/sol_pu_N100_0.npz --N 100,200
   --refine-best 3 --out OUT2, refine ps --warm OUT/sol_pu_N200_0.npz --N 200,400 --out OUT3,
   refine ps --warm OUT3/refined_ps_N400.npz --N 400 --mu-init 1e-4 --out OUT4)
Results: one JSON line per solve in OUT/results.jsonl, solutions as OUT/sol_<case>_N<N>_<k>.npz
(<k> = the k-th distinct optimum at the first N, by increasing peak).
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np
import casadi as ca
from scipy.integrate import solve_ivp

# The paper cat's collocation: its rotations, quaternion steps and exact piecewise-cubic path.
from mintime import Rx, Ry, skew, qmul, qexp, path_eval, interval_map, reintegrate, twist_swing

G = 9.8
T_FALL = math.sqrt(2 * 10 / G)          # 1.4285714 s
T_1M = math.sqrt(2 * 1.0 / 9.81)        # 0.4515236 s: the r* cases' 1 m drop at g = 9.81
MAX_WALL = 300.0                        # s per IPOPT solve (--max-wall)
MU_INIT = None                          # IPOPT's initial barrier parameter (--mu-init; None: 0.1)

CASES = {
    'a': dict(front=(1.0, 0.9, 0.1), rear=(1.0, 0.9, 0.1), joint='universal'),
    'b': dict(front=(1.0, 0.9, 0.1), rear=(1.0, 0.9, 0.1), joint='no-twist'),
    'c': dict(front=(0.8, 0.8, 0.1), rear=(1.2, 1.0, 0.1), joint='universal'),
    'd': dict(front=(0.8, 0.8, 0.1), rear=(1.2, 1.0, 0.1), joint='no-twist'),
    'p': dict(front=(1.0, 1.0, 0.1), rear=(1.0, 1.0, 0.1), joint='universal'),
    'pu': dict(front=(1.0, 1.0, 0.1), rear=(1.0, 1.0, 0.1), joint='universal'),
    'ps': dict(front=(1.0, 1.0, 0.1), rear=(1.0, 1.0, 0.1), joint='spherical'),
    # the near-equal halves of a real cat, a 1 m drop at g = 9.81 (each case's T overrides T_FALL)
    'rm': dict(front=(1.16385, 0.1979, 0.0432), rear=(1.16385, 0.1979, 0.0432), joint='no-twist', T=T_1M),
    'r1': dict(front=(1.169943, 0.198245, 0.043275), rear=(1.157757, 0.197555, 0.043125),
               joint='no-twist', T=T_1M),
    'r1u': dict(front=(1.169943, 0.198245, 0.043275), rear=(1.157757, 0.197555, 0.043125),
                joint='universal', T=T_1M),
    'rmu': dict(front=(1.16385, 0.1979, 0.0432), rear=(1.16385, 0.1979, 0.0432), joint='universal', T=T_1M),
    'rn': dict(front=(1.2857, 0.2048, 0.0447), rear=(1.0420, 0.1910, 0.0417), joint='no-twist', T=T_1M),
    'rnu': dict(front=(1.2857, 0.2048, 0.0447), rear=(1.0420, 0.1910, 0.0417), joint='universal', T=T_1M),
}


def case_T(c):
    """a case's fall time: its own T (the r* cases), else T_FALL."""
    return c.get('T', T_FALL)


def n_coords(joint):
    """joint coordinates (= motors): 3 on the spherical joint, 2 otherwise."""
    return 3 if joint == 'spherical' else 2


# ============================================================================ symbolic model
def cyl(m, l, r):
    ixx = m * (3 * r * r + l * l) / 12.0
    return ca.diag(ca.vertcat(ixx, ixx, m * r * r / 2.0))


def vee_skew(M):
    return 0.5 * ca.vertcat(M[2, 1] - M[1, 2], M[0, 2] - M[2, 0], M[1, 0] - M[0, 1])


def _horner(coef, s):
    out = 0
    for c in reversed(coef):
        out = out * s + c
    return out


_NSER = 16
_CA = [(-1.0) ** k / math.factorial(2 * k + 1) for k in range(_NSER)]   # sin(x)/x, s = x^2
_CB = [(-1.0) ** k / math.factorial(2 * k + 2) for k in range(_NSER)]   # (1-cos x)/x^2


def Rz(a):
    c, s = ca.cos(a), ca.sin(a)
    return ca.vertcat(ca.horzcat(c, -s, 0), ca.horzcat(s, c, 0), ca.horzcat(0, 0, 1))


def joint_rotation(joint, q):
    if joint == 'universal':
        return Rx(q[0]) @ Ry(q[1])
    if joint in ('no-twist', 'spherical'):
        v = ca.vertcat(q[0], q[1], 0)
        s = q[0] ** 2 + q[1] ** 2
        K = skew(v)
        S = ca.DM.eye(3) + _horner(_CA, s) * K + _horner(_CB, s) * (K @ K)
        # spherical: the no-twist joint's swing, then the relative twist q3 about B's own spine
        return S if joint == 'no-twist' else S @ Rz(q[2])
    raise ValueError(joint)


def motor_axes(joint, q):
    ax1 = ca.DM([1, 0, 0])
    ax2 = ca.vertcat(0, ca.cos(q[0]), ca.sin(q[0])) if joint == 'universal' else ca.DM([0, 1, 0])
    if joint == 'spherical':               # the third motor about B's spine e = R z (in A)
        return ca.horzcat(ax1, ax2, joint_rotation(joint, q) @ ca.DM([0, 0, 1])).T
    return ca.horzcat(ax1, ax2).T          # rows: the motor axes in A's frame


def inv3_sym(M):
    """inverse of a symmetric 3x3 SX matrix by its adjugate (much smaller than a symbolic QR)."""
    a, b, c, d, e, f = M[0, 0], M[0, 1], M[0, 2], M[1, 1], M[1, 2], M[2, 2]
    A11, A12, A13 = d * f - e * e, c * e - b * f, b * e - c * d
    A22, A23, A33 = a * f - c * c, b * c - a * e, a * d - b * b
    det = a * A11 + b * A12 + c * A13
    adj = ca.vertcat(ca.horzcat(A11, A12, A13), ca.horzcat(A12, A22, A23), ca.horzcat(A13, A23, A33))
    return adj / det


_CC = [(-1.0) ** k / math.factorial(2 * k + 3) for k in range(_NSER)]   # (x - sin x)/x^3


def model_exprs(front, rear, joint, q, qd, qdd, fast=True):
    """SX expressions of one cat at (q, qd, qdd).  fast=True: closed forms (w_rel = J_l(v) vd on
    the no-twist joint, d' = -w_rel x R jB, Omega' = -I_lock^-1 (I_lock' Omega + h'), adjugate
    inverse) for the NLP; fast=False: the generic route (R' by differentiating R, w_rel =
    vee(R' R^T), Omega' by differentiating Omega, symbolic solve), kept as a check."""
    mA, lA, rA = front
    mB, lB, rB = rear
    IA, IB = cyl(mA, lA, rA), cyl(mB, lB, rB)
    M = mA + mB
    mu = mA * mB / M
    jA, jB = ca.DM([0, 0, -lA / 2]), ca.DM([0, 0, lB / 2])

    def tdot(e):           # A-frame time derivative of an expression of (q, qd)
        return ca.jacobian(e, q) @ qd + ca.jacobian(e, qd) @ qdd

    R = joint_rotation(joint, q)
    J = R @ IB @ R.T
    rho = R @ jB                                           # joint point from B's centre
    d = jA - rho                                           # B's centre from A's
    if fast:
        if joint == 'universal':
            w_rel = qd[0] * ca.DM([1, 0, 0]) + qd[1] * ca.vertcat(0, ca.cos(q[0]), ca.sin(q[0]))
        else:
            v, vd = ca.vertcat(q[0], q[1], 0), ca.vertcat(qd[0], qd[1], 0)
            sv = q[0] ** 2 + q[1] ** 2
            K = skew(v)
            w_rel = vd + _horner(_CB, sv) * (K @ vd) + _horner(_CC, sv) * (K @ (K @ vd))
            if joint == 'spherical':       # + the twist rate about B's spine S z = R z
                w_rel = w_rel + qd[2] * (R @ ca.DM([0, 0, 1]))
        wd_rel = tdot(w_rel)
        dd = -ca.cross(w_rel, rho)
        ddd = -ca.cross(wd_rel, rho) - ca.cross(w_rel, ca.cross(w_rel, rho))
        W = skew(w_rel)
        Jd = W @ J - J @ W
        Ilock = IA + J - mu * skew(d) @ skew(d)
        Ilock_d = Jd - mu * (skew(dd) @ skew(d) + skew(d) @ skew(dd))
        hmom = J @ w_rel + mu * ca.cross(d, dd)
        hmom_d = Jd @ w_rel + J @ wd_rel + mu * ca.cross(d, ddd)
        Linv = inv3_sym(Ilock)
        Om = -Linv @ hmom
        Omd = -Linv @ (Ilock_d @ Om + hmom_d)
    else:
        Rdv = ca.jacobian(ca.vec(R), q) @ qd
        Rd = ca.reshape(Rdv, 3, 3)
        w_rel = vee_skew(Rd @ R.T)
        wd_rel = tdot(w_rel)
        dd = ca.jacobian(d, q) @ qd
        ddd = tdot(dd)
        Ilock = IA + J - mu * skew(d) @ skew(d)
        hmom = J @ w_rel + mu * ca.cross(d, dd)
        Om = -ca.solve(Ilock, hmom)
        Omd = tdot(Om)
    # Newton-Euler on B
    kB = mA / M
    r, rd, rdd = kB * d, kB * dd, kB * ddd                 # B's centre from the system's centre
    acc = rdd + 2 * ca.cross(Om, rd) + ca.cross(Omd, r) + ca.cross(Om, ca.cross(Om, r))
    F = mB * acc                                           # force of A on B at the joint
    wB = Om + w_rel
    wBd = Omd + wd_rel + ca.cross(Om, w_rel)
    tauJ = J @ wBd + ca.cross(wB, J @ wB) - ca.cross(rho, F)
    tau = motor_axes(joint, q) @ tauJ
    out = dict(tau=tau, tauJ=tauJ, Om=Om, Omd=Omd, spine=R @ ca.DM([0, 0, 1]))
    if not fast:
        # generalised forces two ways, and A's side (action = reaction)
        out['Qne'] = ca.jacobian(w_rel, qd).T @ tauJ
        Kin = 0.5 * ca.dot(w_rel, J @ w_rel) + 0.5 * mu * ca.dot(dd, dd) \
            - 0.5 * ca.dot(hmom, ca.solve(Ilock, hmom))
        dKdqd = ca.gradient(Kin, qd)
        out['Qlag'] = ca.jacobian(dKdqd, qd) @ qdd + ca.jacobian(dKdqd, q) @ qd - ca.gradient(Kin, q)
        out['react'] = IA @ Omd + ca.cross(Om, IA @ Om) - (-tauJ + ca.cross(jA, -F))
    return out


class Model:
    """CasADi functions of one cat: tau(q,qd,qdd) (motor torques), Om(q,qd) (A's rate in A),
    spine(q) (B's spine in A's frame), and the checks (the generic route beside the fast one)."""

    def __init__(self, front, rear, joint):
        self.front, self.rear, self.joint = front, rear, joint
        self.nq = nq = n_coords(joint)
        q, qd, qdd = ca.SX.sym('q', nq), ca.SX.sym('qd', nq), ca.SX.sym('qdd', nq)
        f = model_exprs(front, rear, joint, q, qd, qdd, fast=True)
        g = model_exprs(front, rear, joint, q, qd, qdd, fast=False)
        self.tau = ca.Function('tau', [q, qd, qdd], [ca.cse(f['tau'])])
        self.Om = ca.Function('Om', [q, qd], [ca.cse(f['Om'])])
        self.spine = ca.Function('spine', [q], [f['spine']])
        self.checks = ca.Function('checks', [q, qd, qdd],
                                  [g['tauJ'], g['Qne'], g['Qlag'], g['react'], g['tau'],
                                   f['tau'], f['tauJ'], f['Om'], f['Omd'], g['Om'], g['Omd']])
        self.step = interval_map(self.Om, self.tau, self.nq)
        self.solvers = {}


# ============================================================================ numerics
def analyse(model, T, Q, QD, A, U):
    N = Q.shape[1] - 1
    tk = np.linspace(0, T, N + 1)
    tt = np.linspace(0, T, 10 * N + 1)
    q, qd, qdd = path_eval(tt, tk, Q, QD, A)
    tau = np.array(model.tau.map(len(tt))(q, qd, qdd))
    if model.joint == 'universal':
        bend = np.degrees(np.arccos(np.clip(np.cos(q[0]) * np.cos(q[1]), -1, 1)))
    else:                  # no-twist and spherical: the swing angle |(q1, q2)| is the bend
        bend = np.degrees(np.hypot(q[0], q[1]))
    sp = np.array(model.spine.map(len(tt))(q))
    spine_angle = np.degrees(np.arccos(np.clip(sp[2], -1, 1)))
    sel = spine_angle > 0.1 * spine_angle.max()
    phi = np.unwrap(np.arctan2(sp[1][sel], sp[0][sel]))
    turns = float((phi[-1] - phi[0]) / (2 * np.pi))
    if np.all(np.isfinite(tau)) and np.abs(tau).max() < 1e3:
        uq = reintegrate(T, tk, Q, QD, A, model.Om)
    else:                  # a diverged solve: not worth (nor safe) re-integrating
        uq = np.full(4, np.nan)
    tw, sw = twist_swing(uq)
    twc, swc = twist_swing(U[:, -1])
    sign = 1 if tw > 0 else (-1 if tw < 0 else 0)
    out = dict(N=N, peak_dense=float(np.abs(tau).max()), peak_dense_j=np.abs(tau).max(1).tolist(),
               twist_deg=tw, swing_deg=sw, twist_err_deg=tw - sign * 180.0,
               twist_colloc_deg=twc, swing_colloc_deg=swc, twist_sign=sign,
               max_bend_deg=float(bend.max()), max_spine_angle_deg=float(spine_angle.max()),
               turns=turns, peak_qd=float(np.abs(qd).max()))
    if model.nq == 3:
        # the relative twist, and the motors' peaks at the collocation points (nodes, midpoints)
        out['max_q3_deg'] = float(np.degrees(np.abs(q[2]).max()))
        h = T / N
        tc = np.sort(np.concatenate([tk, tk[:-1] + h / 2]))
        qc, qdc, qddc = path_eval(tc, tk, Q, QD, A)
        tc_ = np.abs(np.array(model.tau.map(len(tc))(qc, qdc, qddc)))
        out['peak_colloc_j'] = tc_.max(1).tolist()
    return out


# ============================================================================ starts
def spine_to_q(joint, beta, phi):
    """joint angles putting B's spine at (sin b cos phi, sin b sin phi, cos b) in A's frame."""
    dx, dy, dz = np.sin(beta) * np.cos(phi), np.sin(beta) * np.sin(phi), np.cos(beta)
    if joint == 'universal':
        # Rx(q1) Ry(q2) z = (sin q2, -sin q1 cos q2, cos q1 cos q2)
        return np.stack([np.arctan2(-dy, dz), np.arcsin(np.clip(dx, -1, 1))])
    # exp([v]x) z with v = beta (-sin phi, cos phi, 0) (no-twist; the spherical joint's swing)
    return np.stack([-beta * np.sin(phi), beta * np.cos(phi)])


def guess(model, N, T, beta_deg, turns, sign, kind='cone', twist=0.0):
    """twist (spherical joint only): q3 = twist sin^2(pi s), rad."""
    s = np.linspace(0, 1, N + 1)
    b0 = math.radians(beta_deg)
    # the universal joint locks where B's spine meets joint 1's axis (A's x: bend 90 deg at
    # phi = 0 or pi): a start bending >= 80 deg puts its largest bend (s = 1/2) at phi = pi/2
    phi0 = 0.0
    if model.joint == 'universal' and beta_deg >= 80 and kind == 'cone':
        phi0 = math.pi / 2 - sign * math.pi * turns

    def qf(s):
        beta = b0 * np.sin(np.pi * s) ** 2
        phi = phi0 + sign * 2 * np.pi * turns * (s - np.sin(2 * np.pi * s) / (2 * np.pi))
        if kind == 'circle':               # mintime.py's start: q = beta (cos phi, sin phi)
            q = np.stack([beta * np.cos(phi), beta * np.sin(phi)])
        else:
            q = spine_to_q(model.joint, beta, phi)
        if model.nq == 3:
            q = np.vstack([q, twist * np.sin(np.pi * s) ** 2])
        return q
    e = 1e-5
    Q = qf(s)
    QD = (qf(s + e) - qf(s - e)) / (2 * e) / T
    A = (qf(s + e) - 2 * Q + qf(s - e)) / e ** 2 / T ** 2
    Q[:, [0, -1]] = 0; QD[:, [0, -1]] = 0
    U = np.zeros((4, N + 1)); U[0, 0] = 1
    h = T / N
    for k in range(N):
        U[:, k + 1] = -np.array(model.step(Q[:, k], QD[:, k], A[:, k], Q[:, k + 1], QD[:, k + 1],
                                           A[:, k + 1], U[:, k], np.zeros(4), h)[0][2 * model.nq:]).ravel()
    return Q, QD, A, U


def _np_exp(v):
    """exp([v]x) for rotation vectors v of shape (n, 3) (Rodrigues, series near 0)."""
    th = np.linalg.norm(v, axis=1)
    small = th < 1e-6
    ths = np.where(small, 1.0, th)
    a = np.where(small, 1 - th ** 2 / 6, np.sin(ths) / ths)
    b = np.where(small, 0.5 - th ** 2 / 24, (1 - np.cos(ths)) / ths ** 2)
    K = np.zeros((len(v), 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -v[:, 2], v[:, 1], -v[:, 0]
    K[:, 1, 0], K[:, 2, 0], K[:, 2, 1] = v[:, 2], -v[:, 1], v[:, 0]
    return np.eye(3) + a[:, None, None] * K + b[:, None, None] * (K @ K)


def universal_to_spherical(q):
    """joint angles (2, n) of R = Rx(q1) Ry(q2) -> spherical coordinates (3, n) of the same R by
    its swing-twist decomposition: e = R z, swing v = atan2(|z x e|, e_z) (z x e)/|z x e|,
    exp([v]x) Rz(q3) = R, q3 = the angle of exp(-[v]x) R about z (unwrapped along the samples)."""
    c1, s1, c2, s2 = np.cos(q[0]), np.sin(q[0]), np.cos(q[1]), np.sin(q[1])
    n = q.shape[1]
    R = np.zeros((n, 3, 3))                      # Rx(q1) Ry(q2)
    R[:, 0, 0], R[:, 0, 1], R[:, 0, 2] = c2, 0.0, s2
    R[:, 1, 0], R[:, 1, 1], R[:, 1, 2] = s1 * s2, c1, -s1 * c2
    R[:, 2, 0], R[:, 2, 1], R[:, 2, 2] = -c1 * s2, s1, c1 * c2
    e = R[:, :, 2]
    c = np.stack([-e[:, 1], e[:, 0], np.zeros(n)], 1)          # z x e
    sn = np.linalg.norm(c, axis=1)
    th = np.arctan2(sn, e[:, 2])
    f = np.where(sn < 1e-12, 1.0, th / np.where(sn < 1e-12, 1.0, sn))   # th / sin th
    v = c * f[:, None]
    M = np.swapaxes(_np_exp(v), 1, 2) @ R                      # = Rz(q3)
    assert np.abs(M[:, 2, 2] - 1).max() < 1e-9
    q3 = np.unwrap(np.arctan2(M[:, 1, 0], M[:, 0, 0]))
    return np.stack([v[:, 0], v[:, 1], q3])


def map_universal_solution(T, sol, N):
    """a universal-joint solution (Q, QD, A, U) as a start of the spherical joint on N intervals:
    the same motion R_AB(t) (so the same attitude U), its spherical coordinates at the nodes and
    their rates by central differences (step 1e-5 s) along the exact piecewise-cubic path."""
    Q, QD, A, U = sol
    tk_old = np.linspace(0, T, Q.shape[1])
    tk = np.linspace(0, T, N + 1)
    e = 1e-5
    tt = np.concatenate([tk - e, tk, tk + e])
    qu = path_eval(np.clip(tt, 0, T), tk_old, Q, QD, A)[0]
    qs = np.stack([universal_to_spherical(qu[:, i * (N + 1):(i + 1) * (N + 1)]) for i in range(3)])
    # unwrap consistently across the three sample rows (same branch as the nodes)
    for i in (0, 2):
        qs[i, 2] += 2 * np.pi * np.round((qs[1, 2] - qs[i, 2]) / (2 * np.pi))
    qm, q0, qp = qs
    Qn, QDn, An = q0, (qp - qm) / (2 * e), (qp - 2 * q0 + qm) / e ** 2
    # the ends: the one-sided samples (clipped) would spoil the differences; q = qd = 0 there
    Qn[:, [0, -1]] = 0; QDn[:, [0, -1]] = 0
    Aend = path_eval(np.array([0.0, T]), tk_old, Q, QD, A)[2]
    # at q = 0 the map's Jacobian is the identity on (q1, q2) and q3 has zero slope: qdd maps
    # as the linear part plus a quadratic term in qd = 0
    An[:2, 0], An[:2, -1] = Aend[:, 0], Aend[:, 1]
    An[2, [0, -1]] = 0
    Un = np.stack([np.interp(tk, tk_old, U[i]) for i in range(4)])
    return Qn, QDn, An, Un / np.linalg.norm(Un, axis=0)


def interp_solution(T, sol, N):
    Q, QD, A, U = sol
    tk_old = np.linspace(0, T, Q.shape[1])
    tk = np.linspace(0, T, N + 1)
    q, qd, qdd = path_eval(tk, tk_old, Q, QD, A)
    Un = np.stack([np.interp(tk, tk_old, U[i]) for i in range(4)])
    return q, qd, qdd, Un / np.linalg.norm(Un, axis=0)


# ============================================================================ the NLP
def build_solver(model, N, T, max_iter, max_wall=None):
    """The NLP does not depend on the start: built once per (model, N) and reused."""
    max_wall = MAX_WALL if max_wall is None else max_wall
    key = (N, T, max_iter, max_wall)
    if key in model.solvers:
        return model.solvers[key]
    nq = model.nq
    Q = ca.MX.sym('Q', nq, N + 1); QD = ca.MX.sym('QD', nq, N + 1)
    A = ca.MX.sym('A', nq, N + 1); U = ca.MX.sym('U', 4, N + 1)
    P = ca.MX.sym('P')
    h = T / N
    res, taum, _ = model.step.map(N, 'serial')(Q[:, :-1], QD[:, :-1], A[:, :-1], Q[:, 1:], QD[:, 1:],
                                            A[:, 1:], U[:, :-1], U[:, 1:], h)
    TAU = ca.horzcat(model.tau.map(N + 1, 'serial')(Q, QD, A), taum)
    geq = ca.vertcat(ca.vec(res), Q[:, 0], QD[:, 0], Q[:, -1], QD[:, -1],
                     U[:, 0] - ca.DM([1, 0, 0, 0]), U[[0, 1, 2], -1])
    n = nq * (2 * N + 1)
    gin = ca.vertcat(ca.vec(TAU - P), ca.vec(TAU + P))
    G_ = ca.vertcat(geq, gin)
    lbg = np.concatenate([np.zeros(geq.shape[0]), -np.inf * np.ones(n), np.zeros(n)])
    ubg = np.concatenate([np.zeros(geq.shape[0]), np.zeros(n), np.inf * np.ones(n)])
    x = ca.vertcat(ca.vec(Q), ca.vec(QD), ca.vec(A), ca.vec(U), P)
    lbx = -np.inf * np.ones(x.shape[0]); ubx = np.inf * np.ones(x.shape[0]); lbx[-1] = 0
    opts = {'ipopt.max_iter': max_iter, 'ipopt.print_level': 0, 'print_time': 0,
            'ipopt.tol': 1e-9, 'ipopt.constr_viol_tol': 1e-10, 'ipopt.acceptable_tol': 1e-7,
            'ipopt.mu_strategy': 'adaptive', 'ipopt.linear_solver': 'mumps', 'ipopt.sb': 'yes',
            'ipopt.max_wall_time': float(max_wall)}
    if MU_INIT is not None:                # a warm restart from a (nearly) optimal point
        opts.update({'ipopt.mu_init': MU_INIT, 'ipopt.warm_start_init_point': 'yes',
                     'ipopt.warm_start_bound_push': 1e-9, 'ipopt.warm_start_mult_bound_push': 1e-9})
    S = ca.nlpsol('S', 'ipopt', dict(x=x, f=P, g=G_), opts)
    model.solvers[key] = (S, lbx, ubx, lbg, ubg)
    return model.solvers[key]


def solve(model, N, init, T=T_FALL, max_iter=3000):
    Q0, QD0, A0, U0 = init
    nq = model.nq
    S, lbx, ubx, lbg, ubg = build_solver(model, N, T, max_iter)
    P0 = float(np.abs(np.array(model.tau.map(N + 1)(Q0, QD0, A0))).max())
    if not (np.isfinite(P0) and P0 < 1e3 and np.all(np.isfinite(U0))):
        raise ValueError(f'degenerate start (peak torque of the start {P0:.3g} N m)')
    x0 = np.concatenate([Q0.ravel('F'), QD0.ravel('F'), A0.ravel('F'), U0.ravel('F'), [P0]])
    t0 = time.time()
    sol = S(x0=x0, lbx=lbx, ubx=ubx, lbg=lbg, ubg=ubg)
    wall = time.time() - t0
    st = S.stats()
    xs = np.array(sol['x']).ravel()
    k = 0
    parts = []
    for rows in (nq, nq, nq, 4):
        parts.append(xs[k:k + rows * (N + 1)].reshape((rows, N + 1), order='F')); k += rows * (N + 1)
    Qs, QDs, As, Us = parts
    out = analyse(model, T, Qs, QDs, As, Us)
    out.update(P=float(xs[-1]), status=st['return_status'], iters=st['iter_count'], wall_s=wall,
               # where the wall time went: CasADi's evaluation of the Lagrangian's Hessian and of
               # the constraints' Jacobian; the rest is IPOPT's own (MUMPS, line search)
               hess_s=float(st['t_wall_nlp_hess_l']), jac_s=float(st['t_wall_nlp_jac_g']))
    if 'peak_colloc_j' in out:             # motors whose bound is active (to 1e-6 of P)
        out['n_motors_at_peak'] = int(sum(v >= out['P'] * (1 - 1e-6) for v in out['peak_colloc_j']))
    return out, (Qs, QDs, As, Us)


OK = ('Solve_Succeeded', 'Solved_To_Acceptable_Level')


def fmt(o):
    keys = ['N', 'status', 'iters', 'wall_s', 'hess_s', 'jac_s', 'P', 'peak_dense', 'peak_dense_j', 'twist_sign',
            'twist_deg', 'twist_err_deg', 'swing_deg', 'twist_colloc_deg', 'max_bend_deg',
            'max_spine_angle_deg', 'turns', 'peak_qd']
    keys += [k for k in ('max_q3_deg', 'peak_colloc_j', 'n_motors_at_peak') if k in o]
    r = {}
    for k in keys:
        v = o.get(k)
        if isinstance(v, float):
            v = float('%.10g' % v)
        elif isinstance(v, list):
            v = [float('%.8g' % x) for x in v]
        r[k] = v
    return r


def load_start(model, path, N):
    """a saved solution as a start on N intervals: interpolated, or (a universal-joint solution
    for the spherical joint) mapped onto the spherical coordinates."""
    z = np.load(path)
    sol = (z['Q'], z['QD'], z['A'], z['U'])
    if sol[0].shape[0] == 2 and model.nq == 3:
        return map_universal_solution(float(z['T']), sol, N)
    if sol[0].shape[0] != model.nq:
        raise ValueError(f'{path}: {sol[0].shape[0]} joint coordinates, the case has {model.nq}')
    return interp_solution(float(z['T']), sol, N)


def run_case(name, Ns, starts, budget, out_dir, max_iter, log, refine_best=None):
    c = CASES[name]
    model = Model(c['front'], c['rear'], c['joint'])
    T = case_T(c)
    N0 = Ns[0]
    t_start = time.time()
    found = []
    for i, st in enumerate(starts):
        if time.time() - t_start > budget:
            log(dict(case=name, note=f'budget {budget:.0f} s spent: starts {i}.. skipped',
                     skipped=[list(s) for s in starts[i:]]))
            break
        try:
            if st[0] == 'map':             # a saved solution (universal -> spherical: mapped)
                label = f'from {os.path.basename(st[1])}'
                init = load_start(model, st[1], N0)
            else:
                b, tn, sg, kind = st[:4]
                tw = st[4] if len(st) > 4 else 0.0
                label = f'{kind} beta={b:g} turns={tn:g} sign={sg:+d}' + (f' twist={tw:g}' if tw else '')
                init = guess(model, N0, T, b, tn, sg, kind, tw)
        except Exception as e:  # noqa: BLE001
            log(dict(case=name, N=N0, start=str(st), error=repr(e)))
            continue
        try:
            o, sol = solve(model, N0, init, T=T, max_iter=max_iter)
        except Exception as e:  # noqa: BLE001
            log(dict(case=name, N=N0, start=label, error=repr(e)))
            continue
        o['start'] = label
        log(dict(case=name, start=label, **fmt(o)))
        if o['status'] in OK:
            found.append((o, sol, label))
    # distinct local optima at N0 (peak to 1e-5 N m and twist sign)
    found.sort(key=lambda f: f[0]['P'])
    clusters = []
    for o, sol, label in found:
        key = (round(o['P'], 5), o['twist_sign'])
        if not any(cl['key'] == key for cl in clusters):
            clusters.append(dict(key=key, o=o, sol=sol, starts=[label]))
        else:
            next(cl for cl in clusters if cl['key'] == key)['starts'].append(label)
    for j, cl in enumerate(clusters):
        np.savez(os.path.join(out_dir, f'sol_{name}_N{N0}_{j}.npz'), T=T,
                 **dict(zip(('Q', 'QD', 'A', 'U'), cl['sol'])))
        log(dict(case=name, optimum=j, N=N0, P=cl['o']['P'], twist_sign=cl['o']['twist_sign'],
                 n_starts=len(cl['starts']), starts=cl['starts']))
    # refine on the finer grids: first every distinct optimum, then (while the case has spent
    # less than 2 x budget) every other converged start, each from its own N0 solution
    todo = [(j, cl['o'], cl['sol'], cl['starts'][0], True) for j, cl in enumerate(clusters)]
    todo += [(j, o, sol, label, False) for j, cl in enumerate(clusters)
             for o, sol, label in found if label in cl['starts'][1:]]
    if refine_best is not None:            # only the refine_best lowest distinct optima
        todo = [t for t in todo if t[4] and t[0] < refine_best]
    for j, o0, sol, label, rep in todo:
        if not rep and time.time() - t_start > 2 * budget:
            log(dict(case=name, note=f'2 x budget spent: refinement of start {label} skipped'))
            continue
        for N in Ns[1:]:
            o, sol = solve(model, N, interp_solution(T, sol, N), T=T, max_iter=max_iter)
            log(dict(case=name, optimum=j, representative=rep, start=label,
                     refined_from=f'N={o0["N"]} P={o0["P"]:.7f}', **fmt(o)))
            if rep:
                np.savez(os.path.join(out_dir, f'sol_{name}_N{N}_{j}.npz'), T=T,
                         **dict(zip(('Q', 'QD', 'A', 'U'), sol)))
    log(dict(case=name, note='case done', wall_s=time.time() - t_start))


def default_starts():
    st = []
    for b in (30, 45, 60, 90):
        for tn in (0.75, 1.0, 1.25, 1.5):
            for sg in (1, -1):
                st.append((b, tn, sg, 'cone'))
    return st


# ============================================================================ checks
def check():
    sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
    import models as ref
    rng = np.random.default_rng(20261203)
    worst = {}
    for name, c in CASES.items():
        m = Model(c['front'], c['rear'], c['joint'])
        cat = ref.Cat(*c['front'], *c['rear'], c['joint'])
        n = 8
        nq = m.nq
        q = rng.uniform(-1.6, 1.6, (n, nq)); qd = rng.uniform(-6, 6, (n, nq)); qdd = rng.uniform(-40, 40, (n, nq))
        st = cat.state(q, qd, qdd, check=True)
        e_tau = e_om = e_q = e_r = e_tj = e_fg = e_omd = 0.0
        for i in range(n):
            (tauJ, Qne, Qlag, react, tau_g, tau, tauJ_f, om, omd, om_g, omd_g) = [
                np.array(v).ravel() for v in m.checks(q[i], qd[i], qdd[i])]
            e_fg = max(e_fg, np.abs(tau - tau_g).max() / max(1.0, np.abs(tau).max()),
                       np.abs(omd - omd_g).max() / max(1.0, np.abs(omd).max()))
            e_omd = max(e_omd, np.abs(omd - st['Omd'][i]).max() / max(1.0, np.abs(st['Omd'][i]).max()))
            sc = max(1.0, np.abs(st['tau'][i]).max())
            tau_fn = np.array(m.tau(q[i], qd[i], qdd[i])).ravel()       # the NLP's function
            e_tau = max(e_tau, np.abs(tau - st['tau'][i]).max() / sc, np.abs(tau_g - st['tau'][i]).max() / sc,
                        np.abs(tau_fn - st['tau'][i]).max() / sc)
            e_tj = max(e_tj, np.abs(tauJ_f - st['tauJ'][i]).max() / sc,
                       np.abs(tauJ - st['tauJ'][i]).max() / sc)
            e_om = max(e_om, np.abs(om - st['Om'][i]).max() / max(1.0, np.abs(st['Om'][i]).max()))
            e_q = max(e_q, np.abs(Qne - Qlag).max() / max(1.0, np.abs(Qlag).max()))
            e_r = max(e_r, np.abs(react).max() / sc)
        worst[name] = dict(tau_vs_models_py=e_tau, tauJ_vs_models_py=e_tj, Om_vs_models_py=e_om,
                           Omd_vs_models_py=e_omd, fast_vs_generic=e_fg,
                           newton_euler_vs_lagrange=e_q, action_reaction=e_r,
                           sample_tau=[float('%.12g' % x) for x in np.array(m.tau(q[0], qd[0], qdd[0])).ravel()],
                           sample_tau_models_py=[float('%.12g' % x) for x in st['tau'][0]])
        print(name, c['joint'], json.dumps({k: (float('%.3g' % v) if isinstance(v, float) else v)
                                            for k, v in worst[name].items()}), flush=True)
    ok = all(w['tau_vs_models_py'] < 1e-9 and w['newton_euler_vs_lagrange'] < 1e-9 and w['fast_vs_generic'] < 1e-9
             for w in worst.values())
    print('torque check', 'PASSED (< 1e-9, relative to max(1, |tau|))' if ok else 'FAILED')
    return ok


# ============================================================================ summary
def summary(path):
    """Per case and grid: the best optimum and the values every start reached."""
    rows = [json.loads(x) for x in open(path) if x.strip()]
    for name in CASES:
        rs = [r for r in rows if r.get('case') == name and 'P' in r and 'status' in r]
        if not rs:
            continue
        c = CASES[name]
        print(f"\n## case {name}: A {c['front']}, B {c['rear']} (kg, m, m), {c['joint']} joint, T {case_T(c):.7f} s")
        for N in sorted({r['N'] for r in rs}):
            rn = [r for r in rs if r['N'] == N]
            ok = [r for r in rn if r['status'] in OK]
            if not ok:
                print(f"  N={N}: no converged solve"); continue
            b = min(ok, key=lambda r: r['P'])
            print(f"  N={N}: best P = {b['P']:.7f} N m (dense {b['peak_dense']:.7f}), twist sign {b['twist_sign']:+d}, "
                  f"largest bend {b['max_bend_deg']:.3f} deg, bend-direction turns {b['turns']:+.4f}, "
                  f"re-integrated twist error {b['twist_err_deg']:+.2e} deg, swing {b['swing_deg']:.2e} deg "
                  f"[start {b.get('start')}]")
            vals = {}
            for r in rn:
                key = (f"{r['P']:.6f}" if r['status'] in OK else r['status'], r['twist_sign'])
                v = vals.setdefault(key, dict(n=0, bend=r['max_bend_deg'], turns=r['turns'], starts=[]))
                v['n'] += 1
                v['starts'].append(r.get('start', '').replace('cone ', ''))
            for (P, sg), v in sorted(vals.items()):
                print(f"     {P} sign {sg:+d}: {v['n']:2d} starts, bend {v['bend']:.2f} deg, turns {v['turns']:+.3f}"
                      f"  <- {'; '.join(v['starts'])}")


# ============================================================================ main
def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('what', choices=['check', 'solve', 'summary', 'refine'])
    ap.add_argument('cases', nargs='*', default=['a', 'b', 'c', 'd'])
    ap.add_argument('--N', default='100,200')
    ap.add_argument('--starts', default='',
                    help='beta_deg:turns:sign[:cone|circle],... (default: the 32 cone starts)')
    ap.add_argument('--budget', type=float, default=900.0, help='seconds of starts per case')
    ap.add_argument('--max-iter', type=int, default=3000)
    ap.add_argument('--max-wall', type=float, default=300.0, help='seconds per IPOPT solve')
    ap.add_argument('--mu-init', type=float, default=None,
                    help="IPOPT's initial barrier parameter, with warm_start_init_point (refine from a near optimum)")
    ap.add_argument('--out', default='/tmp/models_minpeak')
    ap.add_argument('--warm', default='', help='refine: a saved sol_*.npz of the (single) case '
                    '(a universal-joint solution is mapped onto a spherical case)')
    ap.add_argument('--map-from', default='',
                    help='solve: saved solutions (comma-separated npz) as extra starts, after --starts; '
                    'a universal-joint solution is mapped onto a spherical case')
    ap.add_argument('--refine-best', type=int, default=None,
                    help='solve: refine only the k lowest distinct optima (default: all, then the rest)')
    a = ap.parse_args()
    if a.what == 'check':
        sys.exit(0 if check() else 1)
    if a.what == 'summary':
        summary(os.path.join(a.out, 'results.jsonl'))
        return
    global MAX_WALL, MU_INIT
    MAX_WALL = a.max_wall
    MU_INIT = a.mu_init
    os.makedirs(a.out, exist_ok=True)
    Ns = [int(x) for x in a.N.split(',')]
    starts = default_starts()
    if a.starts:
        starts = []
        for s in a.starts.split(','):
            f = s.split(':')
            starts.append((float(f[0]), float(f[1]), int(float(f[2])), f[3] if len(f) > 3 else 'cone')
                          + ((float(f[4]),) if len(f) > 4 else ()))
    fh = open(os.path.join(a.out, 'results.jsonl'), 'a')

    def log(d):
        line = json.dumps(d, default=float)
        print(line, flush=True)
        fh.write(line + '\n'); fh.flush()
    log(dict(note='models_minpeak', argv=sys.argv, T=T_FALL,
             T_cases={n: case_T(CASES[n]) for n in a.cases if n in CASES}, date=time.strftime('%Y-%m-%d %H:%M:%S')))
    if a.what == 'refine':          # one case, from a saved solution, on each grid of --N in turn
        name = a.cases[0]
        c = CASES[name]
        model = Model(c['front'], c['rear'], c['joint'])
        T = case_T(c)
        z = np.load(a.warm)
        sol = (z['Q'], z['QD'], z['A'], z['U'])
        for i, N in enumerate(Ns):
            init = load_start(model, a.warm, N) if i == 0 else interp_solution(float(z['T']), sol, N)
            o, sol = solve(model, N, init, T=T, max_iter=a.max_iter)
            log(dict(case=name, start='refine ' + os.path.basename(a.warm), **fmt(o)))
            np.savez(os.path.join(a.out, f'refined_{name}_N{N}.npz'), T=T,
                     **dict(zip(('Q', 'QD', 'A', 'U'), sol)))
            z = dict(T=T)
        return
    if a.map_from:
        starts = (starts if a.starts else []) + [('map', f) for f in a.map_from.split(',')]
    for name in a.cases:
        run_case(name, Ns, starts, a.budget, a.out, a.max_iter, log, a.refine_best)


if __name__ == '__main__':
    main()
