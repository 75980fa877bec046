"""The disc-spring gallery case (figures/gallery_disc_spring.py): a Belleville washer against
the Almen-Laszlo formula of DIN EN 16983, its tolerances and their reasons stated there."""

import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

import gallery_disc_spring as case  # noqa: E402


def test_published_table_is_the_formula():
    """The published CSV holds the formula's values (K1 = 0.6943 at D_e/D_i = 2, DIN's table)."""
    assert case.k1(2.0) == pytest.approx(0.69433, abs=1e-5)
    for name, (s, F, marks) in case.read_published().items():
        assert F == pytest.approx(case.almen_laszlo(s, case.H0[name]), rel=1e-12, abs=1e-9)
        assert "flat" in marks
    assert case.flat_annulus_kirchhoff() / (48 / (case.k1(2.0) * case.D_E**2)) == \
        pytest.approx(case.KIRCHHOFF_OVER_AL, rel=1e-12)


def test_small_deflection_stiffness():
    """The initial stiffness of the h0/t = 0.75 spring within the case's 10 % of the formula's
    slope (the shell is softer: no rigid cross-section), and the flat annulus (h0 = 0), the
    formula's bending part, equal to the exact Kirchhoff plate: the engine's share of the
    difference is nil."""
    k = case.initial_stiffness(case.SCENES["h0/t = 0.75"])
    k_al = case.almen_laszlo_slope0(1.875)
    assert abs(k / k_al - 1) <= case.TOLERANCE["h0/t = 0.75"]
    assert k < k_al
    assert case.flat_annulus_stiffness() == pytest.approx(case.flat_annulus_kirchhoff(),
                                                          rel=1e-6)


@pytest.mark.slow
def test_gallery_disc_spring():
    r = case.run()
    assert r["ok"], [c for c in r["checks"] if not c["ok"]]
