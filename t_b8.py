import numpy as np, dataclasses
from problems import budding
from shellbvp import harmonics as H
eq = budding.equilibrium(0, 1, 4.0)
for d in (16, 24, 40):
    b = dataclasses.replace(H._base(eq, d), clamped=False)
    D = H._derivative_operators(b)
    for n in (0, 1):
        M = H._mass(b, D, n); sp = H._space(b, D, M, n, H._mass_weights(b, n))
        res = H._spectrum(b, D, None, sp, n, 2, M)
        print(d, n, res.rigid, res.eigenvalues)
