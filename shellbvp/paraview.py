"""ParaView files of states and branches: the surface of a state as a VTK unstructured grid
of quadrilaterals (through meshio), a branch as a ParaView collection (``.pvd``) of one
such file per point.

A state's file (:func:`write_surface`) holds the surface of :mod:`shellbvp.surface` on a
closed ring in omega: its points (x, y, z), one quad per cell of the (s, omega) grid (the
last column joined to the first), and as point data every field of the state (vectors with
their three Cartesian components: ``displacement``, for a lobed state
``lobe_displacement``; in single precision, the points in double), the reference arclength
``s``, the angle ``omega``, and the parameter's value (an array named after it, constant).
``.vtu`` (XML) or ``.vtk`` (legacy) by the suffix.

A branch (:func:`write_branch`, :func:`write_lobed_branch`) is a folder of ``NAME_0000.vtu``,
... and ``NAME.pvd`` that lists them with their time: the parameter where it is strictly
monotonic along the branch, else (a branch through a fold, where ParaView, which orders a
collection by its times, would interleave the two sides) the point's index, the parameter
still in every file; ``time=`` chooses.

Every file is written atomically (:func:`shellbvp.cache.atomic_write`); a branch's files
first, its ``.pvd`` last, and on an error the files this call wrote are removed again: a
folder never holds a half-written file or a collection of a partial branch.

meshio is imported here only, when a file is asked for.
"""

from __future__ import annotations

import os
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from .cache import atomic_write, atomic_write_text
from .surface import OutputUnits, Surface, equilibrium_surface, lobed_surface

__all__ = ["write_surface", "write_equilibrium", "write_branch", "write_lobed_branch",
           "write_collection", "collection_times", "RING", "SUFFIXES", "TIMES"]

#: the angles of a file's ring in omega (a lobed state: at least 16 per wave)
RING = 64
#: the fields' precision in a file (the points keep double precision): single, as
#: ParaView draws them, halves the bytes to compress, the larger part of a file's cost
FIELD_DTYPE = np.float32
#: the formats, by suffix, as meshio names them
SUFFIXES = {".vtu": "vtu", ".vtk": "vtk"}
#: what a collection's time may be
TIMES = ("auto", "parameter", "index")


def _format(path) -> str:
    suffix = Path(path).suffix.lower()
    if suffix not in SUFFIXES:
        raise ValueError(f"path must end in one of {', '.join(SUFFIXES)} (the format), got "
                         f"{str(path)!r}")
    return SUFFIXES[suffix]


def _cells(ns: int, nw: int) -> np.ndarray:
    """(ns - 1) nw quads of the closed grid, points numbered i nw + j, counterclockwise
    seen from the outside of a shell traced from its top pole ((s, omega) order)."""
    i, j = np.meshgrid(np.arange(ns - 1), np.arange(nw), indexing="ij")
    jn = (j + 1) % nw
    return np.stack([i * nw + j, (i + 1) * nw + j, (i + 1) * nw + jn, i * nw + jn],
                    axis=-1).reshape(-1, 4).astype(np.int32)


def write_surface(surface: Surface, path) -> None:
    """Write ``surface`` (a closed ring in omega) to ``path`` (module docstring).

    Raises:
        ValueError: a surface that is not a closed ring, a suffix other than ``.vtu`` or
            ``.vtk``.
        OSError: ``path`` cannot be written (nothing is left there).
    """
    import meshio

    fmt = _format(path)
    if not surface.periodic:
        raise ValueError("the surface must be a closed ring in omega (omega a number of "
                         "angles) to be written as a file")
    ns, nw = surface.points.shape[:2]
    data = {name: (v.reshape(ns * nw, 3) if v.ndim == 3 else v.reshape(ns * nw))
            .astype(FIELD_DTYPE) for name, v in surface.fields.items()}
    data["s"] = np.repeat(surface.s, nw).astype(FIELD_DTYPE)
    data["omega"] = np.tile(surface.omega, ns).astype(FIELD_DTYPE)
    # the parameter as a constant array (meshio writes no field data to .vtu), in double
    # precision: the one value that tells the files of a branch apart
    data[surface.parameter if surface.parameter not in data else "parameter"] = \
        np.full(ns * nw, surface.p)
    atomic_write(path, lambda tmp: meshio.write_points_cells(
        str(tmp), surface.points.reshape(ns * nw, 3), [("quad", _cells(ns, nw))],
        point_data=data, file_format=fmt))


def write_equilibrium(eq, path, *, omega: int = RING, units: OutputUnits | None = None) -> None:
    """Write the surface of the equilibrium ``eq`` (:func:`shellbvp.surface.
    equilibrium_surface` on a ring of ``omega`` angles) to ``path``, in ``units`` (default
    the engine's; a scene file's: :meth:`shellbvp.surface.OutputUnits.of`).

    Raises:
        ValueError: bad arguments, an unknown suffix (before anything is written).
        OSError: ``path`` cannot be written.
    """
    _format(path)
    write_surface(equilibrium_surface(eq, omega=_ring(omega), units=units), path)


def _ring(omega) -> int:
    if not (isinstance(omega, (int, np.integer)) and not isinstance(omega, bool)
            and omega >= 3):
        raise ValueError(f"omega must be a number of angles >= 3, got {omega!r}")
    return int(omega)


def collection_times(p, time: str = "auto") -> tuple[np.ndarray, str]:
    """The times of a collection of points whose parameter takes the values p, and what
    they are (``"parameter"`` or ``"index"``; ``time``: module docstring)."""
    if time not in TIMES:
        raise ValueError(f"time must be one of {', '.join(TIMES)}, got {time!r}")
    p = np.asarray(p, dtype=float)
    d = np.diff(p)
    monotonic = bool(np.all(d > 0) or np.all(d < 0))
    if time == "parameter" or (time == "auto" and monotonic):
        return p, "parameter"
    return np.arange(p.size, dtype=float), "index"


def write_collection(folder, name: str, files, times, *, note: str = "") -> Path:
    """Write ``folder/name.pvd``: the ParaView collection of ``files`` (names in
    ``folder``) at ``times``, atomically; ``note`` a comment in its head. Returns its
    path."""
    rows = "\n".join(f'    <DataSet timestep="{float(t)!r}" group="" part="0" '
                     f"file={quoteattr(str(f))}/>" for f, t in zip(files, times))
    comment = f"<!-- {note.replace('--', '-')} -->\n" if note else ""
    text = ('<?xml version="1.0"?>\n' + comment
            + '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">\n'
            "  <Collection>\n" + rows + "\n  </Collection>\n</VTKFile>\n")
    path = Path(folder) / f"{name}.pvd"
    atomic_write_text(path, text)
    return path


def _check_name(name) -> str:
    if not (isinstance(name, str) and name and name == os.path.basename(name)
            and not name.startswith(".")):
        raise ValueError(f"name must be a plain file name (no folder), got {name!r}")
    return name


def _series(folder, name, surfaces, p, time, what) -> Path:
    """Write each surface of the iterable ``surfaces`` as ``name_NNNN.vtu`` and then the
    collection; on an error remove the files written (and the folder where this call
    made it)."""
    folder = Path(folder)
    made = not folder.exists()
    written = []
    try:
        for k, surface in enumerate(surfaces):
            path = folder / f"{name}_{k:04d}.vtu"
            write_surface(surface, path)
            written.append(path)
        times, kind = collection_times(p, time)
        note = (f"shellbvp: {what}, {len(written)} points; time = the parameter"
                if kind == "parameter" else
                f"shellbvp: {what}, {len(written)} points; time = the point's index (the "
                f"parameter is not monotonic along the branch: it is an array of each file)")
        written.append(write_collection(folder, name, [w.name for w in written], times,
                                        note=note))
    except BaseException:
        for w in written:
            w.unlink(missing_ok=True)
        if made and folder.is_dir() and not any(folder.iterdir()):
            folder.rmdir()
        raise
    return written[-1]


def write_branch(branch, folder, *, name: str = "branch", omega: int = RING,
                 units: OutputUnits | None = None, time: str = "auto",
                 progress=None) -> Path:
    """Write every point of ``branch`` (a :class:`shellbvp.Branch`) as a VTK file in
    ``folder`` and their ParaView collection ``folder/name.pvd`` (module docstring).

    Arguments:
        name: the files' stem.
        omega: the angles of each ring.
        units: :class:`shellbvp.surface.OutputUnits` (default the engine's).
        time: ``"auto"`` (the parameter where monotonic, else the index), ``"parameter"``
            or ``"index"``.
        progress: called as ``progress(done, points)`` after every file.

    Returns:
        The path of the ``.pvd``.

    Raises:
        ValueError: bad arguments, a branch without states (before anything is written).
        OSError: the folder cannot be written (nothing of the branch is left there).
    """
    _check_name(name)
    omega = _ring(omega)
    collection_times(branch.p, time)
    if not branch.points:
        raise ValueError("branch has no states to write (a branch of shellbvp.follow keeps "
                         "them)")
    total = len(branch.points)

    def surfaces():
        for k in range(total):
            yield equilibrium_surface(branch.equilibrium(k, energies=False), omega=omega,
                                      units=units)
            if progress is not None:
                progress(k + 1, total)

    return _series(folder, name, surfaces(), branch.p * _scale(units), time,
                   f"branch of {_parameter(units, branch.scene.parameter)}")


def write_lobed_branch(lobed, folder, *, name: str = "lobed", omega: int | None = None,
                       units: OutputUnits | None = None, time: str = "auto",
                       progress=None) -> Path:
    """:func:`write_branch` for a :class:`shellbvp.LobedBranch`: every lobed state's
    surface (:func:`shellbvp.surface.lobed_surface`, ``omega`` angles per ring, default at
    least 16 per wave of the highest harmonic) and the collection ``folder/name.pvd``."""
    _check_name(name)
    f = lobed.discretisation
    if f is None or not lobed.states:
        raise ValueError("lobed has no states to write")
    omega = max(RING, 16 * f.K * f.n) if omega is None else _ring(omega)
    collection_times(lobed.p, time)
    total = len(lobed.states)

    def surfaces():
        for k, (U, p) in enumerate(zip(lobed.states, lobed.p)):
            yield lobed_surface(f, U, p, omega=omega, units=units)
            if progress is not None:
                progress(k + 1, total)

    return _series(folder, name, surfaces(), np.asarray(lobed.p) * _scale(units), time,
                   f"lobed branch (n = {lobed.n}) of {_parameter(units, lobed.parameter)}")


def _scale(units) -> float:
    return 1.0 if units is None else units.parameter_scale


def _parameter(units, name: str) -> str:
    """The parameter's name in ``units`` (a scene file's), else the engine's."""
    return units.parameter if units is not None and units.parameter else name
