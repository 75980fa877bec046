"""The everting-cap gallery case (figures/gallery_everting_cap.py): the paper's onset of
snapping, "no snapping for Theta sqrt(R0/h0) <~ 3.1" (Section 5.2, on Fig. 3), against
shellbvp's onset; the tolerance and its reason are stated there. shellbvp's onset is 1.92
(lam = 1), a miss the case reports (docs/theory.md, "Onset of snapping")."""

import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

import gallery_everting_cap as case


def test_published_threshold_and_tolerance():
    """The published CSV holds the paper's 3.1, and the tolerance is half a unit of its last
    digit."""
    pub = case.read_published()
    assert float(pub["T_onset"]["value"]) == 3.1
    assert "3.1" in pub["T_onset"]["quote"]
    assert case.tolerance(3.1) == pytest.approx(0.05 / 3.1, rel=1e-15)


def test_scene_cap_is_flat_at_kappa_one_between_a_fold_pair():
    """The scene file's cap (T = 2.5): by the mirror symmetry (kappa, w) -> (2 - kappa,
    2H - w) of the shallow cap, kappa R0 is exactly 1 where the edge is level with the apex
    (w = H), independent of the solver; and dkappa/dw < 0 there, so the branch from
    kappa = 0 has a fold pair around the flat state: a cap the paper says does not snap,
    snaps."""
    import shellbvp

    sf = shellbvp.load_scene(case.SCENE)
    assert case.T_SCENE == pytest.approx(case.THETA_SCENE / math.sqrt(sf.units.thickness))
    kappa, slope = case.flat_state(sf)
    assert kappa == pytest.approx(1.0, abs=1e-9)
    assert slope < 0


@pytest.mark.slow
@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="the paper's onset <~ 3.1 is not reproduced: shellbvp's caps snap "
                          "from T = 1.83-2.05 (lam = 0.01-10); docs/theory.md")
def test_gallery_everting_cap():
    r = case.run()
    # what the case computes, to its error estimates (figures/fig3_onset.csv)
    assert r["onsets"]["cg lam=1"]["T_c"] == pytest.approx(1.9243236820, abs=1e-5)
    assert all(abs(v["kappa_at_cusp"] - 1) < 1e-8 for v in r["onsets"].values())
    s = r["snaps_below_3_1"]
    assert s["snaps"] and s["folds"][0]["kappa_R0"] == pytest.approx(1.4931792811, abs=1e-8)
    assert abs(s["fold_sum_minus_2"]) < 1e-9
    assert r["paper_statements"]["relaxed_snaps_every_lam"]
    assert r["paper_statements"]["kappa_s_decreasing_in_lam"]
    # the comparison itself: a miss, reported (strict xfail: a pass would be news)
    assert r["ok"], r["onsets"]
