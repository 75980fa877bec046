"""Continuation and fold refinement: Bratu's exactly known fold through the public API,
fold invariants, passing the fold, option checks, and the cap branch with its CSV."""

import csv
import math

import numpy as np
import pytest

from shellbvp import ContinuationOptions, continuation

# Bratu u'' + lam e^u = 0, u(0) = u(1) = 0: the fold is at lam* = 3.513830719125161
# (Bratu 1914; lam* = 8 x^2 / cosh(x)^2 at the root of x tanh(x) = 1, 16 digits).
LAM_STAR = 3.513830719125161


class Bratu:
    def fun(self, x, y, p):
        return np.vstack([y[1], -p * np.exp(y[0])])

    def fun_jac(self, x, y, p):
        J = np.zeros((2, 2, x.size))
        J[0, 1] = 1.0
        J[1, 0] = -p * np.exp(y[0])
        return J

    def bc(self, ya, yb, p):
        return np.array([ya[0], yb[0]])

    def monitor(self, ya, yb):
        return ya[1]


def test_lam_star_reference_is_the_closed_form():
    from scipy.optimize import brentq

    x = brentq(lambda x: x * math.tanh(x) - 1, 0.5, 2.0)
    assert 8 * x**2 / math.cosh(x) ** 2 == pytest.approx(LAM_STAR, abs=1e-14)


@pytest.fixture(scope="module")
def bratu():
    x = np.linspace(0, 1, 11)
    return continuation(Bratu(), 0.0, x, np.zeros((2, 11)), p_stop=(-1, 5), n_folds=1,
                        options=ContinuationOptions(ds=0.2, ds_max=1.0, tol=1e-8,
                                                    fold_tol=1e-10))


def test_bratu_fold_to_1e_9(bratu):
    (fold,) = bratu.folds
    assert abs(fold.p - LAM_STAR) <= 1e-9
    assert fold.error_estimate <= 1e-9
    # Exact solution u = -2 log(cosh((x - 1/2) t/2) / cosh(t/4)), so u'(0) = t tanh(t/4); at
    # the fold t/4 = x* with x* tanh(x*) = 1, hence u'(0) = 4 exactly.
    assert fold.monitor == pytest.approx(4.0, abs=1e-8)


def test_fold_invariants(bratu):
    (fold,) = bratu.folds
    i, k = fold.bracket
    pts = bratu.points
    lo, hi = sorted((pts[i].monitor, pts[k].monitor))
    assert lo <= fold.monitor <= hi
    assert fold.p >= max(pts[i].p, pts[k].p)
    # dp/ds > 0 before the bracket and < 0 after it (the step into pts[k] when it is the last)
    assert pts[i].p - pts[i - 1].p > 0
    after = pts[k + 1].p - pts[k].p if k + 1 < len(pts) else pts[k].p - pts[k - 1].p
    assert after < 0


def test_continuation_passes_the_fold():
    x = np.linspace(0, 1, 11)
    res = continuation(Bratu(), 0.0, x, np.zeros((2, 11)), p_stop=(0.1, 5), monitor_stop=(-1, 12),
                       options=ContinuationOptions(ds=0.2, ds_max=1.0))
    p = np.array([pt.p for pt in res.points])
    m = np.array([pt.monitor for pt in res.points])
    assert np.all(np.diff(m) > 0)                    # monotone along the branch
    assert m[-1] > 12 or p[-1] < 0.1                 # it went round the fold onto the upper branch
    assert p.max() < LAM_STAR + 1e-12 and len(res.folds) == 1


@pytest.mark.parametrize("kw", [dict(ds=1.0, ds_max=0.5), dict(ds=1e-6, ds_min=1e-5),
                                dict(ds_min=0.0), dict(tol=0.0), dict(fold_tol=2.0),
                                dict(max_steps=1)])
def test_bad_options(kw):
    with pytest.raises(ValueError):
        ContinuationOptions(**kw)


def test_cap_branch_csv_round_trip(tmp_path):
    from problems import cap_eversion as ce

    br = ce.branch(math.pi / 6, 0.01, 1.0, kappa_max=0.6)
    path = tmp_path / "branch.csv"
    br.to_csv(path)
    with open(path) as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["kappa_R0", "w_over_R0", "energy", "stretching_energy",
                             "bending_energy", "arclength", "is_fold"]
    assert len(rows) == br.p.size
    assert np.allclose([float(r["kappa_R0"]) for r in rows], br.p, rtol=0, atol=0)
    assert np.allclose([float(r["w_over_R0"]) for r in rows], br.w, rtol=0, atol=0)
    assert abs(float(rows[0]["energy"])) < 1e-15 and br.energy[-1] > 1e-6
    assert np.allclose(br.energy, br.stretching_energy + br.bending_energy, rtol=1e-14)
    assert not list(tmp_path.glob("*.tmp"))


def test_branch_agrees_with_direct_solves():
    """Points of the continuation diagram are equilibria: a direct solve at the same kappa
    gives the same edge displacement (independent corrector, no arclength condition)."""
    from problems import cap_eversion as ce

    br = ce.branch(math.pi / 6, 0.01, 1.0, kappa_max=0.6)
    k, w = br.p[-1], br.w[-1]
    eq = ce.equilibrium(k, math.pi / 6, 0.01, 1.0)
    assert abs(eq.w - w) <= 1e-6
