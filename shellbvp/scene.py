"""Scenes as data: geometry, stimulus fields, material and boundary conditions (paper Section 5).

A :class:`Scene` describes a spherical cap of reference radius R0 = 1 (meridional angle
s in [0, theta], apex s = 0 on the axis), thickness h = h0/R0, and a stimulus given as fields
on s that may be piecewise (``breaks`` are the interior interfaces, treated exactly as a
multi-point problem) and may depend on one named scalar parameter (``parameter``, e.g.
``"kappa"``). ``fields(piece, s, p)`` returns (g1, g2, kb1, kb2) on piece ``piece``:
target stretch factors abar_11 = g1^2 a°_11, abar_22 = g2^2 a°_22 and target curvatures
kb_a = bbar_aa / abar_aa, in 1/R0; with ``field_parameters`` c, ``fields(piece, s, p, c)``
(numbers the compiled code takes as arguments). A uniform external pressure
``pressure(p)`` may load it. Fields must use array arithmetic only (they are traced by
JAX). A scene with ``metric=False`` promises g1 = g2 = 1 and gets
Euler-Lagrange equations without g terms.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

from . import checks
from .models import MATERIAL_PARAMETER, MATERIALS, MODELS, material_parameter

__all__ = ["Scene", "APEX", "EDGE", "uniform_curvature", "lam_max"]

#: smallest opening angle: the rise 1 - cos Theta ~ Theta^2/2 keeps ~10 digits above it
THETA_MIN = 1e-3
#: smallest thickness: the edge layer (width ~ sqrt(h) R0) then needs ~ 6 Theta/sqrt(h)
#: Chebyshev nodes, at the upper end of what the methods take
H_MIN = 1e-6
#: largest lambda*/mu*: lam = 1e8 is Poisson ratio 0.5 - 5e-9
LAM_MAX = 1e8
#: largest lam / h**2 admitted (Ciarlet-Geymonat): the forces of the lam term carry
#: round-off ~ lam eps and enter the equations beside the moment scaled by 12 / h**2, so
#: Newton stalls once lam eps 12 / h**2 is too large. Measured at tol 1e-8 (relaxed):
#: Theta = pi/6 resolves lam / h**2 = 3e9 at h = 1e-3, 3e-3 and 1e-2 and stalls at 1e10
#: for all three (lam = 1e4, 1e5, 1e6); Theta = pi/3, h = 0.1 resolves 1e9 and fails at
#: 2.5e9 (the inner (lam1, k1) Newton at the fold); Theta = 0.05, h = 1e-4 resolves 3e10 and
#: stalls at 1e11; Theta = 1.5, h = 0.03 resolves 3.3e9; Theta = 0.2, h = 3e-3 stalls at
#: 5.6e9 (no simple law in Theta or T fits all seven). The fence is the largest value
#: resolved anywhere: beyond it nothing measured resolves; below it a cap that does not
#: ends in a ConvergenceError that names the same remedy (driver.follow), rather than a
#: refused case that would have worked.
LAM_OVER_H2_MAX = 3e10
#: what each material uses (for the error of a parameter it does not)
USES = {"cg": "it uses lam and model", "nh": "incompressible: no material parameter, and "
        "J = 1 fixes the through-thickness stretch, so there is no model choice",
        "koiter": "it uses nu; it is a reference energy, not a reduction with models"}
APEX = ("held", "free")   # held: z(0) = 0 (vertical point force allowed); free: F_z = 0
EDGE = ("free", "clamped")


def lam_max(h: float) -> float:
    """The largest lam = lambda*/mu* a Ciarlet-Geymonat scene of thickness h = h0/R0 admits:
    ``min(LAM_MAX, LAM_OVER_H2_MAX h**2)`` (3e6 at h = 0.01, 3e4 at h = 1e-3), where the
    round-off of the lam term's forces, ~ lam eps 12 / h**2 relative to the moment, leaves
    no cap measured resolvable (see ``LAM_OVER_H2_MAX``: from 1/30 of it some caps stall,
    with a ConvergenceError). Beyond it a nearly incompressible shell is
    ``material='nh'``."""
    return min(LAM_MAX, LAM_OVER_H2_MAX * h * h)


def uniform_curvature(piece, s, kappa):
    """The cap-eversion stimulus abar = a°, bbar = b° + kappa a°: kb1 = kb2 = kappa - 1.

    Written with arithmetic only, so that it works on numpy and JAX arrays alike (the
    shooting back-end traces the fields inside its vector field).
    """
    one = 0.0 * s + 1.0
    return one, one, (kappa - 1.0) * one, (kappa - 1.0) * one


def call_fields(fields, piece, s, p, c):
    """``fields(piece, s, p, c)``, or ``fields(piece, s, p)`` where the field parameters c
    are empty: the one place that decides how a scene's fields are called (by NumPy or
    traced by JAX, c then an array of static length)."""
    return fields(piece, s, p, c) if len(c) else fields(piece, s, p)


@dataclass(frozen=True)
class Scene:
    """A spherical cap problem (all lengths in R0).

    Attributes:
        theta: opening half-angle Theta in (0, pi).
        h: thickness h0/R0 in (0, 1).
        lam: lambda*/mu* in (0, :func:`lam_max` (h)] (Ciarlet-Geymonat only: other
            materials refuse a value other than the default 1.0); at most 1e8 and at most
            3e10 h^2, beyond which the lam term's round-off swamps the bending equations.
        model, material: as in :func:`shellbvp.energy_density`; ``model`` applies to
            ``material="cg"`` only (other materials refuse ``"plane_strain"``).
        rhob1: through-thickness stimulus (> 0; rhob2 = rhob3 = 0).
        apex: ``"held"`` (z(0) = 0) or ``"free"`` (no point force at the apex, F_z = 0).
        edge: ``"free"`` (M = F_r = F_z = 0) or ``"clamped"`` (r, z, theta at reference values).
        fields: ``fields(piece, s, p) -> (g1, g2, kb1, kb2)``, or
            ``fields(piece, s, p, c)`` with ``field_parameters``.
        field_parameters: numbers c the fields depend on besides p, passed to them as an
            array ``c`` (empty: fields take three arguments). They are arguments of the
            compiled programs, not constants folded into them: scenes that differ only in
            c share their compiled code (a sweep over a stimulus' amplitude or anisotropy
            compiles once).
        pressure: ``pressure(p) -> P``, a uniform external pressure on the deformed surface
            in mu* h0 / R0 (a follower load; positive toward the centre of curvature of the
            undeformed cap, i.e. pushing the apex down), or None (no load). Its potential
            P V, with V the volume between the surface and the plane of its edge, enters
            the energy (:mod:`shellbvp.euler_lagrange`); meaningful with a clamped edge,
            whose plane is fixed. Array arithmetic only, like ``fields``.
        breaks: interior interfaces of the piecewise fields, increasing, inside (0, theta).
        metric: whether the fields change the metric (g != 1).
        parameter: name of the scalar stimulus parameter p.
        parameter_unit: how p is made dimensionless, for column names: ``"R0"`` (the
            default, p R0 for a curvature such as kappa), ``""`` (p is a pure number, e.g.
            budding's kbar), or e.g. ``"R0_over_mu_h0"`` (a pressure, p R0 / (mu* h0)).
        nu: Poisson ratio of the Koiter reference model (``material="koiter"`` only: other
            materials refuse a value other than the default 0.5).
    """

    theta: float
    h: float
    lam: float = 1.0
    model: str = "relaxed"
    material: str = "cg"
    rhob1: float = 1.0
    apex: str = "held"
    edge: str = "free"
    fields: Callable = uniform_curvature
    breaks: tuple = ()
    metric: bool = False
    parameter: str = "kappa"
    parameter_unit: str = "R0"
    nu: float = 0.5
    pressure: Callable | None = None
    field_parameters: tuple = ()

    @property
    def material_parameter(self) -> float:
        """lam for cg, nu for koiter (the single material slot of the compiled functions)."""
        return material_parameter(self.material, self.lam, self.nu)

    def __post_init__(self):
        checks.check_open_interval("theta", self.theta, THETA_MIN, math.pi,
                                    " (opening half-angle Theta in radians; below "
                                    f"{THETA_MIN:g} the rise 1 - cos Theta is lost to round-off)")
        checks.check_open_interval("h", self.h, H_MIN, 1.0,
                                   f" (h = h0/R0, h0 < R0; below {H_MIN:g} the edge layer of "
                                   f"width ~ sqrt(h) is beyond every method's resolution)")
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
            resolvable = lam_max(self.h)
            if self.lam > resolvable:
                raise ValueError(
                    f"lam = {self.lam:g} is beyond what double precision resolves at "
                    f"h = {self.h:g}: lam must lie in (0, {resolvable:.3g}] there "
                    f"({LAM_OVER_H2_MAX:g} h^2: the forces of the lam term carry round-off "
                    f"~ lam eps and enter beside the moment scaled by 12/h^2). For a nearly "
                    f"incompressible shell use material='nh', the limit lam -> infinity "
                    f"(kappa_s of a cap approaches it like 1/lam)")
        if self.material == "koiter":
            checks.check_open_interval("nu", self.nu, -1.0, 1.0, " (Poisson ratio)")
        checks.check_positive("rhob1", self.rhob1)
        for name in ("parameter", "parameter_unit"):
            if not isinstance(getattr(self, name), str):
                raise ValueError(f"{name} must be a string, got {getattr(self, name)!r}")
        checks.check_choice("apex", self.apex, APEX)
        checks.check_choice("edge", self.edge, EDGE)
        if self.pressure is not None and not callable(self.pressure):
            raise ValueError(f"pressure must be a callable p -> pressure or None, got "
                             f"{type(self.pressure).__name__}")
        b = np.asarray(self.breaks, dtype=float)
        if b.size and (np.any(np.diff(b) <= 0) or b[0] <= 0 or b[-1] >= self.theta
                       or not np.all(np.isfinite(b))):
            raise ValueError(f"breaks must increase strictly inside (0, theta), "
                             f"got {self.breaks!r}")
        object.__setattr__(self, "breaks", tuple(float(x) for x in b))
        c = np.asarray(self.field_parameters, dtype=float) \
            if isinstance(self.field_parameters, (tuple, list, np.ndarray)) else None
        if c is None or c.ndim != 1 or not np.all(np.isfinite(c)):
            raise ValueError(f"field_parameters must be a tuple of finite numbers, got "
                             f"{self.field_parameters!r}")
        object.__setattr__(self, "field_parameters", tuple(float(x) for x in c))

    @property
    def parameter_column(self) -> str:
        """The parameter's column name with its unit, e.g. ``kappa_R0``, ``kbar``."""
        return f"{self.parameter}_{self.parameter_unit}" if self.parameter_unit \
            else self.parameter

    @property
    def pieces(self) -> int:
        return len(self.breaks) + 1

    def field_values(self, piece, s, p):
        """(g1, g2, kb1, kb2) on piece ``piece`` at s and parameter p: ``fields`` called
        with the scene's ``field_parameters`` where it has any."""
        return call_fields(self.fields, piece, s, p, np.asarray(self.field_parameters))

    def fields_admissible(self, F) -> bool:
        """Whether field values F (..., k), (g1, g2, kb1, kb2[, pressure]) along the last
        axis, are all admissible (finite, g > 0, g = 1 without metric stimulus): the cheap
        test of every evaluation; :meth:`check_fields` names what fails."""
        g = F[..., :2]
        # g == 1 (no metric stimulus) or g > 0 is False for nan: one pass over g, one over F
        return bool(((g > 0) if self.metric else (g == 1)).all() and np.isfinite(F).all())

    def check_fields(self, out, piece, p):
        """Raise a named ValueError unless the fields (g1, g2, kb1, kb2[, pressure]) are
        admissible."""
        F = np.asarray(out, dtype=float)
        if self.fields_admissible(F.T):
            return out      # the common case, checked at once
        names = ("g1", "g2", "kb1", "kb2", "pressure")
        for n, v in zip(names, F):
            if not np.all(np.isfinite(v)):
                raise ValueError(f"stimulus field {n} must be finite (piece {piece}, "
                                 f"{self.parameter} = {p!r})")
        if np.any(F[0] <= 0) or np.any(F[1] <= 0):
            raise ValueError("stimulus fields g1, g2 must be > 0")
        raise ValueError("the scene has metric=False but its fields give g1 or g2 != 1")


#: the defaults of the material-dependent fields (Scene's own), which mean "absent" where a
#: material does not use them
SCENE_DEFAULTS = {f.name: f.default for f in dataclasses.fields(Scene)
                  if f.name in ("lam", "nu", "model")}
