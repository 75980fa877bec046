"""Eversion of a spherical cap (paper Section 5.2).

Geometry: a spherical cap of reference radius R0 (lengths in R0), opening half-angle Theta,
thickness h = h0/R0; the shallowness parameter is T = Theta sqrt(R0/h0).
Stimulus (eq. (stimulus)): abar = a°, bbar = b° + kappa a°, so kb1 = kb2 = kappa - 1/R0;
no through-thickness stimulus (we read the paper's rhob1 = rho1 as rhob1 = 1).
Material and model: Ciarlet-Geymonat (lam = lambda*/mu*) or incompressible neo-Hookean,
``plane_strain`` (rho1 = 1, rho2 = 0) or ``relaxed`` (rho1, rho2 minimising the energy).
Boundary conditions: apex held (z(0) = 0), free edge.
Observable: w, the vertical displacement of the free edge relative to the apex, in R0
(w = 2 (1 - cos Theta) for the fully everted cap).
Snapping: the snap curvature kappa_s is the first fold of the branch from kappa = 0, i.e. the
maximum of kappa along the branch; shallow caps evert without a fold.
"""

from __future__ import annotations

import csv
import io
import math
import os
from dataclasses import replace

import numpy as np

import shellbvp
from shellbvp import (Chebyshev, ContinuationOptions, Onset, Scene, SnapCurve, SnapResult,
                      as_method)
from shellbvp.cache import atomic_write_text
from shellbvp.methods import bracketing_nodes
from shellbvp.sweep import CHUNK_SIZE, Chunk, Journal, Record, SweepInterrupted, one_line
from shellbvp.sweep import run as run_sweep

#: the fold tolerance (in kappa R0) where neither ``tol`` nor ``options.fold_tol`` is given
TOL = 1e-9
#: ODE tolerance at which a shooting branch is followed to bracket its snap fold
BRACKET_RTOL = 1e-5
#: largest step in w / H along the fold curve from the first snapping cap to the cusp
ONSET_STEP = 0.05

__all__ = ["scene", "equilibrium", "branch", "snap_curvature", "SnapResult", "snap_curve",
           "SnapCurve", "CURVE_COLUMNS", "onset", "Onset", "flat_slope", "first_instability",
           "KAPPA_SCAN"]


def scene(theta, h, lam=1.0, *, model="relaxed", material="cg", nu=0.5) -> Scene:
    """The cap-eversion scene: uniform curvature stimulus, apex held, free edge.

    ``material="koiter"`` is the morphoelastic Koiter reference shell (Poisson ratio nu),
    whose kappa_s is the paper's "theoretical prediction" (Pezzulla et al. 2018)."""
    return shellbvp.cap(theta, h, lam=lam, model=model, material=material, nu=nu)


def equilibrium(kappa, theta, h, lam=1.0, *, model="relaxed", material="cg", nu=0.5,
                method="spectral", guess=None) -> shellbvp.Equilibrium:
    """The equilibrium at curvature stimulus kappa (1/R0), by natural continuation from the
    undeformed cap when no guess is given (steps of at most 0.5 in kappa R0)."""
    sc = scene(theta, h, lam, model=model, material=material, nu=nu)
    if guess is None:
        for k in np.linspace(0.0, kappa, max(2, int(math.ceil(abs(kappa) / 0.5)) + 1))[1:-1]:
            guess = shellbvp.solve(sc, k, method=method, guess=guess, estimate_error=False)
    return shellbvp.solve(sc, kappa, method=method, guess=guess)


def _fold_options(options, tol, default):
    """The continuation options with the fold tolerance in one place (``tol``, or the given
    options' ``fold_tol``; ValueError where both are set and differ)."""
    if options is None:
        return default.with_(fold_tol=TOL if tol is None else tol)
    if tol is None:
        return options
    return options.with_fold_tol(tol)


def branch(theta, h, lam=1.0, *, model="relaxed", material="cg", nu=0.5, kappa_max=None,
           n_folds=1, w_max=None, method="spectral", tol: float | None = None,
           options: ContinuationOptions | None = None, progress=None,
           energies=True, estimate_errors=True) -> shellbvp.Branch:
    """Continuation diagram kappa(w) from the undeformed cap (a :class:`shellbvp.Branch`).

    Stops after ``n_folds`` folds (default: the snap; None: no limit), at ``kappa_max``
    (1/R0), or when w exceeds ``w_max`` (default: 1.2 times the fully everted displacement
    2 (1 - cos Theta)). Folds are refined until kappa changes by at most ``tol`` (default
    ``options.fold_tol`` where options are given, else ``TOL``; ValueError if both set it,
    differently). ``method``: ``Chebyshev(...)`` (default ``"spectral"``), ``Shooting(...)``
    or ``Collocation(...)``. Every point carries its error estimate (``Branch.p_error``,
    ``w_error``) unless ``estimate_errors`` is False (:func:`shellbvp.follow`).
    """
    sc = scene(theta, h, lam, model=model, material=material, nu=nu)
    return _branch_of(sc, kappa_max=kappa_max, n_folds=n_folds, w_max=w_max, method=method,
                      options=_fold_options(options, tol, ContinuationOptions()),
                      progress=progress, energies=energies, estimate_errors=estimate_errors)


def _branch_of(sc, *, kappa_max, n_folds, w_max, method, options, progress,
               energies, estimate_errors: bool = True) -> shellbvp.Branch:
    """:func:`branch` of the scene ``sc`` (built and checked once by the caller);
    ``estimate_errors=False`` for a branch that only brackets its folds."""
    H = sc.geometry.rise
    w_max = 2.4 * H if w_max is None else float(w_max)
    kmax = math.inf if kappa_max is None else float(kappa_max)
    return shellbvp.follow(sc, method=method, p0=0.0, p_stop=(-math.inf, kmax),
                           n_folds=n_folds, w_stop=(-math.inf, w_max), options=options,
                           progress=progress, energies=energies,
                           estimate_errors=estimate_errors)


def _theta_gradient(fold) -> dict:
    """:func:`shellbvp.fold_gradient` of a snap fold with the meridian's length named as the
    cap's opening angle (on the unit sphere d/dL = d/dTheta)."""
    g = shellbvp.fold_gradient(fold)
    return {("theta" if k == "length" else k): v for k, v in g.items()}


def _default_spectral(method) -> bool:
    """Whether ``method`` is the default spectral method (degree chosen per cap): the one
    whose branches this module may follow on a coarser degree and carry along fold curves."""
    return method in ("spectral", Chebyshev())


def snap_curvature(theta, h, lam=1.0, *, model="relaxed", material="cg", nu=0.5,
                   method="spectral", tol: float | None = None,
                   options: ContinuationOptions | None = None,
                   gradient: bool = False) -> SnapResult:
    """kappa_s: the first fold of the branch from kappa = 0, refined until it changes by at
    most ``tol`` (default ``TOL``, or ``options.fold_tol``) on the method's ladder
    (Chebyshev: 4 more nodes per rung and 32 degrees from the degree tol needs, the branch
    itself followed on a coarser degree only to bracket the fold; shooting: ODE tolerance /
    10 per rung from the method's rtol, or from tol where the method leaves rtol free, the
    branch followed at ``BRACKET_RTOL`` unless the method sets ``bracket_rtol``;
    collocation: every interval halved); that change, with the round-off floor and the
    fold's location error, is the error estimate. Continuation takes long steps
    (:meth:`ContinuationOptions.to_first_fold`) unless ``options`` are given.
    ``gradient=True`` adds the exact derivatives of kappa_s in Theta, h and the material
    parameter (``SnapResult.gradient``; spectral method only), by
    implicit differentiation of the fold: for optimisation and inverse design."""
    if gradient and not _default_spectral(method):
        raise ValueError(f"gradient=True needs method='spectral', got method={method!r}")
    options = _fold_options(options, tol, ContinuationOptions.to_first_fold())
    sc = scene(theta, h, lam, model=model, material=material, nu=nu)
    if not _default_spectral(method):
        method = as_method(method)
    if _default_spectral(method):
        # the branch only brackets the fold, which is then located on the Chebyshev degrees
        # that tol needs: follow it on a coarser grid
        method = Chebyshev(nodes=bracketing_nodes(sc))
    elif isinstance(method, shellbvp.Shooting) and method.bracket_rtol is None \
            and method.steps is None:
        # likewise for shooting: the branch at a loose ODE tolerance, the fold from rtol (or
        # from tol where rtol is left free)
        method = replace(method, bracket_rtol=max(method.rtol or 0.0, BRACKET_RTOL))
    b = _branch_of(sc, kappa_max=None, n_folds=1, w_max=None, method=method,
                   options=options, progress=None, energies=False, estimate_errors=False)
    T = theta / math.sqrt(h)
    if not b.folds and b.stop:
        # the branch ended before full eversion for a reason of its own: "no snap" would be
        # a claim the computation did not make
        raise shellbvp.ConvergenceError(f"kappa_s: the branch ended before a fold or full "
                                        f"eversion: {b.stop}")
    if not b.folds:
        return SnapResult(False, math.nan, math.nan, math.nan, theta, h, lam, model, material,
                          T, dict(b.stats))
    f = b.folds[0]
    return SnapResult(True, float(f.p), float(f.w), float(f.error_estimate), theta, h, lam,
                      model, material, T, dict(b.stats) | {"fold": f.stats}, fold=f,
                      gradient=_theta_gradient(f) if gradient else None)


#: the default end of :func:`first_instability`'s scan of a cap that does not snap: kappa R0
#: = 6, three times the stimulus of full eversion (kappa R0 = 2), well past it (a shallow
#: Koiter cap, nu = 1/2, T = 1.5, bifurcates into n = 2 at kappa R0 = 3.54)
KAPPA_SCAN = 6.0


def first_instability(theta, h, lam=1.0, *, model="relaxed", material="cg", nu=0.5,
                      tol: float = 1e-6, degree: int | None = None, kappa_max=None,
                      w_max=None) -> shellbvp.Instability:
    """The cap's first instability along the branch from kappa = 0 (p = kappa R0): the
    axisymmetric snap (kind ``"fold"``, kappa_s) or a bifurcation into n circumferential
    waves before it (:func:`shellbvp.first_instability`). The cap is free: its rigid
    motions are zero modes of n = 0 and 1, excluded (:mod:`shellbvp.harmonics`). ``tol``:
    relative tolerance of the located kappa; ``degree``: of the perturbations. A cap that
    does not snap is scanned to ``kappa_max`` (default ``KAPPA_SCAN`` = 6, three times
    full eversion's stimulus) and, where given, until its apex displacement exceeds
    ``w_max`` (R0), whichever comes first (kind ``"none"`` with that stop, and how to scan
    further, where nothing is found)."""
    if kappa_max is not None and not (isinstance(kappa_max, (int, float))
                                      and kappa_max > 0):
        raise ValueError(f"kappa_max must be a positive curvature (1/R0), got {kappa_max!r}")
    kmax = KAPPA_SCAN if kappa_max is None else float(kappa_max)
    b = branch(theta, h, lam, model=model, material=material, nu=nu, n_folds=1,
               tol=min(tol, TOL), energies=False, kappa_max=kmax,
               w_max=math.inf if w_max is None else w_max, estimate_errors=False)
    found = shellbvp.first_instability(b, tol=tol, degree=degree)
    if found.kind == "none" and not found.stop:      # the continuation reached a bound
        if b.p[-1] >= kmax:
            bound = (f"kappa R0 passed kappa_max = {kmax:g}" if kappa_max is not None else
                     f"kappa R0 passed {kmax:g}, the default bound (three times full "
                     f"eversion's stimulus; kappa_max=, or --kappa-max, scans further)")
        else:
            bound = f"w passed w_max = {w_max:g} R0"
        found = replace(found, stop=bound)
    elif found.kind == "none" and "raise max_steps or ds_max" in found.stop:
        # the engine's remedy names options this function does not take
        found = replace(found, stop=found.stop.replace(
            "raise max_steps or ds_max", "scan a shorter range with kappa_max= (the "
            "command line's --kappa-max)"))
    return found


#: the columns of a kappa_s sweep's CSV, with their units (the first six as before; status
#: is ok / no snap / failed, reason the error of a failed cap in one line)
CURVE_COLUMNS = ("T", "theta_rad", "kappa_s_R0", "w_s_over_R0", "kappa_s_error", "snaps",
                 "status", "reason")


def snap_curve(T_values, h, lam=1.0, *, model="relaxed", material="cg", nu=0.5, tol=1e-9,
               method="spectral", csv_path=None, progress=True, resume: bool = False,
               jobs: int = 1, executor=None, chunk_size: int = CHUNK_SIZE) -> SnapCurve:
    """kappa_s R0 against the shallowness T = Theta sqrt(R0/h0) at fixed h.

    The caps are cut into chunks of ``chunk_size`` consecutive T (:mod:`shellbvp.sweep`).
    In a chunk each cap is continued from kappa = 0 until a cap snaps; the caps after it
    (spectral method) are points of the fold curve: the fold system (equilibrium and
    dp/dm = 0, exact second derivatives) solved by Newton at exactly that T from the
    extrapolation of the folds of the caps before (:func:`shellbvp.fold_near`), falling
    back to continuation where that fails. Either way every kappa_s is refined on the ladder
    of degrees to ``tol`` and carries the change between its last two rungs as its error
    estimate. A cap that fails does not stop the sweep: its row says ``failed`` and why,
    and the next cap starts from kappa = 0.

    Arguments:
        csv_path: write the sweep there (columns ``CURVE_COLUMNS``), atomically; while it
            runs every finished cap is appended to a journal beside it
            (``csv_path + ".journal"``, removed once the CSV is complete).
        resume: continue from that journal (same sweep: same caps and parameters), skipping
            the caps already finished; the result is that of an uninterrupted run.
        jobs: local processes (1: this one); ``executor``: any
            ``concurrent.futures.Executor`` instead (e.g. Dask's
            ``Client(...).get_executor()``). The chunks, hence the values, are the same
            whatever runs them.
        progress: a progress bar (tqdm) unless False.

    Returns:
        :class:`shellbvp.SnapCurve`: one record per cap (``status``: ok, no snap, failed;
        ``reason``), and its columns as arrays (``curve["kappa_s"]``, ...).

    Raises:
        ValueError: bad T_values (or a cap beyond a hemisphere), jobs, chunk_size, or a
            journal of another sweep.
        SweepInterrupted: Ctrl-C (or SIGTERM where the caller maps it, as the command line
            does): the caps finished before it are written to ``csv_path`` with a last
            line ``# incomplete: ...``, and the journal is kept for ``resume``.
    """
    from tqdm import tqdm

    T_values = np.asarray(T_values, dtype=float)
    if T_values.ndim != 1 or T_values.size == 0 or not np.all(np.isfinite(T_values)) or \
            np.any(T_values <= 0):
        raise ValueError(f"T_values must be a non-empty 1-D array of positive numbers, "
                         f"got {T_values!r}")
    for T in (T_values.min(), T_values.max()):       # every cap is a valid scene
        scene(T * math.sqrt(h), h, lam, model=model, material=material, nu=nu)
    if resume and csv_path is None:
        raise ValueError("resume=True needs csv_path (the journal lives beside it)")
    spec = dict(h=float(h), lam=float(lam), model=model, material=material, nu=float(nu),
                tol=float(tol), method=method)
    journal = None if csv_path is None else os.fspath(csv_path) + ".journal"
    bar = tqdm(total=T_values.size, desc="kappa_s sweep", disable=not progress, unit="cap")
    try:
        records = run_sweep(T_values, _sweep_chunk, spec, chunk_size=chunk_size,
                            journal=journal, resume=resume, jobs=jobs, executor=executor,
                            progress=bar.update)
    except SweepInterrupted as stop:
        if csv_path is not None:
            _write_curve(csv_path, stop.records,
                         f"# incomplete: {len(stop.records)} of {stop.total} caps; "
                         f"resume=True (shellbvp sweep ... --resume) continues")
        raise
    finally:
        bar.close()
    curve = SnapCurve(tuple(records), complete=True)
    if csv_path is not None:
        _write_curve(csv_path, records)
        Journal(journal).remove()
    return curve


def _write_curve(path, records, trailer=""):
    """The sweep's CSV (``CURVE_COLUMNS``, numbers as repr: exact round trip), atomically;
    ``trailer``: a last line (the mark of an incomplete sweep)."""
    buf = io.StringIO()
    wr = csv.writer(buf, lineterminator="\n")
    wr.writerow(CURVE_COLUMNS)
    for r in records:
        v = r.values
        wr.writerow([repr(r.key), repr(v["theta"]), repr(v["kappa_s"]), repr(v["w_s"]),
                     repr(v["error_estimate"]), int(v["snaps"]), r.status, r.reason])
    atomic_write_text(path, buf.getvalue() + (trailer + "\n" if trailer else ""))


def _sweep_chunk(chunk: Chunk) -> list:
    """The caps of one chunk of a sweep, in order (a :mod:`shellbvp.sweep` task): each from
    the folds of the one to three snapping caps before it in the chunk where there are
    such (along the fold curve), else continued from kappa = 0."""
    sp = chunk.spec
    h, lam, model, material, nu, tol, method = (sp[k] for k in (
        "h", "lam", "model", "material", "nu", "tol", "method"))
    out, folds = [], []     # folds: (T, fold) of the caps just before, along the fold curve
    for k, T in enumerate(chunk.keys):
        theta = T * math.sqrt(h)
        try:
            r = None
            if folds and _default_spectral(method):
                r = _along_fold_curve(T, folds, h, lam, model, material, nu, tol)
            if r is None:
                r = snap_curvature(theta, h, lam, model=model, material=material, nu=nu,
                                   tol=tol, method=method)
        except (shellbvp.ConvergenceError, ArithmeticError, RuntimeError) as exc:
            folds = []
            values = dict(theta=theta, kappa_s=math.nan, w_s=math.nan,
                          error_estimate=math.nan, snaps=False, along_fold_curve=False)
            out.append(chunk.emit(Record(chunk.first + k, T, "failed", one_line(exc),
                                         values)))
            continue
        folds = (folds + [(T, r.fold)])[-3:] if r.snaps else []
        values = dict(theta=float(r.theta), kappa_s=float(r.kappa_s), w_s=float(r.w_s),
                      error_estimate=float(r.error_estimate), snaps=bool(r.snaps),
                      along_fold_curve=bool(r.stats.get("along_fold_curve", False)))
        out.append(chunk.emit(Record(chunk.first + k, T, "ok" if r.snaps else "no snap",
                                     "", values)))
    return out


def _along_fold_curve(T, folds, h, lam, model, material, nu, tol):
    """kappa_s at shallowness T from the snap folds at the previous one to three T of a
    sweep (:func:`shellbvp.fold_near`: Newton on the fold system, started from the
    extrapolation of the folds' states and kappa in T along the fold curve), or None where
    that does not find the snap fold (then the sweep continues the cap from kappa = 0): a
    fold that is not the first one (w >= H, the mirror fold past the flat state) or a
    failure, e.g. next to the onset cusp."""
    (T1, f1) = folds[-1]
    # Lagrange weights of the extrapolation to T through the previous folds' T
    Ts = [Tk for Tk, _ in folds]
    weights = [math.prod((T - Tj) / (Ti - Tj) for j, Tj in enumerate(Ts) if j != i)
               for i, Ti in enumerate(Ts)]
    m = sum(wt * f.monitor for wt, (_, f) in zip(weights, folds))
    sc = scene(T * math.sqrt(h), h, lam, model=model, material=material, nu=nu)
    try:
        f = shellbvp.fold_near(sc, f1, monitor=m,
                               extrapolate=[(f, wt) for wt, (_, f) in zip(weights, folds)],
                               options=ContinuationOptions.to_first_fold(fold_tol=tol))
    except shellbvp.ConvergenceError:
        return None
    if not (0 < f.monitor < 1):
        return None
    return SnapResult(True, float(f.p), float(f.w), float(f.error_estimate), sc.length, h, lam,
                      model, material, T, {"fold": f.stats, "along_fold_curve": True}, fold=f)


def flat_slope(T, h, lam=1.0, *, model="relaxed", material="cg", nu=0.5, nodes=None):
    """dkappa/dw (1/R0^2) at the flat state w = H of the branch from kappa = 0 (positive:
    no fold there; negative: between a fold pair); ``nodes``: Chebyshev degree (default
    :func:`shellbvp.default_nodes`)."""
    sc = scene(T * math.sqrt(h), h, lam, model=model, material=material, nu=nu)
    H = sc.geometry.rise
    return shellbvp.at_monitor(sc, H, method=Chebyshev(nodes=nodes)).dp_dw


def onset(h, lam=1.0, *, model="relaxed", material="cg", nu=0.5, T_lo=1.0, T_step=0.25,
          T_max=6.0, tol=1e-6) -> Onset:
    """The onset of snapping, the cusp of the fold curve: scan T upwards from T_lo in steps
    of T_step until the slope at the flat state (:func:`flat_slope`) turns negative (the
    first T that snaps), take the snap fold there (:func:`snap_curvature`) and follow the
    fold curve with the edge displacement w prescribed and T free
    (:func:`shellbvp.fold_curve_point`: Newton on equilibrium, dp/dm = 0 and w, exact
    second derivatives) in steps of at most ``ONSET_STEP`` in w / H up to w = H, where the
    fold curve ends in the cusp. Solved on the fold's finest degree and again on
    the next one (the change, plus ``tol``, is the error estimate). Raises ValueError if the
    slope is already negative at T_lo or stays positive up to T_max, and ConvergenceError
    if the fold curve cannot be followed to the cusp."""
    for name, v in (("T_lo", T_lo), ("T_step", T_step), ("T_max", T_max), ("tol", tol)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a positive number, got {v!r}")

    a, ga = T_lo, flat_slope(T_lo, h, lam, model=model, material=material, nu=nu)
    if ga <= 0:
        raise ValueError(f"onset: the cap already snaps at T_lo = {T_lo} (slope {ga:.3g}); "
                         f"lower T_lo")
    while True:
        b = a + T_step
        if b > T_max:
            raise ValueError(f"onset: no snap up to T_max = {T_max}")
        if flat_slope(b, h, lam, model=model, material=material, nu=nu) < 0:
            break
        a = b
    snap = snap_curvature(b * math.sqrt(h), h, lam, model=model, material=material, nu=nu,
                          tol=min(tol, 1e-8))
    if not snap.snaps:
        raise shellbvp.ConvergenceError(f"onset: the cap at T = {b:g} has a negative slope "
                                        f"at the flat state but no snap fold was found")
    cusp = shellbvp.fold_curve_point(snap.fold, 1.0, step=ONSET_STEP)
    return Onset(T=cusp.theta / math.sqrt(h), error_estimate=cusp.error_estimate / math.sqrt(h)
                 + tol, bracket=(a, b), h=h, lam=lam, model=model, material=material,
                 kappa=cusp.p, stats=dict(cusp.stats, nodes=cusp.stats["resolution"]["nodes"]))
