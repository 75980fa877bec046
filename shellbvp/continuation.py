"""Pseudo-arclength continuation of two-point BVPs in one parameter, with exact fold refinement.

Works on any :class:`BVPModel` (the scenes' multi-point problem, or a textbook problem such as
Bratu's); the corrector is ``scipy.integrate.solve_bvp`` with the parameter as an unknown.

Arclength. The branch is parametrised by arclength in the plane of (monitor, p), where the
monitor m(ya, yb) is a boundary functional chosen by the model (the edge displacement of a
cap, u'(0) for Bratu). The pseudo-arclength condition tau . ((m, p) - (m1, p1)) = ds is then a
boundary condition, so the corrector is an ordinary BVP with one unknown parameter; it passes
folds in p wherever the monitor is monotone along the branch. Predictor: the secant (tangent)
of the last two points, applied to the whole solution profile. Steps adapt between
``ds_min`` and ``ds_max`` (grow 1.5x after easy corrections, halve after a failure).

Folds. A fold is where dp/ds changes sign between successive points. It is refined with the
extended (Moore-Spence) system: y' = f(y, p), phi' = f_y(y, p) phi, the BCs, their
linearisation for phi, and the normalisation dm(phi) = 1; unknowns (y, phi, p). Its solution
is the fold to solver accuracy; its error estimate is the change of p when the extended
system is re-solved on the mesh with every interval halved (4th-order collocation: the
change bounds the error of the coarse solution, and overestimates that of the fine one).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any, Callable, Protocol

import numpy as np
from scipy.integrate import solve_bvp

from .axisym import ConvergenceError

__all__ = ["BVPModel", "ContinuationOptions", "Point", "Fold", "ContinuationResult",
           "continuation", "refine_fold"]


class BVPModel(Protocol):
    """What continuation needs from a problem: y' = fun(x, y, p), bc(ya, yb, p) = 0 on [x0, x1]."""

    def fun(self, x, y, p): ...            # (n, m)
    def fun_jac(self, x, y, p): ...        # (n, n, m)
    def bc(self, ya, yb, p): ...           # (n,)
    def monitor(self, ya, yb) -> float: ...  # the boundary functional that measures the branch


@dataclass(frozen=True)
class ContinuationOptions:
    """Step control and tolerances (checked: 0 < ds_min <= ds <= ds_max)."""

    ds: float = 0.1
    ds_min: float = 1e-5
    ds_max: float = 0.5
    max_steps: int = 400
    tol: float = 1e-6
    fold_tol: float = 1e-8
    max_nodes: int = 20000
    grow: float = 1.5
    easy_iterations: int = 4

    def __post_init__(self):
        if not (0 < self.ds_min <= self.ds <= self.ds_max) or not all(
                math.isfinite(v) for v in (self.ds, self.ds_min, self.ds_max)):
            raise ValueError(f"steps must satisfy 0 < ds_min <= ds <= ds_max, got ds_min = "
                             f"{self.ds_min}, ds = {self.ds}, ds_max = {self.ds_max}")
        for name in ("tol", "fold_tol"):
            if not (0 < getattr(self, name) < 1):
                raise ValueError(f"{name} must lie in (0, 1), got {getattr(self, name)!r}")
        if self.max_steps < 2:
            raise ValueError(f"max_steps must be >= 2, got {self.max_steps!r}")


@dataclass(frozen=True)
class Point:
    """One converged point of a branch: parameter, monitor, arclength and the solution."""

    p: float
    monitor: float
    arclength: float
    x: np.ndarray = field(repr=False)
    y: np.ndarray = field(repr=False)
    sol: Any = field(repr=False, compare=False)
    nodes: int = 0
    niter: int = 0


@dataclass(frozen=True)
class Fold:
    """A refined fold (limit point) in p, with its error estimate and bracket on the branch."""

    p: float
    monitor: float
    error_estimate: float
    bracket: tuple        # indices (i, i + 1) of the branch points that straddle it
    x: np.ndarray = field(repr=False)
    y: np.ndarray = field(repr=False)
    sol: Any = field(repr=False, compare=False)
    stats: dict = field(repr=False, default_factory=dict)


@dataclass(frozen=True)
class ContinuationResult:
    points: tuple
    folds: tuple
    stats: dict = field(repr=False)


def _tangent(a: Point, b: Point):
    d = np.array([b.monitor - a.monitor, b.p - a.p])
    nrm = float(np.linalg.norm(d))
    return d / nrm, nrm


def _extrapolate(a: Point, b: Point, factor: float, max_nodes: int = 161):
    """Secant predictor for the profile y_b + factor (y_b - y_a), on a subset of b's mesh.

    solve_bvp only ever adds nodes; handing it the previous mesh would make meshes grow along
    the branch, so the predictor is sampled on at most ``max_nodes`` of b's nodes and the
    corrector refines where it needs to.
    """
    idx = np.unique(np.linspace(0, b.x.size - 1, min(b.x.size, max_nodes)).round().astype(int))
    x = b.x[idx]
    yb = b.y[:, idx]
    return x, yb + factor * (yb - a.sol(x))


def _solve_fixed(model, x, y, p, tol, max_nodes):
    res = solve_bvp(lambda t, Y: model.fun(t, Y, p), lambda ya, yb: model.bc(ya, yb, p), x, y,
                    fun_jac=lambda t, Y: model.fun_jac(t, Y, p), tol=tol, max_nodes=max_nodes,
                    bc_tol=tol)
    return res


def _dfdp(model, x, y, p):
    d = 1e-6 * (1.0 + abs(p))
    return ((model.fun(x, y, p + d) - model.fun(x, y, p - d)) / (2 * d))[:, None, :]


def _solve_arclength(model, x, y, p_guess, anchor: Point, tau, ds, tol, max_nodes):
    def bc(ya, yb, pp):
        p = pp[0]
        arc = tau[0] * (model.monitor(ya, yb) - anchor.monitor) + tau[1] * (p - anchor.p) - ds
        return np.concatenate([model.bc(ya, yb, p), [arc]])

    def fun(t, Y, pp):
        return model.fun(t, Y, pp[0])

    def fun_jac(t, Y, pp):
        return model.fun_jac(t, Y, pp[0]), _dfdp(model, t, Y, pp[0])

    return solve_bvp(fun, bc, x, y, p=[p_guess], fun_jac=fun_jac, tol=tol, max_nodes=max_nodes,
                     bc_tol=tol)


@dataclass
class _Failed:
    message: str
    success: bool = False


def _point(model, res, s) -> Point:
    p = float(res.p[0]) if res.p is not None else None
    return Point(p=p, monitor=float(model.monitor(res.y[:, 0], res.y[:, -1])), arclength=s,
                 x=res.x, y=res.y, sol=res.sol, nodes=int(res.x.size), niter=int(res.niter))


def continuation(model, p0: float, x0, y0, *, p_stop: tuple = (-math.inf, math.inf),
                 n_folds: int | None = None, direction: float = 1.0,
                 options: ContinuationOptions = ContinuationOptions(),
                 monitor_stop: tuple = (-math.inf, math.inf), refine: bool = True,
                 progress: Callable | None = None) -> ContinuationResult:
    """Follow the branch through (p0, y0) until p leaves ``p_stop``, the monitor leaves
    ``monitor_stop``, ``n_folds`` folds were found, or ``max_steps`` points were taken.

    Arguments:
        model: a :class:`BVPModel`.
        p0: starting parameter; x0, y0: initial mesh and guess (solved at fixed p0 first).
        direction: sign of the first step in p.
        refine: refine every detected fold with the extended system.
        progress: optional callback ``progress(point)`` after every accepted point.

    Raises:
        ConvergenceError: the first point does not converge, or the step fell below ds_min.
    """
    o = options
    t0 = time.perf_counter()
    res = _solve_fixed(model, x0, y0, p0, o.tol, o.max_nodes)
    if not res.success:
        raise ConvergenceError(f"continuation: no solution at the start p = {p0:g}: {res.message}")
    res.p = np.array([p0])
    pts = [_point(model, res, 0.0)]
    # Second point by a natural step in p (a fixed-p solve), halving until it converges.
    dp = direction * o.ds
    while True:
        try:
            r2 = _solve_fixed(model, pts[0].x, pts[0].y, p0 + dp, o.tol, o.max_nodes)
        except ConvergenceError as exc:
            r2 = _Failed(str(exc))
        if r2.success:
            break
        dp /= 2
        if abs(dp) < o.ds_min:
            raise ConvergenceError(f"continuation: cannot leave p = {p0:g} (first step failed "
                                   f"down to ds_min = {o.ds_min:g}): {r2.message}")
    r2.p = np.array([p0 + dp])
    _, d = _tangent(pts[0], _point(model, r2, 0.0))
    pts.append(_point(model, r2, d))
    if progress:
        progress(pts[0])
        progress(pts[1])
    ds = min(max(d, o.ds_min), o.ds_max)
    folds_idx = []
    failures = 0
    while len(pts) < o.max_steps:
        a, b = pts[-2], pts[-1]
        if not (p_stop[0] <= b.p <= p_stop[1]) or not (monitor_stop[0] <= b.monitor <= monitor_stop[1]):
            break
        if n_folds is not None and len(folds_idx) >= n_folds:
            break
        tau, prev = _tangent(a, b)
        x, y = _extrapolate(a, b, ds / prev)
        try:
            res = _solve_arclength(model, x, y, b.p + ds * tau[1], b, tau, ds, o.tol,
                                   o.max_nodes)
        except ConvergenceError as exc:  # e.g. the inner constitutive Newton on a wild iterate
            res = _Failed(str(exc))
        if not res.success:
            failures += 1
            ds /= 2
            if ds < o.ds_min:
                raise ConvergenceError(
                    f"continuation stalled at p = {b.p:.10g} (monitor {b.monitor:.6g}): the "
                    f"corrector failed down to ds_min = {o.ds_min:g} ({res.message}); reduce "
                    f"ds_max or loosen tol")
            continue
        new = _point(model, res, b.arclength + ds)
        if (new.p - b.p) * (b.p - a.p) < 0:
            folds_idx.append(len(pts) - 1)  # the fold lies between pts[-2] and new
        pts.append(new)
        if progress:
            progress(new)
        if res.niter <= o.easy_iterations:
            ds = min(ds * o.grow, o.ds_max)
    folds = []
    if refine:
        for i in folds_idx:
            folds.append(refine_fold(model, pts[i - 1], pts[i], pts[i + 1], (i - 1, i + 1),
                                     tol=o.fold_tol, max_nodes=o.max_nodes))
    stats = dict(points=len(pts), failures=failures, wall_time=time.perf_counter() - t0)
    return ContinuationResult(points=tuple(pts), folds=tuple(folds), stats=stats)


def _linearised_bc(model, ya, yb, p, h=1e-7):
    n = ya.size
    Ba, Bb = np.empty((n, n)), np.empty((n, n))
    for j in range(n):
        e = np.zeros(n)
        e[j] = h
        Ba[:, j] = (model.bc(ya + e, yb, p) - model.bc(ya - e, yb, p)) / (2 * h)
        Bb[:, j] = (model.bc(ya, yb + e, p) - model.bc(ya, yb - e, p)) / (2 * h)
    return Ba, Bb


def _linearised_monitor(model, ya, yb, h=1e-7):
    n = ya.size
    ma, mb = np.empty(n), np.empty(n)
    for j in range(n):
        e = np.zeros(n)
        e[j] = h
        ma[j] = (model.monitor(ya + e, yb) - model.monitor(ya - e, yb)) / (2 * h)
        mb[j] = (model.monitor(ya, yb + e) - model.monitor(ya, yb - e)) / (2 * h)
    return ma, mb


def _solve_extended(model, x, Y, p, tol, max_nodes):
    n = Y.shape[0] // 2

    def fun(t, Z, pp):
        y, phi = Z[:n], Z[n:]
        J = model.fun_jac(t, y, pp[0])
        return np.concatenate([model.fun(t, y, pp[0]), np.einsum("ij...,j...->i...", J, phi)])

    def bc(Za, Zb, pp):
        ya, yb, pa, pb = Za[:n], Zb[:n], Za[n:], Zb[n:]
        Ba, Bb = _linearised_bc(model, ya, yb, pp[0])
        ma, mb = _linearised_monitor(model, ya, yb)
        return np.concatenate([model.bc(ya, yb, pp[0]), Ba @ pa + Bb @ pb,
                               [ma @ pa + mb @ pb - 1.0]])

    return solve_bvp(fun, bc, x, Y, p=[p], tol=tol, max_nodes=max_nodes, bc_tol=tol)


def refine_fold(model, a: Point, b: Point, c: Point, bracket, *, tol=1e-8,
                max_nodes=20000) -> Fold:
    """Solve the extended system for the fold near b (a, c on either side of it).

    The guess for the null vector is the secant dy/dm of the bracketing points. The error
    estimate is the change of p when every mesh interval is halved (the returned fold is the
    one on the refined mesh, so the estimate is conservative). Raises ConvergenceError when it does not converge or
    the fold it finds is not inside the bracket's monitor interval.
    """
    x = b.x
    dy = (c.sol(x) - a.sol(x)) / (c.monitor - a.monitor)
    Y = np.concatenate([b.y, dy])
    t0 = time.perf_counter()
    res = _solve_extended(model, x, Y, b.p, tol, max_nodes)
    if not res.success:
        raise ConvergenceError(f"fold refinement near p = {b.p:.10g} failed: {res.message}")
    # Mesh refinement: the same system on the mesh with every interval halved.
    xf = np.sort(np.concatenate([res.x, 0.5 * (res.x[1:] + res.x[:-1])]))
    fine = _solve_extended(model, xf, res.sol(xf), float(res.p[0]), tol, 2 * max_nodes)
    if not fine.success:
        raise ConvergenceError(f"fold refinement near p = {b.p:.10g} failed at tol = {tol:g}: "
                               f"{fine.message}")
    n = Y.shape[0] // 2
    mon = float(model.monitor(fine.y[:n, 0], fine.y[:n, -1]))
    lo, hi = sorted((a.monitor, c.monitor))
    if not (lo <= mon <= hi):
        raise ConvergenceError(f"fold refinement converged outside its bracket: monitor "
                               f"{mon:.6g} not in [{lo:.6g}, {hi:.6g}] (p = {fine.p[0]:.10g})")
    return Fold(p=float(fine.p[0]), monitor=mon,
                error_estimate=abs(float(fine.p[0]) - float(res.p[0])), bracket=bracket,
                x=fine.x, y=fine.y[:n], sol=fine.sol,
                stats=dict(nodes=int(fine.x.size), niter=int(res.niter) + int(fine.niter),
                           wall_time=time.perf_counter() - t0))
