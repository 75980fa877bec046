"""Branch points of an axisymmetric branch: where the Jacobian of the discrete system becomes
singular without a fold of the parameter (a pitchfork of a symmetric state, such as a flat
plate under in-plane compression, symmetric under w -> -w).

At a branch point p is a coordinate of the branch (no fold), but dR/dU has a null vector
phi, and the bordered matrix of any solve with one scalar condition is singular there too
(the rank of [dR/dU, dR/dp] drops). The location does not solve at the singular point: it
finds the root of a smooth scalar test function along the branch solved at prescribed p,

    [[dR/dU, b], [c^T, 0]] [v; g] = [0; 1]          (minimally augmented, det-free)

g(p) vanishes exactly where dR/dU is singular and changes sign there at a simple
singularity (Govaerts, *Numerical methods for bifurcations of dynamical equilibria*, SIAM
2000, Sec. 3.4). The borders b, c are unit approximations of the left and right null
vectors (inverse iteration at the bracket's interpolated crossing), so the bordered matrix
is well conditioned near the root; v is then the null vector phi (c . v = 1) and the
transposed solve gives the left one, psi. The root is bracketed by the branch's two points
between which the n = 0 eigenvalue changed sign, and found by Brent's method, each value
from a Newton solve at prescribed p started from the nearest solves already made.

Solving at prescribed p right next to the branch point is safe at a symmetric state: the
residual has no component along the symmetry-breaking phi, so Newton's update has none
either; the near-singularity shows up only as round-off in the breaking components.
Where a solve still fails (the discretisation breaks the symmetry, and the residual has a
component along phi) the bracket is narrowed from outside the neighbourhood where solves
fail (:func:`.squeeze.squeeze`), and the result is that bracket, its width the error
estimate (not refined on finer rungs), never an exception after a bracket.

Error estimate: as folds (:mod:`.folds`), the point is located again on the method's next
finer rung (``system.refined()``) until p changes by at most the tolerance on two
consecutive rungs; the larger of those two changes plus the root's own tolerance is the
estimate.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from ..errors import ConvergenceError
from ..methods.base import Discretisation, implements
from .newton import bordered_lu, newton
from .squeeze import narrowest_sign_change, squeeze

__all__ = ["BranchPoint", "test_function", "null_vectors", "locate_branch_point",
           "refine_branch_point", "branch_point_on", "INVERSE_ITERATIONS", "ROOT_FRACTION"]

#: power iterations for the borders (:func:`null_vectors`; each gains the ratio of the
#: distances in p to the nearest and the next singular point)
INVERSE_ITERATIONS = 12
#: the root in p is found to this fraction of the requested tolerance, so that the changes
#: between rungs measure the discretisation rather than the root search (a solve on the
#: branch costs little; Brent's iteration gains digits superlinearly)...
ROOT_FRACTION = 1e-3
#: ... but not below this relative floor (the test function's round-off: ~1e-13 of its
#: slope per unit relative p on a plate, measured at a/t = 100)
ROOT_FLOOR = 1e-12
#: Newton tolerance of the solves at prescribed p
SOLVE_TOL = 1e-12


@dataclass(frozen=True)
class BranchPoint:
    """A branch point of an axisymmetric branch, located on a discrete system.

    Attributes:
        p: the parameter value; monitor: the observable there (w / H).
        U: the discrete solution at p; system: its discretisation.
        null: the right null vector phi of dR/dU (unit max norm, largest entry positive);
            left: the left null vector psi (unit max norm).
        error_estimate: of p: the larger change of p over the last two rungs of the ladder
            plus the root tolerance; or, where the location stopped at a bracket, its width.
        bracket: (lo, hi) in p, the last interval over which the test function changed sign
            on the finest rung.
        converged: False where the ladder or the root search stopped early (``stats``'
            ``stall`` says why); the estimate is then the bracket's width or the last
            change, whichever is larger.
        stats: rungs, solves, changes, wall time.
        previous: the branch point on the rung before (None on the first).
    """

    p: float
    monitor: float
    U: np.ndarray = field(repr=False)
    system: Any = field(repr=False, compare=False)
    null: np.ndarray = field(repr=False)
    left: np.ndarray = field(repr=False)
    error_estimate: float = math.nan
    bracket: tuple = (math.nan, math.nan)
    converged: bool = True
    stats: dict = field(repr=False, default_factory=dict)
    previous: Any = field(repr=False, compare=False, default=None)

    def __repr__(self) -> str:
        name = self.system.bvp.scene.parameter if hasattr(self.system, "bvp") else "p"
        return (f"BranchPoint({name}={self.p:.10g} +- {self.error_estimate:.1e}, "
                f"{self.system.describe() if hasattr(self.system, 'describe') else ''})")

    @property
    def w(self) -> float:
        return float(self.monitor * self.system.bvp.scale)

    @property
    def equilibrium(self):
        from ..results import equilibrium_from

        return equilibrium_from(self.system, self.U, self.p, stats=self.stats,
                                error_estimate=self.error_estimate)


def _solver_of(J):
    """Solves with J and J^T from one LU (J bordered by a unit diagonal entry)."""
    n = J.shape[0]
    fac = bordered_lu(J, np.zeros(n), np.zeros(n), 1.0)
    return (lambda b: fac.solve(np.append(b, 0.0))[:-1],
            lambda b: fac.solve_transposed(np.append(b, 0.0))[:-1])


def null_vectors(J, dJ, *, iterations: int = INVERSE_ITERATIONS, seed: int = 0):
    """Approximate right and left null vectors (unit 2-norm) of J(p) at the singular point
    nearest to p, from J = J(p) and dJ ~ dJ/dp (dense or scipy.sparse), and the distance
    delta to it: J(p + delta) x = 0 to first order is the generalised eigenproblem
    J x = -delta dJ x, whose smallest |delta| is the largest eigenvalue of -J^-1 dJ: power
    iteration on it (and on its transpose for the left vector), from a fixed pseudo-random
    start. Unlike the smallest singular vector of J, this does not depend on how the rows
    and unknowns are scaled (a thin shell's forces and rotations differ by 12 / h^2), nor
    pick a direction that is small but does not change with p."""
    n = J.shape[0]
    solve, solve_t = _solver_of(J)
    rng = np.random.default_rng(seed)
    out, deltas = [], []
    for s, A in ((solve, dJ), (solve_t, dJ.T)):
        x = rng.standard_normal(n)
        x /= np.linalg.norm(x)
        lam = math.nan
        for _ in range(iterations):
            y = -s(A @ x)
            lam = float(x @ y)
            x = y / np.linalg.norm(y)
        out.append(x)
        deltas.append(1.0 / lam if lam else math.inf)
    return out[0], out[1], deltas[0]


def test_function(J, b, c):
    """(g, v, w): the minimally augmented test function of J with borders b (column) and c
    (row), its right vector v (J v + g b = 0, c . v = 1) and its left one w (J^T w + g c =
    0, b . w = 1). g = 0 exactly where J is singular; v, w are then its null vectors."""
    n = J.shape[0]
    fac = bordered_lu(J, b, c, 0.0)
    e = np.zeros(n + 1)
    e[-1] = 1.0
    x = fac.solve(e)
    y = fac.solve_transposed(e)
    return float(x[-1]), x[:-1], y[:-1]


class _Stall(Exception):
    """A solve failed: the location keeps the bracket it had."""


class _Along:
    """The branch at prescribed p on one system: every solve remembered, each new one
    started from the linear interpolation (or extrapolation) of the two nearest."""

    def __init__(self, system, known, tol=SOLVE_TOL):
        self.system, self.tol = system, tol
        self.known = dict(known)        # p -> U
        self.solves = self.iterations = 0

    def __call__(self, p):
        if p in self.known:
            return self.known[p]
        near = sorted(self.known, key=lambda q: abs(q - p))[:2]
        if len(near) == 2 and near[0] != near[1]:
            q0, q1 = near
            U0 = self.known[q0] + (p - q0) / (q1 - q0) * (self.known[q1] - self.known[q0])
        else:
            U0 = self.known[near[0]]
        res = newton(self.system, U0, p, 0.0, 1.0, p, tol=self.tol, maxiter=20)
        self.solves += 1
        self.iterations += res.iterations
        if not res.ok:
            raise _Stall(f"Newton at prescribed {p:.12g} failed: {res.history[-3:]}")
        self.known[p] = res.U
        return res.U


class _Test:
    """g(p) along the branch, with fixed borders; every value logged."""

    def __init__(self, along, b, c):
        self.along, self.b, self.c = along, b, c
        self.log = {}                    # p -> (g, v, w)

    def __call__(self, p):
        if p not in self.log:
            try:
                U = self.along(p)
                q = p
            except _Stall as exc:
                # the bordered matrix of a solve at prescribed p is exactly singular only
                # at the branch point itself: there the next representable neighbourhood
                # has the same test function to round-off
                if "singular" not in str(exc):
                    raise
                q = p + 1e-12 * max(abs(p), 1e-300)
                U = self.along(q)
            _, J, _ = self.along.system.evaluate(U, q)
            self.log[p] = test_function(J, self.b, self.c)
        return self.log[p][0]

    def bracket(self):
        """The narrowest interval between logged values of opposite sign."""
        pair = narrowest_sign_change([(p, v[0]) for p, v in self.log.items()])
        return None if pair is None else (pair[0][0], pair[1][0])


def _normalised(v):
    v = np.asarray(v, dtype=float)
    k = int(np.argmax(np.abs(v)))
    return v / v[k]


def _borders(along, p, q):
    """Unit borders (b ~ left null vector, c ~ right) at the branch's state at p, the rate
    of the Jacobian along the branch from a second state at q != p."""
    _, J, _ = along.system.evaluate(along(p), p)
    _, Jq, _ = along.system.evaluate(along(q), q)
    right, left, _ = null_vectors(J, (Jq - J) / (q - p))
    return left, right


def locate_branch_point(system, lo, hi, *, known=(), xtol: float, guess=None,
                        maxiter: int = 60) -> BranchPoint:
    """The branch point between parameter values lo and hi on ``system`` (a sign change of
    the test function there), to ``xtol`` in p.

    Arguments:
        system: the discrete system R(U, p) = 0.
        lo, hi: the bracket in p.
        known: (p, U) pairs of solutions on this system (at least one: the start of the
            first solve); lo and hi are solved from them.
        xtol: absolute tolerance of p.
        guess: where the borders are computed (default: the middle of the bracket).

    Returns a :class:`BranchPoint` (``error_estimate`` the root's tolerance, or the
    bracket's width where a solve stalled after the bracket was established).

    Raises:
        ConvergenceError: the test function does not change sign over [lo, hi], or a solve
            at an end of the bracket fails (no bracket yet).
    """
    from scipy.optimize import brentq

    t0 = time.perf_counter()
    lo, hi = sorted((float(lo), float(hi)))
    along = _Along(system, known)
    try:
        mid = 0.5 * (lo + hi) if guess is None else float(guess)
        try:
            b, c = _borders(along, mid, hi if abs(hi - mid) >= abs(lo - mid) else lo)
        except _Stall:                  # no solve inside: the borders from the ends
            b, c = _borders(along, hi, lo)
        test = _Test(along, b, c)
        g_lo, g_hi = test(lo), test(hi)
    except _Stall as exc:
        raise ConvergenceError(f"branch point between {lo:.10g} and {hi:.10g}: {exc}") from None
    if not g_lo * g_hi <= 0:
        raise ConvergenceError(f"branch point: the test function does not change sign between "
                               f"{lo:.10g} and {hi:.10g} (g = {g_lo:.3e}, {g_hi:.3e})")
    stall = ""
    try:
        root = brentq(test, lo, hi, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=maxiter)
        bracket = test.bracket() or (root, root)
        # Brent's last evaluations straddle the root within ~xtol: the estimate is xtol,
        # or the straddling interval where it is wider
        error = max(xtol, min(bracket[1] - bracket[0], 2 * xtol))
    except (_Stall, RuntimeError) as exc:
        # narrow the bracket from outside the neighbourhood where solves fail
        squeeze(test, [(q, v[0]) for q, v in test.log.items()], floor=xtol,
                errors=(_Stall,))
        bracket = test.bracket()
        root = 0.5 * (bracket[0] + bracket[1])
        error = 0.5 * (bracket[1] - bracket[0])
        stall = f"the root search stopped on the bracket {bracket}: {exc}"
        try:
            along(root)
        except _Stall:
            root = min(bracket, key=lambda q: abs(test.log[q][0]))
            error = bracket[1] - bracket[0]
    U = along(root)
    _, J, _ = system.evaluate(U, root)
    g, v, w = test_function(J, b, c)
    m, _ = system.monitor(U)
    stats = dict(solves=along.solves, newton_iterations=along.iterations,
                 test_evaluations=len(test.log), g=g, wall_time=time.perf_counter() - t0)
    if stall:
        stats["stall"] = stall
    return BranchPoint(p=float(root), monitor=float(m), U=U, system=system,
                       null=_normalised(v), left=_normalised(w), error_estimate=float(error),
                       bracket=tuple(map(float, bracket)), converged=not stall, stats=stats)


def _on_finer(current: BranchPoint, finer, width: float, xtol: float,
              max_width: float) -> BranchPoint:
    """``current`` located again on ``finer``: a bracket grown around its p until the test
    function changes sign (from ``width`` up to ``max_width``), then Brent."""
    p0 = current.p
    U0 = current.system.transfer(current.U, p0, finer)
    res = newton(finer, U0, p0, 0.0, 1.0, p0, tol=SOLVE_TOL, maxiter=20)
    if not res.ok:
        raise _Stall(f"Newton on {finer.describe()} at {p0:.12g} failed: {res.history[-3:]}")
    along = _Along(finer, {p0: res.U})
    b, c = _borders(along, p0, p0 + max(width, 1e-3 * abs(p0)))
    test = _Test(along, b, c)
    g0 = test(p0)
    d = width
    while True:
        gl, gr = test(p0 - d), test(p0 + d)
        if gl * g0 <= 0:
            lo, hi = p0 - d, p0
            break
        if gr * g0 <= 0:
            lo, hi = p0, p0 + d
            break
        if d >= max_width:
            raise _Stall(f"the test function on {finer.describe()} does not change sign "
                         f"within {d:.3g} of {p0:.12g}")
        d = min(8.0 * d, max_width)
    known = {q: U for q, U in along.known.items()}
    return locate_branch_point(finer, lo, hi, known=known.items(), xtol=xtol, guess=p0)


def refine_branch_point(system, lo, hi, *, known, tol: float, max_refinements: int = 8,
                        first=None) -> BranchPoint:
    """The branch point between lo and hi (p) of ``system``'s branch, to the absolute
    tolerance ``tol`` in p, with its error estimate (module docstring).

    Arguments:
        system: the branch's discrete system; known: (p, U) solutions on it (the branch's
            points next to the bracket).
        lo, hi: the bracket (the n = 0 eigenvalue changed sign between them).
        tol: absolute tolerance of p.
        max_refinements: rungs at most after the first.
        first: the first rung (default ``system.for_tolerance(tol)`` where the system is a
            :class:`Discretisation`, else ``system``).

    Returns the :class:`BranchPoint` on the finest rung; where a rung fails after the first
    one located the point, the last one located, ``converged`` False, its estimate the last
    change (or its bracket's width, the larger). ConvergenceError only where the point is
    not bracketed on the first rung.
    """
    t0 = time.perf_counter()
    xtol = max(ROOT_FRACTION * tol, ROOT_FLOOR * max(abs(lo), abs(hi)))
    known = list(known)
    if first is None:
        # the ladder's first rung for the relative tolerance (fold tolerances are stated in
        # a parameter of order one; a plate's load is not)
        rel = tol / max(abs(lo), abs(hi))
        first = system.for_tolerance(rel) if implements(system, Discretisation) else system
    if first is not system:
        known = [(q, system.transfer(U, q, first)) for q, U in known]
    current = locate_branch_point(first, lo, hi, known=known, xtol=xtol)
    if not current.converged:
        return replace(current, stats=dict(current.stats, rungs=1,
                                           wall_time=time.perf_counter() - t0))
    changes = []
    solves = current.stats["solves"]
    stall = ""
    for _ in range(max_refinements):
        try:
            finer = current.system.refined()
        except (ValueError, AttributeError) as exc:
            stall = f"cannot refine {current.system.describe()}: {exc}"
            break
        # the bracket on the finer rung: a few times the last change, at least a few root
        # tolerances; up to the original bracket
        width = max(4.0 * changes[-1] if changes else 0.0, 10.0 * xtol,
                    1e-6 * abs(current.p))
        try:
            fine = _on_finer(current, finer, width, xtol, hi - lo)
        except (_Stall, ConvergenceError) as exc:
            stall = f"on {finer.describe()}: {exc}"
            break
        solves += fine.stats["solves"]
        changes.append(abs(fine.p - current.p))
        fine = replace(fine, previous=current)
        current = fine
        if not fine.converged:
            stall = fine.stats.get("stall", "")
            break
        if len(changes) >= 2 and max(changes[-2:]) <= tol:
            break
    else:
        stall = (f"not converged to {tol:.2e} after {max_refinements} refinements (last "
                 f"changes {changes[-2:]})")
    last = max(changes[-2:]) if changes else math.nan
    width = current.bracket[1] - current.bracket[0]
    if stall:
        # no finer rung, or one that failed: the bracket (or the last change) is all
        # that is known; with no change at all, the discretisation error is not estimated
        estimate = max(last if changes else 0.0, width, current.error_estimate)
    else:
        estimate = last + current.error_estimate
    stats = dict(current.stats, rungs=1 + len(changes), changes=tuple(changes),
                 first=first.describe() if hasattr(first, "describe") else None,
                 resolution=current.system.describe() if hasattr(current.system, "describe")
                 else None, solves=solves, wall_time=time.perf_counter() - t0)
    if stall:
        stats["stall"] = stall
    return replace(current, error_estimate=float(estimate), converged=not stall, stats=stats)


def branch_point_on(branch, i: int, *, tol: float) -> BranchPoint:
    """The branch point of ``branch`` (a :class:`shellbvp.Branch`) between its points i - 1
    and i, to the relative tolerance ``tol`` in p (:func:`refine_branch_point`)."""
    a, b = branch.points[i - 1], branch.points[i]
    scale = max(abs(a.p), abs(b.p))
    return refine_branch_point(branch.system, a.p, b.p, known=[(a.p, a.U), (b.p, b.U)],
                               tol=tol * scale)
