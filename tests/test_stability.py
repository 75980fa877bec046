"""The discrete second variation (shellbvp.stability), an energy Hessian built independently
of the Euler-Lagrange system: its eigenvalues against what they must be.

References: the undeformed cap is stable and its spectrum converges under refinement; the
snap fold found by the Euler-Lagrange continuation (dp/dw = 0, another computation) is where
the smallest eigenvalue crosses zero (positive before it on the branch, negative after).
"""

import math
from functools import lru_cache

import pytest

import shellbvp
from shellbvp.problems import cap_eversion as ce
from shellbvp.stability import second_variation

THETA, H0 = math.pi / 6, 0.01


@lru_cache(maxsize=None)
def snap_branch():
    return ce.branch(THETA, H0, 1.0, n_folds=1)


def test_undeformed_cap_is_stable_and_its_spectrum_converges():
    eq = ce.equilibrium(0.0, THETA, H0)
    a, b = (second_variation(eq, nodes=N, count=3) for N in (32, 48))
    assert a.stable and a.eigenvalues[0] > 0.01
    assert a.eigenvalues == pytest.approx(b.eigenvalues, rel=1e-6)
    assert a.projected_gradient <= 1e-12      # the reference state is exactly stationary


def test_smallest_eigenvalue_crosses_zero_at_the_snap_fold():
    b = snap_branch()
    fold = b.folds[0]
    at = second_variation(fold.equilibrium, nodes=32, count=2)
    assert abs(at.eigenvalues[0]) <= 1e-7 * at.eigenvalues[1], at.eigenvalues
    before = second_variation(b.equilibrium(fold.index), nodes=32, count=1)
    after = second_variation(b.equilibrium(fold.index + 1), nodes=32, count=1)
    assert before.eigenvalues[0] > 0 > after.eigenvalues[0]
    # and it falls toward the fold along the branch (stable, less and less so)
    lam = [second_variation(b.equilibrium(i), nodes=32, count=1).eigenvalues[0]
           for i in range(0, fold.index + 1, 3)]
    assert all(x > y > 0 for x, y in zip(lam, lam[1:]))


def test_bad_input_is_named():
    eq = ce.equilibrium(0.0, THETA, H0)
    with pytest.raises(ValueError, match="nodes"):
        second_variation(eq, nodes=4)
    with pytest.raises(ValueError, match="count"):
        second_variation(eq, count=0)
    failed = shellbvp.solve(ce.scene(THETA, H0), 1e9, throw=False)
    with pytest.raises(ValueError, match="converged"):
        second_variation(failed)


@pytest.mark.slow  # a budding branch: ~1 min of compilation and continuation
def test_budding_stable_then_ill_posed_at_the_loss_of_ellipticity():
    """eta_a = 0, eta_b = 1: at kbar ~ 20 the smallest eigenvalue is positive and the same at
    degrees 24, 32, 48 (to 1e-3); next to the stop (Legendre condition -> 0 at the apex) it
    is negative, its value changes with the degree by more than 30 % and its mode crowds
    closer to the apex as the degree grows: no physical bifurcation, an ill-posed problem."""
    import numpy as np

    from shellbvp.problems import budding

    b = budding.branch(0.0, 1.0, 40.0)
    mid = b.equilibrium(int(np.argmin(np.abs(b.p - 20.0))))
    lam = [second_variation(mid, nodes=N, count=1).eigenvalues[0] for N in (24, 32, 48)]
    assert min(lam) > 0 and max(lam) - min(lam) <= 1e-3 * min(lam)
    # the last point whose state can be evaluated at all three degrees' points (right at the
    # stop the inner root near the apex has no elliptic solution off the branch's own nodes)
    for i in range(len(b.p) - 1, 0, -1):
        try:
            end = b.equilibrium(i)
            svs = [second_variation(end, nodes=N, count=1) for N in (24, 32, 48)]
            break
        except shellbvp.ConvergenceError:
            continue
    assert b.p[i] > 35.0
    vals = [sv.eigenvalues[0] for sv in svs]
    where = [sv.s[int(np.argmax(np.abs(sv.theta_modes[0])))] for sv in svs]
    assert max(vals) < 0 and min(vals) < 1.3 * max(vals)
    assert where[0] > where[1] > where[2]
