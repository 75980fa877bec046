"""Symbolic 3D -> 2D reduction of the morphoelastic shell energy (paper Sections 2-4).

Everything is written in the principal (diagonal) form: in the lines of
curvature the current and target forms are diagonal, so that with the stretches relative to
the target ``lam_a**2 = a_aa / abar_aa`` and the principal curvatures ``k_a = b_aa / a_aa``,
``kb_a = bbar_aa / abar_aa`` the three-dimensional metrics through the thickness are

    G_aa    = a_aa    (1 - phi  k_a )**2,   G_33    = phi'**2,
    Gbar_aa = abar_aa (1 - phib kb_a)**2,   Gbar_33 = phib'**2,

(the second form of Gbar uses the paper's constraint cbar = bbar abar^-1 bbar, Section 3).
The invariants of C_e are then exact rational functions of (phi, phi', phib, phib'):

    I1 = sum_a lam_a**2 (1 - phi k_a)**2 / (1 - phib kb_a)**2 + (phi'/phib')**2,
    I3 = prod_a lam_a**2 (1 - phi k_a)**2 / (1 - phib kb_a)**2 * (phi'/phib')**2,

and the volume element per unit target area and unit Z is ``phib' prod_a (1 - phib kb_a)``.
The energy per unit target area and unit thickness is

    W = (1/h) int_{-h/2}^{h/2} Phi(Z) phib'(Z) prod_a (1 - phib kb_a) dZ
      = w_s + h**2/12 w_b + O(h**4),

with ``w_s`` the Z**0 and ``w_b`` the Z**2 Taylor coefficient of the integrand. Energies are per
shear modulus mu*, lengths per R0.

Models:

* ``plane_strain``: phi = Z (rho1 = 1, rho2 = rho3 = 0).
* ``relaxed``: phi = rho1 Z + rho2 Z**2, rho1 minimising w_s (paper eq. (a)), rho2 minimising
  w_b at that rho1 (paper eq. (b)); rho3 drops out of w_b at the optimal rho1 (checked in
  the tests), so it is set to zero.
* material ``nh``: incompressible, J = 1 imposed kinematically through the thickness, which
  integrates to the cubic ``Js (phi - H phi**2 + K phi**3/3) = phib - Hb phib**2 + Kb phib**3/3``
  (H, K, Hb, Kb the mean and Gaussian curvatures, Js = lam1 lam2); its series gives rho1..rho3.

This is the only module, with :mod:`shellbvp.series`, that imports sympy. The derivation is
run once per (model, material) and cached on disk (:mod:`shellbvp.cache`).
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from . import cache

__all__ = ["Reduction", "derive", "symbols", "full_energy"]

# --- symbols -------------------------------------------------------------------------------
lam1, lam2 = sp.symbols("lam1 lam2", positive=True)
k1, k2, kb1, kb2 = sp.symbols("k1 k2 kb1 kb2", real=True)
lam = sp.Symbol("lam", positive=True)
rhob1 = sp.Symbol("rhob1", positive=True)
rhob2, rhob3 = sp.symbols("rhob2 rhob3", real=True)
rho1 = sp.Symbol("rho1", positive=True)
rho2, rho3 = sp.symbols("rho2 rho3", real=True)
Z = sp.Symbol("Z", real=True)
h = sp.Symbol("h", positive=True)
phi, phib = sp.symbols("phi phib", real=True)
dphi, dphib = sp.symbols("dphi dphib", positive=True)

#: Arguments of every compiled function, in this order.
STATE = (lam1, lam2, k1, k2, kb1, kb2)
STIMULUS = (rhob1, rhob2, rhob3)
RHOS = (rho1, rho2, rho3)


def symbols() -> dict[str, sp.Symbol]:
    """The symbols used by the derivation, by name."""
    names = STATE + STIMULUS + RHOS + (lam, Z, h, phi, dphi, phib, dphib)
    return {s.name: s for s in names}


from .models import MATERIALS, MODELS  # noqa: E402  (re-exported)


# --- the 3D density in principal form ------------------------------------------------------
def density_3d(material: str) -> sp.Expr:
    """Phi / mu* as a function of (phi, phi', phib, phib') and the principal state.

    ``cg``: Ciarlet-Geymonat, Phi = (I1 - 3 - log I3)/2 + lam/4 (I3 - 1 - log I3).
    ``nh``: incompressible neo-Hookean on J = 1, Phi = (I1 - 3)/2 (the pressure term vanishes
    because the thickness map makes J = 1 exactly).
    """
    A1 = lam1**2 * (1 - phi * k1) ** 2 / (1 - phib * kb1) ** 2
    A2 = lam2**2 * (1 - phi * k2) ** 2 / (1 - phib * kb2) ** 2
    T = (dphi / dphib) ** 2
    I1 = A1 + A2 + T
    if material == "nh":
        return (I1 - 3) / 2
    # log I3 as a sum of logs keeps the Z-derivatives small.
    logI3 = 2 * (
        sp.log(lam1) + sp.log(lam2) + sp.log(1 - phi * k1) + sp.log(1 - phi * k2)
        - sp.log(1 - phib * kb1) - sp.log(1 - phib * kb2) + sp.log(dphi) - sp.log(dphib)
    )
    I3 = A1 * A2 * T
    return (I1 - 3 - logI3) / 2 + lam / 4 * (I3 - 1 - logI3)


def integrand(material: str) -> sp.Expr:
    """Phi times the volume element per unit target area and unit Z."""
    return density_3d(material) * dphib * (1 - phib * kb1) * (1 - phib * kb2)


def _through_thickness(expr: sp.Expr, phi_z: sp.Expr) -> tuple[sp.Expr, sp.Expr]:
    """Z**0 and Z**2 Taylor coefficients of ``expr`` with phi = phi_z(Z), phib polynomial."""
    phib_z = rhob1 * Z + rhob2 * Z**2 + rhob3 * Z**3
    F = expr.subs({dphi: sp.diff(phi_z, Z), dphib: sp.diff(phib_z, Z)}).subs(
        {phi: phi_z, phib: phib_z}
    )
    f0 = F.subs(Z, 0)
    f2 = sp.diff(F, Z, 2).subs(Z, 0) / 2
    return f0, f2


def _nh_rhos() -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """rho1..rho3 from J = 1 integrated through the thickness, solved order by order in Z."""
    H, K = (k1 + k2) / 2, k1 * k2
    Hb, Kb = (kb1 + kb2) / 2, kb1 * kb2
    Js = lam1 * lam2
    phi_z = rho1 * Z + rho2 * Z**2 + rho3 * Z**3
    phib_z = rhob1 * Z + rhob2 * Z**2 + rhob3 * Z**3
    constraint = sp.expand(
        Js * (phi_z - H * phi_z**2 + K * phi_z**3 / 3)
        - (phib_z - Hb * phib_z**2 + Kb * phib_z**3 / 3)
    )
    sol: dict = {}
    for n, r in zip((1, 2, 3), RHOS):
        eq = constraint.coeff(Z, n).subs(sol)
        sol[r] = sp.factor(sp.solve(eq, r)[0])
    return sol[rho1], sol[rho2], sol[rho3]


@dataclass(frozen=True)
class Reduction:
    """The derived reduced energy of one (model, material).

    ``rho1``, ``rho2``, ``rho3`` are expressions to be evaluated in that order: each may use
    the state, the stimulus and the rho's before it. ``w_s`` and ``w_b`` are expressions in the
    state, the stimulus, ``lam`` and the rho's; ``integrand`` is the exact 3D integrand in
    (phi, dphi, phib, dphib) used by the quadrature referee.
    """

    model: str
    material: str
    rho1: sp.Expr
    rho2: sp.Expr
    rho3: sp.Expr
    w_s: sp.Expr
    w_b: sp.Expr
    integrand: sp.Expr


def _koiter() -> Reduction:
    """The morphoelastic Koiter shell (Efrati et al. 2009; Pezzulla et al. PRL 2018), the
    paper's reference model, in principal form: plane-stress stretching
    (h/8) A(a - abar)(a - abar) and bending (h^3/24) A(b - bbar)(b - bbar) with
    A = Y/(1 - nu^2)[nu abar^ abar^ + (1 - nu) abar^ abar^], per mu* (Y = 2 mu* (1 + nu)) and
    per unit thickness. Not derived from 3D: it is the reference, not a reduction. Its
    Poisson ratio nu occupies the material-parameter slot that ``lam`` holds for CG."""
    nu = lam
    e = [lam1**2 - 1, lam2**2 - 1]                    # (a - abar)_aa / abar_aa
    b = [k1 * lam1**2 - kb1, k2 * lam2**2 - kb2]      # (b - bbar)_aa / abar_aa

    def quad(v):
        return (nu * (v[0] + v[1]) ** 2 + (1 - nu) * (v[0] ** 2 + v[1] ** 2)) / (1 - nu)

    return Reduction("relaxed", "koiter", sp.Integer(1), sp.Integer(0), sp.Integer(0),
                     quad(e) / 4, quad(b), sp.Integer(0))


def _derive(model: str, material: str) -> Reduction:
    if material == "koiter":
        return _koiter()
    F = integrand(material)
    phi_z = rho1 * Z + rho2 * Z**2 + rho3 * Z**3
    f0, f2 = _through_thickness(F, phi_z)
    if material == "nh":
        r1, r2, r3 = _nh_rhos()
    elif model == "plane_strain":
        r1, r2, r3 = sp.Integer(1), sp.Integer(0), sp.Integer(0)
    else:
        # rho1: the positive stationary point of w_s (w_s depends on rho1 only).
        roots = [r for r in sp.solve(sp.diff(f0, rho1), rho1) if r.is_positive is not False]
        if len(roots) != 1:
            raise RuntimeError(f"expected one positive rho1, got {roots}")
        r1 = sp.simplify(roots[0])
        # rho2: w_b is quadratic in rho2 (with rho3 = 0, see the module docstring).
        f2_0 = f2.subs(rho3, 0)
        a = sp.diff(f2_0, rho2, 2).subs(rho2, 0) / 2
        b = sp.diff(f2_0, rho2).subs(rho2, 0)
        r2 = sp.simplify(-b / (2 * a))
        r3 = sp.Integer(0)
    return Reduction(model, material, r1, r2, r3, f0, f2, F)


def derive(model: str = "relaxed", material: str = "cg") -> Reduction:
    """Derive (or load from the disk cache) the reduced energy of ``model`` and ``material``.

    For ``material="nh"`` the model is irrelevant (the rho's follow from J = 1) and is
    normalised to ``"relaxed"``.
    """
    if material not in MATERIALS:
        raise ValueError(f"material must be one of {MATERIALS}, got {material!r}")
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}, got {model!r}")
    if material in ("nh", "koiter"):
        model = "relaxed"
    return _derive_cached(model, material)


@lru_cache(maxsize=None)
def _derive_cached(model: str, material: str) -> Reduction:
    key = cache.key("reduction", model, material, inspect.getsource(inspect.getmodule(_derive)))
    return cache.memo(key, lambda: _derive(model, material))


def full_energy(model: str = "relaxed", material: str = "cg", *, stimulus: dict | None = None):
    """W = w_s + h**2/12 w_b as one expression in the state, lam, h and the stimulus.

    ``stimulus`` may substitute values for (rhob1, rhob2, rhob3) (e.g. the defaults 1, 0, 0)
    before the rho's are eliminated, which keeps the expression small.
    """
    red = derive(model, material)
    sub = dict(stimulus or {})
    r1 = red.rho1.subs(sub)
    r2 = red.rho2.subs(sub).subs(rho1, r1)
    r3 = red.rho3.subs(sub).subs({rho1: r1, rho2: r2})
    rhos = {rho1: r1, rho2: r2, rho3: r3}
    w_s = red.w_s.subs(sub).subs(rhos)
    w_b = red.w_b.subs(sub).subs(rhos)
    return w_s + h**2 / 12 * w_b
