"""Past an axisymmetric bifurcation (n = 0 without a fold: a branch point of the
axisymmetric branch, :mod:`shellbvp.continuation.branch_points`): the bifurcated
axisymmetric branch and Koiter's coefficients, both on the branch's own discrete system.

Branch switching. At the branch point (U*, p*) with null vector phi, the bifurcated branch
leaves along phi (the branch's own tangent is orthogonal to it at a symmetric state, and at
a pitchfork the bifurcated branch's p is stationary). Its points are solved with the
monitor prescribed, m = m* + a (the monitor moves along phi wherever dm . phi != 0, as the
centre deflection of a plate does), from the start U* + (a / dm . phi) phi; from the first
one the same pseudo-arclength continuation follows it (:func:`follow_branch_point`).

Koiter's coefficients (:func:`axisymmetric_koiter`). In the classical normalisation
p / p_c = 1 + a_K xi + b_K xi^2 + ..., xi the largest normal displacement from the
branch point's state over the thickness (signed: its value where the mode's normal
displacement is largest), measured on the bifurcated branch itself: solved at monitor
amplitudes +-a and +-a/2, the odd part of p / p_c - 1 over xi gives a_K, the even part over
xi^2 gives b_K, each extrapolated to a -> 0 (Richardson: both are even in a to the next
order); the change of the extrapolation, plus the change from the branch point's coarser
rung, is the error estimate. This uses only the discrete
equations (no third or fourth derivatives), so it holds for any discretisation.
b_K > 0 with a_K = 0: a supercritical (stable) symmetric pitchfork, as the plate's
(Friedrichs & Stoker 1941); b_K < 0: subcritical, imperfection sensitive.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .continuation import ContinuationOptions, newton, pseudo_arclength
from .errors import ConvergenceError
from .results import Branch

__all__ = ["AxisymmetricKoiter", "axisymmetric_koiter", "follow_branch_point",
           "BifurcatedBranch", "KOITER_AMPLITUDE"]

#: the largest amplitude of Koiter's fit, as xi (normal displacement over the thickness)
KOITER_AMPLITUDE = 0.02


@dataclass(frozen=True)
class AxisymmetricKoiter:
    """Koiter's coefficients at an axisymmetric bifurcation (module docstring).

    Attributes:
        p_c: the branch point; parameter: its name.
        a, b: p / p_c = 1 + a xi + b xi^2 + ..., xi = w_max / h.
        a_error, b_error: their error estimates (Richardson's change).
        h: the thickness of the normalisation.
        direction: +1 or -1, the way p moved along the axisymmetric branch to p_c.
        samples: (xi, p) of the bifurcated states used.
    """

    p_c: float
    parameter: str
    a: float
    b: float
    a_error: float
    b_error: float
    h: float
    direction: float
    samples: tuple = field(repr=False, default=())

    @property
    def kind(self) -> str:
        """``"asymmetric"`` (a != 0 to its error: transcritical), else ``"supercritical"``
        (the bifurcated branch goes on along the loading) or ``"subcritical"``."""
        if abs(self.a) > max(10 * self.a_error, 1e-8):
            return "asymmetric"
        return "supercritical" if self.b * self.direction > 0 else "subcritical"

    def __repr__(self) -> str:
        return (f"AxisymmetricKoiter(n = 0, {self.kind}, {self.parameter}_c = {self.p_c:.10g}, "
                f"a = {self.a:.3g} +- {self.a_error:.1e}, b = {self.b:.6g} +- "
                f"{self.b_error:.1e})")


@dataclass(frozen=True)
class BifurcatedBranch:
    """The axisymmetric branch from an axisymmetric bifurcation: ``branch`` (a
    :class:`shellbvp.Branch` of the same scene and discretisation, from the first point
    off the branch point), ``koiter`` (:class:`AxisymmetricKoiter`) and ``branch_point``."""

    branch: Branch
    koiter: AxisymmetricKoiter
    branch_point: object = field(repr=False)

    @property
    def n(self) -> int:
        return 0


def _normal(system, dU):
    """The normal displacement of a change of the unknowns dU at the nodes (P, nodes):
    (dr, dz) . (sin theta0, cos theta0), theta0 the reference's tangent angle."""
    Y0 = system.Y0
    d = system.split(dU)
    return d[:, 0] * np.sin(Y0[:, 2]) + d[:, 1] * np.cos(Y0[:, 2])


class _Off:
    """Bifurcated states at prescribed monitor offsets a from the branch point."""

    def __init__(self, bp, tol):
        self.bp, self.tol = bp, tol
        self.system = bp.system
        _, gm = self.system.monitor(bp.U)
        self.rate = float(gm @ bp.null)
        if not abs(self.rate) > 0:
            raise ConvergenceError("the monitor does not move along the branch point's null "
                                   "vector: it cannot tell the bifurcated branch from the "
                                   "axisymmetric one (give the scene another monitor)")
        w = _normal(self.system, bp.null)
        self.where = np.unravel_index(int(np.argmax(np.abs(w))), w.shape)
        self.known = {}

    def __call__(self, a):
        if a not in self.known:
            bp = self.bp
            U0 = bp.U + (a / self.rate) * bp.null
            res = newton(self.system, U0, bp.p, 1.0, 0.0, bp.monitor + a, tol=self.tol,
                         maxiter=30, fail_fast=False)
            if not res.ok:
                raise ConvergenceError(f"branch switching: no bifurcated state at monitor "
                                       f"offset {a:.3g} ({res.history[-3:]})")
            self.known[a] = res
        return self.known[a]

    def xi(self, res, h):
        w = _normal(self.system, res.U - self.bp.U)
        sign = math.copysign(1.0, w[self.where]) if w[self.where] != 0 else 1.0
        return sign * float(np.abs(w).max()) / h


def _fit(bp, xi_max, tol):
    """(a, b, Richardson's changes of a and b, samples) on ``bp``'s own system."""
    system = bp.system
    h = float(system.bvp.scene.h)
    off = _Off(bp, tol)
    # the monitor offset whose state has xi ~ xi_max: linear in a to leading order
    w = _normal(system, bp.null)
    a1 = xi_max * h / float(np.abs(w).max()) * abs(off.rate)
    fits, samples = [], []
    for a in (a1, 0.5 * a1):
        plus, minus = off(a), off(-a)
        xp, xm = off.xi(plus, h), off.xi(minus, h)
        qp, qm = plus.p / bp.p - 1.0, minus.p / bp.p - 1.0
        samples += [(xp, plus.p), (xm, minus.p)]
        # q = A x + B x^2 at both: the 2 x 2 system
        fits.append(np.linalg.solve([[xp, xp * xp], [xm, xm * xm]], [qp, qm]))
    (A1, B1), (A2, B2) = fits
    # the neglected terms are O(x^2) relative: Richardson over the halved amplitude
    a_K, b_K = (4 * A2 - A1) / 3, (4 * B2 - B1) / 3
    return a_K, b_K, abs(a_K - A2), abs(b_K - B2), tuple(samples)


def axisymmetric_koiter(bp, *, direction: float = 1.0, xi_max: float = KOITER_AMPLITUDE,
                        tol: float = 1e-12) -> AxisymmetricKoiter:
    """Koiter's a and b at the branch point ``bp`` (a
    :class:`shellbvp.continuation.branch_points.BranchPoint`) from its bifurcated states
    (module docstring). ``direction``: the way p moved to p_c along the axisymmetric branch;
    ``xi_max``: the largest amplitude used (normal displacement over the thickness).
    The error estimates: Richardson's change, plus the change from the branch point's
    previous rung (``bp.previous``, where it was located on a ladder)."""
    a_K, b_K, a_err, b_err, samples = _fit(bp, xi_max, tol)
    if bp.previous is not None:
        a_c, b_c, _, _, _ = _fit(bp.previous, xi_max, tol)
        a_err, b_err = a_err + abs(a_K - a_c), b_err + abs(b_K - b_c)
    return AxisymmetricKoiter(
        p_c=float(bp.p), parameter=bp.system.bvp.scene.parameter, a=float(a_K),
        b=float(b_K), a_error=float(a_err), b_error=float(b_err),
        h=float(bp.system.bvp.scene.h), direction=float(direction), samples=samples)


#: the first point's monitor offsets tried, in units of the default (the normal displacement a
#: hundredth of the thickness), where no start is given: next to a branch point whose
#: symmetry the discretisation breaks, a start too near it may not converge (a short cylinder
#: between mirror planes: 1 failed, 4 and 64 converged, 16 did not)
START_FACTORS = (1.0, 4.0, 16.0, 64.0, 256.0)


def follow_branch_point(instability, *, start: float | None = None, p_stop=None,
                        w_stop=None, n_folds=None,
                        options: ContinuationOptions | None = None,
                        progress=None) -> BifurcatedBranch:
    """The bifurcated axisymmetric branch from an axisymmetric bifurcation found by
    :func:`shellbvp.first_instability` (kind ``"bifurcation"``, n = 0), and Koiter's a, b
    there (module docstring).

    Arguments:
        instability: the :class:`shellbvp.Instability` (it carries the branch point).
        start: the monitor offset of the first point (w / H; default: where the normal
            displacement is a hundredth of the thickness, then ``START_FACTORS`` times
            that until the continuation starts), on the side where the monitor grows
            (give it negative for the other half of a pitchfork).
        p_stop, w_stop: (low, high) stops in p and w (R0), as :func:`shellbvp.follow`.
        n_folds: folds to pass before stopping (None: no limit).
        options: the continuation's settings (default ContinuationOptions()).
        progress: called with every accepted continuation point.

    Raises:
        ValueError: an instability that is not an axisymmetric bifurcation, or one with no
            branch point of the branch's own system (``note`` says why).
        ConvergenceError: no first point converges (with the Newton history).
    """
    bp = getattr(instability, "branch_point", None)
    if getattr(instability, "kind", None) == "bifurcation" and instability.n == 0 \
            and bp is None:
        raise ValueError("this axisymmetric bifurcation carries no branch point of the "
                         "branch's own discrete system to switch branches from: "
                         f"{instability.note or 'none was located'}; follow the scene with "
                         "another method (spectral or collocation)")
    if getattr(instability, "kind", None) != "bifurcation" or instability.n != 0 or bp is None:
        raise ValueError("instability must be an axisymmetric bifurcation (kind "
                         "'bifurcation', n = 0) from shellbvp.first_instability, got "
                         f"{instability!r}")
    options = ContinuationOptions() if options is None else options
    system = bp.system
    scene = system.bvp.scene
    H = system.bvp.scale
    direction = math.copysign(1.0, instability.p - instability.scan[0][0]) \
        if instability.scan else 1.0
    kc = axisymmetric_koiter(bp, direction=direction, tol=min(options.newton_tol, 1e-10))
    off = _Off(bp, options.newton_tol)
    if start is None:
        w = _normal(system, bp.null)
        base = 0.01 * scene.h / float(np.abs(w).max()) * abs(off.rate)
        starts = [k * base for k in START_FACTORS]
    else:
        starts = [float(start)]
    lo, hi = (-math.inf, math.inf) if p_stop is None else map(float, p_stop)
    wlo, whi = (-math.inf, math.inf) if w_stop is None else map(float, w_stop)
    for k, start in enumerate(starts):
        stop = ""
        try:
            first = off(start)
            # the way the continuation first moves: away from the branch point in the
            # monitor
            pts, brackets = pseudo_arclength(
                system, first.U, first.p, options=options, p_stop=(lo, hi),
                monitor_stop=(wlo / H, whi / H), n_folds=n_folds,
                direction=math.copysign(1.0, first.p - bp.p) if first.p != bp.p else 1.0,
                progress=progress)
            break
        except ConvergenceError as exc:
            if exc.partial is not None:
                (pts, brackets), stop = exc.partial, f"continuation stalled: {exc}"
                break
            if k == len(starts) - 1:
                raise ConvergenceError(
                    f"branch switching: no start on the bifurcated branch at the monitor "
                    f"offsets {', '.join(f'{s:.3g}' for s in starts)}: {exc}") from exc
    if math.copysign(1.0, pts[-1].monitor - bp.monitor) != math.copysign(1.0, float(start)):
        stop = stop or "the continuation turned back toward the branch point"
    n = len(pts)
    nan = np.full(n, math.nan)
    branch = Branch(scene=scene, p=np.array([q.p for q in pts]),
                    w=np.array([q.monitor for q in pts]) * H, energy=nan,
                    stretching_energy=nan, bending_energy=nan, load_potential=nan,
                    arclength=np.array([q.arclength for q in pts]), folds=(),
                    stats=dict(system.describe(), points=n, folds_passed=len(brackets)),
                    points=tuple(pts), system=system, stop=stop,
                    error_note="not estimated (a bifurcated branch)")
    return BifurcatedBranch(branch=branch, koiter=kc, branch_point=bp)
