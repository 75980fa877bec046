"""A fold as the solution of one system, with exact second derivatives: Newton on the
minimally augmented fold system, the refinement ladder on it, and the fold curve in theta.

Along a branch parametrised by the monitor m, the slope sigma = dp/dm is the last
component of the solution of the bordered system of the monitor-prescribed Newton,

    A [v; sigma] = [0; 1],    A = [[R_U, R_p], [m_U, 0]]

(:func:`shellbvp.continuation.newton.tangent`). A simple fold is a regular solution of the
minimally augmented system (Govaerts, *Numerical methods for bifurcations of dynamical
equilibria*, SIAM 2000, ch. 4; bordered here by R_p and m_U)

    R(U, p) = 0,    sigma(U, p) = 0,

whose last row needs the derivatives of sigma: with [w; w_m] the solution of
A^T [w; w_m] = [0; 1], d sigma/dz = -[w; w_m] . (dA/dz) [v; sigma], the gradient in z of the
second directional derivative d/de [w . R(U + e v, p + e sigma) + w_m m(U + e v)]. The
discrete systems give it exactly (``curvature_terms``: JAX second derivatives along the
inner constitutive root; no finite differences). The Newton matrix is A with its last row
replaced by (sigma_U, sigma_p): a rank-one change of A, solved with A's factors
(Sherman-Morrison), whose pivot sigma_U . v + sigma_p sigma is d2p/dm2, nonzero at a simple
fold. Newton converges quadratically to the fold of the discrete system, so a fold costs a
few evaluations where locating dp/dm = 0 along the branch (:mod:`.folds`) costs a solve per
secant step.

With theta free and the monitor prescribed, (R, sigma, m - m*) = 0 is a point of the fold
curve in (theta, p): :func:`fold_at_monitor`. For a cap, the fold curve's end at w = H
(kappa = 1) is the cusp where the snap is born (the onset).
"""

from __future__ import annotations

import math
import time

import numpy as np

from ..errors import ConvergenceError
from ..results import Fold
from ..methods.base import first_rung
from .folds import climb, refuse_below_round_off
from .newton import (PREDICTED_FRACTION, Stopping, bordered_lu, is_sparse, jacobian_error,
                     relative_step)
from .options import ContinuationOptions

__all__ = ["fold_system_terms", "solve_fold", "fold_ladder", "fold_at_monitor"]

#: relative update at which the fold Newton stops (as the branch Newton of a fold), or
#: that its predicted next update is below
FOLD_STEP_TOL = 1e-10
#: the update below which the fold Newton keeps the gradient of dp/dm of the last iterate
REUSE_STEP = 1e-6
#: at most this many fold Newton iterations (from a seed of a sweep it takes 2-3)
FOLD_MAXITER = 12


def fold_system_terms(system, U, p, *, theta=False, curvature=True):
    """Everything the fold system needs at (U, p): (R, R_U, R_p, m, m_U, the factors of A, v,
    sigma = dp/dm, sigma_U, sigma_p) and, with ``theta``, (sigma_theta, R_theta, m_theta)
    appended (the derivatives in the scene's theta, :meth:`parameter_derivatives`). Without
    ``curvature``, sigma_U and sigma_p are None (no second derivatives taken, and ``theta``
    is ignored)."""
    R, J, Rp = system.evaluate(U, p)
    m, gm = system.monitor(U)
    if not (np.all(np.isfinite(R)) and np.all(np.isfinite(Rp))):
        raise ConvergenceError("fold system: non-finite residual")
    try:
        factor = bordered_lu(J, Rp, gm, 0.0)
    except np.linalg.LinAlgError:
        raise ConvergenceError("fold system: the bordered matrix is singular (the monitor is "
                               "not a coordinate of the branch here)") from None
    e = np.zeros(U.size + 1)
    e[-1] = 1.0
    x = factor.solve(e)
    if not curvature:
        return (R, J, Rp, m, gm, factor, x[:-1], float(x[-1]), None, None)
    w = factor.solve_transposed(e)
    gU, gp, gth = system.curvature_terms(U, p, w, x[:-1], x[-1])
    out = (R, J, Rp, m, gm, factor, x[:-1], float(x[-1]), -gU, -gp)
    if theta:
        dR, dm = system.parameter_derivatives(U, p, names=("length",))["length"]
        out += (-gth, dR, float(dm))
    return out


def solve_fold(system, U, p, *, tol: float = FOLD_STEP_TOL, maxiter: int = FOLD_MAXITER,
               index: int = -1, refining: bool = False) -> Fold:
    """The fold of ``system`` near (U, p): Newton on (R, sigma) = 0 (module docstring).

    Converged, after at least two updates, when the update or its quadratic prediction of
    the next is below ``tol`` relative to the unknowns (``stats["location"]``: the error in
    p that prediction leaves), or, as for the branch Newton, when it stalls twice below the
    round-off floor (``stats["round_off"]`` is then the last update of p).
    ``refining``: (U, p) is the converged fold of a coarser discretisation of the same
    problem carried over (a finer rung of the ladder, ~1e-10 away, its inner roots carried
    along); one update then suffices where the error it can leave, CONTRACTION_BOUND
    (step^2 + delta step) with delta the relative error of the Jacobian (the system's
    ``jacobian_error``), is below the tolerance. ``stats["curvature"]`` is d2p/dm2
    there. Raises ConvergenceError if the iteration fails (a singular bordered matrix, a pivot
    d2p/dm2 = 0, growing updates, an inner solve that fails, or ``maxiter``).
    """
    t0 = time.perf_counter()
    U = np.array(U, dtype=float)
    p = float(p)
    history, noise = [], 0.0
    # the branch Newton's rules, its prediction asked to leave a hundredth of tol: a fold's
    # location error is part of its estimate (stats["location"])
    rule = Stopping(tol, min_iterations=2, predict=True, predicted_fraction=PREDICTED_FRACTION,
                    one_update=refining, jacobian_error=jacobian_error(system))
    for it in range(1, maxiter + 1):
        # after an update below REUSE_STEP the last gradient of sigma is kept: it changes
        # by O(update), so the next update is off by O(update^2) at most, below the
        # quadratic convergence's own error (it saves the second derivatives on the
        # confirming iteration of a finer rung)
        reuse = it >= 2 and history[-1][2] <= REUSE_STEP
        R, _, Rp, m, gm, factor, v, sigma, sU_new, sp_new = fold_system_terms(
            system, U, p, curvature=not reuse)
        if not reuse:
            sU, sp = sU_new, sp_new
        x = np.append(v, sigma)
        rho = np.append(sU - gm, sp)
        pivot = 1.0 + rho @ x                      # = sigma_U . v + sigma_p sigma = d2p/dm2
        if not (math.isfinite(pivot) and pivot != 0.0):
            raise ConvergenceError(f"fold system: d2p/dm2 = {pivot} at p = {p:.10g} (not a "
                                   f"simple fold)")
        z = factor.solve(np.append(R, sigma))
        d = z - x * (rho @ z) / pivot
        U -= d[:-1]
        p -= d[-1]
        step = relative_step(d, U, p)
        history.append((float(np.max(np.abs(R))), abs(sigma), step))
        verdict = rule.after(step)
        if not math.isfinite(step):
            raise ConvergenceError(f"fold system: non-finite update near p = {p:.10g}")
        if verdict == "converged":
            break
        if verdict == "floor":
            noise = abs(d[-1])
            break
        if verdict == "diverging":
            raise ConvergenceError(f"fold system: Newton diverges near p = {p:.10g} "
                                   f"(updates {[f'{h[2]:.1e}' for h in history]})")
    else:
        raise ConvergenceError(f"fold system: no convergence in {maxiter} Newton steps near "
                               f"p = {p:.10g} (updates {[f'{h[2]:.1e}' for h in history]})")
    left = rule.left
    m, _ = system.monitor(U)
    return Fold(p=float(p), monitor=float(m), U=U, system=system, index=index,
                stats=dict(solves=1, newton_iterations=it, curvature=float(pivot),
                           round_off=noise, location=min(left, step) * (1.0 + abs(p)),
                           history=history,
                           wall_time=time.perf_counter() - t0))


def fold_ladder(system, U, p, *, options: ContinuationOptions = ContinuationOptions(),
                index: int = -1, t0: float | None = None) -> Fold:
    """A fold known approximately on ``system`` (state U, parameter p), to
    ``options.fold_tol``: :func:`solve_fold` on the first rung the tolerance needs
    (``system.at_tolerance``), then on its refinement, and so on, until p changes by at
    most ``fold_tol`` on two consecutive rungs. As in :func:`shellbvp.continuation.ladder`
    the larger change (at least the round-off of the Newton floor and of the problem,
    ``bvp.round_off``), plus the error in p the finest rung's last Newton update may have
    left (``stats["location"]``, its quadratic prediction), is the error estimate and the
    finest fold is returned. ConvergenceError if the round-off exceeds ``fold_tol`` or after
    ``options.max_refinements`` rungs."""
    t0 = time.perf_counter() if t0 is None else t0
    refuse_below_round_off(system, p, options.fold_tol)
    first = first_rung(system, options.fold_tol, exact=True)
    current = solve_fold(first, system.transfer(U, p, first), p, index=index)

    def advance(finer, current):
        return solve_fold(finer, current.system.transfer(current.U, current.p, finer),
                          current.p, index=index, refining=True)

    # the error in p the last Newton update may have left (its prediction) counts once
    return climb(system, first, current, advance, options=options, index=index, t0=t0,
                 location_weight=1.0, fold_system=True)


def fold_at_monitor(system, U, p, theta, monitor, at_theta, *, tol: float = FOLD_STEP_TOL,
                    maxiter: int = FOLD_MAXITER):
    """The point of the fold curve in (theta, p) where the monitor equals ``monitor``:
    Newton on (R, sigma, m - monitor) = 0 in (U, p, theta), from the state U, p of
    ``system`` (the scene at ``theta``). ``at_theta(t)`` gives the same discretisation of
    the scene at theta = t (the unknowns keep their piece coordinates). The theta column
    is exact (:meth:`parameter_derivatives` and the theta component of
    ``curvature_terms``). Returns (system, U, p, theta, iterations) at the solution;
    ConvergenceError if the iteration fails."""
    U = np.array(U, dtype=float)
    p, theta = float(p), float(theta)
    rule = Stopping(tol, floor=False)
    history = rule.steps
    for it in range(1, maxiter + 1):
        R, J, Rp, m, gm, factor, v, sigma, sU, sp, sth, Rth, mth = fold_system_terms(
            system, U, p, theta=True)
        n = U.size
        A = np.zeros((n + 2, n + 2))
        A[:n, :n] = J.toarray() if is_sparse(J) else J
        A[:n, n], A[:n, n + 1] = Rp, Rth
        A[n, :n], A[n, n], A[n, n + 1] = sU, sp, sth
        A[n + 1, :n], A[n + 1, n + 1] = gm, mth
        try:
            d = np.linalg.solve(A, np.concatenate([R, [sigma, m - monitor]]))
        except np.linalg.LinAlgError:
            raise ConvergenceError("fold curve: singular Jacobian (theta is not a "
                                   "coordinate of the fold curve here)") from None
        U -= d[:n]
        p -= d[n]
        theta -= d[n + 1]
        system = at_theta(theta)
        verdict = rule.after(max(relative_step(d[:n + 1], U, p),
                                 abs(d[n + 1]) / (1.0 + abs(theta))))
        if verdict == "converged":
            return system, U, p, theta, it
        if verdict == "diverging":
            break
    raise ConvergenceError(f"fold curve: no convergence at monitor {monitor:g} (updates "
                           f"{[f'{h:.1e}' for h in history]})")

