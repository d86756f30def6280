#!/usr/bin/env python3
"""Independent cross-check: least fall time of the two-cylinder cat under motor limits.

Direct collocation + IPOPT (CasADi).  Self-contained: needs numpy, scipy, casadi.

Model (DESIGN.md §1-2, §9): two identical solid cylinders A (front), B (rear), m=1 kg,
l=1 m, r=0.1 m, joined on their axes by a universal joint, R_AB(q) = Rx(q1) Ry(q2).
Zero total angular momentum.  In A's frame (Omega = A's angular velocity):
    H = I_lock(q) Omega + b(q, qd) = 0,
    I_lock = I_A + R I_B R^T - mu [p]x^2,   b = R I_B R^T w_rel + mu p x pdot,
    w_rel = qd1 x + qd2 Rx(q1) y,  p = (0,0,-l/2) - R (0,0,l/2),  mu = m/2.
Reduced kinetic energy (Omega eliminated):  K(q,qd) = K0 - 1/2 b^T I_lock^-1 b with
    K0 = 1/2 w_rel^T R I_B R^T w_rel + 1/2 mu |pdot|^2,
and the joint torques are the generalised forces  tau = d/dt dK/dqd - dK/dq
(= M(q) qdd + (d(dK/dqd)/dq) qd - dK/dq).  A's world orientation: quaternion,
quat' = 1/2 quat (x) (0, Omega)  (body-frame rate, R_A' = R_A [Omega]x).

Discretisation (normalised time s in [0,1], t = s T, N intervals, h = T/N):
  * the joint acceleration qdd is piecewise LINEAR in time (values at the nodes), so
    q is an exact piecewise cubic and qd an exact piecewise quadratic: the q, qd
    continuity conditions are exact (no discretisation error in the joint path);
  * torques (and speed / envelope limits) are enforced at every node AND every
    interval midpoint, where q, qd, qdd are known exactly;
  * orientation: quat_{k+1} = quat_k (x) exp(h Omega_mid / 2)  (exponential midpoint rule,
    2nd order, norm-preserving; exp by a 6th-order Taylor series in |h Omega|^2);
  * boundary: q = qd = 0 at both ends, quat(0) = 1, quat(T) = (0, 0, 0, +-1)  i.e.
    R_A(T) = Rz(pi): twist pi about the initial spine axis, swing 0.
Every solution is re-checked by integrating the orientation with scipy solve_ivp
(DOP853, rtol 1e-10) driven by the exact piecewise-cubic q(t), and by evaluating the
torques on a fine grid (10 points per interval) to catch between-sample overshoot.

Problems:
  minpeak : fixed T = sqrt(2*10/9.8), minimise the peak |tau| (epigraph variable)
  A       : min T  s.t. |tau_j| <= 0.5
  B       : min T  s.t. |tau_j| <= 0.5, |qd_j| <= 6
  C       : min T  s.t. +-tau_j +- 0.05 qd_j <= 0.6   (DC envelope: stall 0.6 N m, free 12 rad/s)

Run:  venv/bin/python mintime.py [minpeak|A|B|C ...] [--N 200,400,800]
"""
import sys, time, json, argparse
import numpy as np
import casadi as ca
from scipy.integrate import solve_ivp

# ---------------------------------------------------------------- parameters
m, l, r = 1.0, 1.0, 0.1
mu = m / 2
Ix = m * (3 * r**2 + l**2) / 12
Iz = m * r**2 / 2
g = 9.8
T_PAPER = np.sqrt(2 * 10 / g)          # 1.4286 s
MAX_ITER = 3000


# ---------------------------------------------------------------- symbolic model
def Rx(a):
    c, s = ca.cos(a), ca.sin(a)
    return ca.vertcat(ca.horzcat(1, 0, 0), ca.horzcat(0, c, -s), ca.horzcat(0, s, c))


def Ry(a):
    c, s = ca.cos(a), ca.sin(a)
    return ca.vertcat(ca.horzcat(c, 0, s), ca.horzcat(0, 1, 0), ca.horzcat(-s, 0, c))


def skew(v):
    return ca.vertcat(ca.horzcat(0, -v[2], v[1]), ca.horzcat(v[2], 0, -v[0]),
                      ca.horzcat(-v[1], v[0], 0))


def build_model():
    q = ca.SX.sym('q', 2); qd = ca.SX.sym('qd', 2); qdd = ca.SX.sym('qdd', 2)
    I = ca.diag(ca.vertcat(Ix, Ix, Iz))
    R = Rx(q[0]) @ Ry(q[1])
    IB = R @ I @ R.T                                     # B's inertia in A's frame
    w_rel = qd[0] * ca.vertcat(1, 0, 0) + qd[1] * (Rx(q[0]) @ ca.vertcat(0, 1, 0))
    p = ca.vertcat(0, 0, -l / 2) - R @ ca.vertcat(0, 0, l / 2)
    pdot = ca.jacobian(p, q) @ qd
    Ilock = I + IB - mu * skew(p) @ skew(p)
    b = IB @ w_rel + mu * ca.cross(p, pdot)
    Om = -ca.solve(Ilock, b)                             # A's angular velocity (A frame)
    K = 0.5 * ca.dot(w_rel, IB @ w_rel) + 0.5 * mu * ca.dot(pdot, pdot) \
        - 0.5 * ca.dot(b, ca.solve(Ilock, b))            # reduced kinetic energy
    dKdqd = ca.gradient(K, qd)
    tau = ca.jacobian(dKdqd, qd) @ qdd + ca.jacobian(dKdqd, q) @ qd - ca.gradient(K, q)
    f_tau = ca.Function('tau', [q, qd, qdd], [tau])
    f_Om = ca.Function('Om', [q, qd], [Om])
    f_K = ca.Function('K', [q, qd], [K])
    return f_tau, f_Om, f_K


F_TAU, F_OM, F_K = build_model()


def qmul(a, b):
    """Hamilton product, quaternions as (w, x, y, z)."""
    return ca.vertcat(a[0]*b[0] - a[1]*b[1] - a[2]*b[2] - a[3]*b[3],
                      a[0]*b[1] + a[1]*b[0] + a[2]*b[3] - a[3]*b[2],
                      a[0]*b[2] - a[1]*b[3] + a[2]*b[0] + a[3]*b[1],
                      a[0]*b[3] + a[1]*b[2] - a[2]*b[1] + a[3]*b[0])


def qexp(v):
    """exp of rotation vector v as a unit quaternion; Taylor series in th2 = |v|^2 (smooth at 0)."""
    th2 = ca.dot(v, v)
    c = 1 - th2 / 8 + th2**2 / 384 - th2**3 / 46080
    s = 0.5 - th2 / 48 + th2**2 / 3840 - th2**3 / 645120     # sin(th/2)/th
    return ca.vertcat(c, s * v)


def interval_map(om, tau, nq=2):
    """Interval map of A's rate `om(q, qd)` and the torques `tau(q, qd, qdd)` for `nq` joint
    coordinates: exact piecewise-cubic joint path, midpoint values, quaternion step."""
    q0, qd0, a0, q1, qd1, a1 = [ca.SX.sym(n, nq) for n in ('q0', 'qd0', 'a0', 'q1', 'qd1', 'a1')]
    u0, u1 = ca.SX.sym('u0', 4), ca.SX.sym('u1', 4)
    h = ca.SX.sym('h')
    # continuity of the piecewise-cubic q with linear acceleration
    rq = q1 - (q0 + h * qd0 + h**2 / 6 * (2 * a0 + a1))
    rqd = qd1 - (qd0 + h / 2 * (a0 + a1))
    # midpoint values
    qm = q0 + qd0 * h / 2 + a0 * h**2 / 8 + (a1 - a0) * h**2 / 48
    qdm = qd0 + a0 * h / 2 + (a1 - a0) * h / 8
    am = (a0 + a1) / 2
    ru = u1 - qmul(u0, qexp(h * om(qm, qdm)))
    return ca.Function('step', [q0, qd0, a0, q1, qd1, a1, u0, u1, h],
                       [ca.vertcat(rq, rqd, ru), tau(qm, qdm, am), qdm])


def build_step():
    """The paper cat's interval map."""
    return interval_map(F_OM, F_TAU)


F_STEP = build_step()


# ---------------------------------------------------------------- numeric helpers
def path_eval(t, tk, Q, QD, A):
    """Exact piecewise-cubic q, qd, qdd at times t (arrays) from node values."""
    t = np.atleast_1d(t)
    h = tk[1] - tk[0]
    k = np.clip(np.floor(t / h).astype(int), 0, len(tk) - 2)
    tau = t - tk[k]
    a0, a1 = A[:, k], A[:, k + 1]
    q = Q[:, k] + QD[:, k] * tau + a0 * tau**2 / 2 + (a1 - a0) * tau**3 / (6 * h)
    qd = QD[:, k] + a0 * tau + (a1 - a0) * tau**2 / (2 * h)
    qdd = a0 + (a1 - a0) * tau / h
    return q, qd, qdd


def twist_swing(quat):
    w, x, y, z = quat / np.linalg.norm(quat)
    twist = 2 * np.arctan2(z, w)                # rotation about the initial spine axis
    swing = 2 * np.arctan2(np.hypot(x, y), np.hypot(w, z))   # tilt of the spine axis
    return np.degrees(twist), np.degrees(swing)


def reintegrate(T, tk, Q, QD, A, om=None):
    """Orientation by solve_ivp (DOP853, rtol 1e-10) driven by the interpolated q(t), with A's
    rate om(q, qd) (the paper cat's by default).
    Restarted on every block of intervals so the piecewise-cubic kinks do not stall it."""
    om = F_OM if om is None else om

    def rhs(t, u):
        q, qd, _ = path_eval(t, tk, Q, QD, A)
        Om = np.array(om(q[:, 0], qd[:, 0])).ravel()
        w, x, y, z = u
        ox, oy, oz = Om
        return 0.5 * np.array([-x*ox - y*oy - z*oz, w*ox + y*oz - z*oy,
                               w*oy - x*oz + z*ox, w*oz + x*oy - y*ox])
    u = np.array([1.0, 0, 0, 0])
    nb = len(tk) - 1
    for k in range(nb):   # integrate interval by interval (the path is smooth inside each)
        sol = solve_ivp(rhs, (tk[k], tk[k + 1]), u, method='DOP853', rtol=1e-10, atol=1e-12)
        u = sol.y[:, -1]
    return u


def analyse(T, Q, QD, A, U, limits):
    N = Q.shape[1] - 1
    tk = np.linspace(0, T, N + 1)
    # fine evaluation of torques and speeds (10 points per interval)
    tt = np.linspace(0, T, 10 * N + 1)
    q, qd, qdd = path_eval(tt, tk, Q, QD, A)
    tau = np.array(F_TAU.map(len(tt))(q, qd, qdd))
    # bend angle between the spine axes and the direction of B's spine in A's frame
    ez = np.stack([np.sin(q[1]), -np.sin(q[0]) * np.cos(q[1]), np.cos(q[0]) * np.cos(q[1])])
    bend = np.degrees(np.arccos(np.clip(ez[2], -1, 1)))
    sel = bend > 0.1 * bend.max()
    phi = np.unwrap(np.arctan2(ez[1][sel], ez[0][sel]))
    turns = (phi[-1] - phi[0]) / (2 * np.pi)
    uq = reintegrate(T, tk, Q, QD, A)
    tw, sw = twist_swing(uq)
    twc, swc = twist_swing(U[:, -1])
    # momentum check along the path: H = I_lock Om + b should be ~0 by construction
    res = dict(T=T, h=g * T**2 / 2, N=N,
               twist_deg=tw, swing_deg=sw, twist_colloc_deg=twc, swing_colloc_deg=swc,
               peak_tau=np.abs(tau).max(), peak_tau_j=np.abs(tau).max(1).tolist(),
               peak_tau_nodes=np.abs(np.array(F_TAU.map(N + 1)(Q, QD, A))).max(),
               peak_qd_j=np.abs(qd).max(1).tolist(), max_bend_deg=bend.max(), turns=turns)
    if limits.get('env'):
        ts, w0 = limits['env']
        res['env_max'] = float((np.abs(tau) / (ts * (1 - np.abs(qd) / w0))).max())
    # fraction of the time each limit is (nearly) active
    act = {}
    if limits.get('tau') is not None:
        act['tau'] = [float(np.mean(np.abs(tau[j]) > 0.995 * limits['tau'])) for j in range(2)]
    if limits.get('qd') is not None:
        act['qd'] = [float(np.mean(np.abs(qd[j]) > 0.995 * limits['qd'])) for j in range(2)]
    if limits.get('env'):
        ts, w0 = limits['env']
        act['env'] = [float(np.mean(np.abs(tau[j]) + ts / w0 * np.abs(qd[j]) > 0.995 * ts))
                      for j in range(2)]
    res['active_frac'] = act
    return res


# ---------------------------------------------------------------- initial guesses
def guess(N, T, beta_deg, turns, sign, phi0=0.0):
    """Bend beta(s) = beta0 sin^2(pi s) whose direction phi circulates `turns` times."""
    s = np.linspace(0, 1, N + 1)
    b0 = np.radians(beta_deg)
    # smooth circulation: phi = phi0 + 2 pi turns * (s - sin(2 pi s)/(2 pi))
    def qf(s):
        beta = b0 * np.sin(np.pi * s)**2
        phi = phi0 + sign * 2 * np.pi * turns * (s - np.sin(2 * np.pi * s) / (2 * np.pi))
        return np.stack([beta * np.cos(phi), beta * np.sin(phi)])
    e = 1e-5
    Q = qf(s)
    QD = (qf(s + e) - qf(s - e)) / (2 * e) / T
    A = (qf(s + e) - 2 * Q + qf(s - e)) / e**2 / T**2
    # orientation by the same discrete rule
    U = np.zeros((4, N + 1)); U[0, 0] = 1
    h = T / N
    for k in range(N):
        U[:, k + 1] = np.array(F_STEP(Q[:, k], QD[:, k], A[:, k], Q[:, k + 1], QD[:, k + 1],
                                      A[:, k + 1], U[:, k], np.zeros(4), h)[0][4:]).ravel() * -1
    return Q, QD, A, U


def interp_solution(sol, N):
    """Resample a solution (T, Q, QD, A, U) onto a finer grid as a warm start."""
    T, Q, QD, A, U = sol
    tk_old = np.linspace(0, T, Q.shape[1])
    tk = np.linspace(0, T, N + 1)
    q, qd, qdd = path_eval(tk, tk_old, Q, QD, A)
    Un = np.stack([np.interp(tk, tk_old, U[i]) for i in range(4)])
    Un /= np.linalg.norm(Un, axis=0)
    return T, q, qd, qdd, Un


# ---------------------------------------------------------------- the NLP
def solve(problem, N, init, T_fixed=None, max_iter=None, print_level=0):
    max_iter = max_iter or MAX_ITER
    T0, Q0, QD0, A0, U0 = init
    Q = ca.MX.sym('Q', 2, N + 1); QD = ca.MX.sym('QD', 2, N + 1)
    A = ca.MX.sym('A', 2, N + 1); U = ca.MX.sym('U', 4, N + 1)
    Tv = ca.MX.sym('T'); P = ca.MX.sym('P')
    # local copies of T per interval, chained by equalities: keeps the Lagrangian Hessian
    # banded (a single T coupling every interval makes it dense in one row/column, which
    # ruins the Hessian colouring and makes every iteration ~10x slower)
    Tk = ca.MX.sym('Tk', 1, N)
    stepm = F_STEP.map(N, 'serial')
    res, taum, qdm = stepm(Q[:, :-1], QD[:, :-1], A[:, :-1], Q[:, 1:], QD[:, 1:], A[:, 1:],
                           U[:, :-1], U[:, 1:], Tk / N)
    tauk = F_TAU.map(N + 1, 'serial')(Q, QD, A)
    TAU = ca.horzcat(tauk, taum)             # torques at nodes and midpoints
    QDall = ca.horzcat(QD, qdm)
    g_eq = [ca.vec(res), Q[:, 0], QD[:, 0], Q[:, -1], QD[:, -1], U[:, 0] - ca.DM([1, 0, 0, 0]),
            U[[0, 1, 2], -1], ca.vec(Tk[1:] - Tk[:-1]), Tk[0] - Tv]
    g_in, lb_in, ub_in = [], [], []
    lim = {}
    if problem == 'minpeak':
        # -P <= tau <= P  as  tau - P <= 0 and tau + P >= 0
        g_in += [ca.vec(TAU - P), ca.vec(TAU + P)]
        n = 2 * (2 * N + 1)
        lb_in += [-np.inf] * n + [0] * n; ub_in += [0] * n + [np.inf] * n
        f = P
        lim = dict(tau=None)
    else:
        if problem in ('A', 'B'):
            g_in += [ca.vec(TAU)]
            n = 2 * (2 * N + 1); lb_in += [-0.5] * n; ub_in += [0.5] * n
            lim['tau'] = 0.5
        if problem == 'B':
            g_in += [ca.vec(QDall)]
            n = 2 * (2 * N + 1); lb_in += [-6] * n; ub_in += [6] * n
            lim['qd'] = 6.0
        if problem == 'C':
            for s1 in (1, -1):
                for s2 in (1, -1):
                    g_in += [ca.vec(s1 * TAU + s2 * 0.05 * QDall)]
                    n = 2 * (2 * N + 1); lb_in += [-np.inf] * n; ub_in += [0.6] * n
            lim['env'] = (0.6, 12.0)
        f = Tv
    x = ca.vertcat(ca.vec(Q), ca.vec(QD), ca.vec(A), ca.vec(U), ca.vec(Tk), Tv, P)
    geq = ca.vertcat(*g_eq); gin = ca.vertcat(*g_in)
    G = ca.vertcat(geq, gin)
    lbg = np.concatenate([np.zeros(geq.shape[0]), lb_in])
    ubg = np.concatenate([np.zeros(geq.shape[0]), ub_in])
    nx = x.shape[0]
    lbx = -np.inf * np.ones(nx); ubx = np.inf * np.ones(nx)
    # T bounds / fixing, P >= 0
    if T_fixed is not None:
        lbx[-2] = ubx[-2] = T_fixed
    else:
        lbx[-2], ubx[-2] = 0.2, 5.0
        lbx[-1] = ubx[-1] = 0.0
    if problem == 'minpeak':
        lbx[-1] = 0.0
    nlp = dict(x=x, f=f, g=G)
    opts = {'ipopt.max_iter': max_iter, 'ipopt.print_level': print_level, 'print_time': 0,
            'ipopt.tol': 1e-9, 'ipopt.constr_viol_tol': 1e-10, 'ipopt.acceptable_tol': 1e-7,
            'ipopt.mu_strategy': 'adaptive', 'ipopt.linear_solver': 'mumps'}
    S = ca.nlpsol('S', 'ipopt', nlp, opts)
    T_init = T_fixed if T_fixed is not None else T0
    P0 = float(np.abs(np.array(F_TAU.map(N + 1)(Q0, QD0, A0))).max()) if problem == 'minpeak' else 0
    x0 = np.concatenate([Q0.ravel('F'), QD0.ravel('F'), A0.ravel('F'), U0.ravel('F'), T_init * np.ones(N), [T_init, P0]])
    t0 = time.time()
    sol = S(x0=x0, lbx=lbx, ubx=ubx, lbg=lbg, ubg=ubg)
    wall = time.time() - t0
    st = S.stats()
    xs = np.array(sol['x']).ravel()
    k = 0
    def take(r, c):
        nonlocal k
        v = xs[k:k + r * c].reshape((r, c), order='F'); k += r * c; return v
    Qs, QDs, As, Us = take(2, N + 1), take(2, N + 1), take(2, N + 1), take(4, N + 1)
    Ts, Ps = xs[k + N], xs[k + N + 1]
    out = analyse(Ts, Qs, QDs, As, Us, lim)
    out.update(status=st['return_status'], iters=st['iter_count'], wall_s=wall,
               obj=float(sol['f']))
    if problem == 'minpeak':
        out['P'] = Ps
    return out, (Ts, Qs, QDs, As, Us)


def fmt(o):
    keys = ['N', 'status', 'iters', 'wall_s', 'T', 'h', 'P', 'peak_tau', 'peak_tau_nodes', 'peak_tau_j',
            'peak_qd_j', 'env_max', 'twist_deg', 'swing_deg', 'twist_colloc_deg', 'max_bend_deg', 'turns',
            'active_frac']
    return {k: (round(o[k], 7) if isinstance(o[k], float) else o[k]) for k in keys if k in o}


def rescale(sol, T_new):
    """Same path in normalised time, run in T_new: speeds scale 1/T, accelerations 1/T^2."""
    T, Q, QD, A, U = sol
    return T_new, Q, QD * (T / T_new), A * (T / T_new)**2, U


def run(problem, Ns, starts, warm=None):
    """Solve `problem` from generic starts (and an optional warm start, e.g. the previous
    case's optimum), keep the best at the coarsest grid, then refine on the finer grids."""
    T_guess = T_PAPER if problem == 'minpeak' else 1.15
    Tfix = T_PAPER if problem == 'minpeak' else None
    best = None
    N0 = Ns[0]
    inits = [('beta=%g turns=%g sign=%+d' % (b, t, s), (T_guess,) + guess(N0, T_guess, b, t, s))
             for (b, t, s) in starts]
    if warm is not None:
        inits.append(('warm (previous optimum rescaled to T=%.4f)' % warm[0],
                      interp_solution(warm, N0)))
    for name, init in inits:
        o, sol = solve(problem, N0, init, T_fixed=Tfix)
        print(f"[{problem}] N={N0} start {name}:", json.dumps(fmt(o)), flush=True)
        ok = o['status'] in ('Solve_Succeeded', 'Solved_To_Acceptable_Level')
        if ok and (best is None or o['obj'] < best[0]['obj'] - 1e-9):
            best = (o, sol)
    results = [best[0]]
    sol = best[1]
    np.savez(f'/work/xcheck/sol_{problem}_N{N0}.npz', T=sol[0], Q=sol[1], QD=sol[2], A=sol[3], U=sol[4])
    for N in Ns[1:]:
        o, sol = solve(problem, N, interp_solution(sol, N), T_fixed=Tfix)
        print(f"[{problem}] refine N={N}:", json.dumps(fmt(o)), flush=True)
        results.append(o)
        np.savez(f'/work/xcheck/sol_{problem}_N{N}.npz', T=sol[0], Q=sol[1], QD=sol[2], A=sol[3], U=sol[4])
    return results, sol


if __name__ == '__main__':
    ap = argparse.ArgumentParser()
    ap.add_argument('problems', nargs='*', default=['minpeak', 'A', 'B', 'C'])
    ap.add_argument('--N', default='100,200,400')
    ap.add_argument('--starts', default='45:0.75:1,45:1:1',
                    help='generic starts beta_deg:turns:sign, comma separated ("" for none)')
    ap.add_argument('--warm', default='', help='npz solution to warm-start the first problem')
    ap.add_argument('--max-iter', type=int, default=3000)
    ap.add_argument('--no-rescale', action='store_true', help='use --warm as is (same case, finer grid)')
    a = ap.parse_args()
    MAX_ITER = a.max_iter
    Ns = [int(x) for x in a.N.split(',')]
    starts = [tuple(float(v) for v in s.split(':')) for s in a.starts.split(',') if s]
    warm = None
    if a.warm:
        z = np.load(a.warm); warm = (float(z['T']), z['Q'], z['QD'], z['A'], z['U'])
    allres = {}
    t0 = time.time()
    for p in a.problems:
        # warm start from the previous case, rescaled in time so that its peak torque
        # sits near the new limits (torque ~ 1/T^2)
        w = None
        if warm is not None and a.no_rescale:
            w = warm
        elif warm is not None:
            T, Q, QD, A, U = warm
            N = Q.shape[1] - 1
            pk = np.abs(np.array(F_TAU.map(N + 1)(Q, QD, A))).max()
            target = 0.5 if p == 'A' else (0.45 if p in ('B', 'C') else pk)
            w = rescale(warm, T * np.sqrt(pk / target)) if p != 'minpeak' else rescale(warm, T_PAPER)
        res, sol = run(p, Ns, starts, warm=w)
        allres[p] = [fmt(o) for o in res]
        warm = sol
        with open('/work/xcheck/results.json', 'a') as fh:
            fh.write(json.dumps({p: allres[p]}, default=float) + '\n')
    print('TOTAL wall', time.time() - t0)
