"""Past the first bifurcation (shellbvp.postbuckling) against independent routes.

References: the bifurcation found by shellbvp.first_instability (axisymmetric equilibria of
the spectral Euler-Lagrange method, the per-harmonic second variation of
shellbvp.harmonics, Brent's method on its lowest eigenvalue: another discretisation and
another solver); Koiter's p2 against the curvature of p(a) fitted to lobed equilibria
solved by Newton with the amplitude prescribed (the computed branch, not the expansion);
the lobed states' stationarity under an independent quadrature in omega (the trapezoidal
rule over the whole circle with more points than the class needs).
"""

import math
from functools import lru_cache

import numpy as np
import pytest

import shellbvp
from shellbvp import postbuckling as pb
from shellbvp.continuation import point_at_monitor
from shellbvp.problems import cap_eversion as ce

THETA, H0 = math.pi / 6, 0.01


@lru_cache(maxsize=None)
def instability():
    return ce.first_instability(THETA, H0, 1.0)


@lru_cache(maxsize=None)
def setup(K=2, degree=None):
    ins = instability()
    f = pb.Fourier2D(ins.equilibrium, ins.n, K, degree=degree)
    crit = pb.critical_point(f, ins.p)
    k, psi, dy0 = pb.koiter(f, crit, direction=1.0)
    return f, crit, k, psi, dy0


def lobed_state(a, K=2, degree=None):
    """The lobed equilibrium at mass-norm amplitude a (Newton with a prescribed, from
    Koiter's prediction)."""
    f, (p_c, y_c, phi, _), k, psi, dy0 = setup(K, degree)
    system = pb.LobedSystem(f, phi)
    dp = k.p2 * a**2
    pt = point_at_monitor(system, y_c + dp * dy0 + a * phi + a**2 * psi, p_c + dp, a, tol=1e-11)
    return f, pt


@pytest.mark.slow
def test_the_bifurcation_is_first_instabilitys():
    """The 2D discretisation's p_c (root of its block-n eigenvalue along its own
    axisymmetric branch) against first_instability's (another discretisation, another root
    finder), within the latter's error estimate; the mode is n = 3."""
    ins = instability()
    f, (p_c, *_), k, *_ = setup()
    assert ins.kind == "bifurcation" and ins.n == 3
    assert abs(p_c - ins.p) <= ins.error_estimate, (p_c, ins.p, ins.error_estimate)


@pytest.mark.slow
def test_the_eigenvalues_rate_is_its_central_difference():
    """mu_n'(p_c) from the Hessian's exact rate along the axisymmetric branch against
    central differences of mu_n with Richardson's extrapolation (steps 2e-3 and 1e-3: mu_n's
    round-off, ~5e-11, spoils smaller ones): 1e-7."""
    f, (p_c, y_c, _, mu_p), *_ = setup()

    def mu(p):
        return pb._lowest(f, pb._axisymmetric(f, p, y_c)[0], p)[0]

    D = [(mu(p_c + d) - mu(p_c - d)) / (2 * d) for d in (2e-3, 1e-3)]
    assert mu_p == pytest.approx((4 * D[1] - D[0]) / 3, rel=1e-7), D


def test_koiter_p2_matches_the_computed_branch():
    """p - p_c = p2 a^2 + c a^4 fitted to lobed equilibria at a = 2e-4 .. 8e-4: its p2
    against the expansion's, within 2 % (the issue's bound); the cap is subcritical (the
    lobed branch turns back to lower curvature: it snaps at the bifurcation)."""
    f, crit, k, *_ = setup()
    a = np.array([2e-4, 4e-4, 6e-4, 8e-4])
    dp = np.array([lobed_state(x)[1].p for x in a]) - crit[0]
    fit = np.polyfit(a**2, dp, 2)        # c a^4 + p2 a^2 + const
    assert abs(fit[1] / k.p2 - 1) < 0.02, (fit, k.p2)
    assert abs(fit[2]) < 1e-3 * abs(k.p2) * a[0] ** 2       # through the bifurcation
    assert k.kind == "subcritical" and k.p2 < 0 and k.a == 0.0


def test_lobed_states_are_stationary_under_an_independent_quadrature():
    """A lobed state (a = 5e-3, far from the bifurcation: harmonic 2n of size 5e-4) has a
    zero gradient under the trapezoidal rule over the whole circle with 4x the points
    (another rule: on [0, 2 pi) instead of the half period), to 1e-9 of the gradient's
    scale; and its energy is the same."""
    f, pt = lobed_state(5e-3)
    g = f.with_points(4 * f.points, full_period=True)
    scale = np.linalg.norm(f.gradient(pt.U + 1e-3 * f.split(pt.U)[1].max()
                                      * np.ones(f.size) / f.size, pt.p))
    assert np.linalg.norm(g.gradient(pt.U, pt.p)) < 1e-9 * max(scale, 1.0)
    assert abs(g.energy(pt.U, pt.p) - f.energy(pt.U, pt.p)) < 1e-12 * abs(f.energy(pt.U, pt.p))


def test_parameter_gradient_and_higher_derivatives_against_differences():
    """dG/dp, E''' and E'''' (JAX jvps) against central differences of the exact lower
    derivative at a smooth lobed state along smooth directions (the critical mode and psi)."""
    f, (p_c, y_c, phi, _), k, psi, _ = setup()
    _, pt = lobed_state(2e-3)
    y, p = pt.U, pt.p
    d = 1e-6
    fd = (f.gradient(y, p + d) - f.gradient(y, p - d)) / (2 * d)
    exact = f.parameter_gradient(y, p)
    assert np.linalg.norm(fd - exact) < 1e-6 * np.linalg.norm(exact)
    u, v = phi, psi / np.linalg.norm(psi)
    e = 1e-5
    fd3 = (f.hessian(y + e * v, p) @ u - f.hessian(y - e * v, p) @ u) / (2 * e)
    t3 = f.third(y, u, v, p)
    assert np.linalg.norm(fd3 - t3) < 1e-5 * np.linalg.norm(t3)
    fd4 = (u @ f.third(y + e * u, u, u, p) - u @ f.third(y - e * u, u, u, p)) / (2 * e)
    assert abs(fd4 - f.fourth(y, u, p)) < 1e-5 * abs(fd4)


@pytest.mark.slow
def test_koiter_converges_in_the_cutoff_and_the_degree():
    """p2 with K = 1, 2, 3 and degree 24, 32: the change from K = 2 to 3 is far smaller than
    from 1 to 2, and the degree's change is below 1e-4 relative."""
    p2 = {(K, d): setup(K, d)[2].p2 for K in (1, 2, 3) for d in (24, 32)}
    assert abs(p2[3, 24] - p2[2, 24]) < 0.1 * abs(p2[2, 24] - p2[1, 24])
    assert abs(p2[2, 32] / p2[2, 24] - 1) < 1e-4


def test_follow_bifurcation_switches_onto_the_lobed_branch():
    """The public route: a short lobed branch from first_instability's bifurcation, its
    first point on Koiter's parabola, p decreasing (subcritical), amplitude growing, the
    harmonics 0 and 2n of the second order (a^2) where n's is a."""
    br = shellbvp.follow_bifurcation(instability(), options=pb.LOBED_OPTIONS.with_(
        max_steps=6), estimate_error=False)
    assert br.koiter.kind == "subcritical" and br.snap == br.p_c
    assert np.all(np.diff(br.p) < 0) and np.all(np.diff(br.amplitude) > 0)
    a = br.amplitude[0]
    assert abs(br.p[0] - br.koiter.p_of(a)) < 0.02 * abs(br.koiter.p2) * a**2
    assert br.harmonics[0, 1] == pytest.approx(a, rel=1e-3)
    assert br.harmonics[0, 2] < 10 * a**2 and br.harmonics[0, 0] < 100 * a**2
    cols = br.columns()
    assert set(cols) == {"kappa", "amplitude", "harmonic_0", "harmonic_3", "harmonic_6"}
    with pytest.raises(ValueError, match="xi must be"):
        br.imperfect_limit(-0.1)


@pytest.mark.parametrize("bad, message", [
    (dict(K=0), "K must be"), (dict(n_folds=-1), "n_folds"),
    (dict(amplitude_max=0.0), "amplitude_max"), (dict(start=-1.0), "start")])
def test_bad_arguments_are_refused(bad, message):
    with pytest.raises(ValueError, match=message):
        shellbvp.follow_bifurcation(instability(), **bad)


def test_an_instability_that_is_not_a_bifurcation_is_refused():
    from dataclasses import replace

    with pytest.raises(ValueError, match="kind 'bifurcation'"):
        shellbvp.follow_bifurcation(replace(instability(), kind="fold"))


def test_imperfection_force_gamma_against_differences():
    """Koiter's gamma = phi . dG/de (a jvp through the imperfect reference's forms) against
    central differences of phi . G of shells built with amplitudes +-e (the whole imperfect
    route: reconstructed surface, its forms, the changed targets and area element); an
    amplitude of zero is the perfect shell to round-off."""
    f, (p_c, y_c, phi, _), k, *_ = setup()
    e = 1e-5
    g = [phi @ f.imperfect(phi, s * e).gradient(y_c, p_c) for s in (1, -1)]
    assert (g[0] - g[1]) / (2 * e) == pytest.approx(k.gamma, rel=1e-8)
    assert k.gamma != 0
    perfect = f.imperfect(phi, 0.0)
    assert np.max(np.abs(perfect.gradient(y_c, p_c) - f.gradient(y_c, p_c))) < 1e-12


@pytest.mark.slow
def test_koiter_limit_load_against_directly_computed_imperfect_shells():
    """Koiter's leading-order limit load p_c + 3 p2 a_s^2 against the fold of the imperfect
    shell's own equilibria (imperfect_limit: continuation from below p_c to the fold, not the
    expansion), imperfection amplitudes 1e-3 and 1e-2 of the thickness: the drops p_c - p_s
    agree to 2 % at 1e-3, and the disagreement shrinks as the amplitude does (the expansion
    is asymptotic in e)."""
    f, crit, k, *_ = setup()
    ratio = []
    for xi in (1e-2, 1e-3):       # Koiter's through knockdown(xi) = p_s / p_c, e = xi h / w_max
        fold = pb.imperfect_limit(f, crit, k, xi * k.h / k.w_max)
        ratio.append((1 - fold.p / k.p_c) / (1 - float(k.knockdown(xi))))
    assert abs(ratio[1] - 1) < 0.02 and abs(ratio[1] - 1) < 0.5 * abs(ratio[0] - 1), ratio


def test_imperfect_arguments_are_refused():
    f, crit, k, *_ = setup()
    with pytest.raises(ValueError, match="shape must be"):
        f.imperfect(np.zeros(3), 1e-3)
    with pytest.raises(ValueError, match="amplitude must be"):
        f.imperfect(crit[2], math.nan)
    with pytest.raises(ValueError, match="amplitude must be"):
        pb.imperfect_limit(f, crit, k, 0.0)


@pytest.mark.slow
def test_a_far_lobed_fold_carries_its_cutoff_error():
    """Relaxed CG, lam = 1, T = 6: the lobed fold lies far from the bifurcation (amplitude
    ~0.012), where K = 2 harmonics do not suffice. Its error estimate (the fold relocated
    on K + 1 harmonics and degree + 8, marching from the transferred state) against the
    fold of a branch continued separately with K = 3 from the bifurcation; K = 4 moves it
    less than K = 3 did (convergence in the cutoff)."""
    ins = ce.first_instability(0.6, H0, 1.0, material="cg")
    folds = {K: shellbvp.follow_bifurcation(ins, K=K, estimate_error=K == 2).folds[0]
             for K in (2, 3, 4)}
    assert folds[2].error_estimate == pytest.approx(abs(folds[3].p - folds[2].p), rel=1e-3)
    assert abs(folds[4].p - folds[3].p) < 0.3 * abs(folds[3].p - folds[2].p)



@pytest.mark.slow
def test_an_imperfect_path_past_the_bifurcation_is_refused():
    """The clamped pressure cap of lambda_B = 7 (n = 3) with an imperfection of half a
    thickness: its path within harmonics 0, 3, 6 rises past p_c (and past the perfect cap's
    n = 2 and 4 bifurcations, outside the class) to a fold at ~1.07 p_c. That fold is not the
    cap's limit load, and imperfect_limit says so instead of returning it."""
    from shellbvp.problems import pressure_cap as pc

    ins = pc.first_instability(7.0, 100.0, 0.3)
    eq = ins.equilibrium
    f = pb.Fourier2D(eq, ins.n, 2)
    crit = pb.critical_point(f, eq.p)
    k, *_ = pb.koiter(f, crit, direction=1.0)
    with pytest.raises(shellbvp.ConvergenceError, match="passes the bifurcation"):
        pb.imperfect_limit(f, crit, k, 0.5 * k.h / k.w_max)
