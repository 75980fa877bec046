"""Thin shells against their classical closed forms: a hemisphere pushed at its pole, a long
cylinder under internal pressure, circular plates under pressure.

Material: the Koiter shell (Kirchhoff-Love, small strain) with Poisson ratio nu, E the
Young's modulus; lengths in the shell's radius R (a plate's radius a), forces per mu h R
per radian of azimuth (mu = E / (2 (1 + nu))), pressures per mu h / R. Every scene is
solved by the default method whatever its thinness (:mod:`shellbvp.mesh`: elements graded
into the layers of width sqrt(R t)), and each closed form is its own theory's thin limit:

* **Reissner's point load** (E. Reissner, J. Math. Phys. 25, 80-85 and 279-300, 1946;
  Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*, 2nd ed., Sec. 16.3): a
  shallow spherical shell of infinite extent under a point force P deflects under it by
  w = P R sqrt(3 (1 - nu^2)) / (4 E t^2). A hemisphere clamped at its equator departs from
  it by the terms shallow-shell theory drops, of relative order (t/R) ln(R/t).
* **The edge zone of a long cylinder** (Timoshenko & Woinowsky-Krieger, Sec. 15.2, the beam
  on an elastic foundation): a long cylinder of radius R and thickness t under internal
  pressure p, clamped at z = 0, has the radial displacement
  u(x) = u_inf [1 - exp(-beta x) (cos beta x + sin beta x)], beta = (3 (1 - nu^2))^(1/4) /
  sqrt(R t), u_inf = p R^2 (1 - nu/2) / (E t) (the pressure on the end plane carries the
  axial force p R / 2: the potential of the pressure is p times the enclosed volume), with
  relative errors of order t/R and exp(-beta L).
* **Kirchhoff's plates** (Timoshenko & Woinowsky-Krieger, Sec. 15-16 of *Theory of Plates*,
  Ch. 3): a circular plate of radius a under a small pressure p deflects at its centre by
  p a^4 / (64 D) clamped and (5 + nu) p a^4 / (64 D (1 + nu)) simply supported,
  D = E t^3 / (12 (1 - nu^2)), to relative order (w/t)^2 (the membrane stiffening).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import shellbvp
from shellbvp import End, Scene, cylinder, disc, spherical_cap

__all__ = ["hemisphere", "reissner_stiffness", "pole_stiffness", "PoleStiffness",
           "long_cylinder", "cylinder_edge", "plate", "plate_deflection", "NU"]

#: Poisson ratio of the steel-like shells of the closed forms
NU = 0.3


def _down(P):
    """A downward point force P (the load functions are module-level: the compiled kernels
    are keyed by them, so a new scene of another thickness reuses them)."""
    return -P


def _same(p):
    """The parameter itself, as a pressure."""
    return p


def _modulus(nu: float) -> float:
    """E in the engine's unit of stress, mu."""
    return 2.0 * (1.0 + nu)


def hemisphere(R_over_t: float, *, nu: float = NU, load: str = "pole force") -> Scene:
    """A hemisphere of radius 1 and thickness 1/``R_over_t``, from its top pole (free, or
    carrying the point force) to its equator, clamped (``load="pole force"``: the parameter
    P is the downward point force, per mu h R) or a symmetry end (``"pressure"``: the
    complete sphere by its upper half, the parameter the external pressure per mu h / R)."""
    if load not in ("pole force", "pressure"):
        raise ValueError(f"load must be 'pole force' or 'pressure', got {load!r}")
    h = 1.0 / float(R_over_t)
    if load == "pole force":
        return Scene(geometry=spherical_cap(math.pi / 2), h=h, material="koiter", nu=nu,
                     ends=(End("pole", force=_down), "clamped"), parameter="P")
    return Scene(geometry=spherical_cap(math.pi / 2), h=h, material="koiter", nu=nu,
                 ends=("pole", "symmetry"), pressure=_same, parameter="p")


def reissner_stiffness(R_over_t: float, nu: float = NU) -> float:
    """Reissner's P / w of the shallow sphere (module docstring) in the engine's units,
    P per mu h R and w per R: 4 E t^2 / (R sqrt(3 (1 - nu^2))) / (mu h)."""
    h = 1.0 / float(R_over_t)
    return 4.0 * _modulus(nu) * h / math.sqrt(3.0 * (1.0 - nu * nu))


@dataclass(frozen=True)
class PoleStiffness:
    """The hemisphere's pole stiffness P / w at a small force (:func:`pole_stiffness`).

    Attributes:
        R_over_t: the shell.
        stiffness: P / w (engine units, as :func:`reissner_stiffness`).
        error_estimate: of it, from w's change on the next finer discretisation.
        w_over_t: the deflection reached, in thicknesses (its nonlinearity is ~0.5 w/t).
        stats: the method's resolution and the solve's statistics.
    """

    R_over_t: float
    stiffness: float
    error_estimate: float
    w_over_t: float
    stats: dict


def pole_stiffness(R_over_t: float, *, w_over_t: float = 1e-4, nu: float = NU,
                   method="spectral") -> PoleStiffness:
    """P / w of the clamped hemisphere under the pole force that Reissner's stiffness says
    deflects it by ``w_over_t`` thicknesses (small: the point-loaded shell stiffens by about
    half of w/t relative), solved with ``method`` and its error estimate."""
    sc = hemisphere(R_over_t, nu=nu)
    P = reissner_stiffness(R_over_t, nu) * w_over_t * sc.h
    b = shellbvp.follow(sc, method=method, p_stop=(0.0, P), energies=False)
    if b.stop or b.p[-1] != P:
        raise shellbvp.ConvergenceError(f"the pole force did not reach P = {P:g}: {b.stop}")
    w = -float(b.w[-1])
    k = P / w
    return PoleStiffness(float(R_over_t), k, k * float(b.w_error[-1]) / w, w / sc.h,
                         dict(b.stats))


def long_cylinder(L_over_sqrt_Rt: float, R_over_t: float, *, nu: float = NU) -> Scene:
    """A cylinder of radius 1 and thickness 1/``R_over_t``, ``L_over_sqrt_Rt`` times
    sqrt(R t) long, clamped at z = 0 with a symmetry end at the top (the lower half of a
    cylinder clamped at both ends), under the internal pressure p (per mu h / R, outward:
    positive along -n, n toward the axis for a cylinder traced upward)."""
    h = 1.0 / float(R_over_t)
    L = float(L_over_sqrt_Rt) * math.sqrt(h)
    return Scene(geometry=cylinder(1.0, L), h=h, material="koiter", nu=nu,
                 ends=("clamped", "symmetry"), pressure=_same, parameter="p",
                 monitor="ur(second)")


def cylinder_edge(x, p: float, R_over_t: float, nu: float = NU):
    """The radial displacement (per R) at distance x (per R) from the clamped edge of the
    long cylinder under internal pressure p (per mu h / R): the beam on an elastic
    foundation (module docstring)."""
    h = 1.0 / float(R_over_t)
    beta = (3.0 * (1.0 - nu * nu)) ** 0.25 / math.sqrt(h)
    u_inf = p * h / (_modulus(nu) * h) * (1.0 - nu / 2.0)   # p mu h / R -> p R^2 / (E t)
    bx = beta * x
    return u_inf * (1.0 - math.exp(-bx) * (math.cos(bx) + math.sin(bx)))


def plate(a_over_t: float, *, edge: str = "clamped", nu: float = NU) -> Scene:
    """A flat circular plate of radius 1 and thickness 1/``a_over_t``, from its centre (a
    pole) to its edge, ``"clamped"`` or simply supported (``"hinged"``), under the pressure
    p per mu h / a, pushing the centre down."""
    if edge not in ("clamped", "hinged"):
        raise ValueError(f"edge must be 'clamped' or 'hinged', got {edge!r}")
    return Scene(geometry=disc(1.0), h=1.0 / float(a_over_t), material="koiter", nu=nu,
                 ends=("pole", edge), pressure=_same, parameter="p")


def plate_deflection(p: float, a_over_t: float, *, edge: str = "clamped",
                     nu: float = NU) -> float:
    """Kirchhoff's centre deflection (per a) of :func:`plate` under the pressure p (per
    mu h / a): p a^4 / (64 D), times (5 + nu) / (1 + nu) simply supported."""
    h = 1.0 / float(a_over_t)
    D = _modulus(nu) * h ** 3 / (12.0 * (1.0 - nu * nu))        # per mu a^3
    w = p * h / (64.0 * D)
    return w * (5.0 + nu) / (1.0 + nu) if edge == "hinged" else w
