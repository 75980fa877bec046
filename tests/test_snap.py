"""Snap curvature of caps: onset of snapping, and kappa_s by the collocation back-end
(long: scipy's solve_bvp continuation takes minutes; run with `pytest -m slow`)."""

import math

import pytest

from shellbvp import Chebyshev, ContinuationOptions
from shellbvp.problems import cap_eversion as ce

H0 = 0.01


@pytest.fixture(scope="module")
def onset():
    return ce.onset(H0, 1.0)


@pytest.mark.slow
def test_onset_is_a_cusp_at_the_flat_state(onset):
    """At the onset T_c (the cusp of the fold curve) the slope dkappa/dw at the flat state
    vanishes (to 1e-6 in T, the next degree agreeing); just below it is positive, just
    above negative."""
    assert onset.error_estimate < 1e-5
    assert onset.bracket[0] < onset.T < onset.bracket[1]
    assert ce.flat_slope(onset.T - 0.01, H0) > 0 > ce.flat_slope(onset.T + 0.01, H0)


@pytest.mark.slow
def test_snap_above_the_onset_none_below(onset):
    above = ce.snap_curvature((onset.T + 0.02) * math.sqrt(H0), H0)
    below = ce.snap_curvature((onset.T - 0.02) * math.sqrt(H0), H0)
    assert above.snaps and not below.snaps
    # Born at the flat state (kappa = 1, w = H): just above the onset the fold is close to it.
    H = 1 - math.cos(above.theta)
    assert 1.0 < above.kappa_s < 1.05
    assert 0.7 < above.w_s / H < 1.0
    assert math.isnan(below.kappa_s)


@pytest.mark.slow
def test_a_deep_cap_snaps_well_above_the_onset(onset):
    r = ce.snap_curvature(math.pi / 6, H0)
    assert r.T > onset.T and r.snaps and r.kappa_s > 2.0


@pytest.mark.slow
def test_collocation_kappa_s_agrees_with_spectral():
    """Third route: solve_bvp's collocation scheme, continued by the common machinery, its
    fold refined by halving every interval until it moves by at most tol."""
    coll = ce.snap_curvature(math.pi / 6, H0, 1.0, method="collocation", tol=1e-8)
    spec = ce.snap_curvature(math.pi / 6, H0, 1.0, tol=1e-10)
    assert coll.snaps and coll.error_estimate <= 1e-8
    assert abs(coll.kappa_s - spec.kappa_s) <= coll.error_estimate + 1e-9
    assert 0 < coll.w_s < 2 * (1 - math.cos(math.pi / 6))


@pytest.mark.slow
def test_collocation_branch_fold_is_a_maximum_of_kappa():
    br = ce.branch(math.pi / 6, H0, 1.0, method="collocation",
                   options=ContinuationOptions(ds=0.1, ds_max=0.5))
    (fold,) = br.folds
    assert fold.p >= br.p.max() - 1e-12


def test_sweep_along_the_fold_curve_equals_independent_caps():
    """snap_curve finds the caps after the first snapping one from the folds before
    (shellbvp.fold_near: Newton on the fold system at that T); the independent route is
    each cap continued from kappa = 0. Both carry an error estimate that bounds their
    error, so they agree within the sum."""
    T = [4.0, 4.25, 4.75, 5.25]                   # steps of 0.25 and 0.5 in T
    out = ce.snap_curve(T, H0, 1.0, tol=1e-9, progress=False)
    assert out["snaps"].all()
    assert list(out["along_fold_curve"]) == [False, True, True, True]
    for T_, k, w, e in zip(T, out["kappa_s"], out["w_s"], out["error_estimate"]):
        r = ce.snap_curvature(T_ * math.sqrt(H0), H0, 1.0, tol=1e-9)
        assert abs(k - r.kappa_s) <= e + r.error_estimate + 1e-12, T_
        assert abs(w - r.w_s) <= 1e-8, T_


def test_the_fold_probe_narrows_the_bracket_and_leaves_kappa_s():
    """``ContinuationOptions.fold_probe`` (on in ``to_first_fold``) takes the point after
    which the secant of dkappa/dw predicts the fold with w prescribed just past it: on the
    default cap the bracket of the fold is then at least four times narrower in w, it
    costs fewer evaluations, and kappa_s (tol 1e-10, the same ladder) is the same to 1e-12
    (the folds of one discrete system, reached from two seeds)."""
    theta = math.pi / 6
    runs = {}
    for probe in (False, True):
        o = ContinuationOptions.to_first_fold(fold_tol=1e-10).with_(fold_probe=probe)
        b = ce.branch(theta, H0, method=Chebyshev(nodes=24), n_folds=1, options=o,
                      energies=False)
        (fold,) = b.folds
        i = fold.index
        runs[probe] = (b.stats["evaluations"], b.w[i + 1] - b.w[i], fold.p)
    (plain, wide, k0), (probed, narrow, k1) = runs[False], runs[True]
    assert narrow < 0.25 * wide and probed < plain, runs
    assert abs(k1 - k0) <= 1e-12, runs


def test_a_finer_rung_stops_after_one_update_where_its_bound_allows():
    """On the ladder of one kappa_s (:func:`shellbvp.continuation.polish_fold`, Newton on
    dkappa/dw = 0 along the branch) a finer rung starts from the coarser rung's fold with
    its inner roots carried (``transfer``), and its first solve stops after one update
    where the error that can leave is below the tolerance. Its fold equals the one
    polished from the same state with cold inner roots to tol 1e-14 (never one update):
    kappa to 1e-12, w / H to 1e-9 (the monitor tolerance), on three rungs from degree 24
    (where the ladder of tol 1e-6 ends: two changes within tol, 16 -> 20 -> 24), the
    later two in fewer Newton iterations (20 -> 24 moves the fold too far for one update,
    which is why the first of the three is not asked to)."""
    from shellbvp.continuation import polish_fold

    current = ce.snap_curvature(0.4, H0, 1.0, tol=1e-6).fold
    assert current.system.N == 24
    c = current.stats["curvature"]
    fewer = []
    for _ in range(3):
        finer = current.system.refined()
        start = current.system.transfer(current.U, current.p, finer)
        carried = polish_fold(finer, start, current.p, current.monitor, curvature=c,
                              refining=True)
        cold = polish_fold(finer.on(finer.bvp), start, current.p, current.monitor,
                           curvature=c, tol=1e-14, monitor_tol=1e-12)
        assert abs(carried.p - cold.p) <= 1e-12
        assert abs(carried.monitor - cold.monitor) <= 1e-9
        fewer.append(carried.stats["newton_iterations"] < cold.stats["newton_iterations"])
        current = carried
    assert fewer[1:] == [True, True], fewer
