"""Scene files: a shell of revolution written as a TOML file, read into a runnable scene.

A user's shell is data, not a script: its meridian (segments), thickness, material,
parameter range, stimulus, loads, ends and the observables to report are keys of a TOML
file (the format is stated key by key in ``docs/scene-files.md``). :func:`load_scene` reads
one into a :class:`SceneFile`: the engine's :class:`shellbvp.Scene` in internal units, the
run settings and the conversions back to the file's units. :meth:`SceneFile.follow`
continues it and reports the observables at every point and fold; the command line
(``shellbvp follow FILE``, ``shellbvp stability FILE``) runs the same.

Expressions (the stimulus, a thickness profile, the pressure, the line loads) go through
:func:`shellbvp.expressions.parse` only, a whitelist parser: a scene file is never run as
Python. Every problem with a file is a :class:`ValueError` of one line that starts with the
key, e.g. ``geometry.segments[1].radius: must be > 0, got -1``.

Units. The file's lengths and moduli are the user's own, in any units used consistently
(metres and pascals, millimetres and N/mm^2, ...). Internally lengths are scaled by
L = :attr:`shellbvp.geometry.Meridian.size` of the file's meridian (its largest r or its
extent in z), stresses by the shear modulus mu (Koiter: mu = E / (2 (1 + nu)); cg, nh: mu
as given) and energies by mu h L^2. With h the thickness in the file's units (its largest
value along the meridian where it varies), a quantity of the file becomes inside:

- a length (geometry, s, breaks) or the thickness: length / L;
- a target curvature kb1, kb2 (1/length): kb L;
- rhob1, rhob2 (1/length), rhob3 (1/length^2): rhob1, rhob2 L, rhob3 L^2;
- the modulus lam (cg): lam / mu;
- a pressure p (force/length^2): P = p L / (mu h);
- a line force q (force/length): q / (mu h);
- a line moment m (force length/length): m / (mu h L);
- a point force F (force), a ring's total force: F / (mu h L); a pole's prescribed
  displacement: d / L;
- an energy E (modulus length^3 = force length): E / (mu h L^2).

Expressions are evaluated in the file's units: they see s, r, z, k1_ref, k2_ref as the
file measures them (the engine's s L, r L, z L, k1 / L, k2 / L) and the parameter p = P t,
and their values are converted as above. Results come
back in the file's units: displacements in its length unit, rotations in radians
(counterclockwise in the (r, z) plane positive), energies in modulus x length^3
(= force x length), the parameter and its error estimates in the parameter's own units.

The parameter p runs from ``from`` to ``to``; the engine follows t = p / P instead, P the
power of ten nearest |to - from| (with its sign), so that t changes by about one over the
range whatever the parameter's size (a pressure of 1e-6 E) and the continuation's steps and
fold tolerances are well scaled: solver messages name it ``t_<name>``. P depends on the
range's size only, so that a file whose range is edited keeps its compiled programs.

The functions built from a file's expressions carry a ``cache_key`` (the canonical form of
their expressions and every number they close over), so that the compiled programs of a
scene file are kept on disk and a second run in a new process loads them
(:func:`shellbvp.kernels.disk_key`).
"""

from __future__ import annotations

import csv
import io
import keyword
import math
import re
import tomllib
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Callable, NamedTuple

import numpy as np

from .expressions import CONSTANTS, FUNCTIONS, Expression, parse
from .geometry import Cone, Cylinder, Ellipse, Meridian, Plate, Points, Sphere, Torus
from .models import MODELS
from .scene import END_KINDS, H_MIN, LOADS_OF, Display, End, Ring, Scene, curvature_radius

__all__ = ["load_scene", "SceneFile", "SceneBranch", "SceneInstability", "Observable",
           "Units", "PointFunction", "LoadFunction", "example", "examples", "METHOD_NAMES"]

#: the methods a file may name ([solver] method)
METHOD_NAMES = ("spectral", "collocation", "shooting", "energy")
#: the fold tolerance, relative to |to - from|, where [solver] tol is not given
DEFAULT_RELATIVE_TOL = 1e-9
#: samples per segment at which a thickness profile and the stimulus are checked on loading
CHECK_SAMPLES = 129
#: the names an expression of the reference point may use besides the parameter's
POINT_SYMBOLS = ("s", "r", "z", "k1_ref", "k2_ref")
#: the keys of the file's top level
TOP_KEYS = ("title", "units", "geometry", "material", "parameter", "solver", "stimulus",
            "loads", "ends", "observe")
#: the column and JSON names an observable may not take (nor any ending in ``_error``, the
#: error estimate columns)
RESERVED = ("p", "error_estimate", "is_fold", "is_requested", "energy")
_MISSING = object()


# --------------------------------------------------------------------------- reading keys

def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def _is_number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool)


class _Table:
    """A TOML table read key by key: every value fetched is checked, and :meth:`done`
    refuses the keys that were not (a misspelt key is an error, never ignored)."""

    def __init__(self, data, key: str, allowed: tuple):
        if not isinstance(data, dict):
            raise ValueError(f"{key}: expected a table of keys ({', '.join(allowed)}), got "
                             f"{_describe(data)}")
        self.data, self.key, self.allowed = data, key, tuple(allowed)
        for name in data:
            if name not in self.allowed:
                raise ValueError(f"{self.at(name)}: unknown key; allowed: "
                                 f"{', '.join(self.allowed)}")

    def at(self, name: str) -> str:
        return f"{self.key}.{name}" if self.key else name

    def __contains__(self, name):
        return name in self.data

    def raw(self, name, default=_MISSING):
        if name in self.data:
            return self.data[name]
        if default is _MISSING:
            raise ValueError(f"{self.at(name)}: missing (required)")
        return default

    def number(self, name, default=_MISSING, *, positive=False, nonnegative=False) -> float:
        value = self.raw(name, default)
        if not _is_number(value) or not math.isfinite(float(value)):
            raise ValueError(f"{self.at(name)}: expected a finite number, got "
                             f"{_describe(value)}")
        value = float(value)
        if positive and not value > 0:
            raise ValueError(f"{self.at(name)}: must be > 0, got {value:g}")
        if nonnegative and value < 0:
            raise ValueError(f"{self.at(name)}: must be >= 0, got {value:g}")
        return value

    def numbers(self, name, *, length=None, minimum=None) -> tuple:
        value = self.raw(name)
        what = f"a list of {length} numbers" if length else "a list of numbers"
        if not isinstance(value, list) or not all(_is_number(v) and math.isfinite(float(v))
                                                  for v in value):
            raise ValueError(f"{self.at(name)}: expected {what}, got {_describe(value)}")
        if length is not None and len(value) != length:
            raise ValueError(f"{self.at(name)}: expected {what}, got {len(value)}")
        if minimum is not None and len(value) < minimum:
            raise ValueError(f"{self.at(name)}: expected at least {minimum} numbers, got "
                             f"{len(value)}")
        return tuple(float(v) for v in value)

    def string(self, name, default=_MISSING, *, choices=None) -> str:
        value = self.raw(name, default)
        if not isinstance(value, str):
            raise ValueError(f"{self.at(name)}: expected a string, got {_describe(value)}")
        if choices is not None and value not in choices:
            raise ValueError(f"{self.at(name)}: must be one of {', '.join(choices)}, got "
                             f"{value!r}")
        return value

    def table(self, name, allowed, *, required=False) -> "_Table":
        return _Table(self.raw(name, _MISSING if required else {}), self.at(name), allowed)


def _describe(value) -> str:
    kind = {bool: "a boolean", str: "a string", list: "a list", dict: "a table",
            int: "a number", float: "a number"}.get(type(value), type(value).__name__)
    text = repr(value)
    return f"{kind} {text if len(text) <= 40 else text[:37] + '...'}"


# --------------------------------------------------------------------------- geometry

def _segment(entry, key: str, scale: float):
    """The segment of one ``geometry.segments`` entry, its lengths divided by ``scale``."""
    if not isinstance(entry, dict):
        raise ValueError(f"{key}: expected an inline table such as {{ type = \"plate\", "
                         f"r = [0.0, 1.0], z = 0.0 }}, got {_describe(entry)}")
    kind = entry.get("type", _MISSING)
    if kind is _MISSING:
        raise ValueError(f"{key}.type: missing (one of {', '.join(SEGMENTS)})")
    if kind not in SEGMENTS:
        raise ValueError(f"{key}.type: unknown segment type {kind!r}; allowed: "
                         f"{', '.join(SEGMENTS)}")
    build, keys = SEGMENTS[kind]
    t = _Table(entry, key, ("type", *keys))
    try:
        return build(t, scale)
    except ValueError as exc:
        message = str(exc)
        if message.startswith(key):
            raise
        raise ValueError(f"{key}: {_one_line(message)}") from None


def _angle_pair(t):
    return t.numbers("angle", length=2)


def _plate(t, k):
    r = t.numbers("r", length=2)
    for v in r:
        if v < 0:
            raise ValueError(f"{t.at('r')}: must be >= 0 (the half-plane of the meridian), "
                             f"got {v:g}")
    return Plate((r[0] / k, r[1] / k), t.number("z", 0.0) / k)


def _cylinder(t, k):
    z = t.numbers("z", length=2)
    return Cylinder(t.number("radius", positive=True) / k, (z[0] / k, z[1] / k))


def _cone(t, k):
    a, b = t.numbers("from", length=2), t.numbers("to", length=2)
    return Cone((a[0] / k, a[1] / k), (b[0] / k, b[1] / k))


def _sphere(t, k):
    return Sphere(t.number("radius", positive=True) / k, t.number("centre_z", 0.0) / k,
                  angle=_angle_pair(t))


def _torus(t, k):
    return Torus(t.number("centre_radius", nonnegative=True) / k,
                 t.number("tube_radius", positive=True) / k, t.number("centre_z", 0.0) / k,
                 angle=_angle_pair(t))


def _ellipse(t, k):
    return Ellipse(t.number("semi_r", positive=True) / k,
                   t.number("semi_z", positive=True) / k, t.number("centre_z", 0.0) / k,
                   angle=_angle_pair(t))


def _points(t, k):
    r, z = t.numbers("r", minimum=4), t.numbers("z", minimum=4)
    if len(r) != len(z):
        raise ValueError(f"{t.at('z')}: expected as many numbers as r ({len(r)}), got "
                         f"{len(z)}")
    return Points(tuple(v / k for v in r), tuple(v / k for v in z))


#: segment type -> (builder, its keys besides type)
SEGMENTS = {
    "plate": (_plate, ("r", "z")),
    "cylinder": (_cylinder, ("radius", "z")),
    "cone": (_cone, ("from", "to")),
    "sphere": (_sphere, ("radius", "centre_z", "angle")),
    "torus": (_torus, ("centre_radius", "tube_radius", "centre_z", "angle")),
    "ellipse": (_ellipse, ("semi_r", "semi_z", "centre_z", "angle")),
    "points": (_points, ("r", "z")),
}


def _meridian(entries, scale: float) -> Meridian:
    segments = tuple(_segment(e, f"geometry.segments[{i}]", scale)
                     for i, e in enumerate(entries))
    try:
        return Meridian(segments)
    except ValueError as exc:
        raise ValueError(f"geometry.segments: {_one_line(exc)}") from None


# --------------------------------------------------------------------------- functions

@dataclass(frozen=True)
class Units:
    """The conversions between a scene file's units and the engine's.

    Attributes:
        length: L, the file's length that is 1 inside the engine (the meridian's size).
        modulus: mu, the shear modulus in the file's units (the engine's unit of stress).
        thickness: h, the reference thickness in the file's units (the largest value of a
            thickness profile).
        length_label, modulus_label, parameter_label: the names of the file's units for
            column names (``[units] length``, ``[units] modulus``, ``[parameter] unit``).
    """

    length: float
    modulus: float
    thickness: float
    length_label: str = "length"
    modulus_label: str = "modulus"
    parameter_label: str = ""

    @property
    def pressure(self) -> float:
        """The engine's unit of pressure, mu h / L, in the file's units."""
        return self.modulus * self.thickness / self.length

    @property
    def line_force(self) -> float:
        """The engine's unit of a line force (force per length), mu h."""
        return self.modulus * self.thickness

    @property
    def point_force(self) -> float:
        """The engine's unit of a point force, mu h L."""
        return self.modulus * self.thickness * self.length

    @property
    def line_moment(self) -> float:
        """The engine's unit of a line moment (moment per length), mu h L."""
        return self.modulus * self.thickness * self.length

    @property
    def energy(self) -> float:
        """The engine's unit of energy, mu h L^2 (modulus x length^3)."""
        return self.modulus * self.thickness * self.length ** 2


@dataclass(frozen=True)
class _Parameter:
    """The map between the file's parameter p and the engine's t = p / scale, and the
    range of t (from, to), where a file's expressions are checked on loading (the range is
    not part of the functions' cache keys: a new range compiles nothing new)."""

    name: str
    scale: float
    ends: tuple = (0.0, 1.0)

    def user(self, t):
        return self.scale * t


def _array_module(*values):
    """numpy for host values, ``jax.numpy`` where one of them is a JAX array or tracer
    (the engine traces the fields inside its compiled programs)."""
    if all(isinstance(v, (np.ndarray, np.generic, float, int)) for v in values):
        return np
    import jax.numpy as jnp

    return jnp


class _KeyedFunction:
    """A function of a scene file, equal to another (and hashed) by its ``cache_key``: the
    engine keeps compiled programs by it, in memory and on disk."""

    cache_key: str

    def __eq__(self, other):
        return type(other) is type(self) and other.cache_key == self.cache_key

    def __hash__(self):
        return hash((type(self).__name__, self.cache_key))

    def __repr__(self):
        return f"{type(self).__name__}({self.cache_key!r})"


def _key_of(kind, expressions, factors, *numbers) -> str:
    body = "; ".join(f"{f!r}*{e.cache_key}" for e, f in zip(expressions, factors))
    return f"shellbvp.scenefile.{kind}({body} | {' '.join(map(repr, numbers))})"


#: how far inside its piece an expression sees a point at an interface, in meridian lengths
#: (:class:`PointFunction`): well above the rounding of s and of a break's position, well
#: below any resolution (a smooth field moves by ~1e-12 of its scale there)
INSIDE = 1e-12


@dataclass(frozen=True, eq=False, repr=False)
class PointFunction(_KeyedFunction):
    """Expressions of a reference point x (and of the parameter), in the file's units,
    converted to the engine's: ``f(x, t)`` -> a tuple of values (the stimulus fields), or
    ``f(x)`` -> one value (``single``: the thickness profile, which sees no parameter).

    Each expression sees s, r, z times ``length``, k1_ref and k2_ref over it, and the
    parameter p = scale t; its value is multiplied by its factor. Evaluated with
    ``jax.numpy`` where the engine traces it, numpy elsewhere.

    ``piece_ends`` (the scene's, internal units; set once the scene's interfaces are
    known): on piece i the expressions see s held inside [a_i + d, b_i - d] at an interior
    interface (d = ``INSIDE`` times the meridian's length), so that a step written in s at
    a break, ``where(s < X, ...)``, takes on each piece that piece's side, whatever the
    comparison and the rounding of X (its node at the interface sees the interface from
    inside, as the multi-point problem has it).
    """

    expressions: tuple
    factors: tuple
    length: float
    parameter: _Parameter
    single: bool = False
    piece_ends: tuple = ()
    cache_key: str = field(init=False)

    def __post_init__(self):
        p = self.parameter
        object.__setattr__(self, "cache_key", _key_of(
            "point" if not self.single else "profile", self.expressions, self.factors,
            self.length, p.name, p.scale, *self.piece_ends))

    def _inside(self, x, xp):
        """x.s held inside its piece (:attr:`piece_ends`; unchanged without them, or at the
        meridian's own ends)."""
        ends = self.piece_ends
        if not ends or not isinstance(x.piece, (int, np.integer)):
            return x.s
        i, d = int(x.piece), INSIDE * (ends[-1] - ends[0])
        lo = ends[i] + d if i > 0 else -np.inf
        hi = ends[i + 1] - d if i < len(ends) - 2 else np.inf
        return xp.clip(x.s, lo, hi)

    def __call__(self, x, t=0.0):
        L = self.length
        xp = _array_module(x.s, x.r, x.z, x.k1, x.k2, t)
        env = {"s": L * self._inside(x, xp), "r": L * x.r, "z": L * x.z, "k1_ref": x.k1 / L,
               "k2_ref": x.k2 / L, self.parameter.name: self.parameter.user(t)}
        values = tuple(f * e(xp=xp, **env) for e, f in zip(self.expressions, self.factors))
        return values[0] if self.single else values


@dataclass(frozen=True, eq=False, repr=False)
class LoadFunction(_KeyedFunction):
    """An expression of the parameter (a pressure, a line load) in the file's units,
    converted to the engine's: ``f(t)`` = factor x value at p = scale t."""

    expression: Expression
    factor: float
    parameter: _Parameter
    cache_key: str = field(init=False)

    def __post_init__(self):
        p = self.parameter
        object.__setattr__(self, "cache_key", _key_of(
            "load", (self.expression,), (self.factor,), p.name, p.scale))

    def __call__(self, t):
        xp = _array_module(t)
        return self.factor * self.expression(xp=xp, **{self.parameter.name:
                                                       self.parameter.user(t)})


# --------------------------------------------------------------------------- observables

_TERM = re.compile(r"\s*([+-]?)\s*(ur|uz|rotation|force)\s*\(\s*(first|second|s\s*=\s*([^()]*?))"
                   r"\s*\)\s*")


@dataclass(frozen=True)
class Observable:
    """A named column: a displacement from the reference or a rotation at an end or at an
    arclength, or a sum or difference of such terms (``"uz(second) - uz(first)"``), or the
    axial force on an end (``"force(first)"``: the total force, along +z, that the support
    or the load applies to the shell there; a held pole's reaction under displacement
    control).

    Attributes:
        name: the column's name.
        text: as the file gives it.
        terms: ((sign, component, where), ...), component ``"ur"``, ``"uz"``,
            ``"rotation"`` or ``"force"``, where ``"first"``, ``"second"`` or (not for a
            force) an arclength s in the file's length unit.
        unit: the column's unit (the file's length label, ``rad`` for rotations, modulus x
            length^2 for a force).
    """

    name: str
    text: str
    terms: tuple
    unit: str

    @property
    def column(self) -> str:
        return f"{self.name}[{self.unit}]"


def _observable(name, text, key, length_label, arclength, force_label="force") -> Observable:
    if not isinstance(text, str):
        raise ValueError(f"{key}: expected a string such as \"uz(second)\", got "
                         f"{_describe(text)}")
    terms, at = [], 0
    while at < len(text):
        m = _TERM.match(text, at)
        if m is None or m.end() == at or (terms and not m.group(1)):
            raise ValueError(f"{key}: cannot read {text!r} at column {at + 1}: expected "
                             f"ur(END), uz(END) or rotation(END) with END = first, second "
                             f"or s=VALUE, force(first) or force(second), or a sum or "
                             f"difference of such terms")
        where = m.group(3)
        if m.group(4) is not None:
            try:
                where = float(m.group(4))
            except ValueError:
                raise ValueError(f"{key}: s={m.group(4)!r} is not a number") from None
            if not (math.isfinite(where) and 0.0 <= where <= arclength):
                raise ValueError(f"{key}: s = {where:g} outside the meridian, s in "
                                 f"[0, {arclength:.10g}]")
        if m.group(2) == "force" and isinstance(where, float):
            raise ValueError(f"{key}: force(...) is read at an end: force(first) or "
                             f"force(second)")
        terms.append((-1.0 if m.group(1) == "-" else 1.0, m.group(2), where))
        at = m.end()
    if not terms:
        raise ValueError(f"{key}: empty; expected e.g. \"uz(second)\"")
    kinds = {"rotation" if c == "rotation" else "force" if c == "force" else "length"
             for _, c, _ in terms}
    if len(kinds) > 1:
        raise ValueError(f"{key}: {text!r} adds terms of different units (a rotation, a "
                         f"displacement, a force)")
    unit = {"rotation": "rad", "force": force_label, "length": length_label}[kinds.pop()]
    return Observable(name, text, tuple(terms), unit)


# --------------------------------------------------------------------------- the scene file

@dataclass(frozen=True)
class SceneFile:
    """A scene file read by :func:`load_scene`: the scene in the engine's units, the run
    settings and the conversions back to the file's units.

    Attributes:
        source: the file it was read from.
        title: its ``title`` ("" if none).
        scene: the :class:`shellbvp.Scene` (lengths / L, energies per mu h L^2, parameter
            t = p / scale).
        parameter: the parameter's name (e.g. ``"p"``, ``"kappa"``).
        start, stop: the parameter's range, ``from`` and ``to``, in its own units.
        scale: the engine's unit of the parameter: the power of ten nearest |to - from|,
            with the sign of to - from (t increases from ``from`` to ``to``).
        folds: stop after this many folds (None: at the end of the range).
        method: the method's name (:data:`METHOD_NAMES`), or its object where
            ``[solver] degree`` sets its degree per element.
        tol: the fold tolerance, in the parameter's units.
        observables: the named columns (:class:`Observable`).
        units: :class:`Units`.
        points: at least this many points on the branch (``[solver] points``): the
            continuation's steps are at most 1/points of the branch's arclength, measured
            by a first pass with the step control's own steps (which it costs); None: those
            steps alone (long where the branch is straight).
        at: parameter values (its own units) at which the states are reported exactly
            (``[parameter] at``), in order from ``from``.
    """

    source: str
    title: str
    scene: Scene = field(repr=False)
    parameter: str
    start: float
    stop: float
    scale: float
    folds: int | None
    method: object
    tol: float
    observables: tuple = field(repr=False)
    units: Units = field(repr=False)
    points: int | None = None
    at: tuple = ()

    @property
    def t_range(self) -> tuple[float, float]:
        """(from, to) as the engine's t = p / scale (increasing)."""
        return self.start / self.scale, self.stop / self.scale

    def parameter_value(self, t):
        """The file's parameter at the engine's t: scale t."""
        return self.scale * np.asarray(t, dtype=float)

    def follow(self, progress: Callable | None = None, *, at=None) -> "SceneBranch":
        """Continue the scene from ``from`` to ``to`` (:func:`shellbvp.follow`; the last
        point exactly at ``to`` where the branch gets there), stopping after ``folds``
        folds where the file says so, and observe every point and fold, each value with its
        error estimate (the point on the method's next finer discretisation; a fold's from
        its ladder).

        Arguments:
            progress: called as ``progress(p)`` after every point, p in the parameter's
                units.
            at: parameter values (its own units, in [from, to]) at which the states are
                wanted exactly, instead of the file's ``[parameter] at``.

        Returns:
            :class:`SceneBranch`; where the continuation stalls, the points that converged
            before it, with the reason (``SceneBranch.complete`` False).

        Raises:
            ValueError: an ``at`` value outside [from, to].
            ConvergenceError: the continuation failed at its start (with the engine's
                diagnosis).
        """
        at = self.at if at is None else check_at("at", at, self.start, self.stop)
        return self._follow(self.folds, progress, at=at)

    def _follow(self, folds, progress=None, *, at=(), estimate_errors=True) -> "SceneBranch":
        from .continuation.options import ContinuationOptions
        from .driver import follow as follow_scene

        options = ContinuationOptions(fold_tol=self.tol / abs(self.scale))
        report = None if progress is None else \
            (lambda pt: progress(float(self.parameter_value(pt.p))))

        def run(options, report, at=(), estimate_errors=False):
            return follow_scene(self.scene, method=self.method, p0=self.t_range[0],
                                p_stop=self.t_range, n_folds=folds, options=options,
                                progress=report, on_stall="stop",
                                estimate_errors=estimate_errors,
                                at=tuple(v / self.scale for v in at))

        if self.points is not None:
            # the branch's length in the continuation's norm from a first pass with the step
            # control's own steps, then steps of at most 1/points of it, less a tenth (the
            # first steps start shorter, and chords are shorter than the arcs they span)
            step = run(options, None).points[-1].path / (1.1 * self.points)
            options = replace(options, ds_max=step, ds=min(options.ds, step),
                              ds_min=min(options.ds_min, step / 100),
                              max_steps=max(options.max_steps, 4 * self.points))
        branch = run(options, report, at, estimate_errors)
        return SceneBranch.of(self, branch, folds, at)

    def first_instability(self, *, tol: float = 1e-6, progress: Callable | None = None,
                          checked: Callable | None = None) -> "SceneInstability":
        """The first instability along the branch from ``from`` (to its first fold, or to
        ``to``): the fold or a bifurcation into n circumferential waves
        (:func:`shellbvp.first_instability`), in the parameter's units.

        Arguments:
            tol: relative tolerance of a bifurcation's parameter value, in (0, 1).
            progress: called as ``progress(p)`` after every point of the branch (as in
                :meth:`follow`); checked: as ``checked(done, points)`` after each point's
                harmonics are checked.
        """
        from .instability import first_instability

        branch = self._follow(1, progress, estimate_errors=False).branch
        found = first_instability(branch, tol=tol, progress=checked)
        none = found.kind == "none"
        return SceneInstability(
            kind=found.kind, n=None if none else int(found.n),
            p=float(self.parameter_value(found.p)),
            error_estimate=math.nan if none else float(found.error_estimate)
            * abs(self.scale), stop=file_remedy(found.stop), instability=found,
            nearby=tuple((int(n), float(self.parameter_value(p)), float(e) * abs(self.scale))
                         for n, p, e in found.nearby))

    def observe(self, system, U, t) -> dict:
        """{name: value in the file's units} of every observable at the discrete solution
        U of ``system`` (a method's discretisation of this scene) at the engine's t.

        Read from the discretisation's own interpolant (``bvp.profile(system.dense(U,
        t))``), evaluated once at every place the observables name, not from an
        :class:`shellbvp.Equilibrium`, which also inverts the constitutive law at every
        node and integrates the energies (tens of times the cost per point). End values at
        a pole are the pole's own: its z from the regular series, r and the rotation zero.
        """
        bvp = system.bvp
        places = list(dict.fromkeys(self._place(bvp, where) for ob in self.observables
                                    for _, _, where in ob.terms))
        states = bvp.profile(system.dense(U, t))(np.array([s for _, s in places]))
        at = {place: states[:, k] for k, place in enumerate(places)}
        return {ob.name: sum(sign * self._component(bvp, at[self._place(bvp, where)], comp,
                                                    where, t)
                             for sign, comp, where in ob.terms)
                for ob in self.observables}

    def _place(self, bvp, where) -> tuple:
        """(end or None, s in the BVP's domain) of ``where`` (first, second, or an arclength
        in the file's units): an arclength inside a pole's offset is the pole."""
        if isinstance(where, float):
            s = where / self.units.length
            if s < bvp.s_a:
                return 0, bvp.s_a
            return (1, bvp.s_b) if s > bvp.s_b else (None, s)
        return (0, bvp.s_a) if where == "first" else (1, bvp.s_b)

    def _component(self, bvp, y, comp, where, t) -> float:
        """One term of an observable, ``comp`` (ur, uz, rotation, force) at ``where`` with
        the unknowns y there, at the parameter t, in the file's units."""
        from .kernels import end_value

        geo = self.scene.geometry
        end, s = self._place(bvp, where)
        if comp == "force":
            # the axial force resultant per radian: the multiplier F_z (the unknown is
            # scaled by 12 / h^2) plus, under a pressure P, P r^2 / 2, for the pressure's
            # potential P pi int r^2 Lambda sin(theta) ds sits beside F_z's in the
            # Lagrangian (the pressure on the disc of radius r); the support's force on the
            # shell is minus that times 2 pi at the first end, plus at the second
            F = float(y[5]) * self.scene.h ** 2 / 12.0
            if self.scene.pressure is not None:
                F += float(self.scene.pressure(t)) * float(y[0]) ** 2 / 2.0
            return (2 * math.pi * F * (1.0 if end == 1 else -1.0)
                    * self.units.point_force)
        index = {"ur": 0, "uz": 1, "rotation": 2}[comp]
        if end is None:
            value = y[index] - float(geo.evaluate(s)[index])
        elif bvp.poles[end] and comp != "uz":
            value = 0.0          # a pole stays on the axis, its tangent normal to it
        else:
            ref = geo.at_end(("first", "second")[end])[index]
            value = float(end_value(y, ("r", "z", "theta")[index], bvp.poles[end],
                                    (0.0, math.pi)[end], np)) - ref
        # the engine's theta turns clockwise in (r, z): a counterclockwise rotation is -dtheta
        return float(-value if comp == "rotation" else value * self.units.length)


class _Row(NamedTuple):
    """A row of a :class:`SceneBranch`'s table, before it is laid out in columns: the
    parameter, every observable and the energy, each with its error estimate (nan where
    there is none)."""

    arclength: float
    p: float
    p_error: float
    observed: dict
    errors: dict
    energy: float
    energy_error: float
    is_fold: int
    is_requested: int = 0

    def values(self) -> dict:
        """{"p", "p_error", <observable>, <observable>_error, ...}."""
        out = {"p": self.p, "p_error": self.p_error}
        for name, v in self.observed.items():
            out[name] = v
            out[f"{name}_error"] = self.errors[name]
        return out


@dataclass(frozen=True)
class SceneBranch:
    """A scene file's branch in the file's units, every value with its error estimate.

    Attributes:
        scene_file: the :class:`SceneFile`.
        branch: the engine's :class:`shellbvp.Branch` (parameter t, lengths / L).
        columns: the table's column names, units in brackets; each value's error estimate
            in the column after it (``<name>_error``).
        rows: the table: every point of the branch and every fold in order of arclength
            (parameter, observables, energy, each followed by its error; is_fold,
            is_requested).
        folds: per fold, {"p", "p_error", <observable>, <observable>_error} in the file's
            units.
        at: the same for every state asked for at a parameter value (``at``), in order
            along the branch (a value crossed twice, e.g. on either side of a fold pair,
            twice).
        last: the same for the last point.
        stop: why the branch ended.
        complete: False where the continuation stalled (the rows are the points that
            converged before it; ``stop`` says where and why).
        missing: the ``at`` values the branch did not reach.
        error_note: why some error estimates are nan ("" where none is).
    """

    scene_file: SceneFile = field(repr=False)
    branch: object = field(repr=False)
    columns: tuple
    rows: tuple = field(repr=False)
    folds: tuple
    last: dict
    stop: str
    at: tuple = ()
    complete: bool = True
    missing: tuple = ()
    error_note: str = ""

    @classmethod
    def of(cls, scene_file: SceneFile, branch, n_folds, at=()) -> "SceneBranch":
        """The table of ``branch``, a branch of ``scene_file``'s scene (``at``: the values
        asked for, in the parameter's units)."""
        from .continuation.estimates import change

        sf, u = scene_file, scene_file.units
        unit_p = abs(sf.scale)

        # what each observable is computed from: coordinates of the shell's size (L) for a
        # displacement, angles of order one for a rotation, the force itself for a force
        scale = {ob.name: {"rad": math.pi, u.length_label: u.length}.get(ob.unit, 0.0)
                 for ob in sf.observables}

        ratio = branch.system.rung_ratio

        def errors_of(observed, other):
            return {k: (change(v, other[k], scale[k], ratio) if other is not None
                        else math.nan) for k, v in observed.items()}

        refined = branch.refined
        requested = {i for _, i in branch.requested}
        points = []
        for i, pt in enumerate(branch.points):
            observed = sf.observe(branch.system, pt.U, pt.p)
            fine = None if refined is None else refined.points[i]
            other = None if fine is None else sf.observe(refined.system, fine[0], fine[1])
            points.append(_Row(float(branch.arclength[i]), float(sf.parameter_value(pt.p)),
                               float(branch.p_error[i]) * unit_p, observed,
                               errors_of(observed, other), float(branch.energy[i]) * u.energy,
                               float(branch.energy_error[i]) * u.energy, 0,
                               int(i in requested)))
        last = len(points) - 1
        # a fold's row sits between the points that bracket it, as in Branch.rows
        folds = []
        for f in branch.folds:
            observed = sf.observe(f.system, f.U, f.p)
            prev = f.previous
            other = None if prev is None else sf.observe(prev.system, prev.U, prev.p)
            folds.append(_Row(0.5 * float(branch.arclength[f.index]
                                          + branch.arclength[min(f.index + 1, last)]),
                              float(sf.parameter_value(f.p)),
                              float(f.error_estimate) * unit_p, observed,
                              errors_of(observed, other), math.nan, math.nan, 1))
        label = f"[{u.parameter_label}]" if u.parameter_label else ""
        energy = f"[{u.modulus_label}*{u.length_label}^3]"
        columns = (f"{sf.parameter}{label}", f"{sf.parameter}_error{label}",
                   *[c for ob in sf.observables
                     for c in (ob.column, f"{ob.name}_error[{ob.unit}]")],
                   f"energy{energy}", f"energy_error{energy}", "is_fold", "is_requested")
        rows = tuple((r.p, r.p_error, *[x for ob in sf.observables
                                        for x in (r.observed[ob.name], r.errors[ob.name])],
                      r.energy, r.energy_error, r.is_fold, r.is_requested)
                     for r in sorted(points + folds, key=lambda r: (r.arclength, r.is_fold)))
        reached = [float(sf.parameter_value(v)) for v, _ in branch.requested]
        missing = tuple(v for v in at if not any(math.isclose(v, x, rel_tol=1e-12,
                                                              abs_tol=1e-300)
                                                 for x in reached))
        return cls(scene_file, branch, columns, rows,
                   tuple(r.values() for r in folds), points[-1].values(),
                   _stop_reason(sf, branch, n_folds),
                   tuple(points[i].values() for _, i in branch.requested),
                   not branch.stop, missing, branch.error_note)

    def to_csv(self, path) -> None:
        """Write the table to ``path`` atomically (:func:`shellbvp.cache.
        atomic_write_text`); the units are in the column names."""
        from .cache import atomic_write_text

        buf = io.StringIO()
        wr = csv.writer(buf, lineterminator="\n")
        wr.writerow(self.columns)
        for row in self.rows:
            wr.writerow([int(v) if name in ("is_fold", "is_requested") else repr(float(v))
                         for name, v in zip(self.columns, row)])
        atomic_write_text(path, buf.getvalue())

    def summary(self) -> dict:
        """The command line's JSON object: ``{"folds": [...], "at": [...], "last": {...},
        "stop": ..., "complete": ...}``, each point ``{"p", "p_error", <observable>,
        <observable>_error}`` (nan as null), and ``"missing"``: the ``at`` values the
        branch did not reach; ``"error_note"``: why some estimates are null."""
        return {"folds": [_json_values(f) for f in self.folds],
                "at": [_json_values(a) for a in self.at],
                "last": _json_values(self.last), "stop": self.stop,
                "complete": self.complete, "missing": list(self.missing),
                "error_note": self.error_note}


@dataclass(frozen=True)
class SceneInstability:
    """The first instability of a scene file's branch, in the parameter's units.

    Attributes:
        kind: ``"fold"``, ``"bifurcation"`` or ``"none"`` (:class:`shellbvp.Instability`).
        n: the harmonic (0 for the fold; None for none).
        p: the parameter there (for ``"none"``: the last point checked).
        error_estimate: of p (nan for none).
        stop: the branch's stop reason where nothing was found.
        instability: the engine's :class:`shellbvp.Instability` (parameter t).
        nearby: ((n, p, error), ...) in the parameter's units
            (:attr:`shellbvp.Instability.nearby`).
    """

    kind: str
    n: int | None
    p: float
    error_estimate: float
    stop: str = field(repr=False, default="")
    instability: object = field(repr=False, default=None)
    nearby: tuple = ()

    def summary(self) -> dict:
        """The command line's JSON object ``{"kind", "n", "p", "error_estimate",
        "nearby"}``, with ``"stop"`` where nothing was found (why the branch ended there:
        ``to`` reached, or another reason, which then bounds the answer) and ``"note"``
        where p's error is larger than the tolerance asked (why). ``"nearby"``: a
        bifurcation's cluster, ``[{"n", "p", "error_estimate"}, ...]`` (the harmonics
        crossing within 1 % of p, :attr:`shellbvp.Instability.nearby`; [] for none)."""
        out = {"kind": self.kind, "n": self.n, "p": self.p,
               "error_estimate": self.error_estimate}
        if self.kind == "none":
            out["stop"] = self.stop
        note = getattr(self.instability, "note", "")
        if note:
            out["note"] = note
        out = _json_values(out)
        out["nearby"] = [_json_values({"n": n, "p": p, "error_estimate": e})
                         for n, p, e in self.nearby]
        return out


def _json_values(d: dict) -> dict:
    """``d`` with non-finite floats as None (JSON has no nan)."""
    return {k: (None if isinstance(v, float) and not math.isfinite(v) else v)
            for k, v in d.items()}


#: the engine's remedy for a branch that reached its step limit, which a scene file's user
#: cannot take as worded (ContinuationOptions are not file keys) ...
ENGINE_STEP_REMEDY = "raise max_steps or ds_max"
#: ... and the file's own: ``points`` sets the limit to max(400, 4 points)
FILE_STEP_REMEDY = ("set [solver] points = N (the step limit becomes the larger of 400 and "
                    "4 N) or narrow [parameter] from/to")


def file_remedy(stop: str) -> str:
    """A stop reason with the engine's remedy for the step limit replaced by the scene
    file's (:data:`FILE_STEP_REMEDY`)."""
    return stop.replace(ENGINE_STEP_REMEDY, FILE_STEP_REMEDY)


def _stop_reason(sf: SceneFile, branch, n_folds) -> str:
    if branch.stop:
        return file_remedy(branch.stop)
    if n_folds is not None and len(branch.folds) >= n_folds:
        return f"after {len(branch.folds)} fold(s)"
    t, (t_from, t_to) = float(branch.p[-1]), sf.t_range
    if t >= t_to:
        return f"reached {sf.parameter} = {sf.stop:.10g} (to)"
    if t <= t_from and branch.p.size > 1:
        return f"returned to {sf.parameter} = {sf.start:.10g} (from)"
    return "ended inside the range"


# --------------------------------------------------------------------------- load_scene

def load_scene(path) -> SceneFile:
    """Read a scene file (TOML; the format is stated in ``docs/scene-files.md``).

    Arguments:
        path: the file.

    Returns:
        :class:`SceneFile`.

    Raises:
        ValueError: the file cannot be read, is not TOML, or a key is missing, unknown or
            wrong: one line that starts with the key (e.g.
            ``geometry.segments[1].radius: must be > 0, got -1``).
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"cannot read the scene file {str(path)!r}: "
                         f"{_one_line(getattr(exc, 'strerror', None) or exc)}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"not a TOML file: {_one_line(exc)}") from None
    return _read(data, str(path))


def _read(data: dict, source: str) -> SceneFile:
    top = _Table(data, "", TOP_KEYS)
    title = top.string("title", "")
    labels = top.table("units", ("length", "modulus"))
    length_label = labels.string("length", "length")
    modulus_label = labels.string("modulus", "modulus")
    for name, value in (("length", length_label), ("modulus", modulus_label)):
        if not re.fullmatch(r"[\w/^*.+-]+", value):
            raise ValueError(f"units.{name}: a unit's name in letters, digits and / ^ * . "
                             f"(no spaces or brackets), got {value!r}")

    # the meridian in the file's units gives L; the engine's is the same divided by L
    geometry = top.table("geometry", ("segments", "thickness"), required=True)
    entries = geometry.raw("segments")
    if not isinstance(entries, list) or not entries:
        raise ValueError(f"geometry.segments: expected a list of segments ({{ type = ... }}),"
                         f" got {_describe(entries)}")
    L = _meridian(entries, 1.0).size
    meridian = _meridian(entries, L)

    parameter, start, stop, folds, p_label, at = _parameter(top)
    scale = math.copysign(10.0 ** round(math.log10(abs(stop - start))), stop - start)
    param = _Parameter(parameter, scale, (start / scale, stop / scale))
    mu, material = _material(top)
    h_user, thickness = _thickness(geometry, meridian, L, param)
    units = Units(L, mu, h_user, length_label, modulus_label, p_label)

    stimulus = _stimulus(top, meridian, units, param)
    pressure = _pressure(top, units, param)
    ends = _pole_force(top, meridian, units, param, _ends(top, meridian, units, param))
    rings = _rings(top, meridian, units, param)
    method, tol, monitor, points = _solver(top, stop - start, scale)
    observables = _observables(top, units, meridian, parameter)
    try:
        # the engine's parameter is t = p / scale, its lengths the file's / L; its messages
        # quote both in the file's own units
        display = Display(parameter, scale, p_label, L,
                          "" if length_label == "length" else length_label)
        scene = Scene(geometry=meridian, h=h_user / L, ends=ends, thickness=thickness,
                      pressure=pressure, parameter=f"t_{parameter}", monitor=monitor,
                      rings=rings, display=display, **material, **stimulus)
    except ValueError as exc:
        raise ValueError(f"{_scene_key(str(exc))}: {_one_line(exc)}") from None
    if scene.pieces > 1:
        # the expressions see each piece from inside (PointFunction.piece_ends)
        ends = tuple(float(x) for x in scene.piece_ends)
        scene = replace(scene, **{name: replace(getattr(scene, name), piece_ends=ends)
                                  for name in ("fields", "through_thickness", "thickness")
                                  if isinstance(getattr(scene, name), PointFunction)})
    return SceneFile(source, title, scene, parameter, start, stop, scale, folds, method, tol,
                     observables, units, points, at)


def _scene_key(message: str) -> str:
    """The file's key behind an error of :class:`shellbvp.Scene` (checked here before
    where the file's units matter; what remains is named by its first word)."""
    first = message.split(" ", 1)[0]
    return {"lam": "material.lam", "nu": "material.nu", "model": "material.reduction",
            "h": "geometry.thickness", "breaks": "stimulus.breaks",
            "monitor": "solver.monitor", "ring": "loads.rings",
            "rings:": "loads.rings"}.get(first, "scene")


def _parameter(top):
    t = top.table("parameter", ("name", "from", "to", "folds", "unit", "at"), required=True)
    name = t.string("name", "p")
    taken = (*POINT_SYMBOLS, *CONSTANTS, *FUNCTIONS, "xp")
    if not name.isidentifier() or keyword.iskeyword(name) or name in taken:
        raise ValueError(f"parameter.name: must be a name (letters, digits, _) other than "
                         f"{', '.join(taken)}, got {name!r}")
    start, stop = t.number("from"), t.number("to")
    if start == stop:
        raise ValueError(f"parameter.to: must differ from parameter.from, both {start:g}")
    folds = None
    if "folds" in t:
        folds = t.raw("folds")
        if not (isinstance(folds, int) and not isinstance(folds, bool) and folds >= 1):
            raise ValueError(f"parameter.folds: expected an integer >= 1, got "
                             f"{_describe(folds)}")
    label = t.string("unit", "")
    if label and not re.fullmatch(r"[\w/^*.+-]+", label):
        raise ValueError(f"parameter.unit: a unit's name in letters, digits and / ^ * . "
                         f"(no spaces or brackets), got {label!r}")
    at = check_at("parameter.at", t.numbers("at") if "at" in t else (), start, stop)
    return name, start, stop, folds, label, at


def check_at(key: str, values, start: float, stop: float) -> tuple:
    """The parameter values at which states are asked for (``[parameter] at``, ``--at``):
    finite, inside [from, to]; ValueError naming ``key`` else."""
    lo, hi = min(start, stop), max(start, stop)
    out = []
    for v in values:
        if not (isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                and lo <= v <= hi):
            raise ValueError(f"{key}: each value must be a number in [{lo:g}, {hi:g}] "
                             f"(from, to), got {v!r}")
        out.append(float(v))
    return tuple(sorted(set(out), key=lambda v: abs(v - start)))


def _material(top):
    """(mu in the file's units, the Scene's material keywords)."""
    t = top.raw("material", _MISSING)
    if t is _MISSING:
        raise ValueError("material: missing (required); e.g. [material] name = \"koiter\", "
                         "E = 1.0, nu = 0.3")
    if not isinstance(t, dict):
        raise ValueError(f"material: expected a table, got {_describe(t)}")
    name = t.get("name", _MISSING)
    if name is _MISSING or name not in MATERIAL_KEYS:
        raise ValueError(f"material.name: must be one of {', '.join(MATERIAL_KEYS)}, got "
                         f"{'nothing' if name is _MISSING else _describe(name)}")
    t = _Table(t, "material", ("name", *MATERIAL_KEYS[name]))
    if name == "koiter":
        E, nu = t.number("E", positive=True), t.number("nu")
        if not -1.0 < nu <= 0.5:
            raise ValueError(f"material.nu: must lie in (-1, 0.5] (0.5: incompressible), "
                             f"got {nu:g}")
        return E / (2.0 * (1.0 + nu)), {"material": "koiter", "nu": nu}
    mu = t.number("mu", positive=True)
    if name == "nh":
        return mu, {"material": "nh"}
    lam = t.number("lam", positive=True)
    model = t.string("reduction", "relaxed", choices=MODELS)
    return mu, {"material": "cg", "lam": lam / mu, "model": model}


#: material name -> its keys besides name (the engine's MATERIALS, each with its moduli)
MATERIAL_KEYS = {"koiter": ("E", "nu"), "cg": ("mu", "lam", "reduction"), "nh": ("mu",)}


def _samples(meridian: Meridian) -> np.ndarray:
    """Arclengths at which a file's fields are checked: CHECK_SAMPLES per segment, each
    segment's ends included (a joint on both sides)."""
    out = []
    for start, seg in zip(meridian.segment_starts, meridian.segments):
        u = np.linspace(0.0, seg.length, CHECK_SAMPLES)
        u[-1] = np.nextafter(u[-1], 0.0)
        out.append(start + u)
    out.append([meridian.length])
    return np.concatenate(out)


def _reference_points(meridian: Meridian):
    from .fields import ReferencePoint

    s = _samples(meridian)
    r, z, theta, _ = meridian.evaluate(s)
    k1, k2 = meridian.curvatures(s)
    return ReferencePoint(0, s, np.asarray(r), np.asarray(z), np.asarray(theta),
                          np.asarray(k1), np.asarray(k2))


def _thickness(geometry, meridian, L, param):
    """(h in the file's units, the Scene's thickness profile or None)."""
    expr = parse(geometry.raw("thickness"), ("s", "r", "z"), key="geometry.thickness")
    x = _reference_points(meridian)
    with np.errstate(all="ignore"):
        h = np.asarray(PointFunction((expr,), (1.0,), L, param, single=True)(x), dtype=float)
    h = np.broadcast_to(h, x.s.shape)
    bad = ~np.isfinite(h) | (h <= 0)
    if bad.any():
        k = int(np.argmax(bad))
        raise ValueError(f"geometry.thickness: must be > 0 along the meridian, got "
                         f"{h[k]:.6g} at s = {x.s[k] * L:.6g}")
    h_max = float(h.max())
    Rc = curvature_radius(meridian) * L
    if not H_MIN * Rc < h_max < Rc:
        raise ValueError(f"geometry.thickness: {h_max:.6g} must lie in ({H_MIN * Rc:.3g}, "
                         f"{Rc:.6g}), below the reference's smallest radius of curvature "
                         f"{Rc:.6g} (a thin shell) and above {H_MIN:g} of it (the edge layer, "
                         f"of width ~ sqrt(h R), is beyond every method's resolution below)")
    if expr.is_constant:
        return h_max, None
    return h_max, PointFunction((expr,), (1.0 / h_max,), L, param, single=True)


def _stimulus(top, meridian, units, param):
    """The Scene's stimulus keywords: fields, through_thickness, metric, breaks."""
    t = top.table("stimulus", ("g1", "g2", "kb1", "kb2", "rhob1", "rhob2", "rhob3",
                               "breaks"))
    L = units.length
    symbols = (param.name, *POINT_SYMBOLS)

    def group(names, defaults, factors):
        if not any(n in t for n in names):
            return None
        exprs = tuple(parse(t.raw(n, d), symbols, key=f"stimulus.{n}")
                      for n, d in zip(names, defaults))
        return PointFunction(exprs, factors, L, param)

    fields = group(("g1", "g2", "kb1", "kb2"), (1.0, 1.0, "k1_ref", "k2_ref"),
                   (1.0, 1.0, L, L))
    through = group(("rhob1", "rhob2", "rhob3"), (1.0, 0.0, 0.0), (1.0, L, L * L))
    x = _reference_points(meridian)
    for fn, names, positive in ((fields, ("g1", "g2", "kb1", "kb2"), (0, 1)),
                                (through, ("rhob1", "rhob2", "rhob3"), (0,))):
        if fn is not None:
            _check_values(fn, x, names, positive, units, param)
    breaks = ()
    if "breaks" in t:
        values = t.numbers("breaks")
        total = meridian.length * L
        for a, b in zip(values, values[1:]):
            if not b > a:
                raise ValueError(f"stimulus.breaks: must increase, got {a:g} then {b:g}")
        for v in values:
            if not 0.0 < v < total:
                raise ValueError(f"stimulus.breaks: {v:g} outside the meridian's interior "
                                 f"(0, {total:.10g}) (arclength from its first end)")
            near = [j * L for j in meridian.joints if abs(v / L - j) <= 1e-9 * meridian.length]
            if near:
                raise ValueError(f"stimulus.breaks: {v:g} lies on a joint of the segments "
                                 f"(s = {near[0]:.10g}), already an interface")
        breaks = tuple(v / L for v in values)
    metric = "g1" in t or "g2" in t
    return {"fields": fields, "through_thickness": through, "metric": metric,
            "breaks": breaks}


def _check_values(fn, x, names, positive, units, param):
    """Refuse stimulus values that are not finite, or not > 0 where they must be, on the
    check samples at the range's two ends."""
    for t in param.ends:
        with np.errstate(all="ignore"):
            values = fn(x, t)
        for k, (name, v) in enumerate(zip(names, values)):
            v = np.broadcast_to(np.asarray(v, dtype=float), x.s.shape)
            bad = ~np.isfinite(v) | ((v <= 0) if k in positive else False)
            if bad.any():
                i = int(np.argmax(bad))
                what = "finite and > 0" if k in positive else "finite"
                raise ValueError(f"stimulus.{name}: must be {what} along the meridian, got "
                                 f"{v[i] / fn.factors[k]:.6g} at s = "
                                 f"{x.s[i] * units.length:.6g}, {param.name} = "
                                 f"{param.user(t):.6g}")


def _load(value, key, factor, param) -> LoadFunction:
    fn = LoadFunction(parse(value, (param.name,), key=key), factor, param)
    for t in param.ends:
        with np.errstate(all="ignore"):
            v = float(fn(t))
        if not math.isfinite(v):
            raise ValueError(f"{key}: not finite at {param.name} = {param.user(t):.6g}")
    return fn


LOAD_KEYS = ("pressure", "pole_force", "pole_displacement", "pole", "rings")


def _pressure(top, units, param):
    t = top.table("loads", LOAD_KEYS)
    if "pressure" not in t:
        return None
    return _load(t.raw("pressure"), "loads.pressure", 1.0 / units.pressure, param)


def _pole_force(top, meridian, units, param, ends):
    """The ends with ``[loads] pole_force`` (a point force along +z, the file's force unit)
    or ``pole_displacement`` (the pole's prescribed axial displacement, the file's length
    unit: displacement control) on the pole ``[loads] pole`` (default: the only pole, or the
    second of two, the first holding a free body's axial position)."""
    t = top.table("loads", LOAD_KEYS)
    given = [k for k in ("pole_force", "pole_displacement") if k in t]
    if len(given) > 1:
        raise ValueError("loads.pole_displacement: a pole takes a force or a prescribed "
                         "displacement, not both")
    if not given:
        if "pole" in t:
            raise ValueError("loads.pole: names the pole of a pole_force or "
                             "pole_displacement, and there is none")
        return ends
    key = given[0]
    poles = [w for w, pole in zip(("first", "second"), meridian.poles) if pole]
    if not poles:
        raise ValueError(f"loads.{key}: the meridian has no pole (no end on the axis) to "
                         f"push; use the ends' axial_force for a line load on an edge")
    which = t.string("pole", poles[-1], choices=("first", "second"))
    if which not in poles:
        raise ValueError(f"loads.pole: the {which} end is not a pole (on the axis); the poles "
                         f"are: {', '.join(poles)}")
    factor = 1.0 / (units.point_force if key == "pole_force" else units.length)
    fn = _load(t.raw(key), f"loads.{key}", factor, param)
    k = ("first", "second").index(which)
    field_ = "force" if key == "pole_force" else "displacement"
    return tuple(replace(e, **{field_: fn}) if i == k else e for i, e in enumerate(ends))


def _rings(top, meridian, units, param) -> tuple:
    """``[loads] rings = [{ s = ..., axial = "...", radial = "..." }, ...]``: total forces
    (the file's force unit; 2 pi r times a line load) on the circles at arclength s (the
    file's length unit) of the meridian, as :class:`shellbvp.Ring`."""
    t = top.table("loads", LOAD_KEYS)
    if "rings" not in t:
        return ()
    entries = t.raw("rings")
    if not isinstance(entries, list) or not entries:
        raise ValueError(f"loads.rings: expected a list of rings ({{ s = ..., axial = ..., "
                         f"radial = ... }}), got {_describe(entries)}")
    L = meridian.length * units.length
    out = []
    for k, entry in enumerate(entries):
        r = _Table(entry, f"loads.rings[{k}]", ("s", "axial", "radial"))
        s = r.number("s")
        if not 0.0 < s < L:
            raise ValueError(f"loads.rings[{k}].s: must lie inside the meridian, (0, {L:.6g})"
                             f" (its arclength in the file's length unit; a load on an end "
                             f"is that end's), got {s:g}")
        if "axial" not in r and "radial" not in r:
            raise ValueError(f"loads.rings[{k}]: give axial, radial or both (total forces)")
        loads = {name: _load(r.raw(name), f"loads.rings[{k}].{name}",
                             1.0 / units.point_force, param)
                 for name in ("axial", "radial") if name in r}
        try:
            out.append(Ring(s / units.length, **loads))
        except ValueError as exc:
            raise ValueError(f"loads.rings[{k}]: {_one_line(exc)}") from None
    at = sorted(r.s for r in out)
    for x, y in zip(at[:-1], at[1:]):
        if y - x <= 1e-9 * meridian.length:
            raise ValueError(f"loads.rings: two rings at s = {x * units.length:.6g}; give one "
                             f"ring with the sum of their loads")
    return tuple(out)


#: the file's names of an end's loads -> the End's
END_LOADS = {"axial_force": "axial", "radial_force": "radial", "moment": "moment"}


def _ends(top, meridian, units, param):
    which = ("first", "second")
    t = top.table("ends", (*which, *[f"{w}_{n}" for w in which for n in END_LOADS]))
    factors = {"axial": 1.0 / units.line_force, "radial": 1.0 / units.line_force,
               "moment": 1.0 / units.line_moment}
    out = []
    for k, w in enumerate(which):
        pole = meridian.poles[k]
        kind = t.string(w, "pole" if pole else "free", choices=tuple(END_KINDS))
        r0, _, theta0 = meridian.at_end(w)
        if pole and kind != "pole":
            raise ValueError(f"ends.{w}: the meridian's {w} end is on the axis (r = 0): it "
                             f"must be 'pole', got {kind!r}")
        if kind == "pole" and not pole:
            raise ValueError(f"ends.{w}: 'pole' but the meridian's {w} end is at "
                             f"r = {r0 * units.length:.6g}; choose free, clamped, hinged, "
                             f"roller, sliding, diaphragm or symmetry")
        if kind == "symmetry" and abs(math.cos(theta0)) > 1e-9:
            raise ValueError(f"ends.{w}: 'symmetry' needs the tangent parallel to the axis "
                             f"there (a mirror plane normal to the axis); it makes "
                             f"{math.degrees(math.acos(abs(math.sin(theta0)))):.6g} degrees "
                             f"with the axis")
        loads = {}
        for name, engine in END_LOADS.items():
            key = f"{w}_{name}"
            if key not in t:
                continue
            if engine not in LOADS_OF[kind]:
                takes = ", ".join(f"{w}_{n}" for n, e in END_LOADS.items()
                                  if e in LOADS_OF[kind]) or "none"
                raise ValueError(f"ends.{key}: a {kind} end takes no {name.replace('_', ' ')}"
                                 f" ({END_KINDS[kind]}); loads it takes: {takes}")
            loads[engine] = _load(t.raw(key), f"ends.{key}", factors[engine], param)
        out.append(End(kind, **loads))
    return tuple(out)


def _solver(top, span, scale):
    t = top.table("solver", ("method", "tol", "monitor", "points", "degree"))
    method = t.string("method", "spectral", choices=METHOD_NAMES)
    if "degree" in t:
        from .methods import Chebyshev, Ritz

        value = t.raw("degree")
        kinds = {"spectral": (Chebyshev, "nodes", 8, 400), "energy": (Ritz, "degree", 6, 64)}
        if method not in kinds:
            raise ValueError(f"solver.degree: the degree per element is a setting of the "
                             f"spectral and energy methods, not of {method!r}")
        cls, name, lo, hi = kinds[method]
        if isinstance(value, bool) or not isinstance(value, int) or not lo <= value <= hi:
            raise ValueError(f"solver.degree: expected an integer in [{lo}, {hi}] (the "
                             f"polynomial degree per element), got {_describe(value)}")
        method = cls(**{name: value})
    tol = t.number("tol", DEFAULT_RELATIVE_TOL * abs(span), positive=True)
    if not tol < 0.1 * abs(scale):
        raise ValueError(f"solver.tol: must be below {0.1 * abs(scale):g} (a tenth of the "
                         f"power of ten nearest |to - from|), got {tol:g}")
    monitor = t.string("monitor", "") or None
    if monitor is not None and re.search(r"s\s*=", monitor):
        raise ValueError(f"solver.monitor: the continuation's monitor is an end value "
                         f"(uz, ur or rotation of first or second, or a difference of two), "
                         f"got {monitor!r}")
    points = None
    if "points" in t:
        value = t.raw("points")
        if isinstance(value, bool) or not isinstance(value, int) or not 2 <= value <= 100000:
            raise ValueError(f"solver.points: expected an integer in [2, 100000], got "
                             f"{_describe(value)}")
        points = value
    return method, tol, monitor, points


def _observables(top, units, meridian, parameter):
    t = top.raw("observe", {})
    if not isinstance(t, dict):
        raise ValueError(f"observe: expected a table of named observables, got "
                         f"{_describe(t)}")
    out = []
    for name, text in t.items():
        key = f"observe.{name}"
        if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
            raise ValueError(f"{key}: a column's name is letters, digits and _ (not starting "
                             f"with a digit)")
        if name in RESERVED or name == parameter or name.endswith("_error"):
            raise ValueError(f"{key}: the name is taken (reserved: "
                             f"{', '.join((*RESERVED, parameter))} and names ending in "
                             f"_error, the error estimates' columns)")
        out.append(_observable(name, text, key, units.length_label,
                               meridian.length * units.length,
                               f"{units.modulus_label}*{units.length_label}^2"))
    return tuple(out)


# --------------------------------------------------------------------------- examples

def examples() -> tuple:
    """The names of the example scene files installed with the package
    (``shellbvp/problems/scenes/*.toml``), e.g. ``"everting-cap"``."""
    return tuple(sorted(p.stem for p in _examples_folder().glob("*.toml")))


def example(name: str) -> Path:
    """The path of the installed example scene file ``name`` (:func:`examples`).

    Raises:
        ValueError: no example of that name (the message lists them).
    """
    path = _examples_folder() / f"{name}.toml"
    if not path.is_file():
        raise ValueError(f"no example scene {name!r}; examples: {', '.join(examples())}")
    return path


def _examples_folder() -> Path:
    from importlib.resources import files

    return Path(str(files("shellbvp.problems") / "scenes"))
