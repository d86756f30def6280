import numpy as np
from cat import *
from cloud import cyl_cloud, positions, omega_cloud
sc,D = make_schedule(profile="cyc")
ts = [0.5, 0.7088942857142857, 1.0]
def L(q,qd): return 0.5*qd@Mmat(q)@qd
def tau_fd(t, h=1e-4, e=1e-5):
    # dL/dqd along trajectory, differentiated in time by 4th-order central diff; dL/dq by central diff
    def p(tt):
        q,qd,_ = sc(tt)
        return np.array([(L(q,qd+e*np.eye(2)[i])-L(q,qd-e*np.eye(2)[i]))/(2*e) for i in range(2)])
    dp = (-p(t+2*h)+8*p(t+h)-8*p(t-h)+p(t-2*h))/(12*h)
    q,qd,_ = sc(t)
    dLq = np.array([(L(q+e*np.eye(2)[i],qd)-L(q-e*np.eye(2)[i],qd))/(2*e) for i in range(2)])
    return dp - dLq
for t in ts:
    q,qd,qdd = sc(t)
    print(f"t={t}: phase s={t-T1:.6f} tau_cs={torque(q,qd,qdd)} tau_fd={tau_fd(t)}")
# dense max over twist phase
tt = np.linspace(T1, T1+T2, 20001)
taus = np.array([torque(*sc(t)) for t in tt])
i1 = np.argmax(np.abs(taus[:,0])); i2 = np.argmax(np.abs(taus[:,1]))
from scipy.optimize import minimize_scalar
def refine(i,k):
    r = minimize_scalar(lambda t: -abs(torque(*sc(t))[k]), bounds=(tt[max(i-1,0)], tt[min(i+1,len(tt)-1)]), method='bounded', options=dict(xatol=1e-13))
    return r.x, -r.fun
print("max|tau1| twist:", refine(i1,0), " max|tau2| twist:", refine(i2,1))
# paper cosine profile for comparison
scp,_ = make_schedule()
taus = np.array([torque(*scp(t)) for t in tt])
print("paper-cosine twist-phase max|tau|:", np.abs(taus).max(0))
# bend and unbend phases, cyc
for name,(a,b) in {"bend":(0,T1),"unbend":(T1+T2,T)}.items():
    t2 = np.linspace(a,b,5001)
    print(name, "max|tau| cyc:", np.abs(np.array([torque(*sc(t)) for t in t2])).max(0))
# KE check vs cloud
PA = cyl_cloud(60,12); mi = m/len(PA); I = mi*(np.sum(PA**2)*np.eye(3)-PA.T@PA)
for t in ts:
    q,qd,_ = sc(t); h=1e-5
    X = positions(q,PA,PA)
    Xd = (-positions(sc(t+2*h)[0],PA,PA)+8*positions(sc(t+h)[0],PA,PA)-8*positions(sc(t-h)[0],PA,PA)+positions(sc(t-2*h)[0],PA,PA))/(12*h)
    Om = omega_cloud(sc,t,PA,PA,mi)
    Y = X-X.mean(0); V = np.cross(Om,Y) + Xd - Xd.mean(0)
    KEc = 0.5*mi*np.sum(V**2); KEa = 0.5*qd@Mmat(q,IA=I,IB=I)@qd
    print(f"KE cloud {KEc:.12f} analytic(cloud I) {KEa:.12f} rel {abs(KEc-KEa)/KEa:.1e}")
