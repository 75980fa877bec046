"""Every branch point with its error: the same point on the next, finer discretisation.

A branch's points solve the discrete system R(U, p) = 0 of one resolution. Each is carried
to the method's next rung (:meth:`refined`, the one the folds' ladder climbs) and corrected
there by Newton with the coordinate that dominates the point's tangent held: the parameter
where the branch moves mostly in p (then p is exact and the observables change), the
monitor where it moves mostly in the monitor (near a fold, where p at fixed p does not
exist on both resolutions). The change of every quantity between the two points is its
error estimate, as a fold's is (the change from one rung to the next); it costs one or two
Newton updates on the finer system per point, from a start next to the solution.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from ..errors import ConvergenceError
from .newton import newton

__all__ = ["Refined", "refine_points", "REFINE_TOL", "REFINE_MAXITER"]

#: Newton tolerance (relative update) of a point's finer correction
REFINE_TOL = 1e-10
#: updates allowed to it (it starts next to the solution)
REFINE_MAXITER = 8


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
    held, or the monitor where the point's tangent moves more in it than in p (module
    docstring); ``held``: per point ``"p"``, ``"monitor"`` or None (that choice), e.g.
    ``"p"`` for a state asked for at a parameter value. Never raises: a missing estimate is
    None with the reason in :attr:`Refined.reason`."""
    held = (None,) * len(points) if held is None else tuple(held)
    try:
        fine = system.refined()
    except ValueError as exc:
        return Refined(None, (None,) * len(points), (), f"no finer discretisation: {exc}")
    out, pinned, failed = [], [], []
    for k, pt in enumerate(points):
        along_p = abs(pt.tangent[1]) >= abs(pt.tangent[0]) if held[k] is None \
            else held[k] == "p"
        pinned.append("p" if along_p else "monitor")
        alpha, beta, c = (0.0, 1.0, pt.p) if along_p else (1.0, 0.0, pt.monitor)
        try:
            U0 = system.transfer(pt.U, pt.p, fine)
        except ConvergenceError as exc:
            out.append(None)
            failed.append((k, str(exc)))
            continue
        res = newton(fine, U0, pt.p, alpha, beta, c, tol=tol, maxiter=REFINE_MAXITER,
                     fail_fast=False, one_update=True)
        if res.ok and math.isfinite(res.p):
            out.append((res.U, float(res.p), float(res.m)))
        else:
            out.append(None)
            failed.append((k, f"Newton history {res.history[-3:]}"))
    reason = "" if not failed else (
        f"{len(failed)} of {len(points)} points did not converge on the finer "
        f"discretisation ({fine.describe()}), e.g. point {failed[0][0]}: {failed[0][1]}")
    return Refined(fine, tuple(out), tuple(pinned), reason)
