"""Public entry points: one equilibrium (:func:`solve`), a branch with its folds
(:func:`follow`), and the branch point where the observable takes a value
(:func:`at_monitor`). Each takes a method object (or its name) and returns a result of
:mod:`shellbvp.results`.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from .continuation import (ContinuationOptions, fold_at_monitor, fold_ladder, fold_sensitivity,
                           ladder, newton, pseudo_arclength, refine_fold, tangent)
from .continuation.arclength import point_at_parameter
from .continuation.estimates import change, refine_points
from .errors import ConvergenceError
from .models import MATERIAL_PARAMETER
from .methods import Collocation, as_method
from .methods.base import DirectSolver, MidSurface, SecondOrder, Transplantable, implements
from .ellipticity import elliptic_point, stall_reason
from .results import Branch, Equilibrium, Fold, equilibrium_from, failed_equilibrium
from .scene import Scene

__all__ = ["solve", "follow", "at_monitor", "fold_near", "fold_gradient", "MonitorPoint",
           "SOLVE_NEWTON_TOL"]

#: Newton on a discrete system at fixed p stops at this relative update (quadratic
#: convergence: the residual left is ~1e-20)
SOLVE_NEWTON_TOL = 1e-10
SOLVE_MAXITER = 40
#: points per piece at which a solution and its refinement are compared (error estimate)
ERROR_SAMPLES = 65
def _shell_bvp(scene, eps):
    """The BVP of ``scene`` (imported here: its compiled kernels bring JAX, which
    ``import shellbvp`` does not load)."""
    from .bvp import ShellBVP

    return ShellBVP(scene, eps)


def _check_p(scene, p):
    if np.ndim(p) != 0 or not np.isfinite(p):
        raise ValueError(f"{scene.parameter} must be a finite scalar, got {p!r}")


def _profile_of(guess):
    if guess is None:
        return None
    if isinstance(guess, Equilibrium):
        return guess.unknowns
    if not callable(guess):
        raise ValueError(f"guess must be an Equilibrium or a callable s -> (6, n), got "
                         f"{type(guess).__name__}")
    return guess


def _continuation_method(method):
    """The method object of a continuation: options that only :func:`solve` reads are
    refused here rather than ignored."""
    method = as_method(method)
    if isinstance(method, Collocation) and method.tol is not None:
        raise ValueError(f"Collocation.tol = {method.tol!r} is solve_bvp's tolerance for one "
                         f"equilibrium (solve); a continuation refines its folds to "
                         f"options.fold_tol (a scene's tol): leave Collocation.tol unset")
    return method


def _newton_at(system, U, p, what):
    res = newton(system, U, p, 0.0, 1.0, p, tol=SOLVE_NEWTON_TOL, maxiter=SOLVE_MAXITER,
                 fail_fast=False)
    if not res.ok:
        why = res.diagnosis or "try a closer guess"
        raise ConvergenceError(f"{what}: Newton did not converge at {system.bvp.scene.parameter}"
                               f" = {p:g} ({system.describe()}): {why}; history (|residual|, "
                               f"|update|): {res.history}")
    return res


def _discrete_solve(method, bvp, p, profile):
    if implements(method, DirectSolver):    # a method with its own solver (solve_bvp)
        return method.solve(bvp, p, profile)
    system = method.discretise(bvp)
    res = _newton_at(system, system.from_profile(profile), p, method.name)
    return system, res.U, dict(newton_iterations=res.iterations, newton_history=res.history)


def solve(scene: Scene, p: float, *, method="spectral", guess=None, eps: float | None = None,
          estimate_error: bool = True, throw: bool = True) -> Equilibrium:
    """The axisymmetric equilibrium of ``scene`` at parameter value ``p``.

    Arguments:
        scene: the problem (geometry, stimulus, material, boundary conditions).
        p: value of ``scene.parameter`` (e.g. kappa, in 1/R0).
        method: ``Chebyshev(nodes=...)`` (default ``"spectral"``), ``Shooting(...)`` or
            ``Collocation(tol=...)`` (scipy's solve_bvp with its adaptive mesh), or a name.
        guess: an :class:`Equilibrium` (e.g. at a nearby p) or a callable s -> (6, n) of
            the BVP's unknowns; default the undeformed cap.
        eps: pole offset (default ``POLE_OFFSET * theta``).
        estimate_error: also solve on the method's next finer discretisation and report
            the largest change of (r, z, theta) and of w as ``error_estimate``.
        throw: raise on failure (else return ``success=False`` with the message).

    Returns:
        :class:`Equilibrium`.

    Raises:
        ValueError: bad arguments. ConvergenceError: no convergence (with diagnostics).
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a shellbvp.Scene, got {type(scene).__name__}")
    _check_p(scene, p)
    method = as_method(method)
    bvp = _shell_bvp(scene, eps)
    profile = _profile_of(guess) or bvp.reference
    t0 = time.perf_counter()
    try:
        system, U, stats = _discrete_solve(method, bvp, float(p), profile)
        bvp = system.bvp                    # the method's (e.g. on its elements)
        err = math.nan
        if estimate_error:
            fine = system.refined()
            Uf = _newton_at(fine, system.transfer(U, p, fine), p, "error estimate").U
            t = np.linspace(0.0, 1.0, ERROR_SAMPLES)
            s = np.concatenate([bvp.s_of(i, t) for i in range(bvp.P)])
            a, b = bvp.profile(system.dense(U, p)), bvp.profile(fine.dense(Uf, p))
            err = max(float(np.max(np.abs(a(s)[:3] - b(s)[:3]))),
                      abs(fine.monitor(Uf)[0] - system.monitor(U)[0]) * bvp.scale)
    except ConvergenceError as exc:
        if throw:
            raise
        return failed_equilibrium(scene, p, str(exc), {"method": method.name})
    stats = dict(stats, **system.describe(), evaluations=bvp.evaluations,
                 wall_time=time.perf_counter() - t0)
    return equilibrium_from(system, U, p, stats=stats, error_estimate=err)


def follow(scene: Scene, *, method="spectral", p0: float = 0.0,
           p_stop=(-math.inf, math.inf), w_stop=(-math.inf, math.inf), n_folds=None,
           options: ContinuationOptions | None = None, eps: float | None = None,
           progress=None, energies: bool = True, on_stall: str = "raise",
           check_ellipticity: bool = False, check_stability: bool = False,
           estimate_errors: bool = True, at=()) -> Branch:
    """Continue ``scene`` in its parameter from the undeformed state at p0.

    Pseudo-arclength continuation (:mod:`shellbvp.continuation`) of the method's discrete
    system; every fold passed is located exactly (dp/dw = 0) and refined on the method's
    ladder of finer discretisations until p changes by at most ``options.fold_tol``, the
    change being its error estimate.

    Stops when p leaves ``p_stop``, w leaves ``w_stop`` (R0), after ``n_folds`` folds or at
    ``options.max_steps`` points. ``energies=False`` skips the energy columns (nan).
    ``progress(point)`` is called after every point. Raises ValueError for bad arguments and
    ConvergenceError on failure. ``on_stall="stop"`` returns instead the branch converged
    before a stall (no step down to ``options.ds_min`` converges), with the reason in
    ``Branch.stop``; nothing past the last converged point is returned.
    ``check_ellipticity=True`` evaluates the Legendre condition of the reduced energy
    (:func:`shellbvp.ellipticity.ellipticity`) at every point and ends the branch before the
    first point where it fails anywhere on the meridian: past it the energy is not elliptic,
    the equations admit solutions that depend on the discretisation, and the branch would
    no longer be physics (a crease forms below the resolution).
    ``check_stability=True`` (a method that discretises the mid-surface, such as
    :class:`shellbvp.Ritz`) ends the branch before the first point where the Hessian of its
    discrete energy at fixed parameter is not positive definite
    (:func:`shellbvp.stability.stable_point`): the loss of stability of the axisymmetric
    state, or, where the reduced energy is not elliptic, of the model itself.
    ``estimate_errors=True`` gives every point its error estimate (``Branch.p_error``,
    ``w_error``, ``energy_error``): the point solved again on the method's next finer
    discretisation (:func:`shellbvp.continuation.estimates.refine_points`, one or two
    Newton updates per point); False skips it (nan), for a branch used only to bracket
    its folds, which carry their own estimates.
    ``at``: parameter values at which the branch's states are wanted exactly: every
    crossing of each value between two points is solved with the parameter prescribed and
    inserted in the branch (``Branch.requested``: (value, point index) pairs, in order);
    a value the branch does not reach is absent from it.
    """
    if on_stall not in ("raise", "stop"):
        raise ValueError(f"on_stall must be 'raise' or 'stop', got {on_stall!r}")
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a shellbvp.Scene, got {type(scene).__name__}")
    _check_p(scene, p0)
    options = ContinuationOptions() if options is None else options
    if not isinstance(options, ContinuationOptions):
        raise ValueError(f"options must be a ContinuationOptions, got {type(options).__name__}")
    t0 = time.perf_counter()
    method = _continuation_method(method)
    system = method.discretise(_shell_bvp(scene, eps))
    bvp = system.bvp                        # the method's (e.g. on its elements)
    H = bvp.scale
    stop = ""
    surface = implements(system, MidSurface)
    if check_stability and not surface:
        raise ValueError(f"check_stability needs a method that discretises the mid-surface "
                         f"(shellbvp.Ritz), got {method.name!r}")
    checks = []
    if check_ellipticity:
        checks.append(lambda pt: elliptic_point(system, pt))
    if check_stability:
        from .stability import stable_point

        checks.append(lambda pt: stable_point(system, pt))

    def admissible(pt):
        return next((why for why in (c(pt) for c in checks) if why), "")

    try:
        pts, brackets = pseudo_arclength(
            system, system.from_profile(bvp.reference), float(p0), options=options,
            p_stop=p_stop, monitor_stop=(w_stop[0] / H, w_stop[1] / H), n_folds=n_folds,
            progress=progress, admissible=admissible if checks else None,
            describe=lambda pt: f"{scene.quote(pt.p, 10)} (w = "
                                f"{scene.display.length_scale * pt.monitor * H:.6g})")
    except ConvergenceError as exc:
        if exc.round_off and scene.material == "cg" and scene.lam > 1e3:
            raise ConvergenceError(f"lam = {scene.lam:g} is beyond what double precision "
                                   f"resolves here; for a nearly incompressible shell use "
                                   f"material='nh' (the limit lam -> infinity). {exc}",
                                   partial=exc.partial, round_off=True) from None
        if on_stall == "raise" or exc.partial is None:
            raise
        (pts, brackets), stop = exc.partial, stall_reason(system, exc.partial[0], str(exc))
    if not stop and len(pts) >= options.max_steps and (n_folds is None
                                                        or len(brackets) < n_folds):
        # the branch did not reach any of its stops: say so rather than end in silence
        stop = (f"options.max_steps = {options.max_steps} points reached at "
                f"{scene.quote(pts[-1].p)}, w = {pts[-1].monitor * H:.6g} "
                f"before any stop; raise max_steps or ds_max")
    folds = []
    for i, j in brackets:
        try:
            folds.append(refine_fold(system, pts[i], pts[j], options=options, index=i))
        except ConvergenceError as exc:
            if on_stall == "raise":
                raise
            # p and w turn back together: not a fold of p(w) but a singular point (or the
            # edge of the model's validity); keep the branch up to it
            pts = pts[:i + 1]
            stop = stall_reason(system, pts, f"the branch turns back in {scene.parameter} "
                                 f"and w at once after {scene.quote(pts[i].p)}: {exc}")
            break
    requested = ()
    if len(at):
        pts, requested, moved = _states_at(system, pts, at, options)
        folds = [replace(f, index=moved[f.index]) for f in folds]
    folds = tuple(folds)

    def energy(system, U, p):
        """(E_s, E_b, E_p), nan where the quadrature between the nodes finds no inner root
        (next to a loss of ellipticity; the state at the nodes stands)."""
        try:
            return system.energies(U, p) if surface else \
                system.bvp.energies(system.dense(U, p), p)
        except ConvergenceError:
            return (math.nan,) * 3

    E = np.array([energy(system, pt.U, pt.p) for pt in pts]) if energies \
        else np.full((len(pts), 3), math.nan)
    refined, note = None, "not estimated (estimate_errors=False)"
    p_err, w_err, E_err = (np.full(len(pts), math.nan) for _ in range(3))
    if estimate_errors:
        asked = {i for _, i in requested}
        held = ["p" if k in asked else None for k in range(len(pts))]
        refined = refine_points(system, pts, held=held)
        note = refined.reason
        ratio = system.rung_ratio
        for k, (pt, fine) in enumerate(zip(pts, refined.points)):
            if fine is None:
                continue
            U_f, p_f, m_f = fine
            p_err[k] = change(pt.p, p_f, ratio=ratio)
            w_err[k] = change(pt.monitor, m_f, scene.geometry.size / H, ratio) * H
            if energies:
                E_err[k] = change(E[k].sum(), sum(energy(refined.system, U_f, p_f)),
                                  ratio=ratio)
    return Branch(scene=scene, p=np.array([pt.p for pt in pts]),
                  w=np.array([pt.monitor for pt in pts]) * H, energy=E.sum(axis=1),
                  stretching_energy=E[:, 0], bending_energy=E[:, 1], load_potential=E[:, 2],
                  arclength=np.array([pt.arclength for pt in pts]), folds=folds,
                  stats=dict(system.describe(), points=len(pts), evaluations=bvp.evaluations,
                             wall_time=time.perf_counter() - t0),
                  points=tuple(pts), system=system, stop=stop, method=method,
                  p_error=p_err, w_error=w_err, energy_error=E_err, refined=refined,
                  error_note=note, requested=requested)


def _states_at(system, pts, values, options):
    """The branch ``pts`` with the states at the parameter values ``values`` inserted
    (every crossing between two points solved with p prescribed, from the interpolation
    between them; a point already at a value is that state): (points, ((value, index),
    ...) in order of arclength, old index -> new index)."""
    values = [float(v) for v in values]
    out, requested, moved = [], [], {}
    for k, b in enumerate(pts):
        if k:
            a = pts[k - 1]
            hits = sorted((v for v in values if (a.p - v) * (b.p - v) < 0),
                          key=lambda v: abs(v - a.p))
            for v in hits:
                frac = (v - a.p) / (b.p - a.p)
                q = point_at_parameter(system, a.U + frac * (b.U - a.U), v, v,
                                       tol=SOLVE_NEWTON_TOL, sign_like=a)
                out.append(replace(q, arclength=a.arclength
                                   + frac * (b.arclength - a.arclength)))
                requested.append((v, len(out) - 1))
        moved[k] = len(out)
        out.append(b)
        requested.extend((v, len(out) - 1) for v in values if b.p == v)
    return out, tuple(requested), moved


@dataclass(frozen=True)
class MonitorPoint:
    """The branch where its observable takes a prescribed value.

    ``p``: the parameter there; ``w``: the prescribed observable (R0); ``dp_dw``: the slope
    dp/dw there (exact, from the bordered Jacobian; 1/R0^2 for kappa), negative between a
    fold pair; ``resolution``: the discretisation used.
    """

    p: float
    w: float
    dp_dw: float
    resolution: dict


def at_monitor(scene: Scene, w: float, *, p0: float = 0.0, method="spectral",
               eps: float | None = None,
               options: ContinuationOptions | None = None) -> MonitorPoint:
    """Follow the branch from the undeformed state at p0 until w (R0) is first reached, and
    solve there with w prescribed and the parameter unknown.

    The monitor is a displacement, zero in the undeformed state, so a negative w is reached
    from above (e.g. a pole pushed down) and a positive one from below.

    Raises ValueError for a non-finite w and ConvergenceError if the branch does not reach w.
    """
    if not math.isfinite(w):
        raise ValueError(f"w must be finite, got {w!r}")
    system = _continuation_method(method).discretise(_shell_bvp(scene, eps))
    bvp = system.bvp
    target = w / bvp.scale
    sign = 1.0 if target >= 0 else -1.0
    stop = (-math.inf, target) if sign > 0 else (target, math.inf)
    pts, _ = pseudo_arclength(system, system.from_profile(bvp.reference), float(p0),
                              options=options or ContinuationOptions.to_first_fold(),
                              monitor_stop=stop)
    # the continuation's last step lands on the target (to round-off) where it crosses it
    if sign * (pts[-1].monitor - target) < -1e-12 * (1.0 + abs(target)):
        raise ConvergenceError(f"the branch did not reach w = {w:g} (last w = "
                               f"{pts[-1].monitor * bvp.scale:.6g})")
    q = min(pts[-2:], key=lambda q: abs(q.monitor - target))
    res = newton(system, *q.predicted(target), 1.0, 0.0, target, tol=SOLVE_NEWTON_TOL)
    if not res.ok:
        raise ConvergenceError(f"no solution with w = {w:g} prescribed: {res.history}")
    _, _, slope = tangent(res)
    return MonitorPoint(p=res.p, w=w, dp_dw=slope / bvp.scale, resolution=system.describe())


def fold_near(scene: Scene, near, *, monitor: float | None = None, p: float | None = None,
              options: ContinuationOptions | None = None, eps: float | None = None,
              extrapolate=()):
    """The fold of ``scene`` near ``near``, a :class:`Fold` of a nearby scene with the same
    pieces (e.g. the same cap at a nearby shallowness): a fold curve followed one scene at a
    time, without continuing each scene from p0.

    The nearby fold's state is carried over as a displacement from the reference state (at
    the same piece coordinates and discretisation) with the parameter ``p`` (default: the
    nearby fold's; pass an extrapolation along the fold curve), and the fold is solved for
    directly, by Newton on the fold system with exact second derivatives, on the ladder of
    degrees to ``options.fold_tol`` (:func:`shellbvp.continuation.fold_ladder`). Where that
    fails it is located along the branch from the monitor ``monitor`` (default: the nearby
    fold's) with the nearby fold's d2p/dm2 and refined as in :func:`follow`. Either way the
    error estimate is the change between the last two rungs.

    ``extrapolate``: pairs (fold, weight) of folds of nearby scenes (``near`` among them,
    weights summing to 1, e.g. Lagrange weights of an extrapolation along the fold curve):
    the Newton iteration then starts from that combination of their displacements and
    parameters instead (a quadratic extrapolation in T saves one iteration in three).

    Raises ValueError if ``near`` was not found by a method whose systems can be carried to
    another scene (Chebyshev), and ConvergenceError if no fold is found there (the fold may
    have vanished, e.g. at a cusp): then continue the scene from p0 with :func:`follow`.
    """
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a shellbvp.Scene, got {type(scene).__name__}")
    old = near.system
    if not implements(old, Transplantable) or old.bvp.scene.pieces != scene.pieces:
        raise ValueError("fold_near needs a fold found by the Chebyshev method on a scene with "
                         "the same pieces")
    options = ContinuationOptions() if options is None else options
    bvp = _shell_bvp(scene, eps)
    system = old.on(bvp)
    def displacement(f):
        d = f.U - f.system.from_profile(f.system.bvp.reference)
        return d if f.system is old or f.system.size == old.size and np.array_equal(
            f.system.t, old.t) else f.system.transfer(d, f.p, old)

    m0 = near.monitor if monitor is None else float(monitor)
    p0 = near.p if p is None else float(p)
    if extrapolate:
        D = sum(wt * displacement(f) for f, wt in extrapolate)
        p0 = float(sum(wt * f.p for f, wt in extrapolate)) if p is None else p0
    else:
        D = displacement(near)
    U = D + system.from_profile(bvp.reference)
    # the ladder starts where the tolerance needs it, not on the nearby fold's last rung
    if implements(system, SecondOrder):
        try:
            return fold_ladder(system, U, p0, options=options)
        except ConvergenceError:
            pass          # e.g. the carried state outside Newton's basin: locate it in m
    start = system.at_tolerance(options.fold_tol)
    return ladder(start, system.transfer(U, p0, start), p0, m0,
                  near.stats.get("curvature"), options=options)


@dataclass(frozen=True)
class FoldCurvePoint:
    """A point of a fold curve in (theta, p) where the monitor takes a prescribed value.

    ``theta``: the scene's opening angle there; ``p``: the fold's parameter; ``monitor``:
    the prescribed w / H; ``error_estimate``: the change of theta with the next Chebyshev
    degree; ``fold``: the fold (a :class:`Fold` of the scene at ``theta``, finer degree);
    ``stats``: steps and Newton iterations."""

    theta: float
    p: float
    monitor: float
    error_estimate: float
    fold: object = None
    stats: dict = None


def fold_curve_point(near, monitor: float, *, step: float = 0.05) -> FoldCurvePoint:
    """Follow the fold curve of ``near`` (a :class:`Fold` found by the spectral method) in
    (theta, p), with the monitor prescribed and theta free, from ``near.monitor`` to
    ``monitor`` in steps of at most ``step`` (in w / H): Newton on (equilibrium, dp/dm = 0,
    m - monitor) in (U, p, theta) (:func:`shellbvp.continuation.fold_at_monitor`, exact
    derivatives), then the last point again on the next degree (its change in theta is the
    error estimate). For a cap the fold curve ends at w = H (monitor 1) in the cusp where
    the snap is born. Raises ValueError for a fold of another method or a non-finite or
    non-positive step, ConvergenceError where the curve cannot be followed (e.g. past its
    end, where the fold ceases to exist)."""
    if not (isinstance(near, Fold) and implements(near.system, SecondOrder)):
        raise ValueError("fold_curve_point needs a fold found by the spectral method")
    if not (math.isfinite(monitor) and math.isfinite(step) and step > 0):
        raise ValueError(f"monitor must be finite and step positive, got monitor={monitor!r}, "
                         f"step={step!r}")
    base = near.system.bvp.scene
    eps = near.system.bvp.eps if near.system.bvp.eps_given else None

    def at_theta(system):
        return lambda th: system.on(_shell_bvp(base.with_length(float(th)), eps))

    system, U, p, theta = near.system, near.U, near.p, base.length
    steps = max(1, math.ceil(abs(monitor - near.monitor) / step))
    iterations = 0
    for m in np.linspace(near.monitor, monitor, steps + 1)[1:]:
        system, U, p, theta, its = fold_at_monitor(system, U, p, theta, m, at_theta(system))
        iterations += its
    finer = system.refined()
    fine, U2, p2, theta2, its = fold_at_monitor(finer, system.transfer(U, p, finer), p, theta,
                                                monitor, at_theta(finer))
    m2, _ = fine.monitor(U2)
    fold = Fold(p=float(p2), monitor=float(m2), U=U2, system=fine,
                error_estimate=abs(float(p2) - float(p)))
    return FoldCurvePoint(theta=float(theta2), p=float(p2), monitor=float(monitor),
                          error_estimate=abs(float(theta2) - float(theta)), fold=fold,
                          stats=dict(steps=steps, newton_iterations=iterations + its,
                                     resolution=fine.describe()))


def fold_gradient(fold) -> dict:
    """Exact derivatives of a fold's parameter value (e.g. kappa_s) in the scene's data:
    ``{"length": dp/dL, "h": dp/dh, <material>: ...}`` with L the meridian's length (the
    second end moved along its segment: dp/dTheta for a cap of the unit sphere) and
    <material> ``"lam"`` (Ciarlet-Geymonat) or ``"nu"`` (Koiter); an incompressible
    neo-Hookean shell has no material parameter. Each derivative holds the other quantities
    (and the scene's interfaces, in s) fixed; at fixed h, d/dT = sqrt(h) d/dTheta
    (T = Theta / sqrt(h)).

    By implicit differentiation of the fold of the discrete system the fold was refined on
    (:func:`shellbvp.continuation.fold_sensitivity`), with the derivatives of the equations
    from JAX: exact to round-off for that system, and as accurate as the fold itself for
    the continuous problem. Needs a fold found by the spectral method (ValueError else).
    """
    d = fold_sensitivity(fold)
    name = MATERIAL_PARAMETER[fold.system.bvp.scene.material]
    out = {"length": d["length"], "h": d["h"]}
    if name is not None:
        out[name] = d["material"]
    return out
