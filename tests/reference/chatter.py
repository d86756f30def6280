#!/usr/bin/env python3
"""Chatter of the independent minimum-peak collocation (mintime.py), measured as catflip's
`optimize::whole::measure::chatter` defines it: switches of each torque between -P/2 and +P/2
(P the peak of both joints), total variation over that of a clean bang-bang profile with the
same switches and end values, minus one, and the least |tau|/P farther than 1 % of the fall from
the joint's own switches.  Torques on 16 points per interval of the exact piecewise-cubic path.

Run after `mintime.py minpeak --N 100,200` (which writes /work/xcheck/sol_minpeak_N200.npz):
    venv/bin/python chatter.py [/work/xcheck/sol_minpeak_N200.npz]
"""
import sys
import numpy as np

path = sys.argv[1] if len(sys.argv) > 1 else '/work/xcheck/sol_minpeak_N200.npz'
sys.argv = sys.argv[:1]
here = __file__.rsplit('/', 1)[0] if '/' in __file__ else '.'
exec(open(f'{here}/mintime.py').read().split("if __name__ == '__main__':")[0])

z = np.load(path)
T, Q, QD, A = float(z['T']), z['Q'], z['QD'], z['A']
N = Q.shape[1] - 1
tk = np.linspace(0, T, N + 1)
tt = np.linspace(0, T, 16 * N + 1)
q, qd, qdd = path_eval(tt, tk, Q, QD, A)
tau = np.array(F_TAU.map(len(tt))(q, qd, qdd))
P = np.abs(tau).max()
print('peak', P)
for j in range(2):
    x = tau[j]
    side, switches = 0, []
    for k, v in enumerate(x):
        if abs(v) > 0.5 * P:
            if side != 0 and np.sign(v) != side:
                switches.append(tt[k])
            side = np.sign(v)
    tv = np.abs(np.diff(x)).sum()
    clean = 2 * P * len(switches) + (P - min(abs(x[0]), P)) + (P - min(abs(x[-1]), P))
    away = np.array([all(abs(t - s) > 0.01 * T for s in switches) for t in tt])
    print(f'joint {j + 1}: {len(switches)} switches at', [f'{s:.4f}' for s in switches],
          f'excess variation {tv / clean - 1:+.4f}, deepest dip {np.abs(x[away]).min() / P:.4f}')
