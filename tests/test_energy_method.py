"""The energy method (shellbvp.Ritz): direct minimisation of the discrete reduced energy.

References are independent of this method: the spectral method's solutions of the
Euler-Lagrange system (another formulation: inner inversion, pole conditions), its
energy quadrature, finite differences of the method's own residual, and the undeformed cap.
"""

import math

import numpy as np
import pytest

import shellbvp
from shellbvp import Chebyshev, ContinuationOptions, Ritz
from shellbvp.bvp import ShellBVP
from shellbvp.problems import budding
from shellbvp.problems import cap_eversion as ce

DEG = 16                 # one compiled program shared by these tests


@pytest.fixture(scope="module")
def cap():
    return ce.scene(theta=math.pi / 6, h=0.01, lam=1.0, model="relaxed")


@pytest.fixture(scope="module")
def cap_system(cap):
    return Ritz(degree=DEG).discretise(ShellBVP(cap))


def test_undeformed_cap_is_stationary_at_zero_stimulus(cap, cap_system):
    U0 = cap_system.from_profile(cap_system.bvp.reference)   # Lambda by differences: ~1e-11
    R, _, _ = cap_system.evaluate(U0, 0.0)
    m, _ = cap_system.monitor(U0)
    assert np.abs(R).max() < 1e-10 and abs(m) < 1e-10
    eq = shellbvp.solve(cap, 0.0, method=Ritz(degree=DEG), estimate_error=False)
    assert abs(eq.w) < 1e-14
    assert np.allclose(eq.r, np.sin(eq.s), atol=1e-14)
    assert np.allclose(eq.theta, eq.s, atol=1e-14)
    assert np.allclose(eq.lam1, 1.0, atol=1e-13) and np.allclose(eq.k2, -1.0, atol=1e-12)
    # and it is stable: the Hessian at zero stimulus is positive definite
    assert cap_system.spectrum(U0, 0.0, count=1).eigenvalues[0] > 0


def test_jacobian_and_parameter_derivative_against_differences(cap_system):
    rng = np.random.default_rng(1)
    U = cap_system.from_profile(cap_system.bvp.reference) + 1e-3 * rng.standard_normal(
        cap_system.size)
    R, J, Rp = cap_system.evaluate(U, 1.5)
    assert abs(J - J.T).max() < 1e-12 * abs(J).max()          # a Hessian: symmetric
    v, e = rng.standard_normal(U.size), 1e-6
    d = (cap_system.evaluate(U + e * v, 1.5)[0] - cap_system.evaluate(U - e * v, 1.5)[0]) / (2 * e)
    assert np.abs(d - J @ v).max() < 1e-6 * np.abs(J @ v).max()
    dp = (cap_system.evaluate(U, 1.5 + e)[0] - cap_system.evaluate(U, 1.5 - e)[0]) / (2 * e)
    assert np.abs(dp - Rp).max() < 1e-6 * np.abs(Rp).max()
    m, dm = cap_system.monitor(U)
    fd = (cap_system.monitor(U + e * v)[0] - cap_system.monitor(U - e * v)[0]) / (2 * e)
    assert fd == pytest.approx(dm @ v, rel=1e-7)


def test_snap_curvature_agrees_with_the_first_order_system(cap):
    """kappa_s by the energy method (its own fold ladder) against the spectral solution of
    the Euler-Lagrange system (another formulation), both to 1e-10."""
    br = shellbvp.follow(cap, method=Ritz(degree=DEG), n_folds=1, energies=False,
                         options=ContinuationOptions.to_first_fold(1e-10))
    fold = br.folds[0]
    ref = ce.snap_curvature(math.pi / 6, 0.01, 1.0, tol=1e-10)
    assert abs(fold.p - ref.kappa_s) <= fold.error_estimate + ref.error_estimate + 1e-12
    assert fold.error_estimate < 1e-10
    assert fold.w == pytest.approx(ref.w_s, abs=1e-8)
    # at the fold the Hessian at fixed kappa is singular (the fold of the axisymmetric
    # branch): its smallest eigenvalue vanishes to the fold's accuracy, the next does not
    sv = fold.system.spectrum(fold.U, fold.p, count=2)
    assert abs(sv.eigenvalues[0]) < 1e-6 * sv.eigenvalues[1]


@pytest.mark.slow      # the default suite compares w and the energy below, on cached branches
def test_budding_at_kbar_20_agrees_with_the_spectral_method():
    """w_apex and the energy at kbar = 20 (eta_a = 0, eta_b = 1): the energy method's own
    quadrature against the spectral equilibrium's (another discretisation and quadrature)."""
    a = budding.equilibrium(0.0, 1.0, 20.0, method=Ritz(degree=DEG))
    b = budding.equilibrium(0.0, 1.0, 20.0, method=Chebyshev(nodes=32))
    assert a.w == pytest.approx(b.w, abs=1e-10)
    assert a.energy == pytest.approx(b.energy, rel=1e-9)
    assert a.stats["method"] == "energy"
    # the shape along the meridian (each solution's own interpolant), and the meridional
    # force: from the multipliers of r' = Lambda cos(theta) here, an unknown there
    s = np.linspace(0.01, budding.THETA, 40)
    ya, yb = a(s), b(s)
    assert np.allclose(ya[[0, 2]], yb[[0, 2]], atol=1e-9)
    assert np.allclose(ya[1] - ya[1, -1], yb[1] - yb[1, -1], atol=1e-9)
    assert np.allclose(ya[4], yb[4], atol=1e-8 * np.abs(yb[4]).max())


@pytest.mark.slow
def test_observed_convergence_at_a_singular_apex():
    """eta = (0, 0.5): the target curvature is anisotropic at the apex (curvatures ~ log s);
    on the graded elements w converges with the degree (measured: changes 1.8e-9, 1.4e-10,
    4.6e-11 from degree 8 to 12, 16, 20: fast, then slower, as the innermost element's
    singular part dominates) and agrees with the spectral solution of the first-order
    system, whose anisotropic pole condition (k1 - k2 = A) treats the same singularity."""
    w = [budding.equilibrium(0.0, 0.5, 10.0, method=Ritz(degree=q)).w for q in (8, 12, 16, 20)]
    d = np.abs(np.diff(w))
    assert d[0] > d[1] > d[2] and d[1] < 0.2 * d[0] and d[2] < 1e-10
    ref = budding.equilibrium(0.0, 0.5, 10.0, method=Chebyshev(nodes=48)).w
    assert abs(w[-1] - ref) < 1e-8


@pytest.mark.parametrize("kwargs,name", [(dict(degree=3), "degree"), (dict(elements=0), "elements"),
                                         (dict(layers=-1), "layers"), (dict(grading=1.5), "grading")])
def test_bad_options_are_named(kwargs, name):
    with pytest.raises(ValueError, match=name):
        Ritz(**kwargs)


def test_stability_check_needs_a_mid_surface_method(cap):
    with pytest.raises(ValueError, match="check_stability"):
        shellbvp.follow(cap, check_stability=True)


def test_energy_method_equilibrium_is_stationary_by_an_independent_quadrature():
    """eta = (0, 1), kbar = 20: w and the energy agree with the spectral solution, and the
    first variation of the reduced energy,
    by Simpson's rule on 3000 panels with complex steps through the first-order system's own
    state (tests/quadrature.py), vanishes at the energy method's equilibrium relative to
    its value at a state that is not an equilibrium."""
    from dataclasses import replace

    from quadrature import first_variation
    from test_budding import at as spectral_at

    T = budding.THETA
    w = 2 * math.pi / T
    directions = [(lambda s: np.sin(w * s) ** 2, lambda s: w * np.sin(2 * w * s), lambda s: 0 * s),
                  (lambda s: 0 * s, lambda s: 0 * s, lambda s: 1 + s)]
    eq = budding.equilibrium(0.0, 1.0, 20.0, method=Ritz(degree=DEG))
    ref = spectral_at(0.0, 1.0, 20.0)     # the spectral branch test_budding follows (cached)
    assert eq.w == pytest.approx(ref.w, abs=1e-10)
    assert eq.energy == pytest.approx(ref.energy, rel=1e-9)
    off = replace(budding.equilibrium(0.0, 1.0, 10.0, method=Ritz(degree=DEG)), p=20.0)
    for a, b in zip(first_variation(eq, directions), first_variation(off, directions)):
        assert abs(b) > 1e-6 and abs(a) <= 1e-6 * abs(b)


@pytest.mark.parametrize("lambda_B", [5.5])
def test_pressure_cap_agrees_with_the_spectral_method(lambda_B):
    """A clamped Koiter cap under follower pressure (R/t = 100, nu = 0.3): p_cr / p0 by both
    formulations, each refined to 1e-9 (measured: 0.75425120992 both, 8e-13 apart;
    lambda_B = 4 and 8: 8e-14 and 9e-13)."""
    from shellbvp.problems import pressure_cap as pc

    a = pc.critical_pressure(lambda_B, tol=1e-9, method=Ritz(degree=DEG))
    b = pc.critical_pressure(lambda_B, tol=1e-9)
    assert a.branch.stats["method"] == "energy"
    assert abs(a.p_cr_over_p0 - b.p_cr_over_p0) <= a.error_estimate + b.error_estimate
    assert a.w_apex == pytest.approx(b.w_apex, abs=1e-8)


@pytest.mark.slow
@pytest.mark.parametrize("T,lam,model,material", [(3.0, 0.01, "relaxed", "cg"),
                                                  (8.0, 10.0, "plane_strain", "cg"),
                                                  (5.0, 1.0, "relaxed", "nh")])
def test_fig3_caps_agree_with_the_spectral_method(T, lam, model, material):
    """kappa_s of caps of Fig. 3's set (h = 0.01) by both formulations, to 1e-9 each."""
    h = 0.01
    kw = dict(lam=lam, model=model) if material == "cg" else {}
    sc = ce.scene(theta=T * math.sqrt(h), h=h, material=material, **kw)
    br = shellbvp.follow(sc, method=Ritz(degree=DEG), n_folds=1, energies=False,
                         options=ContinuationOptions.to_first_fold(1e-9))
    ref = ce.snap_curvature(T * math.sqrt(h), h, material=material, tol=1e-9, **kw)
    f = br.folds[0]
    assert abs(f.p - ref.kappa_s) <= f.error_estimate + ref.error_estimate


def test_command_line_snap_with_the_energy_method(capsys):
    from shellbvp import cli

    assert cli.main(["snap", "--method", "energy", "--tol", "1e-9"]) == 0
    out = capsys.readouterr().out
    assert "4.22142913" in out


@pytest.mark.slow
def test_observed_convergence_at_a_cone_apex():
    """eta = (2, 1), kbar = 20: the target is a deficit cone at the apex. w_apex and the hoop
    strain away from the apex converge with the degree (measured: w changes 2.0e-7, 1.2e-8,
    ~1e-12 from degree 8 to 12, 16, 20), the strain next to the apex does not (it grows like
    log s as the first node moves toward the apex)."""
    out = []
    for q in (8, 12, 16, 20):
        eq = budding.equilibrium(2.0, 1.0, 20.0, method=Ritz(degree=q))
        r = eq(np.array([0.3]))[0][0]
        out.append((eq.w, ((r / math.sin(0.3)) ** 2 - 1) / 2, eq.eps22[0]))
    w, e_far, e_apex = np.array(out).T
    dw, de = np.abs(np.diff(w)), np.abs(np.diff(e_far))
    assert dw[1] < 0.2 * dw[0] and dw[2] < 1e-10
    assert de[2] < 1e-9
    assert np.all(np.diff(e_apex) < -1e-3)       # the apex strain keeps moving


def test_inadmissible_fields_are_named_by_the_energy_method_too():
    """The energy method checks the fields at its quadrature points as the first-order form
    does at its nodes: a metric stimulus on a scene that says it has none, and a thickness
    profile that changes sign inside the shell, are named errors, not an energy of
    nothing."""
    from shellbvp.geometry import disc

    def scene(**kw):
        return shellbvp.Scene(disc(1.0), 0.01, material="koiter", nu=0.3,
                              ends=("pole", "clamped"), **kw)

    metric = scene(fields=lambda x, p: (1 + p * x.s, 1 + 0 * x.s, x.k1, x.k2))
    with pytest.raises(ValueError, match="metric=False"):
        shellbvp.solve(metric, 0.1, method="energy")
    thin = scene(thickness=lambda x: 0.5 - x.s, pressure=lambda p: p)
    with pytest.raises(ValueError, match="thickness profile must be > 0 inside the shell"):
        shellbvp.solve(thin, 1e-6, method="energy")
