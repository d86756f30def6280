#!/usr/bin/env python3
"""Replay catflip's whole optimum through models.py's independent Newton-Euler model.

Reads the JSON of `catflip optimize PROBLEM --whole --json` (the best solution's clamped B-spline:
degree, knots, each joint's control points), rebuilds q(t), q'(t), q''(t) with SciPy's BSpline
and measures, in models.py's `Cat` (zero-momentum base rate and Newton-Euler joint torques,
written without the Rust source):
  - A's final attitude: SciPy DOP853 at rtol = atol = 1e-12 on the unit quaternion, integrated
    knot span by knot span (q''' jumps at every knot), twist and swing about A's initial spine;
  - the peak motor torque per joint on 40 points per knot span, each maximum polished by a
    bounded scalar search between its neighbours.

Usage (the halves as mass,length,radius; the joint as in problem files):
  catflip optimize problems/kane-scher.toml --whole --set cat.length=0.9 --json > b.json
  python3 spline_replay.py b.json --front 1.0,0.9,0.1 --rear 1.0,0.9,0.1 --joint no-twist
With --npz OUT --N N it also writes the optimum at N + 1 uniform nodes (q, q', q'' and A's attitude
quaternion) in the format of models_minpeak.py's saved solutions, a warm start for its `refine`.
"""
import argparse
import json
import math

import numpy as np
from scipy.integrate import solve_ivp
from scipy.interpolate import BSpline
from scipy.optimize import minimize_scalar

from models import Cat, qmul, swing_twist


def splines(doc):
    """The best solution's spline; without a best (no start converged), the lowest-peak start's."""
    sols = doc['outcome']['solutions']
    best = doc['outcome']['best']
    sol = sols[best] if best is not None else min(sols, key=lambda s: s['peak_torque_nm'])
    s = sol['spline']
    knots = np.array(s['knots'])
    curves = [BSpline(knots, np.array(c), s['degree']) for c in s['coefficients']]
    return knots, [(c, c.derivative(1), c.derivative(2)) for c in curves], sol


def state(curves, t):
    t = np.atleast_1d(np.asarray(t, dtype=float))
    return tuple(np.stack([c[k](t) for c in curves], -1) for k in range(3))


def flip(cat, knots, curves, nodes=()):
    """Twist and swing, and A's attitude quaternion at each of `nodes` (s, increasing)."""
    qa = np.array([1.0, 0.0, 0.0, 0.0])
    psi = [0.0]
    at = []
    breaks = np.unique(knots)
    for a, b in zip(breaks[:-1], breaks[1:]):
        def rhs(t, y):
            om = cat.state(*state(curves, t))['Om'][0]
            return 0.5 * qmul(y, np.array([0.0, *om]))
        sol = solve_ivp(rhs, (a, b), qa, method='DOP853', rtol=1e-12, atol=1e-12, dense_output=True)
        at.extend(sol.sol(t) for t in nodes if a <= t < b or (t == b == breaks[-1]))
        qa = sol.y[:, -1] / np.linalg.norm(sol.y[:, -1])
        psi.append(math.atan2(qa[3], qa[0]))
    twist, swing = swing_twist(qa, psi)
    return twist, swing, np.array(at).T


def peaks(cat, knots, curves, per_span=40):
    breaks = np.unique(knots)
    tt = np.unique(np.concatenate([np.linspace(a, b, per_span + 1) for a, b in zip(breaks[:-1], breaks[1:])]))
    st = cat.state(*state(curves, tt), check=True)
    out = []
    for j in range(len(curves)):
        a = np.abs(st['tau'][:, j])
        k = int(np.argmax(a))
        best = a[k]
        if 0 < k < len(tt) - 1:
            r = minimize_scalar(lambda t: -abs(cat.state(*state(curves, t))['tau'][0, j]),
                                bounds=(tt[k - 1], tt[k + 1]), method='bounded', options=dict(xatol=1e-13))
            best = max(best, -r.fun)
        out.append(best)
    return out, st['reaction_residual'] / st['reaction_scale'], st['momentum']


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('json')
    ap.add_argument('--front', required=True, help='mass,length,radius of the front half A')
    ap.add_argument('--rear', required=True, help='mass,length,radius of the rear half B')
    ap.add_argument('--joint', required=True, choices=['universal', 'no-twist', 'spherical'])
    ap.add_argument('--npz', default='', help='write the optimum at --N + 1 nodes here')
    ap.add_argument('--N', type=int, default=200)
    a = ap.parse_args()
    doc = json.load(open(a.json))
    front = [float(x) for x in a.front.split(',')]
    rear = [float(x) for x in a.rear.split(',')]
    cat = Cat(*front, *rear, a.joint)
    knots, curves, sol = splines(doc)
    nodes = np.linspace(knots[0], knots[-1], a.N + 1) if a.npz else ()
    twist, swing, U = flip(cat, knots, curves, nodes)
    if a.npz:
        q, qd, qdd = state(curves, nodes)
        np.savez(a.npz, T=knots[-1], Q=q.T, QD=qd.T, A=qdd.T, U=U / np.linalg.norm(U, axis=0))
    per_motor, reaction, momentum = peaks(cat, knots, curves)
    print(json.dumps(dict(
        catflip=dict(start=sol['start'], status=sol['status'], twist_deg=math.degrees(sol['twist']), swing_deg=math.degrees(sol['swing']),
                     peak_nm=sol['peak_torque_nm']),
        replay=dict(twist_deg=math.degrees(twist), swing_deg=math.degrees(swing), peak_nm=per_motor,
                    reaction_residual=reaction, momentum=momentum)), indent=1))


if __name__ == '__main__':
    main()
