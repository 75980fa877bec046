"""Numerical reduced energy densities, compiled from the symbolic reduction.

Public functions :func:`energy_density` and :func:`energy_terms` evaluate, for the principal
state (stretches relative to the target metric, principal and target curvatures, in
units of 1/R0; see :mod:`shellbvp.reduction`), the energy per unit target area, per shear
modulus mu*, per unit thickness

    W = w_s + h**2/12 * w_b        (h = h0/R0),

derived in :mod:`shellbvp.reduction`, or its referee ``exact=True``: the same thickness map
integrated through the thickness by Gauss-Legendre quadrature with no Taylor truncation.
All functions broadcast like numpy and accept complex arguments (ranges are then checked on
the real part), which makes complex-step derivatives exact to round-off.
"""

from __future__ import annotations

from functools import lru_cache
from typing import NamedTuple

import numpy as np

from . import checks
from .models import MATERIALS, MODELS, material_parameter

__all__ = ["energy_density", "energy_terms", "EnergyTerms", "thickness_map"]

#: Gauss-Legendre nodes of the exact referee. The integrand is analytic in Z on a disc of
#: radius ~ 1/max|k| around 0, so for h max|k| <= 1 the quadrature error is ~ 3**(-2n).
QUAD_NODES = 48


class EnergyTerms(NamedTuple):
    """Stretching and bending densities and the thickness-map coefficients (per mu*)."""

    w_s: np.ndarray
    w_b: np.ndarray
    rho1: np.ndarray
    rho2: np.ndarray


@lru_cache(maxsize=None)
def _compiled(model: str, material: str):
    """numpy functions of the derivation, compiled once per process (derivation cached on disk)."""
    import sympy as sp

    from . import reduction as R

    red = R.derive(model, material)
    args = R.STATE + (R.lam,) + R.STIMULUS + R.RHOS
    f = lambda e: sp.lambdify(args, e, modules="numpy", cse=True)  # noqa: E731
    exact_args = R.STATE + (R.lam,) + (R.phi, R.dphi, R.phib, R.dphib)
    return {
        "rho1": f(red.rho1),
        "rho2": f(red.rho2),
        "rho3": f(red.rho3),
        "w_s": f(red.w_s),
        "w_b": f(red.w_b),
        "integrand": sp.lambdify(exact_args, red.integrand, modules="numpy", cse=True),
    }


def _validate(state, h, lam, model, material, rhob, exact, nu=0.5):
    checks.check_choice("material", material, MATERIALS)
    if material == "koiter":
        checks.check_finite("nu", nu)
        if not -1.0 < float(np.real(nu)) < 1.0:
            raise ValueError(f"nu must lie in (-1, 1) (Poisson ratio; 0.5 incompressible), "
                             f"got {nu!r}")
        if exact:
            raise ValueError("exact=True is not available for material='koiter' (a reference "
                             "model, not a reduction of a 3D energy)")
    checks.check_choice("model", model, MODELS)
    names = ("lam1", "lam2", "k1", "k2", "kb1", "kb2")
    arrays = [checks.check_finite(n, v) for n, v in zip(names, state)]
    for n, a in zip(names[:2], arrays[:2]):
        if not np.all(np.real(a) > 0):
            raise ValueError(f"{n} (a stretch) must be > 0, got {a!r}")
    if h is not None:
        h = checks.check_open_interval("h", h, 0.0, 1.0, " (h = h0/R0, thickness per radius)")
    if material == "cg":
        checks.check_positive("lam", lam)
    rb = [checks.check_finite(n, v) for n, v in zip(("rhob1", "rhob2", "rhob3"), rhob)]
    checks.check_positive("rhob1", rb[0])
    if exact:
        # Orientation of the thickness map: 1 - Z k > 0 across the thickness.
        kmax = max(float(np.max(np.abs(np.real(a)))) for a in arrays[2:])
        if h * kmax >= 2.0:
            raise ValueError(
                f"curvatures times h must satisfy h*max|k| < 2 for the exact model "
                f"(the thickness map folds), got h*max|k| = {h * kmax:g}"
            )
    return arrays, rb, h


def _terms(arrays, lam, model, material, rb):
    fns = _compiled(model, material)
    args = (*arrays, lam, *rb)
    r1 = fns["rho1"](*args, 0.0, 0.0, 0.0)
    r2 = fns["rho2"](*args, r1, 0.0, 0.0)
    r3 = fns["rho3"](*args, r1, r2, 0.0)
    ws = fns["w_s"](*args, r1, r2, r3)
    wb = fns["w_b"](*args, r1, r2, r3)
    shape = np.broadcast_shapes(*(np.shape(a) for a in (*arrays, *rb)))
    bc = lambda x: np.broadcast_to(np.asarray(x), shape)[()]  # noqa: E731
    return bc(ws), bc(wb), bc(r1), bc(r2), bc(r3)


def energy_terms(lam1, lam2, k1, k2, kb1, kb2, *, lam=1.0, model="relaxed", material="cg",
                 rhob1=1.0, rhob2=0.0, rhob3=0.0, nu=0.5) -> EnergyTerms:
    """Stretching and bending densities of the reduced model and its thickness map.

    Arguments:
        lam1, lam2: meridional/azimuthal stretch relative to the target metric (> 0).
        k1, k2: principal curvatures of the current mid-surface, in 1/R0 (outward normal:
            the reference sphere has k = -1).
        kb1, kb2: target principal curvatures bbar_aa / abar_aa, in 1/R0.
        lam: lambda*/mu* (Ciarlet-Geymonat only, > 0).
        model: ``"plane_strain"`` or ``"relaxed"`` (ignored for ``material="nh"``).
        material: ``"cg"`` (compressible Ciarlet-Geymonat), ``"nh"`` (incompressible), or
            ``"koiter"`` (the morphoelastic Koiter reference shell, Poisson ratio ``nu``).
        rhob1, rhob2, rhob3: through-thickness stimulus, phib = rhob1 Z + rhob2 Z^2 + rhob3 Z^3.
        nu: Poisson ratio of the Koiter model, in (-1, 1) (default 1/2).

    Returns:
        ``EnergyTerms(w_s, w_b, rho1, rho2)``: W = w_s + h^2/12 w_b; phi = rho1 Z + rho2 Z^2 + ...

    Raises:
        ValueError: a parameter out of range (message names it and the range).
    """
    arrays, rb, _ = _validate((lam1, lam2, k1, k2, kb1, kb2), None, lam, model, material,
                              (rhob1, rhob2, rhob3), False, nu)
    ws, wb, r1, r2, _ = _terms(arrays, material_parameter(material, lam, nu), model, material, rb)
    return EnergyTerms(ws, wb, r1, r2)


def thickness_map(Z, lam1, lam2, k1, k2, kb1, kb2, *, lam=1.0, model="relaxed",
                  material="cg", rhob1=1.0, rhob2=0.0, rhob3=0.0):
    """(phi, phi', phib, phib') at the thickness coordinates Z (the model's exact rule).

    For ``cg`` phi is the model's polynomial (plane strain: Z; relaxed: rho1 Z + rho2 Z^2).
    For ``nh`` phi solves J = 1 exactly: the cubic
    ``Js (phi - H phi^2 + K phi^3/3) = phib - Hb phib^2 + Kb phib^3/3`` by Newton's method
    from its linear approximation (the root continuously connected to phi = 0 at Z = 0).
    """
    arrays = [np.asarray(a) for a in (lam1, lam2, k1, k2, kb1, kb2)]
    return _thickness_map(np.asarray(Z), arrays, lam, model, material,
                          [np.asarray(r) for r in (rhob1, rhob2, rhob3)])


def _thickness_map(Z, arrays, lam, model, material, rb):
    l1, l2, c1, c2, cb1, cb2 = arrays
    b1, b2, b3 = rb
    phib = b1 * Z + b2 * Z**2 + b3 * Z**3
    dphib = b1 + 2 * b2 * Z + 3 * b3 * Z**2
    if material == "nh":
        Js = l1 * l2
        H, K = (c1 + c2) / 2, c1 * c2
        rhs = (phib - (cb1 + cb2) / 2 * phib**2 + cb1 * cb2 * phib**3 / 3) / Js
        phi = rhs
        for _ in range(60):
            g = phi - H * phi**2 + K * phi**3 / 3 - rhs
            step = g / ((1 - phi * c1) * (1 - phi * c2))
            phi = phi - step
            if np.all(np.abs(step) <= 1e-15 * (np.abs(phi) + 1e-300)):
                break
        else:
            raise RuntimeError("thickness map (J = 1 cubic) did not converge in 60 Newton steps")
        dphi = dphib * (1 - phib * cb1) * (1 - phib * cb2) / (Js * (1 - phi * c1) * (1 - phi * c2))
        return phi, dphi, phib, dphib
    _, _, r1, r2, r3 = _terms(arrays, lam, model, material, rb)
    phi = r1 * Z + r2 * Z**2 + r3 * Z**3
    dphi = r1 + 2 * r2 * Z + 3 * r3 * Z**2
    return phi, dphi, phib, dphib


def _exact(arrays, h, lam, model, material, rb):
    t, wts = np.polynomial.legendre.leggauss(QUAD_NODES)
    fns = _compiled(model, material)
    total = 0.0
    for tj, wj in zip(t, wts):
        Zj = 0.5 * h * tj
        phi, dphi, phib, dphib = _thickness_map(Zj, arrays, lam, model, material, rb)
        total = total + 0.5 * wj * fns["integrand"](*arrays, lam, phi, dphi, phib, dphib)
    return total


def energy_density(lam1, lam2, k1, k2, kb1, kb2, *, h, lam=1.0, model="relaxed",
                   material="cg", rhob1=1.0, rhob2=0.0, rhob3=0.0, exact=False, nu=0.5):
    """Energy per unit target area, per mu*, per unit thickness: W = w_s + h^2/12 w_b.

    Arguments are those of :func:`energy_terms`, plus:
        h: thickness per reference radius, h0/R0, in (0, 1).
        exact: integrate the model's thickness map through the thickness by Gauss-Legendre
            quadrature with no Taylor truncation (the referee of the reduction; differs from
            the reduced W by O(h^4)). For ``nh`` it uses the exact J = 1 thickness map.

    The shell energy is mu* h0 R0^2 times the integral of W over the target area (R0 = 1).

    Raises:
        ValueError: a parameter out of range (message names it and the range).
    """
    arrays, rb, h = _validate((lam1, lam2, k1, k2, kb1, kb2), h, lam, model, material,
                              (rhob1, rhob2, rhob3), exact, nu)
    if exact:
        return _exact(arrays, h, lam, model, material, rb)
    ws, wb, *_ = _terms(arrays, material_parameter(material, lam, nu), model, material, rb)
    return ws + h**2 / 12 * wb
