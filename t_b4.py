import numpy as np
from problems import budding
from shellbvp import second_variation
eq = budding.equilibrium(0, 1, 14.2)
for N in (24, 32, 48, 64):
    print(N, second_variation(eq, nodes=N, count=2).eigenvalues)
print(eq.legendre.min() if eq.legendre is not None else None)
