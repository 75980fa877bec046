"""Pictures of results (shellbvp.plotting): what they mark is checked against the scene's
own data, not against a picture."""

import math

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")

from shellbvp.plotting import stimulated  # noqa: E402
from shellbvp.problems import cap_eversion as ce  # noqa: E402

THETA, H = math.pi / 6, 0.01


@pytest.fixture(scope="module")
def branch():
    return ce.branch(THETA, H, kappa_max=4.5)


def test_equilibrium_plot_draws_the_meridian_and_both_strains(branch):
    eq = branch.folds[0].equilibrium
    shape_ax, strain_ax = eq.plot()
    x, y = shape_ax.lines[0].get_data()
    assert np.allclose(x, eq.r) and np.allclose(y, eq.z)
    assert np.allclose(shape_ax.lines[2].get_xdata(), -eq.r)   # the mirrored meridian
    labels = [line.get_label() for line in strain_ax.lines]
    assert labels[:2] == ["eps11 (meridional)", "eps22 (hoop)"]
    assert np.allclose(strain_ax.lines[1].get_ydata(), eq.eps22)
    only = eq.plot(strains=False, mirror=False)
    assert len(only.lines) == 2      # the meridian and its stimulated part


def test_stimulus_marks_follow_the_fields(branch):
    """A uniform curvature stimulus acts everywhere once kappa != 0 and nowhere at the
    undeformed start (kappa = 0: the target is the reference sphere)."""
    assert stimulated(branch.equilibrium(-1)).all()
    assert not stimulated(branch.equilibrium(0)).any()


@pytest.mark.slow   # a budding scene compiles its own programs (~30 s)
def test_stimulus_marks_the_budding_patch_only():
    from shellbvp.problems import budding as bd

    eq = bd.equilibrium(0.0, 1.0, 10.0)
    edge = eq.scene.breaks[0]
    on = stimulated(eq)
    assert on[eq.s < edge - 1e-12].all() and not on[eq.s > edge + 1e-12].any()


def test_branch_plot_marks_its_folds(branch):
    ax = branch.plot(label="relaxed")
    w, p = ax.lines[0].get_data()
    assert np.allclose(w, branch.w) and np.allclose(p, branch.p)
    fold = branch.folds[0]
    assert ax.lines[1].get_xydata().tolist() == [[fold.w, fold.p]]
    assert ax.get_ylabel() == branch.scene.parameter_column
