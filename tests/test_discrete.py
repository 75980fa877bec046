"""Continuation and fold location for discretised systems (shellbvp.discrete), tested on
problems with exactly known folds, independent of the shell equations:

* the scalar fold p = 2u - u^2 (fold at u = 1, p = 1);
* Bratu's problem u'' + p e^u = 0, u(0) = u(1) = 0, discretised here by Chebyshev
  collocation (the differentiation matrix is checked on its own first); the fold is
  p* = 3.513830719125161 (Bratu 1914; 8 x^2 / cosh(x)^2 at the root of x tanh x = 1, checked
  in test_continuation.py), with u'(0) = 4 exactly there.
"""

import math

import numpy as np
import pytest

from shellbvp import ConvergenceError
from shellbvp.discrete import follow_discrete, locate_fold, newton, polish_fold
from shellbvp.spectral import chebyshev_points, coefficients, differentiation_matrix

LAM_STAR = 3.513830719125161


class Scalar:
    """R(u, p) = u^2 - 2u + p, monitor u: the branch p = 2u - u^2 folds at (u, p) = (1, 1)."""

    size = 1

    def evaluate(self, U, p):
        u = U[0]
        return np.array([u * u - 2 * u + p]), np.array([[2 * u - 2]]), np.array([1.0])

    def monitor(self, U):
        return float(U[0]), np.array([1.0])


class ChebyshevBratu:
    """u'' + p e^u = 0 on [0, 1], u = 0 at both ends, on N + 1 Chebyshev points; the
    boundary rows replace the ODE rows at the ends. Monitor: u'(0)."""

    def __init__(self, N):
        self.N, self.size = N, N + 1
        D = differentiation_matrix(N)
        self.D, self.D2 = D, D @ D

    def evaluate(self, U, p):
        R = self.D2 @ U + p * np.exp(U)
        J = self.D2 + np.diag(p * np.exp(U))
        Rp = np.exp(U)
        R[0], R[-1] = U[0], U[-1]
        J[0], J[-1] = 0.0, 0.0
        J[0, 0] = J[-1, -1] = 1.0
        Rp[0] = Rp[-1] = 0.0
        return R, J, Rp

    def monitor(self, U):
        return float(self.D[0] @ U), self.D[0].copy()


def test_chebyshev_differentiation_and_coefficients_are_exact_for_polynomials():
    N = 12
    t = chebyshev_points(N)
    assert t[0] == 0.0 and t[-1] == pytest.approx(1.0, abs=1e-15)
    p = t**7 - 3 * t**2 + 1
    assert np.max(np.abs(differentiation_matrix(N) @ p - (7 * t**6 - 6 * t))) < 1e-11
    # T_k(1 - 2t) has exactly one nonzero coefficient.
    c = coefficients(np.cos(5 * np.arccos(1 - 2 * t)))
    assert c[5] == pytest.approx(1.0, abs=1e-13)
    assert np.max(np.abs(np.delete(c, 5))) < 1e-13


def test_scalar_fold_is_passed_and_located_exactly():
    pts, brackets = follow_discrete(Scalar(), np.array([0.0]), 0.0, ds=0.1, ds_max=0.3,
                                    p_stop=(-1.0, 2.0), monitor_stop=(-1.0, 2.5))
    assert len(brackets) == 1
    i, j = brackets[0]
    a, b = pts[i], pts[j]
    assert a.tangent[1] > 0 > b.tangent[1]           # dp/ds changes sign across the fold
    assert a.monitor < 1.0 < b.monitor
    fold = locate_fold(Scalar(), a, b)
    assert fold.p == pytest.approx(1.0, abs=1e-14)
    assert fold.monitor == pytest.approx(1.0, abs=1e-9)
    assert min(a.monitor, b.monitor) <= fold.monitor <= max(a.monitor, b.monitor)
    # Every point is on the branch p = 2u - u^2.
    for q in pts:
        assert q.p == pytest.approx(2 * q.U[0] - q.U[0] ** 2, abs=1e-12)
    assert pts[-1].p < 1.0 and pts[-1].monitor > 1.0   # the branch was followed past the fold


@pytest.fixture(scope="module")
def bratu():
    system = ChebyshevBratu(24)
    pts, brackets = follow_discrete(system, np.zeros(25), 0.0, ds=0.5, ds_max=2.0,
                                    n_folds=1, p_stop=(-1.0, 5.0))
    return system, pts, brackets


def test_bratu_fold_through_the_discrete_api(bratu):
    system, pts, brackets = bratu
    (i, j), = brackets
    fold = locate_fold(system, pts[i], pts[j])
    assert abs(fold.p - LAM_STAR) <= 1e-12
    assert fold.monitor == pytest.approx(4.0, abs=1e-9)
    # The refined fold lies between the bracketing points and is the largest p seen.
    assert pts[i].monitor <= fold.monitor <= pts[j].monitor
    assert fold.p >= max(q.p for q in pts)


def test_bratu_fold_polished_on_a_finer_discretisation(bratu):
    system, pts, brackets = bratu
    (i, j), = brackets
    coarse = locate_fold(ChebyshevBratu(12), *_resampled(pts[i], pts[j], 12))
    fine_sys = ChebyshevBratu(32)
    c = coefficients(coarse.U)
    U = np.polynomial.chebyshev.chebval(1 - 2 * chebyshev_points(32), c)
    fine = polish_fold(fine_sys, U, coarse.p, coarse.monitor)
    assert abs(fine.p - LAM_STAR) <= 1e-12
    assert abs(coarse.p - LAM_STAR) > 1e-10   # the coarse one really was coarser


def _resampled(a, b, N):
    """The bracketing points of the N = 24 branch, re-solved on N nodes at their monitor."""
    system = ChebyshevBratu(N)
    out = []
    for q in (a, b):
        U = np.polynomial.chebyshev.chebval(1 - 2 * chebyshev_points(N), coefficients(q.U))
        res = newton(system, U, q.p, 1.0, 0.0, q.monitor)
        assert res.ok
        x = np.linalg.solve(np.block([[system.evaluate(res.U, res.p)[1],
                                       system.evaluate(res.U, res.p)[2][:, None]],
                                      [res.gm[None, :], np.zeros((1, 1))]]),
                            np.append(np.zeros(N + 1), 1.0))
        nrm = math.hypot(1.0, x[-1])
        out.append(type(q)(res.p, res.m, 0.0, res.U, (1 / nrm, x[-1] / nrm), x[:-1] / nrm))
    return out


def test_newton_failure_is_reported_not_returned():
    res = newton(Scalar(), np.array([0.0]), 2.0, 0.0, 1.0, 2.0)   # no solution for p > 1
    assert not res.ok
    with pytest.raises(ConvergenceError, match="no solution at the start"):
        follow_discrete(Scalar(), np.array([0.0]), 2.0)


def test_locate_fold_refuses_a_bracket_without_a_turn():
    pts, _ = follow_discrete(Scalar(), np.array([0.0]), 0.0, ds=0.1, ds_max=0.1,
                             p_stop=(-1.0, 0.5))
    with pytest.raises(ConvergenceError, match="does not change sign"):
        locate_fold(Scalar(), pts[0], pts[1])
