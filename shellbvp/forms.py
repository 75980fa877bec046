"""The reduced energy of general (non-diagonal) fundamental forms, for perturbations beyond
axisymmetry.

:mod:`shellbvp.reduction` works in the lines of curvature, where every form is diagonal. A
perturbation ``cos(n omega)`` shears the surface, and the forms a (first), b (second) of the
current mid-surface no longer commute with the target's abar, bbar. This module evaluates the
same reduced energy for arbitrary symmetric 2x2 forms, from the same 3D densities and the same
through-thickness kinematics (normal fibres, thickness maps phi(Z), phib(Z)):

    G(Z)    = a (I - phi S)^2,       S    = a^-1 b       (shape operator),
    Gbar(Z) = abar (I - phib Sb)^2,  Sb   = abar^-1 bbar
              (bbar abar^-1 bbar the target's third form),
    I1 = tr(Gbar^-1 G) + (phi'/phib')^2,   I3 = det(G) / det(Gbar) (phi'/phib')^2,
    dV = phib' det(I - phib Sb) dZ dA_target,

which reduce to the principal expressions of :mod:`shellbvp.reduction` when every form is
diagonal. W = w_s + h^2/12 w_b are the Z^0 and Z^2 Taylor coefficients of Phi dV/dZ, taken
here by automatic differentiation in Z (JAX), not by sympy; the thickness-map coefficients
are the same as the principal derivation's, written with invariants
(:func:`shellbvp.reduction.invariant_rhos`): incompressible ``nh`` from J = 1, relaxed ``cg``
rho1 from the areal stretch and rho2 minimising w_b (a quadratic in rho2, minimised exactly).
The Koiter reference shell is A(E, E) h/8 + A(B, B) h^3/24 with E = abar^-1 (a - abar),
B = abar^-1 (b - bbar) mixed tensors and A(X, X) = [nu (tr X)^2 + (1 - nu) tr(X X)] / (1 - nu)
(Efrati et al. 2009), per mu* and unit thickness, as in the principal form.

Everything is per unit target area, per mu*, per unit thickness, lengths in R0, and is a JAX
function of the forms (so that its Hessian in the mid-surface's derivatives is exact, see
:mod:`shellbvp.harmonics`). W is a scalar: invariant under any change of the surface
coordinates (a -> P^T a P for all four forms).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np

from .jaxsetup import jax
from .models import MODELS

import jax.numpy as jnp  # noqa: E402

__all__ = ["reduced_energy", "exact_energy"]


def _inv(m):
    det = m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]
    return jnp.array([[m[1, 1], -m[0, 1]], [-m[1, 0], m[0, 0]]]) / det, det


def _det(m):
    return m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]


@lru_cache(maxsize=None)
def _rho_functions(model: str, material: str):
    """The invariant thickness-map coefficients as JAX functions (None: minimised here)."""
    import sympy as sp

    from . import reduction as R

    return tuple(None if r is None else sp.lambdify(R.INVARIANTS, r, modules="jax")
                 for r in R.invariant_rhos(model, material))


def _integrand(Z, rhos, a, b, abar, bbar, lam, rhob, material):
    """Phi times the volume element per unit target area and unit Z, at Z."""
    r1, r2, r3 = rhos
    b1, b2, b3 = rhob
    phi, dphi = r1 * Z + r2 * Z**2 + r3 * Z**3, r1 + 2 * r2 * Z + 3 * r3 * Z**2
    phib, dphib = b1 * Z + b2 * Z**2 + b3 * Z**3, b1 + 2 * b2 * Z + 3 * b3 * Z**2
    return _density(phi, dphi, phib, dphib, a, b, abar, bbar, lam, material)


def _density(phi, dphi, phib, dphib, a, b, abar, bbar, lam, material):
    eye = jnp.eye(2)
    S, Sb = _inv(a)[0] @ b, _inv(abar)[0] @ bbar
    A = eye - phi * S
    Ab = eye - phib * Sb
    G = a @ A @ A
    Gb = abar @ Ab @ Ab
    Gbi, detGb = _inv(Gb)
    T = (dphi / dphib) ** 2
    I1 = jnp.trace(Gbi @ G) + T
    vol = dphib * _det(Ab)
    if material == "nh":
        return (I1 - 3) / 2 * vol
    logI3 = jnp.log(_det(G)) - jnp.log(detGb) + jnp.log(T)
    I3 = jnp.exp(logI3)
    return ((I1 - 3 - logI3) / 2 + lam / 4 * (I3 - 1 - logI3)) * vol


def invariants(a, b, abar, bbar):
    """The joint invariants W depends on (:data:`shellbvp.reduction.GENERAL`, without lam, h
    and the stimulus): tr C, Js, H, K, Hb, Kb, tr(CS), tr(CSS), tr(SbC), tr(SbSbC),
    tr(SbCS) with C = abar^-1 a, S = a^-1 b, Sb = abar^-1 bbar."""
    ai, deta = _inv(a)
    abi, detab = _inv(abar)
    C, S, Sb = abi @ a, ai @ b, abi @ bbar
    CS = C @ S
    return (jnp.trace(C), jnp.sqrt(deta / detab), jnp.trace(S) / 2, _det(S), jnp.trace(Sb) / 2,
            _det(Sb), jnp.trace(CS), jnp.trace(CS @ S), jnp.trace(Sb @ C),
            jnp.trace(Sb @ Sb @ C), jnp.trace(Sb @ CS))


def reduced_energy(a, b, abar, bbar, *, h, lam=1.0, model="relaxed", material="cg", nu=0.5,
                   rhob=(1.0, 0.0, 0.0)):
    """W(a, b; abar, bbar) = w_s + h^2/12 w_b for symmetric 2x2 forms (module docstring).

    Arguments:
        a, b: first and second fundamental forms of the current mid-surface (2x2, in any
            surface coordinates; outward normal, so the unit sphere has b = -a).
        abar, bbar: the target forms in the same coordinates.
        h: thickness h0/R0; lam: lambda*/mu* (cg); nu: Poisson ratio (koiter).
        model, material: as in :func:`shellbvp.energy_density`.
        rhob: the through-thickness stimulus (rhob1, rhob2, rhob3).

    JAX-traceable (no checks): callers validate (:func:`shellbvp.energy_density` does for the
    principal form, :mod:`shellbvp.harmonics` for an equilibrium's state)."""
    if material == "koiter":
        Ai = _inv(abar)[0]
        E, B = Ai @ (a - abar), Ai @ (b - bbar)

        def quad(X):
            return (nu * jnp.trace(X) ** 2 + (1 - nu) * jnp.trace(X @ X)) / (1 - nu)

        return quad(E) / 4 + h**2 / 12 * quad(B)
    from .compiled import general_energy_function

    W = general_energy_function("relaxed" if material == "nh" else model, material)
    return W(*invariants(a, b, abar, bbar), lam, h, *rhob)


def exact_energy(a, b, abar, bbar, *, h, lam=1.0, model="relaxed", material="cg",
                 rhob=(1.0, 0.0, 0.0), nodes=48):
    """The referee of :func:`reduced_energy`: (1/h) int Phi dV over the thickness by
    Gauss-Legendre quadrature, with the model's thickness map and no Taylor truncation (for
    ``nh`` the exact J = 1 map: the cubic Js (phi - H phi^2 + K phi^3/3) = phib - Hb phib^2
    + Kb phib^3/3 solved by Newton's method). Differs from the reduced W by O(h^4)."""
    if material not in ("cg", "nh"):
        raise ValueError(f"material must be 'cg' or 'nh' for the exact referee, got {material!r}")
    if model not in MODELS:
        raise ValueError(f"model must be one of {MODELS}, got {model!r}")
    a, b, abar, bbar = (jnp.asarray(x, dtype=float) for x in (a, b, abar, bbar))
    _, Js, H, K, Hb, Kb, *_ = invariants(a, b, abar, bbar)
    inv = (Js, H, K, Hb, Kb, lam, *rhob)
    t, wts = np.polynomial.legendre.leggauss(nodes)
    b1, b2, b3 = rhob
    total = 0.0
    if material == "nh":
        for tj, wj in zip(t, wts):
            Z = 0.5 * h * tj
            phib, dphib = b1 * Z + b2 * Z**2 + b3 * Z**3, b1 + 2 * b2 * Z + 3 * b3 * Z**2
            rhs = (phib - Hb * phib**2 + Kb * phib**3 / 3) / Js
            phi = rhs
            for _ in range(60):
                phi = phi - (phi - H * phi**2 + K * phi**3 / 3 - rhs) / (1 - 2 * H * phi
                                                                          + K * phi**2)
            dphi = dphib * (1 - 2 * Hb * phib + Kb * phib**2) / (Js * (1 - 2 * H * phi
                                                                       + K * phi**2))
            total = total + 0.5 * wj * _density(phi, dphi, phib, dphib, a, b, abar, bbar, lam,
                                                material)
        return float(total)
    f1, f2, f3 = _rho_functions(model, material)
    r1 = float(f1(*inv))
    r3 = float(f3(*inv))
    if f2 is None:
        # rho2 minimises the Z^2 coefficient of the 3D integrand (a quadratic in rho2),
        # here by differentiating the integrand itself in Z (independently of the reduction)
        def f2(r2):
            F = lambda Z: _integrand(Z, (r1, r2, r3), a, b, abar, bbar, lam, rhob,  # noqa
                                     material)
            return float(jax.jacfwd(jax.jacfwd(F))(0.0)) / 2
        fm, f0, fp = f2(-1.0), f2(0.0), f2(1.0)
        r2 = -(fp - fm) / 2 / (2 * ((fp + fm) / 2 - f0))
    else:
        r2 = float(f2(*inv))
    for tj, wj in zip(t, wts):
        Z = 0.5 * h * tj
        total = total + 0.5 * wj * _integrand(Z, (r1, r2, r3), a, b, abar, bbar, lam, rhob,
                                              material)
    return float(total)
