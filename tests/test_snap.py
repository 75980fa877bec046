"""Snap curvature of caps (long: continuation from kappa = 0; run with `pytest -m slow`)."""

import math

import pytest

from shellbvp import ContinuationOptions
from problems import cap_eversion as ce


@pytest.mark.slow
def test_kappa_s_is_stable_under_fold_tolerance_refinement():
    """kappa_s refined at fold tolerances 1e-6 and 1e-8 agrees within the error estimate of
    the coarse one plus 1e-9 (mesh refinement of the extended system is the estimate)."""
    coarse = ce.snap_curvature(math.pi / 6, 0.01, 1.0, tol=1e-6)
    fine = ce.snap_curvature(math.pi / 6, 0.01, 1.0, tol=1e-8)
    assert coarse.snaps and fine.snaps
    assert abs(coarse.kappa_s - fine.kappa_s) <= coarse.error_estimate + 1e-9
    assert fine.error_estimate <= 1e-8
    # the fold lies before full eversion, on the way from the cap to the flat state and beyond
    assert 0 < fine.w_s < 2 * (1 - math.cos(math.pi / 6))


@pytest.mark.slow
def test_branch_fold_is_a_maximum_of_kappa():
    br = ce.branch(math.pi / 6, 0.01, 1.0, options=ContinuationOptions(ds=0.1, ds_max=0.5))
    (fold,) = br.folds
    assert fold.p >= br.p.max() - 1e-12
