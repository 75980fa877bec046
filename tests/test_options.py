"""Every option is honoured or refused: for each named option of a method, a continuation or a
scene, changing it changes the result, or the call raises a ValueError that names it (never
silently ignored). The references are either exact (Bratu's fold, tests/bratu.py) or the
option's own documented effect (the resolution a ladder starts from)."""

import math

import numpy as np
import pytest

import shellbvp
from bratu import LAM_STAR, BratuBVP
from shellbvp import Collocation, ContinuationOptions, Shooting, cap
from shellbvp.bvp import ShellBVP
from shellbvp.continuation import pseudo_arclength, refine_fold
from shellbvp.problems import cap_eversion as ce
from shellbvp.problems import pressure_cap as pc

CAP = dict(theta=math.pi / 6, h=0.01)


def _bratu_fold(method, fold_tol):
    system = method.discretise(BratuBVP())
    o = ContinuationOptions(ds=0.5, ds_max=2.0, ds_min=1e-5, fold_tol=fold_tol)
    pts, brackets = pseudo_arclength(system, np.zeros(system.size), 0.0, options=o,
                                     n_folds=1, p_stop=(-1.0, 5.0))
    (i, j), = brackets
    return refine_fold(system, pts[i], pts[j], options=o, index=i)


# --- Collocation -------------------------------------------------------------------------------
def test_collocation_tol_changes_a_solve():
    """solve_bvp's tolerance decides its final mesh (Bratu's problem at p = 3)."""
    zero = lambda s: np.zeros((2, np.size(s)))  # noqa: E731
    loose = Collocation(tol=1e-3, nodes=11).solve(BratuBVP(), 3.0, zero)[2]
    tight = Collocation(tol=1e-9, nodes=11).solve(BratuBVP(), 3.0, zero)[2]
    assert tight["nodes"] > loose["nodes"]


def test_collocation_tol_is_refused_by_a_continuation():
    with pytest.raises(ValueError, match="Collocation.tol"):
        ce.branch(kappa_max=0.5, method=Collocation(tol=1e-8), **CAP)
    with pytest.raises(ValueError, match="Collocation.tol"):
        shellbvp.at_monitor(ce.scene(**CAP), 0.001, method=Collocation(tol=1e-8))


def test_collocation_max_nodes_bounds_the_fold_ladder():
    """Bratu's fold to 1e-12 needs meshes beyond 100 nodes (4th order from 11): with
    max_nodes = 100 the ladder stops and says so; with the default it reaches the fold."""
    assert abs(_bratu_fold(Collocation(nodes=11), 1e-10).p - LAM_STAR) <= 1e-10
    with pytest.raises(shellbvp.ConvergenceError, match="max_nodes = 100"):
        _bratu_fold(Collocation(nodes=11, max_nodes=100), 1e-12)


# --- Shooting ----------------------------------------------------------------------------------
def test_shooting_fixed_steps_exclude_tolerances():
    for kw in (dict(steps=8, rtol=1e-8), dict(steps=8, bracket_rtol=1e-5)):
        with pytest.raises(ValueError, match="steps"):
            Shooting(**kw)


def test_shooting_fold_ladder_starts_where_the_tolerance_asks():
    """rtol left free: the ladder's first rung is at the fold tolerance (the work follows
    tol); rtol given: there, whatever the tolerance; bracket_rtol: the branch's system."""
    bvp = ShellBVP(ce.scene(**CAP))
    free = Shooting().discretise(bvp)
    assert free.rtol == 1e-10                      # equilibria and branches: SOLVE_RTOL
    assert free.for_tolerance(1e-7).rtol == 1e-7
    assert free.for_tolerance(1e-9).rtol == 1e-9
    fixed = Shooting(rtol=1e-11).discretise(bvp)
    assert fixed.for_tolerance(1e-7).rtol == 1e-11
    bracket = Shooting(bracket_rtol=1e-5).discretise(bvp)
    assert bracket.rtol == 1e-5 and bracket.for_tolerance(1e-8).rtol == 1e-8
    assert Shooting(steps=16).discretise(bvp).for_tolerance(1e-8).steps == 16


@pytest.mark.slow  # the shooting back-end compiles for ~20 s
def test_shooting_snap_curvature_follows_tol():
    """method="shooting" with tol: the ladder starts at rtol = tol, and kappa_s agrees with
    the spectral method within the estimates."""
    ref = ce.snap_curvature(tol=1e-10, **CAP)
    r = ce.snap_curvature(tol=1e-7, method="shooting", **CAP)
    assert r.stats["fold"]["first"]["rtol"] == 1e-7
    assert abs(r.kappa_s - ref.kappa_s) <= r.error_estimate + ref.error_estimate


# --- the fold tolerance: one place ---------------------------------------------------------------
def test_fold_tolerance_given_twice_is_refused():
    with pytest.raises(ValueError, match="fold tolerance was given twice"):
        ce.snap_curvature(tol=1e-8, options=ContinuationOptions(fold_tol=1e-6), **CAP)
    with pytest.raises(ValueError, match="fold tolerance was given twice"):
        pc.critical_pressure(5.0, tol=1e-8, options=ContinuationOptions(fold_tol=1e-3))


def test_options_fold_tol_alone_is_honoured():
    """A looser fold tolerance starts the ladder on a coarser degree (fewer rungs' work)."""
    loose = ce.snap_curvature(options=ContinuationOptions.to_first_fold(fold_tol=1e-5), **CAP)
    tight = ce.snap_curvature(tol=1e-10, **CAP)
    first = lambda r: r.stats["fold"]["first"]["nodes"]  # noqa: E731
    assert first(loose) < first(tight)
    assert abs(loose.kappa_s - tight.kappa_s) <= loose.error_estimate <= 1e-5


# --- parameters a material does not use ----------------------------------------------------------
@pytest.mark.parametrize("kw,name", [
    (dict(material="nh", lam=-3.0), "lam"),
    (dict(material="nh", lam=2.0), "lam"),
    (dict(material="nh", model="plane_strain"), "model"),
    (dict(material="koiter", lam=2.0), "lam"),
    (dict(material="koiter", model="plane_strain"), "model"),
    (dict(material="cg", nu=0.3), "nu"),
])
def test_unused_material_parameters_are_refused(kw, name):
    with pytest.raises(ValueError, match=rf"^{name} = .* does not apply"):
        cap(0.5, 0.01, **kw)
    with pytest.raises(ValueError, match=name):
        ce.snap_curvature(0.5, 0.01, **{"lam": 1.0, **kw})


def test_pressure_cap_refuses_the_unused_material_parameter():
    with pytest.raises(ValueError, match="nu = 0.25 does not apply"):
        pc.scene(5.0, 100.0, 0.25, material="cg", lam=2.0)
    with pytest.raises(ValueError, match="lam = 2.0 does not apply"):
        pc.scene(5.0, 100.0, material="koiter", lam=2.0)


def test_parameter_column_names_its_unit():
    assert ce.scene(**CAP).parameter_column == "kappa_R0"
    assert pc.scene(5.0).parameter_column == "pressure_R0_over_mu_h0"
    from shellbvp.problems import budding as bd

    assert bd.scene(0.0, 1.0).parameter_column == "kbar"
