import numpy as np, warnings
from cat import *
from cloud import cyl_cloud, omega_cloud
for name,kw in [("paper",{}),("cyc",dict(profile="cyc")),("cone",dict(theta_deg=120, profile="cyc", path="cone", D=2.5))]:
    sc,_=make_schedule(**kw)
    r = [simulate(sc, rtol=t, atol=t)[:2] for t in (1e-11,1e-12,1e-13)]
    print(name, ["%.10f %.10f"%x for x in r])
# reversibility: run cyc schedule backwards after forwards
sc,_=make_schedule(profile="cyc")
back = lambda t: (lambda q,qd,qdd:(q,-qd,qdd))(*sc(T-t))
_,_,qf = simulate(sc)
import cat
q1 = qf.copy()
# integrate backward schedule starting from qf
def simfrom(sched,quat):
    for (a,b) in [(0,T3),(T3,T3+T2),(T3+T2,T)]:
        f=lambda t,y: 0.5*qmul(y,np.array([0.0,*omega_analytic(*sched(t)[:2])]))
        quat = solve_ivp(f,(a,b),quat,method="DOP853",rtol=1e-12,atol=1e-12).y[:,-1]
    return quat
print("forward+backward quat:", simfrom(back,qf))
# cloud-omega integration (case 3) vs analytic with cloud inertia
PA=cyl_cloud(30,8); mi=m/len(PA); I=mi*(np.sum(PA**2)*np.eye(3)-PA.T@PA)
sc,_=make_schedule(theta_deg=120, profile="cyc", path="cone", D=2.5)
tc = None
def cloud_fn_factory():
    pass
# omega_cloud needs sched and t; wrap simulate's omega_fn via closure on current t
import types
def simulate_cloud(sched):
    quat=np.array([1.0,0,0,0])
    for (a,b) in [(0,T1),(T1,T1+T2),(T1+T2,T)]:
        def sub(t):  # phase-local schedule for FD (avoid crossing boundaries)
            return sched(min(max(t,a+1e-12),b-1e-12))
        f=lambda t,y: 0.5*qmul(y,np.array([0.0,*omega_cloud(lambda tt: sched(tt) if a<tt<b else extrap(tt), t, PA, PA, mi)]))
        # FD within a phase: schedule formulas are smooth per phase; use each phase's own formula beyond its ends
        quat=solve_ivp(f,(a,b),quat,method="DOP853",rtol=1e-10,atol=1e-10).y[:,-1]
    return quat
