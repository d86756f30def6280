import numpy as np, casadi as ca
import mintime_spin as M
from spin import *
sc, D = make_schedule()
L = np.array([0.01,0.02,-0.03])
run = Run(sc, L)
for ph,t in [(0,0.1),(1,0.5),(1,0.9),(2,1.3)]:
    R = run.R_at(t,ph); q,qd,qdd = sc(t,ph)
    u = run.sols[ph].sol(t)[:4]
    ell = np.array(M.F_ELL(u, L)).ravel()
    print(np.abs(ell - R.T@L).max(), np.array(M.F_TAU(q,qd,qdd,ell)).ravel(), torque_NE(sc,L,t,R,ph)[0],
          np.abs(np.array(M.F_OM(q,qd,ell)).ravel()-omega_spin(q,qd,R.T@L)).max())
U = np.random.randn(4,5)
print(np.array(M.F_ELL.map(5)(U, L)).shape)
