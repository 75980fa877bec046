"""The Chebyshev (spectral) method and the snap curvature it computes.

References, all independent of the spectral code: the undeformed cap (closed form); the
collocation method (scipy's solve_bvp) for an equilibrium; the shooting method (diffrax)
for kappa_s; convergence of kappa_s under refinement (geometric for a spectral method); the
mirror symmetry of the free cap (z -> -z with kappa -> 2 - kappa, which maps w to 2H - w).
"""

import math
from functools import lru_cache

import numpy as np
import pytest

from shellbvp import (Chebyshev, Collocation, ContinuationOptions, Shooting, cap,
                      solve)
from shellbvp.bvp import ShellBVP
from shellbvp.continuation import locate_fold, newton, polish_fold, pseudo_arclength
from shellbvp.problems import cap_eversion as ce

THETA, H0 = math.pi / 6, 0.01
CAP = cap(THETA, H0, lam=1.0, model="relaxed", material="cg")
RISE = 1.0 - math.cos(THETA)
LONG = ContinuationOptions(ds=0.5, ds_max=100.0)


def cheb(N, scene=CAP):
    return Chebyshev(nodes=N).discretise(ShellBVP(scene))


@lru_cache(maxsize=None)
def kappa_s(nodes):
    """kappa_s located on one discretisation (no refinement), from continuation at N = 24."""
    base = cheb(24)
    pts, brackets = pseudo_arclength(base, base.from_profile(base.bvp.reference), 0.0,
                                     options=LONG, n_folds=1)
    (i, j), = brackets
    fold = locate_fold(base, pts[i], pts[j])
    if nodes == 24:
        return fold
    system = cheb(nodes)
    return polish_fold(system, base.transfer(fold.U, fold.p, system), fold.p, fold.monitor)


def test_zero_stimulus_is_the_undeformed_cap():
    eq = solve(CAP, 0.0, method=Chebyshev(nodes=24), estimate_error=False)
    assert np.max(np.abs(eq.theta - eq.s)) < 1e-12
    assert np.max(np.abs(eq.r - np.sin(eq.s))) < 1e-12
    assert abs(eq.w) < 1e-12


@pytest.mark.slow  # minutes; the default suite keeps a faster check of the same kind
def test_spectral_equilibrium_agrees_with_collocation():
    ref = ce.equilibrium(3.0, THETA, H0, method=Collocation(tol=1e-8))
    eq = solve(CAP, 3.0, method=Chebyshev(nodes=32), guess=ref)
    s = np.linspace(1e-3, THETA, 101)
    assert np.max(np.abs(eq(s)[:3] - ref(s)[:3])) < 1e-7
    assert abs(eq.w - ref.w) < 1e-8
    assert eq.error_estimate < 1e-10          # N = 32 against N = 40
    assert eq.energy == pytest.approx(ref.energy, rel=1e-7)


def test_kappa_s_converges_geometrically_in_the_chebyshev_degree():
    ref = kappa_s(48).p
    err = {N: abs(kappa_s(N).p - ref) for N in (24, 32, 40)}
    # Each +8 nodes gains more than two orders of magnitude (observed ~230x at 24 -> 32).
    assert err[24] / err[32] > 100
    assert err[32] < 1e-9
    assert err[40] < 1e-11
    rate = math.log(err[24] / err[32]) / 8
    assert 0.5 < rate < 1.5, rate     # observed convergence rate ~0.68 per node


def test_snap_curvature_error_estimate_bounds_the_error():
    r = ce.snap_curvature(THETA, H0, 1.0, tol=1e-9)
    assert r.snaps
    assert r.error_estimate <= 1e-9
    assert abs(r.kappa_s - kappa_s(48).p) <= max(r.error_estimate, 1e-12)
    # The fold is the maximum of kappa along the branch: nearby states have smaller kappa.
    system = kappa_s(40).system
    for dm in (-1e-3, 1e-3):
        m = r.w_s / RISE + dm
        res = newton(system, kappa_s(40).U, r.kappa_s, 1.0, 0.0, m)
        assert res.ok and res.p < r.kappa_s


@pytest.mark.slow  # minutes; the default suite keeps a faster check of the same kind
@pytest.mark.parametrize("method,tol", [("shooting", 1e-9),
                                        # the branch at rtol 1e-5 only brackets the fold
                                        (Shooting(rtol=1e-8), 1e-7)])
def test_spectral_and_shooting_agree_on_kappa_s(method, tol):
    a = ce.snap_curvature(THETA, H0, 1.0, tol=1e-9)
    b = ce.snap_curvature(THETA, H0, 1.0, method=method, tol=tol)
    assert abs(a.kappa_s - b.kappa_s) <= 1e-7, (a.kappa_s, b.kappa_s)
    assert abs(a.w_s - b.w_s) <= 1e-6
    assert b.error_estimate <= 1e-7


def test_mirror_branch_is_the_point_reflection_of_the_primary_branch():
    """kappa(2H - w) = 2 - kappa(w): the branch from the everted state (kappa = 2, w = 2H)
    downwards is the point reflection of the branch from the undeformed cap, fold included."""
    primary = kappa_s(40)
    system = cheb(40)
    everted = solve(CAP, 2.0, method=Chebyshev(nodes=40), estimate_error=False,
                    guess=lambda s: np.stack([np.sin(s), 1 - np.cos(s), -s, 0 * s, 0 * s,
                                              0 * s]))
    assert abs(everted.w - 2 * RISE) < 1e-10  # the target shape, reached exactly
    pts, brackets = pseudo_arclength(system, system.from_profile(everted.unknowns), 2.0,
                                     options=LONG, n_folds=1, direction=-1.0)
    (i, j), = brackets
    mirror = locate_fold(system, pts[i], pts[j])
    assert mirror.p == pytest.approx(2.0 - primary.p, abs=1e-10)
    assert mirror.monitor == pytest.approx(2.0 - primary.monitor, abs=1e-8)


@pytest.mark.slow
def test_shallow_cap_branch_is_point_symmetric_about_the_flat_state():
    """For a shallow cap (T = 2.5) the branch from kappa = 0 passes through the flat state
    (w = H, kappa = 1) and is itself point-symmetric: its two folds are each other's
    reflection and kappa(m) + kappa(2 - m) = 2 along it (m = w / H)."""
    T = 2.5
    b = ce.branch(T * math.sqrt(H0), H0, 1.0, n_folds=2, energies=False)
    H = 1.0 - math.cos(T * math.sqrt(H0))
    f1, f2 = b.folds
    assert f1.p + f2.p == pytest.approx(2.0, abs=1e-9)
    assert (f1.w + f2.w) / H == pytest.approx(2.0, abs=1e-8)
    sc = ce.scene(T * math.sqrt(H0), H0)
    system = cheb(24, sc)
    pts, _ = pseudo_arclength(system, system.from_profile(system.bvp.reference), 0.0,
                              options=ContinuationOptions(ds=0.2, ds_max=1.0),
                              monitor_stop=(-1.0, 2.0))
    ms = np.array([q.monitor for q in pts])
    checked = 0
    for q in pts:
        if 0.05 < q.monitor < 0.95:
            near = pts[int(np.argmin(np.abs(ms - (2.0 - q.monitor))))]
            res = newton(system, near.U, near.p, 1.0, 0.0, 2.0 - q.monitor)
            assert res.ok
            assert q.p + res.p == pytest.approx(2.0, abs=1e-9)
            checked += 1
    assert checked >= 3
    flat = min(pts, key=lambda q: abs(q.monitor - 1.0))
    res = newton(system, flat.U, flat.p, 1.0, 0.0, 1.0)
    assert res.ok and res.p == pytest.approx(1.0, abs=1e-10)


def test_bad_nodes_are_named():
    with pytest.raises(ValueError, match="nodes"):
        Chebyshev(nodes=4)
    with pytest.raises(ValueError, match="nodes"):
        Chebyshev(nodes=401)


def test_monitor_gradient_matches_finite_differences():
    """dm/dU (used in every bordered solve) against central differences of m itself."""
    system = cheb(24)
    rng = np.random.default_rng(0)
    U = system.from_profile(system.bvp.reference) + 1e-2 * rng.standard_normal(system.size)
    _, g = system.monitor(U)
    fd = np.empty_like(g)
    for k in range(U.size):
        e = np.zeros_like(U)
        e[k] = 1e-6
        fd[k] = (system.monitor(U + e)[0] - system.monitor(U - e)[0]) / 2e-6
    assert np.max(np.abs(g - fd)) < 1e-7


def test_inner_warm_start_is_carried_to_second_order_from_the_states_it_was_taken_at():
    """The inner roots (lam1, k1) of one evaluation, carried to the next iterate along their
    implicit derivative (:func:`shellbvp.nodal.carried_roots`), start the next inner Newton
    O(change^2) from its roots; the warm start keeps the states it was taken at even when
    the outer Newton updates its unknowns in place (it once held a view of them, and the
    roots were then carried by the change in p alone)."""
    from shellbvp.nodal import carried_roots, flat_nodes

    fold = kappa_s(24)
    system = cheb(24)
    direction = system.from_profile(system.bvp.reference) - fold.U
    errors = []
    for size in (1e-3, 1e-4):
        # each change from the fold's own states (U - a + a is not U to the last bit)
        U = fold.U.copy()
        system.evaluate(U, fold.p)
        hint = system._hint
        taken_at = flat_nodes(system.states(U))
        assert not np.shares_memory(hint.y, U)
        U -= size * direction                      # in place, as Newton updates its iterate
        assert np.array_equal(hint.y, taken_at)
        y_new = flat_nodes(system.states(U))
        start = carried_roots(hint, y_new, fold.p)
        system.evaluate(U, fold.p)                 # its roots at the new states
        roots = system._hint.q
        errors.append(np.max(np.abs(start - roots) / (1.0 + np.abs(roots))))
    # second order: a 10x smaller change leaves a ~100x smaller start error
    assert errors[1] < errors[0] / 30, errors


@pytest.mark.parametrize("N, M", [(24, 28), (32, 24), (36, 36), (9, 40)])
def test_regridding_matrix_interpolates_polynomials_exactly(N, M):
    """Carrying values between Chebyshev degrees (the fold ladder's rungs) by the
    barycentric matrix: exact for a polynomial of degree N (closed form at the new points),
    and the interpolant of the DCT route (coefficients, then Clenshaw) for any values."""
    from shellbvp.methods.chebyshev import (chebyshev_points, coefficients, evaluate,
                                            regridding_matrix)

    rng = np.random.default_rng(N + M)
    c = rng.standard_normal(N + 1)
    poly = np.polynomial.Polynomial(c, domain=[0.0, 1.0])
    moved = poly(chebyshev_points(N)) @ regridding_matrix(N, M).T
    assert np.max(np.abs(moved - poly(chebyshev_points(M)))) < 1e-12 * np.sum(np.abs(c))
    values = rng.standard_normal((6, N + 1))
    via_dct = evaluate(coefficients(values), chebyshev_points(M))
    assert np.max(np.abs(values @ regridding_matrix(N, M).T - via_dct)) < 1e-13
