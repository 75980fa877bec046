"""The continuation and fold machinery (shellbvp.continuation), tested on problems with
exactly known folds, independent of the shell equations:

* the scalar fold p = 2u - u^2 (fold at u = 1, p = 1);
* Bratu's problem u'' + p e^u = 0, u(0) = u(1) = 0, first as a hand-written Chebyshev system
  (the differentiation matrix is checked on its own first), then as a first-order BVP
  y = (u, u') handed to the package's methods through the same protocol as the shell BVP
  (Chebyshev and solve_bvp's collocation), with the refinement ladder's error estimate.
  The fold is p* = 3.513830719125161 (Bratu 1914; 8 x^2 / cosh(x)^2 at the root of
  x tanh x = 1, checked below), with u'(0) = 4 exactly there.

Then the cap's branch: CSV round trip, points that are equilibria, states kept by the results.
"""

import math

import numpy as np
import pytest

from shellbvp import Chebyshev, Collocation, ContinuationOptions, ConvergenceError
from bratu import BratuBVP
from shellbvp.continuation import (locate_fold, newton, polish_fold, pseudo_arclength,
                                   refine_fold)
from shellbvp.continuation.arclength import point_at_monitor, point_at_parameter
from shellbvp.continuation.folds import bracket_estimate
from shellbvp.methods.chebyshev import chebyshev_points, coefficients, differentiation_matrix
from shellbvp.problems import cap_eversion as ce

LAM_STAR = 3.513830719125161


def opts(ds, ds_max, **kw):
    return ContinuationOptions(ds=ds, ds_max=ds_max, ds_min=min(1e-5, ds), **kw)


def test_lam_star_reference_is_the_closed_form():
    from scipy.optimize import brentq

    x = brentq(lambda x: x * math.tanh(x) - 1, 0.5, 2.0)
    assert 8 * x**2 / math.cosh(x) ** 2 == pytest.approx(LAM_STAR, abs=1e-14)


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


class CountedBratu(ChebyshevBratu):
    """:class:`ChebyshevBratu` that counts its evaluations (the cost of a continuation)."""

    evaluations = 0

    def evaluate(self, U, p):
        self.evaluations += 1
        return super().evaluate(U, p)


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
    pts, brackets = pseudo_arclength(Scalar(), np.array([0.0]), 0.0, options=opts(0.1, 0.3),
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


def test_a_start_on_the_edge_of_p_stop_is_followed():
    """p0 on the edge of p_stop: the start's p is p0 only to round-off, on either side (a
    budding branch from kbar = 0 once ended at its start, p = -1e-28), so the start is
    exempt from the stop test and does not count as leaving the range; the branch ends on
    the far edge, exactly (its last step shortened onto it)."""
    for edge in (0.0, 1e-15, -1e-15):           # the start just inside, on, just outside
        pts, _ = pseudo_arclength(Scalar(), np.array([0.0]), 0.0, options=opts(0.1, 0.3),
                                  p_stop=(edge, 0.5))
        assert len(pts) > 2 and all(edge <= q.p <= 0.5 for q in pts[1:-1])
        assert pts[-1].p == 0.5                    # landed on the edge it left by


def test_the_last_step_lands_on_the_stop_it_crosses():
    """A branch that leaves p_stop or monitor_stop ends on the bound the last step crossed,
    solved with that coordinate prescribed: exactly there, on the branch (its residual
    converged), oriented as the step was, and the same state as the wide run's branch holds
    there (the steps are measured in fractions of the range asked for, so the points between
    differ; the branch is one)."""
    wide = dict(p_stop=(-1.0, 4.0), monitor_stop=(-1.0, 12.0))
    plain, _ = pseudo_arclength(CountedBratu(24), np.zeros(25), 0.0, options=opts(0.5, 2.0),
                                **wide)
    for stops in (dict(p_stop=(-1.0, 2.5)), dict(monitor_stop=(-1.0, 3.0))):
        system = CountedBratu(24)
        pts, _ = pseudo_arclength(system, np.zeros(25), 0.0, options=opts(0.5, 2.0),
                                  **(wide | stops))
        last = pts[-1]
        if "p_stop" in stops:
            assert last.p == 2.5
        else:
            assert abs(last.monitor - 3.0) <= 1e-10
        R, _, _ = system.evaluate(last.U, last.p)
        assert np.abs(R).max() <= 1e-8
        assert last.tangent[1] * pts[-2].tangent[1] > 0      # the same way along
        # the wide branch's own state there: its first crossing of the stop, solved exactly
        key = (lambda q: q.p - 2.5) if "p_stop" in stops else (lambda q: q.monitor - 3.0)
        i = next(i for i in range(len(plain) - 1) if key(plain[i]) * key(plain[i + 1]) <= 0)
        a, b = plain[i], plain[i + 1]
        f = key(a) / (key(a) - key(b))
        U = (1 - f) * a.U + f * b.U
        p = (1 - f) * a.p + f * b.p
        there = (point_at_parameter(system, U, p, 2.5, tol=1e-12) if "p_stop" in stops
                 else point_at_monitor(system, U, p, 3.0, tol=1e-12))
        assert abs(there.p - last.p) <= 1e-9 and abs(there.monitor - last.monitor) <= 1e-9


def test_predicted_stop_keeps_points_within_the_tolerance_for_fewer_evaluations():
    """``predicted_stop``: the corrector stops on the next update quadratic convergence
    predicts. On Bratu's branch every point is then within 10 newton_tol of the point
    solved to 1e-13 at its monitor (the plain corrector is ~newton_tol^2 off), the folds
    bracketed are the same, and it costs fewer evaluations."""
    runs = {}
    for predicted in (False, True):
        system = CountedBratu(24)
        o = opts(0.5, 2.0, newton_tol=1e-6, predicted_stop=predicted)
        pts, brackets = pseudo_arclength(system, np.zeros(25), 0.0, options=o,
                                         p_stop=(-1.0, 4.0), monitor_stop=(-1.0, 12.0))
        runs[predicted] = (system.evaluations, brackets, pts)
    (plain, b0, _), (fewer, b1, pts) = runs[False], runs[True]
    assert b1 == b0 and len(b1) == 1 and fewer < plain, (plain, fewer)
    for q in pts[1:]:
        exact = newton(ChebyshevBratu(24), q.U, q.p, 1.0, 0.0, q.monitor, tol=1e-13)
        assert exact.ok and abs(q.p - exact.p) <= 1e-5 * (1 + abs(q.p))


def test_fold_probe_brackets_the_fold_tightly_with_a_branch_point():
    """``fold_probe``: where the secant of dp/dm predicts the fold within the next step,
    the next point is taken with the monitor prescribed just past it. On Bratu's branch
    the probe brackets the fold (in the monitor u'(0), whose fold value is 4 exactly) with
    a branch point (the point solved to 1e-13 at its monitor), the fold located in either
    bracket is the closed form, and the probe costs fewer evaluations than the ordinary
    step it replaces (here that step happened to land just past the fold, so the bracket
    is no narrower; on the cap it is four times narrower, ``test_snap``)."""
    runs = {}
    for probe in (False, True):
        system = CountedBratu(24)
        o = opts(0.5, 2.0, fold_probe=probe)
        pts, brackets = pseudo_arclength(system, np.zeros(25), 0.0, options=o, n_folds=1,
                                         p_stop=(-1.0, 5.0))
        (i, j), = brackets
        fold = locate_fold(ChebyshevBratu(24), pts[i], pts[j])
        assert abs(fold.p - LAM_STAR) <= 1e-12
        assert pts[i].monitor < 4.0 < pts[j].monitor
        runs[probe] = (system.evaluations, pts[j])
    (plain, _), (probed, q) = runs[False], runs[True]
    assert probed < plain, (plain, probed)
    exact = newton(ChebyshevBratu(24), q.U, q.p, 1.0, 0.0, q.monitor, tol=1e-13)
    assert exact.ok and abs(q.p - exact.p) <= 1e-12


def test_fold_probe_is_a_checked_option():
    with pytest.raises(ValueError, match="fold_probe"):
        ContinuationOptions(fold_probe=1)


@pytest.fixture(scope="module")
def bratu():
    system = ChebyshevBratu(24)
    pts, brackets = pseudo_arclength(system, np.zeros(25), 0.0, options=opts(0.5, 2.0),
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
        pseudo_arclength(Scalar(), np.array([0.0]), 2.0)


class NoisyScalar(Scalar):
    """Scalar with a residual carrying uniform noise of size ``noise`` (round-off in a
    stiff problem's equations): Newton cannot get below ~noise / |dR/du|."""

    def __init__(self, noise):
        self.noise, self.rng = noise, np.random.default_rng(7)

    def evaluate(self, U, p):
        R, J, Rp = super().evaluate(U, p)
        return R + self.noise * self.rng.uniform(-1, 1), J, Rp


def test_newton_at_a_round_off_floor_converges_and_says_how_far():
    """Noise 1e-9 (below ROUND_OFF_STEP, above tol): two stalled updates in a row end the
    iteration as converged, p_noise the last update of p, and the answer is within it plus
    the noise of the exact p = 0.75 at u = 0.5 (monitor prescribed)."""
    res = newton(NoisyScalar(1e-9), np.array([0.6]), 0.7, 1.0, 0.0, 0.5, tol=1e-12)
    assert res.ok and 0 < res.p_noise < 1e-8
    assert res.p == pytest.approx(0.75, abs=1e-8)


def test_newton_stalled_above_the_floor_fails_with_a_diagnosis():
    """Noise 1e-5: the updates stall at ~1e-5, which is no converged answer; the failure
    says that they stall (round-off), not just that Newton failed."""
    res = newton(NoisyScalar(1e-5), np.array([0.6]), 0.7, 1.0, 0.0, 0.5, tol=1e-12,
                 fail_fast=False)
    assert not res.ok
    assert "stall" in res.diagnosis and "round-off" in res.diagnosis


def test_locate_fold_refuses_a_bracket_without_a_turn():
    pts, _ = pseudo_arclength(Scalar(), np.array([0.0]), 0.0, options=opts(0.1, 0.1),
                              p_stop=(-1.0, 0.5))
    with pytest.raises(ConvergenceError, match="does not change sign"):
        locate_fold(Scalar(), pts[0], pts[1])


def bratu_fold(method, fold_tol):
    system = method.discretise(BratuBVP())
    o = opts(0.5, 2.0, fold_tol=fold_tol)
    pts, brackets = pseudo_arclength(system, np.zeros(system.size), 0.0, options=o, n_folds=1,
                                     p_stop=(-1.0, 5.0))
    (i, j), = brackets
    return refine_fold(system, pts[i], pts[j], options=o, index=i)


def test_bratu_fold_through_the_chebyshev_method():
    fold = bratu_fold(Chebyshev(nodes=12), 1e-12)
    assert abs(fold.p - LAM_STAR) <= 1e-12
    assert fold.error_estimate <= 1e-12 and fold.stats["refinements"] >= 1
    assert fold.monitor == pytest.approx(4.0, abs=1e-8)


def test_bratu_fold_through_the_collocation_method_with_an_honest_estimate():
    """solve_bvp's 4th-order scheme: the ladder halves every interval until the fold moves by
    at most fold_tol; the estimate (the last change) bounds the true error, and the errors of
    successive rungs fall like h^4."""
    fold = bratu_fold(Collocation(nodes=11), 1e-9)
    assert abs(fold.p - LAM_STAR) <= fold.error_estimate <= 1e-9
    errs = []
    system = Collocation(nodes=11).discretise(BratuBVP())
    o = opts(0.5, 2.0)
    pts, ((i, j),) = pseudo_arclength(system, np.zeros(system.size), 0.0, options=o,
                                      n_folds=1, p_stop=(-1.0, 5.0))
    f = locate_fold(system, pts[i], pts[j])
    for _ in range(3):
        errs.append(abs(f.p - LAM_STAR))
        finer = f.system.refined()
        f = polish_fold(finer, f.system.transfer(f.U, f.p, finer), f.p, f.monitor)
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all((orders > 3.5) & (orders < 4.5)), orders


def test_bad_options_are_named():
    for kw, name in [(dict(ds=1.0, ds_max=0.5), "ds"), (dict(ds=1e-6, ds_min=1e-5), "ds"),
                     (dict(ds_min=0.0), "ds"), (dict(newton_tol=0.0), "newton_tol"),
                     (dict(fold_tol=2.0), "fold_tol"), (dict(max_steps=1), "max_steps"),
                     (dict(turn=0.0), "turn")]:
        with pytest.raises(ValueError, match=name):
            ContinuationOptions(**kw)


def test_bad_method_options_are_named():
    from shellbvp import Shooting

    for kw, name in [(dict(segments=0), "segments"), (dict(rtol=1e-20), "rtol"),
                     (dict(rtol=1e-8, bracket_rtol=1e-9), "bracket_rtol"),
                     (dict(bracket_rtol=0.5), "bracket_rtol"), (dict(steps=0), "steps")]:
        with pytest.raises(ValueError, match=name):
            Shooting(**kw)


@pytest.fixture(scope="module")
def cap_branch():
    return ce.branch(math.pi / 6, 0.01, 1.0, kappa_max=0.6)


def test_cap_branch_csv_round_trip(tmp_path, cap_branch):
    import csv

    br = cap_branch
    path = tmp_path / "branch.csv"
    br.to_csv(path)
    with open(path) as f:
        rows = list(csv.DictReader(f))
    assert list(rows[0]) == ["kappa_R0", "w_over_R0", "energy", "stretching_energy",
                             "bending_energy", "arclength", "is_fold", "kappa_R0_error",
                             "w_error_over_R0", "energy_error"]
    for name, values in (("kappa_R0_error", br.p_error), ("w_error_over_R0", br.w_error),
                         ("energy_error", br.energy_error)):
        assert np.array_equal([float(r[name]) for r in rows], values, equal_nan=True)
    assert len(rows) == br.p.size
    assert np.allclose([float(r["kappa_R0"]) for r in rows], br.p, rtol=0, atol=0)
    assert np.allclose([float(r["w_over_R0"]) for r in rows], br.w, rtol=0, atol=0)
    assert abs(float(rows[0]["energy"])) < 1e-15 and br.energy[-1] > 1e-6
    assert np.allclose([float(r["energy"]) for r in rows], br.energy, rtol=0, atol=0)
    assert not list(tmp_path.glob("*.tmp"))


def test_branch_energy_against_an_independent_quadrature(cap_branch):
    """The branch's energy at its last point against 2 pi int W sin s ds with W from the
    numpy energy density (shellbvp.energy_density, not the compiled one), at the
    equilibrium's principal state interpolated from its nodes (Chebyshev, degree 32) onto
    Gauss-Legendre points: agreement to 1e-8 relative. The apex cap s < eps, where W is
    that of the pole, adds ~W(eps) eps^2 / 2 (1e-8 relative at most)."""
    from numpy.polynomial.chebyshev import Chebyshev as Cheb

    from shellbvp import energy_density

    br = cap_branch
    eq = br.equilibrium(-1)
    kb = br.p[-1] - 1.0
    t = 2 * (eq.s - eq.s[0]) / (eq.s[-1] - eq.s[0]) - 1
    fits = [Cheb.fit(t, v, deg=t.size - 1) for v in (eq.lam1, eq.lam2, eq.k1, eq.k2)]
    x, wq = np.polynomial.legendre.leggauss(80)
    s = eq.s[0] + (x + 1) / 2 * (eq.s[-1] - eq.s[0])
    W = energy_density(*(f(x) for f in fits), kb, kb, h=0.01, lam=1.0)
    E = 2 * np.pi * np.sum(wq * W * np.sin(s)) * (eq.s[-1] - eq.s[0]) / 2
    assert E == pytest.approx(br.energy[-1], rel=1e-8)
    assert br.stretching_energy[-1] + br.bending_energy[-1] == pytest.approx(E, rel=1e-8)


def test_branch_points_are_equilibria_and_keep_their_states(cap_branch):
    """A direct solve at the last kappa of the branch (no arclength condition, another
    corrector) gives the same state as branch.equilibrium(-1), which needs no solve."""
    br = cap_branch
    kept = br.equilibrium(-1)
    eq = ce.equilibrium(br.p[-1], math.pi / 6, 0.01, 1.0, method=Collocation(tol=1e-9))
    assert abs(eq.w - br.w[-1]) <= 1e-8 and kept.w == pytest.approx(br.w[-1], abs=1e-15)
    s = np.linspace(eq.s[0], math.pi / 6, 50)
    assert np.max(np.abs(kept(s) - eq(s))) <= 1e-7
    assert kept.energy == pytest.approx(br.energy[-1], rel=1e-12)
    with pytest.raises(ValueError, match="index"):
        br.equilibrium(br.p.size)


def test_fold_keeps_its_state():
    """The state a fold keeps solves the BVP at kappa_s as another discretisation sees it:
    solve_bvp's collocation residual (fine fixed mesh) of the fold's equilibrium is at the
    level of that mesh's truncation (6e-9 at 801 nodes), a thousandth of the residual of the
    same state with kappa moved by 1e-4 (what a state of another kappa would leave)."""
    r = ce.snap_curvature(math.pi / 6, 0.01, 1.0)
    eq = r.fold.equilibrium
    assert eq.stats["resolution"]["nodes"] > 24          # the finest rung of the ladder
    system = Collocation(nodes=801).discretise(r.fold.system.bvp)
    U = system.from_profile(eq.unknowns)
    at_fold = np.max(np.abs(system.evaluate(U, r.kappa_s)[0]))
    moved = np.max(np.abs(system.evaluate(U, r.kappa_s + 1e-4)[0]))
    assert at_fold < 1e-3 * moved, (at_fold, moved)


def test_ladder_estimate_survives_an_error_that_crosses_zero():
    """The refinement ladder (``climb``) on a synthetic sequence of rungs whose fold error
    oscillates in sign with the degree, the sequence measured on a thick deep plane-strain
    cap (h = 0.124, Theta = 1.96): errors -1.0e-9, 6.7e-12, 1.8e-11, -3.6e-12 at N = 36,
    40, 44, 48. A single change within tol = 1e-10 (40 -> 44: 1.1e-11) would have stopped
    at 44 with an estimate below its error; two consecutive changes go on to 48, whose
    estimate (2.2e-11) bounds its error (3.6e-12)."""
    from dataclasses import dataclass

    from shellbvp.continuation.folds import climb
    from shellbvp.results import Fold

    exact = 3.13545366550586
    errors = {36: -1.0e-9, 40: 6.7e-12, 44: 1.8e-11, 48: -3.6e-12, 52: 3.3e-13}

    @dataclass(frozen=True)
    class Rung:
        N: int

        def refined(self):
            return Rung(self.N + 4)

        def describe(self):
            return {"method": "synthetic", "nodes": self.N}

    stats = dict(solves=1, newton_iterations=1, round_off=0.0, location=0.0, curvature=-1.0)

    def fold_on(rung):
        return Fold(p=exact + errors[rung.N], monitor=0.5, U=None, system=rung,
                    stats=dict(stats))

    first = Rung(36)
    fold = climb(first, first, fold_on(first), lambda finer, current: fold_on(finer),
                 options=ContinuationOptions(fold_tol=1e-10), index=-1, t0=0.0,
                 location_weight=1.0)
    assert fold.system.N == 48
    assert fold.error_estimate == pytest.approx(abs(errors[48] - errors[44]))
    assert abs(fold.p - exact) <= fold.error_estimate


def test_bracket_estimate_is_the_stationary_point_of_the_cubic_hermite_interpolant():
    """The fold seed between two branch points, in closed form, against scipy's
    CubicHermiteSpline (the independent route it replaced): the first stationary point in
    the bracket and d2p/dm2 there, on 500 random brackets with opposite slopes (a fold
    inside: exactly one stationary point) and with slopes of one sign (none or two: the
    midpoint, or the one of smaller m; scipy lists roots unsorted)."""
    from types import SimpleNamespace
    from scipy.interpolate import CubicHermiteSpline

    rng = np.random.default_rng(20261202)
    for k in range(500):
        ma, mb = np.sort(rng.normal(size=2))
        pa, pb = rng.normal(size=2)
        ga, gb = rng.normal(size=2)
        if k % 2 == 0:
            ga, gb = abs(ga), -abs(gb)
        cubic = CubicHermiteSpline([ma, mb], [pa, pb], [ga, gb])
        roots = cubic.derivative().roots(extrapolate=False)
        roots = roots[np.isfinite(roots)]
        m_ref = float(roots.min()) if roots.size else (ma + mb) / 2
        a = SimpleNamespace(monitor=ma, p=pa, slope=ga)
        b = SimpleNamespace(monitor=mb, p=pb, slope=gb)
        m, c = bracket_estimate(b, a)          # either order
        assert m == pytest.approx(m_ref, rel=1e-9, abs=1e-9)
        assert c == pytest.approx(float(cubic(m_ref, 2)), rel=1e-8, abs=1e-8)
