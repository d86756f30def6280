#!/usr/bin/env python3
"""Independent re-evaluation of catflip's whole-manoeuvre optimum with spin.

Reads the JSON of `catflip optimize problems/spin.toml --whole --json` (default: ./catflip_spin.json),
takes the best solution's joint path (a cubic B-spline q(t), knots in seconds), and with the Python
reference engine only (tests/reference/spin/spin.py):
  * integrates A's orientation by DOP853 at rtol = atol = 1e-12, restarted at every knot span,
    Omega = I_lock^-1 (R^T L - h)  (DESIGN.md 9);
  * reports the continuous twist, the swing and the flip error (angle to Rz(pi));
  * evaluates the joint torques by Newton-Euler on B (spin.torque_NE) on 16 points per span and
    refines the largest sample by a bounded 1-D maximisation.
usage: python check_catflip.py [catflip.json]
"""
import os
import sys
import json

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path[:0] = [HERE, os.path.dirname(HERE)]   # spin.py here; cat.py, mintime.py one folder up
import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import BSpline
from scipy.optimize import minimize_scalar
import spin as sp

L = np.array([0.0, 0.0, 0.01])
fn = sys.argv[1] if len(sys.argv) > 1 else os.path.join(HERE, 'catflip_spin.json')
d = json.load(open(fn))
best = d['outcome']['solutions'][d['outcome']['best']]
spl = BSpline(np.array(best['spline']['knots']), np.array(best['spline']['coefficients']).T,
              best['spline']['degree'])
d1, d2, d3 = spl.derivative(1), spl.derivative(2), spl.derivative(3)


def sched(t, _ph=None):
    """q, qd, qdd at t; accepts the complex time t0 + i*eps of spin.torque_NE's complex step
    (first-order Taylor in the imaginary part, which is all a complex step uses)."""
    if np.iscomplexobj(t):
        t0, e = float(np.real(t)), float(np.imag(t))
        return spl(t0) + 1j * e * d1(t0), d1(t0) + 1j * e * d2(t0), d2(t0) + 1j * e * d3(t0)
    return spl(t), d1(t), d2(t)


def rhs(t, y):
    q, qd, _ = sched(t)
    Om = sp.omega_spin(q, qd, sp.quat_to_R(y).T @ L)
    return 0.5 * sp.qmul(y, np.array([0.0, *Om]))


brk = np.unique(spl.t)                       # span boundaries (the path is smooth inside a span)
u = np.array([1.0, 0, 0, 0])
acc = prev = 0.0
peak, arg, dense = 0.0, None, []
for a, b in zip(brk[:-1], brk[1:]):
    sol = solve_ivp(rhs, (a, b), u, method='DOP853', rtol=1e-12, atol=1e-12, dense_output=True)
    dense.append((a, b, sol.sol))
    for t in np.linspace(a, b, 17):
        y = sol.sol(t)
        tw = 2 * np.arctan2(y[3], y[0]); acc += (tw - prev + np.pi) % (2 * np.pi) - np.pi; prev = tw
        tau = np.abs(sp.torque_NE(sched, L, t, sp.quat_to_R(y), 0)[0])
        if tau.max() > peak:
            peak, arg = tau.max(), (t, int(np.argmax(tau)), a, b, sol.sol)
    u = sol.y[:, -1] / np.linalg.norm(sol.y[:, -1])

# refine the largest sample within its span
t0, j, a, b, so = arg
h = (b - a) / 16
res = minimize_scalar(lambda t: -abs(sp.torque_NE(sched, L, t, sp.quat_to_R(so(t)), 0)[0][j]),
                      bounds=(max(a, t0 - h), min(b, t0 + h)), method='bounded', options=dict(xatol=1e-12))
w, x, y, z = u
flip = 2 * np.arctan2(np.sqrt(w * w + x * x + y * y), abs(z))
swing = np.degrees(2 * np.arctan2(np.hypot(x, y), np.hypot(w, z)))
print(json.dumps(dict(file=fn, catflip_peak=d['peak_torque_nm']['max'], catflip_twist_deg=d['twist_deg'],
                      spans=len(brk) - 1, twist_deg=np.degrees(acc), swing_deg=swing, flip_err_rad=flip,
                      peak_NE_16_per_span=peak, peak_NE_refined=max(peak, -res.fun), t_peak=float(res.x))))
