import numpy as np
from problems import budding
from shellbvp import harmonics as H
eq = budding.equilibrium(0, 1, 4.0)
b = H._base(eq, 40)
print('ends', b.ends)
sp = H.modes(eq, [2], degree=40, count=1)[2]
w = sp.w[0]; u=sp.u[0]; s=sp.s
j=np.argsort(-np.abs(w))[:5]; print('max w at', s[j], w[j])
m=b.s.shape[1]
print('near interface piece0 last', s[m-4:m], w[m-4:m], u[m-4:m]); print('piece1 first', s[m:m+4], w[m:m+4], u[m:m+4])
print('stretch p0 end', b.stretch[0,-3:], 'p1 start', b.stretch[1,:3])
