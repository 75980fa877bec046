"""Bryan's circular plate under uniform radial edge compression
(figures/gallery_bryan_plate.py): its n = 0 bifurcation against the closed form, simply
supported and clamped (sliding); the tolerance (x t / a)^2 and its reasons are stated in the
case's docstring."""

import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

import gallery_bryan_plate as case  # noqa: E402


def test_closed_form_roots():
    """The roots found by brentq are the textbook's: x^2 = 4.19779 (nu = 0.3, simply
    supported; Timoshenko & Gere Sec. 8.2) and j_{1,1}^2 = 14.68197 (clamped)."""
    assert case.root("simply supported") ** 2 == pytest.approx(4.19779, abs=1e-5)
    assert case.root("clamped (sliding)") ** 2 == pytest.approx(14.68197, abs=1e-5)
    assert case.root("clamped (sliding)") == pytest.approx(3.8317059702, abs=1e-9)


@pytest.mark.slow
def test_clamped_plate_buckles_at_bryan_load():
    """The sliding clamped plate at a/t = 100 (one plate, ~10 s): an n = 0 bifurcation at
    q_cr a^2 / D within (x t/a)^2 = 1.5e-3 of j_{1,1}^2, its mode the Bessel mode to 1e-6."""
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        r = case.locate("clamped (sliding)", 100.0, Path(d))
    assert r["kind"] == "bifurcation" and r["n"] == 0
    assert abs(r["difference"]) + r["error_estimate"] <= r["tolerance"], r
    assert r["mode_difference"] <= case.MODE_TOL


@pytest.mark.slow
def test_gallery_bryan_plate():
    r = case.run()
    assert r["ok"], [c for c in r["checks"] if not c["ok"]]
