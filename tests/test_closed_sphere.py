"""Closed-sphere scene (paper Section 5.3): physical checks, the paper's expansions, the
symbolic series against the numerical root, and the reduced model against 3D quadrature."""

import numpy as np
import pytest
import sympy as sp

import paper_formulas as P
from shellbvp.problems import closed_sphere as cs

h_, lam_ = sp.symbols("h lam", positive=True)


@pytest.mark.parametrize("model,material", [("plane_strain", "cg"), ("relaxed", "cg"),
                                            ("relaxed", "nh")])
@pytest.mark.parametrize("exact", [False, True])
def test_zero_stimulus_leaves_sphere_undeformed(model, material, exact):
    r = cs.equilibrium(0.0, h=0.02, lam=3.0, model=model, material=material, exact=exact)
    assert abs(r.w_over_R0) < 1e-15 and r.stiffness > 0


def test_plane_strain_quadratic_coefficient_matches_paper_exactly():
    """Paper: w/R0 = (1 - lam)/(24 (1 + lam)) (kappa h0)^2 + O((kappa h0)^3); the symbolic
    series gives c1 = 0 and this c2, exactly in h."""
    c1, c2 = cs.series(2, model="plane_strain")
    assert c1 == 0
    assert sp.simplify(c2 - P.sphere_plane_strain_c2(h_, lam_)) == 0


def test_relaxed_linear_coefficient_matches_paper_exactly():
    (c1,) = cs.series(1, model="relaxed")
    assert sp.simplify(c1 - P.sphere_relaxed_c1(h_, lam_)) == 0


@pytest.mark.parametrize("model", ["plane_strain", "relaxed"])
def test_series_error_is_third_order_in_kappa(model):
    """|w(root of dW/dw) - (c1 kappa + c2 kappa^2)| = O(kappa^3): the numerical root and the
    symbolic series are independent routes to the same equilibrium."""
    ks = np.array([0.4, 0.2, 0.1, 0.05])
    err = [abs(cs.equilibrium(k, h=0.05, lam=0.3, model=model).w_over_R0
               - cs.series_value(k, h=0.05, lam=0.3, model=model)) for k in ks]
    slope = np.polyfit(np.log(ks), np.log(err), 1)[0]
    assert 2.7 < slope < 3.5, (err, slope)


def test_lam_one_plane_strain_does_not_change_radius():
    """Paper: for lam = 1 'any effect of the stimulus is exactly compensated'. For the reduced
    model it holds beyond the series: the root is w = 0 to round-off at finite kappa. The 3D
    quadrature of the same (plane-strain) kinematics moves the sphere at O(h^4) only
    (measured 1.1e-7 at h = 0.1, kappa = 0.5): the claim is a property of the truncation."""
    for k in (0.5, 2.0):
        assert abs(cs.equilibrium(k, h=0.1, lam=1.0, model="plane_strain").w_over_R0) < 1e-14
    w = [cs.equilibrium(0.5, h=h, lam=1.0, model="plane_strain", exact=True).w_over_R0
         for h in (0.1, 0.05)]
    assert 0 < abs(w[0]) < 0.1**4
    assert np.log2(w[0] / w[1]) == pytest.approx(4, abs=0.3)


@pytest.mark.parametrize("lam,sign", [(100.0, -1), (0.1, 1)])
def test_plane_strain_sign_of_radius_change(lam, sign):
    """Fig. 4: lam > 1 deflates, lam < 1 inflates, whatever the sign of kappa."""
    for k in (-1.0, 1.0, 2.0):
        assert sign * cs.equilibrium(k, h=0.01, lam=lam, model="plane_strain").w_over_R0 > 0


@pytest.mark.parametrize("model,material", [("plane_strain", "cg"), ("relaxed", "cg"),
                                            ("relaxed", "nh")])
def test_reduced_root_converges_to_exact_like_h4(model, material):
    hs = np.array([0.08, 0.04, 0.02])
    d = [abs(cs.equilibrium(1.0, h=h, lam=0.5, model=model, material=material).w_over_R0
             - cs.equilibrium(1.0, h=h, lam=0.5, model=model, material=material,
                              exact=True).w_over_R0) for h in hs]
    slope = np.polyfit(np.log(hs), np.log(d), 1)[0]
    assert 3.6 < slope < 4.4, (d, slope)


@pytest.mark.parametrize("kwargs,name", [
    (dict(h=0.0), "h"), (dict(h=1.0), "h"), (dict(h=0.01, lam=-1.0), "lam"),
    (dict(h=0.01, model="membrane"), "model"), (dict(h=0.01, material="steel"), "material"),
    (dict(h=float("nan")), "h"),
])
def test_bad_input_is_named(kwargs, name):
    with pytest.raises(ValueError, match=name):
        cs.equilibrium(1.0, **kwargs)
    with pytest.raises(ValueError, match="kappa"):
        cs.equilibrium(float("inf"), h=0.01)


def test_cli_runs_and_rejects_bad_input(capsys):
    assert cs.main(["--kappa", "0.5", "--model", "plane_strain", "--lam", "0.1"]) == 0
    assert "w/R0" in capsys.readouterr().out
    with pytest.raises(SystemExit) as e:
        cs.main(["--h", "1.5"])
    assert e.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "h must lie in (0, 1)" in err[0]


@pytest.mark.parametrize("model,material", [("plane_strain", "cg"), ("relaxed", "cg"),
                                            ("relaxed", "nh")])
def test_shell_of_revolution_returns_the_homogeneous_state(model, material):
    """The closed sphere as a scene like any other (the meridian from pole to pole, two
    poles): its boundary-value problem, solved without the homogeneous ansatz, returns the
    homogeneous state, radius 1 + w with w the root of dW/dw (an independent route: a scalar
    root of the energy density), uniform along the meridian and free of forces."""
    kappa, h = 1.5, 0.05
    lam = 3.0 if material == "cg" else 1.0
    root = cs.equilibrium(kappa, h=h, lam=lam, model=model, material=material)
    eq = cs.shell_equilibrium(kappa, h=h, lam=lam, model=model, material=material)
    r_eq, z_eq = eq(np.array([np.pi / 2]))[:2, 0]  # the equator: its height is the centre's
    radius = np.hypot(eq.r, eq.z - z_eq)
    assert abs(r_eq - (1 + root.w_over_R0)) < 1e-10
    assert np.max(np.abs(radius - (1 + root.w_over_R0))) < 1e-10
    assert np.max(np.abs(eq.lam1 - eq.lam2)) < 1e-10
    assert np.max(np.abs(eq.F_r)) < 1e-12 and np.max(np.abs(eq.F_z)) < 1e-12
