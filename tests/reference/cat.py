import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

m, l, r = 1.0, 1.0, 0.1
mu = m / 2
Ix = m * (3 * r**2 + l**2) / 12
Iz = m * r**2 / 2
IA_an = np.diag([Ix, Ix, Iz])
T = np.sqrt(2 * 10 / 9.8)
T1, T2, T3 = 0.2 * T, 0.6 * T, 0.2 * T


def Rx(a):
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    return np.array([[o, z, z], [z, c, -s], [z, s, c]])


def Ry(a):
    c, s = np.cos(a), np.sin(a)
    o, z = np.ones_like(a), np.zeros_like(a)
    return np.array([[c, z, s], [z, o, z], [-s, z, c]])


def skew(v):
    return np.array([[0 * v[0], -v[2], v[1]], [v[2], 0 * v[0], -v[0]], [-v[1], v[0], 0 * v[0]]])


def C_of(theta):
    Iyy = Ix * np.cos(theta / 2) ** 2 + Iz * np.sin(theta / 2) ** 2
    return 1 - Iz * np.sin(theta / 2) / Iyy


# ---------------- schedules: return q, qd, qdd (arrays of 2) -----------------
def make_schedule(theta_deg=45.0, profile="paper", path="circle", D=None):
    th = np.deg2rad(theta_deg)
    beta = np.pi - th
    if D is None:
        D = np.pi / C_of(th)

    def phi(s):
        u = s / T2
        if profile == "paper":
            return (D * (u - np.sin(np.pi * u) / np.pi), D / T2 * (1 - np.cos(np.pi * u)),
                    D / T2**2 * np.pi * np.sin(np.pi * u))
        else:
            return (D * (u - np.sin(2 * np.pi * u) / (2 * np.pi)), D / T2 * (1 - np.cos(2 * np.pi * u)),
                    D / T2**2 * 2 * np.pi * np.sin(2 * np.pi * u))

    def twist_q(f, fd, fdd):
        if path == "circle":
            q = np.array([beta * np.cos(f), beta * np.sin(f)])
            qd = np.array([-beta * np.sin(f) * fd, beta * np.cos(f) * fd])
            qdd = np.array([-beta * (np.cos(f) * fd**2 + np.sin(f) * fdd),
                            beta * (-np.sin(f) * fd**2 + np.cos(f) * fdd)])
            return q, qd, qdd
        # cone: q1 = atan2(sb cos f, cb), q2 = asin(sb sin f); derivatives via complex step in f
        assert np.cos(beta) > 0
        q = np.array([np.arctan2(np.sin(beta) * np.cos(f), np.cos(beta)), np.arcsin(np.sin(beta) * np.sin(f))])
        # analytic derivatives wrt f
        sb, cb = np.sin(beta), np.cos(beta)
        # q1 = atan(a cos f), a = sb/cb
        a = sb / cb
        d1 = -a * np.sin(f) / (1 + a**2 * np.cos(f) ** 2)
        dd1 = (-a * np.cos(f) * (1 + a**2 * np.cos(f) ** 2) - (-a * np.sin(f)) * (-2 * a**2 * np.cos(f) * np.sin(f))) / (1 + a**2 * np.cos(f) ** 2) ** 2
        w = sb * np.sin(f)
        d2 = sb * np.cos(f) / np.sqrt(1 - w**2)
        dd2 = (-sb * np.sin(f) * np.sqrt(1 - w**2) - sb * np.cos(f) * (-w * sb * np.cos(f) / np.sqrt(1 - w**2))) / (1 - w**2)
        dq = np.array([d1, d2]); ddq = np.array([dd1, dd2])
        return q, dq * fd, ddq * fd**2 + dq * fdd

    qe = twist_q(*phi(T2))[0]

    def sched(t, ph=None):
        if ph is None: ph = 0 if t <= T1 else (1 if t <= T1 + T2 else 2)
        if ph == 0:
            c = np.pi / T1
            return (np.array([beta / 2 * (1 - np.cos(c * t)), 0.0]), np.array([beta / 2 * c * np.sin(c * t), 0.0]),
                    np.array([beta / 2 * c**2 * np.cos(c * t), 0.0]))
        if ph == 1:
            return twist_q(*phi(t - T1))
        u = t - T1 - T2
        c = np.pi / T3
        return (qe * (1 + np.cos(c * u)) / 2, -qe * c * np.sin(c * u) / 2, -qe * c**2 * np.cos(c * u) / 2)

    return sched, D


# ---------------- analytic zero-momentum Omega -----------------
def geom(q, IA=IA_an, IB=IA_an):
    R = Rx(q[0]) @ Ry(q[1])
    p = np.array([0, 0, -l / 2]) - R @ np.array([0, 0, l / 2])
    return R, p


def omega_analytic(q, qd, IA=IA_an, IB=IA_an):
    R = Rx(q[0]) @ Ry(q[1])
    ez = np.array([0, 0, l / 2])
    p = np.array([0, 0, -l / 2]) - R @ ez
    wrel = qd[0] * np.array([1.0, 0, 0]) + qd[1] * (Rx(q[0]) @ np.array([0, 1.0, 0]))
    pd = -np.cross(wrel, R @ ez)  # d/dt(R ez) = wrel x (R ez)
    IBa = R @ IB @ R.T
    P = skew(p)
    Ilock = IA + IBa - mu * P @ P
    b = IBa @ wrel + mu * np.cross(p, pd)
    return -np.linalg.solve(Ilock, b)


def Mmat(q, IA=IA_an, IB=IA_an):
    """reduced kinetic metric: KE = 1/2 qd^T M qd with Omega eliminated. Works with complex q."""
    R = Rx(q[0]) @ Ry(q[1])
    ez = np.array([0, 0, l / 2])
    p = np.array([0, 0, -l / 2]) - R @ ez
    IBa = R @ IB @ R.T
    P = skew(p)
    Ilock = IA + IBa - mu * P @ P
    # columns: wrel per unit qd_i, pd per unit qd_i
    a1 = np.array([1.0, 0, 0]) + 0 * q[0]
    a2 = Rx(q[0]) @ np.array([0, 1.0, 0])
    W = np.stack([a1, a2], axis=1)                       # 3x2
    Pd = np.stack([-np.cross(a1, R @ ez), -np.cross(a2, R @ ez)], axis=1)  # 3x2
    Bm = IBa @ W + mu * P @ Pd                           # H = Ilock Om + Bm qd
    Om = -np.linalg.solve(Ilock, Bm)                     # 3x2
    # KE = 1/2 Om'IA Om + 1/2 (Om+W)' IBa (Om+W) + 1/2 mu |Om x p + Pd|^2
    V = -P @ Om + Pd   # Om x p = -p x Om
    M = Om.T @ IA @ Om + (Om + W).T @ IBa @ (Om + W) + mu * V.T @ V
    return M


def dM(q, k, h=1e-20):
    qc = np.array(q, dtype=complex)
    qc[k] += 1j * h
    return Mmat(qc).imag / h


def torque(q, qd, qdd):
    M = Mmat(q)
    dMs = [dM(q, 0), dM(q, 1)]
    tau = M @ qdd
    for i in range(2):
        for j in range(2):
            for k in range(2):
                tau[i] += (dMs[k][i, j] - 0.5 * dMs[i][j, k]) * qd[j] * qd[k]
    return tau


# ---------------- integration -----------------
def qmul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def simulate(sched, omega_fn=omega_analytic, rtol=1e-12, atol=1e-12):
    quat = np.array([1.0, 0, 0, 0])
    prev_tw = 0.0
    tw_acc = 0.0
    for (a, b) in [(0, T1), (T1, T1 + T2), (T1 + T2, T1 + T2 + T3)]:
        def f(t, y):
            q, qd, _ = sched(t)
            Om = omega_fn(q, qd)
            return 0.5 * qmul(y[:4], np.array([0.0, *Om]))
        sol = solve_ivp(f, (a, b), quat, method="DOP853", rtol=rtol, atol=atol, dense_output=True)
        # track twist continuously
        for tt in np.linspace(a, b, 400)[1:]:
            y = sol.sol(tt)
            tw = 2 * np.arctan2(y[3], y[0])
            d = (tw - prev_tw + np.pi) % (2 * np.pi) - np.pi
            tw_acc += d
            prev_tw = tw
        quat = sol.y[:, -1]
        quat = quat / np.linalg.norm(quat)
    tw = 2 * np.arctan2(quat[3], quat[0])
    d = (tw - prev_tw + np.pi) % (2 * np.pi) - np.pi
    tw_acc += d
    # swing: angle between R ez and ez
    w, x, y, z = quat
    Rz_z = 1 - 2 * (x * x + y * y)
    swing = np.arccos(np.clip(Rz_z, -1, 1))
    # more accurate swing: sin(swing/2) = sqrt(x^2+y^2)
    swing = 2 * np.arcsin(np.sqrt(x * x + y * y))
    return np.rad2deg(tw_acc), np.rad2deg(swing), quat
