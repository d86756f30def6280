import numpy as np
from cat import *

def cyl_cloud(nz, nxy):
    # Cartesian grid midpoints inside cylinder radius r, length l, centred at origin
    zs = (np.arange(nz)+0.5)/nz*l - l/2
    xs = (np.arange(nxy)+0.5)/nxy*2*r - r
    X,Y,Z = np.meshgrid(xs,xs,zs,indexing='ij')
    msk = X**2+Y**2 <= r*r
    P = np.stack([X[msk],Y[msk],Z[msk]],1)
    P -= P.mean(0)  # exact centroid at 0 (grid symmetric anyway)
    return P

def inertia(P, mi):
    return mi*(np.sum(P**2)*np.eye(3) - P.T@P)

def positions(q, PA, PB):
    R = Rx(q[0])@Ry(q[1])
    p = np.array([0,0,-l/2]) - R@np.array([0,0,l/2])
    return np.vstack([PA, PB@R.T + p])

def omega_cloud(sched, t, PA, PB, mi, h=1e-5):
    q = sched(t)[0]
    X = positions(q, PA, PB)
    # 4th-order central difference for relative velocity in A frame
    Xd = (-positions(sched(t+2*h)[0],PA,PB) + 8*positions(sched(t+h)[0],PA,PB)
          - 8*positions(sched(t-h)[0],PA,PB) + positions(sched(t-2*h)[0],PA,PB))/(12*h)
    c = X.mean(0); cd = Xd.mean(0)
    Y = X - c; Yd = Xd - cd
    I = mi*(np.sum(Y**2)*np.eye(3) - Y.T@Y)
    h0 = mi*np.cross(Y, Yd).sum(0)
    return -np.linalg.solve(I, h0)

if __name__=="__main__":
  for nz,nxy in [(60,12),(200,40)]:
      PA = cyl_cloud(nz,nxy); N=len(PA); mi = m/N
      I = inertia(PA, mi)
      print(f"grid {nz}x{nxy}x{nxy}: N={N}, I diag={np.diag(I)}, analytic={[Ix,Ix,Iz]}, offdiag max={np.abs(I-np.diag(np.diag(I))).max():.2e}")
      for kw in [dict(profile="cyc"), dict(theta_deg=120, profile="cyc", path="cone", D=2.5)]:
          sc,_ = make_schedule(**kw)
          worst=0; worst_an=0
          for t in [0.1,0.2,0.5,0.7088942857142857,1.0,1.2,1.35]:
              q,qd,_ = sc(t)
              Oc = omega_cloud(sc,t,PA,PA,mi)
              Oa_cloudI = omega_analytic(q,qd,IA=I,IB=I)
              Oa = omega_analytic(q,qd)
              worst=max(worst,np.abs(Oc-Oa_cloudI).max()); worst_an=max(worst_an,np.abs(Oc-Oa).max())
          print("  ",kw, "max|Om_cloud - Om_analytic(cloud I)|=%.2e"%worst, " vs analytic I: %.2e"%worst_an)
