"""Step control and tolerances of continuation and fold location: the one source of defaults."""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

__all__ = ["ContinuationOptions"]


@dataclass(frozen=True)
class ContinuationOptions:
    """Pseudo-arclength continuation settings (checked: 0 < ds_min <= ds <= ds_max).

    Steps are arclengths in the space (U, p) with the RMS norm of U (``U`` the discrete
    unknowns: shapes in R0, moment and forces scaled by 12/h^2), so ds = 1 is a change of
    about one R0 in shape or one unit in the parameter.

    Attributes:
        ds, ds_min, ds_max: first, smallest and largest step.
        max_steps: points per branch at most.
        turn: target turning angle of the tangent per step (radians): the step grows or
            shrinks (within a factor 2 per step) to keep it.
        contraction: target ratio of the second to the first Newton update (a step whose
            corrector contracts worse than this is shortened next time).
        newton_tol: the corrector stops when the update is below this relative to the
            unknowns (quadratic convergence: the point is then good to ~newton_tol^2).
        newton_maxiter: corrector iterations at most.
        predicted_stop: the corrector also stops where quadratic convergence predicts its
            next update (C update^2, C from the last two updates) below newton_tol, which
            saves the evaluation that would only confirm it; the point is then good to
            ~newton_tol rather than ~newton_tol^2. For computations that use the branch
            only to bracket a fold (:meth:`to_first_fold`).
        fold_probe: where the slope dp/dm of the last two points predicts a fold within
            the next step, the next point is taken with the monitor prescribed just past
            the predicted fold (twice as far as predicted) instead, so that the fold's
            bracket is tight and its location starts close (the ordinary step where that
            fails). For computations that need the first fold (:meth:`to_first_fold`).
        fold_tol: every fold is refined (the method's ladder of finer discretisations)
            until its parameter changes by at most this; the change is its error estimate.
        max_refinements: rungs of that ladder at most (then a ConvergenceError).
    """

    ds: float = 0.5
    ds_min: float = 1e-5
    ds_max: float = 2.0
    max_steps: int = 400
    turn: float = 0.3
    contraction: float = 0.05
    newton_tol: float = 1e-7
    newton_maxiter: int = 15
    fold_tol: float = 1e-9
    max_refinements: int = 30
    predicted_stop: bool = False
    fold_probe: bool = False

    def __post_init__(self):
        if not all(math.isfinite(v) for v in (self.ds, self.ds_min, self.ds_max)) or not (
                0 < self.ds_min <= self.ds <= self.ds_max):
            raise ValueError(f"steps must satisfy 0 < ds_min <= ds <= ds_max, got ds_min = "
                             f"{self.ds_min}, ds = {self.ds}, ds_max = {self.ds_max}")
        for name in ("newton_tol", "fold_tol", "contraction"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and 0 < v < 1):
                raise ValueError(f"{name} must lie in (0, 1), got {v!r}")
        if not (0 < self.turn <= math.pi / 2):
            raise ValueError(f"turn must lie in (0, pi/2], got {self.turn!r}")
        for name in ("predicted_stop", "fold_probe"):
            if not isinstance(getattr(self, name), bool):
                raise ValueError(f"{name} must be True or False, got "
                                 f"{getattr(self, name)!r}")
        for name, lo in (("max_steps", 2), ("newton_maxiter", 2), ("max_refinements", 1)):
            v = getattr(self, name)
            if not (isinstance(v, int) and v >= lo):
                raise ValueError(f"{name} must be an integer >= {lo}, got {v!r}")

    @classmethod
    def to_first_fold(cls, fold_tol: float = 1e-9) -> "ContinuationOptions":
        """Long steps for a computation that needs only the first fold (kappa_s): the step
        control shortens them where the branch turns, and the fold is located exactly
        afterwards, so long steps cost no accuracy. The corrector stops on its predicted
        next update (``predicted_stop``), and the step that would cross the fold is a probe
        just past it (``fold_probe``). Per kappa_s of the default cap: 25 evaluations
        with neither, 21 with the first, 17 with both; with a first step ds = 15 instead
        of 5, 13. (Over 15 caps, T = 3.3 ... 9 and lam = 0.01 ... 10 at tol 1e-8, a first
        step of 5 / 10 / 15 / 20 / 30 / 50 took 248 / 226 / 212 / 219 / 230 / 272
        evaluations, every kappa_s the same to 1e-12; a corrector stopped at 1e-4 saved
        10 % of the evaluations but stalled next to the onset cusp, where the branch is
        delicate and the predictor needs accurate tangents.)"""
        return cls(ds=15.0, ds_max=100.0, fold_tol=fold_tol, predicted_stop=True,
                   fold_probe=True)

    def with_(self, **changes) -> "ContinuationOptions":
        return replace(self, **changes)

    def with_fold_tol(self, fold_tol: float, *, name: str = "tol",
                      scale: float = 1.0) -> "ContinuationOptions":
        """These options, passed by a caller, with ``fold_tol`` set from a scene's tolerance
        ``name`` (``fold_tol`` = that tolerance times ``scale``, its unit in the scene's
        parameter): they may not set a fold_tol of their own that differs (one concept, one
        place: a ValueError says which to use)."""
        if self.fold_tol != ContinuationOptions.fold_tol and \
                not math.isclose(self.fold_tol, fold_tol, rel_tol=1e-12):
            raise ValueError(f"the fold tolerance was given twice: {name}={fold_tol / scale!r} "
                             f"and options.fold_tol={self.fold_tol!r}; give it as {name} only")
        return replace(self, fold_tol=fold_tol)
