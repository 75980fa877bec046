"""What every Newton iteration of the package (the inner constitutive root at each node, the
bordered Newton of a branch point, the fold systems) assumes about quadratic convergence.

Near a simple root, Newton's next update is ~C update^2. C is measured from the last two
updates; a C above :data:`CONTRACTION_BOUND` is not that regime but a stall (e.g. on an
inexact Jacobian, or at the round-off floor), and no update is predicted from it.
"""

__all__ = ["CONTRACTION_BOUND"]

#: the largest quadratic-convergence constant C (next update ~ C update^2, relative) from
#: which a next update is predicted
CONTRACTION_BOUND = 100.0
