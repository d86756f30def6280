#!/usr/bin/env python3
"""Min-peak-torque flip of the paper's cat released with spin, with an ACCURATE orientation
integration inside the collocation, and every optimum re-checked by DOP853.

Question (catflip, release with spin L = [0, 0, 0.01] N m s): catflip's whole-manoeuvre optimiser
reports 0.250143 N m with an exact flip; the older collocation tests/reference/spin/mintime_spin.py
reports 0.2261427 (N = 100) and 0.2307801 (N = 200).  That collocation integrates A's orientation by
one exponential-midpoint step per interval (2nd order), so its flip is off by 1e-4 .. 3e-5 rad when
re-integrated exactly.  This script decides whether the lower number is a better optimum or the
price of that discretisation error.

Model (DESIGN.md 1, 2, 9; identical to mintime_spin.py, whose CasADi functions are imported from the
same folder, unchanged):  Omega = I_lock(q)^-1 (R^T L - h(q, qd)),  R' = R [Omega]x  (quaternion
u' = 1/2 u (x) (0, Omega)),  joint torques tau = d/dt dK/dqd - dK/dq with Omega as quasi-velocity
(mintime_spin.build_model; checked against Newton-Euler on B by the reference's test_mt.py, and here
again at every dense peak with spin.torque_NE).

Discretisation (normalised grid, N uniform intervals of h = T/N, T = sqrt(2*10/9.8) fixed):
  * joints exactly as mintime_spin.py: qdd piecewise linear (node values), q an exact C2 piecewise
    cubic; q = qd = 0 at both ends;
  * orientation, scheme 'em'  : the reference's rule, u_{k+1} = u_k (x) exp(h Omega_mid), ell at the
                                normalised mean (u_k + u_{k+1})/2           (2nd order, implicit);
                 scheme 'rk4' : M classical RK4 substeps per interval on the quaternion, driven by the
                                exact cubic q(t), ell = R(u/|u|)^T L at every stage  (4th order);
  * peak: epigraph variable P >= |tau_i| at every node and every interval midpoint (the midpoint
    orientation is the RK4 state after M/2 substeps, or the mean for 'em');
  * end: A's final orientation = target quaternion u_T, imposed as vec(conj(u_T) (x) U_N) = 0.
    u_T = (0,0,0,1) is the half turn about the initial spine z (twist +-pi, swing 0) and reproduces
    the reference's U[0:3, N] = 0.

Every optimum is then re-integrated independently: SciPy DOP853, rtol = atol = 1e-12, interval by
interval, driven by the solution's own piecewise-cubic q(t), with spin.py's numpy Omega (not CasADi).
Reported: flip error = rotation angle between the final attitude and Rz(pi); continuous twist and
swing (as DESIGN.md 2); peak |tau| at the nodes (DOP853 orientation), the NLP's P (nodes+midpoints),
and the dense peak on 16 points per interval (DOP853 orientation), the dense argmax re-evaluated by
Newton-Euler on B (spin.torque_NE).

Defect correction ("shooting", --correct K): the discrete orientation map differs from the exact one
by a small rotation e = conj(U_N) (x) u_DOP853(T).  The NLP is re-solved (warm) with the target moved
to u_T' = u_target (x) conj(e), K times, so that the DOP853-exact flip of the optimum tends to zero
while the NLP keeps its own integrator: this imposes the flip through the DOP853 map.

Usage (one IPOPT process at a time; results appended as JSON lines to results_minpeak_hi.jsonl):
  python minpeak_spin_hi.py --scheme rk4 --M 2 --N 100,200,400 --start ref
  python minpeak_spin_hi.py --scheme em --N 100,200 --start ref --correct 3
  starts: ref (45:0.75:-1, the old reference's), b:turns:sign (mintime_spin.guess), cone:b:turns:sign
  (constant-bend cone, cosine ramps over the first/last 20 %), catflip:<json> (catflip's spline),
  npz:<file> (a saved solution, interpolated to the new grid).
"""
import os
import sys
import time
import json
import argparse

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.dirname(HERE)]   # spin.py here; cat.py, mintime.py one folder up

import numpy as np
import casadi as ca
from scipy.integrate import solve_ivp
from scipy.interpolate import BSpline

import mintime_spin as ref          # CasADi model of the reference (unchanged copy)
import spin as sp                   # numpy engine + Newton-Euler torques of the reference

F_TAU, F_OM, F_ELL, qmul_ca, qexp = ref.F_TAU, ref.F_OM, ref.F_ELL, ref.qmul, ref.qexp
T_FALL = float(np.sqrt(2 * 10 / 9.8))
L_SPIN = np.array([0.0, 0.0, 0.01])
NDENSE = 16
FLIP_TOL = 1e-9                     # stop the defect correction below this DOP853 flip error (rad)
PRINT_LEVEL = 0
WARM_OPTS = False                   # --warm-opts: small initial barrier for warm starts
MAX_CPU = 1150.0                    # s per IPOPT solve (the machine is shared)


# ------------------------------------------------------------------ quaternion helpers (numpy)
def qconj(u):
    return np.array([u[0], -u[1], -u[2], -u[3]])


def qmul(a, b):
    return sp.qmul(np.asarray(a, float), np.asarray(b, float))


def flip_error(u, target=(0, 0, 0, 1)):
    """Rotation angle (rad) between attitude u and the target attitude (sign of u irrelevant)."""
    d = qmul(qconj(np.asarray(target, float)), u / np.linalg.norm(u))
    return 2 * np.arctan2(np.linalg.norm(d[1:]), abs(d[0]))


# ------------------------------------------------------------------ interval map (CasADi SX)
def build_step(scheme, M):
    q0, qd0, a0, q1, qd1, a1 = [ca.SX.sym(n, 2) for n in ('q0', 'qd0', 'a0', 'q1', 'qd1', 'a1')]
    u0, u1 = ca.SX.sym('u0', 4), ca.SX.sym('u1', 4)
    h = ca.SX.sym('h')
    Lw = ca.SX.sym('L', 3)
    rq = q1 - (q0 + h * qd0 + h**2 / 6 * (2 * a0 + a1))          # exact cubic continuity
    rqd = qd1 - (qd0 + h / 2 * (a0 + a1))

    def joint(t):                                                 # exact cubic, local time t
        return (q0 + qd0 * t + a0 * t**2 / 2 + (a1 - a0) * t**3 / (6 * h),
                qd0 + a0 * t + (a1 - a0) * t**2 / (2 * h),
                a0 + (a1 - a0) * t / h)

    def f(t, u):                                                  # u' = 1/2 u (x) (0, Omega)
        q, qd, _ = joint(t)
        Om = F_OM(q, qd, F_ELL(u, Lw))                            # F_ELL normalises u
        return 0.5 * qmul_ca(u, ca.vertcat(0, Om))

    def rk4(t, u, hs):
        k1 = f(t, u)
        k2 = f(t + hs / 2, u + hs / 2 * k1)
        k3 = f(t + hs / 2, u + hs / 2 * k2)
        k4 = f(t + hs, u + hs * k3)
        return u + hs / 6 * (k1 + 2 * k2 + 2 * k3 + k4)

    qm, qdm, am = joint(h / 2)
    if scheme == 'em':                                            # the reference's rule
        umid = (u0 + u1) / 2
        ru = u1 - qmul_ca(u0, qexp(h * F_OM(qm, qdm, F_ELL(umid, Lw))))
    elif scheme == 'rk4':
        hs = h / M
        u = u0
        umid = None
        for j in range(M):
            u = rk4(j * hs, u, hs)
            if 2 * (j + 1) == M:
                umid = u
        if umid is None:   # odd M: cubic Hermite midpoint from u0, u1 and their slopes (O(h^4))
            umid = (u0 + u1) / 2 + h / 8 * (f(0, u0) - f(h, u1))
        ru = u1 - u
    else:
        raise ValueError(scheme)
    taum = F_TAU(qm, qdm, am, F_ELL(umid, Lw))
    return ca.Function('step', [q0, qd0, a0, q1, qd1, a1, u0, u1, h, Lw],
                       [ca.vertcat(rq, rqd, ru), taum])


# ------------------------------------------------------------------ piecewise cubic (numpy)
def path_eval(t, h, Q, QD, A):
    """Exact piecewise-cubic q, qd, qdd at times t; interval index k chosen by the caller if given."""
    t = np.atleast_1d(np.asarray(t, float))
    N = Q.shape[1] - 1
    k = np.clip(np.floor(t / h + 1e-12).astype(int), 0, N - 1)
    s = t - k * h
    a0, a1 = A[:, k], A[:, k + 1]
    q = Q[:, k] + QD[:, k] * s + a0 * s**2 / 2 + (a1 - a0) * s**3 / (6 * h)
    qd = QD[:, k] + a0 * s + (a1 - a0) * s**2 / (2 * h)
    return q, qd, a0 + (a1 - a0) * s / h


def cubic_on(k, h, Q, QD, A):
    """q, qd, qdd on interval k as functions of absolute time (for the ODE and for torque_NE)."""
    def sched(t, _ph=None):
        s = t - k * h
        a0, a1 = A[:, k], A[:, k + 1]
        return (Q[:, k] + QD[:, k] * s + a0 * s**2 / 2 + (a1 - a0) * s**3 / (6 * h),
                QD[:, k] + a0 * s + (a1 - a0) * s**2 / (2 * h), a0 + (a1 - a0) * s / h)
    return sched


# ------------------------------------------------------------------ DOP853 re-integration
def reintegrate(T, Q, QD, A, L=L_SPIN, rtol=1e-12, atol=1e-12):
    """A's orientation by DOP853 driven by the solution's piecewise-cubic q(t), restarted on every
    interval (the cubic's third derivative jumps at the nodes).  numpy Omega from spin.py."""
    N = Q.shape[1] - 1
    h = T / N
    u = np.array([1.0, 0, 0, 0])
    dense, nodes = [], [u.copy()]
    for k in range(N):
        sched = cubic_on(k, h, Q, QD, A)

        def rhs(t, y):
            q, qd, _ = sched(t)
            Om = sp.omega_spin(q, qd, sp.quat_to_R(y).T @ L)
            return 0.5 * sp.qmul(y, np.array([0.0, *Om]))
        sol = solve_ivp(rhs, (k * h, (k + 1) * h), u, method='DOP853', rtol=rtol, atol=atol,
                        dense_output=True)
        assert sol.success, sol.message
        dense.append(sol.sol)
        u = sol.y[:, -1] / np.linalg.norm(sol.y[:, -1])
        nodes.append(u.copy())
    return np.array(nodes).T, dense


def analyse(T, Q, QD, A, U, target, L=L_SPIN):
    """Independent re-check of a collocation optimum (see the module docstring)."""
    N = Q.shape[1] - 1
    h = T / N
    Un, dense = reintegrate(T, Q, QD, A, L)
    uT = Un[:, -1]
    # continuous twist (about the initial spine z) along the dense output, and the swing
    acc, prev = 0.0, 0.0
    tt = np.concatenate([np.linspace(k * h, (k + 1) * h, NDENSE + 1)[:-1] for k in range(N)] + [[T]])
    kk = np.minimum((np.arange(len(tt)) // NDENSE), N - 1)
    uu = np.stack([dense[k](t) for k, t in zip(kk, tt)], 1)
    uu /= np.linalg.norm(uu, axis=0)
    for j in range(uu.shape[1]):
        tw = 2 * np.arctan2(uu[3, j], uu[0, j])
        acc += (tw - prev + np.pi) % (2 * np.pi) - np.pi
        prev = tw
    twist = np.degrees(acc)
    swing = np.degrees(2 * np.arctan2(np.hypot(uT[1], uT[2]), np.hypot(uT[0], uT[3])))
    # dense torques (16 points per interval, DOP853 orientation)
    q, qd, qdd = path_eval(tt, h, Q, QD, A)
    ells = np.stack([sp.quat_to_R(uu[:, j]).T @ L for j in range(uu.shape[1])], 1)
    tau = np.array(F_TAU.map(len(tt))(q, qd, qdd, ells))
    j = int(np.argmax(np.abs(tau).max(0)))
    k = int(kk[j])
    tau_ne = sp.torque_NE(cubic_on(k, h, Q, QD, A), L, tt[j], sp.quat_to_R(dense[k](tt[j])), k)[0]
    # at the nodes, with the DOP853 orientation
    ellk = np.stack([sp.quat_to_R(Un[:, i]).T @ L for i in range(N + 1)], 1)
    tau_nodes = np.array(F_TAU.map(N + 1)(Q, QD, A, ellk))
    # bend and circulation of B's spine direction in A's frame (as mintime.analyse)
    ez = np.stack([np.sin(q[1]), -np.sin(q[0]) * np.cos(q[1]), np.cos(q[0]) * np.cos(q[1])])
    bend = np.degrees(np.arccos(np.clip(ez[2], -1, 1)))
    sel = bend > 0.1 * bend.max()
    phi = np.unwrap(np.arctan2(ez[1][sel], ez[0][sel]))
    return dict(
        flip_err_rad=float(flip_error(uT)),
        flip_err_colloc_rad=float(flip_error(U[:, -1], target)),     # vs the NLP's own target
        twist_deg=float(twist), swing_deg=float(swing),
        branch='with spin (+pi)' if twist > 0 else 'against spin (-pi)',
        peak_nodes=float(np.abs(tau_nodes).max()),
        peak_dense=float(np.abs(tau).max()), t_peak_dense=float(tt[j]),
        peak_dense_NE=float(np.abs(tau_ne).max()),
        max_bend_deg=float(bend.max()), turns=float((phi[-1] - phi[0]) / (2 * np.pi)),
        uT_dop853=uT.tolist(), uN_colloc=(U[:, -1] / np.linalg.norm(U[:, -1])).tolist())


# ------------------------------------------------------------------ the NLP
class MinPeak:
    """min P  s.t. collocation equalities, -P <= tau <= P at nodes and midpoints,
    q = qd = 0 at both ends, U_0 = 1, vec(conj(u_T) U_N) = 0 (u_T a parameter)."""

    def __init__(self, N, scheme, M, L=L_SPIN, T=T_FALL):
        self.N, self.T, self.L = N, T, np.asarray(L, float)
        step = build_step(scheme, M)
        Q = ca.MX.sym('Q', 2, N + 1); QD = ca.MX.sym('QD', 2, N + 1)
        A = ca.MX.sym('A', 2, N + 1); U = ca.MX.sym('U', 4, N + 1)
        P = ca.MX.sym('P')
        uT = ca.MX.sym('uT', 4)                        # target attitude (parameter)
        Lrep = ca.repmat(ca.DM(self.L), 1, N)
        res, taum = step.map(N, 'serial')(Q[:, :-1], QD[:, :-1], A[:, :-1], Q[:, 1:], QD[:, 1:],
                                          A[:, 1:], U[:, :-1], U[:, 1:], T / N, Lrep)
        tauk = F_TAU.map(N + 1, 'serial')(Q, QD, A, F_ELL.map(N + 1, 'serial')(
            U, ca.repmat(ca.DM(self.L), 1, N + 1)))
        TAU = ca.horzcat(tauk, taum)
        d = qmul_ca(ca.vertcat(uT[0], -uT[1], -uT[2], -uT[3]), U[:, -1])
        geq = ca.vertcat(ca.vec(res), Q[:, 0], QD[:, 0], Q[:, -1], QD[:, -1],
                         U[:, 0] - ca.DM([1, 0, 0, 0]), d[1:])
        gin = ca.vertcat(ca.vec(TAU - P), ca.vec(TAU + P))
        n = 2 * (2 * N + 1)
        self.lbg = np.concatenate([np.zeros(geq.shape[0]), -np.inf * np.ones(n), np.zeros(n)])
        self.ubg = np.concatenate([np.zeros(geq.shape[0]), np.zeros(n), np.inf * np.ones(n)])
        x = ca.vertcat(ca.vec(Q), ca.vec(QD), ca.vec(A), ca.vec(U), P)
        self.nx = x.shape[0]
        opts = {'ipopt.max_iter': 3000, 'ipopt.print_level': PRINT_LEVEL, 'print_time': 0,
                'ipopt.tol': 1e-9, 'ipopt.constr_viol_tol': 1e-10, 'ipopt.acceptable_tol': 1e-7,
                'ipopt.mu_strategy': 'adaptive', 'ipopt.linear_solver': 'mumps',
                'ipopt.max_cpu_time': MAX_CPU}
        nlp = dict(x=x, f=P, g=ca.vertcat(geq, gin), p=uT)
        self.S = ca.nlpsol('S', 'ipopt', nlp, opts)
        # warm starts (a finer grid, or a corrected target): start the barrier small and do not
        # push the (nearly optimal) point away from the active torque constraints
        wopts = dict(opts, **{'ipopt.mu_init': 1e-6, 'ipopt.bound_push': 1e-9, 'ipopt.bound_frac': 1e-9,
                              'ipopt.slack_bound_push': 1e-9, 'ipopt.slack_bound_frac': 1e-9})
        self.Swarm = ca.nlpsol('Sw', 'ipopt', nlp, wopts) if WARM_OPTS else self.S
        # correction rounds (same grid, target moved by ~1e-9..1e-5 rad): primal-dual warm start
        mopts = dict(opts, **{'ipopt.warm_start_init_point': 'yes', 'ipopt.mu_init': 1e-8,
                              'ipopt.warm_start_bound_push': 1e-9, 'ipopt.warm_start_mult_bound_push': 1e-9,
                              'ipopt.warm_start_slack_bound_push': 1e-9,
                              'ipopt.warm_start_slack_bound_frac': 1e-9, 'ipopt.warm_start_bound_frac': 1e-9})
        self.Smult = ca.nlpsol('Sm', 'ipopt', nlp, mopts)
        self.lam = None

    def solve(self, init, target=(0, 0, 0, 1), warm=False, use_lam=False):
        Q0, QD0, A0, U0 = init
        N = self.N
        ells = np.stack([sp.quat_to_R(U0[:, i]).T @ self.L for i in range(N + 1)], 1)
        P0 = float(np.abs(np.array(F_TAU.map(N + 1)(Q0, QD0, A0, ells))).max())
        x0 = np.concatenate([Q0.ravel('F'), QD0.ravel('F'), A0.ravel('F'), U0.ravel('F'), [P0]])
        if use_lam and self.lam is not None:
            x0 = self.x_prev                      # the previous optimum itself (P included)
        lbx = -np.inf * np.ones(self.nx); lbx[-1] = 0.0
        t0 = time.time()
        S = self.Swarm if warm else self.S
        kw = {}
        if use_lam and self.lam is not None:      # multipliers of the previous solve on this grid
            S = self.Smult
            kw = dict(lam_x0=self.lam[0], lam_g0=self.lam[1])
        sol = S(x0=x0, lbx=lbx, ubx=np.inf * np.ones(self.nx), lbg=self.lbg, ubg=self.ubg,
                p=np.asarray(target, float), **kw)
        self.lam = (np.array(sol['lam_x']).ravel(), np.array(sol['lam_g']).ravel())
        wall = time.time() - t0
        st = S.stats()
        xs = np.array(sol['x']).ravel()
        self.x_prev = xs
        o = 0
        out = []
        for r in (2, 2, 2, 4):
            out.append(xs[o:o + r * (N + 1)].reshape((r, N + 1), order='F')); o += r * (N + 1)
        return (*out,), dict(status=st['return_status'], iters=int(st['iter_count']),
                             wall_s=round(wall, 1), P=float(xs[-1]),
                             warm_opts=bool(warm and WARM_OPTS), primal_dual_warm=bool(kw))


# ------------------------------------------------------------------ starts
def consistent_U(T, Q, QD, A):
    """Node orientations of a joint path by DOP853 (a consistent orientation for a start)."""
    return reintegrate(T, Q, QD, A, rtol=1e-10, atol=1e-12)[0]


def start_guess(spec, N, T=T_FALL):
    s = np.linspace(0, 1, N + 1)
    tk = s * T
    if spec == 'ref':
        spec = '45:0.75:-1'
    if spec.startswith('catflip:'):
        # catflip's whole-manoeuvre optimum: a cubic B-spline q(t), best solution of the JSON
        d = json.load(open(spec.split(':', 1)[1]))
        sol = d['outcome']['solutions'][d['outcome']['best']]
        spl = BSpline(np.array(sol['spline']['knots']), np.array(sol['spline']['coefficients']).T,
                      sol['spline']['degree'])
        Q, QD, A = spl(tk).T, spl.derivative(1)(tk).T, spl.derivative(2)(tk).T
    elif spec.startswith('npz:'):
        z = np.load(spec.split(':', 1)[1])
        Nz = z['Q'].shape[1] - 1
        Q, QD, A = path_eval(tk, T / Nz, z['Q'], z['QD'], z['A'])
    elif spec.startswith('cone:'):
        # cone: bend beta0 reached by a cosine ramp over the first 20 %, held, released over the
        # last 20 %; bend direction phi circulates `turns` times (sign: +1 / -1) with a smooth speed
        b0, turns, sign = (float(v) for v in spec.split(':')[1:])
        def qf(s):
            ramp = np.clip(s / 0.2, 0, 1); ramp2 = np.clip((1 - s) / 0.2, 0, 1)
            beta = np.radians(b0) * 0.5 * (1 - np.cos(np.pi * np.minimum(ramp, ramp2)))
            phi = sign * 2 * np.pi * turns * (s - np.sin(2 * np.pi * s) / (2 * np.pi))
            return np.stack([beta * np.cos(phi), beta * np.sin(phi)])
        e = 1e-5
        Q = qf(s); QD = (qf(s + e) - qf(s - e)) / (2 * e) / T
        A = (qf(s + e) - 2 * Q + qf(s - e)) / e**2 / T**2
    else:
        b0, turns, sign = (float(v) for v in spec.split(':'))
        ref.LSPIN[:] = L_SPIN
        Q, QD, A, _ = ref.guess(N, T, b0, turns, sign)
    Q[:, [0, -1]] = 0; QD[:, [0, -1]] = 0
    return Q, QD, A, consistent_U(T, Q, QD, A)


# ------------------------------------------------------------------ driver
def run_one(N, scheme, M, init, ncorrect, label, out_prefix, log, warm=False):
    prob = MinPeak(N, scheme, M)
    target = np.array([0.0, 0, 0, 1])
    sol, st = prob.solve(init, target, warm)
    rounds = []
    for c in range(ncorrect + 1):
        T, (Q, QD, A, U) = T_FALL, sol
        an = analyse(T, Q, QD, A, U, target)
        rec = dict(N=N, scheme=scheme + (f'x{M}' if scheme == 'rk4' else ''), start=label,
                   correction_round=c, target=target.tolist(), **st, **an)
        print(json.dumps({k: (round(v, 10) if isinstance(v, float) else v) for k, v in rec.items()
                          if k not in ('uT_dop853', 'uN_colloc')}), flush=True)
        log.write(json.dumps(rec) + '\n'); log.flush()
        rounds.append(rec)
        tag = f'{out_prefix}_N{N}' + (f'_c{c}' if ncorrect else '')
        np.savez(os.path.join(HERE, 'sols', tag + '.npz'), T=T, Q=Q, QD=QD, A=A, U=U, target=target)
        if c == ncorrect or (c > 0 and an['flip_err_rad'] < FLIP_TOL):
            break
        # defect correction: e = conj(U_N) u_exact; aim the NLP at target (x) conj(e)
        uN = U[:, -1] / np.linalg.norm(U[:, -1])
        uN *= np.sign(uN @ np.array(an['uT_dop853']))
        e = qmul(qconj(uN), np.array(an['uT_dop853']))
        target = qmul(np.array([0.0, 0, 0, 1]) * np.sign(target[3]), qconj(e))
        target /= np.linalg.norm(target)
        sol, st = prob.solve((Q, QD, A, U), target, warm=True, use_lam=True)
    return sol, rounds


if __name__ == '__main__':
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--scheme', default='rk4', choices=['rk4', 'em'])
    ap.add_argument('--M', type=int, default=2, help='RK4 substeps per interval')
    ap.add_argument('--N', default='100,200', help='grids, coarse to fine (warm start from the previous)')
    ap.add_argument('--start', default='ref')
    ap.add_argument('--correct', type=int, default=0, help='defect-correction rounds (DOP853 flip)')
    ap.add_argument('--flip-tol', type=float, default=1e-9, help='stop correcting below this flip error')
    ap.add_argument('--warm-opts', action='store_true', help='mu_init 1e-6, no bound push for warm starts')
    ap.add_argument('--print-level', type=int, default=0, help='IPOPT print level')
    ap.add_argument('--out', default='', help='file-name prefix of the saved solutions')
    ap.add_argument('--max-cpu', type=float, default=1150.0, help='IPOPT max_cpu_time per solve (s)')
    a = ap.parse_args()
    MAX_CPU = a.max_cpu
    FLIP_TOL = a.flip_tol
    WARM_OPTS = a.warm_opts
    PRINT_LEVEL = a.print_level
    os.makedirs(os.path.join(HERE, 'sols'), exist_ok=True)
    Ns = [int(v) for v in a.N.split(',')]
    prefix = a.out or f"{a.scheme}{a.M if a.scheme == 'rk4' else ''}_{a.start.split('/')[-1].replace(':', '_')}"
    with open(os.path.join(HERE, 'results_minpeak_hi.jsonl'), 'a') as log:
        init = start_guess(a.start, Ns[0])
        for i, N in enumerate(Ns):
            if i > 0:          # warm start: previous optimum's cubic resampled, orientation by DOP853
                Q, QD, A = path_eval(np.linspace(0, T_FALL, N + 1), T_FALL / Ns[i - 1], *sol[:3])
                init = (Q, QD, A, consistent_U(T_FALL, Q, QD, A))
            sol, _ = run_one(N, a.scheme, a.M, init, a.correct, a.start if i == 0 else f'warm N={Ns[i-1]}',
                             prefix, log, warm=(i > 0 or a.start.startswith('npz:')))
