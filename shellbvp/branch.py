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
import time
from dataclasses import dataclass, field

import numpy as np

from .axisym import ConvergenceError
from .cache import atomic_write_text
from .continuation import ContinuationOptions, continuation
from .equilibrium import _energy, _Problem, reference_state
from .scene import Scene

__all__ = ["Branch", "FoldPoint", "follow", "BRANCH_BACKENDS", "default_nodes", "MonitorPoint",
           "at_monitor"]


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


BRANCH_BACKENDS = ("spectral", "shooting", "collocation")


def follow(scene: Scene, *, backend: str = "spectral", p0: float = 0.0,
           p_stop=(-math.inf, math.inf), n_folds=None, w_stop=(-math.inf, math.inf),
           options: ContinuationOptions | None = None, eps: float | None = None,
           progress=None, energies: bool = True, nodes: int | None = None,
           shooting_segments: int = 16) -> Branch:
    """Continue ``scene`` in its parameter from p0 (starting from the undeformed cap).

    Back-ends: ``"spectral"`` (Chebyshev collocation, :mod:`shellbvp.spectral`; the fast
    default), ``"shooting"`` (multiple shooting with diffrax), both continued by
    :mod:`shellbvp.discrete` (exact tangents, folds located by dp/dm = 0), or
    ``"collocation"`` (scipy's solve_bvp, :mod:`shellbvp.continuation`, Moore-Spence folds).

    Fold accuracy: every fold is located to ``options.fold_tol`` in p and carries an error
    estimate from refinement - spectral: the fold is re-located with 8 more nodes per piece
    until p changes by at most fold_tol (the change is the estimate; the finer value is
    returned); shooting: re-located at 1/10 of the ODE tolerance; collocation: mesh halving.

    Stops when p leaves ``p_stop``, w leaves ``w_stop`` (in R0), after ``n_folds`` folds, or
    after ``options.max_steps`` points. ``energies=False`` skips the energy columns (nan).
    Raises ValueError for bad arguments and ConvergenceError on failure.
    """
    if backend not in BRANCH_BACKENDS:
        raise ValueError(f"backend must be one of {BRANCH_BACKENDS}, got {backend!r}")
    eps = 1e-4 * scene.theta if eps is None else float(eps)
    if backend == "collocation":
        return _follow_collocation(scene, p0, p_stop, n_folds, w_stop,
                                   options or ContinuationOptions(), eps, progress, energies)
    return _follow_discrete(scene, backend, p0, p_stop, n_folds, w_stop,
                            options or ContinuationOptions(ds=5.0, ds_max=100.0), eps,
                            progress, energies, nodes, shooting_segments)


def _nan_energies(n):
    return np.full((n, 2), math.nan)


def _follow_collocation(scene, p0, p_stop, n_folds, w_stop, options, eps, progress,
                        energies):
    prob = _Problem(scene, p0, eps)
    H = 1.0 - math.cos(scene.theta)
    t = np.linspace(0.0, 1.0, 41)
    res = continuation(prob, p0, t, prob.stack(t, reference_state), p_stop=p_stop,
                       n_folds=n_folds, options=options,
                       monitor_stop=(w_stop[0] / H, w_stop[1] / H), progress=progress)
    pts = res.points
    E = np.array([_energy(prob, pt.sol, pt.p) for pt in pts]) if energies else \
        _nan_energies(len(pts))
    folds = tuple(FoldPoint(p=f.p, w=f.monitor * H, error_estimate=f.error_estimate,
                            index=f.bracket[0] + 1 if f.bracket else 0, stats=f.stats)
                  for f in res.folds)
    return Branch(scene=scene, p=np.array([pt.p for pt in pts]),
                  w=np.array([pt.monitor for pt in pts]) * H, energy=E.sum(axis=1),
                  stretching_energy=E[:, 0], bending_energy=E[:, 1],
                  arclength=np.array([pt.arclength for pt in pts]), folds=folds,
                  stats=dict(res.stats, backend="collocation"))


def default_nodes(scene: Scene) -> int:
    """Chebyshev degree per piece for the continuation: the edge boundary layer has width
    ~ sqrt(h) R0, so the degree grows with the shallowness theta / sqrt(h) (24 at T <= 4)."""
    T = scene.theta / math.sqrt(scene.h)
    return int(8 * math.ceil(max(3.0, 0.75 * T)))


MAX_NODES = 256


def _system(scene, backend, eps, nodes, shooting_segments, refine=0):
    if backend == "spectral":
        from .spectral import SpectralSystem

        return SpectralSystem(scene, nodes + 8 * refine, eps)
    from .shooting import ShootingSystem

    return ShootingSystem(scene, shooting_segments, eps, ode_tol=1e-10 / 10**refine)


def _follow_discrete(scene, backend, p0, p_stop, n_folds, w_stop, options, eps, progress,
                     energies, nodes, shooting_segments):
    from .discrete import follow_discrete, locate_fold, polish_fold

    t0 = time.perf_counter()
    nodes = default_nodes(scene) if nodes is None else int(nodes)
    cont = _system(scene, backend, eps, nodes, shooting_segments)
    H = 1.0 - math.cos(scene.theta)
    U0 = cont.from_profile(reference_state)
    pts, brackets = follow_discrete(
        cont, U0, p0, ds=options.ds, ds_min=options.ds_min, ds_max=options.ds_max,
        max_steps=options.max_steps, p_stop=p_stop,
        monitor_stop=(w_stop[0] / H, w_stop[1] / H), n_folds=n_folds,
        progress=progress, tol=1e-7)   # Newton step 1e-7: the points are good to ~1e-14
    folds = []
    for i, j in brackets:
        system = cont
        # The coarse fold only seeds the refinement: w to 1e-7 gives kappa to O(1e-14).
        coarse = locate_fold(system, pts[i], pts[j], monitor_tol=1e-7)
        stats = dict(coarse.stats)
        for k in range(1, 64):
            fine_sys = _system(scene, backend, eps, nodes, shooting_segments, refine=k)
            if backend == "spectral" and fine_sys.N > MAX_NODES:
                raise ConvergenceError(
                    f"fold near {scene.parameter} = {coarse.p:.10g}: no convergence to "
                    f"fold_tol = {options.fold_tol:g} up to {MAX_NODES} nodes (last change "
                    f"{stats.get('error_estimate', math.nan):.2e})")
            Uf = system.resample(coarse.U, fine_sys.N) if backend == "spectral" else coarse.U
            fine = polish_fold(fine_sys, Uf, coarse.p, coarse.monitor)
            err = float(abs(fine.p - coarse.p))
            stats = dict(stats, error_estimate=err, refinements=k,
                         resolution=getattr(fine_sys, "N", None))
            if err <= options.fold_tol or backend != "spectral":
                break
            system, coarse = fine_sys, fine
        folds.append(FoldPoint(p=float(fine.p), w=float(fine.monitor * H), error_estimate=err,
                               index=i, stats=stats))
    if energies:
        E = np.array([_energy(_Problem(scene, pt.p, eps), cont.dense(pt.U, pt.p), pt.p)
                      for pt in pts])
    else:
        E = _nan_energies(len(pts))
    return Branch(scene=scene, p=np.array([pt.p for pt in pts]),
                  w=np.array([pt.monitor for pt in pts]) * H, energy=E.sum(axis=1),
                  stretching_energy=E[:, 0], bending_energy=E[:, 1],
                  arclength=np.array([pt.arclength for pt in pts]), folds=tuple(folds),
                  stats=dict(backend=backend, points=len(pts), nodes=nodes,
                             evaluations=getattr(cont, "evaluations", None),
                             wall_time=time.perf_counter() - t0))


@dataclass(frozen=True)
class MonitorPoint:
    """The state of a branch where its observable takes a prescribed value.

    ``p``: the parameter there; ``w``: the prescribed observable (R0); ``dp_dw``: the slope
    of the branch dp/dw there (exact, from the bordered Jacobian; 1/R0^2 for kappa),
    negative between a fold pair; ``nodes``: Chebyshev degree used.
    """

    p: float
    w: float
    dp_dw: float
    nodes: int


def at_monitor(scene: Scene, w: float, *, p0: float = 0.0, nodes: int | None = None,
               eps: float | None = None) -> MonitorPoint:
    """Follow the branch from the undeformed state at p0 until w (in R0) is first reached,
    and solve there with w prescribed and the parameter unknown (spectral back-end).

    Raises ValueError for a non-finite w and ConvergenceError if the branch does not reach w.
    """
    from .discrete import _direction, follow_discrete, newton
    from .spectral import SpectralSystem

    if not math.isfinite(w):
        raise ValueError(f"w must be finite, got {w!r}")
    nodes = default_nodes(scene) if nodes is None else int(nodes)
    system = SpectralSystem(scene, nodes, eps)
    H = 1.0 - math.cos(scene.theta)
    target = w / H
    pts, _ = follow_discrete(system, system.from_profile(reference_state), p0, ds=0.5,
                             ds_max=100.0, monitor_stop=(-math.inf, target))
    if pts[-1].monitor < target:
        raise ConvergenceError(f"the branch did not reach w = {w:g} (last w = "
                               f"{pts[-1].monitor * H:.6g})")
    a, b = pts[-2], pts[-1]
    q = a if abs(a.monitor - target) < abs(b.monitor - target) else b
    dUdm, dpdm = q.dU / q.tangent[0], q.tangent[1] / q.tangent[0]
    res = newton(system, q.U + (target - q.monitor) * dUdm, q.p + (target - q.monitor) * dpdm,
                 1.0, 0.0, target)
    if not res.ok:
        raise ConvergenceError(f"no solution with w = {w:g} prescribed: {res.history}")
    _, _, slope = _direction(res)
    return MonitorPoint(p=res.p, w=w, dp_dw=slope / H, nodes=nodes)
