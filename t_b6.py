import numpy as np
from problems import budding
eq = budding.equilibrium(0, 1, 4.0)
print(len(eq.s)); j=np.argmin(abs(eq.s-budding.PATCH)); print(eq.s[j-2:j+3], eq.lam1[j-2:j+3], eq.k1[j-2:j+3])
