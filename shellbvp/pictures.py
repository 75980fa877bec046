"""3D pictures of states and animations of branches (matplotlib's mplot3d).

A state is drawn as its deformed surface (:mod:`shellbvp.surface`) with a sector cut away
so that its inside shows (the sector that faces the viewer; the cut's two meridians drawn
as lines), each face coloured by a field through a colormap, with a colour bar naming the
field and its unit. A field that takes both signs gets a diverging map centred on zero.
The three axes have one scale: a shallow shell looks shallow (``magnify`` exaggerates the
displacement, not the geometry).

An animation draws the states of a branch, one frame each, in one colour scale and one
box, beside the branch's diagram with the current point marked, and writes a GIF (Pillow)
or an MP4 (ffmpeg), atomically.

matplotlib is imported here only, when a picture is asked for.
"""

from __future__ import annotations

import math
import shutil
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable

import numpy as np

from .surface import (EQUILIBRIUM_FIELDS, LOBED_FIELDS, OutputUnits, Surface,
                      equilibrium_surface, lobed_surface)

__all__ = ["plot3d", "plot_lobed3d", "draw_surface", "animate", "animate_lobed",
           "frame_indices", "Look", "FORMATS"]

#: the animation formats, by suffix, and what writes them
FORMATS = {".gif": "pillow", ".mp4": "ffmpeg"}
#: the picture's angles around the full circle (fewer where a sector is cut; a lobed state
#: at least 16 per wave of its highest harmonic)
POINTS = 96
#: the 3D box's zoom: the default leaves a wide margin around the drawing
ZOOM = 1.3


@dataclass(frozen=True)
class Look:
    """How a state is drawn, checked once (every option of :func:`plot3d`).

    Attributes:
        cut: the sector removed, degrees in [0, 360), centred on the side facing the viewer.
        view: (elevation, azimuth) of the camera, degrees.
        cmap: a colormap or its name; None: ``coolwarm`` for a field of both signs (centred
            on zero), else ``viridis``.
        vmin, vmax: the colour range (None: the field's).
        axes: draw the axes with their ticks and the length unit (else none).
    """

    cut: float = 90.0
    view: tuple = (30.0, -60.0)
    cmap: object = None
    vmin: float | None = None
    vmax: float | None = None
    axes: bool = False

    def __post_init__(self):
        if not (isinstance(self.cut, (int, float)) and not isinstance(self.cut, bool)
                and 0 <= self.cut < 360):
            raise ValueError(f"cut must be an angle in [0, 360) degrees, got {self.cut!r}")
        v = self.view
        if not (isinstance(v, (tuple, list)) and len(v) == 2
                and all(isinstance(a, (int, float)) and math.isfinite(a) for a in v)):
            raise ValueError(f"view must be (elevation, azimuth) in degrees, got {v!r}")
        for name in ("vmin", "vmax"):
            x = getattr(self, name)
            if x is not None and not (isinstance(x, (int, float)) and math.isfinite(x)):
                raise ValueError(f"{name} must be a finite number or None, got {x!r}")
        if self.vmin is not None and self.vmax is not None and not self.vmin < self.vmax:
            raise ValueError(f"vmin must lie below vmax, got {self.vmin!r}, {self.vmax!r}")

    def angles(self, points: int) -> np.ndarray:
        """The angles drawn: the full circle less the sector of ``cut`` degrees centred on
        the camera's azimuth (the side that faces the viewer)."""
        mid, half = math.radians(self.view[1]), math.radians(self.cut) / 2
        count = max(8, int(round(points * (1 - self.cut / 360))) + 1)
        return np.linspace(mid + half, mid + 2 * math.pi - half, count)

    def colours(self, values):
        """(norm, colormap) for ``values``: the given range, else theirs, symmetric about
        zero with a diverging map where they take both signs."""
        import matplotlib
        from matplotlib.colors import Normalize

        finite = np.asarray(values)[np.isfinite(values)]
        lo = float(finite.min()) if finite.size else 0.0
        hi = float(finite.max()) if finite.size else 1.0
        diverging = self.vmin is None and self.vmax is None and lo < 0 < hi
        if diverging:
            lo, hi = -max(-lo, hi), max(-lo, hi)
        lo = lo if self.vmin is None else float(self.vmin)
        hi = hi if self.vmax is None else float(self.vmax)
        if hi <= lo:                    # a constant field: a band around it
            pad = max(abs(lo), 1.0) * 1e-9
            lo, hi = lo - pad, hi + pad
        cmap = self.cmap or ("coolwarm" if diverging else "viridis")
        return Normalize(lo, hi), (cmap if callable(cmap) else matplotlib.colormaps[cmap])


def _check_field(field, allowed: dict) -> None:
    """Refuse an unknown field before anything is computed."""
    if field not in allowed:
        raise ValueError(f"field must be one of {', '.join(allowed)}, got {field!r}")


def draw_surface(ax, surface: Surface, field: str, *, norm, cmap, look: Look = Look(),
                 colorbar: bool = True, title: str | None = None, box=None):
    """Draw ``surface`` on the 3D axes ``ax``, its faces coloured by ``field`` through
    ``norm`` and ``cmap`` (each face the mean of its four corners), the first and last
    columns as lines where a sector is cut away (the cut's meridians), the rows at the ends
    of the meridian as thin lines, one scale on the three axes over ``box`` ((low, high)
    corners; default the surface's).

    Arguments:
        look: the axes shown or not, the cut (:class:`Look`; the view is the caller's).
        colorbar: add a colour bar with the field's name and unit.
        title: the axes' title (default: the parameter's value, and the magnification
            where it is not 1).

    Returns:
        The ``ScalarMappable`` of the colours.

    Raises:
        ValueError: a field the surface does not have (the message names those it has).
    """
    import matplotlib

    values = surface.scalar(field)
    pts = surface.points
    if surface.periodic:             # close the ring
        pts = np.concatenate([pts, pts[:, :1]], axis=1)
        values = np.concatenate([values, values[:, :1]], axis=1)
    face = (values[:-1, :-1] + values[1:, :-1] + values[:-1, 1:] + values[1:, 1:]) / 4
    colours = np.zeros(values.shape + (4,))
    colours[:-1, :-1] = cmap(norm(face))
    X, Y, Z = pts[..., 0], pts[..., 1], pts[..., 2]
    ax.plot_surface(X, Y, Z, facecolors=colours, rstride=1, cstride=1, shade=False,
                    linewidth=0, antialiased=False)
    for i in (0, -1):                # the ends of the meridian: edges, or a pole's ring
        ax.plot(X[i], Y[i], Z[i], color="0.35", lw=0.6, zorder=9)
    if not surface.periodic and look.cut > 0:
        for j in (0, -1):
            ax.plot(X[:, j], Y[:, j], Z[:, j], color="k", lw=1.0, zorder=10)
    lo, hi = box if box is not None else (pts.reshape(-1, 3).min(axis=0),
                                          pts.reshape(-1, 3).max(axis=0))
    _box(ax, np.asarray(lo), np.asarray(hi), look.axes, surface.units.length_label)
    if title is None:
        what = "lobes" if "lobe_displacement" in surface.fields else "displacement"
        title = surface.parameter_text + (f", {what} x {surface.magnify:g}"
                                          if surface.magnify != 1 else "")
    ax.set_title(title, fontsize=9)
    mappable = matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)
    if colorbar:
        ax.figure.colorbar(mappable, ax=ax, shrink=0.6, pad=0.02).set_label(
            surface.label(field), fontsize=8)
    return mappable


def _box(ax, lo, hi, axes: bool, unit: str) -> None:
    """One scale on the three axes over the box [lo, hi]; the axes shown (labelled with
    the length unit) or hidden."""
    span = np.maximum(hi - lo, 1e-3 * float(np.max(hi - lo)))
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(span), zoom=ZOOM)
    if not axes:
        ax.set_axis_off()
        return
    for name, axis in zip("xyz", (ax.xaxis, ax.yaxis, ax.zaxis)):
        axis.set_label_text(f"{name} / {unit}" if unit == "R0" else f"{name} [{unit}]",
                            fontsize=7)
    ax.tick_params(labelsize=6)


def _axes3d(ax, look: Look):
    """``ax`` (3D axes), or new ones on a new figure; the view set."""
    if ax is None:
        import matplotlib.pyplot as plt

        fig = plt.figure(figsize=(6.0, 4.2), layout="constrained")
        ax = fig.add_subplot(projection="3d")
    if getattr(ax, "name", "") != "3d":
        raise ValueError("ax must be 3D axes (e.g. fig.add_subplot(projection='3d'))")
    ax.view_init(elev=look.view[0], azim=look.view[1])
    return ax


def _draw(surface, field, ax, look, colorbar, title):
    ax = _axes3d(ax, look)
    norm, cmap = look.colours(surface.scalar(field))
    draw_surface(ax, surface, field, norm=norm, cmap=cmap, look=look, colorbar=colorbar,
                 title=title)
    return ax


def plot3d(eq, field: str = "normal_displacement", ax=None, *, cut: float = 90.0,
           magnify: float = 1.0, view=Look.view, cmap=None, vmin=None, vmax=None,
           axes: bool = False, units: OutputUnits | None = None, colorbar: bool = True,
           title: str | None = None):
    """The deformed surface of the axisymmetric equilibrium ``eq`` in 3D, a sector cut
    away, coloured by ``field`` (module docstring).

    Arguments:
        eq: a converged :class:`shellbvp.Equilibrium`.
        field: one of :data:`shellbvp.surface.EQUILIBRIUM_FIELDS` (normal_displacement,
            displacement, radial_displacement, axial_displacement, eps11, eps22, k1, k2, N1,
            N2, moment, thickness, g1, g2, kb1, kb2).
        ax: 3D axes to draw on (default new ones).
        cut, view, cmap, vmin, vmax, axes: how it is drawn (:class:`Look`).
        magnify: draw the displacement from the reference this many times (the colours
            stay the state's).
        units: :class:`shellbvp.surface.OutputUnits` (default the engine's: R0, mu* h).
        colorbar, title: a colour bar with the field and its unit; the title (default the
            parameter's value).

    Returns:
        The 3D axes.

    Raises:
        ValueError: an unknown field (the message names the allowed ones), bad arguments.
    """
    _check_field(field, EQUILIBRIUM_FIELDS)
    look = Look(cut, view, cmap, vmin, vmax, axes)
    surface = equilibrium_surface(eq, omega=look.angles(POINTS), magnify=magnify,
                                  units=units)
    return _draw(surface, field, ax, look, colorbar, title)


def _lobed_points(f) -> int:
    return max(POINTS, 16 * f.K * f.n)


def plot_lobed3d(f, U, p, field: str = "lobe_normal_displacement", ax=None, *,
                 cut: float = 90.0, magnify: float = 1.0, view=Look.view, cmap=None,
                 vmin=None, vmax=None, axes: bool = False, units: OutputUnits | None = None,
                 colorbar: bool = True, title: str | None = None):
    """:func:`plot3d` for a lobed state: the state U of the 2D discretisation ``f`` at the
    parameter p (:func:`shellbvp.surface.lobed_surface`; a point of a
    :class:`shellbvp.LobedBranch` through :meth:`shellbvp.LobedBranch.plot3d`).
    ``field``: one of :data:`shellbvp.surface.LOBED_FIELDS` (default the normal
    displacement of the lobes, the harmonics k >= n); ``magnify``: of the lobes."""
    _check_field(field, LOBED_FIELDS)
    look = Look(cut, view, cmap, vmin, vmax, axes)
    surface = lobed_surface(f, U, p, omega=look.angles(_lobed_points(f)), magnify=magnify,
                            units=units)
    return _draw(surface, field, ax, look, colorbar, title)


# --- animations ----------------------------------------------------------------------------
def frame_indices(position, frames: int) -> np.ndarray:
    """Up to ``frames`` indices of points, evenly spaced in ``position`` (increasing, e.g.
    the branch's arclength), the first and the last among them, each point at most once."""
    x = np.asarray(position, dtype=float)
    if x.size <= frames:
        return np.arange(x.size)
    targets = np.linspace(x[0], x[-1], frames)
    return np.unique(np.clip(np.searchsorted(x, targets), 0, x.size - 1))


def _writer(path, frames, fps, dpi) -> str:
    """The format's writer, refused before anything is computed: an unknown suffix, a
    missing ffmpeg for MP4, bad counts."""
    suffix = Path(path).suffix.lower()
    if suffix not in FORMATS:
        raise ValueError(f"path must end in one of {', '.join(FORMATS)} (the format), got "
                         f"{str(path)!r}")
    if not (isinstance(frames, (int, np.integer)) and frames >= 2):
        raise ValueError(f"frames must be an integer >= 2, got {frames!r}")
    for name, v in (("fps", fps), ("dpi", dpi)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a positive number, got {v!r}")
    writer = FORMATS[suffix]
    if writer == "ffmpeg":
        import matplotlib

        exe = matplotlib.rcParams["animation.ffmpeg_path"]
        if shutil.which(exe) is None:
            raise RuntimeError(f"writing {Path(path).name} (MP4) needs ffmpeg, which was not "
                               f"found ({exe!r} is not on PATH): install ffmpeg, or write "
                               f"a GIF instead ({Path(path).with_suffix('.gif').name})")
    return writer


def _progress(progress, total: int) -> tuple[Callable, Callable]:
    """(tick(), close()) of a progress report: a tqdm bar on stderr where ``progress`` is
    None (shown only when stderr is a terminal) or True, nothing for False, else
    ``progress(done, total)`` called after every frame."""
    if callable(progress):
        done = iter(range(1, total + 1))
        return (lambda: progress(next(done), total)), (lambda: None)
    if progress is False:
        return (lambda: None), (lambda: None)
    import sys

    from tqdm import tqdm

    bar = tqdm(total=total, desc="animation", unit="frame", file=sys.stderr,
               disable=None if progress is None else False, leave=False)
    return (lambda: bar.update(1)), bar.close


@dataclass(frozen=True)
class _Movie:
    """What an animation draws: a surface per frame, the diagram (x, y) with its folds and
    the frame's point, and the diagram's axis labels."""

    surfaces: list
    curve: tuple
    marks: list
    folds: list
    xlabel: str
    ylabel: str


def _write(path, movie: _Movie, field: str, look: Look, *, fps, dpi, progress, writer):
    """Draw ``movie`` frame by frame (one colour scale, one box) and write it to ``path``
    atomically."""
    import matplotlib.pyplot as plt
    from matplotlib.animation import FFMpegWriter, FuncAnimation, PillowWriter

    from .cache import atomic_write

    surfaces = movie.surfaces
    norm, cmap = look.colours(np.concatenate([s.scalar(field).ravel() for s in surfaces]))
    box = (np.min([s.points.reshape(-1, 3).min(axis=0) for s in surfaces], axis=0),
           np.max([s.points.reshape(-1, 3).max(axis=0) for s in surfaces], axis=0))
    fig = plt.figure(figsize=(9.0, 4.0))
    grid = fig.add_gridspec(1, 2, width_ratios=(1.5, 1.0), left=0.0, right=0.97,
                            bottom=0.14, top=0.9, wspace=0.2)
    ax3 = fig.add_subplot(grid[0], projection="3d")
    ax2 = fig.add_subplot(grid[1])
    ax2.plot(*movie.curve, "-", lw=1.2, color="C0")
    for x, y in movie.folds:
        ax2.plot(x, y, "o", ms=4, color="C0")
    mark, = ax2.plot([], [], "o", ms=8, color="C3")
    ax2.set_xlabel(movie.xlabel)
    ax2.set_ylabel(movie.ylabel)
    fig.colorbar(_mappable(norm, cmap), ax=ax3, shrink=0.6, pad=0.0).set_label(
        surfaces[0].label(field), fontsize=8)
    tick, close = _progress(progress, len(surfaces))
    # the parameter's round-off about zero (the first point of a branch from p = 0) as 0
    span = max(abs(s.p) for s in surfaces)
    titles = [replace(s, p=s.p if abs(s.p) > 1e-12 * span else 0.0).parameter_text
              for s in surfaces]

    def draw(k):
        ax3.cla()
        ax3.view_init(elev=look.view[0], azim=look.view[1])
        draw_surface(ax3, surfaces[k], field, norm=norm, cmap=cmap, look=look,
                     colorbar=False, box=box, title=titles[k])
        mark.set_data([movie.marks[k][0]], [movie.marks[k][1]])
        return []

    def save(tmp):        # the animation made once its file can be
        out = PillowWriter(fps=fps) if writer == "pillow" else FFMpegWriter(fps=fps)
        FuncAnimation(fig, draw, frames=len(surfaces), blit=False).save(
            str(tmp), writer=out, dpi=dpi, progress_callback=lambda i, n: tick())

    try:
        atomic_write(path, save, keep_suffix=True)
    finally:
        close()
        plt.close(fig)


def _mappable(norm, cmap):
    import matplotlib

    return matplotlib.cm.ScalarMappable(norm=norm, cmap=cmap)


def _parameter_label(name: str, units: OutputUnits | None, column: str) -> str:
    if units is None:
        return column
    return f"{name} [{units.parameter_label}]" if units.parameter_label else name


def animate(branch, path, *, field: str = "normal_displacement", frames: int = 60,
            fps: float = 12, cut: float = 90.0, magnify: float = 1.0, view=Look.view,
            cmap=None, vmin=None, vmax=None, axes: bool = False, dpi: float = 80,
            units: OutputUnits | None = None, progress=None) -> None:
    """Write an animation of ``branch`` (a :class:`shellbvp.Branch`) to ``path``: its
    states in 3D (:func:`plot3d`; one colour scale and one box for all frames) beside the
    parameter against the monitor w, the current point marked.

    Arguments:
        path: a ``.gif`` (written with Pillow) or ``.mp4`` (needs ffmpeg) file, written
            atomically (nothing is left at ``path`` or beside it on an error).
        field, cut, magnify, view, cmap, vmin, vmax, axes, units: as for :func:`plot3d`.
        frames: at most this many frames, at points evenly spaced in the branch's
            arclength (every point where it has fewer).
        fps, dpi: frames per second, and the frames' resolution (dots per inch of a 9 x 4
            inch figure).
        progress: None: a progress bar (tqdm) on stderr when it is a terminal; False:
            none; True: always; a callable: called as ``progress(done, frames)``.

    Raises:
        ValueError: an unknown field or format (the message names the allowed ones), a
            branch without states, bad arguments.
        RuntimeError: an MP4 without ffmpeg (the message says to write a GIF instead).
        OSError: ``path`` cannot be written.
    """
    _check_field(field, EQUILIBRIUM_FIELDS)
    writer = _writer(path, frames, fps, dpi)
    look = Look(cut, view, cmap, vmin, vmax, axes)
    if not branch.points:
        raise ValueError("branch has no states to draw (a branch of shellbvp.follow keeps "
                         "them)")
    idx = frame_indices(branch.arclength, int(frames))
    angles = look.angles(POINTS)
    surfaces = [equilibrium_surface(branch.equilibrium(int(i), energies=False), omega=angles,
                                    magnify=magnify, units=units) for i in idx]
    u = surfaces[0].units
    L, P = u.length, u.parameter_scale
    movie = _Movie(surfaces, (branch.w * L, branch.p * P),
                   [(branch.w[i] * L, branch.p[i] * P) for i in idx],
                   [(f.w * L, f.p * P) for f in branch.folds],
                   f"w / {u.length_label}" if units is None else f"w [{u.length_label}]",
                   _parameter_label(surfaces[0].parameter, units,
                                    branch.scene.parameter_column))
    _write(path, movie, field, look, fps=fps, dpi=dpi, progress=progress, writer=writer)


def animate_lobed(lobed, path, *, field: str = "lobe_normal_displacement", frames: int = 60,
                  fps: float = 12, cut: float = 90.0, magnify: float = 1.0, view=Look.view,
                  cmap=None, vmin=None, vmax=None, axes: bool = False, dpi: float = 80,
                  units: OutputUnits | None = None, progress=None) -> None:
    """:func:`animate` for a :class:`shellbvp.LobedBranch`: its lobed states (frames evenly
    spaced in the point index) beside the parameter against the critical mode's amplitude.
    ``field``: one of :data:`shellbvp.surface.LOBED_FIELDS`; ``magnify``: of the lobes."""
    _check_field(field, LOBED_FIELDS)
    writer = _writer(path, frames, fps, dpi)
    look = Look(cut, view, cmap, vmin, vmax, axes)
    f = lobed.discretisation
    if f is None or not lobed.states:
        raise ValueError("lobed has no states to draw")
    idx = frame_indices(np.arange(len(lobed.states)), int(frames))
    angles = look.angles(_lobed_points(f))
    surfaces = [lobed_surface(f, lobed.states[i], lobed.p[i], omega=angles,
                              magnify=magnify, units=units) for i in idx]
    P = surfaces[0].units.parameter_scale
    a, p = np.asarray(lobed.amplitude), np.asarray(lobed.p) * P
    movie = _Movie(surfaces, (a, p), [(a[i], p[i]) for i in idx],
                   [(fo.amplitude, fo.p * P) for fo in lobed.folds],
                   "amplitude of the critical mode (mass norm)",
                   _parameter_label(surfaces[0].parameter, units, lobed.parameter))
    _write(path, movie, field, look, fps=fps, dpi=dpi, progress=progress, writer=writer)
