"""The 3D surface of a state: the deformed shell of revolution on a grid in (s, omega) with
the fields that pictures colour it by and ParaView files carry.

An axisymmetric :class:`shellbvp.Equilibrium` is the meridian (r(s), z(s)) turned about the
axis: the point (r cos omega, r sin omega, z), and every field constant in omega. A lobed
state of :func:`shellbvp.follow_bifurcation` is that of its base equilibrium (the
axisymmetric state at the bifurcation) plus the 2D displacement of
:mod:`shellbvp.fourier2d`,

    dx = sum over k of U_r^k(s) cos(k omega) e_r + U_w^k(s) sin(k omega) e_omega
         + U_z^k(s) cos(k omega) e_z,

each U^k evaluated from its Chebyshev series on its piece. The grid in s is the
equilibrium's own nodes (a pole's first node at its offset eps: a pin-hole of radius ~eps
at the axis); in omega either a closed ring of ``omega`` equispaced angles on [0, 2 pi)
(``periodic``: what a file stores) or the angles given (a picture's sector).

Fields (:data:`EQUILIBRIUM_FIELDS`, :data:`LOBED_FIELDS`), with the reference surface
X(s, omega) (the meridian (r0, z0) turned) and its outward normal n0 = (sin theta0, 0,
cos theta0) in the frame (e_r, e_omega, e_z):

* ``displacement`` x - X (a vector; its length where a scalar is needed),
  ``normal_displacement`` (x - X) . n0, ``radial_displacement`` and ``axial_displacement``
  its e_r and e_z components;
* ``eps11``, ``eps22``: the elastic mid-surface strains relative to the target metric,
  (a_aa / abar_aa - 1) / 2, and for a lobed state the shear ``eps12`` = a_12 /
  (2 sqrt(abar_11 abar_22)) (a the current metric in (s, omega), abar = diag(g1^2,
  g2^2 r0^2) the target's); at a lobed state they are computed from the surface's own
  tangents x_s, x_omega, so that with no lobes they are the equilibrium's;
* an equilibrium's ``k1``, ``k2`` (principal curvatures), ``N1``, ``N2`` (stress
  resultants per unit deformed length, :class:`shellbvp.Equilibrium`) and ``moment`` (the
  meridional bending moment per unit deformed hoop length, M / r);
* a lobed state's lobes: ``lobe_displacement``, the part of dx in the harmonics k >= n
  (the state less its axisymmetric part), and ``lobe_normal_displacement``, that part
  along n = (sin theta, 0, cos theta), the base equilibrium's normal: the 2D field's
  normal displacement, harmonic 0 left out;
* ``thickness`` (h times the thickness profile) and the stimulus at the state's parameter:
  ``g1``, ``g2`` (the target metric's stretches) and ``kb1``, ``kb2`` (target curvatures).

Units (:class:`OutputUnits`): the engine's (lengths in the geometry's unit R0, line forces
per mu* h, line moments per mu* h R0) or a scene file's own (:meth:`OutputUnits.of`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

__all__ = ["Surface", "OutputUnits", "EQUILIBRIUM_FIELDS", "LOBED_FIELDS", "KINDS",
           "equilibrium_surface", "lobed_surface", "ring"]

#: the kinds of unit a field has
KINDS = ("length", "1", "1/length", "line_force", "line_moment")
#: name: (what it is, its kind of unit), for an axisymmetric equilibrium
EQUILIBRIUM_FIELDS = {
    "normal_displacement": ("normal displacement", "length"),
    "displacement": ("displacement", "length"),
    "radial_displacement": ("radial displacement", "length"),
    "axial_displacement": ("axial displacement", "length"),
    "eps11": ("meridional strain eps11", "1"),
    "eps22": ("hoop strain eps22", "1"),
    "k1": ("meridional curvature k1", "1/length"),
    "k2": ("hoop curvature k2", "1/length"),
    "N1": ("meridional stress resultant N1", "line_force"),
    "N2": ("hoop stress resultant N2", "line_force"),
    "moment": ("meridional bending moment", "line_moment"),
    "thickness": ("thickness", "length"),
    "g1": ("target metric stretch g1", "1"),
    "g2": ("target metric stretch g2", "1"),
    "kb1": ("target curvature kb1", "1/length"),
    "kb2": ("target curvature kb2", "1/length"),
}
#: the same for a lobed state (no curvatures or stress resultants: those of the 2D state
#: are not computed)
LOBED_FIELDS = {
    **{k: v for k, v in EQUILIBRIUM_FIELDS.items()
       if k not in ("k1", "k2", "N1", "N2", "moment")},
    "eps12": ("shear strain eps12", "1"),
    "lobe_displacement": ("lobes' displacement", "length"),
    "lobe_normal_displacement": ("lobes' normal displacement", "length"),
}


@dataclass(frozen=True)
class OutputUnits:
    """The units results are written in: factors from the engine's units to the user's,
    and their labels.

    Attributes:
        length: a length of the engine's (R0) in the user's unit.
        line_force, line_moment: the engine's line force (mu* h) and line moment
            (mu* h R0) in the user's units.
        parameter_scale: the parameter in the user's units per the engine's.
        parameter: the parameter's name ("": the scene's).
        length_label, line_force_label, line_moment_label, parameter_label: their names
            ("" for a parameter without a unit).
    """

    length: float = 1.0
    line_force: float = 1.0
    line_moment: float = 1.0
    parameter_scale: float = 1.0
    parameter: str = ""
    length_label: str = "R0"
    line_force_label: str = "mu* h"
    line_moment_label: str = "mu* h R0"
    parameter_label: str = ""

    @classmethod
    def of(cls, scene_file) -> "OutputUnits":
        """A scene file's own units (:class:`shellbvp.SceneFile`): its length, force per
        length (modulus x length) and moment per length (modulus x length^2), and its
        parameter."""
        u = scene_file.units
        return cls(length=u.length, line_force=u.line_force, line_moment=u.line_moment,
                   parameter_scale=float(scene_file.scale),
                   parameter=scene_file.parameter, length_label=u.length_label,
                   line_force_label=f"{u.modulus_label}*{u.length_label}",
                   line_moment_label=f"{u.modulus_label}*{u.length_label}^2",
                   parameter_label=u.parameter_label)

    def factor(self, kind: str) -> float:
        """The factor of a field of this kind (:data:`KINDS`)."""
        return {"length": self.length, "1": 1.0, "1/length": 1.0 / self.length,
                "line_force": self.line_force, "line_moment": self.line_moment}[kind]

    def label(self, kind: str) -> str:
        """The unit's name for a field of this kind ("" for a pure number)."""
        return {"length": self.length_label, "1": "", "1/length": f"1/{self.length_label}",
                "line_force": self.line_force_label,
                "line_moment": self.line_moment_label}[kind]


@dataclass(frozen=True)
class Surface:
    """A state's surface on a grid (module docstring), in the units of ``units``.

    Attributes:
        points: (ns, nw, 3) positions (x, y, z), z along the axis.
        s: (ns,) the reference meridian's arclength at the rows; omega: (nw,) the columns'
            angles (radians).
        periodic: the columns close a ring (omega equispaced on [0, 2 pi)): the last column
            joins the first.
        fields: name -> (ns, nw) values, or (ns, nw, 3) for a vector.
        catalogue: name -> (what it is, kind of unit) of the fields
            (:data:`EQUILIBRIUM_FIELDS` or :data:`LOBED_FIELDS`).
        units: :class:`OutputUnits`.
        parameter, p: the parameter's name and value (in ``units``).
        magnify: the factor the drawn displacement carries (1: the state as computed).
    """

    points: np.ndarray = field(repr=False)
    s: np.ndarray = field(repr=False)
    omega: np.ndarray = field(repr=False)
    periodic: bool
    fields: dict = field(repr=False)
    catalogue: dict = field(repr=False)
    units: OutputUnits = field(repr=False)
    parameter: str
    p: float
    magnify: float = 1.0

    def scalar(self, name: str) -> np.ndarray:
        """The field ``name`` as (ns, nw) numbers (a vector's length).

        Raises:
            ValueError: a name this surface has no field of (the message names those it
                has).
        """
        if name not in self.fields:
            raise ValueError(f"field must be one of {', '.join(self.fields)}, got {name!r}")
        v = self.fields[name]
        return np.linalg.norm(v, axis=-1) if v.ndim == 3 else v

    def label(self, name: str) -> str:
        """The field's description with its unit, e.g. ``hoop strain eps22`` or
        ``normal displacement [mm]``."""
        what, kind = self.catalogue[name]
        unit = self.units.label(kind)
        return f"{what} [{unit}]" if unit else what

    @property
    def parameter_text(self) -> str:
        """``name = value unit`` of the state's parameter."""
        unit = f" {self.units.parameter_label}" if self.units.parameter_label else ""
        return f"{self.parameter} = {self.p:.6g}{unit}"


def ring(omega) -> tuple[np.ndarray, bool]:
    """(angles, periodic) of a grid in omega: an int n gives n equispaced angles on
    [0, 2 pi) (a closed ring), an array its own angles.

    Raises:
        ValueError: fewer than 3 angles, or angles that are not finite.
    """
    if isinstance(omega, (int, np.integer)) and not isinstance(omega, bool):
        if omega < 3:
            raise ValueError(f"omega must be at least 3 angles, got {omega!r}")
        return 2 * math.pi * np.arange(int(omega)) / int(omega), True
    w = np.asarray(omega, dtype=float)
    if w.ndim != 1 or w.size < 2 or not np.all(np.isfinite(w)):
        raise ValueError(f"omega must be a number of angles (>= 3) or a 1D array of at least "
                         f"2 finite angles, got {omega!r}")
    return w, False


def _check_magnify(magnify) -> float:
    if not (isinstance(magnify, (int, float)) and not isinstance(magnify, bool)
            and math.isfinite(magnify) and magnify > 0):
        raise ValueError(f"magnify must be a positive number, got {magnify!r}")
    return float(magnify)


def _pieces(scene, s) -> np.ndarray:
    """The piece of every node s, a node at an interface on the piece before it (where
    the equilibrium's arrays took it from)."""
    inner = np.asarray(scene.piece_ends[1:-1], dtype=float)
    return np.searchsorted(inner, s, side="left")


def _reference(scene, s, p) -> dict:
    """The reference meridian and the fields at the nodes s and parameter p: r0, z0,
    theta0, and g1, g2, kb1, kb2, thickness (h t)."""
    from . import kinematics as K
    from .fields import point_fields, reference_point

    piece = _pieces(scene, s)
    c = np.asarray(scene.field_parameters, dtype=float)
    out = {k: np.empty(s.shape) for k in ("r0", "z0", "theta0", "g1", "g2", "kb1", "kb2",
                                          "thickness")}
    for i in np.unique(piece):
        on = piece == i
        x = reference_point(scene, int(i), s[on])
        F = point_fields(scene, int(i), s[on], p, c)
        out["r0"][on], out["z0"][on], out["theta0"][on] = (
            np.broadcast_to(v, s[on].shape) for v in (x.r, x.z, x.theta))
        for name, k in (("g1", K.G1), ("g2", K.G2), ("kb1", K.KB1), ("kb2", K.KB2)):
            out[name][on] = F[k]
        out["thickness"][on] = scene.h * F[K.THICKNESS]
    return out


def _cartesian(local, omega) -> np.ndarray:
    """(ns, nw, 3) Cartesian components of vectors given in the frame (e_r, e_omega, e_z)
    at every angle: ``local`` (3, ns, nw)."""
    c, s = np.cos(omega), np.sin(omega)
    vr, vw, vz = local
    return np.stack([vr * c - vw * s, vr * s + vw * c, vz], axis=-1)


def _finish(values: dict, catalogue: dict, units, points, s, omega, periodic, scene, p,
            magnify) -> Surface:
    """The :class:`Surface` of fields in the engine's units, converted to ``units``."""
    units = OutputUnits() if units is None else units
    if not isinstance(units, OutputUnits):
        raise ValueError(f"units must be a shellbvp.surface.OutputUnits, got {units!r}")
    fields = {name: np.asarray(values[name], dtype=float) * units.factor(kind)
              for name, (_, kind) in catalogue.items()}
    return Surface(points=points * units.length, s=s * units.length, omega=omega,
                   periodic=periodic, fields=fields, catalogue=catalogue, units=units,
                   parameter=units.parameter or scene.parameter,
                   p=float(p) * units.parameter_scale,
                   magnify=magnify)


def equilibrium_surface(eq, *, omega=96, magnify: float = 1.0,
                        units: OutputUnits | None = None) -> Surface:
    """The surface of the axisymmetric equilibrium ``eq`` (module docstring).

    Arguments:
        eq: a converged :class:`shellbvp.Equilibrium`.
        omega: the grid in omega (:func:`ring`): a number of angles on [0, 2 pi), or the
            angles.
        magnify: the points are X + magnify (x - X) (1: the state itself; the fields are
            not scaled).
        units: :class:`OutputUnits` (default the engine's).

    Raises:
        ValueError: an equilibrium that did not converge, bad arguments.
    """
    if not getattr(eq, "success", False) or not len(eq.s):
        raise ValueError("eq must be a converged shellbvp.Equilibrium")
    w, periodic = ring(omega)
    magnify = _check_magnify(magnify)
    sc = eq.scene
    ref = _reference(sc, eq.s, eq.p)
    ur, uz = eq.r - ref["r0"], eq.z - ref["z0"]
    one = np.ones(w.size)
    local = np.stack([np.outer(ur, one), np.zeros((eq.s.size, w.size)), np.outer(uz, one)])
    base = np.stack([np.outer(ref["r0"], one), np.zeros_like(local[0]),
                     np.outer(ref["z0"], one)])
    points = _cartesian(base + magnify * local, w)
    per_node = {
        "normal_displacement": ur * np.sin(ref["theta0"]) + uz * np.cos(ref["theta0"]),
        "radial_displacement": ur, "axial_displacement": uz,
        "eps11": eq.eps11, "eps22": eq.eps22, "k1": eq.k1, "k2": eq.k2,
        "N1": eq.N1, "N2": eq.N2, "moment": eq.M / eq.r,
        **{k: ref[k] for k in ("thickness", "g1", "g2", "kb1", "kb2")}}
    values = {k: np.outer(v, one) for k, v in per_node.items()}
    values["displacement"] = _cartesian(local, w)
    return _finish(values, EQUILIBRIUM_FIELDS, units, points, eq.s, w, periodic, sc, eq.p,
                   magnify)


def _harmonics(f, U, s) -> tuple[np.ndarray, np.ndarray]:
    """(U, U') of every harmonic of the state U of the 2D discretisation f at the nodes s:
    two arrays (K + 1, 3 components (r, omega, z), ns), from the Chebyshev series of each
    piece (a node at an interface on the piece before it, as the base equilibrium's)."""
    C = np.polynomial.chebyshev
    pieces = f.base.pieces
    piece = _pieces(f.eq.scene, s)
    P = len(pieces)
    value = np.zeros((f.K + 1, 3, s.size))
    slope = np.zeros_like(value)
    for j, c in enumerate(f.coefficients(U)):
        c = c.reshape(P, 3, f.degree + 1)
        for i, (a, b) in enumerate(pieces):
            on = piece == i
            x = (2 * s[on] - a - b) / (b - a)
            for comp in range(3):
                value[j, comp, on] = C.chebval(x, c[i, comp])
                slope[j, comp, on] = C.chebval(x, C.chebder(c[i, comp])) * 2 / (b - a)
    return value, slope


def lobed_surface(f, U, p, *, omega=None, magnify: float = 1.0,
                  units: OutputUnits | None = None) -> Surface:
    """The surface of a lobed state (module docstring): the state U (unknowns of the 2D
    discretisation ``f``, a :class:`shellbvp.fourier2d.Fourier2D`, e.g. a point of a
    :class:`shellbvp.LobedBranch`) at the parameter p.

    Arguments:
        f, U, p: the discretisation, the state and its parameter (the engine's).
        omega: the grid in omega (:func:`ring`; default 16 angles per wave of the highest
            harmonic K n, at least 96).
        magnify: the lobes drawn this many times: the points are x0 + dx + (magnify - 1)
            times the lobes (x0 the base equilibrium; 1: the state itself; the fields are
            not scaled).
        units: :class:`OutputUnits` (default the engine's).

    Raises:
        ValueError: a state that is not a vector of f's unknowns, bad arguments.
    """
    U = np.asarray(U, dtype=float)
    if U.shape != (f.size,):
        raise ValueError(f"U must be a vector of the discretisation's {f.size} unknowns, "
                         f"got shape {U.shape}")
    w, periodic = ring(max(96, 16 * f.K * f.n) if omega is None else omega)
    magnify = _check_magnify(magnify)
    eq, sc = f.eq, f.eq.scene
    s = eq.s
    ref = _reference(sc, s, p)
    value, slope = _harmonics(f, U, s)
    ks = np.array(f.ks, dtype=float)[:, None]
    cos, sin = np.cos(ks * w), np.sin(ks * w)                   # (K + 1, nw)

    def synthesis(v, c, s_):     # (3, ns, nw) in the frame (e_r, e_omega, e_z)
        return np.stack([v[:, 0].T @ c, v[:, 1].T @ s_, v[:, 2].T @ c])

    # dx, its s- and omega-derivatives, and its lobes (the harmonics k >= n)
    dx = synthesis(value, cos, sin)
    dx_s = synthesis(slope, cos, sin)
    dx_w = synthesis(value, -ks * sin, ks * cos)
    lobes = synthesis(value[1:], cos[1:], sin[1:])
    one = np.ones(w.size)
    zero = np.zeros((s.size, w.size))
    x0 = np.stack([np.outer(eq.r, one), zero, np.outer(eq.z, one)])
    X = np.stack([np.outer(ref["r0"], one), zero, np.outer(ref["z0"], one)])
    x = x0 + dx
    # the tangents: x_s of the base (|x_s| = g1 lam1 along its tangent) plus dx_s; x_omega
    # = d/domega of x's components plus e_r' = e_omega, e_omega' = -e_r
    g1 = ref["g1"] if p == eq.p else _reference(sc, s, eq.p)["g1"]
    speed = g1 * eq.lam1
    x_s = np.stack([np.outer(speed * np.cos(eq.theta), one), zero,
                    np.outer(-speed * np.sin(eq.theta), one)]) + dx_s
    x_w = np.stack([dx_w[0] - x[1], dx_w[1] + x[0], dx_w[2]])
    abar11 = np.outer(ref["g1"] ** 2, one)
    abar22 = np.outer((ref["g2"] * ref["r0"]) ** 2, one)
    u = x - X
    n0 = (np.outer(np.sin(ref["theta0"]), one), np.outer(np.cos(ref["theta0"]), one))
    n = (np.outer(np.sin(eq.theta), one), np.outer(np.cos(eq.theta), one))
    values = {
        "normal_displacement": u[0] * n0[0] + u[2] * n0[1],
        "displacement": _cartesian(u, w),
        "radial_displacement": u[0], "axial_displacement": u[2],
        "eps11": (np.sum(x_s * x_s, axis=0) / abar11 - 1) / 2,
        "eps22": (np.sum(x_w * x_w, axis=0) / abar22 - 1) / 2,
        "eps12": np.sum(x_s * x_w, axis=0) / (2 * np.sqrt(abar11 * abar22)),
        "lobe_displacement": _cartesian(lobes, w),
        "lobe_normal_displacement": lobes[0] * n[0] + lobes[2] * n[1],
        **{k: np.outer(ref[k], one) for k in ("thickness", "g1", "g2", "kb1", "kb2")}}
    points = _cartesian(x0 + dx + (magnify - 1) * lobes, w)
    return _finish(values, LOBED_FIELDS, units, points, s, w, periodic, sc, p, magnify)
