"""Release with spin: exact reorientation and joint torques of the two-cylinder cat with a
nonzero total angular momentum L (world frame = A's frame at release).

Written independently of the Rust code (only DESIGN.md, the paper and the Python reference
scripts cat.py/run.py/torq.py were read).  Reuses cat.py's model and schedules.

Derivation (A's frame components throughout; R = A's world orientation, Omega = A's body rate,
w_rel = qd1 x + qd2 Rx(q1) y, p = centre of B minus centre of A, mu = m/2).  The system centre of
mass is at p/2 from A's centre: A sits at -p/2, B at +p/2.  The angular momentum about the system
centre, in A's components, is
    H = I_A Omega + R_AB I_B R_AB^T (Omega + w_rel) + m(-p/2) x (-v/2) + m(p/2) x (v/2),
    v = Omega x p + pdot  (the velocity of B's centre relative to A's, A components)
      = I_lock(q) Omega + h(q, qd),
    I_lock = I_A + R_AB I_B R_AB^T - mu [p]x^2,   h = R_AB I_B R_AB^T w_rel + mu p x pdot.
L = R H is constant (no external torque about the centre of mass; uniform gravity exerts none),
so with ell = R^T L (L in A's frame):
    Omega = I_lock^-1 (ell - h),   Rdot = R [Omega]x,   and ell' = ell x Omega.
"""
import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import minimize_scalar
from cat import (m, l, r, mu, Ix, Iz, IA_an, T, T1, T2, T3, Rx, Ry, skew, make_schedule, qmul,
                 C_of)

IA = IA_an
jA = np.array([0.0, 0.0, -l / 2])   # joint point in A
jB = np.array([0.0, 0.0, l / 2])    # joint point in B
PHASES = [(0.0, T1), (T1, T1 + T2), (T1 + T2, T1 + T2 + T3)]


def parts(q, qd, IAm=IA, IBm=IA):
    """Kinematic pieces in A's frame; works with complex q, qd."""
    RAB = Rx(q[0]) @ Ry(q[1])
    a1 = np.array([1.0, 0, 0]) + 0 * q[0]
    a2 = Rx(q[0]) @ np.array([0.0, 1, 0])
    W = np.stack([a1, a2], axis=1)                 # w_rel = W qd
    rb = RAB @ jB
    p = jA - rb
    Pd = np.stack([-np.cross(a1, rb), -np.cross(a2, rb)], axis=1)   # dp/dq (pdot = Pd qd)
    IBa = RAB @ IBm @ RAB.T
    P = skew(p)
    Ilock = IAm + IBa - mu * P @ P
    Bm = IBa @ W + mu * P @ Pd                     # h = Bm qd
    return dict(RAB=RAB, a1=a1, a2=a2, W=W, wrel=W @ qd, p=p, Pd=Pd, pd=Pd @ qd, IBa=IBa,
                Ilock=Ilock, Bm=Bm, h=Bm @ qd)


def quat_to_R(y):
    w, x, yy, z = y / np.linalg.norm(y)
    return np.array([[1 - 2 * (yy * yy + z * z), 2 * (x * yy - w * z), 2 * (x * z + w * yy)],
                     [2 * (x * yy + w * z), 1 - 2 * (x * x + z * z), 2 * (yy * z - w * x)],
                     [2 * (x * z - w * yy), 2 * (yy * z + w * x), 1 - 2 * (x * x + yy * yy)]])


def omega_spin(q, qd, ell):
    d = parts(q, qd)
    return np.linalg.solve(d['Ilock'], ell - d['h'])


def twist_swing_deg(y):
    w, x, yy, z = y / np.linalg.norm(y)
    return np.degrees(2 * np.arctan2(z, w)), np.degrees(2 * np.arctan2(np.hypot(x, yy), np.hypot(w, z)))


class Run:
    """Integrate A's orientation for schedule `sched` and momentum L.
    form='quat': 4 states (quaternion), ell = R(quat)^T L;
    form='quat+ell': 7 states, ell integrated by ell' = ell x Omega (a redundant check)."""

    def __init__(self, sched, L, rtol=1e-13, atol=1e-13, form='quat', nsamp=4000, rigid=False):
        self.sched, self.L = sched, np.asarray(L, float)
        self.sols = []
        y = np.array([1.0, 0, 0, 0]) if form == 'quat' else np.concatenate([[1.0, 0, 0, 0], self.L])
        prev, acc = 0.0, 0.0
        self.nfev = 0
        for ph, (a, b) in enumerate(PHASES):
            def f(t, yv, ph=ph):
                if rigid:
                    q, qd = np.zeros(2), np.zeros(2)
                else:
                    q, qd, _ = sched(t, ph)
                if form == 'quat':
                    ell = quat_to_R(yv[:4]).T @ self.L
                    Om = omega_spin(q, qd, ell)
                    return 0.5 * qmul(yv, np.array([0.0, *Om]))
                ell = yv[4:]
                Om = omega_spin(q, qd, ell)
                return np.concatenate([0.5 * qmul(yv[:4], np.array([0.0, *Om])), np.cross(ell, Om)])
            sol = solve_ivp(f, (a, b), y, method='DOP853', rtol=rtol, atol=atol, dense_output=True)
            assert sol.success, sol.message
            self.nfev += sol.nfev
            self.sols.append(sol)
            # continue the twist through +-pi
            for tt in np.linspace(a, b, nsamp)[1:]:
                yq = sol.sol(tt)[:4]
                tw = 2 * np.arctan2(yq[3], yq[0])
                acc += (tw - prev + np.pi) % (2 * np.pi) - np.pi
                prev = tw
            y = sol.y[:, -1].copy()
            y[:4] /= np.linalg.norm(y[:4])
        tw = 2 * np.arctan2(y[3], y[0])
        acc += (tw - prev + np.pi) % (2 * np.pi) - np.pi
        self.quat = y[:4]
        self.twist = np.degrees(acc)
        self.swing = twist_swing_deg(y[:4])[1]
        self.ell_end = y[4:] if form != 'quat' else quat_to_R(y[:4]).T @ self.L

    def R_at(self, t, ph):
        return quat_to_R(self.sols[ph].sol(t)[:4])


# ------------------------------------------------------------------ torques
def world_state(sched, L, t, R, ph):
    """World-frame momenta/velocities; R may be complex (complex step in time)."""
    q, qd, _ = sched(t, ph)
    d = parts(q, qd)
    ell = R.T @ L
    Om = np.linalg.solve(d['Ilock'], ell - d['h'])
    HA = R @ (IA @ Om)                               # A's momentum about its centre (world)
    HB = R @ (d['IBa'] @ (Om + d['wrel']))           # B's momentum about its centre (world)
    vB = R @ (np.cross(Om, d['p'] / 2) + d['pd'] / 2)  # B's centre velocity rel. system centre
    return dict(HA=HA, HB=HB, vB=vB, Om=Om, d=d, q=q, qd=qd)


def cs_dt(fun, sched, L, t, R, ph, hh=1e-30):
    """Complex-step time derivative of world_state quantities: t -> t + i h, R -> R + i h R[Om]x."""
    s0 = world_state(sched, L, t, R, ph)
    Rc = R + 1j * hh * (R @ skew(s0['Om']))
    sc = world_state(sched, L, t + 1j * hh, Rc, ph)
    return s0, {k: np.imag(fun(sc, k)) / hh for k in ('HA', 'HB', 'vB')}


def torque_NE(sched, L, t, R, ph):
    """Newton-Euler on B (and on A: action = reaction). Returns (tau_B_side, tau_A_side)."""
    s0, dd = cs_dt(lambda s, k: s[k], sched, L, t, R, ph)
    d = s0['d']
    aB = dd['vB']
    F = m * aB                                        # joint force on B
    tJ_B = dd['HB'] - np.cross(R @ (jA - d['p']), F)
    tJ_A = -dd['HA'] - np.cross(R @ jA, F)
    ax = np.stack([R @ d['a1'], R @ d['a2']])
    return ax @ tJ_B, ax @ tJ_A


def Kfull(q, Om, qd):
    d = parts(q, qd)
    wB = Om + d['wrel']
    v = np.cross(Om, d['p']) + d['pd']
    return 0.5 * Om @ IA @ Om + 0.5 * wB @ d['IBa'] @ wB + 0.5 * mu * v @ v


def torque_lagrange(sched, L, t, R, ph, hh=1e-30):
    """Euler-Lagrange for q with A's body rate as quasi-velocity:
    tau = d/dt dK/dqd - dK/dq |_(Omega, qd fixed),  K = K(q, Omega, qd)."""
    def pq(tt, RR):
        q, qd, _ = sched(tt, ph)
        d = parts(q, qd)
        Om = np.linalg.solve(d['Ilock'], RR.T @ L - d['h'])
        return d['W'].T @ d['IBa'] @ (Om + d['wrel']) + mu * d['Pd'].T @ (np.cross(Om, d['p']) + d['pd']), Om
    p0, Om = pq(t, R)
    pc, _ = pq(t + 1j * hh, R + 1j * hh * (R @ skew(Om)))
    dp = np.imag(pc) / hh
    q, qd, _ = sched(t, ph)
    dKq = np.array([np.imag(Kfull(q + 1j * hh * np.eye(2)[i], Om, qd)) / hh for i in range(2)])
    return dp - dKq


def vee(S):
    return np.array([S[2, 1] - S[1, 2], S[0, 2] - S[2, 0], S[1, 0] - S[0, 1]]) / 2


C1 = np.array([1 / 280, -4 / 105, 1 / 5, -4 / 5, 0, 4 / 5, -1 / 5, 4 / 105, -1 / 280])
C2 = np.array([-1 / 560, 8 / 315, -1 / 5, 8 / 5, -205 / 72, 8 / 5, -1 / 5, 8 / 315, -1 / 560])


def torque_fd(run, L, t, ph, dt=2e-3):
    """Newton-Euler on B from real 8th-order central differences of the integrated motion only
    (dense output of R and the schedule's q(t)): B's world orientation R_B = R R_AB and B's centre
    r_B = R p/2 are differenced; omega = vee(Rdot R^T), alpha = vee(skew(Rddot R^T)),
    dH_B/dt = I_w alpha + omega x I_w omega.  No rate formula is used."""
    ks = range(-4, 5)
    RB, rB = [], []
    for k in ks:
        tt = t + k * dt
        Rw = run.R_at(tt, ph)
        q = run.sched(tt, ph)[0]
        d = parts(q, np.zeros(2))
        RB.append(Rw @ d['RAB']); rB.append(Rw @ (d['p'] / 2))
    RB, rB = np.array(RB), np.array(rB)
    R0 = RB[4]
    Rd = np.tensordot(C1, RB, 1) / dt
    Rdd = np.tensordot(C2, RB, 1) / dt**2
    w = vee(Rd @ R0.T)
    al = vee(Rdd @ R0.T)
    Iw = R0 @ IA @ R0.T
    dHB = Iw @ al + np.cross(w, Iw @ w)
    aB = C2 @ rB / dt**2
    Rw = run.R_at(t, ph)
    d = parts(run.sched(t, ph)[0], np.zeros(2))
    tJ = dHB - np.cross(Rw @ (jA - d['p']), m * aB)
    return np.array([Rw @ d['a1'] @ tJ, Rw @ d['a2'] @ tJ])


def momentum_direct(run, L, t, ph, dt=2e-3):
    """Total angular momentum about the system centre from the two bodies' own velocities,
    obtained by differencing the integrated motion (world frame)."""
    tot = np.zeros(3)
    for body in ('A', 'B'):
        Rs, rs = [], []
        for k in range(-4, 5):
            tt = t + k * dt
            Rw = run.R_at(tt, ph)
            d = parts(run.sched(tt, ph)[0], np.zeros(2))
            if body == 'A':
                Rs.append(Rw); rs.append(Rw @ (-d['p'] / 2))
            else:
                Rs.append(Rw @ d['RAB']); rs.append(Rw @ (d['p'] / 2))
        Rs, rs = np.array(Rs), np.array(rs)
        w = vee(np.tensordot(C1, Rs, 1) / dt @ Rs[4].T)
        v = C1 @ rs / dt
        tot += Rs[4] @ IA @ Rs[4].T @ w + m * np.cross(rs[4], v)
    return tot


def momentum_bodies(sched, L, t, R, ph):
    """Same sum, but from the rate formula's Omega (checks the I_lock / h algebra)."""
    s = world_state(sched, L, t, R, ph)
    d = s['d']
    Om = s['Om']
    wA = R @ Om; wB = R @ (Om + d['wrel'])
    rA = R @ (-d['p'] / 2); rB = -rA
    vB = s['vB']; vA = -vB
    RBw = R @ d['RAB']
    return R @ IA @ R.T @ wA + RBw @ IA @ RBw.T @ wB + m * np.cross(rA, vA) + m * np.cross(rB, vB)


def peak_torques(run, L, ngrid=4001, which=torque_NE):
    """Per phase, per joint: max |tau_i| (grid + bounded refinement + phase endpoints)."""
    out = []
    for ph, (a, b) in enumerate(PHASES):
        def tau(t):
            return which(run.sched, L, t, run.R_at(t, ph), ph)[0] if which is torque_NE else \
                which(run.sched, L, t, run.R_at(t, ph), ph)
        tt = np.linspace(a, b, ngrid)
        taus = np.array([tau(t) for t in tt])
        row = []
        for k in range(2):
            i = int(np.argmax(np.abs(taus[:, k])))
            best = (abs(taus[i, k]), tt[i])
            lo, hi = tt[max(i - 1, 0)], tt[min(i + 1, ngrid - 1)]
            res = minimize_scalar(lambda s: -abs(tau(s)[k]), bounds=(lo, hi), method='bounded',
                                  options=dict(xatol=1e-12))
            if -res.fun > best[0]:
                best = (-res.fun, res.x)
            row.append(best)
        out.append(row)
    return out
