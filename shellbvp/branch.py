"""Branches of equilibria of a scene by pseudo-arclength continuation, and their CSV export.

:func:`follow` continues a scene in its parameter from the undeformed state with the generic
machinery of :mod:`shellbvp.continuation` (collocation corrector), refines the folds with the
extended system, and returns a :class:`Branch`: per point the parameter, the edge
displacement w (R0), the energy split and the arclength; per fold the refined parameter, w and
error estimate.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field

import numpy as np

from .cache import atomic_write_text
from .continuation import ContinuationOptions, continuation
from .equilibrium import _energy, _Problem, reference_state
from .scene import Scene

__all__ = ["Branch", "FoldPoint", "follow"]


@dataclass(frozen=True)
class FoldPoint:
    """A refined fold: parameter (1/R0 for kappa), w (R0), error estimate of the parameter."""

    p: float
    w: float
    error_estimate: float
    index: int          # position in the branch's point list after which it lies
    stats: dict = field(repr=False, default_factory=dict)


@dataclass(frozen=True)
class Branch:
    """A continuation diagram (arrays over the branch points, in order of arclength).

    ``p``: parameter values; ``w``: edge displacement relative to the apex (free edge) or apex
    relative to the edge (clamped), in R0; ``energy``, ``stretching_energy``,
    ``bending_energy``: E / (mu* h0 R0^2); ``arclength``: in the (w / H, p) plane, H the rise;
    ``folds``: refined folds.
    """

    scene: Scene = field(repr=False)
    p: np.ndarray
    w: np.ndarray
    energy: np.ndarray = field(repr=False)
    stretching_energy: np.ndarray = field(repr=False)
    bending_energy: np.ndarray = field(repr=False)
    arclength: np.ndarray = field(repr=False)
    folds: tuple
    stats: dict = field(repr=False)

    def rows(self):
        """Table rows (p, w, E, E_s, E_b, arclength, is_fold), folds merged in order."""
        out = [(self.p[i], self.w[i], self.energy[i], self.stretching_energy[i],
                self.bending_energy[i], self.arclength[i], 0) for i in range(self.p.size)]
        for k, f in enumerate(sorted(self.folds, key=lambda f: f.index, reverse=True)):
            i = f.index
            s = 0.5 * (self.arclength[i] + self.arclength[min(i + 1, self.p.size - 1)])
            out.insert(i + 1, (f.p, f.w, math.nan, math.nan, math.nan, s, 1))
        return out

    def to_csv(self, path) -> None:
        """Write the diagram to ``path`` atomically; units are in the column names."""
        buf = io.StringIO()
        wr = csv.writer(buf, lineterminator="\n")
        wr.writerow([f"{self.scene.parameter}_R0", "w_over_R0", "energy", "stretching_energy",
                     "bending_energy", "arclength", "is_fold"])
        for r in self.rows():
            wr.writerow([repr(float(v)) for v in r[:6]] + [int(r[6])])
        atomic_write_text(path, buf.getvalue())


def follow(scene: Scene, *, p0: float = 0.0, p_stop=(-math.inf, math.inf), n_folds=None,
           w_stop=(-math.inf, math.inf), options: ContinuationOptions = ContinuationOptions(),
           eps: float | None = None, progress=None) -> Branch:
    """Continue ``scene`` in its parameter from p0 (starting from the undeformed cap).

    Stops when p leaves ``p_stop``, w leaves ``w_stop`` (in R0), after ``n_folds`` folds, or
    after ``options.max_steps`` points. Raises ConvergenceError on failure.
    """
    eps = 1e-4 * scene.theta if eps is None else float(eps)
    prob = _Problem(scene, p0, eps)
    H = 1.0 - math.cos(scene.theta)
    t = np.linspace(0.0, 1.0, 41)
    res = continuation(prob, p0, t, prob.stack(t, reference_state), p_stop=p_stop,
                       n_folds=n_folds, options=options,
                       monitor_stop=(w_stop[0] / H, w_stop[1] / H), progress=progress)
    pts = res.points
    E = np.array([_energy(prob, pt.sol, pt.p) for pt in pts])
    folds = tuple(FoldPoint(p=f.p, w=f.monitor * H, error_estimate=f.error_estimate,
                            index=f.bracket[0] + 1 if f.bracket else 0, stats=f.stats)
                  for f in res.folds)
    return Branch(scene=scene, p=np.array([pt.p for pt in pts]),
                  w=np.array([pt.monitor for pt in pts]) * H, energy=E.sum(axis=1),
                  stretching_energy=E[:, 0], bending_energy=E[:, 1],
                  arclength=np.array([pt.arclength for pt in pts]), folds=folds,
                  stats=res.stats)
