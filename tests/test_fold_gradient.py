"""Exact derivatives of kappa_s (implicit differentiation of the fold, ``gradient=True``)
against central differences of independent kappa_s computations, and the docs'
inverse-design example."""

import math

import pytest

from shellbvp.problems import cap_eversion as ce

THETA, H0, LAM = math.pi / 6, 0.01, 1.0
TOL = 1e-11
#: relative step of the central differences: their truncation error is ~STEP^2 relative
#: (1e-8) and the fold's error TOL / (2 STEP |x| |dkappa/dx|) <= 1e-7 here
STEP = 1e-4


@pytest.fixture(scope="module")
def snap():
    return ce.snap_curvature(THETA, H0, LAM, model="plane_strain", tol=TOL, gradient=True)


@pytest.mark.parametrize("name", ["theta", "h", "lam"])
def test_gradient_matches_central_differences(snap, name):
    """dkappa_s/dx from the fold's implicit derivative equals (kappa_s(x + d) -
    kappa_s(x - d)) / 2d of two independent continuations, to 1e-6 relative."""
    x0 = dict(theta=THETA, h=H0, lam=LAM)
    d = STEP * x0[name]

    def kappa_s(v):
        x = dict(x0, **{name: v})
        return ce.snap_curvature(x["theta"], x["h"], x["lam"], model="plane_strain",
                                 tol=TOL).kappa_s

    fd = (kappa_s(x0[name] + d) - kappa_s(x0[name] - d)) / (2 * d)
    assert snap.gradient[name] == pytest.approx(fd, rel=1e-6)


def test_gradient_in_h_is_mostly_the_shallowness(snap):
    """kappa_s depends on h mostly through T = Theta / sqrt(h): dkappa/dh is close to
    dkappa/dTheta dTheta/dh at fixed T (= Theta / 2h), opposite in sign (a physical check)."""
    g = snap.gradient
    assert g["h"] == pytest.approx(-g["theta"] * THETA / (2 * H0), rel=0.05)


def test_gradient_is_refused_for_other_methods():
    with pytest.raises(ValueError, match="gradient=True needs method='spectral'"):
        ce.snap_curvature(THETA, H0, gradient=True, method="collocation")


@pytest.mark.slow   # ~2 min on a fresh process: four kappa_s with gradients at tol 1e-10
def test_design_example_of_the_docs_hits_its_target():
    """The design() of the docs (theory page): Newton with the exact gradient finds the
    opening angle whose kappa_s is the target; checked by an independent kappa_s there."""
    from docs_blocks import python_block

    block = python_block("def design(")
    namespace = {}
    exec(block.split("\ntheta = design(")[0], namespace)
    theta = namespace["design"](5.0)
    assert ce.snap_curvature(theta, H0, LAM, tol=1e-10).kappa_s == pytest.approx(5.0, abs=1e-8)
