"""The point-loaded hemisphere gallery case (figures/gallery_reissner.py): the pole stiffness
P / w against Reissner's (1946) shallow-shell point-load result at R/t = 100, 300, 1000; the
tolerance (t/R) ln(R/t) and its reason are stated there."""

import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

import gallery_reissner as case  # noqa: E402


def test_published_table_is_reissners_formula():
    """The published CSV holds P / w = 4 E t^2 / (R sqrt(3 (1 - nu^2))) = 8 sqrt(D E t) / R,
    and the profile's w(0) is the same deflection (kei(0) = -pi/4)."""
    for rt, k in case.read_published().items():
        t = case.R / rt
        D = case.E * t**3 / (12 * (1 - case.NU**2))
        assert k == pytest.approx(8 * math.sqrt(D * case.E * t) / case.R, rel=1e-12)
        assert case.reissner_profile(0.0, t) == pytest.approx(case.P / k, rel=1e-12)


def test_file_thickness_within_tolerance():
    """The scene file's shell (R/t = 300) within (t/R) ln(R/t) of Reissner's stiffness."""
    r = case.run(quick=True)
    assert abs(r["difference"]) <= r["tolerance"], r


@pytest.mark.slow
def test_gallery_reissner():
    r = case.run()
    assert set(r["by_R_over_t"]) == {"100", "300", "1000"}
    assert r["ok"], r["by_R_over_t"]
