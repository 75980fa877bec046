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

__all__ = ["Reduction", "derive", "symbols", "full_energy", "invariant_rhos", "INVARIANTS",
           "general_energy", "GENERAL"]

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


def _nh_rhos(H=(k1 + k2) / 2, K=k1 * k2, Hb=(kb1 + kb2) / 2, Kb=kb1 * kb2,
             Js=lam1 * lam2) -> tuple[sp.Expr, sp.Expr, sp.Expr]:
    """rho1..rho3 from J = 1 integrated through the thickness, solved order by order in Z.

    The constraint involves the forms only through their invariants: the areal stretch
    Js = sqrt(det a / det abar) and the mean and Gaussian curvatures (H, K) and (Hb, Kb) of
    the current and target surfaces, principal ones by default."""
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


# --- invariants (the general, non-diagonal forms of :mod:`shellbvp.forms`) ------------------
J_s = sp.Symbol("Js", positive=True)
H_s, K_s, Hb_s, Kb_s = sp.symbols("H K Hb Kb", real=True)
#: Arguments of the thickness-map coefficients as functions of invariants, in this order.
INVARIANTS = (J_s, H_s, K_s, Hb_s, Kb_s, lam) + STIMULUS


def invariant_rhos(model: str, material: str) -> tuple:
    """The thickness-map coefficients that do not depend on the frame, as functions of the
    invariants ``INVARIANTS`` (areal stretch, mean and Gaussian curvatures, lam, stimulus):
    for ``nh`` rho1..rho3 from J = 1; for relaxed ``cg`` rho1, which depends on the areal
    stretch only (checked here: its principal form is a function of lam1 lam2); for plane
    strain (1, 0, 0). None where a coefficient is left to a minimisation (relaxed rho2)."""
    red = derive(model, material)
    if material == "nh":
        return _nh_rhos(H_s, K_s, Hb_s, Kb_s, J_s)
    if model == "plane_strain" or material == "koiter":
        return sp.Integer(1), sp.Integer(0), sp.Integer(0)
    r1 = sp.simplify(red.rho1.subs(lam1, J_s / lam2))
    if lam2 in r1.free_symbols or r1.free_symbols & {k1, k2, kb1, kb2}:
        raise RuntimeError(f"relaxed rho1 is not a function of the areal stretch: {r1}")
    return r1, None, sp.Integer(0)


#: the joint invariants of general (non-diagonal) forms the reduced energy depends on, with
#: C = abar^-1 a, S = a^-1 b, Sb = abar^-1 bbar (mixed tensors): tr C, the areal stretch Js,
#: the curvatures H, K, Hb, Kb, and tr(C S), tr(C S S), tr(Sb C), tr(Sb Sb C), tr(Sb C S)
trC = sp.Symbol("trC", positive=True)
t_CS, t_CSS, t_SbC, t_SbSbC, t_SbCS = sp.symbols("tCS tCSS tSbC tSbSbC tSbCS", real=True)
GENERAL = (trC, J_s, H_s, K_s, Hb_s, Kb_s, t_CS, t_CSS, t_SbC, t_SbSbC, t_SbCS, lam, h) \
    + STIMULUS


def _general(model: str, material: str) -> sp.Expr:
    """W = w_s + h^2/12 w_b of general forms in the invariants ``GENERAL``.

    Through the thickness G = a (I - phi S)^2 and Gbar = abar (I - phib Sb)^2, so that
    tr(Gbar^-1 G) = tr[(I - phib Sb)^-2 C (I - phi S)^2], whose Z^0..Z^2 coefficients are
    trC, -2 rho1 tr(CS) + 2 rhob1 tr(SbC) and -2 rho2 tr(CS) + rho1^2 tr(CSS)
    + 2 rhob2 tr(SbC) + 3 rhob1^2 tr(SbSbC) - 4 rho1 rhob1 tr(SbCS) ((I - x)^-2 = I + 2x
    + 3x^2 + ...); det(Gbar^-1 G) = Js^2 det(I - phi S)^2 / det(I - phib Sb)^2 with
    det(I - phi S) = 1 - 2 H phi + K phi^2, and the volume element is
    phib' (1 - 2 Hb phib + Kb phib^2). The rest is the principal derivation's: the same
    density, the same Taylor coefficients, the same thickness-map coefficients."""
    phi_z = rho1 * Z + rho2 * Z**2 + rho3 * Z**3
    phib_z = rhob1 * Z + rhob2 * Z**2 + rhob3 * Z**3
    dphi_z, dphib_z = sp.diff(phi_z, Z), sp.diff(phib_z, Z)
    trM = (trC + Z * (-2 * rho1 * t_CS + 2 * rhob1 * t_SbC)
           + Z**2 * (-2 * rho2 * t_CS + rho1**2 * t_CSS + 2 * rhob2 * t_SbC
                     + 3 * rhob1**2 * t_SbSbC - 4 * rho1 * rhob1 * t_SbCS))
    det_c = 1 - 2 * H_s * phi_z + K_s * phi_z**2
    det_b = 1 - 2 * Hb_s * phib_z + Kb_s * phib_z**2
    T = (dphi_z / dphib_z) ** 2
    I1 = trM + T
    vol = dphib_z * det_b
    if material == "nh":
        Phi = (I1 - 3) / 2
    else:
        logI3 = (2 * sp.log(J_s) + 2 * sp.log(det_c) - 2 * sp.log(det_b)
                 + 2 * sp.log(dphi_z) - 2 * sp.log(dphib_z))
        I3 = J_s**2 * det_c**2 / det_b**2 * T
        Phi = (I1 - 3 - logI3) / 2 + lam / 4 * (I3 - 1 - logI3)
    F = Phi * vol
    f0 = F.subs(Z, 0)
    f2 = sp.diff(F, Z, 2).subs(Z, 0) / 2
    r1, r2, r3 = invariant_rhos(model, material)
    if r2 is None:
        f2_0 = f2.subs({rho3: 0, rho1: r1})
        qa = sp.diff(f2_0, rho2, 2).subs(rho2, 0) / 2
        qb = sp.diff(f2_0, rho2).subs(rho2, 0)
        r2 = -qb / (2 * qa)
    sub = {rho1: r1, rho2: r2, rho3: r3}
    return f0.subs(sub) + h**2 / 12 * f2.subs({rho3: r3}).subs({rho2: r2}).subs({rho1: r1})


def general_energy(model: str = "relaxed", material: str = "cg") -> sp.Expr:
    """W of general forms as one expression in ``GENERAL`` (derived once, cached on disk);
    ``material`` cg or nh (Koiter's general form is written directly in
    :mod:`shellbvp.forms`)."""
    if material not in ("cg", "nh"):
        raise ValueError(f"material must be 'cg' or 'nh', got {material!r}")
    if material == "nh":
        model = "relaxed"
    key = cache.key("reduction-general", model, material,
                    inspect.getsource(inspect.getmodule(_derive)))
    return cache.memo(key, lambda: _general(model, material))


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
