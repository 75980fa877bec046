"""Pleodorina californica: a bowl of cells turned inside out by a travelling wave of cell
wedging (after Tribet & Haas, arXiv 2603.15171, 2026, and the description of the process by
Höhn & Hallmann, BMC Dev. Biol. 16, 35, 2016).

Sources. The stored copies of these papers hold their first pages (title and abstract)
only: no equation, parameter value or figure of them could be read. What the scene takes
from them is what their abstracts say: the embryo of P. californica (64 cells) is a
bowl-shaped cell sheet that turns itself inside out by a wave of cell wedging, modelled as a
change of the intrinsic curvature of an elastic surface; in Tribet & Haas's model a
mechanical bifurcation makes inversion possible in a subset of the parameter space only,
which contains the parameters estimated for 64 cells but not those extrapolated to 256 or
more. Every number below is this module's own choice, stated as such.

Geometry: a spherical cap of radius R (lengths in R, so R = 1), half-angle Theta (the
bowl; default pi/2, a hemisphere), thickness h (the cell height over R), traced from its
posterior pole (a pole, s = 0) to its rim (a free edge, s = Theta). The thickness from the
number of cells N (:func:`thickness_for_cells`, our estimate, not the paper's allometry):
N cuboidal cells, as tall as they are wide, tile the bowl, N d^2 = 2 pi (1 - cos Theta) R^2,
and h = d / R: 0.313 for N = 64 and 0.157 for N = 256 on the hemisphere.

Material: the Koiter shell with nu = 1/2 (incompressible, the classical law of a cell
sheet; default), or the reduced energies derived from 3D (``material="nh"``, or ``"cg"``
with ``lam``).

Stimulus (:func:`wave`): isotropic intrinsic curvature, no change of the metric (g = 1). A
band of ``band_cells`` cells (width W = band_cells h, default two cells) with intrinsic
curvature k_band (the wedged cells; k_band h is the wedging of one cell: its apical and
basal faces meet at an angle k_band d, and a cell wedged to a triangle has k_band h ~ 2)
travels from the rim to the pole. Ahead of it the cells keep the bowl's curvature -1/R
(outward normal: the sphere has k = -1/R); behind it they take the inverted bowl's
curvature k_after = +1/R. The band's edges are steps of width delta = W / 4 (tanh: a
field that moves with the stage must be smooth for the pieces to resolve it; a step at a
fixed break cannot travel); at the band's centre the steps stand at (1 +- tanh 2) / 2 of
their heights, so its curvature peaks short of k_band by 0.018 ((k_band + 1) + (k_band -
k_after)). The stage p places the band's centre at

    s_f = Theta + S - p (Theta + 2 S),   S = W / 2 + 6 delta:

p = 0 the band lies outside the rim (its steps reach the rim at tanh(-6): the stimulus
there is 6e-6 of its amplitude), p = 1 past the pole (the whole bowl targets the inverted
bowl to the same 6e-6).

Ends: the posterior pole (regular), the rim free. Observable w: the axial displacement of
the rim relative to the pole, 0 for the bowl and H = 2 (1 - cos Theta) R for the inverted
bowl, its mirror image (which is exactly stress-free at p = 1 up to the 6e-6 above).

Outcome of a wave (:func:`outcome`): the branch is followed in p from the bowl to p = 1.
``"continuous"``: it reaches the inverted bowl (w within ``INVERTED_TOL`` of H) with p
increasing all along; ``"snap"``: it reaches it past one or more folds (at the first fold
the sheet snaps); ``"stalls"``: the branch reaches p = 1 elsewhere, a frustrated bowl that
the wave has passed without turning it; ``"stopped"``: the continuation ended early (its
reason kept). The boundary between inverting and stalling waves in the wedging k_band h,
at given h (:func:`boundary`), is where the branch from the bowl changes the state it
connects to: bisection on the outcome, to a stated tolerance.
"""

from __future__ import annotations

import math
import time

import shellbvp
from shellbvp.methods import default_nodes
from shellbvp.sweep import Chunk, Record, one_line, run

__all__ = ["scene", "wave", "thickness_for_cells", "band_centre", "branch", "outcome",
           "boundary", "region_map", "OUTCOMES", "INVERTED_TOL", "THETA", "BAND_CELLS",
           "K_AFTER", "MAP_COLUMNS", "wave_nodes", "method_for", "NODES_PER_STEP"]

#: the bowl's half-angle (a hemisphere)
THETA = math.pi / 2
#: the band of wedged cells, in cells
BAND_CELLS = 2.0
#: the intrinsic curvature behind the wave (1/R): the inverted bowl
K_AFTER = 1.0
#: the band's edges are tanh steps of width delta = W * EDGE; the band starts and ends
#: SPAN_EDGES step widths beyond the bowl
EDGE, SPAN_EDGES = 0.25, 6.0
#: the inverted bowl is reached where w lies within this fraction of H = 2 (1 - cos Theta)
INVERTED_TOL = 0.01
#: what a wave does to the bowl (module docstring)
OUTCOMES = ("continuous", "snap", "stalls", "stopped")
#: folds located to this tolerance in p along a branch
FOLD_TOL = 1e-8
#: Chebyshev degree per step width of the band's edges over the meridian (the tanh steps
#: travel, so no piece boundary can follow them): 4.8 L / delta, in multiples of 8, resolves
#: w to ~1e-7 R (the 64-cell bowl: 48; the 256-cell bowl: 96)
NODES_PER_STEP = 4.8


def thickness_for_cells(cells: float, theta: float = THETA) -> float:
    """h = d / R for ``cells`` cuboidal cells (as tall as wide) tiling a bowl of half-angle
    theta: N d^2 = 2 pi (1 - cos theta) R^2 (our estimate, module docstring)."""
    if not (isinstance(cells, (int, float)) and cells >= 4):
        raise ValueError(f"cells must be a number >= 4, got {cells!r}")
    _check_theta(theta)
    return math.sqrt(2.0 * math.pi * (1.0 - math.cos(theta)) / cells)


def _check_theta(theta):
    if not (isinstance(theta, (int, float)) and 0.1 <= theta <= math.pi - 0.1):
        raise ValueError(f"theta must lie in [0.1, pi - 0.1] (the bowl's half-angle, "
                         f"radians), got {theta!r}")


def band_centre(p, theta, band, delta):
    """The centre s_f of the band at stage p (module docstring); array arithmetic."""
    span = band / 2 + SPAN_EDGES * delta
    return theta + span - p * (theta + 2 * span)


def wave(x, p, c):
    """The travelling band (module docstring): c = (Theta, W, delta, k_band, k_after);
    returns (g1, g2, kb1, kb2). Traced by JAX (in s, in p, or both): array arithmetic, and
    tanh from the array module of the step's argument (numpy or jax.numpy, by the array
    API; the argument is traced wherever s or p is)."""
    theta, band, delta, k_band, k_after = c[0], c[1], c[2], c[3], c[4]
    sf = band_centre(p, theta, band, delta)
    front = (x.s - (sf - band / 2)) / delta + 0.0 * x.s
    back = front - band / delta
    xp = front.__array_namespace__()
    enter = 0.5 * (1 + xp.tanh(front))          # 1 behind the band's front
    leave = 0.5 * (1 + xp.tanh(back))           # 1 behind its back
    one = 0.0 * x.s + 1.0
    k1 = x.k1 + (k_band - x.k1) * enter + (k_after - k_band) * leave
    k2 = x.k2 + (k_band - x.k2) * enter + (k_after - k_band) * leave
    return one, one, k1, k2


def scene(h: float, wedging: float, *, theta: float = THETA, band_cells: float = BAND_CELLS,
          k_after: float = K_AFTER, material: str = "koiter", nu: float = 0.5,
          lam: float = 1.0, model: str = "relaxed") -> shellbvp.Scene:
    """The bowl and its wave (module docstring).

    Arguments:
        h: thickness over R, in (0.01, 0.5).
        wedging: k_band h, the band's intrinsic curvature times the thickness, in
            (0, 2.5] (a cell wedged to a triangle: ~2).
        theta: the bowl's half-angle; band_cells: the band's width in cells (h each), in
            [0.5, 10]; k_after: the intrinsic curvature behind the wave (1/R).
        material, nu, lam, model: as :class:`shellbvp.Scene` (``nu`` for ``koiter``,
            ``lam`` and ``model`` for ``cg``).
    """
    if not (isinstance(h, (int, float)) and 0.01 < h < 0.5):
        raise ValueError(f"h must lie in (0.01, 0.5) (the cell height over the bowl's "
                         f"radius), got {h!r}")
    if not (isinstance(wedging, (int, float)) and 0 < wedging <= 2.5):
        raise ValueError(f"wedging must lie in (0, 2.5] (k_band h; a cell wedged to a "
                         f"triangle has ~2), got {wedging!r}")
    _check_theta(theta)
    if not (isinstance(band_cells, (int, float)) and 0.5 <= band_cells <= 10):
        raise ValueError(f"band_cells must lie in [0.5, 10], got {band_cells!r}")
    band = band_cells * h
    c = (float(theta), band, EDGE * band, wedging / h, float(k_after))
    material_args = {"koiter": dict(nu=nu), "nh": {}, "cg": dict(lam=lam, model=model)}
    if material not in material_args:
        raise ValueError(f"material must be one of {tuple(material_args)}, got {material!r}")
    return shellbvp.cap(theta, h, fields=wave, parameter="stage", parameter_unit="",
                        field_parameters=c, material=material, **material_args[material])


def wave_nodes(sc: shellbvp.Scene, nodes_per_step: float = NODES_PER_STEP) -> int:
    """The Chebyshev degree that resolves the travelling band of scene sc:
    ``nodes_per_step`` L / delta in multiples of 8, at least the scene's default
    (:func:`shellbvp.methods.default_nodes`)."""
    delta = sc.field_parameters[2]
    return max(default_nodes(sc), 8 * math.ceil(nodes_per_step * sc.length / delta / 8))


def method_for(sc: shellbvp.Scene, nodes_per_step: float = NODES_PER_STEP):
    """The spectral method at :func:`wave_nodes` (every solve of this scene should use it)."""
    return shellbvp.Chebyshev(nodes=wave_nodes(sc, nodes_per_step))


def branch(sc: shellbvp.Scene, *, stage_max: float = 1.0, fold_tol: float = FOLD_TOL,
           method=None, **follow_options) -> shellbvp.Branch:
    """The bowl's branch from stage 0 past ``stage_max`` (pseudo-arclength, folds located
    to ``fold_tol``), or to where the continuation stalls (``Branch.stop`` says why).
    ``method``: default the spectral method at :func:`wave_nodes`."""
    options = shellbvp.ContinuationOptions(fold_tol=fold_tol)
    if method is None:
        method = method_for(sc)
    return shellbvp.follow(sc, p_stop=(-0.5, stage_max), options=options, method=method,
                           on_stall="stop", **follow_options)


def _rise(sc) -> float:
    return 2.0 * sc.geometry.rise


def outcome(b: shellbvp.Branch) -> str:
    """What the wave did to the bowl along branch b (module docstring, ``OUTCOMES``)."""
    if b.stop:
        return "stopped"
    H = _rise(b.scene)
    if abs(b.w[-1] - H) > INVERTED_TOL * H:
        return "stalls"
    return "snap" if b.folds else "continuous"


def _classify(h, wedging, theta, band_cells, material, nodes_per_step=NODES_PER_STEP):
    sc = scene(h, wedging, theta=theta, band_cells=band_cells, material=material)
    b = branch(sc, energies=False, method=method_for(sc, nodes_per_step))
    first = b.folds[0] if b.folds else None
    return outcome(b), (float(first.p) if first else math.nan), b


def boundary(h: float, lo: float, hi: float, *, tol: float = 0.005, theta: float = THETA,
             band_cells: float = BAND_CELLS, material: str = "koiter",
             nodes_per_step: float = NODES_PER_STEP) -> tuple:
    """The wedging k_band h at which waves stop inverting the bowl of thickness h:
    bisection between ``lo`` (a wave that stalls) and ``hi`` (one that inverts) until the
    bracket is below ``tol``; ``nodes_per_step``: the resolution (:func:`wave_nodes`).
    Returns (lower, upper): the largest wedging found to stall and the smallest found to
    invert. Raises ValueError if the ends do not bracket."""
    def inverts(k):
        return _classify(h, k, theta, band_cells, material, nodes_per_step)[0] in (
            "continuous", "snap")
    if inverts(lo) or not inverts(hi):
        raise ValueError(f"boundary: wedging {lo} must stall and {hi} invert at h = {h}")
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if inverts(mid) else (mid, hi)
    return lo, hi


#: the map's columns (:func:`region_map`), one row per (h, wedging)
MAP_COLUMNS = ("h", "cells", "wedging", "outcome", "first_fold_stage", "w_end", "seconds",
               "folds", "stop")


def _map_chunk(chunk: Chunk) -> list:
    """One thickness of the map (a :mod:`shellbvp.sweep` task): the outcome at every
    wedging of the grid, then the boundary by bisection inside the bracket the grid
    found (``spec``: wedgings, tol, theta, band_cells, material)."""
    sp = chunk.spec
    out = []
    for k, h in enumerate(chunk.keys):
        rows = []
        try:
            for q in sp["wedgings"]:
                t0 = time.perf_counter()
                kind, fold, b = _classify(h, q, sp["theta"], sp["band_cells"], sp["material"])
                rows.append((q, kind, fold, float(b.w[-1]), time.perf_counter() - t0,
                             len(b.folds), b.stop[:200]))
            # the first wedging of the grid that inverts right after one that stalls
            pair = next(((a[0], b_[0]) for a, b_ in zip(rows, rows[1:])
                         if a[1] == "stalls" and b_[1] in ("continuous", "snap")), None)
            edge = (math.nan, math.nan)
            t0 = time.perf_counter()
            if pair is not None:
                edge = boundary(h, *pair, tol=sp["tol"], theta=sp["theta"],
                                band_cells=sp["band_cells"], material=sp["material"])
            values = dict(rows=rows, boundary=edge, boundary_seconds=time.perf_counter() - t0)
            out.append(chunk.emit(Record(chunk.first + k, h, "ok", "", values)))
        except (shellbvp.ConvergenceError, ArithmeticError, RuntimeError, ValueError) as exc:
            out.append(chunk.emit(Record(chunk.first + k, h, "failed", one_line(exc),
                                         dict(rows=rows, boundary=(math.nan, math.nan)))))
    return out


def region_map(thicknesses, wedgings, *, tol: float = 0.005, theta: float = THETA,
               band_cells: float = BAND_CELLS, material: str = "koiter", jobs: int = 1,
               executor=None, journal=None, resume: bool = False, progress=None) -> list:
    """The parameter region where the wave inverts the bowl: for every thickness h, the
    outcome at every wedging k_band h of the grid and the boundary between stalling and
    inverting waves to ``tol`` (:func:`boundary`). A sweep (:func:`shellbvp.sweep.run`):
    one thickness per chunk, run by ``jobs`` local processes or any ``executor`` (Dask's);
    ``journal``/``resume`` as there. Returns one :class:`shellbvp.sweep.Record` per
    thickness (values ``rows``: (wedging, outcome, first fold's stage, w at the end, wall
    time, number of folds, the stop reason); ``boundary``: (stalls, inverts) or NaN where
    the grid holds no such pair, and ``boundary_seconds``)."""
    spec = dict(wedgings=tuple(float(q) for q in wedgings), tol=float(tol), theta=float(theta),
                band_cells=float(band_cells), material=material)
    for h in thicknesses:                              # every item a valid scene
        scene(float(h), spec["wedgings"][0], theta=theta, band_cells=band_cells)
    return run([float(h) for h in thicknesses], _map_chunk, spec, chunk_size=1,
               journal=journal, resume=resume, jobs=jobs, executor=executor,
               progress=progress)
