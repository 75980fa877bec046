"""Continuation and exact fold location for discretised problems R(U, p) = 0.

A back-end that turns the BVP into a finite system (Chebyshev collocation,
:mod:`shellbvp.spectral`; multiple shooting, :mod:`shellbvp.shooting`) provides the residual,
its exact Jacobians dR/dU and dR/dp, and a scalar monitor m(U) with its gradient (the edge
displacement w / H for a cap). Everything here is then plain linear algebra on the bordered
matrix

    A = [[dR/dU, dR/dp], [alpha dm/dU, beta]],

whose last row is one scalar condition alpha m(U) + beta p = c: beta = 0 prescribes the
monitor, alpha = 0 the parameter; the pseudo-arclength condition
tau . ((U, p) - (U_b, p_b)) = ds (tau the unit tangent at the last point) adds the row tau_U.

Tangent. A [v; dp] = [0; 1] gives the branch direction (v, dp), exactly (no secant), so the
predictor is the tangent and dp/ds is known at every point: a fold is where it changes sign.

Folds. Along the branch parametrised by the monitor, p(m) is smooth and a fold of p is a
stationary point, dp/dm = 0, where dp/dm follows from the same bordered solve with
beta = 0. The fold is located by Brent's method on dp/dm inside the bracket of the two
branch points that straddle it; each evaluation is a Newton solve at prescribed m. This is an
exact fold system (the bordered Jacobian is singular exactly where the branch turns), not a
fit through coarse points: p_fold is found to the discretisation's accuracy, and since
p is stationary there, an error delta in m costs only O(delta^2) in p.
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field
from typing import Callable, Protocol

import numpy as np
import scipy.linalg as sla
from scipy.optimize import brentq

from .axisym import ConvergenceError

__all__ = ["DiscreteSystem", "DiscretePoint", "DiscreteFold", "newton", "follow_discrete",
           "locate_fold", "polish_fold"]


class DiscreteSystem(Protocol):
    size: int

    def evaluate(self, U, p): ...   # (R (n,), dR/dU (n, n), dR/dp (n,))
    def monitor(self, U): ...       # (m, dm/dU (n,))


@dataclass(frozen=True)
class DiscretePoint:
    """A converged point: parameter, monitor, arclength in the (m, p) plane, the unknowns,
    the unit tangent (dm/ds, dp/ds) and the tangent of U per unit arclength."""

    p: float
    monitor: float
    arclength: float
    U: np.ndarray = field(repr=False)
    tangent: tuple = (0.0, 0.0)
    dU: np.ndarray = field(repr=False, default=None)
    iterations: int = 0


@dataclass(frozen=True)
class DiscreteFold:
    """A located fold: p, monitor, the state, and the bracket it came from."""

    p: float
    monitor: float
    U: np.ndarray = field(repr=False)
    bracket: tuple
    stats: dict = field(repr=False, default_factory=dict)


@dataclass(frozen=True)
class _Newton:
    U: np.ndarray
    p: float
    m: float
    ok: bool
    iterations: int
    history: list
    lu: tuple          # LU factors of the bordered matrix at the last iterate
    gm: np.ndarray


def newton(system, U, p, alpha, beta, c, *, row=None, tol=1e-11, maxiter=15,
           contraction: float | None = 0.5) -> _Newton:
    """Bordered Newton on R(U, p) = 0, alpha m(U) + row . U + beta p = c (row optional).

    Converged when the update is below ``tol`` relative to the unknowns (the iteration is
    quadratic, so the error left is O(tol^2)). Returns ok = False (never raises) on
    non-finite values, too many iterations, or - when ``contraction`` is given - as soon as
    an update is not at least that factor smaller than the one before (a continuation step
    that is too long fails fast and is retried shorter); the caller decides.
    """
    U = np.array(U, dtype=float)
    p = float(p)
    history = []
    lu = gm = None
    m = math.nan
    for it in range(1, maxiter + 1):
        try:
            R, J, Rp = system.evaluate(U, p)
        except ConvergenceError as exc:     # inner constitutive Newton on a wild iterate
            history.append(("inner", str(exc)))
            return _Newton(U, p, m, False, it, history, lu, gm)
        m, gm = system.monitor(U)
        last = alpha * m + beta * p - c + (0.0 if row is None else float(row @ U))
        r = np.append(R, last)
        A = np.zeros((system.size + 1, system.size + 1))
        A[:-1, :-1], A[:-1, -1] = J, Rp
        A[-1, :-1], A[-1, -1] = alpha * gm, beta
        if row is not None:
            A[-1, :-1] += row
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(A))):
            history.append(("non-finite", it))
            return _Newton(U, p, m, False, it, history, lu, gm)
        with warnings.catch_warnings():
            warnings.simplefilter("error", sla.LinAlgWarning)
            try:
                lu = sla.lu_factor(A, check_finite=False)
            except sla.LinAlgWarning:   # exactly singular: at a fold in the prescribed quantity
                history.append(("singular", it))
                return _Newton(U, p, m, False, it, history, lu, gm)
        d = sla.lu_solve(lu, r, check_finite=False)
        U -= d[:-1]
        p -= d[-1]
        step = max(float(np.max(np.abs(d[:-1]))) / (1.0 + float(np.max(np.abs(U)))),
                   abs(d[-1]) / (1.0 + abs(p)))
        history.append((float(np.max(np.abs(r))), step))
        if step <= tol:
            m, gm = system.monitor(U)
            return _Newton(U, p, m, True, it, history, lu, gm)
        if contraction is not None and it >= 2 and step > contraction * history[-2][1]:
            break   # not contracting: outside the Newton basin
        if it >= 4 and history[-1][1] > history[-2][1] > history[-3][1]:
            break   # the steps grow: diverging
    return _Newton(U, p, m, False, len(history), history, lu, gm)


def _direction(res: _Newton):
    """Branch direction at a converged Newton result: A [v; dp] = [0; 1] with its bordered
    matrix (factored at the last iterate, within O(tol) of the solution); returns
    (v, dm, dp) with dm = dm/dU . v."""
    rhs = np.zeros(res.U.size + 1)
    rhs[-1] = 1.0
    x = sla.lu_solve(res.lu, rhs, check_finite=False)
    v, dp = x[:-1], x[-1]
    return v, float(res.gm @ v), dp


def _point(res: _Newton, v, dp, sign, arclength, n) -> DiscretePoint:
    nrm = math.sqrt(float(v @ v) / n + dp * dp)
    v, dp = sign * v / nrm, sign * dp / nrm
    return DiscretePoint(res.p, res.m, arclength, res.U, (float(res.gm @ v), dp), v,
                         res.iterations)


def follow_discrete(system, U0, p0, *, ds=0.1, ds_min=1e-5, ds_max=0.5, max_steps=400,
                    p_stop=(-math.inf, math.inf), monitor_stop=(-math.inf, math.inf),
                    n_folds=None, direction=1.0, tol=1e-10, turn=0.3,
                    progress: Callable | None = None):
    """Pseudo-arclength continuation of R(U, p) = 0 from a guess U0 at p0.

    Arclength is measured in the whole space (U, p) with the RMS norm of U (|U|^2 / n + p^2),
    so that a change of shape counts as much as a change of parameter. ``DiscretePoint``
    records the unit tangent (dU/ds, dp/ds) and, for the user, dm/ds and the arclength
    in the (m, p) plane. Step control: the next step is scaled so that the tangent turns by
    about ``turn`` radians per step and the first Newton contraction stays near 0.05 (at most
    doubling, halving after a failed correction), within [ds_min, ds_max].

    Returns (points, brackets): the converged points and, for every fold passed, the index
    pair (i, i + 1) of the points between which dp/ds changed sign.
    Raises ConvergenceError (with the Newton history) if the start does not converge or the
    step falls below ds_min.
    """
    n = system.size
    res = newton(system, U0, p0, 0.0, 1.0, p0, tol=tol, maxiter=40, contraction=None)
    if not res.ok:
        raise ConvergenceError(f"continuation: no solution at the start {p0:g}: Newton history "
                               f"{res.history}")
    v, _, dp = _direction(res)
    pts = [_point(res, v, dp, math.copysign(1.0, direction * dp), 0.0, n)]
    if progress:
        progress(pts[0])
    brackets = []
    failures = 0
    while len(pts) < max_steps:
        b = pts[-1]
        inside = p_stop[0] <= b.p <= p_stop[1] and monitor_stop[0] <= b.monitor <= monitor_stop[1]
        if not inside:
            break
        if n_folds is not None and len(brackets) >= n_folds:
            break
        tp = b.tangent[1]
        row = b.dU / n
        c = float(row @ b.U) + tp * b.p + ds
        res = newton(system, b.U + ds * b.dU, b.p + ds * tp, 0.0, tp, c, row=row, tol=tol)
        if not res.ok:
            failures += 1
            ds /= 2
            if ds < ds_min:
                raise ConvergenceError(
                    f"continuation stalled at p = {b.p:.10g} (monitor {b.monitor:.6g}): Newton "
                    f"failed down to ds_min = {ds_min:g}; last history {res.history}")
            continue
        v, _, dp = _direction(res)
        sign = 1.0 if float(v @ b.dU) / n + dp * tp > 0 else -1.0   # keep the orientation
        arc = b.arclength + math.hypot(res.m - b.monitor, res.p - b.p)
        new = _point(res, v, dp, sign, arc, n)
        if new.tangent[1] * tp < 0:
            brackets.append((len(pts) - 1, len(pts)))
        pts.append(new)
        if progress:
            progress(new)
        # Next step: the tangent should turn by ~``turn`` and the first Newton contraction
        # (second update / first) stay near 0.05, within [ds / 2, 2 ds].
        cosang = float(new.dU @ b.dU) / n + new.tangent[1] * tp
        angle = math.acos(max(-1.0, min(1.0, cosang)))
        factor = turn / max(angle, 1e-12)
        if len(res.history) >= 2 and res.history[0][1] > 0:
            theta = res.history[1][1] / res.history[0][1]
            factor = min(factor, math.sqrt(0.05 / max(theta, 1e-12)))
        ds = min(max(ds * min(2.0, max(0.5, factor)), ds_min), ds_max)
    return pts, brackets


class _Slope:
    """dp/dm along the branch at prescribed monitor values, remembering every solve (the
    nearest one, with its exact tangent, is the predictor for the next)."""

    def __init__(self, system, points, tol):
        self.system, self.tol = system, tol
        self.known = [(q.monitor, q.U, q.p, q.dU / q.tangent[0], q.tangent[1] / q.tangent[0])
                      for q in points]
        self.solves = self.iterations = 0

    def __call__(self, mv):
        for k in self.known:
            if k[0] == mv:
                return k[4]
        m0, U0, p0, dU0, g0 = min(self.known, key=lambda k: abs(k[0] - mv))
        res = newton(self.system, U0 + (mv - m0) * dU0, p0 + (mv - m0) * g0, 1.0, 0.0, mv,
                     tol=self.tol)
        self.solves += 1
        self.iterations += res.iterations
        if not res.ok:
            raise ConvergenceError(f"fold location: Newton failed at monitor {mv:.10g}: "
                                   f"{res.history}")
        v, _, dp = _direction(res)   # with the monitor prescribed: (v, dp) = (dU/dm, dp/dm)
        self.known.append((mv, res.U, res.p, v, dp))
        return dp

    def state(self, mv):
        self(mv)
        k = next(k for k in reversed(self.known) if k[0] == mv)
        return k[2], k[1]


def locate_fold(system, a: DiscretePoint, b: DiscretePoint, *, tol=1e-10,
                monitor_tol=1e-10) -> DiscreteFold:
    """The fold between branch points a and b (dp/ds of opposite signs): Brent's method on
    dp/dm over the bracket [m_a, m_b], each value from a Newton solve at prescribed m.

    Raises ConvergenceError if dp/dm does not change sign over the bracket (the monitor is
    not a coordinate of the branch there) or a Newton solve fails.
    """
    t0 = time.perf_counter()
    if a.tangent[0] == 0 or b.tangent[0] == 0 or not (
            a.tangent[1] / a.tangent[0] * b.tangent[1] / b.tangent[0] < 0):
        raise ConvergenceError(f"fold location: dp/dm does not change sign between monitor "
                               f"{a.monitor:.6g} and {b.monitor:.6g} (tangents {a.tangent}, "
                               f"{b.tangent}): the monitor is not a coordinate of the branch")
    slope = _Slope(system, (a, b), tol)
    lo, hi = sorted((a.monitor, b.monitor))
    m_star = brentq(slope, lo, hi, xtol=monitor_tol, rtol=4 * np.finfo(float).eps)
    p, U = slope.state(m_star)
    return DiscreteFold(p=p, monitor=m_star, U=U, bracket=(a.monitor, b.monitor),
                        stats=dict(solves=slope.solves, newton_iterations=slope.iterations,
                                   wall_time=time.perf_counter() - t0))


def polish_fold(system, U, p, monitor, *, step=1e-5, window=0.05, tol=1e-10,
                monitor_tol=1e-10, maxiter=12) -> DiscreteFold:
    """Re-locate a fold known approximately (e.g. from a coarser discretisation): secant
    iteration on dp/dm = 0 from ``monitor`` and ``monitor + step``.

    Raises ConvergenceError if the secant iteration does not converge or leaves
    [monitor - window, monitor + window].
    """
    t0 = time.perf_counter()
    res = newton(system, U, p, 1.0, 0.0, monitor, tol=tol)
    if not res.ok:
        raise ConvergenceError(f"fold polishing: Newton failed at monitor {monitor:.10g}: "
                               f"{res.history}")
    v, _, dp = _direction(res)
    first = DiscretePoint(res.p, res.m, 0.0, res.U, (1.0, dp), v, res.iterations)
    slope = _Slope(system, (first,), tol)
    m0, g0 = monitor, dp
    m1 = monitor + step
    g1 = slope(m1)
    for _ in range(maxiter):
        if g1 == g0:
            break
        m2 = m1 - g1 * (m1 - m0) / (g1 - g0)
        if abs(m2 - monitor) > window:
            raise ConvergenceError(f"fold polishing left its window: monitor {m2:.10g} from "
                                   f"{monitor:.10g} (window {window:g}); the estimate is too "
                                   f"far (use a finer starting discretisation)")
        m0, g0, m1 = m1, g1, m2
        g1 = slope(m1)
        if abs(m1 - m0) <= monitor_tol:
            break
    else:
        raise ConvergenceError(f"fold polishing: no convergence in {maxiter} secant steps "
                               f"(last monitor change {abs(m1 - m0):.2e})")
    p, U = slope.state(m1)
    return DiscreteFold(p=p, monitor=m1, U=U, bracket=(monitor - window, monitor + window),
                        stats=dict(solves=slope.solves + 1,
                                   newton_iterations=slope.iterations + res.iterations,
                                   wall_time=time.perf_counter() - t0))
