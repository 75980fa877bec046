"""The isotropic bud past its bifurcation (slow): the lobed branch of a shell of two pieces,
whose patch edge is a rigid joint imposed at finite amplitude (:mod:`shellbvp.fourier2d`).

Independent routes: the bifurcation of ``budding.first_instability`` (the energy method's
axisymmetric branch and the per-harmonic second variation with the joint linearised); the
joint's angle measured pointwise on a rule of 8x the points (only its projections on the
class's harmonics are imposed); the fold located again with twice the points in omega;
the fold's restabilisation seen in the spectrum of the Hessian on the joints' null space
(not in the continuation's monitor)."""

from functools import lru_cache

import numpy as np
import pytest

import shellbvp
from shellbvp import postbuckling as pb

pytestmark = pytest.mark.slow


@lru_cache(maxsize=None)
def bud():
    from shellbvp.problems import budding

    ins = budding.first_instability(1.0, 1.0)
    br = shellbvp.follow_bifurcation(
        ins, K=2, n_folds=1, p_stop=(0.0, 60.0), estimate_error=False,
        options=pb.LOBED_OPTIONS.with_(ds_max=0.5, max_steps=600))
    return ins, br


def test_the_bud_bifurcates_subcritically_where_first_instability_says():
    ins, br = bud()
    assert ins.kind == "bifurcation" and ins.n == br.n == 8
    assert abs(br.p_c - ins.p) <= ins.error_estimate, (br.p_c, ins.p, ins.error_estimate)
    assert br.koiter.kind == "subcritical"


def test_the_lobed_branch_restabilises_at_its_fold():
    """The unstable lobed branch (a negative eigenvalue within the class, -0.96 at its first
    point) turns at a fold below p_c, past which the eigenvalue is positive (1.08 at the
    last point): a stable lobed state exists there."""
    _, br = bud()
    assert len(br.folds) == 1, br.stop
    fo = br.folds[0]
    assert 25.0 < fo.p < br.p_c
    f = br.discretisation
    assert br.amplitude[-1] > fo.amplitude and br.p[-1] > fo.p      # past the fold
    before, after = (f.eigenvalues(br.states[j], br.p[j])[0] for j in (fo.index - 2, -1))
    assert before < 0 < after, (before, after)


def test_the_joint_holds_pointwise_near_the_bifurcation():
    """Only the joint angle's projections on the class's harmonics are imposed: measured on
    8x the rule's points, its largest value is 1.0e-3 of the tangent's turn across the
    edge at the branch's first point (amplitude 1e-3, nearly linear) and grows with the
    amplitude (0.11 rad, a fifth of the turn, at the fold with K = 2: the lobed states far
    from the bifurcation need more harmonics, figures/bud_lobed.py)."""
    _, br = bud()
    f = br.discretisation

    def ratio(U):     # the tangent's turn: harmonics n, 2n of x_s on the left over |x_s|
        turn = np.abs(f.joint_values(U)[1:, 3:6]).sum() / f.base.ends[(0, "b")][1]
        return np.max(np.abs(f.joint_angles(U))) / turn

    near, fold = ratio(br.states[0]), ratio(br.folds[0].y)
    assert near < 2e-3 and fold > 10 * near, (near, fold)


def test_the_fold_converges_in_the_rule_in_omega():
    """Far from the bifurcation the lobes are strongly nonlinear (slopes of order one at the
    patch edge) and the rule in omega aliases: the fold state's gradient under the
    full-circle rule with 4x the points is 7e-5 of its parts. The fold itself, located
    again with twice the points per period, moves by 6e-5 in kbar (1.7e-6 relative): the
    rule is not what limits it (the harmonics are: figures/bud_lobed.py)."""
    _, br = bud()
    fo = br.folds[0]
    f = br.discretisation
    fine = pb._fold_on(f.with_points(2 * f.points), br.critical, fo.y, fo.p, fo.amplitude,
                       1e-9)
    assert abs(fine.p - fo.p) < 1e-5 * fo.p, (fine.p, fo.p)
