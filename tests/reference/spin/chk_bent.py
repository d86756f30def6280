import numpy as np
from spin import *
from scipy.integrate import solve_ivp
qfix = np.array([3*np.pi/4, 0.3])
sf = lambda t, ph=None: (qfix, np.zeros(2), np.zeros(2))
Il = parts(qfix, np.zeros(2))['Ilock']
L = np.array([0.01,0.02,-0.03])
rr = Run(sf, L)
ellT = quat_to_R(rr.quat).T @ L
print("ell(0)", L, "ell(T)", ellT)
E0 = 0.5*L@np.linalg.solve(Il,L); E1 = 0.5*ellT@np.linalg.solve(Il,ellT); print(E0, E1, (E1-E0)/E0)
# independent: Euler's equations for the body momentum (world-free), compare ell(T)
f = lambda t,y: np.cross(y, np.linalg.solve(Il, y))
s = solve_ivp(f, (0,T), L, method='DOP853', rtol=1e-13, atol=1e-15)
print("Euler eqs ell(T)", s.y[:,-1], "diff", np.abs(s.y[:,-1]-ellT).max())
