import numpy as np
from problems import budding
from shellbvp import harmonics as H
eq = budding.equilibrium(0, 1, 14.2)
for d in (12, 16, 20, 24, 32, 40):
    M = H.modes(eq, [0, 2, 3], degree=d, count=2)
    print(d, [sp.eigenvalues.round(5) for sp in M.spectra])
sp = H.modes(eq,[2])[2]
i = np.argmax(np.abs(sp.w[0])); print('mode max at s', sp.s[i], 'patch', budding.PATCH, 'theta', budding.THETA)
