"""The fold system (equilibrium and dp/dm = 0) with exact second derivatives: its
derivatives against finite differences, Newton's order, folds against the branch route, and
the onset as the cusp of the fold curve against the root of the flat-state slope."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

import shellbvp
import shellbvp.bvp
from shellbvp.continuation import fold_system_terms, solve_fold
from shellbvp.continuation.newton import bordered_lu
from shellbvp.problems import cap_eversion as ce

H0 = 0.01


@pytest.fixture(scope="module")
def fold():
    """The snap fold of the cap at T = 4 (degree 24 after the ladder at tol 1e-6)."""
    return ce.snap_curvature(0.4, H0, 1.0, tol=1e-6).fold


def sigma(system, U, p):
    """dp/dm from the bordered system, computed plainly (the quantity differentiated). The
    state is evaluated twice: the Jacobian comes from the inner root's last Newton iterate,
    which after a warm start from another state may be ~1e-8 from the root (noise of that
    size in sigma, amplified by the differences); from the root itself it is exact."""
    system.evaluate(U, p)
    R, J, Rp = system.evaluate(U, p)
    _, gm = system.monitor(U)
    e = np.zeros(U.size + 1)
    e[-1] = 1.0
    return bordered_lu(J, Rp, gm, 0.0).solve(e)[-1]


def smooth_direction(fold, rng):
    """A direction in the unknowns that keeps the pole regular: the fold's displacement from
    the reference state, reshaped along the meridian by random smooth factors (a random
    vector would move r(eps) ~ 4e-5 through zero)."""
    system = fold.system
    disp = system.split(fold.U - system.from_profile(system.bvp.reference))
    a, b = rng.uniform(-1, 1, (2, 6, 1))
    return (disp * (1 + a * np.cos(3 * b * system.s[:, None, :]))).ravel()


def central(f, e):
    """Fourth-order central difference of f at 0 with step e (error ~ e^4 f^(5))."""
    return (-f(2 * e) + 8 * f(e) - 8 * f(-e) + f(-2 * e)) / (12 * e)


def test_fold_function_derivatives_equal_finite_differences(fold):
    """d sigma/d(U, p, theta) from the exact second derivatives (JAX, along the inner root)
    against fourth-order central differences of sigma itself, at a state off the branch
    (sigma != 0, so every term of the formula counts): relative 1e-6."""
    system = fold.system
    rng = np.random.default_rng(7)

    def direction():
        return smooth_direction(fold, rng)

    U, p = fold.U + 0.05 * direction(), fold.p + 0.01
    *_, s0, sU, sp, sth, _, _ = fold_system_terms(system, U, p, theta=True)
    assert abs(s0) > 1e-3
    for _ in range(2):
        d = direction()
        fd = central(lambda e: sigma(system, U + e * d, p), 1e-4)
        assert abs(sU @ d - fd) <= 1e-6 * abs(fd), (sU @ d, fd)
    fd = central(lambda e: sigma(system, U, p + e), 1e-4)
    assert abs(sp - fd) <= 1e-6 * abs(fd), (sp, fd)
    sc = system.bvp.scene

    def at(e):
        return sigma(system.on(shellbvp.bvp.ShellBVP(sc.with_length(sc.length + e))), U, p)

    fd = central(at, 1e-4)
    assert abs(sth - fd) <= 1e-6 * abs(fd), (sth, fd)


def test_fold_newton_converges_quadratically(fold):
    """From a state 1e-3 off the fold the updates fall with order >= 1.8 (measured 2.2), to
    the fold the branch route found on the same system; the pivot is d2p/dm2, which the
    branch route estimates from secants of dp/dm (a few digits)."""
    system = fold.system
    rng = np.random.default_rng(3)
    start = fold.U + 1e-3 * smooth_direction(fold, rng)
    f = solve_fold(system, start, fold.p + 1e-3, tol=1e-14)
    steps = [h[2] for h in f.stats["history"]]
    # observed order log(s3 / s2) / log(s2 / s1) of successive updates (2: Newton)
    orders = [math.log(steps[k + 2] / steps[k + 1]) / math.log(steps[k + 1] / steps[k])
              for k in range(len(steps) - 2) if steps[k + 2] > 1e-14]
    assert len(orders) >= 1 and min(orders) >= 1.8, steps
    assert abs(f.p - fold.p) <= 1e-11
    assert abs(f.monitor - fold.monitor) <= 1e-8
    assert f.stats["curvature"] == pytest.approx(fold.stats["curvature"], rel=1e-3)


def test_a_finer_rung_takes_one_update_where_its_error_bound_allows(fold):
    """A fold carried to the next degree (``transfer``) is re-solved in one update where
    the error that update can leave is below the tolerance (from degree 24 on here;
    20 -> 24 moves the fold too far), to the fold a converged Newton (tol 1e-14, never one
    update) finds from the same state with cold inner roots: 1e-12 apart on every rung.
    The bound counts the Jacobian's error, round-off here (derivatives at the inner roots
    themselves); the same state with inner roots carried or cold gives the same Jacobian
    to ~1e-12 relative."""
    current = solve_fold(fold.system, fold.U, fold.p)
    updates = []
    for _ in range(3):
        finer = current.system.refined()
        start = current.system.transfer(current.U, current.p, finer)
        assert finer.jacobian_error == 0.0
        carried = solve_fold(finer, start, current.p, refining=True)
        warm = finer.on(finer.bvp)
        current.system.transfer(current.U, current.p, warm)      # roots carried
        J_warm = warm.evaluate(start, current.p)[1]
        J_cold = finer.on(finer.bvp).evaluate(start, current.p)[1]
        assert np.max(np.abs(J_warm - J_cold)) <= 1e-11 * np.max(np.abs(J_cold))
        cold = solve_fold(finer.on(finer.bvp), start, current.p, tol=1e-14)
        assert cold.stats["newton_iterations"] >= 2
        assert abs(carried.p - cold.p) <= 1e-12
        updates.append(carried.stats["newton_iterations"])
        current = carried
    assert updates[1:] == [1, 1], updates


def test_onset_is_the_cusp_of_the_fold_curve():
    """onset() follows the fold curve in (T, kappa) with w prescribed up to w = H; the
    independent route is today's: the root of the flat-state slope dkappa/dw (each value
    from a branch solved at w = H) by Brent's method, on the same degree. At the cusp the
    fold's kappa is 1 (the mirror symmetry; not imposed)."""
    o = ce.onset(H0, 1.0)
    N = o.stats["nodes"]
    T_brent = brentq(lambda T: ce.flat_slope(T, H0, 1.0, nodes=N), *o.bracket, xtol=1e-12)
    assert abs(o.T - T_brent) <= 1e-8, (o.T, T_brent)
    assert abs(o.kappa - 1.0) <= 1e-9
    assert o.error_estimate < 1e-5


def test_fold_curve_point_rejects_bad_input(fold):
    with pytest.raises(ValueError, match="step"):
        shellbvp.fold_curve_point(fold, 1.0, step=0.0)
    with pytest.raises(ValueError, match="monitor"):
        shellbvp.fold_curve_point(fold, math.nan)
    from dataclasses import replace

    # a fold of a discretisation without second derivatives (shooting, collocation)
    with pytest.raises(ValueError, match="spectral"):
        shellbvp.fold_curve_point(replace(fold, system=object()), 1.0)
