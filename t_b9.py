import numpy as np
import shellbvp
from problems import budding
from shellbvp import harmonics as H
eq = budding.equilibrium(0, 1, 4.0, method=shellbvp.Ritz())
print(eq)
for d in (16, 24, 40):
    print(d, [sp.eigenvalues.round(6) for sp in H.modes(eq, [0, 2], degree=d, count=2).spectra])
eq = budding.equilibrium(0, 1, 4.0, nodes=48)
for d in (16, 24, 40):
    print('spec48', d, [sp.eigenvalues.round(6) for sp in H.modes(eq, [0, 2], degree=d, count=2).spectra])
