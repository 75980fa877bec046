"""The kinematic map of an axisymmetric shell, written once: from the reference and target
shells and the current meridian to the principal stretches and curvatures, and from those to
the energy per unit length of the meridian.

Every stage uses these functions: the symbolic Euler-Lagrange derivation (with sympy),
the compiled first-order system, the direct minimisation of the energy and both second
variations (with jax.numpy), and the post-processing of a solved meridian (with numpy).
They are pure arithmetic, so the array module ``xp`` (``numpy``, ``jax.numpy`` or
``sympy``) only supplies ``sin``.

Conventions (paper Section 2; DESIGN notes section 12). The reference meridian is traced by
its arclength s, so its first form is a° = diag(1, r0^2); the current meridian has tangent
angle theta (``(r', z') = Lambda (cos theta, -sin theta)``, Lambda = |x'| its speed), and
the target forms are abar = diag(g1^2, g2^2 r0^2), bbar_aa = kb_a abar_aa. Then

    lam1 = Lambda / g1,   lam2 = r / (g2 r0),   k1 = -theta' / Lambda,   k2 = -sin(theta) / r

(stretches relative to the target metric, principal curvatures with the outward normal
n = (sin theta, cos theta) in (r, z): the unit sphere traced from its top pole has
k1 = k2 = -1), and the target area element per ds domega is g1 g2 r0. The energy per unit
length of the meridian and radian of azimuth, per mu* h R^2 (h the scene's reference
thickness, R its length unit), is

    t W(lam1, lam2, k1, k2; kb1, kb2, h t, rhob) g1 g2 r0

with t = h(s) / h the thickness profile and W the reduced energy per unit target area and
unit thickness (:mod:`shellbvp.reduction`), evaluated at the local thickness h t.

The fields of a point are carried as one vector F (:data:`FIELDS`): the target (g1, g2,
kb1, kb2), the pressure, the reference radius r0, the thickness profile t and the
through-thickness stimulus (rhob1, rhob2, rhob3).
"""

from __future__ import annotations

__all__ = ["FIELDS", "N_FIELDS", "G1", "G2", "KB1", "KB2", "PRESSURE", "R0", "THICKNESS",
           "RHOB", "principal_state", "area_factor", "target_forms", "target_matrices",
           "energy_per_length",
           "W_ARGUMENTS"]

#: the fields of a point of the meridian, in the order of the vector F every stage passes
FIELDS = ("g1", "g2", "kb1", "kb2", "pressure", "r0", "thickness", "rhob1", "rhob2",
          "rhob3")
N_FIELDS = len(FIELDS)
G1, G2, KB1, KB2, PRESSURE, R0, THICKNESS = range(7)
#: the slice of F holding (rhob1, rhob2, rhob3)
RHOB = slice(7, 10)
#: the arguments of every compiled reduced energy W, in this order
W_ARGUMENTS = ("lam1", "lam2", "k1", "k2", "kb1", "kb2", "material_parameter", "h",
               "rhob1", "rhob2", "rhob3")


def principal_state(r, theta, speed, dtheta, r0, g1, g2, xp):
    """(lam1, lam2, k1, k2) of the current meridian at a point: radius r, tangent angle
    theta, speed Lambda = |x'| (``speed``) and theta' = d theta / ds (``dtheta``), over the
    reference radius r0 and the target stretch factors g1, g2 (module docstring)."""
    return speed / g1, r / (g2 * r0), -dtheta / speed, -xp.sin(theta) / r


def area_factor(F):
    """The target area per ds domega times the thickness profile, t g1 g2 r0, from the
    fields F (:data:`FIELDS`, along the first axis): what multiplies the energy per unit
    target area and thickness W to give the energy per unit length of the meridian."""
    return F[THICKNESS] * F[G1] * F[G2] * F[R0]


def target_forms(F):
    """The diagonal entries of the target forms in the coordinates (s, omega):
    ((abar_11, abar_22), (bbar_11, bbar_22)) = ((g1^2, g2^2 r0^2), (kb1 g1^2, kb2 g2^2 r0^2))
    (the reference meridian is parametrised by arclength)."""
    a11, a22 = F[G1] ** 2, (F[G2] * F[R0]) ** 2
    return (a11, a22), (F[KB1] * a11, F[KB2] * a22)


def target_matrices(F, change=None):
    """(abar, bbar, area) for the reduced energy of general forms
    (:func:`shellbvp.forms.reduced_energy`): the target forms as 2 x 2 matrices in (s, omega)
    (JAX) and the area factor t sqrt(det abar). ``change``: the six numbers (da11, da12,
    da22, db11, db12, db22) added to the forms where the reference surface departs from a
    surface of revolution (an imperfection, :meth:`shellbvp.fourier2d.Fourier2D.imperfect`);
    None for the axisymmetric target (diagonal forms, :func:`area_factor`)."""
    import jax.numpy as jnp

    (a11, a22), (b11, b22) = target_forms(F)
    if change is None:
        return (jnp.array([[a11, 0.0], [0.0, a22]]), jnp.array([[b11, 0.0], [0.0, b22]]),
                area_factor(F))
    d = change
    abar = jnp.array([[a11 + d[0], d[1]], [d[1], a22 + d[2]]])
    bbar = jnp.array([[b11 + d[3], d[4]], [d[4], b22 + d[5]]])
    area = F[THICKNESS] * jnp.sqrt(abar[0, 0] * abar[1, 1] - abar[0, 1] ** 2)
    return abar, bbar, area


def energy_per_length(W, X, F, material_parameter, h):
    """t W(X; kb, h t, rhob) g1 g2 r0: the energy per unit length of the meridian and radian
    (per mu* h R^2) at principal state X = (lam1, lam2, k1, k2), fields F (:data:`FIELDS`),
    with W a compiled reduced energy taking :data:`W_ARGUMENTS`."""
    rb = RHOB.start
    return area_factor(F) * W(X[0], X[1], X[2], X[3], F[KB1], F[KB2], material_parameter,
                              h * F[THICKNESS], F[rb], F[rb + 1], F[rb + 2])
