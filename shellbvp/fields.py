"""The fields of a scene at points of its meridian, written once: the reference point from the
geometry, the scene's stimulus, thickness profile, through-thickness stimulus and pressure,
stacked as the vector F of :data:`shellbvp.kinematics.FIELDS` that every stage consumes
(the compiled first-order system, the direct minimisation, both second variations, the
post-processing).

The same code runs with numpy on the host and traced by JAX inside the compiled programs
(the array module ``xp``); the piece is a Python int, so each piece's segment of the
geometry and each piece's branch of the fields is chosen when the program is traced.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .geometry import AXIS_TOL

__all__ = ["ReferencePoint", "call_fields", "point_fields", "reference_point",
           "interface_jumps", "parameter_fields"]


class ReferencePoint(NamedTuple):
    """A point of the reference meridian, as the scene's fields see it: the piece it lies
    on (a Python int, so that fields may branch on it), its arclength s, its position
    (r, z), tangent angle theta (``(r', z') = (cos theta, -sin theta)``) and principal
    curvatures k1 (meridional) and k2 (hoop) with the outward normal
    (:mod:`shellbvp.kinematics`; the unit sphere traced from its top pole has
    k1 = k2 = -1). Arrays (numpy, or traced by JAX) shaped like s."""

    piece: int
    s: object
    r: object
    z: object
    theta: object
    k1: object
    k2: object


def call_fields(fields, x, p, c):
    """``fields(x, p, c)``, or ``fields(x, p)`` where the field parameters c are empty: the
    one place that decides how a scene's fields are called (by NumPy or traced by JAX, c
    then an array of static length)."""
    return fields(x, p, c) if len(c) else fields(x, p)




def interface_jumps(scene) -> np.ndarray:
    """(P - 1, 6): the jump of the unknowns (r, z, theta, m, f_r, f_z) across each interface,
    right minus left: the geometry's kink angle in theta at a joint (the joint is rigid: the
    deformed tangent turns by the reference's angle), zero at a break of the fields."""
    geo = scene.geometry
    out = np.zeros((scene.pieces - 1, 6))
    for i, x in enumerate(scene.interfaces):
        for j, kink in zip(geo.joints, geo.kinks):
            if abs(x - j) <= 1e-12 * scene.length:
                out[i, 2] = kink
    return out


def reference_point(scene, piece: int, s, xp=np) -> ReferencePoint:
    """The reference point (:class:`shellbvp.scene.ReferencePoint`) at arclength s on piece
    ``piece``: the piece's segment evaluated at its local arclength; the hoop curvature
    k2 = -sin(theta) / r with its limit k1 on the axis."""
    k = scene.piece_segments[piece]
    seg = scene.geometry.segments[k]
    r, z, theta, k1 = seg.evaluate(s - scene.geometry.segment_starts[k], xp)
    theta = theta + scene.geometry.theta_offsets[k]      # theta0 continuous but at kinks
    # on the axis to the meridian's tolerance (a pole's r0 is round-off, not 0, where the
    # segment's parametrisation ends at an angle such as pi): the pole limit k2 = k1
    on_axis = r <= AXIS_TOL * scene.geometry.size
    k2 = xp.where(on_axis, k1, -xp.sin(theta) / xp.where(on_axis, 1.0, r))
    return ReferencePoint(piece, s, r, z, theta, k1, k2)


def parameter_fields(scene) -> tuple[int, ...]:
    """The indices of F (:func:`point_fields`) that may depend on the parameter p: the target
    where the scene has a stimulus, the pressure where it has one, the through-thickness
    stimulus where it has one (the reference radius and the thickness profile never do). A
    derivative in p need not be taken in the others."""
    from . import kinematics as K

    out = list(range(K.G1, K.KB2 + 1)) if scene.fields is not None else []
    out += [K.PRESSURE] if scene.pressure is not None else []
    out += list(range(K.RHOB.start, K.RHOB.stop)) if scene.through_thickness is not None \
        else []
    return tuple(out)


def _broadcast(v, s, xp):
    return xp.asarray(v, dtype=float) + 0.0 * s


def point_fields(scene, piece: int, s, p, c, xp=np):
    """F (:data:`shellbvp.kinematics.FIELDS` along the first axis, then the shape of s) at
    arclength s on piece ``piece`` and parameter p, field parameters c: (g1, g2, kb1, kb2)
    from the scene's stimulus (the reference's curvatures and g = 1 without one), the
    pressure, the reference radius r0, the thickness profile t and (rhob1, rhob2, rhob3)."""
    x = reference_point(scene, piece, s, xp)
    one = _broadcast(1.0, s, xp)
    if scene.fields is None:
        target = (one, one, x.k1 + 0.0 * s, x.k2 + 0.0 * s)
    else:
        target = call_fields(scene.fields, x, p, c)
    rhob = (one, 0.0 * one, 0.0 * one) if scene.through_thickness is None else \
        call_fields(scene.through_thickness, x, p, c)
    t = one if scene.thickness is None else scene.thickness(x)
    load = 0.0 if scene.pressure is None else scene.pressure(p)
    return xp.stack([_broadcast(v, s, xp) for v in (*target, load, x.r, t, *rhob)])
