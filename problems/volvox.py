"""Volvox: the initiation of inversion of a spherical embryo by a bend region of wedged cells
and a contracting posterior hemisphere (after Höhn, Honerkamp-Smith, Haas, Trong &
Goldstein, Phys. Rev. Lett. 114, 178101, 2015, and Haas & Goldstein, J. R. Soc. Interface
12, 20150671, 2015).

Sources. The stored copies of these papers hold their first pages (title and abstract)
only: no equation, parameter value or figure of them could be read. What the scene takes
from them is what their abstracts say: inversion of V. globator is described by the
deformations of an elastic shell under local variations of its intrinsic curvatures and
stretches (Höhn et al.), and appropriate local deformations overcome global constraints
to initiate it (Haas & Goldstein); the bend region, the posterior contraction and the
anterior stretch below are that description's three cell-shape changes. Every number
below is this module's own choice, stated as such.

Geometry: a closed sphere of radius R (lengths in R, so R = 1), thickness h (default 0.1),
traced from its anterior pole (the first end, s = 0, on top) to its posterior pole (the
second, s = pi). The phialopore, the opening at the anterior pole, is left out: the sheet
is closed (both ends are poles; the anterior pole's height is held, the one rigid motion).

Regions (exact interfaces at the breaks s1 < s2): the anterior s < s1, the bend region
s1 < s < s2, the posterior s > s2; default a bend region of width ``BEND_WIDTH`` centred on
the equator.

Stimulus (:func:`cell_shapes`): in each region a target stretch g (isotropic, g1 = g2) and a
target curvature k (isotropic, kb1 = kb2, in 1/R; the sphere has -1 with the outward
normal), each reached linearly in the stage p of the process from the undeformed sheet at
p = 0 (g = 1, k = -1) to the region's values at p = 1:

    g(p) = 1 + p (g_region - 1),   k(p) = -1 + p (k_region + 1).

Defaults: the bend region's cells wedge to k_bend = -10/R (a lip ten times as curved as the
sphere, the same way: the sheet turns by |k_bend| W ~ 3.5 rad across it), the posterior
cells contract to g_post = 0.8 (the anterior's stay, g_ant = 1), the other curvatures
unchanged. With a uniform stretch g and curvature -1/g everywhere the target is a sphere of
radius g R, an exact stress-free state (the tests' closed form).

Material: the Koiter shell with nu = 1/2 (default), or the reduced energies derived from
3D (``material="nh"``, ``"cg"``).

Observable w: the invagination, the axial displacement of the posterior pole toward the
anterior one (``uz(second) - uz(first)``, positive as the posterior moves in). The
process starts where the branch in p from the sphere first folds: the sheet snaps into the
invaginated state (:func:`branch`, ``n_folds=1``).
"""

from __future__ import annotations

import math

import shellbvp

__all__ = ["scene", "cell_shapes", "branch", "BEND_WIDTH", "H", "K_BEND", "G_POST"]

#: the bend region's width (in R) and default placement, centred on the equator
BEND_WIDTH = 0.35
#: the default thickness over R
H = 0.1
#: the default bend curvature and posterior stretch at p = 1
K_BEND, G_POST = -10.0, 0.8
#: folds located to this tolerance in p
FOLD_TOL = 1e-8


def cell_shapes(x, p, c):
    """(g1, g2, kb1, kb2) of region x.piece (0 anterior, 1 bend, 2 posterior) at stage p:
    c = (g_ant, k_ant, g_bend, k_bend, g_post, k_post), each reached linearly in p from
    (1, -1) (module docstring)."""
    g_end, k_end = c[2 * x.piece], c[2 * x.piece + 1]
    one = 0.0 * x.s + 1.0
    g = 1.0 + p * (g_end - 1.0)
    k = -1.0 + p * (k_end + 1.0)
    return g * one, g * one, k * one, k * one


def scene(h: float = H, *, k_bend: float = K_BEND, g_post: float = G_POST,
          g_ant: float = 1.0, g_bend: float = 1.0, k_ant: float = -1.0, k_post: float = -1.0,
          bend=None, material: str = "koiter", nu: float = 0.5, lam: float = 1.0,
          model: str = "relaxed") -> shellbvp.Scene:
    """The embryo (module docstring).

    Arguments:
        h: thickness over R, in (0.01, 0.5).
        k_bend, k_ant, k_post: the regions' target curvatures at p = 1 (1/R), with
            |k| h <= 2.
        g_post, g_ant, g_bend: their target stretches at p = 1, in [0.5, 2].
        bend: (s1, s2), the bend region in arclength from the anterior pole, inside
            (0, pi) (default: ``BEND_WIDTH`` centred on the equator).
        material, nu, lam, model: as :class:`shellbvp.Scene`.
    """
    if not (isinstance(h, (int, float)) and 0.01 < h < 0.5):
        raise ValueError(f"h must lie in (0.01, 0.5) (the sheet's thickness over the "
                         f"embryo's radius), got {h!r}")
    for name, v in (("g_post", g_post), ("g_ant", g_ant), ("g_bend", g_bend)):
        if not (isinstance(v, (int, float)) and 0.5 <= v <= 2.0):
            raise ValueError(f"{name} must lie in [0.5, 2] (a target stretch), got {v!r}")
    for name, v in (("k_bend", k_bend), ("k_ant", k_ant), ("k_post", k_post)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and abs(v) * h <= 2.0):
            raise ValueError(f"{name} must be a curvature (1/R) with |{name}| h <= 2 (a cell "
                             f"wedged to a triangle), got {v!r}")
    s1, s2 = (math.pi / 2 - BEND_WIDTH / 2, math.pi / 2 + BEND_WIDTH / 2) if bend is None \
        else bend
    if not (0 < s1 < s2 < math.pi):
        raise ValueError(f"bend must be (s1, s2) with 0 < s1 < s2 < pi, got {bend!r}")
    material_args = {"koiter": dict(nu=nu), "nh": {}, "cg": dict(lam=lam, model=model)}
    if material not in material_args:
        raise ValueError(f"material must be one of {tuple(material_args)}, got {material!r}")
    c = (g_ant, k_ant, g_bend, k_bend, g_post, k_post)
    return shellbvp.Scene(geometry=shellbvp.closed_sphere(1.0), h=h, ends=("pole", "pole"),
                          fields=cell_shapes, breaks=(float(s1), float(s2)), metric=True,
                          parameter="stage", parameter_unit="",
                          field_parameters=tuple(float(v) for v in c),
                          monitor="uz(second) - uz(first)", material=material,
                          **material_args[material])


def branch(sc: shellbvp.Scene, *, stage_max: float = 1.5, n_folds: int | None = 1,
           fold_tol: float = FOLD_TOL, method="spectral", **follow_options) -> shellbvp.Branch:
    """The embryo's branch from the sphere at stage 0, to its ``n_folds``-th fold (the snap
    that starts inversion) or past ``stage_max``, or to where the continuation stalls
    (``Branch.stop`` says why)."""
    options = shellbvp.ContinuationOptions(fold_tol=fold_tol)
    return shellbvp.follow(sc, p_stop=(-0.5, stage_max), n_folds=n_folds, options=options,
                           method=method, on_stall="stop", **follow_options)
