"""Every branch point with its error: the same point on the next, finer discretisation.

A branch's points solve the discrete system R(U, p) = 0 of one resolution. Each is carried
to the method's next rung (:meth:`refined`, the one the folds' ladder climbs) and corrected
there by Newton with one coordinate held: the parameter (then p is exact and the observables
change), or the monitor where the branch is steep, next to a fold (where the state at
fixed p does not exist on both resolutions). The change of every quantity between the two
points is its error estimate, as a fold's is (the change from one rung to the next); it
costs one or two Newton updates on the finer system per point, from a start next to the
solution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import ConvergenceError
from .newton import newton

__all__ = ["Refined", "refine_points", "held_coordinate", "change", "STEEP", "REFINE_TOL", "REFINE_MAXITER",
           "ROUND_OFF_ULPS"]

#: Newton tolerance (relative update) of a point's finer correction
REFINE_TOL = 1e-10
#: updates allowed to it (it starts next to the solution)
REFINE_MAXITER = 8
#: an estimate is at least this many units in the last place of the value: two converged
#: resolutions can agree to the last bit, and a value carries its own rounding
ROUND_OFF_ULPS = 8


def change(value: float, other: float, scale: float = 0.0, ratio: float = 0.0) -> float:
    """The error estimate of ``value`` from its counterpart ``other`` on the finer
    discretisation: their difference over 1 - ``ratio`` (the discretisation's
    ``rung_ratio``: the part of the coarse error the finer point still holds), at least
    ``ROUND_OFF_ULPS`` units of rounding of the larger of the two and ``scale`` (the size of
    what the value is computed from: a displacement is a difference of coordinates of the
    size of the shell, rounded to theirs, however small it is)."""
    return max(abs(other - value) / (1.0 - ratio),
               ROUND_OFF_ULPS * math.ulp(max(abs(value), abs(other), abs(scale))))


@dataclass(frozen=True)
class Refined:
    """The points of a branch on the next, finer discretisation (:func:`refine_points`).

    Attributes:
        system: the finer discrete system (None where the method cannot refine).
        points: per branch point, (U, p, m) on ``system``, or None where its correction did
            not converge.
        pinned: per branch point, ``"p"`` or ``"monitor"``: the coordinate held.
        reason: why estimates are missing (the method cannot refine, a correction failed),
            "" where all are there.
    """

    system: object = field(repr=False)
    points: tuple = field(repr=False)
    pinned: tuple = ()
    reason: str = ""


def refine_points(system, points, *, held=None, tol: float = REFINE_TOL) -> Refined:
    """The branch points ``points`` (:class:`~.arclength.Point` of ``system``) on
    ``system.refined()``: each carried there (``transfer``) and corrected by Newton with p
    held, or the monitor where the branch is steep in it (:func:`held_coordinate`; the
    other coordinate where that correction fails); ``held``: per point ``"p"``,
    ``"monitor"`` or None (that choice), e.g. ``"p"`` for a state asked for at a parameter
    value. Never raises: a missing estimate is None with the reason in
    :attr:`Refined.reason`."""
    held = (None,) * len(points) if held is None else tuple(held)
    try:
        fine = system.refined()
    except ValueError as exc:
        return Refined(None, (None,) * len(points), (), f"no finer discretisation: {exc}")
    span_p = _span([pt.p for pt in points])
    span_m = _span([pt.monitor for pt in points])
    out, pinned, failed = [], [], []
    for k, pt in enumerate(points):
        first = held[k] or held_coordinate(pt.tangent, span_m, span_p)
        try:
            U0 = system.transfer(pt.U, pt.p, fine)
        except ConvergenceError as exc:
            out.append(None)
            pinned.append(first)
            failed.append((k, str(exc)))
            continue
        # a requested state keeps its parameter; a branch point may fall back on the other
        for coordinate in (first,) if held[k] else (first, _OTHER[first]):
            alpha, beta, c = (0.0, 1.0, pt.p) if coordinate == "p" else (1.0, 0.0, pt.monitor)
            res = newton(fine, U0, pt.p, alpha, beta, c, tol=tol, maxiter=REFINE_MAXITER,
                         fail_fast=False, one_update=True)
            if res.ok and math.isfinite(res.p):
                break
        pinned.append(coordinate)
        if res.ok and math.isfinite(res.p):
            out.append((res.U, float(res.p), float(res.m)))
        else:
            out.append(None)
            failed.append((k, f"Newton history {res.history[-3:]}"))
    reason = "" if not failed else (
        f"{len(failed)} of {len(points)} points did not converge on the finer "
        f"discretisation ({fine.describe()}), e.g. point {failed[0][0]}: {failed[0][1]}")
    return Refined(fine, tuple(out), tuple(pinned), reason)


_OTHER = {"p": "monitor", "monitor": "p"}


def _span(values) -> float:
    """The range a coordinate covers along the branch (0 for one point)."""
    return float(max(values) - min(values)) if len(values) else 0.0


def held_coordinate(tangent, span_m: float, span_p: float) -> str:
    """``"p"``, or ``"monitor"`` where the branch's tangent (dm, dp) is steep: its monitor
    moves more than ``STEEP`` times faster than p, each relative to the range it covers on
    the branch (raw units would compare a displacement with a force). The state at fixed p
    is then what a user reads, except next to a fold, where it does not exist on both
    resolutions."""
    dm, dp = abs(float(tangent[0])), abs(float(tangent[1]))
    if span_m <= 0.0 or span_p <= 0.0:
        return "p"
    return "monitor" if dm / span_m > STEEP * dp / span_p else "p"


#: how much steeper than the branch's average slope a point must be for its monitor to be
#: held (a straight branch has slope ratio 1 everywhere; next to a fold it grows without
#: bound)
STEEP = 10.0
