"""Re-evaluate a mintime_spin.py optimum with spin.py (independent of the CasADi model):
orientation by DOP853 (1e-12) interval by interval, torques by Newton-Euler on B (complex step)
on 20 points per interval.  usage: verify_t3.py sol.npz Lx,Ly,Lz"""
import sys
import numpy as np
from scipy.integrate import solve_ivp
from spin import parts, omega_spin, quat_to_R, qmul, twist_swing_deg, torque_NE

z = np.load(sys.argv[1]); L = np.array([float(v) for v in sys.argv[2].split(',')])
Tt, Q, QD, A = float(z['T']), z['Q'], z['QD'], z['A']
N = Q.shape[1] - 1; h = Tt / N

def sched(t, k):
    tau = t - k * h
    a0, a1 = A[:, k], A[:, k + 1]
    return (Q[:, k] + QD[:, k] * tau + a0 * tau**2 / 2 + (a1 - a0) * tau**3 / (6 * h),
            QD[:, k] + a0 * tau + (a1 - a0) * tau**2 / (2 * h), a0 + (a1 - a0) * tau / h)

u = np.array([1.0, 0, 0, 0]); peak = np.zeros(2); prev = acc = 0.0
for k in range(N):
    f = lambda t, y: 0.5 * qmul(y, np.array([0.0, *omega_spin(*sched(t, k)[:2], quat_to_R(y).T @ L)]))
    sol = solve_ivp(f, (k * h, (k + 1) * h), u, method='DOP853', rtol=1e-12, atol=1e-12, dense_output=True)
    for t in np.linspace(k * h, (k + 1) * h, 21):
        y = sol.sol(t)
        tw = 2 * np.arctan2(y[3], y[0]); acc += (tw - prev + np.pi) % (2 * np.pi) - np.pi; prev = tw
        peak = np.maximum(peak, np.abs(torque_NE(sched, L, t, quat_to_R(y), k)[0]))
    u = sol.y[:, -1] / np.linalg.norm(sol.y[:, -1])
tw, sw = twist_swing_deg(u)
print(f"{sys.argv[1]} L={L.tolist()}: N={N} twist {np.degrees(acc):.7f} deg, swing {sw:.7f} deg, "
      f"peak |tau| per joint {peak.tolist()} max {peak.max():.7f}; |q(T)|,|qd(T)| = {np.abs(Q[:, -1]).max():.1e} {np.abs(QD[:, -1]).max():.1e}")
