"""Pseudo-arclength continuation of a discrete system R(U, p) = 0, with exact tangents.

Arclength is measured in the whole space (U, p) with the RMS norm of U
(|U|^2 / n + p^2), so that a change of shape counts as much as a change of parameter; a
group of unknowns (a nodal method's components r, z, theta, m, f_r, f_z) whose rate per
unit parameter at the branch's start exceeds ``RATE_CAP`` enters scaled down to it
(:func:`unknown_weights`): a thin shell's forces, scaled by 12/h^2, grow like (R/h)^2 per
unit load, and would otherwise make every step a tiny change of the parameter. The
predictor is the exact tangent (from the bordered matrix of the converged corrector, no
secant), so dp/ds is known at every point and a fold is where it changes sign. Step
control: the next step is scaled so that the tangent turns by about ``options.turn`` radians
and the first Newton contraction stays near ``options.contraction`` (at most doubling,
halving after a failed correction), within [ds_min, ds_max].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from typing import Callable, Protocol, runtime_checkable

import numpy as np

from ..errors import ConvergenceError
from .newton import NewtonResult, newton, tangent
from .options import ContinuationOptions

__all__ = ["Point", "point_at_monitor", "point_at_parameter", "pseudo_arclength",
           "unknown_weights", "Grouped", "RATE_CAP"]

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
    tangent of U per unit arclength, the corrector's iteration count and the branch's
    length so far in the continuation's norm."""

    p: float
    monitor: float
    arclength: float
    U: np.ndarray = field(repr=False)
    tangent: tuple = (0.0, 0.0)
    dU: np.ndarray = field(repr=False, default=None)
    iterations: int = 0
    #: the length of the branch from its start to here in the continuation's own norm (the
    #: one its steps ds are measured in: the module docstring), summed over the chords
    path: float = 0.0

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
                    arclength: float = 0.0, weights=None) -> "Point":
        """The point of a converged corrector ``res`` with its tangent (v, dp) (from
        :func:`~.newton.tangent`), normalised to unit length in the norm of the module
        docstring (``weights``, see :func:`unknown_weights`; None: the plain RMS of U) and
        oriented by ``sign``."""
        n = res.U.size
        wv = v if weights is None else weights * v
        nrm = math.sqrt(float(wv @ wv) / n + dp * dp)
        v, dp = sign * v / nrm, sign * dp / nrm
        return cls(res.p, res.m, arclength, res.U, (float(res.gm @ v), dp), v, res.iterations)


@runtime_checkable
class Grouped(Protocol):
    """A discrete system whose unknowns fall into groups of one kind each (a nodal method's
    components r, z, theta, m, f_r, f_z): ``groups`` (size,) of small integers."""

    groups: np.ndarray


#: the largest rate per unit parameter at which a group of unknowns enters the
#: continuation's norm (:func:`unknown_weights`)
RATE_CAP = 20.0


def unknown_weights(system, rate) -> np.ndarray | None:
    """Weights w of the continuation's norm |dU|^2 = sum (w_i dU_i)^2 / n: 1, but for a
    group of unknowns (:class:`Grouped`; one group otherwise) whose RMS rate dU/dp at the
    branch's start exceeds ``RATE_CAP``, which is scaled down to that rate. The forces of a
    thin shell, scaled by 12/h^2, grow like (R/h)^2 per unit load: unscaled, they would
    make every step a tiny change of the parameter (a nearly straight branch crossed in
    thousands of steps). None where no group is scaled (the plain RMS norm)."""
    from ..methods.base import implements

    rate = np.asarray(rate, dtype=float)
    n = rate.size
    groups = np.asarray(system.groups) if implements(system, Grouped) else np.zeros(n, int)
    w = np.ones(n)
    for g in np.unique(groups):
        members = groups == g
        size = float(np.sqrt(np.mean(rate[members] ** 2)))
        if size > RATE_CAP and math.isfinite(size):
            w[members] = RATE_CAP / size
    return None if np.all(w == 1.0) else w


def _prescribed(res, v, dp, sign_like, weights) -> Point:
    """The :class:`Point` of a converged solve with one coordinate prescribed, oriented as
    ``sign_like`` (where given) in the norm of ``weights``."""
    sign = 1.0
    if sign_like is not None:
        trial = Point.from_newton(res, v, dp, weights=weights)
        ww = 1.0 if weights is None else weights * weights
        sign = 1.0 if float(trial.dU @ (ww * sign_like.dU)) / res.U.size \
            + trial.tangent[1] * sign_like.tangent[1] >= 0 else -1.0
    return Point.from_newton(res, v, dp, sign=sign, weights=weights)


def point_at_monitor(system, U, p, monitor: float, *, tol: float, maxiter: int = 25,
                     sign_like: Point | None = None, weights=None) -> Point:
    """The branch point with the monitor prescribed: bordered Newton from (U, p) (e.g.
    :meth:`Point.predicted` of a nearby point), as a :class:`Point` with its exact tangent
    (in the norm of ``weights``, :func:`unknown_weights`; oriented as ``sign_like`` where
    given). Raises ConvergenceError where Newton does not converge."""
    res = newton(system, U, p, 1.0, 0.0, monitor, tol=tol, maxiter=maxiter, fail_fast=False)
    if not res.ok:
        raise ConvergenceError(f"no branch point with the monitor at {monitor:.10g}: "
                               f"{res.history}")
    v, _, dp = tangent(res)
    return _prescribed(res, v, dp, sign_like, weights)


def point_at_parameter(system, U, p, value: float, *, tol: float, maxiter: int = 25,
                       sign_like: Point | None = None, weights=None) -> Point:
    """The branch point with the parameter prescribed (p = ``value``): Newton from (U, p)
    (e.g. an interpolation between two branch points), as a :class:`Point` with its exact
    tangent, oriented as ``sign_like``'s where given. Raises ConvergenceError where Newton
    does not converge (at a fold in p the system is singular)."""
    res = newton(system, U, value, 0.0, 1.0, value, tol=tol, maxiter=maxiter,
                 fail_fast=False)
    if not res.ok:
        raise ConvergenceError(f"no branch point with the parameter at {value:.10g}: "
                               f"{res.history}")
    v, _, dp = tangent(res)
    return _prescribed(res, v, dp, sign_like, weights)


def _crossing(a: Point, b: Point, p_stop, monitor_stop):
    """Where the step a -> b leaves the stops (b outside a bound that a is not outside of,
    beyond round-off): (fraction of the step, "p" or "monitor", the bound) for the first
    bound crossed, linear in each coordinate, or None."""
    found = None
    for name, (lo, hi), x0, x1 in (("p", p_stop, a.p, b.p),
                                   ("monitor", monitor_stop, a.monitor, b.monitor)):
        for bound, side in ((lo, -1.0), (hi, 1.0)):
            if not math.isfinite(bound) or x1 == x0:
                continue
            # leaving: b beyond the bound, a on its inner side or on it to round-off (a
            # start at p0 = bound sits there to round-off on either side)
            slack = 1e-12 * (1.0 + abs(bound))
            if side * (x1 - bound) > 0 and side * (x0 - bound) <= slack:
                frac = min(max((bound - x0) / (x1 - x0), 0.0), 1.0)
                if frac > 0 and (found is None or frac < found[0]):
                    found = (frac, name, bound)
    return found


def _land(system, a: Point, b: Point, crossing, o: ContinuationOptions, weights=None):
    """The point on the bound that the step a -> b crossed (``crossing`` from
    :func:`_crossing`), solved with that coordinate prescribed from the interpolation
    between a and b and oriented as b (in the norm of ``weights``); None where that
    fails."""
    frac, name, bound = crossing
    U0, p0 = a.U + frac * (b.U - a.U), a.p + frac * (b.p - a.p)
    solve = point_at_parameter if name == "p" else point_at_monitor
    try:
        q = solve(system, U0, p0, bound, tol=o.newton_tol, maxiter=o.newton_maxiter,
                  sign_like=b, weights=weights)
    except ConvergenceError:
        return None
    dU = q.U - a.U
    wdU = dU if weights is None else weights * dU
    chord = math.sqrt(float(wdU @ wdU) / dU.size + (q.p - a.p) ** 2)
    return replace(q, arclength=a.arclength + math.hypot(q.monitor - a.monitor, q.p - a.p),
                   path=a.path + chord)


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


class _ScaledParameter:
    """``system`` in the parameter t = (p - p0) / span, span < 1: the continuation's steps
    are then measured in fractions of the short range the branch is asked to cross (a
    pressure of 1e-6 and a curvature of 4 are both crossed in a few steps; a range longer
    than one is crossed in the parameter's own units)."""

    def __init__(self, system, p0: float, span: float):
        self.system, self.p0, self.span = system, float(p0), float(span)
        self.size = system.size
        self.jacobian_error = getattr(system, "jacobian_error", math.inf)

    def p(self, t):
        return self.p0 + self.span * t

    def evaluate(self, U, t):
        R, J, Rp = self.system.evaluate(U, self.p(t))
        return R, J, self.span * Rp

    def monitor(self, U):
        return self.system.monitor(U)

    @property
    def groups(self):
        from ..methods.base import implements

        return self.system.groups if implements(self.system, Grouped) \
            else np.zeros(self.size, int)

    def point(self, q: Point) -> Point:
        """A point of the scaled branch in the system's own parameter (its tangent's dp/ds
        scaled alike: the slope dp/dm is the system's)."""
        return replace(q, p=self.p(q.p), tangent=(q.tangent[0], self.span * q.tangent[1]))


def pseudo_arclength(system, U0, p0, *, options: ContinuationOptions = ContinuationOptions(),
                     p_stop=(-math.inf, math.inf), monitor_stop=(-math.inf, math.inf),
                     n_folds=None, direction=1.0, progress: Callable | None = None,
                     admissible: Callable | None = None, describe: Callable | None = None):
    """Follow the branch of ``system`` through the solution near (U0, p0), in the
    parameter's own units, or, where ``p_stop`` is a finite range shorter than one, in
    fractions of it (the steps of ``options`` then measure t = (p - p0) / (p_stop[1] -
    p_stop[0]): a thin shell's loads are small numbers in the engine's units).

    Stops when p leaves ``p_stop`` or the monitor leaves ``monitor_stop`` (its last point
    then on the bound the last step crossed, solved with that coordinate prescribed; past
    it where that fails), after ``n_folds`` folds, or at ``options.max_steps`` points. ``direction``: sign of the first step in p.
    ``progress(point)`` is called after every accepted point. ``admissible(point)`` may
    veto a converged point: it returns "" to accept it, else the reason why not; a vetoed
    step is retried shorter, and a veto down to ``ds_min`` ends the branch as a stall does
    (ConvergenceError with that reason and ``partial``). ``describe(point)`` says where a
    point is in a message (default ``"p = ..., monitor ..."``).

    Returns (points, brackets): the points and, for every fold passed, the index pair
    (i, i + 1) of the points between which dp/ds changed sign.
    Raises ConvergenceError (with the Newton history) if the start does not converge or the
    step falls below ``ds_min``; in the latter case its ``partial`` is (points, brackets) so
    far, every one of them converged.
    """
    lo, hi = p_stop
    span = hi - lo
    if not (math.isfinite(span) and 0 < span < 1.0):
        return _pseudo_arclength(system, U0, p0, o=options, p_stop=p_stop,
                                 monitor_stop=monitor_stop, n_folds=n_folds,
                                 direction=direction, progress=progress,
                                 admissible=admissible, describe=describe)
    scaled = _ScaledParameter(system, p0, span)

    def back(f):
        return None if f is None else (lambda q: f(scaled.point(q)))

    try:
        pts, brackets = _pseudo_arclength(
            scaled, U0, 0.0, o=options, p_stop=((lo - p0) / span, (hi - p0) / span),
            monitor_stop=monitor_stop, n_folds=n_folds, direction=direction,
            progress=back(progress), admissible=back(admissible), describe=back(describe))
    except ConvergenceError as exc:
        if exc.partial is not None:
            exc.partial = ([scaled.point(q) for q in exc.partial[0]], exc.partial[1])
        raise
    return [scaled.point(q) for q in pts], brackets


def _pseudo_arclength(system, U0, p0, *, o: ContinuationOptions, p_stop, monitor_stop,
                      n_folds, direction, progress, admissible, describe):
    """:func:`pseudo_arclength` in the system's parameter."""
    n = system.size
    res = newton(system, U0, p0, 0.0, 1.0, p0, tol=o.newton_tol, maxiter=START_MAXITER,
                 fail_fast=False)
    if not res.ok:
        why = f"{res.diagnosis}; " if res.diagnosis else ""
        raise ConvergenceError(f"continuation: no solution at the start {p0:g}: {why}Newton "
                               f"history {res.history}", round_off=bool(res.diagnosis))
    v, _, dp = tangent(res)
    # the norm's weights from the start's rate dU/dp (the start solve holds p: dp is 1)
    w = unknown_weights(system, v / dp) if dp != 0 else None
    ww = np.ones(n) if w is None else w * w
    pts = [Point.from_newton(res, v, dp, sign=math.copysign(1.0, direction * dp), weights=w)]
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
            sign = 1.0 if float(v @ (ww * b.dU)) / n + dp * b.tangent[1] > 0 else -1.0
        arc = b.arclength + math.hypot(res.m - b.monitor, res.p - b.p)
        dU = res.U - b.U
        chord = math.sqrt(float(dU @ (ww * dU)) / n + (res.p - b.p) ** 2)
        return replace(Point.from_newton(res, v, dp, sign=sign, arclength=arc, weights=w),
                       path=b.path + chord)

    landed = False

    def accept(new, b):
        nonlocal landed
        crossing = _crossing(b, new, p_stop, monitor_stop)
        if crossing is not None:
            # the step leaves the range: the point on its bound instead, exactly (the last
            # step shortened onto it), where that converges
            on_bound = _land(system, b, new, crossing, o, w)
            if on_bound is not None:
                new, landed = on_bound, True
        if new.tangent[1] * b.tangent[1] < 0:
            brackets.append((len(pts) - 1, len(pts)))
        pts.append(new)
        if progress:
            progress(new)

    while len(pts) < o.max_steps and not landed:
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
        row = ww * b.dU / n
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
                where = describe(b) if describe else \
                    f"p = {b.p:.10g} (monitor {b.monitor:.6g})"
                raise ConvergenceError(why or (
                    f"continuation stalled at {where}: Newton failed down to ds_min = "
                    f"{o.ds_min:g}; last history {res.history}"), partial=(pts, brackets))
            continue
        accept(new, b)
        cosang = float(new.dU @ (ww * b.dU)) / n + new.tangent[1] * tp
        angle = math.acos(max(-1.0, min(1.0, cosang)))
        factor = o.turn / max(angle, 1e-12)
        if len(res.history) >= 2 and res.history[0][1] > 0:
            theta = res.history[1][1] / res.history[0][1]
            factor = min(factor, math.sqrt(o.contraction / max(theta, 1e-12)))
        ds = min(max(ds * min(2.0, max(0.5, factor)), o.ds_min), o.ds_max)
    return pts, brackets
