"""Bordered Newton on a discrete system and its exact branch tangent.

Everything in continuation and fold location is linear algebra on the bordered matrix

    A = [[dR/dU, dR/dp], [alpha dm/dU + row, beta]],

whose last row is one scalar condition alpha m(U) + row . U + beta p = c: beta = 0
prescribes the monitor m, alpha = 0 (row = 0) the parameter, and row = tau_U with
beta = tau_p is the pseudo-arclength condition. dR/dU may be dense or scipy.sparse.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sps
import scipy.sparse.linalg as spla
from scipy.linalg.lapack import dgetrf as _getrf, dgetrs as _getrs

from ..errors import ConvergenceError

__all__ = ["NewtonResult", "newton", "tangent", "bordered_lu", "one_update_error",
           "FAIL_CONTRACTION", "CONTRACTION_BOUND", "PREDICTED_FRACTION"]

#: a corrector whose update is not at least this factor smaller than the previous one is
#: outside its basin: fail fast, so the continuation retries with a shorter step
FAIL_CONTRACTION = 0.5
#: relative update at which an iteration that stops contracting has reached the round-off
#: floor of the discrete equations rather than left its basin: thin shells (h0/R0 <= 1e-3)
#: stall at updates of ~1e-9 (the inner constitutive root is itself accepted at its floor,
#: 1e-9). Such an iterate is converged to about that update (``NewtonResult.p_noise``).
ROUND_OFF_STEP = 1e-8
#: bound on the quadratic-convergence constant C (next update ~ C update^2) measured from
#: the last two updates: above it the iteration is not in that regime (a stall, e.g. on an
#: inexact Jacobian), and no update is predicted from it
CONTRACTION_BOUND = 100.0
#: a predicted next update counts as converged at this fraction of the tolerance (the
#: prediction C step^2 is good to a factor of a few, not to digits)
PREDICTED_FRACTION = 0.01


def one_update_error(step: float, jacobian_error: float) -> float:
    """The error one Newton update of relative size ``step`` can leave from a start next to
    the solution (e.g. a converged solution of a coarser discretisation carried over):
    CONTRACTION_BOUND (step^2 + delta step), with delta the Jacobian's relative error (the
    system's ``jacobian_error``; inf where unknown, so that one update never counts then: a
    Jacobian taken 1e-5 from the inner roots once left 1.2e-11 in kappa_s where C step^2
    predicted 1e-14)."""
    return CONTRACTION_BOUND * (step * step + jacobian_error * step)


class _Factor:
    """LU of the bordered matrix, dense or sparse."""

    def __init__(self, A):
        if sps.issparse(A):
            try:
                self._lu = spla.splu(A.tocsc())
            except RuntimeError as exc:          # "Factor is exactly singular"
                raise np.linalg.LinAlgError(str(exc)) from None
            self.solve = self._lu.solve
            self.solve_transposed = lambda b: self._lu.solve(b, trans="T")
        else:
            # LAPACK directly, in place, on A^T: A is this factor's own C-ordered copy, so
            # A^T is Fortran-ordered and factors with no copy (scipy's lu_factor would copy
            # it twice and check it, a tenth of a small system's factorisation); A x = b is
            # then A^T's transposed solve
            lu, piv, info = _getrf(A.T, overwrite_a=True)
            if info > 0:
                raise np.linalg.LinAlgError(f"exactly singular: U[{info - 1}, {info - 1}] = 0")
            if info < 0:
                raise ValueError(f"getrf: illegal argument {-info}")
            self.solve = lambda b: _getrs(lu, piv, b, trans=1)[0]
            self.solve_transposed = lambda b: _getrs(lu, piv, b)[0]


def _bordered(J, Rp, last_row, beta):
    if sps.issparse(J):
        return sps.bmat([[J, sps.csc_matrix(Rp[:, None])],
                         [sps.csc_matrix(last_row[None, :]), sps.csc_matrix([[beta]])]],
                        format="csc")
    n = J.shape[0]
    A = np.empty((n + 1, n + 1))
    A[:-1, :-1], A[:-1, -1], A[-1, :-1], A[-1, -1] = J, Rp, last_row, beta
    return A


def bordered_lu(J, Rp, last_row, beta):
    """The factored bordered matrix [[J, Rp], [last_row, beta]] (``.solve(b)``,
    ``.solve_transposed(b)``); raises
    numpy.linalg.LinAlgError if it is singular."""
    return _Factor(_bordered(J, Rp, last_row, beta))


@dataclass(frozen=True)
class NewtonResult:
    """Outcome of :func:`newton`: the iterate, the monitor there, ``ok``, the iteration
    count, the history of (max |residual|, relative update) per iteration (or the reason it
    stopped) and the factorisation of the bordered matrix at the last iterate."""

    U: np.ndarray = field(repr=False)
    p: float
    m: float
    ok: bool
    iterations: int
    history: list = field(repr=False)
    factor: object = field(repr=False, default=None)
    gm: np.ndarray = field(repr=False, default=None)
    #: with convergence at the round-off floor: the last update of p, the uncertainty of p
    #: it leaves (0 after quadratic convergence, where the error is far below the update)
    p_noise: float = 0.0

    @property
    def diagnosis(self) -> str:
        """Why the iteration failed, in words, when the history says more than its numbers:
        updates that stall far below 1 (not a bad start: round-off in the equations above
        the tolerance)."""
        steps = [h[1] for h in self.history if isinstance(h[0], float)]
        # stalled: small updates that wander instead of falling quadratically
        if self.ok or len(steps) < 3 or max(steps[-3:]) > 1e-3 \
                or steps[-1] < 0.01 * min(steps[-3:-1]):
            return ""
        return (f"the updates stall at ~{min(steps[-3:]):.0e} relative: round-off in the "
                f"discrete equations is above the Newton tolerance (a very stiff material or "
                f"a very thin shell)")


def newton(system, U, p, alpha, beta, c, *, row=None, tol=1e-10, maxiter=15,
           fail_fast: bool = True, min_iterations: int = 1,
           predict: bool = False, one_update: bool = False) -> NewtonResult:
    """Bordered Newton on R(U, p) = 0, alpha m(U) + row . U + beta p = c (row optional).

    Converged when the update is below ``tol`` relative to the unknowns (with ``predict``,
    also when the next one, C update^2 with C from the last two updates while C is at most
    CONTRACTION_BOUND, is: the evaluation that would only confirm it is saved), or when it stalls
    twice in a row below ``ROUND_OFF_STEP`` (the round-off floor: ``p_noise`` is then the
    last update of p), after at least ``min_iterations`` iterations (2: the point is then
    the result of a step taken with the Jacobian of a point already within tol, not of a
    start's Jacobian alone, whose error may be unknown). ``one_update``: U starts next to
    the solution (a converged solution carried to another discretisation, or one predicted
    along the exact tangent from a nearby solution); the first update then suffices,
    whatever ``min_iterations``, where the error it can leave (:func:`one_update_error` with
    the system's ``jacobian_error``) is below ``PREDICTED_FRACTION * tol``. Returns
    ``ok = False`` (never raises) on non-finite values, a singular matrix, too many
    iterations, growing updates, or - with ``fail_fast`` - an update not at least
    ``FAIL_CONTRACTION`` times the one before; the caller decides what to do.
    """
    U = np.array(U, dtype=float)
    p = float(p)
    history = []
    fac = gm = None
    m = math.nan
    floor_hits = 0
    for it in range(1, maxiter + 1):
        try:
            R, J, Rp = system.evaluate(U, p)
        except ConvergenceError as exc:     # e.g. the inner constitutive Newton, wild iterate
            history.append(("inner", str(exc)))
            return NewtonResult(U, p, m, False, it, history, fac, gm)
        m, gm = system.monitor(U)
        last = alpha * gm + (0.0 if row is None else row)
        r = np.append(R, alpha * m + beta * p - c + (0.0 if row is None else float(row @ U)))
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(Rp))
                and np.all(np.isfinite(J.data if sps.issparse(J) else J))):
            history.append(("non-finite", it))
            return NewtonResult(U, p, m, False, it, history, fac, gm)
        try:
            fac = bordered_lu(J, Rp, last, beta)
        except np.linalg.LinAlgError:       # exactly singular: a fold in the prescribed quantity
            history.append(("singular", it))
            return NewtonResult(U, p, m, False, it, history, None, gm)
        d = fac.solve(r)
        U -= d[:-1]
        p -= d[-1]
        step = max(float(np.max(np.abs(d[:-1]))) / (1.0 + float(np.max(np.abs(U)))),
                   abs(d[-1]) / (1.0 + abs(p)))
        history.append((float(np.max(np.abs(r))), step))
        if predict and it >= 2 and history[-2][1] > 0:
            C = step / history[-2][1] ** 2         # quadratic convergence: next ~ C step^2
            converged = C <= CONTRACTION_BOUND and C * step**2 <= tol
        else:
            converged = False
        # one update from a start next to the solution, where its error bound allows
        first_suffices = it == 1 and one_update and one_update_error(
            step, getattr(system, "jacobian_error", math.inf)) <= PREDICTED_FRACTION * tol
        if first_suffices or ((step <= tol or converged) and it >= min_iterations):
            m, gm = system.monitor(U)
            return NewtonResult(U, p, m, True, it, history, fac, gm)
        stalled = it >= 2 and step > FAIL_CONTRACTION * history[-2][1]
        if stalled and step <= ROUND_OFF_STEP:
            # a tiny update that does not contract once can be a start's inexact step (the
            # next one undoes it, the one after converges), so only two stalls in a row are
            # the round-off floor
            floor_hits += 1
            if floor_hits >= 2:
                m, gm = system.monitor(U)
                return NewtonResult(U, p, m, True, it, history, fac, gm, p_noise=abs(d[-1]))
            continue
        floor_hits = 0
        if fail_fast and stalled:
            break
        if it >= 4 and history[-1][1] > history[-2][1] > history[-3][1]:
            break   # the updates grow: diverging
    return NewtonResult(U, p, m, False, len(history), history, fac, gm)


def tangent(res: NewtonResult):
    """The branch direction at a converged result: A [v; dp] = [0; 1] with its bordered
    matrix (factored at the last iterate, within O(tol) of the solution). Returns
    (v, dm, dp) with dm = dm/dU . v; with the monitor prescribed (beta = 0, alpha = 1) this
    is (dU/dm, 1, dp/dm) up to the normalisation, exactly."""
    rhs = np.zeros(res.U.size + 1)
    rhs[-1] = 1.0
    x = res.factor.solve(rhs)
    v, dp = x[:-1], x[-1]
    return v, float(res.gm @ v), float(dp)
