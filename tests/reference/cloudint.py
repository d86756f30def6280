import numpy as np
from cat import *
from cloud import cyl_cloud, omega_cloud
PA=cyl_cloud(30,8); mi=m/len(PA); I=mi*(np.sum(PA**2)*np.eye(3)-PA.T@PA)
def run(sc, cloud):
    quat=np.array([1.0,0,0,0])
    for ph,(a,b) in enumerate([(0,T1),(T1,T1+T2),(T1+T2,T)]):
        s = lambda t: sc(t,ph)
        if cloud: f=lambda t,y: 0.5*qmul(y,np.array([0.0,*omega_cloud(s,t,PA,PA,mi,h=1e-4)]))
        else:     f=lambda t,y: 0.5*qmul(y,np.array([0.0,*omega_analytic(*s(t)[:2],IA=I,IB=I)]))
        quat=solve_ivp(f,(a,b),quat,method="DOP853",rtol=1e-10,atol=1e-10).y[:,-1]
    return quat
for kw in [dict(profile="cyc"), dict(theta_deg=120, profile="cyc", path="cone", D=2.5)]:
    sc,_=make_schedule(**kw)
    qc=run(sc,True); qa=run(sc,False)
    tw=lambda q: np.degrees(2*np.arctan2(q[3],q[0]))
    sw=lambda q: np.degrees(2*np.arcsin(np.hypot(q[1],q[2])))
    print(len(PA), kw, "cloud tw/sw %.9f %.9f"%(tw(qc),sw(qc)), "analytic(cloudI) %.9f %.9f"%(tw(qa),sw(qa)))
