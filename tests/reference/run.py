import numpy as np, time
from cat import *
from scipy.optimize import brentq
cases = {"1 paper":dict(), "2 cycloidal":dict(profile="cyc"),
         "3 cone120 cyc D=2.5":dict(theta_deg=120, profile="cyc", path="cone", D=2.5)}
for name,kw in cases.items():
    sc,D = make_schedule(**kw)
    tw,sw,qf = simulate(sc)
    tw2,sw2,_ = simulate(sc, rtol=1e-10, atol=1e-10)
    print(f"{name}: D={D:.12f} twist={tw:.10f} swing={sw:.10f}  (tol1e-10 diff tw {tw-tw2:.1e} sw {sw-sw2:.1e})")
# calibrated
def g(D):
    sc,_ = make_schedule(D=D); return abs(simulate(sc)[0]) - 180.0
D0 = np.pi/C_of(np.pi/4)
print("g(D0)", g(D0))
Dc = brentq(g, D0*0.9, D0*1.1, xtol=1e-14, rtol=1e-15)
sc,_ = make_schedule(D=Dc); tw,sw,_ = simulate(sc)
print(f"4 calibrated: D={Dc:.12f} twist={tw:.10f} swing={sw:.10f}")
