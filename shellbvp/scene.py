"""Scenes as data: the reference shell, its stimulus, material, ends and loads (paper Sections
2-5 for any shell of revolution).

A :class:`Scene` is a shell of revolution whose reference meridian is a
:class:`shellbvp.geometry.Meridian` (plates, cylinders, cones, spheres, tori, ellipses and
measured curves, joined end to end, kinks allowed), traced by its arclength s from its first
end to its second. Lengths are in the geometry's unit R (any unit used consistently; the
engine is accurate for lengths of order one in that unit), energies per mu* h R^2 with h the
reference thickness, forces per radian of azimuth in mu* h R.

The stimulus is given as fields of the reference point x (:class:`ReferencePoint`: its
piece, s, r, z, tangent angle and principal curvatures) and of one scalar parameter p
(``parameter``, e.g. ``"kappa"``): ``fields(x, p) -> (g1, g2, kb1, kb2)``, the target
stretch factors (abar_11 = g1^2 a°_11, abar_22 = g2^2 a°_22) and the target principal
curvatures kb_a = bbar_aa / abar_aa, or ``fields(x, p, c)`` with numbers c
(``field_parameters``) that the compiled programs take as arguments. Without ``fields`` the
target is the reference (no stimulus: kb = (x.k1, x.k2), g = 1). The through-thickness
stimulus ``through_thickness(x, p[, c]) -> (rhob1, rhob2, rhob3)`` (phib = rhob1 Z + rhob2
Z^2 + rhob3 Z^3; default none: (1, 0, 0)) and the thickness profile ``thickness(x) -> t``
(the thickness is h t, default t = 1) are fields too. Fields may be piecewise: ``breaks``
are interior interfaces in s where they may jump, treated exactly as a multi-point problem,
as are the joints of the geometry. Fields use array arithmetic only (they are traced by
JAX).

The ends (:class:`End`) say what holds each end of the meridian: ``pole`` (an end on the
axis, regular there), ``free``, ``clamped``, ``hinged``, ``roller``, ``sliding``,
``diaphragm`` or ``symmetry``, with given line loads where they are free to move. An axisymmetric shell has one rigid motion
its unknowns see, the axial translation; a scene whose ends do not fix the axial position
has it removed by holding the first end's z (:attr:`Scene.pinned`), with the axial force
there left free: it is zero when the loads balance, as they must for a free body. Ring
loads (:class:`Ring`) are dead forces on circles of the meridian, each an interface of the
pieces across which the meridional force resultants jump.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import cached_property, lru_cache, wraps
from typing import Callable

import numpy as np

from . import checks
from .fields import ReferencePoint, point_fields
from .geometry import Meridian, spherical_cap
from .models import MATERIAL_PARAMETER, MATERIALS, MODELS, material_parameter

__all__ = ["Scene", "End", "Ring", "Display", "ReferencePoint", "END_KINDS",
           "uniform_curvature", "lam_max", "cap"]

#: smallest opening angle of a cap (:func:`cap`): the rise 1 - cos Theta ~ Theta^2/2 keeps
#: ~10 digits above it
THETA_MIN = 1e-3
#: smallest thickness over the reference's radius of curvature: the edge layer (width
#: ~ sqrt(h R)) then needs ~ 6 L / sqrt(h R) Chebyshev nodes, at the upper end of what the
#: methods take
H_MIN = 1e-6
#: largest lambda*/mu*: lam = 1e8 is Poisson ratio 0.5 - 5e-9
LAM_MAX = 1e8
#: largest lam / h**2 admitted (Ciarlet-Geymonat; h over the reference's radius of
#: curvature): the forces of the lam term carry round-off ~ lam eps and enter the equations
#: beside the moment scaled by 12 / h**2, so Newton stalls once lam eps 12 / h**2 is too
#: large. Measured at tol 1e-8 (relaxed) on caps: Theta = pi/6 resolves lam / h**2 = 3e9 at
#: h = 1e-3, 3e-3 and 1e-2 and stalls at 1e10 for all three (lam = 1e4, 1e5, 1e6);
#: Theta = pi/3, h = 0.1 resolves 1e9 and fails at 2.5e9 (the inner (lam1, k1) Newton at
#: the fold); Theta = 0.05, h = 1e-4 resolves 3e10 and stalls at 1e11; Theta = 1.5,
#: h = 0.03 resolves 3.3e9; Theta = 0.2, h = 3e-3 stalls at 5.6e9 (no simple law in Theta
#: or T fits all seven). The fence is the largest value resolved anywhere: beyond it nothing
#: measured resolves; below it a shell that does not ends in a ConvergenceError that names
#: the same remedy (driver.follow), rather than a refused case that would have worked.
LAM_OVER_H2_MAX = 3e10
#: what each material uses (for the error of a parameter it does not)
USES = {"cg": "it uses lam and model", "nh": "incompressible: no material parameter, and "
        "J = 1 fixes the through-thickness stretch, so there is no model choice",
        "koiter": "it uses nu; it is a reference energy, not a reduction with models"}
#: the kinds of end: what each fixes of (r, z, theta) and which of its conjugate forces
#: (F_r, F_z, M) are given (the rest follow); a pole fixes r = 0 by its regularity
END_KINDS = {
    "pole": ("an end on the axis: regular there (equal stretches and curvatures), the point "
             "force given (default zero) or its axial displacement prescribed"),
    "free": "nothing fixed; the forces and the moment given (line loads, default zero)",
    "clamped": "r, z and theta fixed at the reference's values",
    "hinged": "r and z fixed; the moment given",
    "roller": "z fixed; the radial force and the moment given",
    "sliding": ("z and theta fixed at the reference's values (a clamp that slides "
                "radially); the radial force given"),
    "diaphragm": ("r fixed at the reference's value (a shear diaphragm: the end ring keeps "
                  "its radius, in the harmonics also the circumferential displacement held), "
                  "z free; the axial force and the moment given (line loads, default zero)"),
    "symmetry": ("a mirror plane normal to the axis: theta fixed (the tangent parallel to "
                 "the axis), no shear (F_r = 0), the axial force given"),
}
#: the loads an end may carry (a pole's prescribed displacement among them: what the end is
#: given as a function of the parameter), in the order of :attr:`End.loads`
LOAD_NAMES = ("axial", "radial", "moment", "force", "displacement")
#: the ends that fix the axial position z
FIXES_Z = ("clamped", "hinged", "roller", "sliding")
#: the line loads each kind of end accepts (where it is free to move)
LOADS_OF = {"pole": ("force", "displacement"), "free": ("axial", "radial", "moment"), "clamped": (),
            "hinged": ("moment",), "roller": ("radial", "moment"), "symmetry": ("axial",),
            "sliding": ("radial",), "diaphragm": ("axial", "moment")}


def lam_max(h: float) -> float:
    """The largest lam = lambda*/mu* a Ciarlet-Geymonat scene of thickness h (over the
    reference's radius of curvature) admits: ``min(LAM_MAX, LAM_OVER_H2_MAX h**2)`` (3e6 at
    h = 0.01, 3e4 at h = 1e-3), where the round-off of the lam term's forces, ~ lam eps
    12 / h**2 relative to the moment, leaves no cap measured resolvable (see
    ``LAM_OVER_H2_MAX``: from 1/30 of it some caps stall, with a ConvergenceError). Beyond
    it a nearly incompressible shell is ``material='nh'``."""
    return min(LAM_MAX, LAM_OVER_H2_MAX * h * h)


def uniform_curvature(x, kappa):
    """The cap-eversion stimulus abar = a°, bbar = b° + kappa a° (paper eq. (stimulus)):
    g = 1, kb_a = k_a + kappa, a uniform change kappa of both target curvatures (on the unit
    sphere kb = kappa - 1; kappa = 2 targets the everted cap). Array arithmetic only."""
    one = 0.0 * x.s + 1.0
    return one, one, x.k1 + kappa, x.k2 + kappa


def per_scene(fn):
    """``fn(scene, *args)`` cached by value: a :class:`Scene` is an immutable value, so
    equal scenes (a cap built anew for every call of a sweep's repeated point, say) share
    what is derived from them. Hashable arguments only; a scene holding an unhashable field
    value is computed afresh."""
    cached = lru_cache(maxsize=256)(fn)

    @wraps(fn)
    def wrapper(scene, *args):
        try:
            return cached(scene, *args)
        except TypeError:                   # unhashable: no cache
            return fn(scene, *args)

    return wrapper


def load_rate(load, p, order: int = 1) -> float:
    """The ``order``-th derivative of a load in p at p (a load is a function of the
    parameter traced by JAX, as the compiled programs trace it; order 0 its value)."""
    from .jaxsetup import jax

    f = lambda x: load(x) + 0.0 * x             # noqa: E731  (a constant load traces too)
    for _ in range(order):
        f = (lambda g: lambda x: jax.jvp(g, (x,), (1.0,))[1])(f)
    return float(f(float(p)))


def _constant(value):
    """A load that is the same at every parameter value (a number given where a function of
    p is expected)."""
    v = float(value)
    return lambda p: 0.0 * p + v


@dataclass(frozen=True)
class End:
    """What holds one end of the meridian (:data:`END_KINDS`), and the line loads on it.

    Attributes:
        kind: ``"pole"``, ``"free"``, ``"clamped"``, ``"hinged"``, ``"roller"``,
            ``"sliding"``, ``"diaphragm"`` or ``"symmetry"``.
        axial, radial: line forces per unit length of the reference edge along +z and +r
            (per mu* h: a force per length over mu* h is a pure number), functions of the
            parameter p (a number: constant), or None (zero); only where the end is free to
            move that way (:data:`LOADS_OF`).
        moment: line moment per unit length of the reference edge (per mu* h R), positive
            where it turns the meridian's tangent counterclockwise in the (r, z) plane
            (from +r toward +z); a function of p, a number or None.
        force: at a pole, the axial point force there (the total, per mu* h R, along +z),
            a function of p, a number or None (zero). A dead load: its potential is
            -force z(pole).
        displacement: at a pole, instead of a force, its axial displacement from the
            reference (along +z, in R), a function of p: displacement control (a rigid
            indenter on the pole), which passes the load maxima a force cannot. The pole then
            holds z; the force it takes is the reaction, ``2 pi F_z`` per mu* h R at a
            second end and ``-2 pi F_z`` at a first (:attr:`shellbvp.Equilibrium.F_z` at the
            pole). Another end must hold z too (a free body has nothing to push against).
    """

    kind: str
    axial: Callable | float | None = None
    radial: Callable | float | None = None
    moment: Callable | float | None = None
    force: Callable | float | None = None
    displacement: Callable | float | None = None

    def __post_init__(self):
        checks.check_choice("end kind", self.kind, tuple(END_KINDS))
        for name in LOAD_NAMES:
            value = getattr(self, name)
            if value is None:
                continue
            if name not in LOADS_OF[self.kind]:
                raise ValueError(
                    f"a {self.kind} end takes no {name} load ({END_KINDS[self.kind]}); "
                    f"loads it takes: {', '.join(LOADS_OF[self.kind]) or 'none'}")
            if isinstance(value, (int, float, np.floating, np.integer)):
                checks.check_finite(name, value)
                object.__setattr__(self, name, _constant(value))
            elif not callable(value):
                raise ValueError(f"{name} load must be a number or a function of the "
                                 f"parameter, got {type(value).__name__}")
        if self.force is not None and self.displacement is not None:
            raise ValueError("a pole takes a force or a prescribed displacement, not both")

    @property
    def fixes_z(self) -> bool:
        return self.kind in FIXES_Z or self.displacement is not None

    def conjugate(self, p, r0, order: int = 0) -> np.ndarray:
        """The loads on this end as the conjugate forces per radian (Q_r, Q_z, Q_theta) of
        the end's r, z and theta at p (their ``order``-th p-derivatives): a line load per
        unit reference length times the end's reference radius r0, Q_theta = -moment r0 (a
        counterclockwise moment turns theta negatively), and a pole's point force over
        2 pi in Q_z."""
        Q = np.zeros(3)
        for name, j, factor in (("radial", 0, r0), ("axial", 1, r0), ("moment", 2, -r0),
                                ("force", 1, 1.0 / (2.0 * math.pi))):
            load = getattr(self, name)
            if load is not None:
                Q[j] += factor * load_rate(load, p, order)
        return Q

    @property
    def loaded(self) -> bool:
        return any(getattr(self, n) is not None for n in LOAD_NAMES)

    @property
    def loads(self) -> tuple:
        """The load functions in :data:`LOAD_NAMES` order (None where not given)."""
        return tuple(getattr(self, n) for n in LOAD_NAMES)


@dataclass(frozen=True)
class Ring:
    """Forces on the circle at arclength s of the reference meridian, a dead load: an exact
    interface of the pieces, across which the meridional force resultants jump by the load
    (F(s+) - F(s-) = -Q per radian: the corner condition of the potential -Q . x(s)).

    Attributes:
        s: the circle's arclength on the reference meridian, inside (0, L): an end's loads
            are its :class:`End`'s. On a joint of the geometry or a break of the fields
            (to 1e-9 L) it loads that interface.
        axial: the total force along +z (2 pi r0 times the line load per unit reference
            length; per mu* h R), a function of the parameter p, a number or None (zero).
        radial: the total outward force, 2 pi r0 times the outward line load (per mu* h R),
            a function of p, a number or None.
    """

    s: float
    axial: Callable | float | None = None
    radial: Callable | float | None = None

    def __post_init__(self):
        checks.check_finite("ring s", self.s)
        object.__setattr__(self, "s", float(self.s))
        for name in RING_LOADS:
            value = getattr(self, name)
            if isinstance(value, (int, float, np.floating, np.integer)):
                checks.check_finite(f"ring {name}", value)
                object.__setattr__(self, name, _constant(value))
            elif value is not None and not callable(value):
                raise ValueError(f"ring {name} load must be a number or a function of the "
                                 f"parameter, got {type(value).__name__}")
        if self.axial is None and self.radial is None:
            raise ValueError(f"the ring at s = {self.s:g} carries no load: give axial or "
                             f"radial")

    def conjugate(self, p, order: int = 0) -> np.ndarray:
        """(Q_r, Q_z): the total forces per radian at p (their ``order``-th derivatives in
        p), the conjugates of the circle's r and z."""
        return np.array([0.0 if f is None else load_rate(f, p, order) / (2.0 * math.pi)
                         for f in (self.radial, self.axial)])

    @property
    def loads(self) -> tuple:
        """The load functions in :data:`RING_LOADS` order (None where not given)."""
        return tuple(getattr(self, n) for n in RING_LOADS)


#: a ring's loads, in the order of :attr:`Ring.loads`
RING_LOADS = ("axial", "radial")


@dataclass(frozen=True)
class Display:
    """How the engine's numbers read in a user's own units (a scene file's, whose lengths
    and parameter the engine scales): the parameter is ``parameter_scale`` p, named
    ``parameter`` in ``parameter_unit``, an arclength ``length_scale`` s in ``length_unit``.
    The default is the engine's own units (the scene's parameter name)."""

    parameter: str | None = None
    parameter_scale: float = 1.0
    parameter_unit: str = ""
    length_scale: float = 1.0
    length_unit: str = ""


def _as_end(value, which) -> End:
    if isinstance(value, End):
        return value
    if isinstance(value, str):
        return End(value)
    raise ValueError(f"ends[{which}] must be an End or one of {tuple(END_KINDS)}, got "
                     f"{value!r}")


@dataclass(frozen=True)
class Scene:
    """A shell of revolution and what acts on it (module docstring).

    Attributes:
        geometry: the reference meridian (:class:`shellbvp.geometry.Meridian`).
        h: reference thickness, in the geometry's unit, in (``H_MIN`` R_c, R_c) with R_c the
            reference's smallest radius of curvature (:attr:`curvature_radius`).
        lam: lambda*/mu* in (0, :func:`lam_max` (h / R_c)] (Ciarlet-Geymonat only: other
            materials refuse a value other than the default 1.0).
        model, material: as in :func:`shellbvp.energy_density`; ``model`` applies to
            ``material="cg"`` only (other materials refuse ``"plane_strain"``).
        ends: (first, second): :class:`End` or kind names; default ``("pole", "free")`` where
            the first end is on the axis, else ``("free", "free")``. An end on the axis must
            be a ``pole`` and a pole must be on the axis.
        fields: the stimulus ``fields(x, p[, c]) -> (g1, g2, kb1, kb2)`` of the reference
            point x (:class:`ReferencePoint`), or None (target = reference).
        through_thickness: ``(x, p[, c]) -> (rhob1, rhob2, rhob3)`` or None ((1, 0, 0)).
        thickness: ``t(x)``, the thickness profile (thickness h t, t > 0), or None (t = 1).
        field_parameters: numbers c the fields depend on besides p, passed to them as an
            array ``c`` (empty: fields take two arguments). They are arguments of the
            compiled programs, not constants folded into them: scenes that differ only in
            c share their compiled code (a sweep over a stimulus' amplitude compiles once).
        pressure: ``pressure(p) -> P``, a uniform follower pressure on the deformed surface,
            in mu* h / R, along -n (n the outward normal: positive P pushes a cap traced
            from its apex toward its centre of curvature), or None. Its potential P V, V the
            volume between the surface and the plane of its end, enters the energy
            (:mod:`shellbvp.euler_lagrange`): conservative for a closed shell and for ends
            whose plane is fixed (clamped, hinged, roller).
        breaks: interior interfaces of the piecewise fields (arclength), increasing, inside
            (0, L), not on a joint of the geometry.
        metric: whether the fields change the metric (g != 1).
        parameter: name of the scalar stimulus parameter p.
        parameter_unit: how p is made dimensionless, for column names: ``"R0"`` (p R0 for a
            curvature such as kappa), ``""`` (p is a pure number), or e.g.
            ``"R0_over_mu_h0"`` (a pressure, p R0 / (mu* h0)).
        nu: Poisson ratio of the Koiter reference model (``material="koiter"`` only).
        monitor: the observable that continuation follows and that a branch reports as
            ``w``: ``"uz"``, ``"ur"`` or ``"rotation"`` of an end, written
            ``"uz(second)"``, or the relative axial displacement ``"uz(second)-uz(first)"``
            (the default: the axial displacement of the end that does not fix z relative
            to the one that does; where both fix z, the radial displacement or rotation of
            an end free to make it; :attr:`monitor_terms`).
        rings: :class:`Ring` loads on circles of the meridian (dead forces), at distinct s
            inside (0, L); kept sorted by s.
        display: how messages quote the parameter and arclengths (:class:`Display`; a
            scene file's own units), the engine's units by default.
    """

    geometry: Meridian
    h: float
    lam: float = 1.0
    model: str = "relaxed"
    material: str = "cg"
    ends: tuple | None = None
    fields: Callable | None = None
    through_thickness: Callable | None = None
    thickness: Callable | None = None
    breaks: tuple = ()
    metric: bool = False
    parameter: str = "p"
    parameter_unit: str = ""
    nu: float = 0.5
    pressure: Callable | None = None
    field_parameters: tuple = ()
    monitor: str | None = None
    rings: tuple = ()
    display: Display = Display()

    def quote(self, p, digits: int = 6) -> str:
        """The parameter value p as a message says it: ``"kappa = 4.2"`` (in the user's
        units and name where :attr:`display` gives them)."""
        d = self.display
        unit = f" {d.parameter_unit}" if d.parameter_unit else ""
        return f"{d.parameter or self.parameter} = {d.parameter_scale * float(p):.{digits}g}{unit}"

    def quote_s(self, s, digits: int = 4) -> str:
        """An arclength s as a message says it: ``"s = 1.03"`` (in the user's length unit
        where :attr:`display` gives it)."""
        d = self.display
        unit = f" {d.length_unit}" if d.length_unit else ""
        return f"s = {d.length_scale * float(s):.{digits}g}{unit}"

    @property
    def material_parameter(self) -> float:
        """lam for cg, nu for koiter (the single material slot of the compiled functions)."""
        return material_parameter(self.material, self.lam, self.nu)

    def __post_init__(self):
        if not isinstance(self.geometry, Meridian):
            raise ValueError(f"geometry must be a shellbvp.geometry.Meridian, got "
                             f"{type(self.geometry).__name__}")
        geo = self.geometry
        Rc = self.curvature_radius
        checks.check_open_interval("h", self.h, H_MIN * Rc, Rc,
                                   f" (the thickness, below the reference's smallest radius "
                                   f"of curvature {Rc:.4g}; below {H_MIN:g} of it the edge "
                                   f"layer of width ~ sqrt(h R) is beyond every method's "
                                   f"resolution)")
        checks.check_choice("model", self.model, MODELS)
        checks.check_choice("material", self.material, MATERIALS)
        # a parameter the material does not use must stay at its default (absent): a value
        # that changes nothing is refused rather than silently ignored
        used = MATERIAL_PARAMETER[self.material]
        unused = [n for n in ("lam", "nu") if n != used] + \
            ([] if self.material == "cg" else ["model"])     # only the reduction has models
        for name in unused:
            if getattr(self, name) != SCENE_DEFAULTS[name]:
                raise ValueError(f"{name} = {getattr(self, name)!r} does not apply to material="
                                 f"{self.material!r} ({USES[self.material]}): leave {name} at "
                                 f"its default {SCENE_DEFAULTS[name]!r}")
        if self.material == "cg":
            checks.check_open_interval("lam", self.lam, 0.0, LAM_MAX,
                                       " (lambda*/mu*; beyond, the bulk term swamps the "
                                       "shear one in double precision: use material='nh' for "
                                       "an incompressible shell)")
            resolvable = lam_max(self.h / Rc)
            if self.lam > resolvable:
                raise ValueError(
                    f"lam = {self.lam:g} is beyond what double precision resolves at "
                    f"h = {self.h:g}: lam must lie in (0, {resolvable:.3g}] there "
                    f"({LAM_OVER_H2_MAX:g} (h/R_c)^2: the forces of the lam term carry "
                    f"round-off ~ lam eps and enter beside the moment scaled by 12/h^2). For "
                    f"a nearly incompressible shell use material='nh', the limit "
                    f"lam -> infinity (kappa_s of a cap approaches it like 1/lam)")
        if self.material == "koiter":
            checks.check_open_interval("nu", self.nu, -1.0, 1.0, " (Poisson ratio)")
        for name in ("parameter", "parameter_unit"):
            if not isinstance(getattr(self, name), str):
                raise ValueError(f"{name} must be a string, got {getattr(self, name)!r}")
        for name in ("fields", "through_thickness", "thickness", "pressure"):
            value = getattr(self, name)
            if value is not None and not callable(value):
                raise ValueError(f"{name} must be a function or None, got "
                                 f"{type(value).__name__}")
        self._check_ends(geo)
        b = np.asarray(self.breaks, dtype=float)
        if b.ndim != 1 or (b.size and (np.any(np.diff(b) <= 0) or b[0] <= 0
                                       or b[-1] >= geo.length or not np.all(np.isfinite(b)))):
            raise ValueError(f"breaks must increase strictly inside (0, {geo.length:.6g}) "
                             f"(arclength of the meridian), got {self.breaks!r}")
        near = [float(x) for x in b for j in geo.joints
                if abs(x - j) <= 1e-9 * geo.length]
        if near:
            raise ValueError(f"breaks {near} lie on joints of the geometry (already "
                             f"interfaces: {tuple(float(j) for j in geo.joints)})")
        object.__setattr__(self, "breaks", tuple(float(x) for x in b))
        c = np.asarray(self.field_parameters, dtype=float) \
            if isinstance(self.field_parameters, (tuple, list, np.ndarray)) else None
        if c is None or c.ndim != 1 or not np.all(np.isfinite(c)):
            raise ValueError(f"field_parameters must be a tuple of finite numbers, got "
                             f"{self.field_parameters!r}")
        object.__setattr__(self, "field_parameters", tuple(float(x) for x in c))
        self._check_rings(geo)
        if not isinstance(self.display, Display):
            raise ValueError(f"display must be a shellbvp.scene.Display, got "
                             f"{type(self.display).__name__}")
        if self.monitor is not None:
            self.monitor_terms            # parses and checks the monitor

    def _check_rings(self, geo):
        if not (isinstance(self.rings, (tuple, list))
                and all(isinstance(r, Ring) for r in self.rings)):
            raise ValueError(f"rings must be a tuple of shellbvp.Ring, got {self.rings!r}")
        L = geo.length
        rings = sorted(self.rings, key=lambda r: r.s)
        for ring in rings:
            if not 0.0 < ring.s < L:
                raise ValueError(f"ring s = {ring.s:g} lies outside the meridian's interior "
                                 f"(0, {L:.6g}): a load on an end is that End's (axial, "
                                 f"radial; force at a pole)")
            if min(ring.s, L - ring.s) <= 1e-9 * L:
                raise ValueError(f"ring s = {ring.s:g} lies on an end of the meridian "
                                 f"(to 1e-9 L): give the load as that End's")
        for a, b in zip(rings[:-1], rings[1:]):
            if b.s - a.s <= 1e-9 * L:
                raise ValueError(f"rings: two at s = {a.s:g}; give one ring with the sum of "
                                 f"their loads")
        object.__setattr__(self, "rings", tuple(rings))

    def _check_ends(self, geo):
        if self.ends is None:
            ends = ("pole" if geo.poles[0] else "free", "pole" if geo.poles[1] else "free")
        else:
            if not (isinstance(self.ends, (tuple, list)) and len(self.ends) == 2):
                raise ValueError(f"ends must be a pair (first, second), got {self.ends!r}")
            ends = tuple(self.ends)
        ends = tuple(_as_end(e, k) for k, e in zip(("first", "second"), ends))
        for which, end, pole in zip(("first", "second"), ends, geo.poles):
            if pole and end.kind != "pole":
                raise ValueError(f"the {which} end of the meridian is on the axis (r = 0): it "
                                 f"must be a 'pole', got {end.kind!r}")
            if end.kind == "pole" and not pole:
                r0 = geo.at_end(which)[0]
                raise ValueError(f"the {which} end is a 'pole' but lies at r = {r0:.6g}, not "
                                 f"on the axis: choose free, clamped, hinged, roller, "
                                 f"sliding, diaphragm or symmetry")
            if end.kind == "symmetry":
                theta0 = geo.at_end(which)[2]
                if abs(math.cos(theta0)) > 1e-9:
                    raise ValueError(
                        f"a symmetry end needs the reference tangent parallel to the axis "
                        f"there (a mirror plane normal to the axis); the {which} end's "
                        f"tangent makes {math.degrees(theta0):.6g} degrees with the plane")
        object.__setattr__(self, "ends", ends)
        for which, end, other in zip(("first", "second"), ends, ends[::-1]):
            if end.displacement is not None and not other.fixes_z:
                raise ValueError(f"the {which} end's prescribed displacement needs the other "
                                 f"end to hold z (clamped, hinged, roller, or a pole with a "
                                 f"displacement): on a free body it would move it rigidly, "
                                 f"against nothing")
        if not any(e.fixes_z for e in ends) and ends[0].force is not None:
            raise ValueError("the first end's point force would be taken by the reaction that "
                             "holds the first end's z (no end fixes the axial position, so "
                             "the first is held): put the force on the second end, where the "
                             "held first end balances it")

    # --- derived data ---------------------------------------------------------------------
    @property
    def length(self) -> float:
        """The meridian's arclength L."""
        return self.geometry.length

    @cached_property
    def curvature_radius(self) -> float:
        """The reference's smallest radius of curvature 1 / max |k_a| over the meridian (its
        length where it is flat): the length the thickness is small against."""
        return curvature_radius(self.geometry)

    @cached_property
    def shallowness(self) -> float:
        """T = L / sqrt(h R_c): the meridian's length in widths of the bending layer
        (Theta / sqrt(h) for a cap of the unit sphere), which sets the resolution the
        methods need."""
        return self.length / math.sqrt(self.h * self.curvature_radius)

    @cached_property
    def pinned(self) -> int | None:
        """The end (0 first, 1 second) whose axial position is held to remove the axial
        translation where no end fixes z (the first; its axial force is then a reaction,
        zero when the loads balance), or None."""
        return None if any(e.fixes_z for e in self.ends) else 0

    @cached_property
    def z_anchor(self) -> int:
        """The end (0 first, 1 second) whose axial position stays at its reference's: one
        held without a prescribed displacement, the first where none or both are; the
        other end's z is it -+ the meridian's drop."""
        held = [e.fixes_z and e.displacement is None for e in self.ends]
        return 1 if held[1] and not held[0] else 0

    @cached_property
    def monitor_terms(self) -> tuple:
        """The monitor as ((coefficient, component, end), ...), components ``"z"``,
        ``"r"``, ``"theta"`` of the displacement from the reference at end 0 (first) or 1
        (second); default (:attr:`monitor` None): the axial displacement of the end that does
        not fix z relative to one that does (the pinned end counting as fixed), or of the
        second end relative to the first."""
        if self.monitor is None:
            fixed = [e.fixes_z for e in self.ends]
            if self.pinned is not None:
                fixed[self.pinned] = True
            if fixed == [True, False]:
                return ((1.0, "z", 1), (-1.0, "z", 0))
            if fixed == [False, True]:
                return ((1.0, "z", 0), (-1.0, "z", 1))
            # both ends hold z: the radial displacement of an end that leaves r free, else
            # the rotation of one that leaves theta free (a clamped-clamped shell has no end
            # that moves: give a monitor, or observe an interior point in a scene file)
            for comp, holds in (("r", ("clamped", "hinged", "pole", "diaphragm")),
                                ("theta", ("clamped", "symmetry", "pole", "sliding"))):
                for end in (1, 0):
                    if self.ends[end].kind not in holds:
                        return ((1.0, comp, end),)
            return ((1.0, "z", 1), (-1.0, "z", 0))
        return _parse_monitor(self.monitor)

    @cached_property
    def monitor_scale(self) -> float:
        """The length the monitor is measured in (continuation steps in its units): the
        reference's rise |z0(L) - z0(0)| (1 - cos Theta for a cap), or the thickness where
        the meridian has no rise (a plate, an annulus)."""
        rise = self.geometry.rise
        return rise if rise > 1e-12 * self.geometry.size else float(self.h)

    @property
    def parameter_column(self) -> str:
        """The parameter's column name with its unit, e.g. ``kappa_R0``, ``kbar``."""
        return f"{self.parameter}_{self.parameter_unit}" if self.parameter_unit \
            else self.parameter

    @cached_property
    def interfaces(self) -> np.ndarray:
        """Every interior interface of the pieces, in s: the joints of the geometry, the
        breaks of the fields and the rings' circles, merged."""
        known = sorted(tuple(float(j) for j in self.geometry.joints) + self.breaks)
        tol = 1e-9 * self.length
        extra = [r.s for r in self.rings if not any(abs(r.s - x) <= tol for x in known)]
        return np.array(sorted(known + extra))

    @cached_property
    def ring_interfaces(self) -> tuple:
        """The interface (index into :attr:`interfaces`) each ring of :attr:`rings` loads."""
        x = self.interfaces
        return tuple(int(np.argmin(np.abs(x - r.s))) for r in self.rings)

    @cached_property
    def pieces(self) -> int:
        return len(self.interfaces) + 1

    @cached_property
    def piece_ends(self) -> np.ndarray:
        """The ends of the pieces in s, (P + 1,): 0, the interfaces (joints and breaks),
        L."""
        return np.concatenate([[0.0], self.interfaces, [self.length]])

    @cached_property
    def piece_segments(self) -> tuple:
        """The index of the geometry's segment each piece lies on."""
        ends = self.piece_ends
        mid = 0.5 * (ends[:-1] + ends[1:])
        starts = np.asarray(self.geometry.segment_starts, dtype=float)
        return tuple(int(k) for k in np.searchsorted(starts, mid, side="right") - 1)

    @property
    def through_thickness_stimulus(self) -> bool:
        return self.through_thickness is not None

    @property
    def varying_thickness(self) -> bool:
        return self.thickness is not None

    @property
    def uses_metric(self) -> bool:
        """Whether the compiled equations need the g terms (a metric stimulus)."""
        return bool(self.metric)

    def with_length(self, length: float) -> "Scene":
        """The same scene on the meridian extended or shortened at its second end
        (:meth:`shellbvp.geometry.Meridian.with_length`): a cap of another opening angle."""
        return dataclasses.replace(self, geometry=self.geometry.with_length(float(length)))

    def field_values(self, piece, s, p):
        """(g1, g2, kb1, kb2) on piece ``piece`` at s and parameter p (numpy)."""
        from . import kinematics as K

        F = point_fields(self, piece, np.asarray(s, dtype=float), p,
                         np.asarray(self.field_parameters), np)
        return F[K.G1], F[K.G2], F[K.KB1], F[K.KB2]

    def fields_admissible(self, F) -> bool:
        """Whether field values F (..., k), the fields (:data:`shellbvp.kinematics.FIELDS`)
        along the last axis, are all admissible (finite, g > 0 and g = 1 without metric
        stimulus, the thickness profile and rhob1 > 0 where the scene gives them): the cheap
        test of every evaluation; :meth:`check_fields` names what fails."""
        g = F[..., :2]
        ok = ((g > 0) if self.metric else (g == 1)).all() and np.isfinite(F).all()
        if ok and self._positive_fields and F.shape[-1] > 7:
            ok = (F[..., self._positive_fields] > 0).all()
        return bool(ok)

    @cached_property
    def _positive_fields(self) -> list:
        """The fields beyond g that must be positive and are not constant: the thickness
        profile t and rhob1, where the scene gives them."""
        return ([6] if self.thickness is not None else []) + \
            ([7] if self.through_thickness is not None else [])

    def check_fields(self, out, piece, p, *, interior=False):
        """Raise a named ValueError unless the fields F (:data:`shellbvp.kinematics.FIELDS`
        along the first axis) are admissible; ``interior``: F at interior points only (the
        energy method's quadrature), where a thickness vanishing at an end is allowed."""
        from .kinematics import FIELDS

        F = np.asarray(out, dtype=float)
        if self.fields_admissible(F.T):
            return out      # the common case, checked at once
        for n, v in zip(FIELDS, F):
            if not np.all(np.isfinite(v)):
                raise ValueError(f"field {n} must be finite (piece {piece}, "
                                 f"{self.quote(p)})")
        if np.any(F[0] <= 0) or np.any(F[1] <= 0):
            raise ValueError("stimulus fields g1, g2 must be > 0")
        if len(F) > 6 and np.any(F[6] <= 0) and interior:
            raise ValueError(f"the thickness profile must be > 0 inside the shell (piece "
                             f"{piece}, {self.quote(p)})")
        if len(F) > 6 and np.any(F[6] <= 0):
            raise ValueError(f"the thickness profile must be > 0 along the meridian (piece "
                             f"{piece}): the first-order form divides by the bending "
                             f"stiffness; for a thickness that vanishes at an end use "
                             f"method='energy' (direct minimisation), or give a small positive "
                             f"thickness there")
        if len(F) > 7 and np.any(F[7] <= 0):
            raise ValueError("through-thickness stimulus rhob1 must be > 0")
        raise ValueError("the scene has metric=False but its fields give g1 or g2 != 1")


@lru_cache(maxsize=256)
def curvature_radius(geometry: Meridian) -> float:
    """1 / max |k_a| of the reference over a sample of every segment (both principal
    curvatures, :meth:`shellbvp.geometry.Meridian.curvatures`), or the meridian's length
    where it is flat everywhere."""
    starts = geometry.segment_starts
    kmax = 0.0
    for k, seg in enumerate(geometry.segments):
        s = starts[k] + seg.length * np.linspace(0.0, 1.0, 65)
        s[-1] = np.nextafter(s[-1], -np.inf) if k < len(geometry.segments) - 1 else s[-1]
        k1, k2 = geometry.curvatures(s)
        kmax = max(kmax, float(np.max(np.abs(k1))), float(np.max(np.abs(k2))))
    return 1.0 / kmax if kmax > 0 else float(geometry.length)


def _parse_monitor(text) -> tuple:
    """``"uz(second)"``, ``"ur(first)"``, ``"rotation(second)"`` or a difference of two such
    -> ((coefficient, component, end), ...)."""
    comps = {"uz": "z", "ur": "r", "rotation": "theta"}
    ends = {"first": 0, "second": 1}
    if not isinstance(text, str):
        raise ValueError(f"monitor must be a string such as 'uz(second)', got {text!r}")
    terms, sign, rest = [], 1.0, text.replace(" ", "")
    while rest:
        for name in comps:
            for end in ends:
                token = f"{name}({end})"
                if rest.startswith(token):
                    terms.append((sign, comps[name], ends[end]))
                    rest = rest[len(token):]
                    break
            else:
                continue
            break
        else:
            raise ValueError(f"monitor {text!r}: expected uz, ur or rotation of first or "
                             f"second, e.g. 'uz(second)' or 'uz(second)-uz(first)'")
        if rest:
            if rest[0] not in "+-" or len(terms) >= 2:
                raise ValueError(f"monitor {text!r}: at most a difference or sum of two end "
                                 f"values, e.g. 'uz(second)-uz(first)'")
            sign, rest = (1.0 if rest[0] == "+" else -1.0), rest[1:]
    return tuple(terms)


def cap(theta, h, *, ends=("pole", "free"), fields=uniform_curvature, parameter="kappa",
        parameter_unit="R0", **kwargs) -> Scene:
    """A spherical cap of the unit sphere (lengths in its radius R0), opening half-angle
    theta, traced from its apex (at z = 0) to its edge: by default the everting cap of the
    paper's Section 5.2 (apex a pole, free edge, stimulus :func:`uniform_curvature` in
    kappa). Keyword arguments are the :class:`Scene`'s; ``theta`` must lie in
    (``THETA_MIN``, pi)."""
    checks.check_open_interval("theta", theta, THETA_MIN, math.pi,
                               " (opening half-angle Theta in radians; below "
                               f"{THETA_MIN:g} the rise 1 - cos Theta is lost to round-off)")
    return Scene(geometry=spherical_cap(theta), h=h, ends=ends, fields=fields,
                 parameter=parameter, parameter_unit=parameter_unit, **kwargs)


#: the defaults of the material-dependent fields (Scene's own), which mean "absent" where a
#: material does not use them
SCENE_DEFAULTS = {f.name: f.default for f in dataclasses.fields(Scene)
                  if f.name in ("lam", "nu", "model")}
