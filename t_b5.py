import numpy as np, math
from problems import budding, cap_eversion as ce
from shellbvp import harmonics as H
for kb in (0.0, 4.0):
    eq = budding.equilibrium(0, 1, kb)
    for d in (16, 24, 40):
        print('bud', kb, d, [sp.eigenvalues.round(6) for sp in H.modes(eq, [0, 2], degree=d, count=2).spectra])
eq = ce.equilibrium(1.0, math.pi/8, 0.02)
for d in (16, 24, 40):
    print('cap', d, [sp.eigenvalues.round(6) for sp in H.modes(eq, [0, 2], degree=d, count=2).spectra])
