"""Pseudo-arclength continuation of a discrete system R(U, p) = 0, with exact tangents.

Arclength is measured in the whole space (U, p) with the RMS norm of U
(|U|^2 / n + p^2), so that a change of shape counts as much as a change of parameter. The
predictor is the exact tangent (from the bordered matrix of the converged corrector, no
secant), so dp/ds is known at every point and a fold is where it changes sign. Step
control: the next step is scaled so that the tangent turns by about ``options.turn`` radians
and the first Newton contraction stays near ``options.contraction`` (at most doubling,
halving after a failed correction), within [ds_min, ds_max].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..errors import ConvergenceError
from .newton import NewtonResult, newton, tangent
from .options import ContinuationOptions

__all__ = ["Point", "point_at_monitor", "pseudo_arclength"]

#: iterations allowed to the first (natural-parameter) solve, which may start far away
START_MAXITER = 40
#: a fold probe (``ContinuationOptions.fold_probe``) aims this many times as far as the
#: secant of dp/dm predicts the fold: past it even where that prediction falls short by
#: half (it did by 5-10 % on the default cap, where dp/dm is convex in m)
PROBE_REACH = 2.0


@dataclass(frozen=True)
class Point:
    """A converged point of a branch: parameter p, monitor m (w / H for a shell), the
    arclength in the (m, p) plane, the unknowns U, the unit tangent (dm/ds, dp/ds) and the
    tangent of U per unit arclength, and the corrector's iteration count."""

    p: float
    monitor: float
    arclength: float
    U: np.ndarray = field(repr=False)
    tangent: tuple = (0.0, 0.0)
    dU: np.ndarray = field(repr=False, default=None)
    iterations: int = 0

    @property
    def slope(self) -> float:
        """dp/dm along the branch here (exact, from the tangent)."""
        return self.tangent[1] / self.tangent[0]

    def predicted(self, monitor: float):
        """(U, p) at the monitor value ``monitor`` predicted along this point's exact tangent
        (the start of a Newton solve with that monitor prescribed)."""
        dm = monitor - self.monitor
        return self.U + dm * self.dU / self.tangent[0], self.p + dm * self.slope

    @classmethod
    def from_newton(cls, res: NewtonResult, v, dp, *, sign: float = 1.0,
                    arclength: float = 0.0) -> "Point":
        """The point of a converged corrector ``res`` with its tangent (v, dp) (from
        :func:`~.newton.tangent`), normalised to unit length in the RMS norm of the module
        docstring and oriented by ``sign``."""
        n = res.U.size
        nrm = math.sqrt(float(v @ v) / n + dp * dp)
        v, dp = sign * v / nrm, sign * dp / nrm
        return cls(res.p, res.m, arclength, res.U, (float(res.gm @ v), dp), v, res.iterations)


def point_at_monitor(system, U, p, monitor: float, *, tol: float,
                     maxiter: int = 25) -> Point:
    """The branch point with the monitor prescribed: bordered Newton from (U, p) (e.g.
    :meth:`Point.predicted` of a nearby point), as a :class:`Point` with its exact tangent.
    Raises ConvergenceError where Newton does not converge."""
    res = newton(system, U, p, 1.0, 0.0, monitor, tol=tol, maxiter=maxiter, fail_fast=False)
    if not res.ok:
        raise ConvergenceError(f"no branch point with the monitor at {monitor:.10g}: "
                               f"{res.history}")
    v, _, dp = tangent(res)
    return Point.from_newton(res, v, dp)


def _fold_ahead(a: Point, b: Point, reach: float):
    """The monitor value at which to probe for a fold ahead of b, or None: dp/dm at a and b
    (consecutive points, the monitor moving the same way at both) has one sign and falls
    in size, its secant in m predicts a zero at m* within ``reach`` (the next step's
    predicted move in m) of b, so that the next step would likely cross the fold: then
    b.monitor + PROBE_REACH (m* - b.monitor). (Probing only where that point, rather than
    m*, lies within reach missed the default cap in plane strain, whose next step then
    landed far past the fold: 16 evaluations instead of 14.)"""
    if a.tangent[0] * b.tangent[0] <= 0:
        return None
    ga, gb = a.slope, b.slope
    if not (ga * gb > 0 and abs(gb) < abs(ga)):
        return None
    move = -PROBE_REACH * gb * (b.monitor - a.monitor) / (gb - ga)
    return b.monitor + move if 0 < move / reach <= PROBE_REACH else None


def _hermite(a: Point, b: Point, monitor: float):
    """(U, p) at the monitor value ``monitor`` ahead of b, extrapolated by the cubic Hermite
    interpolant in m through a and b (values and exact tangents at both). A fold probe aims
    past the fold, where p(m) turns: the linear prediction along b's tangent overshoots p
    there, and a quadratic in m (symmetric about the fold it predicts) comes back to b's p
    (6.07 and 2.47 for a probe whose point lies at p = 4.195 on the default cap; Newton
    needed 3-4 updates from either)."""
    h = b.monitor - a.monitor
    t = (monitor - a.monitor) / h
    t2, t3 = t * t, t * t * t
    h00, h10, h01, h11 = 2 * t3 - 3 * t2 + 1, t3 - 2 * t2 + t, 3 * t2 - 2 * t3, t3 - t2
    ua, ub = a.dU / a.tangent[0], b.dU / b.tangent[0]
    return (h00 * a.U + h10 * h * ua + h01 * b.U + h11 * h * ub,
            h00 * a.p + h10 * h * a.slope + h01 * b.p + h11 * h * b.slope)


def _probe(system, a: Point, b: Point, target: float, o: ContinuationOptions):
    """The branch point past b where the monitor equals ``target`` (Newton with the monitor
    prescribed, from the cubic extrapolation through a and b), or None where that
    fails."""
    res = newton(system, *_hermite(a, b, target), 1.0, 0.0, target, tol=o.newton_tol,
                 maxiter=o.newton_maxiter, predict=o.predicted_stop)
    return res if res.ok else None


def pseudo_arclength(system, U0, p0, *, options: ContinuationOptions = ContinuationOptions(),
                     p_stop=(-math.inf, math.inf), monitor_stop=(-math.inf, math.inf),
                     n_folds=None, direction=1.0, progress: Callable | None = None,
                     admissible: Callable | None = None):
    """Follow the branch of ``system`` through the solution near (U0, p0).

    Stops when p leaves ``p_stop``, the monitor leaves ``monitor_stop``, after ``n_folds``
    folds, or at ``options.max_steps`` points. ``direction``: sign of the first step in p.
    ``progress(point)`` is called after every accepted point. ``admissible(point)`` may
    veto a converged point: it returns "" to accept it, else the reason why not; a vetoed
    step is retried shorter, and a veto down to ``ds_min`` ends the branch as a stall does
    (ConvergenceError with that reason and ``partial``).

    Returns (points, brackets): the points and, for every fold passed, the index pair
    (i, i + 1) of the points between which dp/ds changed sign.
    Raises ConvergenceError (with the Newton history) if the start does not converge or the
    step falls below ``ds_min``; in the latter case its ``partial`` is (points, brackets) so
    far, every one of them converged.
    """
    o = options
    n = system.size
    res = newton(system, U0, p0, 0.0, 1.0, p0, tol=o.newton_tol, maxiter=START_MAXITER,
                 fail_fast=False)
    if not res.ok:
        why = f"{res.diagnosis}; " if res.diagnosis else ""
        raise ConvergenceError(f"continuation: no solution at the start {p0:g}: {why}Newton "
                               f"history {res.history}", round_off=bool(res.diagnosis))
    v, _, dp = tangent(res)
    pts = [Point.from_newton(res, v, dp, sign=math.copysign(1.0, direction * dp))]
    if progress:
        progress(pts[0])
    brackets = []
    ds = o.ds
    probed = 0          # the point a fold probe was last tried from (one try per point)

    def oriented(res, b, probe=False):
        v, dm, dp = tangent(res)
        if probe:
            # the monitor, prescribed, is the coordinate: it keeps moving the way it did at
            # b (v = dU/dm, dm = 1), so dp/ds changes sign exactly where dp/dm does (the
            # angle to b's tangent can exceed 90 degrees over a probe's long step)
            sign = math.copysign(1.0, b.tangent[0] * dm)
        else:
            sign = 1.0 if float(v @ b.dU) / n + dp * b.tangent[1] > 0 else -1.0  # keep it
        arc = b.arclength + math.hypot(res.m - b.monitor, res.p - b.p)
        return Point.from_newton(res, v, dp, sign=sign, arclength=arc)

    def accept(new, b):
        if new.tangent[1] * b.tangent[1] < 0:
            brackets.append((len(pts) - 1, len(pts)))
        pts.append(new)
        if progress:
            progress(new)

    while len(pts) < o.max_steps:
        b = pts[-1]
        # the start is exempt: at p0 on the edge of p_stop (e.g. p0 = 0, p_stop = (0, ...)),
        # its p is p0 to round-off, on either side
        if len(pts) > 1 and not (p_stop[0] <= b.p <= p_stop[1]
                                 and monitor_stop[0] <= b.monitor <= monitor_stop[1]):
            break
        if n_folds is not None and len(brackets) >= n_folds:
            break
        tp = b.tangent[1]
        if o.fold_probe and len(pts) >= 2 and probed < len(pts):
            # a fold predicted within the next step: a point just past it instead (the
            # monitor prescribed), so that the bracket is tight; a failure or a veto leaves
            # the ordinary step to be taken
            probed = len(pts)
            target = _fold_ahead(pts[-2], b, ds * b.tangent[0])
            res = None if target is None else _probe(system, pts[-2], b, target, o)
            if res is not None:
                new = oriented(res, b, probe=True)
                if not (admissible and admissible(new)):
                    accept(new, b)
                    continue
        row = b.dU / n
        c = float(row @ b.U) + tp * b.p + ds
        res = newton(system, b.U + ds * b.dU, b.p + ds * tp, 0.0, tp, c, row=row,
                     tol=o.newton_tol, maxiter=o.newton_maxiter, predict=o.predicted_stop)
        why = ""
        if res.ok:
            new = oriented(res, b)
            why = admissible(new) if admissible else ""
        if not res.ok or why:
            # a failed or vetoed step is retried shorter: a long step may jump to another
            # solution; a veto that persists down to ds_min is where the branch ends
            ds /= 2
            if ds < o.ds_min:
                raise ConvergenceError(why or (
                    f"continuation stalled at p = {b.p:.10g} (monitor {b.monitor:.6g}): Newton "
                    f"failed down to ds_min = {o.ds_min:g}; last history {res.history}"),
                    partial=(pts, brackets))
            continue
        accept(new, b)
        cosang = float(new.dU @ b.dU) / n + new.tangent[1] * tp
        angle = math.acos(max(-1.0, min(1.0, cosang)))
        factor = o.turn / max(angle, 1e-12)
        if len(res.history) >= 2 and res.history[0][1] > 0:
            theta = res.history[1][1] / res.history[0][1]
            factor = min(factor, math.sqrt(o.contraction / max(theta, 1e-12)))
        ds = min(max(ds * min(2.0, max(0.5, factor)), o.ds_min), o.ds_max)
    return pts, brackets
