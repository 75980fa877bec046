"""Stiff and extreme caps (the study is figures/extreme_cases.py): limits of the model and
of double precision end in clear errors or honest answers, never in silent wrong numbers."""

import math

import pytest

from shellbvp import ConvergenceError
from shellbvp.problems import cap_eversion as ce

THETA = math.pi / 6


def test_relaxed_kappa_s_tends_to_the_incompressible_limit():
    """As lam -> infinity the relaxed CG cap tends to the incompressible neo-Hookean one
    (an independent material model), like 1/lam: the gap shrinks ~10x per decade. At
    lam = 1e5 the fold's Newton updates stall at round-off (2-4e-10, above the monitor
    tolerance 1e-10): the polishing trusts updates at that floor and takes no secant of
    d2p/dm2 over moves smaller than its points' uncertainty (it used to wander in the noise
    and fail after 12 steps)."""
    nh = ce.snap_curvature(THETA, 0.01, material="nh").kappa_s
    gaps = [ce.snap_curvature(THETA, 0.01, lam).kappa_s - nh for lam in (1e3, 1e4, 1e5)]
    assert 0 < gaps[2] < gaps[1] / 5 < gaps[0] / 25


def test_round_off_beyond_double_precision_is_a_clear_error():
    """Relaxed CG at lam = 1e6 (h = 0.01): the forces carry round-off ~ lam eps 12/h^2 and
    Newton stalls at ~5e-7; the error says so and names the incompressible material. Beyond
    lam / h^2 = 3e10, where no cap measured resolves, the scene refuses lam at once with the
    range at its h (3e6 at h = 0.01, 3e4 at h = 1e-3)."""
    with pytest.raises(ConvergenceError, match="material='nh'.*round-off"):
        ce.snap_curvature(THETA, 0.01, 1e6)
    with pytest.raises(ValueError, match=r"lam must lie in \(0, 3e\+06\] there.*material='nh'"):
        ce.snap_curvature(THETA, 0.01, 1e7)
    with pytest.raises(ValueError, match=r"\(0, 3e\+04\]"):
        ce.snap_curvature(THETA, 1e-3, 1e5)


@pytest.mark.slow
@pytest.mark.parametrize("h", [1e-3, 1e-2])
def test_stiff_material_resolved_everywhere_measured_is_honest(h):
    """lam = 1e9 h^2 (1e3 at h = 1e-3, 1e5 at h = 1e-2), where every cap measured resolves:
    kappa_s at tol 1e-8 agrees with tol 1e-9 within its estimate, and lies between the
    compressible value at lam / 10 and the incompressible limit (neo-Hookean, an
    independent material model)."""
    lam = 1e9 * h * h
    a = ce.snap_curvature(THETA, h, lam, tol=1e-8)
    b = ce.snap_curvature(THETA, h, lam, tol=1e-9)
    assert abs(a.kappa_s - b.kappa_s) <= a.error_estimate
    nh = ce.snap_curvature(THETA, h, material="nh", tol=1e-8).kappa_s
    softer = ce.snap_curvature(THETA, h, lam / 10, tol=1e-8).kappa_s
    assert min(nh, softer) < a.kappa_s < max(nh, softer)


@pytest.mark.slow
def test_thin_shell_reaches_its_round_off_floor_honestly():
    """h = 1e-3 (T = 16.6, N ~ 100): the polishing Newton's first step from a cold inner
    root is off by ~1e-9 and the next undoes it (it used to fail there); kappa_s at tol 1e-9
    agrees with tol 1e-10 (its own ladder) within the estimate, which includes the round-off
    floor 5 eps (1 + kappa_s) / h = 1.7e-11; tol 1e-11 is below that floor and refused."""
    a = ce.snap_curvature(THETA, 1e-3, model="plane_strain", tol=1e-9)
    b = ce.snap_curvature(THETA, 1e-3, model="plane_strain", tol=1e-10)
    assert abs(a.kappa_s - b.kappa_s) <= a.error_estimate
    with pytest.raises(ConvergenceError, match="ask for a tolerance >= 2e-11"):
        ce.snap_curvature(THETA, 1e-3, model="plane_strain", tol=1e-11)


def test_tolerance_below_the_round_off_floor_is_refused_with_the_allowed_one():
    """The default cap's kappa_s scatters by ~1e-13 with round-off (the floor in the
    estimate is 5 eps (1 + kappa_s) / h = 6e-13): tol 1e-13 cannot be promised."""
    with pytest.raises(ConvergenceError, match=r"ask for a tolerance >= 6e-13"):
        ce.snap_curvature(THETA, 0.01, tol=1e-13)


def test_stiff_material_floor_grows_with_lam():
    """Relaxed CG at lam = 1e3: the lam term's forces carry round-off ~ lam eps, and folds
    located at different degrees scatter by 2.7e-12 (test below), five times the floor of a
    soft material; the floor is then 5 eps (1 + kappa_s) / h x lam / 100 = 5.007e-12, and
    tol 1e-12 (which a soft cap allows) is refused with the tolerance allowed, rounded up
    (6e-12 is accepted). (A work-precision run at tol 1e-12
    gave an error of 2.6e-12 against an estimate of 7.9e-13 before the floor grew.)"""
    with pytest.raises(ConvergenceError, match=r"ask for a tolerance >= 6e-12"):
        ce.snap_curvature(THETA, 0.01, 1e3, tol=1e-12)
    assert ce.snap_curvature(THETA, 0.01, 1e3, tol=6e-12).error_estimate <= 6e-12


@pytest.mark.slow
@pytest.mark.parametrize("lam", [1e3, 1e4])
def test_stiff_material_floor_bounds_the_scatter_between_degrees(lam):
    """Folds of the stiff cap located on ladders from degrees 40, 48, 56, 64 (different
    Newton paths and discretisations, each converged far below the floor) lie within the
    floor of each other; each estimate is at least that floor."""
    from shellbvp import Chebyshev, cap
    from shellbvp.bvp import ShellBVP

    runs = [ce.snap_curvature(THETA, 0.01, lam, tol=1e-10, method=Chebyshev(nodes=N))
            for N in (40, 48, 56, 64)]
    k = [r.kappa_s for r in runs]
    floor = ShellBVP(cap(THETA, 0.01, lam=lam)).round_off(k[0])
    assert max(k) - min(k) <= floor
    assert min(r.error_estimate for r in runs) >= floor


@pytest.mark.slow
def test_deep_cap_estimate_bounds_its_error():
    """Theta = 0.95 pi (T = 29.8, N ~ 180): with rungs of 4 degrees the fold converged by a
    factor ~0.6 per rung and one change (3e-10) understated the error (1e-9); rungs in
    proportion to N make the estimate bound the difference to a finer computation."""
    a = ce.snap_curvature(0.95 * math.pi, 0.01, tol=1e-9)
    b = ce.snap_curvature(0.95 * math.pi, 0.01, tol=1e-11)
    assert abs(a.kappa_s - b.kappa_s) <= a.error_estimate


@pytest.mark.slow
def test_loose_tolerance_estimate_includes_the_fold_location():
    """h = 1e-3 at tol 1e-4: both rungs stop at a monitor within 1e-5 of the fold, so their
    change (~1e-12) missed the location error in kappa_s (6e-9); the estimate includes it."""
    loose = ce.snap_curvature(THETA, 1e-3, tol=1e-4)
    fine = ce.snap_curvature(THETA, 1e-3, tol=1e-9)
    assert abs(loose.kappa_s - fine.kappa_s) <= loose.error_estimate


def test_a_branch_cut_short_is_no_claim_of_no_snap():
    """A branch that ends at max_steps before a fold or full eversion says so in
    Branch.stop, and kappa_s refuses to report "no snap" from it (it used to)."""
    from shellbvp import ContinuationOptions

    short = ContinuationOptions(max_steps=10)
    b = ce.branch(THETA, 0.01, options=short, energies=False)
    assert not b.folds and "max_steps = 10" in b.stop
    with pytest.raises(ConvergenceError, match="ended before a fold or full eversion"):
        ce.snap_curvature(THETA, 0.01, options=short)
