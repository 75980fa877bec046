"""The results of the scenes' own questions (a snap curvature, the onset of snapping, a
critical pressure): small frozen dataclasses with their error estimates, defined here so
that they are part of the public API (:mod:`shellbvp`) like :class:`shellbvp.Branch`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = ["SnapResult", "Onset", "PressureResult", "SnapCurve"]


@dataclass(frozen=True)
class SnapResult:
    """Snap-through of an everting cap.

    Attributes:
        snaps: whether the branch from kappa = 0 has a fold before full eversion.
        kappa_s: snap curvature kappa_s R0 (nan when it does not snap).
        w_s: edge displacement at the fold, in R0 (nan when it does not snap).
        error_estimate: estimate of the error in kappa_s (mesh refinement of the fold system).
        T: shallowness Theta sqrt(R0/h0).
        fold: the :class:`shellbvp.Fold` (``fold.equilibrium`` is the shape at the snap).
        gradient: with ``gradient=True``, exact derivatives of kappa_s R0:
            ``{"theta": dkappa_s/dTheta, "h": dkappa_s/dh, "lam": dkappa_s/dlam}`` (``"nu"``
            for Koiter, no material entry for neo-Hookean), each at fixed other data
            (:func:`shellbvp.fold_gradient`); None otherwise or when the cap does not snap.
    """

    snaps: bool
    kappa_s: float
    w_s: float
    error_estimate: float
    theta: float
    h: float
    lam: float
    model: str
    material: str
    T: float
    stats: dict = field(repr=False, default_factory=dict)
    fold: object = field(repr=False, default=None)
    gradient: dict | None = None

    def __repr__(self) -> str:
        cap = f"T={self.T:.6g}, h={self.h:g}, {self.material}"
        if not self.snaps:
            return f"SnapResult(no snap, {cap})"
        return (f"SnapResult(kappa_s={self.kappa_s:.10g} +- {self.error_estimate:.1e}, "
                f"w_s={self.w_s:.6g} R0, {cap})")


@dataclass(frozen=True)
class Onset:
    """The smallest shallowness T = Theta sqrt(R0/h0) at which the cap snaps.

    By the mirror symmetry (kappa, w) -> (2 - kappa, 2H - w) the branch of a shallow cap
    passes through the flat state (w = H, kappa = 1), where dkappa/dw is even in w - H: the
    first fold pair is born there when dkappa/dw at the flat state changes sign. On the
    fold curve in (T, kappa) that is the cusp where the snap fold and its mirror meet, at
    w = H. ``T`` is found there (:func:`onset`); ``error_estimate`` is its change with the
    next Chebyshev degree plus the solver's tolerance; ``bracket`` the T interval of the
    scan; ``kappa`` the fold's kappa R0 at the cusp (1 by the symmetry: computed, a check);
    ``stats``: the fold-curve steps and Newton iterations.
    """

    T: float
    error_estimate: float
    bracket: tuple
    h: float
    lam: float
    model: str
    material: str
    kappa: float = math.nan
    stats: dict = field(repr=False, default_factory=dict)


@dataclass(frozen=True)
class PressureResult:
    """The axisymmetric snap-through pressure of a clamped cap.

    Attributes:
        lambda_B, R_over_t, nu: the cap (module docstring); theta, h: its Theta and t/R.
        snaps: whether the branch from p = 0 has a pressure maximum before the apex has
            gone ``W_STOP_RISES`` rises down.
        p_cr_over_p0: the pressure maximum in units of p0 (nan when it does not snap).
        error_estimate: estimate of the error in p_cr_over_p0 (refinement ladder of the
            fold, with the round-off floor).
        w_apex: apex displacement at the fold, in R0 (negative: downward); w_apex_over_t
            and w_apex_over_H the same in t and in the rise H.
        fold, branch: the :class:`shellbvp.Fold` and :class:`shellbvp.Branch`.
    """

    lambda_B: float
    R_over_t: float
    nu: float
    material: str
    theta: float
    h: float
    snaps: bool
    p_cr_over_p0: float
    error_estimate: float
    w_apex: float
    fold: object = field(repr=False, default=None)
    branch: object = field(repr=False, default=None)

    def __repr__(self) -> str:
        cap = f"lambda_B={self.lambda_B:g}, R/t={self.R_over_t:g}, {self.material}"
        if not self.snaps:
            return f"PressureResult(no snap, {cap})"
        return (f"PressureResult(p_cr/p0={self.p_cr_over_p0:.8g} +- {self.error_estimate:.1e}, "
                f"w_apex/t={self.w_apex_over_t:.4g}, {cap})")

    @property
    def w_apex_over_t(self) -> float:
        return self.w_apex / self.h

    @property
    def w_apex_over_H(self) -> float:
        return self.w_apex / (1.0 - math.cos(self.theta))


@dataclass(frozen=True)
class SnapCurve:
    """kappa_s against the shallowness T, one record per cap (a sweep,
    :func:`shellbvp.problems.cap_eversion.snap_curve`).

    Attributes:
        records: per cap, in sweep order, a :class:`shellbvp.sweep.Record`: ``key`` = T,
            ``status`` ("ok", "no snap" or "failed"), ``reason`` (why it failed, one line)
            and ``values`` (theta, kappa_s, w_s, error_estimate, snaps, along_fold_curve).
        complete: every cap of the sweep is here.

    ``curve[name]`` is a column as an array: ``"T"``, ``"status"``, ``"reason"`` or one of
    the values (kappa_s = nan where the cap does not snap or failed).
    """

    records: tuple
    complete: bool = True

    def __getitem__(self, name: str):
        import numpy as np

        if name == "T":
            return np.array([r.key for r in self.records])
        if name in ("status", "reason"):
            return np.array([getattr(r, name) for r in self.records], dtype=object)
        if not self.records or name not in self.records[0].values:
            raise KeyError(name)
        return np.array([r.values[name] for r in self.records])

    def counts(self) -> dict:
        """How many caps ended in each status."""
        out = {"ok": 0, "no snap": 0, "failed": 0}
        for r in self.records:
            out[r.status] += 1
        return out

    def __repr__(self) -> str:
        c = self.counts()
        return (f"SnapCurve({len(self.records)} caps: {c['ok']} snap, {c['no snap']} no snap, "
                f"{c['failed']} failed{'' if self.complete else ', incomplete'})")
