#!/usr/bin/env python3
"""Independent cross-check of catflip's cat models (no-twist joint, unequal halves).

Derived from DESIGN.md (sections 1-3, 10) and the paper only, by a session that read no catflip
source (2026-12-03). Run from the repository root after `cargo build --release`:
/tmp/xcheck-venv/bin/python tests/reference/models.py [--quick]

Conventions (DESIGN.md): body frames at each half's centre, z along the spine toward the head;
joint point (0,0,-l_A/2) in A and (0,0,+l_B/2) in B; R_AB = B's attitude in A's frame;
universal R_AB = Rx(q1) Ry(q2); no-twist R_AB = exp([q1, q2, 0]x).
Everything below is in A's body frame unless said otherwise.
"""
import json
import math
import os
import subprocess
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, minimize_scalar

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
CATFLIP = os.path.join(ROOT, "target", "release", "catflip")
PROBLEMS = os.path.join(ROOT, "problems")


# ----------------------------------------------------------------------------- small algebra
def hat(v):
    """[v]x for v of shape (..., 3)."""
    z = np.zeros(v.shape[:-1])
    return np.stack([
        np.stack([z, -v[..., 2], v[..., 1]], -1),
        np.stack([v[..., 2], z, -v[..., 0]], -1),
        np.stack([-v[..., 1], v[..., 0], z], -1)], -2)


def vee_skew(M):
    """vee of the skew part of M (..., 3, 3)."""
    return 0.5 * np.stack([M[..., 2, 1] - M[..., 1, 2],
                           M[..., 0, 2] - M[..., 2, 0],
                           M[..., 1, 0] - M[..., 0, 1]], -1)


def mv(M, v):
    return np.einsum("...ij,...j->...i", M, v)


def T(M):
    return np.swapaxes(M, -1, -2)


def cylinder_inertia(m, l, r):
    ixx = m * (3 * r * r + l * l) / 12.0
    izz = m * r * r / 2.0
    return np.diag([ixx, ixx, izz])


# series for a(s) = sin(sqrt s)/sqrt s and b(s) = (1 - cos sqrt s)/s and their s-derivatives
_NS = 40
_ka = np.array([(-1.0) ** k / math.factorial(2 * k + 1) for k in range(_NS)])
_kb = np.array([(-1.0) ** k / math.factorial(2 * k + 2) for k in range(_NS)])
_k = np.arange(_NS)


def _series(c, s):
    s = np.asarray(s)[..., None]
    p0 = np.sum(c * s ** _k, -1)
    p1 = np.sum((c * _k)[1:] * s ** (_k[1:] - 1), -1)
    p2 = np.sum((c * _k * (_k - 1))[2:] * s ** (_k[2:] - 2), -1)
    return p0, p1, p2


# ----------------------------------------------------------------------------- the cat
class Cat:
    def __init__(self, mA, lA, rA, mB, lB, rB, joint):
        self.mA, self.lA, self.rA, self.mB, self.lB, self.rB = mA, lA, rA, mB, lB, rB
        self.joint = joint
        self.IA = cylinder_inertia(mA, lA, rA)
        self.IB = cylinder_inertia(mB, lB, rB)
        self.M = mA + mB
        self.mu = mA * mB / self.M
        self.jA = np.array([0.0, 0.0, -lA / 2])
        self.jB = np.array([0.0, 0.0, lB / 2])

    # joint rotation and its first two time derivatives from (q, qd, qdd), shape (N, 2)
    def rotation(self, q, qd, qdd):
        N = q.shape[0]
        if self.joint == "universal":
            a, b = q[:, 0], q[:, 1]
            ad, bd = qd[:, 0], qd[:, 1]
            add, bdd = qdd[:, 0], qdd[:, 1]
            ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
            o, z = np.ones(N), np.zeros(N)
            Rx = np.stack([np.stack([o, z, z], -1), np.stack([z, ca, -sa], -1), np.stack([z, sa, ca], -1)], -2)
            Rx1 = np.stack([np.stack([z, z, z], -1), np.stack([z, -sa, -ca], -1), np.stack([z, ca, -sa], -1)], -2)
            Rx2 = np.stack([np.stack([z, z, z], -1), np.stack([z, -ca, sa], -1), np.stack([z, -sa, -ca], -1)], -2)
            Ry = np.stack([np.stack([cb, z, sb], -1), np.stack([z, o, z], -1), np.stack([-sb, z, cb], -1)], -2)
            Ry1 = np.stack([np.stack([-sb, z, cb], -1), np.stack([z, z, z], -1), np.stack([-cb, z, -sb], -1)], -2)
            Ry2 = np.stack([np.stack([-cb, z, -sb], -1), np.stack([z, z, z], -1), np.stack([sb, z, -cb], -1)], -2)
            X, Xd = Rx, Rx1 * ad[:, None, None]
            Xdd = Rx2 * (ad ** 2)[:, None, None] + Rx1 * add[:, None, None]
            Y, Yd = Ry, Ry1 * bd[:, None, None]
            Ydd = Ry2 * (bd ** 2)[:, None, None] + Ry1 * bdd[:, None, None]
            R = X @ Y
            Rd = Xd @ Y + X @ Yd
            Rdd = Xdd @ Y + 2 * Xd @ Yd + X @ Ydd
            return R, Rd, Rdd
        elif self.joint == "spherical":
            # exp([q1, q2, 0]x) Rz(q3): the no-twist joint's bend, then the relative twist.
            S, Sd, Sdd = self._no_twist(q[:, :2], qd[:, :2], qdd[:, :2])
            c, s = np.cos(q[:, 2]), np.sin(q[:, 2])
            o, z = np.ones(N), np.zeros(N)
            Z = np.stack([np.stack([c, -s, z], -1), np.stack([s, c, z], -1), np.stack([z, z, o], -1)], -2)
            Z1 = np.stack([np.stack([-s, -c, z], -1), np.stack([c, -s, z], -1), np.stack([z, z, z], -1)], -2)
            Z2 = np.stack([np.stack([-c, s, z], -1), np.stack([-s, -c, z], -1), np.stack([z, z, z], -1)], -2)
            e = lambda x: x[:, None, None]
            Zd = Z1 * e(qd[:, 2])
            Zdd = Z2 * e(qd[:, 2] ** 2) + Z1 * e(qdd[:, 2])
            return S @ Z, Sd @ Z + S @ Zd, Sdd @ Z + 2 * Sd @ Zd + S @ Zdd
        elif self.joint == "no-twist":
            return self._no_twist(q, qd, qdd)
        raise ValueError(self.joint)

    def _no_twist(self, q, qd, qdd):
        """exp([q1, q2, 0]x) and its first two time derivatives."""
        N = q.shape[0]
        z = np.zeros((N, 1))
        v, vd, vdd = (np.hstack([x, z]) for x in (q, qd, qdd))
        s = np.sum(v * v, -1)
        sd = 2 * np.sum(v * vd, -1)
        sdd = 2 * (np.sum(vd * vd, -1) + np.sum(v * vdd, -1))
        A0, A1, A2 = _series(_ka, s)
        B0, B1, B2 = _series(_kb, s)
        a, ad, add = A0, A1 * sd, A2 * sd ** 2 + A1 * sdd
        b, bd, bdd = B0, B1 * sd, B2 * sd ** 2 + B1 * sdd
        K, Kd, Kdd = hat(v), hat(vd), hat(vdd)
        K2 = K @ K
        K2d = Kd @ K + K @ Kd
        K2dd = Kdd @ K + 2 * Kd @ Kd + K @ Kdd
        e = lambda x: x[:, None, None]
        R = np.eye(3) + e(a) * K + e(b) * K2
        Rd = e(ad) * K + e(a) * Kd + e(bd) * K2 + e(b) * K2d
        Rdd = e(add) * K + 2 * e(ad) * Kd + e(a) * Kdd + e(bdd) * K2 + 2 * e(bd) * K2d + e(b) * K2dd
        return R, Rd, Rdd

    def motor_axes(self, q):
        """joint axes in A's frame, shape (N, 2, 3), or (N, 3, 3) on the spherical joint, whose
        third motor acts about B's spine (DESIGN.md section 10)."""
        N = q.shape[0]
        ax1 = np.tile([1.0, 0.0, 0.0], (N, 1))
        if self.joint == "universal":
            ax2 = np.stack([np.zeros(N), np.cos(q[:, 0]), np.sin(q[:, 0])], -1)   # Rx(q1) y
        else:
            ax2 = np.tile([0.0, 1.0, 0.0], (N, 1))
        if self.joint == "spherical":
            R, _, _ = self.rotation(q, np.zeros_like(q), np.zeros_like(q))
            return np.stack([ax1, ax2, R[:, :, 2]], 1)
        return np.stack([ax1, ax2], 1)

    def state(self, q, qd, qdd, check=False):
        """Zero-momentum base motion and joint torques. Returns dict of arrays."""
        R, Rd, Rdd = self.rotation(q, qd, qdd)
        w_rel = vee_skew(Rd @ T(R))                         # B's rate relative to A, in A
        wd_rel = vee_skew(Rdd @ T(R) + Rd @ T(Rd))          # its A-frame derivative
        ez = np.array([0.0, 0.0, 1.0])
        lb2 = self.lB / 2
        d = self.jA - lb2 * mv(R, ez)                       # B's centre - A's centre
        dd = -lb2 * mv(Rd, ez)
        ddd = -lb2 * mv(Rdd, ez)
        J = R @ self.IB @ T(R)
        Jd = Rd @ self.IB @ T(R) + R @ self.IB @ T(Rd)
        Hd, Hdd = hat(d), hat(dd)
        mu = self.mu
        Ilock = self.IA + J - mu * Hd @ Hd
        Ilock_d = Jd - mu * (Hdd @ Hd + Hd @ Hdd)
        h = mv(J, w_rel) + mu * np.cross(d, dd)
        h_d = mv(Jd, w_rel) + mv(J, wd_rel) + mu * np.cross(d, ddd)
        Om = -np.linalg.solve(Ilock, h[..., None])[..., 0]
        Omd = -np.linalg.solve(Ilock, (mv(Ilock_d, Om) + h_d)[..., None])[..., 0]
        # Newton-Euler on B (components in A's frame at the instant, inertial derivatives)
        wB = Om + w_rel
        aB = Omd + wd_rel + np.cross(Om, w_rel)
        kB = self.mA / self.M
        r, rd, rdd = kB * d, kB * dd, kB * ddd               # B's centre from the system's centre
        acc = rdd + 2 * np.cross(Om, rd) + np.cross(Omd, r) + np.cross(Om, np.cross(Om, r))
        F = self.mB * acc                                   # force from A on B at the joint
        tau_cm = mv(J, aB) + np.cross(wB, mv(J, wB))
        rho = lb2 * mv(R, ez)                               # joint point from B's centre
        tauJ = tau_cm - np.cross(rho, F)                    # couple the joint transmits to B
        axes = self.motor_axes(q)
        tau = np.einsum("nij,nj->ni", axes, tauJ)
        out = dict(Om=Om, Omd=Omd, tau=tau, tauJ=tauJ, R=R)
        if check:
            # A's side: I_A Omd + Om x I_A Om = -tauJ + jA x (-F)
            lhs = mv(np.broadcast_to(self.IA, J.shape), Omd) + np.cross(Om, mv(np.broadcast_to(self.IA, J.shape), Om))
            rhs = -tauJ + np.cross(np.broadcast_to(self.jA, F.shape), -F)
            out["reaction_residual"] = np.max(np.abs(lhs - rhs))
            out["reaction_scale"] = np.max(np.abs(tauJ))
            # momentum from the bodies one by one (about the system's centre, in A)
            rA, rAd = -(self.mB / self.M) * d, -(self.mB / self.M) * dd
            vA = rAd + np.cross(Om, rA)
            vB = rd + np.cross(Om, r)
            Hsum = (mv(np.broadcast_to(self.IA, J.shape), Om) + self.mA * np.cross(rA, vA)
                    + mv(J, wB) + self.mB * np.cross(r, vB))
            out["momentum"] = np.max(np.abs(Hsum))
            out["w_rel"], out["wd_rel"] = w_rel, wd_rel
        return out


# ----------------------------------------------------------------------------- schedule
class Schedule:
    def __init__(self, T, theta_deg, profile, circulation, path, joint, phases=(0.2, 0.6, 0.2),
                 cone_branch="continuous"):
        self.Tfall = T
        self.T1, self.T2, self.T3 = (f * T for f in phases)
        self.theta = math.radians(theta_deg)
        self.beta = math.pi - self.theta
        self.profile = profile
        self.Phi = circulation
        # on the no-twist joint the joint circle is its own cone
        self.path = "joint-circle" if joint == "no-twist" else path
        self.cone_branch = cone_branch
        if self.path == "cone" and abs(math.cos(self.beta)) < math.sin(math.radians(5.0)):
            raise ValueError("cone path: gimbal lock (bend within 5 deg of 90)")
        self.qend = self._twist(np.array([self.T2]))[0][0]

    def _phi(self, s):
        T2, Phi = self.T2, self.Phi
        w0 = Phi / T2
        if self.profile == "paper-cosine":
            k = math.pi / T2
        elif self.profile == "cycloidal":
            k = 2 * math.pi / T2
        else:
            raise ValueError(self.profile)
        phi = w0 * (s - np.sin(k * s) / k)
        phid = w0 * (1 - np.cos(k * s))
        phidd = w0 * k * np.sin(k * s)
        return phi, phid, phidd

    def _twist(self, s):
        phi, pd, pdd = self._phi(s)
        b = self.beta
        if self.path == "joint-circle":
            c, sn = np.cos(phi), np.sin(phi)
            q = np.stack([b * c, b * sn], -1)
            qd = np.stack([-b * sn * pd, b * c * pd], -1)
            qdd = np.stack([-b * sn * pdd - b * c * pd ** 2, b * c * pdd - b * sn * pd ** 2], -1)
            return q, qd, qdd
        # cone through Rx(q1) Ry(q2): B's spine Rx(q1)Ry(q2) z = (sin q2, -sin q1 cos q2, cos q1 cos q2)
        # = (sin b sin phi, -sin b cos phi, cos b)  =>  q2 = asin(sin b sin phi),
        # q1 = atan2(sin b cos phi, cos b) on the branch through (b, 0) at phi = 0.
        sb, cb = math.sin(b), math.cos(b)
        y, y1, y2 = sb * np.cos(phi), -sb * np.sin(phi), -sb * np.cos(phi)
        q1 = np.arctan2(y, cb)
        if self.cone_branch == "continuous" and cb < 0:
            q1 = np.mod(q1, 2 * math.pi)               # stays in (pi/2, 3pi/2), continuous
        den = cb * cb + y * y
        q1p = cb * y1 / den
        q1pp = cb * y2 / den - 2 * cb * y * y1 ** 2 / den ** 2
        u, u1, u2 = sb * np.sin(phi), sb * np.cos(phi), -sb * np.sin(phi)
        sq = np.sqrt(1 - u * u)
        q2 = np.arcsin(u)
        q2p = u1 / sq
        q2pp = u2 / sq + u * u1 ** 2 / sq ** 3
        q = np.stack([q1, q2], -1)
        qd = np.stack([q1p * pd, q2p * pd], -1)
        qdd = np.stack([q1pp * pd ** 2 + q1p * pdd, q2pp * pd ** 2 + q2p * pdd], -1)
        return q, qd, qdd

    def phase(self, name, t):
        """(q, qd, qdd) at local times t of a phase."""
        t = np.atleast_1d(np.asarray(t, float))
        z = np.zeros_like(t)
        if name == "bend":
            k = math.pi / self.T1
            b2 = self.beta / 2
            return (np.stack([b2 * (1 - np.cos(k * t)), z], -1),
                    np.stack([b2 * k * np.sin(k * t), z], -1),
                    np.stack([b2 * k * k * np.cos(k * t), z], -1))
        if name == "twist":
            return self._twist(t)
        if name == "unbend":
            k = math.pi / self.T3
            f = (1 + np.cos(k * t)) / 2
            fd = -k * np.sin(k * t) / 2
            fdd = -k * k * np.cos(k * t) / 2
            qe = self.qend
            return f[:, None] * qe, fd[:, None] * qe, fdd[:, None] * qe
        raise ValueError(name)

    def durations(self):
        return [("bend", self.T1), ("twist", self.T2), ("unbend", self.T3)]


# ----------------------------------------------------------------------------- attitude
def qmul(p, q):
    w1, x1, y1, z1 = p
    w2, x2, y2, z2 = q
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2,
                     w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2,
                     w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def swing_twist(qf, psi_hist):
    """twist (signed, continued) and swing of A's final attitude about its initial z."""
    w, x, y, z = qf
    swing = 2 * math.atan2(math.hypot(x, y), math.hypot(w, z))
    psi = np.unwrap(np.array(psi_hist))
    return 2 * psi[-1], swing


def integrate_dop853(cat, sch, rtol=1e-13, atol=1e-13, nout=401):
    """A's attitude quaternion (world from A), q' = 1/2 q (0, Omega), phase by phase."""
    qa = np.array([1.0, 0.0, 0.0, 0.0])
    psi = [0.0]
    nfev = 0
    for name, dur in sch.durations():
        def rhs(t, y):
            Om = cat.state(*sch.phase(name, t))["Om"][0]
            return 0.5 * qmul(y, np.array([0.0, *Om]))
        sol = solve_ivp(rhs, (0.0, dur), qa, method="DOP853", rtol=rtol, atol=atol,
                        dense_output=True)
        nfev += sol.nfev
        ys = sol.sol(np.linspace(0, dur, nout))
        psi.extend(np.arctan2(ys[3], ys[0])[1:])
        qa = sol.y[:, -1]
        qa = qa / np.linalg.norm(qa)
    tw, sw = swing_twist(qa, psi)
    return dict(twist=tw, swing=sw, q=qa, nfev=nfev)


def integrate_rk4(cat, sch, n_per_phase):
    """fixed-step classical RK4 with Omega(t) precomputed (it depends on time only)."""
    qa = np.array([1.0, 0.0, 0.0, 0.0])
    psi = [0.0]
    for name, dur in sch.durations():
        h = dur / n_per_phase
        tt = np.linspace(0, dur, 2 * n_per_phase + 1)
        Om = cat.state(*sch.phase(name, tt))["Om"]
        w, x, y, z = qa
        for k in range(n_per_phase):
            o0, o1, o2 = Om[2 * k], Om[2 * k + 1], Om[2 * k + 2]

            def f(w, x, y, z, o):
                a, b, c = o
                return (0.5 * (-x * a - y * b - z * c), 0.5 * (w * a + y * c - z * b),
                        0.5 * (w * b - x * c + z * a), 0.5 * (w * c + x * b - y * a))
            k1 = f(w, x, y, z, o0)
            k2 = f(w + h / 2 * k1[0], x + h / 2 * k1[1], y + h / 2 * k1[2], z + h / 2 * k1[3], o1)
            k3 = f(w + h / 2 * k2[0], x + h / 2 * k2[1], y + h / 2 * k2[2], z + h / 2 * k2[3], o1)
            k4 = f(w + h * k3[0], x + h * k3[1], y + h * k3[2], z + h * k3[3], o2)
            w += h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
            x += h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
            y += h / 6 * (k1[2] + 2 * k2[2] + 2 * k3[2] + k4[2])
            z += h / 6 * (k1[3] + 2 * k2[3] + 2 * k3[3] + k4[3])
            if k % 50 == 0:
                psi.append(math.atan2(z, w))
        nrm = math.sqrt(w * w + x * x + y * y + z * z)
        qa = np.array([w, x, y, z]) / nrm
        psi.append(math.atan2(qa[3], qa[0]))
    tw, sw = swing_twist(qa, psi)
    return dict(twist=tw, swing=sw, q=qa)


# ----------------------------------------------------------------------------- peaks
def peaks(cat, sch, n=20001, refine=True):
    res = {}
    checks = dict(reaction=0.0, momentum=0.0)
    for name, dur in sch.durations():
        tt = np.linspace(0, dur, n)
        st = cat.state(*sch.phase(name, tt), check=True)
        checks["reaction"] = max(checks["reaction"], st["reaction_residual"] / max(st["reaction_scale"], 1e-300))
        checks["momentum"] = max(checks["momentum"], st["momentum"])
        a = np.abs(st["tau"])
        vals = []
        for i in range(2):
            k = int(np.argmax(a[:, i]))
            dense = a[k, i]
            best = dense
            if refine and 0 < k < n - 1:
                fn = lambda t: -abs(cat.state(*sch.phase(name, t))["tau"][0, i])
                r = minimize_scalar(fn, bounds=(tt[k - 1], tt[k + 1]), method="bounded",
                                    options=dict(xatol=1e-14 * dur, maxiter=500))
                best = max(dense, -r.fun)
            vals.append((dense, best))
        res[name] = vals
    return res, checks


def impulse_at_unbend(cat, sch):
    """The paper-cosine profile ends at 2 w0: the joint rates jump to 0 when unbending starts.
    Angular impulse the joint transmits to B about the joint point, on the motor axes:
    dH_B(cm) - rho x dP_B (positions fixed through the impulse; Omega jumps with q-dot)."""
    q, qd, qdd = sch.phase("twist", np.array([sch.T2]))
    st = cat.state(q, qd, qdd, check=True)
    R = st["R"][0]
    Om, w_rel = st["Om"][0], st["w_rel"][0]
    ez = np.array([0.0, 0.0, 1.0])
    lb2 = cat.lB / 2
    Rd = cat.rotation(q, qd, qdd)[1][0]
    d = cat.jA - lb2 * R @ ez
    dd = -lb2 * Rd @ ez
    kB = cat.mA / cat.M
    vB = kB * dd + np.cross(Om, kB * d)
    J = R @ cat.IB @ R.T
    dH = -(J @ (Om + w_rel))
    dP = -cat.mB * vB
    rho = lb2 * R @ ez
    imp = dH - np.cross(rho, dP)
    axes = cat.motor_axes(q)[0]
    out = dict(rates_before=qd[0].tolist(), impulse=(axes @ imp).tolist(), Omega_before=Om.tolist())
    if cat.joint == "no-twist":
        # for comparison only: the generalised impulse conjugate to the rotation-vector rates,
        # J_l(q)^T . impulse (J_l the left Jacobian of exp, w_rel = J_l(q) q-dot)
        v = np.array([*q[0], 0.0])
        th = np.linalg.norm(v)
        K = hat(v)
        Jl = np.eye(3) + (1 - math.cos(th)) / th ** 2 * K + (th - math.sin(th)) / th ** 3 * K @ K
        out["impulse_generalized"] = (Jl.T @ imp)[:2].tolist()
    return out


# ----------------------------------------------------------------------------- problems
def paper_C(m, l, r, theta):
    I = cylinder_inertia(m, l, r)
    ixx, izz = I[0, 0], I[2, 2]
    iyy = ixx * math.cos(theta / 2) ** 2 + izz * math.sin(theta / 2) ** 2
    return 1 - izz * math.sin(theta / 2) / iyy


def make(joint, front, rear, theta_deg, profile, circulation, path, h=10.0, g=9.8, **kw):
    cat = Cat(*front, *rear, joint)
    Tf = math.sqrt(2 * h / g)
    sch = Schedule(Tf, theta_deg, profile, circulation, path, joint, **kw)
    return cat, sch


def calibrate(joint, front, rear, theta_deg, profile, path, target, guess, **kw):
    def f(Phi):
        cat, sch = make(joint, front, rear, theta_deg, profile, Phi, path, **kw)
        return integrate_dop853(cat, sch)["twist"] - target
    a, b = guess * 0.9, guess * 1.1
    fa, fb = f(a), f(b)
    while fa * fb > 0:
        a, b = a * 0.9, b * 1.1
        fa, fb = f(a), f(b)
    return brentq(f, a, b, xtol=1e-13, rtol=4 * np.finfo(float).eps, maxiter=200)


def run_catflip(problem, sets):
    cmd = [CATFLIP, "simulate", os.path.join(PROBLEMS, problem)]
    for s in sets:
        cmd += ["--set", s]
    cmd.append("--json")
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=900)
    except FileNotFoundError:
        return None, "binary absent"
    if p.returncode != 0:
        return None, (p.stderr.strip() or p.stdout.strip())[:400]
    return json.loads(p.stdout), None


def case_list():
    eq = (1.0, 1.0, 0.1)
    fr, re = (0.8, 0.8, 0.1), (1.2, 1.0, 0.1)
    cases = []
    for th in (45.0, 100.0):
        for prof in ("paper-cosine", "cycloidal"):
            sets = [f"manoeuvre.profile={prof}"] + ([f"manoeuvre.theta_deg={th:g}"] if th != 45 else [])
            cases.append(dict(label=f"1 kane-scher θ={th:g}° {prof}", problem="kane-scher.toml", sets=sets,
                              joint="no-twist", front=eq, rear=eq, theta=th, profile=prof, circ="paper",
                              path="joint-circle"))
    for path in ("joint-circle", "cone"):
        for prof in ("paper-cosine", "cycloidal"):
            sets = [f"manoeuvre.profile={prof}"] + (["manoeuvre.bend_path=cone"] if path == "cone" else [])
            # q1 on the cone: atan2's principal value (catflip's choice, see REPORT.md); the
            # "continuous" branch is available for diagnostics (diagnose_cone_branch)
            branches = ("principal",) if path == "cone" else ("continuous",)
            for br in branches:
                cases.append(dict(label=f"2 unequal universal {path} {prof}" + (f" [q1 {br}]" if path == "cone" else ""),
                                  problem="unequal-halves.toml", sets=sets, joint="universal", front=fr, rear=re,
                                  theta=45.0, profile=prof, circ="calibrated", path=path, branch=br))
    cases.append(dict(label="3 unequal no-twist paper-cosine", problem="unequal-halves.toml",
                      sets=["cat.joint=no-twist"], joint="no-twist", front=fr, rear=re, theta=45.0,
                      profile="paper-cosine", circ="calibrated", path="joint-circle"))
    cases.append(dict(label="4 paper's cat (control)", problem="paper.toml", sets=[], joint="universal",
                      front=eq, rear=eq, theta=45.0, profile="paper-cosine", circ="paper", path="joint-circle"))
    return cases


def compute(c, cf, quick=False):
    t0 = time.time()
    kw = dict(cone_branch=c.get("branch", "continuous"))
    mean = tuple((a + b) / 2 for a, b in zip(c["front"], c["rear"]))
    piC = math.pi / paper_C(*mean, math.radians(c["theta"]))
    args = (c["joint"], c["front"], c["rear"], c["theta"], c["profile"])
    target = None
    if c["circ"] == "paper":
        Phi = piC
    else:
        target = -math.pi
        if cf is not None and cf.get("twist_deg", -180.0) > 0:
            target = math.pi
        Phi = calibrate(*args, c["path"], target, piC, **kw)
    cat, sch = make(*args, Phi, c["path"], **kw)
    r = integrate_dop853(cat, sch)
    r12 = integrate_dop853(cat, sch, rtol=1e-12, atol=1e-12)
    n = 2000 if quick else 8000
    k1 = integrate_rk4(cat, sch, n)
    k2 = integrate_rk4(cat, sch, 2 * n)
    pk, chk = peaks(cat, sch, n=2001 if quick else 20001)
    pk_coarse, _ = peaks(cat, sch, n=2001, refine=False)
    conv = dict(dop_tol=math.degrees(abs(r["twist"] - r12["twist"])),
                dop_tol_swing=math.degrees(abs(r["swing"] - r12["swing"])),
                rk4_n=n, rk4_halving=math.degrees(abs(k1["twist"] - k2["twist"])),
                rk4_vs_dop=math.degrees(abs(k2["twist"] - r["twist"])),
                rk4_vs_dop_swing=math.degrees(abs(k2["swing"] - r["swing"])),
                nfev=r["nfev"])
    return dict(c, Phi=Phi, piC=piC, target=target, twist=math.degrees(r["twist"]),
                swing=math.degrees(r["swing"]), peaks=pk, peaks_coarse=pk_coarse, checks=chk, conv=conv,
                jump=impulse_at_unbend(cat, sch) if c["profile"] == "paper-cosine" else None,
                qend=[float(x) for x in sch.qend], nsamp=2001 if quick else 20001, secs=time.time() - t0)


def main():
    quick = "--quick" in sys.argv
    print("independent cross-check of catflip (no-twist joint, unequal halves)")
    print(time.strftime("%Y-%m-%d %H:%M:%S UTC", time.gmtime()))
    results = []
    cache = {}
    for c in case_list():
        key = (c["problem"], tuple(c["sets"]))
        if key not in cache:
            cache[key] = run_catflip(c["problem"], c["sets"])
        cf, err = cache[key]
        row = compute(c, cf, quick)
        row["catflip"], row["err"] = cf, err
        results.append(row)
        report_row(row)
    with open(os.path.join(os.environ.get("TMPDIR", "/tmp"), "catflip-models-xcheck.json"), "w") as fh:
        json.dump(results, fh, indent=1, default=float)
    summary(results)
    if "--no-probes" not in sys.argv:
        extra_probes()
    return results


def summary(results):
    print("\n## summary: worst |difference| xcheck - catflip over the brief's cases")
    wt = ws = wp = wc = 0.0
    for r in results:
        cf = r["catflip"]
        if cf is None:
            continue
        wt = max(wt, abs(r["twist"] - cf["twist_deg"]))
        ws = max(ws, abs(r["swing"] - cf["swing_deg"]))
        wc = max(wc, abs(r["Phi"] - cf["circulation_rad"]))
        if r.get("jump") and cf.get("velocity_jumps"):
            ci = np.array(cf["velocity_jumps"][0]["impulse"])
            mine = np.array(r["jump"]["impulse"])
            gi = r["jump"].get("impulse_generalized")
            extra = (f"; catflip vs generalised J_l^T impulse {np.max(np.abs(ci - np.array(gi))):.1e}" if gi else "")
            print(f"   {r['label']}: impulse |xcheck - catflip| {np.max(np.abs(mine - ci)):.1e} N·m·s "
                  f"(catflip/xcheck {np.round(ci / mine, 6).tolist()}){extra}")
        for ph, vals in r["peaks"].items():
            for i, (dense, best) in enumerate(vals):
                th = cf["peak_torque_nm"][ph][i]
                if max(abs(th), best) > 1e-12:
                    wp = max(wp, abs(best - th) / abs(th))
    print(f"   twist {wt:.1e}° (target 1e-6°), swing {ws:.1e}° (1e-6°), peaks {wp:.1e} relative (1e-3), "
          f"circulation {wc:.1e} rad (1e-6 rad)")


def extra_probes():
    """Beyond the brief: unequal radii and lengths on both halves at a fixed circulation, and
    catflip's bend_path = "cone" on the no-twist joint."""
    print("\n## probe A: halves 0.7 kg/0.6 m/r 0.12 and 1.4 kg/1.1 m/r 0.08, drop 3 m, circulation 3.1 rad")
    fr, re = (0.7, 0.6, 0.12), (1.4, 1.1, 0.08)
    base = ["cat.front.mass=0.7", "cat.front.length=0.6", "cat.front.radius=0.12", "cat.rear.mass=1.4",
            "cat.rear.length=1.1", "cat.rear.radius=0.08", "drop.height=3.0"]
    Tf = math.sqrt(2 * 3.0 / 9.8)
    for joint in ("universal", "no-twist"):
        for path, th in (("joint-circle", 45.0), ("cone", 100.0), ("cone", 60.0)):
            for prof in ("paper-cosine", "cycloidal"):
                sets = base + ["manoeuvre.circulation=3.1", f"cat.joint={joint}", f"manoeuvre.bend_path={path}",
                               f"manoeuvre.theta_deg={th:g}", f"manoeuvre.profile={prof}"]
                cf, err = run_catflip("unequal-halves.toml", sets)
                cat = Cat(*fr, *re, joint)
                sch = Schedule(Tf, th, prof, 3.1, path, joint, cone_branch="principal")
                r = integrate_dop853(cat, sch)
                pk, _ = peaks(cat, sch, n=4001)
                tw, sw = math.degrees(r["twist"]), math.degrees(r["swing"])
                worst = 0.0
                for ph in ("bend", "twist", "unbend"):
                    for i in range(2):
                        mine, theirs = pk[ph][i][1], cf["peak_torque_nm"][ph][i]
                        if max(mine, theirs) > 1e-12:
                            worst = max(worst, abs(mine - theirs) / abs(theirs))
                print(f"   {joint:9s} {path:12s} θ={th:5.1f} {prof:12s} twist {tw:+14.9f} vs {cf['twist_deg']:+14.9f} "
                      f"(Δ {tw - cf['twist_deg']:+.1e}), swing {sw:13.9f} vs {cf['swing_deg']:13.9f} "
                      f"(Δ {sw - cf['swing_deg']:+.1e}), worst peak Δ {worst:.1e} rel")
    print("   (xcheck's no-twist 'cone' is the joint circle, the joint's own cone; catflip's is not, see probe B)")
    print("\n## probe B: catflip's bend_path = \"cone\" on Kane and Scher's cat (no-twist, equal halves, π/C)")
    eq = (1.0, 1.0, 0.1)
    for th in (100.0, 45.0):
        Phi = math.pi / paper_C(*eq, math.radians(th))
        cat = Cat(*eq, *eq, "no-twist")
        cf, _ = run_catflip("kane-scher.toml", ["manoeuvre.bend_path=cone", f"manoeuvre.theta_deg={th:g}"])
        print(f"   θ={th:g}°: catflip cone: twist {cf['twist_deg']:+.9f}° swing {cf['swing_deg']:.9f}° "
              f"twist-phase peaks {cf['peak_torque_nm']['twist'][0]:.9g}, {cf['peak_torque_nm']['twist'][1]:.9g} N·m")
        sch = Schedule(math.sqrt(2 * 10 / 9.8), th, "paper-cosine", Phi, "cone", "universal", cone_branch="continuous")
        r = integrate_dop853(cat, sch)
        pk, _ = peaks(cat, sch, n=4001)
        s = np.linspace(0, sch.T2, 4001)
        q, _, _ = sch.phase("twist", s)
        ang = np.degrees(np.arccos(np.clip(cat.rotation(q, 0 * q, 0 * q)[0][:, 2, 2], -1, 1)))
        print(f"      universal-joint cone angles fed to exp([q1,q2,0]x): twist {math.degrees(r['twist']):+.9f}° "
              f"swing {math.degrees(r['swing']):.9f}° twist-phase peaks {pk['twist'][0][1]:.9g}, {pk['twist'][1][1]:.9g} N·m; "
              f"angle between the spines {ang.min():.3f}..{ang.max():.3f}° (a cone keeps {180 - th:g}°)")
        sch = Schedule(math.sqrt(2 * 10 / 9.8), th, "paper-cosine", Phi, "joint-circle", "no-twist")
        r = integrate_dop853(cat, sch)
        pk, _ = peaks(cat, sch, n=4001)
        print(f"      the joint's true cone (its joint circle): twist {math.degrees(r['twist']):+.12f}° "
              f"swing {math.degrees(r['swing']):.1e}° twist-phase peaks {pk['twist'][0][1]:.6g}, {pk['twist'][1][1]:.6g} N·m")
    print("\n## probe C: catflip's no-twist 'cone' at θ = 60° (β = 120° > 90°) against the circulation "
          "(probe A's cat, cycloidal): the flip jumps where φ_end crosses π/2")
    cat = Cat(*fr, *re, "no-twist")
    for Phi in (1.2, 1.5, 1.5707, 1.5709, 1.65, 2.0, 3.1):
        sets = base + [f"manoeuvre.circulation={Phi}", "cat.joint=no-twist", "manoeuvre.bend_path=cone",
                       "manoeuvre.theta_deg=60", "manoeuvre.profile=cycloidal"]
        cf, err = run_catflip("unequal-halves.toml", sets)
        sch = Schedule(Tf, 60.0, "cycloidal", Phi, "cone", "universal", cone_branch="continuous")
        r = integrate_dop853(cat, sch)
        print(f"   Φ = {Phi:<6}: catflip twist {cf['twist_deg']:+12.6f}° swing {cf['swing_deg']:10.6f}° | "
              f"u-joint cone angles through exp, q1 continuous: {math.degrees(r['twist']):+12.6f}° {math.degrees(r['swing']):10.6f}°"
              f" | catflip velocity_jumps {len(cf['velocity_jumps'])}, momentum_max {cf['momentum_max']:.0e}")


def cf_peaks(cf):
    p = cf.get("peak_torque_nm", {})
    out = {}
    for ph in ("bend", "twist", "unbend"):
        v = p.get(ph)
        if isinstance(v, dict):
            v = v.get("tau_nm", v.get("joints", list(v.values())))
        out[ph] = v
    return out


def report_row(row):
    cf = row["catflip"]
    print()
    print(f"## {row['label']}   ({row['problem']} {' '.join('--set ' + s for s in row['sets'])})  [{row['secs']:.1f} s]")
    if cf is None:
        print("   catflip:", row["err"])
    print(f"   {'quantity':<22}{'xcheck':>22}{'catflip':>22}{'difference':>14}")

    def line(name, mine, theirs, rel=False):
        if theirs is None:
            print(f"   {name:<22}{mine:>22.12f}{'-':>22}")
            return
        d = mine - theirs
        if rel:
            d = d / theirs if theirs else float("nan")
            print(f"   {name:<22}{mine:>22.9f}{theirs:>22.9f}{d:>14.2e}")
        else:
            print(f"   {name:<22}{mine:>22.12f}{theirs:>22.12f}{d:>14.2e}")
    g = (lambda k: cf.get(k)) if cf else (lambda k: None)
    line("circulation (rad)", row["Phi"], g("circulation_rad"))
    line("twist (deg)", row["twist"], g("twist_deg"))
    line("swing (deg)", row["swing"], g("swing_deg"))
    cp = cf_peaks(cf) if cf else {}
    for ph, vals in row["peaks"].items():
        for i, (dense, best) in enumerate(vals):
            theirs = None
            if cp.get(ph) is not None:
                theirs = cp[ph][i]
            line(f"peak {ph} τ{i + 1} (N·m)", best, theirs, rel=True)
    print(f"   checks: action-reaction residual (rel) {row['checks']['reaction']:.1e}, "
          f"momentum from body sum {row['checks']['momentum']:.1e} N·m·s")
    cv = row["conv"]
    print(f"   convergence: DOP853 tol 1e-12 vs 1e-13 Δtwist {cv['dop_tol']:.1e}°, Δswing {cv['dop_tol_swing']:.1e}°; "
          f"RK4 {cv['rk4_n']}→{2 * cv['rk4_n']} steps/phase Δtwist {cv['rk4_halving']:.1e}°, "
          f"RK4({2 * cv['rk4_n']}) vs DOP853 Δtwist {cv['rk4_vs_dop']:.1e}° Δswing {cv['rk4_vs_dop_swing']:.1e}°")
    dig = []
    for ph, vals in row["peaks"].items():
        for i, (dense, best) in enumerate(vals):
            coarse = row["peaks_coarse"][ph][i][0]
            rel = abs(best - dense) / best if best else 0.0
            relc = abs(best - coarse) / best if best else 0.0
            dig.append(f"{ph}τ{i + 1} {rel:.0e}/{relc:.0e}")
    print(f"   peaks, rel. change refined vs {row['nsamp']} samples / vs 2001 samples: " + ", ".join(dig))
    if row.get("target") is not None:
        print(f"   calibration target twist {math.degrees(row['target']):+.0f}° (π/C of the mean half {row['piC']:.9f} rad)")
    print(f"   end-of-twist joints q = ({row['qend'][0]:.9f}, {row['qend'][1]:.9f}) rad")
    if row.get("jump"):
        j = row["jump"]
        cj = (cf or {}).get("velocity_jumps") or [{}]
        cj = cj[0]
        print(f"   velocity jump at unbend: rates before {np.round(j['rates_before'], 12).tolist()} "
              f"(catflip {cj.get('rates_before')}); impulse on motor axes {np.round(j['impulse'], 12).tolist()} N·m·s "
              f"(catflip {cj.get('impulse')})")
        if "impulse_generalized" in j:
            print(f"      generalised impulse J_l(q)^T·impulse (NOT the contract's A-axis projection) "
                  f"{np.round(j['impulse_generalized'], 12).tolist()}")


if __name__ == "__main__":
    main()
