"""The tutorial's morphoelastic examples (docs/tutorial.md, "Beyond the anchors";
figures/tutorial_morphoelastic.py): the two scene files load and are the ones the page
shows, each example's sanity check against its closed form (the tolerances and their
reasons are stated in the script's docstring), and, slow, the whole script."""

import math
import os
import sys

import pytest
from scipy.integrate import quad

import shellbvp
from docs_blocks import ROOT, blocks

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

import tutorial_morphoelastic as case  # noqa: E402

PAGE = ROOT / "docs" / "tutorial.md"
FILES = (case.SPRING, case.CYLINDER)


def _without_header(text: str) -> str:
    """A scene file without its leading comment lines (the page shows the rest)."""
    lines = text.splitlines(keepends=True)
    k = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    return "".join(lines[k:])


def test_scene_files_load_with_the_stated_cases():
    spring = shellbvp.load_scene(case.SPRING)
    assert spring.parameter == "F" and spring.units.length_label == "mm"
    assert spring.scene.breaks == pytest.approx((8.0 / 50.0, 9.0 / 50.0))
    cyl = shellbvp.load_scene(case.CYLINDER)
    assert cyl.parameter == "g" and cyl.scene.breaks == pytest.approx((68.0 / 100, 70.0 / 100))
    # the stated geometry: R/t = 100, Z = 244, F0 = 0.8 N_cl (N_cl = 1210.46 N/mm)
    L = 2 * case.HALF
    assert L * L * math.sqrt(1 - case.NU**2) / (case.R * case.T) == pytest.approx(244.2, abs=0.1)
    assert case.N_CL == pytest.approx(1210.455, rel=1e-6)
    assert case.F0 / case.N_CL == pytest.approx(0.8, rel=1e-4)


def test_the_page_shows_the_scene_files():
    """The tutorial's toml blocks are the two files, as they are (less their headers)."""
    shown = [code for language, code in blocks(PAGE) if language == "toml"]
    for path in FILES:
        assert _without_header(path.read_text()) in shown, path.name


def test_closed_forms_against_quadrature():
    """The checks' closed forms, against direct quadrature of what they integrate: the
    annulus' area average of the band, and the bulge as the beam on an elastic foundation's
    Green function (beta / (2 k)) exp(-beta |x|) (cos beta x + sin beta |x|) over the load."""
    a, c, r1, r2 = 25.0, 50.0, 33.0, 34.0

    def e(r):
        return min(max(r2 - r, 0.0), 1.0)

    avg = 2 * quad(lambda r: e(r) * r, a, c, points=(r1, r2))[0] / (c * c - a * a)
    assert case.annulus_average() == pytest.approx(avg, rel=1e-12)
    assert avg == pytest.approx(2 * (232 + 50 / 3) / 1875, rel=1e-12)
    beta = (3 * (1 - case.NU**2)) ** 0.25 / math.sqrt(case.R * case.T)

    def band(x):
        return min(max((case.BAND + case.RAMP - x) / case.RAMP, 0.0), 1.0)

    def kernel(x):
        return beta * math.exp(-beta * x) * (math.cos(beta * x) + math.sin(beta * x))

    w = quad(lambda x: band(x) * kernel(x), 0, case.BAND + case.RAMP, points=(case.BAND,))[0]
    assert case.ring_bulge() == pytest.approx(w, rel=1e-10)


def test_swollen_band_of_a_flat_annulus_is_lames():
    """The spring's band on a flat annulus, swollen by 1e-6: both edges move by the area
    average of the growth (Lame), to 1e-5 (measured 1.8e-6: the nonlinear terms)."""
    c = case.spring_check()
    assert c["difference"] <= case.TOL_ANNULUS, c


def test_ring_bulge_without_the_load_is_the_beam_on_elastic_foundation():
    """The cylinder's ring grown by 1e-6 without the load: the bulge at its centre is the
    shallow linear theory's 0.960691 g R, to 1e-3 (measured 1.0e-4)."""
    c = case.cylinder_check()
    assert abs(c["difference"]) <= case.TOL_RING, c


@pytest.mark.slow
def test_tutorial_morphoelastic_script(tmp_path):
    """The whole script: the numbers the tutorial states, and its outputs."""
    r = case.main(["--out", str(tmp_path)])
    sp, cy = r["spring"], r["cylinder"]
    assert sp["dry_folds"] == 0 and len(sp["folds"]) == 2
    assert sp["folds"][0]["p"] == pytest.approx(6695.83, abs=0.01)
    assert sp["folds"][1]["p"] == pytest.approx(504.17, abs=0.01)
    assert sp["rise"] == pytest.approx(2.593, abs=1e-3)
    assert sp["instability"]["kind"] == "fold" and sp["instability"]["n"] == 0
    assert cy["instability"]["kind"] == "bifurcation" and cy["instability"]["n"] == 7
    assert cy["instability"]["p"] == pytest.approx(0.0018795, abs=1e-7)
    assert sp["check"]["difference"] <= case.TOL_ANNULUS
    assert abs(cy["check"]["difference"]) <= case.TOL_RING
    assert (tmp_path / "tutorial_morphoelastic.png").stat().st_size > 0
    assert (tmp_path / "tutorial_morphoelastic.csv").read_text().count("\n") > 50
