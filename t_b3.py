import numpy as np
from problems import budding
from shellbvp import harmonics as H
from shellbvp.jaxsetup import jax
import jax.numpy as jnp
from shellbvp.forms import reduced_energy
eq = budding.equilibrium(0, 1, 4.0)
sp = H.modes(eq,[0],degree=40, count=1)[0]
print('n0 lowest', sp.lowest, 'max|u|', np.abs(sp.u).max(), 'max|v|', np.abs(sp.v).max(), 'max|w|', np.abs(sp.w).max())
i=np.argmax(np.abs(sp.v[0])+np.abs(sp.w[0])+np.abs(sp.u[0])); print('at s', sp.s[i])
sc = eq.scene
base = H._base(eq, 24)
# hessian of W wrt (a11,a12,a22,b11,b12,b22) at points
def W6(ab, d):
    g1,g2,kb1,kb2,sn = d
    a=jnp.array([[ab[0],ab[1]],[ab[1],ab[2]]]); b=jnp.array([[ab[3],ab[4]],[ab[4],ab[5]]])
    abar=jnp.array([[g1**2,0.],[0.,(g2*sn)**2]]); bbar=jnp.array([[kb1*g1**2,0.],[0.,kb2*(g2*sn)**2]])
    return reduced_energy(a,b,abar,bbar,h=sc.h,lam=sc.lam,model=sc.model,material=sc.material)
HW = jax.jit(jax.hessian(W6))
P,m = base.s.shape
for pi in range(P):
  for j in range(0,m,12):
    s=base.s[pi,j]; th=base.theta[pi,j]; r=base.r[pi,j]; lam=base.stretch[pi,j]
    fv = np.asarray(sc.field_values(pi, np.array([s]), eq.p), float).ravel()
    # a, b of base: diag
    k1 = None
    a11=lam**2; a22=r**2
    # b from H? compute via q
    q = None
    d = np.array([fv[0],fv[1],fv[2],fv[3],np.sin(s)])
    # need b11: use theta' ~ numerical from base
    th_all=base.theta[pi]; s_all=base.s[pi]
    dth=np.gradient(th_all,s_all)[j]
    b11 = -lam*dth; b22 = -r*np.sin(th)
    ab=np.array([a11,0.,a22,b11,0.,b22])
    Hh=np.asarray(HW(ab,d))
    # scale: normalize by metric
    Ha = Hh[:3,:3]; Hb=Hh[3:,3:]
    D=np.diag(1/np.sqrt(np.abs(np.diag(Hh)))); print(pi, round(s,4), "joint scaled eig", np.linalg.eigvalsh(D@Hh@D).round(5))
