"""Results: an equilibrium, a fold, a branch. Frozen, with error estimates and statistics,
and keeping their discrete states so that shapes and strains need no re-solve.

Units everywhere: lengths in the geometry's unit R (R0 for a cap of the unit sphere);
curvatures in 1/R; the meridional moment M and the force multipliers F_r, F_z per mu* h R
per radian of azimuth (the BVP's unknowns m, f_r, f_z are 12/h^2 times these); energies per
mu* h R^2.
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from .cache import atomic_write_text
from .ellipticity import ellipticity
from .kinematics import THICKNESS
from .errors import ConvergenceError
from .methods.base import InnerRoots, MidSurface, implements
from .scene import Scene

__all__ = ["Equilibrium", "Fold", "Branch", "equilibrium_from"]


@dataclass(frozen=True)
class Equilibrium:
    """An axisymmetric equilibrium.

    Attributes:
        scene, p: the problem and its parameter value (e.g. kappa in 1/R0).
        s: nodes (arclength of the reference meridian; from the pole offset eps at a pole).
        r, z, theta: current meridian (in the reference's frame, whose axial position the
            ends fix) and tangent angle.
        lam1, lam2: stretches relative to the target metric; k1, k2: principal curvatures.
        eps11, eps22: elastic mid-surface strains (a_aa - abar_aa) / (2 abar_aa)
            = (lam_a^2 - 1) / 2, relative to the target metric.
        M, F_r, F_z: meridional moment and force multipliers (see the module docstring).
        N1, N2: the membrane stress resultants, meridional and hoop, per unit deformed
            length and per mu* h: the derivatives of the energy per unit reference area in
            the actual stretches, t W_lam1 / lam2 and t W_lam2 / lam1, positive in tension
            (for a closed sphere of radius R traced from its top pole, a small pressure P
            pushes along -n, inward: N1 = N2 = -P R / 2; t the thickness profile).
        energy, stretching_energy, bending_energy: E / (mu* h0 R0^2) = 2 pi int W dA_target,
            split into the w_s and h^2/12 w_b parts, plus ``load_potential``.
        load_potential: the pressure's potential P V (V the volume between the surface and
            the plane of its edge; 0 without a load), included in ``energy``, which is then
            the total potential energy. The energies are nan where their quadrature points
            between the nodes have no elliptic inner root (next to a loss of ellipticity).
        w: the scene's monitor in R (:attr:`shellbvp.Scene.monitor_terms`; by default the
            axial displacement of the end that does not fix z relative to one that does,
            positive along +z: for a cap with a free edge the edge's relative to the apex,
            with a clamped edge the apex's relative to the edge).
        legendre: per node, the Legendre condition of the axisymmetric energy: smallest
            eigenvalue of the Hessian of W in (lam1, lam1 k1) (scaled; positive where the
            reduced energy is elliptic, see :func:`shellbvp.ellipticity.ellipticity`).
        hessian_block: per node, the same for the (lam1, k1) block of the Hessian of W.
        pole_hessian_min: the same for the whole Hessian in (lam1, lam2, k1, k2) at the
            first node (at a pole lam2 = lam1, k2 = k1 are tied).
        thin_shell: max over the meridian of h |k_a| and of h |kb_a| (current and target
            curvatures times the reference thickness; the reduced model assumes both
            small).
        error_estimate: max change of (r, z, theta) and of w on the next finer
            discretisation (``nan`` when not requested).
        stats: solver statistics (method, resolution, iterations, wall time).
        success, message: convergence flag and message.

    Calling ``eq(s)`` gives (r, z, theta, M, F_r, F_z) at any s (shape (6, len(s))), in the
    units of the attributes; :meth:`unknowns` gives the BVP's unknowns (a guess for another
    solve).
    """

    scene: Scene = field(repr=False)
    p: float
    s: np.ndarray = field(repr=False)
    r: np.ndarray = field(repr=False)
    z: np.ndarray = field(repr=False)
    theta: np.ndarray = field(repr=False)
    lam1: np.ndarray = field(repr=False)
    lam2: np.ndarray = field(repr=False)
    k1: np.ndarray = field(repr=False)
    k2: np.ndarray = field(repr=False)
    eps11: np.ndarray = field(repr=False)
    eps22: np.ndarray = field(repr=False)
    M: np.ndarray = field(repr=False)
    F_r: np.ndarray = field(repr=False)
    F_z: np.ndarray = field(repr=False)
    energy: float
    stretching_energy: float
    bending_energy: float
    w: float
    error_estimate: float
    stats: dict = field(repr=False)
    success: bool
    message: str
    z_pole: float = field(repr=False, default=math.nan)
    profile: Any = field(repr=False, compare=False, default=None)
    legendre: np.ndarray = field(repr=False, default=None)
    hessian_block: np.ndarray = field(repr=False, default=None)
    pole_hessian_min: float = math.nan
    thin_shell: tuple = (math.nan, math.nan)
    load_potential: float = 0.0
    N1: np.ndarray = field(repr=False, default=None)
    N2: np.ndarray = field(repr=False, default=None)

    def __repr__(self) -> str:
        if not self.success:
            return f"Equilibrium({self.scene.parameter}={self.p:.6g}, failed: {self.message})"
        return (f"Equilibrium({self.scene.parameter}={self.p:.6g}, w={self.w:.6g} R0 "
                f"+- {self.error_estimate:.1e}, energy={self.energy:.6g}, "
                f"{_resolution(self.stats)})")

    def plot(self, ax=None, *, strains: bool = True, mirror: bool = True,
             origin: str = "apex", label: str | None = None, color=None):
        """The meridian, stimulated part marked, and the strains on a second axes
        (:func:`shellbvp.plotting.plot_equilibrium`); returns the matplotlib axes."""
        from .plotting import plot_equilibrium

        return plot_equilibrium(self, ax, strains=strains, mirror=mirror, origin=origin,
                                label=label, color=color)

    def plot3d(self, field: str = "normal_displacement", ax=None, **options):
        """The deformed surface in 3D, a sector cut away, coloured by ``field`` with a
        colour bar (:func:`shellbvp.pictures.plot3d`: the fields, ``cut``, ``magnify``,
        ``view``, ``units``); returns the 3D axes."""
        from .pictures import plot3d

        return plot3d(self, field, ax, **options)

    def to_vtk(self, path, **options) -> None:
        """Write the surface and its fields to a ParaView file ``path`` (``.vtu``),
        atomically (:func:`shellbvp.paraview.write_equilibrium`: ``omega``, ``units``)."""
        from .paraview import write_equilibrium

        write_equilibrium(self, path, **options)

    def unknowns(self, s):
        """The BVP's unknowns (r, z, theta, m, f_r, f_z) at s (m, f = 12/h^2 M, F): a guess
        for another solve."""
        if not self.success:
            raise ConvergenceError(f"this equilibrium did not converge: {self.message}")
        return self.profile(s)

    def __call__(self, s):
        y = np.array(self.unknowns(s), dtype=float)
        y[3:] *= self.scene.h**2 / 12
        return y


def _resolution(stats: dict) -> str:
    """The method and resolution in a result's statistics, e.g. ``spectral, nodes=32``."""
    res = stats.get("resolution", stats)
    method = res.get("method", stats.get("method", "?"))
    size = ", ".join(f"{k}={v}" for k, v in res.items()
                     if k in ("nodes", "segments", "rtol", "steps") and v is not None)
    return f"{method}, {size}" if size else str(method)


def equilibrium_from(system, U, p, *, stats=None, error_estimate=math.nan,
                     energies: bool = True) -> Equilibrium:
    """The :class:`Equilibrium` of a converged discrete solution U at p (``energies=False``:
    the energies nan, not integrated; the shape, strains and stress resultants alone, at a
    third of the cost: pictures and files of every point of a branch)."""
    if implements(system, MidSurface):
        return _equilibrium_of_surface(system, U, p, stats, error_estimate, energies)
    bvp = system.bvp
    sc = bvp.scene
    t, Ys = system.nodes(U, p)
    Y = Ys.reshape(bvp.P, 6, t.size)
    s_all = np.stack([bvp.s_of(i, t) for i in range(bvp.P)])
    # the inner roots the solver converged to, as starts: next to a loss of ellipticity a
    # root followed along the meridian from the pole may find none (the budding branches'
    # last points could not be evaluated before)
    roots = None
    if implements(system, InnerRoots):
        try:
            roots = system.inner_roots(U, p)
        except ConvergenceError:
            roots = None
    X, F, gw, Hw = bvp.state_and_hessian(s_all, Y, p, roots, all_fields=True)
    keep = [slice(None) if i == 0 else slice(1, None) for i in range(bvp.P)]  # interfaces once
    s = np.concatenate([s_all[i, k] for i, k in enumerate(keep)])
    y = np.concatenate([Y[i][:, k] for i, k in enumerate(keep)], axis=1)
    X = np.concatenate([X[i][:, k] for i, k in enumerate(keep)], axis=1)
    F = np.concatenate([F[i][:, k] for i, k in enumerate(keep)], axis=1)
    gw = np.concatenate([gw[i][:, k] for i, k in enumerate(keep)], axis=1)
    Hw = np.concatenate([Hw[i][:, :, k] for i, k in enumerate(keep)], axis=-1)
    legendre, block, full = ellipticity(X.T, gw.T, np.moveaxis(Hw, -1, 0), sc.h)
    thick = F[THICKNESS]
    F = F[:4]
    dense_t = system.dense(U, p)
    # the first pole's height from the regular series at eps
    z_pole = y[1, 0] + y[0, 0] * y[2, 0] / 2 if bvp.poles[0] else math.nan
    m, _, _ = bvp.monitor(Y[0, :, 0], Y[-1, :, -1])
    message = "converged"
    Es = Eb = Ep = math.nan
    try:
        if energies:
            Es, Eb, Ep = bvp.energies(dense_t, p, None if roots is None else (t, roots))
    except ConvergenceError as exc:
        # the quadrature needs the state between the nodes, where next to a loss of
        # ellipticity the interpolated meridian may have no elliptic inner root: the shape
        # and strains at the nodes stand, the energy is not available
        Es = Eb = Ep = math.nan
        message = f"converged; energies not available (quadrature between the nodes: {exc})"
    scale = sc.h**2 / 12
    return Equilibrium(
        scene=sc, p=float(p), s=s, r=y[0], z=y[1], theta=y[2], lam1=X[0], lam2=X[1],
        k1=X[2], k2=X[3], eps11=(X[0] ** 2 - 1) / 2, eps22=(X[1] ** 2 - 1) / 2,
        M=scale * y[3], F_r=scale * y[4], F_z=scale * y[5], energy=Es + Eb + Ep,
        stretching_energy=Es, bending_energy=Eb, w=float(m * bvp.scale),
        error_estimate=float(error_estimate), stats=dict(stats or {}), success=True,
        message=message, z_pole=float(z_pole), profile=bvp.profile(dense_t),
        legendre=legendre, hessian_block=block, pole_hessian_min=float(full[0]),
        thin_shell=(float(sc.h * np.abs(X[2:]).max()), float(sc.h * np.abs(F[2:]).max())),
        load_potential=float(Ep), N1=thick * gw[0] / X[1], N2=thick * gw[1] / X[0])


def _equilibrium_of_surface(system, U, p, stats, error_estimate, energies) -> Equilibrium:
    """The :class:`Equilibrium` of a :class:`shellbvp.methods.base.MidSurface` solution: the
    state read from the mid-surface at the method's own points (no inner inversion), the
    energies by its own quadrature, the force F_r from its multipliers."""
    sc = system.scene
    st = system.state_at(U, p, system.output_points())
    X, F = st["X"], st["F"]
    legendre, block, full = ellipticity(X.T, st["gw"], st["Hw"], sc.h)
    Es, Eb, Ep = system.energies(U, p) if energies else (math.nan,) * 3
    m, _ = system.monitor(U)
    return Equilibrium(
        scene=sc, p=float(p), s=st["s"], r=st["r"], z=st["z"], theta=st["theta"],
        lam1=X[0], lam2=X[1], k1=X[2], k2=X[3], eps11=(X[0] ** 2 - 1) / 2,
        eps22=(X[1] ** 2 - 1) / 2, M=st["M"], F_r=st["F_r"], F_z=st["F_z"],
        energy=Es + Eb + Ep, stretching_energy=Es, bending_energy=Eb,
        w=float(m * system.bvp.scale), error_estimate=float(error_estimate),
        stats=dict(stats or {}), success=True, message="converged",
        z_pole=float(st["z_pole"]) if system.bvp.poles[0] else math.nan,
        profile=system.profile(U, p), legendre=legendre, hessian_block=block,
        pole_hessian_min=float(full[0]),
        thin_shell=(float(sc.h * np.abs(X[2:]).max()), float(sc.h * np.abs(F[2:]).max())),
        load_potential=float(Ep), N1=st["t"] * st["gw"][:, 0] / X[1],
        N2=st["t"] * st["gw"][:, 1] / X[0])


def failed_equilibrium(scene, p, message, stats) -> Equilibrium:
    """The result of a solve that did not converge (``success=False``; ``throw=False``)."""
    e = np.array([])
    nan = math.nan
    return Equilibrium(scene=scene, p=float(p), s=e, r=e, z=e, theta=e, lam1=e, lam2=e, k1=e,
                       k2=e, eps11=e, eps22=e, M=e, F_r=e, F_z=e, energy=nan,
                       stretching_energy=nan, bending_energy=nan, w=nan, error_estimate=nan,
                       stats=stats, success=False, message=message)


@dataclass(frozen=True)
class Fold:
    """A fold (limit point) of a branch in its parameter.

    Attributes:
        p: the parameter there (kappa_s R0 for the snap of a cap).
        w: the observable there, in R0; ``monitor`` = w / H.
        error_estimate: change of p on the last rung of the refinement ladder (``nan`` for
            a fold located on one discretisation only).
        monitor_error: the same for the monitor (``w_error`` = monitor_error H).
        index: the branch point after which it lies (-1 when not part of a branch).
        stats: location statistics (solves, iterations, refinements, resolution, time).
        previous: the fold on the ladder's rung before (None for a fold located on one
            discretisation): any quantity's change from it is that quantity's error
            estimate.
    ``fold.equilibrium`` is the full state there (built on demand).
    """

    p: float
    monitor: float
    U: np.ndarray = field(repr=False)
    system: Any = field(repr=False, compare=False)
    error_estimate: float = math.nan
    index: int = -1
    stats: dict = field(repr=False, default_factory=dict)
    monitor_error: float = math.nan
    previous: Any = field(repr=False, compare=False, default=None)

    @property
    def w(self) -> float:
        return float(self.monitor * self.system.bvp.scale)

    @property
    def w_error(self) -> float:
        """The error estimate of :attr:`w` (R0)."""
        return float(self.monitor_error * self.system.bvp.scale)

    def __repr__(self) -> str:
        name = self.system.bvp.scene.parameter if self.system is not None else "p"
        return (f"Fold({name}={self.p:.10g} +- {self.error_estimate:.1e}, w={self.w:.6g} R0, "
                f"{_resolution(self.stats)})")

    @property
    def equilibrium(self) -> Equilibrium:
        return equilibrium_from(self.system, self.U, self.p, stats=self.stats,
                                error_estimate=self.error_estimate)

    def with_estimate(self, error_estimate, *, index=None, stats=None) -> "Fold":
        return replace(self, error_estimate=float(error_estimate),
                       index=self.index if index is None else index,
                       stats=self.stats if stats is None else stats)


@dataclass(frozen=True)
class Branch:
    """A continuation diagram (arrays over the points, in order of arclength).

    Attributes:
        p: parameter values; w: the monitor (in R; see :class:`Equilibrium`).
        energy, stretching_energy, bending_energy, load_potential: E / (mu* h0 R0^2) (nan
            when not computed; ``energy`` is their total, see :class:`Equilibrium`).
        arclength: in the (w / H, p) plane, H the monitor's unit length
            (:attr:`shellbvp.Scene.monitor_scale`; the rise 1 - cos Theta of a cap).
        folds: the folds passed, refined (:class:`Fold`).
        stats: method, resolution, points, evaluations, wall time.
        stop: why the branch ended before its stopping criteria ("" if it met one), e.g. the
            stall of a continuation followed with ``on_stall="stop"``.
        method: the method object the branch was followed with (its points are solved
            again with it, e.g. at a parameter value between them).
        p_error, w_error, energy_error: per point, the change of p, w and the energy when
            the point is solved on the method's next finer discretisation with p held (0
            then in p_error), or with w held where the branch is steep, next to a fold (0
            in w_error): every point's error estimate (:mod:`shellbvp.continuation.
            estimates`); nan where it could not be computed (``error_note`` says why) or
            was not asked for (``follow(..., estimate_errors=False)``).
        refined: the points on that finer discretisation
            (:class:`shellbvp.continuation.estimates.Refined`; None without estimates):
            any other quantity's change between the two is its error estimate.
        error_note: why some or all estimates are missing ("" if none is).
        requested: (value, point index) of every state asked for at a parameter value
            (``follow(..., at=...)``), in order along the branch.
    ``branch.equilibrium(i)`` is the full state at point i (built on demand).
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
    points: tuple = field(repr=False, compare=False, default=())
    system: Any = field(repr=False, compare=False, default=None)
    stop: str = ""
    load_potential: np.ndarray = field(repr=False, default=None)
    method: Any = field(repr=False, compare=False, default=None)
    p_error: np.ndarray = field(repr=False, default=None)
    w_error: np.ndarray = field(repr=False, default=None)
    energy_error: np.ndarray = field(repr=False, default=None)
    refined: Any = field(repr=False, compare=False, default=None)
    error_note: str = ""
    requested: tuple = ()

    def __post_init__(self):
        nan = np.full(np.shape(self.p), math.nan)
        for name in ("p_error", "w_error", "energy_error"):
            if getattr(self, name) is None:
                object.__setattr__(self, name, nan.copy())

    def __repr__(self) -> str:
        name = self.scene.parameter
        folds = ", ".join(f"{f.p:.8g}" for f in self.folds)
        return (f"Branch({name} {self.p[0]:.6g} -> {self.p[-1]:.6g}, w {self.w[0]:.4g} -> "
                f"{self.w[-1]:.4g} R0, {self.p.size} points, {len(self.folds)} fold(s)"
                + (f" at {name} = {folds}" if folds else "")
                + (f", stopped: {self.stop}" if self.stop else "") + ")")

    def equilibrium(self, i: int, *, energies: bool = True) -> Equilibrium:
        """The equilibrium at point i of the branch (``energies=False``: without them,
        :func:`equilibrium_from`)."""
        if not -len(self.points) <= i < len(self.points):
            raise ValueError(f"i must index the branch's {len(self.points)} points, got {i!r}")
        pt = self.points[i]
        return equilibrium_from(self.system, pt.U, pt.p, stats=self.stats, energies=energies)

    def plot(self, ax=None, *, instability=None, label: str | None = None):
        """The parameter against w, folds marked, and an instability of the branch if given
        (:func:`shellbvp.plotting.plot_branch`); returns the matplotlib axes."""
        from .plotting import plot_branch

        return plot_branch(self, ax, instability=instability, label=label)

    def animate(self, path, **options) -> None:
        """Write the branch's states in 3D beside its diagram, the current point marked, as
        a GIF or MP4 ``path`` (:func:`shellbvp.pictures.animate`: ``field``, ``frames``,
        ``fps``, ``magnify``, ``progress``, ...)."""
        from .pictures import animate

        animate(self, path, **options)

    def to_vtk(self, folder, **options):
        """Write every point as a ParaView file in ``folder`` and their collection
        ``branch.pvd`` (:func:`shellbvp.paraview.write_branch`: ``name``, ``units``,
        ``time``); returns the collection's path."""
        from .paraview import write_branch

        return write_branch(self, folder, **options)

    def rows(self, errors: bool = False):
        """Table rows (p, w, E, E_s, E_b, arclength, is_fold), folds merged in order; with
        ``errors``, each followed by (p_error, w_error, energy_error) (a fold's: its
        estimates in p and w, its energy not computed)."""
        out = [(self.p[i], self.w[i], self.energy[i], self.stretching_energy[i],
                self.bending_energy[i], self.arclength[i], 0)
               + ((self.p_error[i], self.w_error[i], self.energy_error[i]) if errors else ())
               for i in range(self.p.size)]
        for f in sorted(self.folds, key=lambda f: f.index, reverse=True):
            i = f.index
            s = 0.5 * (self.arclength[i] + self.arclength[min(i + 1, self.p.size - 1)])
            out.insert(i + 1, (f.p, f.w, math.nan, math.nan, math.nan, s, 1)
                       + ((f.error_estimate, f.w_error, math.nan) if errors else ()))
        return out

    def to_csv(self, path) -> None:
        """Write the diagram to ``path`` atomically; units are in the column names, every
        value's error estimate in the ``_error`` columns (nan where there is none)."""
        buf = io.StringIO()
        wr = csv.writer(buf, lineterminator="\n")
        p = self.scene.parameter_column
        wr.writerow([p, "w_over_R0", "energy", "stretching_energy", "bending_energy",
                     "arclength", "is_fold", f"{p}_error", "w_error_over_R0", "energy_error"])
        for r in self.rows(errors=True):
            wr.writerow([repr(float(v)) for v in r[:6]] + [int(r[6])]
                        + [repr(float(v)) for v in r[7:]])
        atomic_write_text(path, buf.getvalue())
