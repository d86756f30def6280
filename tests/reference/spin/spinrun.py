"""Task 1 + 2 driver: twist/swing with spin, per-phase peak torques, checks.
Run: nice -n 10 /tmp/xcheck-venv/bin/python spinrun.py [--quick]"""
import sys, json, time
import numpy as np
from spin import *
import cat

quick = '--quick' in sys.argv
sc, D = make_schedule()          # paper schedule: theta 45, paper-cosine, joint circle, pi/C
print(f"T={T!r} T1={T1!r} T2={T2!r} D=pi/C={D!r} C={C_of(np.pi/4)!r}")
Ls = [[0, 0, 0], [0.01, 0, 0], [0, 0.01, 0], [0, 0, 0.01], [0.05, 0, 0], [0, 0.05, 0], [0, 0, 0.05],
      [0.01, 0.02, -0.03]]
res = {}

# ---------------------------------------------------------------- Task 1a: twist / swing
print("\n== twist/swing of the paper schedule released with spin (deg) ==")
print("L | twist(1e-13) | swing(1e-13) | twist(1e-12)-twist(1e-13) | swing diff | twist(quat+ell,1e-13)-twist | swing diff | twist(3e-14)-twist | swing diff | nfev")
for L in Ls:
    a = Run(sc, L, 1e-13, 1e-13)
    b = Run(sc, L, 1e-12, 1e-12)
    c = Run(sc, L, 1e-13, 1e-13, form='quat+ell')
    e = Run(sc, L, 3e-14, 3e-14)
    res[str(L)] = dict(twist=a.twist, swing=a.swing, d12=(b.twist - a.twist, b.swing - a.swing),
                       dell=(c.twist - a.twist, c.swing - a.swing), d314=(e.twist - a.twist, e.swing - a.swing),
                       quat=a.quat.tolist())
    print(f"{L} | {a.twist:.12f} | {a.swing:.12f} | {b.twist-a.twist:.1e} | {b.swing-a.swing:.1e} |"
          f" {c.twist-a.twist:.1e} | {c.swing-a.swing:.1e} | {e.twist-a.twist:.1e} | {e.swing-a.swing:.1e} | {a.nfev}", flush=True)
tw0, sw0, _ = cat.simulate(sc, rtol=1e-13, atol=1e-13)
print(f"check: L=0 vs cat.simulate (run.py's engine) at 1e-13: twist diff {res[str(Ls[0])]['twist']-tw0:.2e}, swing diff {res[str(Ls[0])]['swing']-sw0:.2e}")

# ---------------------------------------------------------------- momentum checks along the motion
print("\n== checks: total momentum of the two bodies along the motion (world frame) ==")
for L in [Ls[3], Ls[4], Ls[7]]:
    L = np.array(L, float)
    run = Run(sc, L)
    e1 = e2 = 0.0
    for ph, (a, b) in enumerate(PHASES):
        for t in np.linspace(a, b, 41):
            e1 = max(e1, np.abs(momentum_bodies(sc, L, t, run.R_at(t, ph), ph) - L).max())
        for t in np.linspace(a + 0.01, b - 0.01, 21):
            e2 = max(e2, np.abs(momentum_direct(run, L, t, ph) - L).max())
    print(f"L={L.tolist()}: max|sum_bodies(Omega formula) - L| = {e1:.1e};  max|sum_bodies(differenced integrated motion) - L| = {e2:.1e}")

# ---------------------------------------------------------------- rigid checks
print("\n== checks: rigid cats ==")
It = 2 * Ix + mu * l**2; I3 = 2 * Iz
d0 = parts(np.zeros(2), np.zeros(2))
print(f"straight I_lock diag = {np.diag(d0['Ilock'])}, expected [{It}, {It}, {I3}]")
for Lz in (0.01, 0.05):
    rr = Run(sc, [0, 0, Lz], rigid=True)
    print(f"straight, L=[0,0,{Lz}]: twist {rr.twist:.12f} deg, closed form Lz T/(2 Iz) = {np.degrees(Lz*T/I3):.12f}, diff {rr.twist-np.degrees(Lz*T/I3):.1e}; swing {rr.swing:.1e}")

def qexpv(v):
    th = np.linalg.norm(v)
    return np.array([np.cos(th / 2), *(np.sin(th / 2) * v / th)]) if th > 0 else np.array([1.0, 0, 0, 0])

def top_closed(L, t):
    """torque-free symmetric top, R0 = I: R(t) = exp(t [L]x / It) exp(t lam [e3]x),
    lam = (1/I3 - 1/It) L.e3  (body rate Omega = ell/It + lam e3, ell.e3 constant)."""
    L = np.asarray(L, float)
    lam = (1 / I3 - 1 / It) * L[2]
    return qmul(qexpv(t * L / It), qexpv(np.array([0, 0, t * lam])))

def closed_twist(L, n=20000):
    prev, acc = 0.0, 0.0
    for tt in np.linspace(0, T, n)[1:]:
        y = top_closed(L, tt); tw = 2 * np.arctan2(y[3], y[0])
        acc += (tw - prev + np.pi) % (2 * np.pi) - np.pi; prev = tw
    return np.degrees(acc), twist_swing_deg(top_closed(L, T))[1], top_closed(L, T)

for L in ([0.01, 0.02, -0.03], [0.05, 0, 0.01]):
    rr = Run(sc, L, rigid=True)
    ct, cs, cq = closed_twist(L)
    print(f"straight rigid top L={L}: numeric twist {rr.twist:.12f} swing {rr.swing:.12f}; closed form {ct:.12f} {cs:.12f}; |dquat| {np.abs(rr.quat*np.sign(rr.quat@cq)-cq).max():.1e}")

# rigid bent cat: q frozen at the twist-phase start (beta, 0); generic L; energy and |ell| conserved,
# and L along a principal axis of I_lock gives a steady rotation
qfix = np.array([3 * np.pi / 4, 0.3])
sched_fix = lambda t, ph=None: (qfix, np.zeros(2), np.zeros(2))
Il = parts(qfix, np.zeros(2))['Ilock']
L = np.array([0.01, 0.02, -0.03])
rr = Run(sched_fix, L)
ellT = quat_to_R(rr.quat).T @ L
E0 = 0.5 * L @ np.linalg.solve(Il, L); E1 = 0.5 * ellT @ np.linalg.solve(Il, ellT)
print(f"bent rigid (q={qfix.tolist()}), L={L.tolist()}: energy rel. drift {abs(E1-E0)/E0:.1e}")
w, V = np.linalg.eigh(Il)
for k in range(3):
    Lk = 0.02 * V[:, k]
    rr = Run(sched_fix, Lk)
    ang = Lk / w[k] * T     # steady rotation about the fixed principal axis
    cq = qexpv(ang)
    print(f"bent rigid, L along principal axis {k} (I={w[k]:.6f}): |quat - exp(T L/I)| = {np.abs(rr.quat*np.sign(rr.quat@cq)-cq).max():.1e}")

# ---------------------------------------------------------------- Task 2
print("\n== Task 2: rigid straight cat, L = [0.01, 0, 0.02] ==")
L2 = [0.01, 0, 0.02]
ct, cs, cq = closed_twist(L2)
rr = Run(sc, L2, rigid=True); rr12 = Run(sc, L2, 1e-12, 1e-12, rigid=True)
lam = (1 / I3 - 1 / It) * L2[2]
print(f"It={It!r} I3={I3!r} precession rate |L|/It={np.linalg.norm(L2)/It!r} rad/s, body spin lam={lam!r} rad/s")
print(f"closed-form quat(T) (w,x,y,z) = {cq.tolist()}")
print(f"closed-form twist {ct:.12f} deg swing {cs:.12f} deg")
print(f"numeric     twist {rr.twist:.12f} deg swing {rr.swing:.12f} deg (1e-12: {rr12.twist-rr.twist:.1e}, {rr12.swing-rr.swing:.1e}); |dquat| {np.abs(rr.quat*np.sign(rr.quat@cq)-cq).max():.1e}")
res['task2'] = dict(quat=cq.tolist(), twist=ct, swing=cs, num_twist=rr.twist, num_swing=rr.swing)

# ---------------------------------------------------------------- Task 1b: torques
print("\n== per-phase peak motor torques (N m), Newton-Euler on B, complex-step in time ==")
names = ['bend', 'twist', 'unbend']
for L in [[0, 0, 0], [0, 0, 0.01], [0.05, 0, 0], [0.01, 0.02, -0.03]]:
    L = np.array(L, float)
    ra = Run(sc, L, 1e-13, 1e-13); rb = Run(sc, L, 1e-12, 1e-12)
    pa = peak_torques(ra, L, ngrid=1001 if quick else 4001)
    pb = peak_torques(rb, L, ngrid=1001 if quick else 4001)
    print(f"L={L.tolist()}")
    out = {}
    for ph in range(3):
        for k in range(2):
            v, tp = pa[ph][k]; v2, _ = pb[ph][k]
            a_, b_ = PHASES[ph]
            # local dense re-scan around the peak: nothing higher within +-2 grid spacings
            dg = (b_ - a_) / 4000
            loc = np.linspace(max(a_, tp - 2 * dg), min(b_, tp + 2 * dg), 801)
            vloc = max(abs(torque_NE(sc, L, t, ra.R_at(t, ph), ph)[0][k]) for t in loc)
            if v < 1e-12:
                print(f"  {names[ph]:6s} joint {k+1}: {v:.3e} (identically zero by symmetry; 1e-12 run {v2:.1e}, local rescan {vloc:.1e})")
                out[f"{names[ph]}_{k+1}"] = (v, tp)
                continue
            R = ra.R_at(tp, ph)
            ne_b, ne_a = torque_NE(sc, L, tp, R, ph)
            lag = torque_lagrange(sc, L, tp, R, ph)
            msg = (f"  {names[ph]:6s} joint {k+1}: {v:.10f} at t={tp:.9f} | 1e-12 run: rel {abs(v2-v)/v:.1e}"
                   f" | A-side rel {abs(abs(ne_a[k])-v)/v:.1e} | Lagrange rel {abs(abs(lag[k])-v)/v:.1e}")
            msg += f" | local rescan excess {max(vloc-v,0)/v:.1e}"
            if a_ + 0.009 < tp < b_ - 0.009:
                fd = torque_fd(ra, L, tp, ph)
                msg += f" | FD rel {abs(abs(fd[k])-v)/v:.1e}"
            else:
                msg += " | (phase end: FD stencil n/a)"
            if not L.any():
                q, qd, qdd = sc(tp, ph)
                msg += f" | cat.torque rel {abs(abs(cat.torque(q, qd, qdd)[k])-v)/v:.1e}"
            print(msg, flush=True)
            out[f"{names[ph]}_{k+1}"] = (v, tp)
    res['tau' + str(L.tolist())] = out
json.dump(res, open('results_spin.json', 'w'), indent=1, default=float)
