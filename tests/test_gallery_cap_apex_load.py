"""The point-loaded cap gallery case (figures/gallery_cap_apex_load.py): a clamped shallow
spherical cap under an apex load against Teng & Rotter (1989), Fig. 12, and the linear
shallow-shell theory; the tolerances and their reasons are stated there."""

import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

import gallery_cap_apex_load as case  # noqa: E402


def test_reissner_stiffness_limits():
    """The closed form the engine is checked against reproduces its two limits: the
    Kirchhoff plate (R -> infinity, 16 pi D / a^2) and the shell of infinite extent,
    8 sqrt(D E t) / R, approached as (l / a)^2 when the base a grows in bending lengths l
    (the clamp holds the membrane forces, whose disturbance decays algebraically)."""
    E, nu, t, R = case.E, case.NU, case.T, case.R
    D = E * t**3 / (12 * (1 - nu**2))
    assert case.reissner_stiffness(R=1e5) == pytest.approx(16 * math.pi * D / case.A**2,
                                                            rel=1e-5)
    k_inf = 8 * math.sqrt(D * E * t) / R
    l = (D * R**2 / (E * t)) ** 0.25
    for n in (20.0, 30.0):
        assert 0 < case.reissner_stiffness(a=n * l) / k_inf - 1 < 2.5 / n**2


def test_initial_stiffness_against_linear_shallow_shell():
    """The scene file's shell at a small apex load within 1 % of the linear shallow-shell
    stiffness (the theories differ at order (a/R)^2 = 3.6 %; observed -0.36 %)."""
    import shellbvp

    sf = shellbvp.load_scene(case.SCENE)
    k = case.initial_stiffness(sf)
    assert abs(k / case.reissner_stiffness() - 1) <= case.SLOPE_TOLERANCE


@pytest.mark.slow
def test_gallery_cap_apex_load():
    r = case.run()
    assert r["limit_point"] is None
    assert r["ok"], {k: r[k] for k in ("published", "shellbvp", "difference", "tolerance",
                                       "initial_stiffness")}
