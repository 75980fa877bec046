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
from functools import lru_cache
from typing import Protocol, runtime_checkable

import numpy as np

from ..convergence import CONTRACTION_BOUND
from ..errors import ConvergenceError
from ..methods.base import implements

__all__ = ["NewtonResult", "newton", "tangent", "bordered_lu", "one_update_error",
           "jacobian_error", "round_off_step", "Stopping", "relative_step", "is_sparse",
           "FAIL_CONTRACTION",
           "CONTRACTION_BOUND", "PREDICTED_FRACTION"]

#: a corrector whose update is not at least this factor smaller than the previous one is
#: outside its basin: fail fast, so the continuation retries with a shorter step
FAIL_CONTRACTION = 0.5
#: relative update at which an iteration that stops contracting has reached the round-off
#: floor of the discrete equations rather than left its basin: thin shells (h0/R0 <= 1e-3)
#: stall at updates of ~1e-9 (the inner constitutive root is itself accepted at its floor,
#: 1e-9). Such an iterate is converged to about that update (``NewtonResult.p_noise``). A
#: system may state a higher floor of its own (:func:`round_off_step`: a thinner shell's).
ROUND_OFF_STEP = 1e-8
#: a predicted next update counts as converged at this fraction of the tolerance (the
#: prediction C step^2 is good to a factor of a few, not to digits)
PREDICTED_FRACTION = 0.01


@runtime_checkable
class StatesJacobianError(Protocol):
    """A discrete system that states the relative error of its Jacobian dR/dU (the nodal
    systems: that of their BVP's derivatives, round-off for a shell problem)."""

    jacobian_error: float


@runtime_checkable
class StatesRoundOff(Protocol):
    """A discrete system that states the relative update at which its Newton iterations
    reach the round-off floor of its equations (a thin shell's, whose forces enter scaled
    by 12/h^2)."""

    round_off_step: float


def round_off_step(system) -> float:
    """The floor of ``system``'s Newton updates: its ``round_off_step`` where it states
    one, at least ``ROUND_OFF_STEP``."""
    own = float(system.round_off_step) if implements(system, StatesRoundOff) else 0.0
    return max(ROUND_OFF_STEP, own)


def jacobian_error(system) -> float:
    """The relative error of ``system``'s Jacobian where it states one, inf where it does not
    (e.g. a hand-written system): one Newton update then never counts as converged alone."""
    return float(system.jacobian_error) if implements(system, StatesJacobianError) \
        else math.inf


def one_update_error(step: float, jacobian_error: float) -> float:
    """The error one Newton update of relative size ``step`` can leave from a start next to
    the solution (e.g. a converged solution of a coarser discretisation carried over):
    CONTRACTION_BOUND (step^2 + delta step), with delta the Jacobian's relative error (the
    system's ``jacobian_error``; inf where unknown, so that one update never counts then: a
    Jacobian taken 1e-5 from the inner roots once left 1.2e-11 in kappa_s where C step^2
    predicted 1e-14)."""
    return CONTRACTION_BOUND * (step * step + jacobian_error * step)


class Stopping:
    """The stopping rules of every Newton iteration in the package (branch points, folds,
    fold curves), applied to the sequence of relative updates one at a time
    (:meth:`after`), which returns what the iteration should do:

    * ``"converged"``: the update is below ``tol`` after at least ``min_iterations``
      updates; or, with ``predict``, the next update predicted by quadratic convergence,
      C step^2 with C from the last two updates (while C <= ``CONTRACTION_BOUND``), is below
      ``predicted_fraction * tol`` (the evaluation that would only confirm it is saved); or,
      with ``one_update``, the first update from a start next to the solution leaves at most
      ``PREDICTED_FRACTION * tol`` (:func:`one_update_error` with ``jacobian_error``);
    * ``"floor"``: with ``floor``, two updates in a row that do not contract (by
      ``FAIL_CONTRACTION``) below ``floor_step``: the round-off floor of the discrete
      equations, converged to about that update;
    * ``"stalled"``: with ``fail_fast``, an update that does not contract: outside the
      basin (the continuation retries with a shorter step);
    * ``"diverging"``: the updates grew twice in a row (the first update, which from a
      carried start may be tiny, not counted);
    * ``"continue"`` otherwise.

    ``left`` is the error the last update leaves by that prediction (inf outside the
    quadratic regime): with a tolerance met, the location error of the result.
    """

    def __init__(self, tol: float, *, min_iterations: int = 1, predict: bool = False,
                 predicted_fraction: float = 1.0, one_update: bool = False,
                 jacobian_error: float = math.inf, fail_fast: bool = False,
                 floor: bool = True, floor_step: float = ROUND_OFF_STEP):
        self.tol, self.min_iterations = tol, min_iterations
        self.predict, self.predicted_fraction = predict, predicted_fraction
        self.one_update, self.jacobian_error = one_update, jacobian_error
        self.fail_fast, self.floor, self.floor_step = fail_fast, floor, floor_step
        self.steps: list[float] = []
        self.left = math.inf
        self._floor_hits = 0

    def after(self, step: float) -> str:
        steps = self.steps
        steps.append(step)
        it = len(steps)
        if not math.isfinite(step):
            return "diverging"
        C = step / steps[-2] ** 2 if it >= 2 and steps[-2] > 0 else math.inf
        self.left = C * step**2 if C <= CONTRACTION_BOUND else math.inf
        predicted = self.predict and it >= 2 and self.left <= self.predicted_fraction * self.tol
        if it == 1 and self.one_update:
            self.left = one_update_error(step, self.jacobian_error)
            if self.left <= PREDICTED_FRACTION * self.tol:
                return "converged"
        if (step <= self.tol or predicted) and it >= self.min_iterations:
            return "converged"
        stalled = it >= 2 and step > FAIL_CONTRACTION * steps[-2]
        if self.floor and stalled and step <= self.floor_step:
            # a tiny update that does not contract once can be a start's inexact step (the
            # next one undoes it, the one after converges), so only two stalls in a row are
            # the round-off floor
            self._floor_hits += 1
            return "floor" if self._floor_hits >= 2 else "continue"
        self._floor_hits = 0
        if self.fail_fast and stalled:
            return "stalled"
        if it >= 4 and steps[-1] > steps[-2] > steps[-3]:
            return "diverging"
        return "continue"


def relative_step(d, U, p) -> float:
    """The size of a bordered Newton update d = (dU, dp) relative to the unknowns (U, p)."""
    return max(float(np.abs(d[:-1]).max()) / (1.0 + float(np.abs(U).max())),
               abs(d[-1]) / (1.0 + abs(p)))


@lru_cache(maxsize=None)
def _lapack():
    """LAPACK's dgetrf and dgetrs, imported on first use (``import shellbvp`` does not load
    scipy) and then held: an import statement in the factorisation costs ~50 us a call."""
    from scipy.linalg.lapack import dgetrf, dgetrs

    return dgetrf, dgetrs


def is_sparse(J) -> bool:
    """Whether a Jacobian is scipy.sparse (the dense ones are numpy arrays): decided without
    importing scipy.sparse, which ``import shellbvp`` does not load."""
    return not isinstance(J, np.ndarray)


class _Factor:
    """LU of the bordered matrix, dense or sparse."""

    def __init__(self, A):
        if is_sparse(A):
            import scipy.sparse.linalg as spla

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
            _getrf, _getrs = _lapack()
            lu, piv, info = _getrf(A.T, overwrite_a=True)
            if info > 0:
                raise np.linalg.LinAlgError(f"exactly singular: U[{info - 1}, {info - 1}] = 0")
            if info < 0:
                raise ValueError(f"getrf: illegal argument {-info}")
            self.solve = lambda b: _getrs(lu, piv, b, trans=1)[0]
            self.solve_transposed = lambda b: _getrs(lu, piv, b)[0]


def _bordered(J, Rp, last_row, beta):
    if is_sparse(J):
        import scipy.sparse as sps

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
    twice in a row below the system's floor (:func:`round_off_step`; ``p_noise`` is then the
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
    rule = Stopping(tol, min_iterations=min_iterations, predict=predict,
                    one_update=one_update, jacobian_error=jacobian_error(system),
                    fail_fast=fail_fast, floor_step=round_off_step(system))
    for it in range(1, maxiter + 1):
        try:
            R, J, Rp = system.evaluate(U, p)
        except ConvergenceError as exc:     # e.g. the inner constitutive Newton, wild iterate
            history.append(("inner", str(exc)))
            return NewtonResult(U, p, m, False, it, history, fac, gm)
        m, gm = system.monitor(U)
        last = alpha * gm + (0.0 if row is None else row)
        r = np.append(R, alpha * m + beta * p - c + (0.0 if row is None else float(row @ U)))
        if not (np.isfinite(r).all() and np.isfinite(Rp).all()
                and np.isfinite(J.data if is_sparse(J) else J).all()):
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
        step = relative_step(d, U, p)
        history.append((float(np.max(np.abs(r))), step))
        verdict = rule.after(step)
        if verdict in ("converged", "floor"):
            m, gm = system.monitor(U)
            return NewtonResult(U, p, m, True, it, history, fac, gm,
                                p_noise=abs(d[-1]) if verdict == "floor" else 0.0)
        if verdict in ("stalled", "diverging"):
            break
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
