"""Clamped spherical caps under uniform external pressure: the axisymmetric snap-through
(buckling) pressure, the classical benchmark of shell software.

Geometry: a spherical cap of radius R (= R0, lengths in R0), thickness t (h = t/R),
opening half-angle Theta, rise H = R (1 - cos Theta). The classical analyses (Budiansky
1959; Huang 1964; Dumir & Nath 1984; Teng & Rotter 1989) tabulate the snap pressure against
the geometric parameter

    lambda_B = 2 [3 (1 - nu^2)]^(1/4) sqrt(H / t),

so that, given lambda_B and R/t, 1 - cos Theta = lambda_B^2 / (4 sqrt(3 (1 - nu^2)) R/t),
and in units of the buckling pressure of the complete sphere (Zoelly)

    p0 = 2 E t^2 / (R^2 sqrt(3 (1 - nu^2))).

Load: a uniform pressure p on the deformed surface (a follower load), positive toward the
centre of curvature (external pressure, pushing the apex down). It enters the energy as
p V, V the volume between the cap and the plane of its clamped edge
(:mod:`shellbvp.euler_lagrange`). The scene's parameter is the pressure in mu* h0 / R0,
P = p R0 / (mu* h0) = (p / p0) c with c = 2 (E / mu*) h / sqrt(3 (1 - nu^2)).

Material: the Koiter shell with Poisson ratio nu (the classical analyses' model; E = 2 mu*
(1 + nu)); or the paper's Ciarlet-Geymonat (``material="cg"``, lam = lambda*/mu*, so that
nu = lam / (2 (lam + 1)), E = mu* (3 lam + 2) / (lam + 1)) and incompressible neo-Hookean
(``"nh"``: nu = 1/2, E = 3 mu*) reductions; E and nu of p0 and lambda_B are then the 3D ones.
Boundary conditions: edge clamped (r, z, tangent at their reference values), apex free of
point force. No stimulus (the target is the reference sphere).
Observable: w, the vertical displacement of the apex relative to the edge, in R0, positive
along +z (so negative under external pressure).
Snap: the first fold (maximum) of p along the branch from p = 0, found by pseudo-arclength
continuation, which passes points where the apex deflection reverses (lambda_B >= ~6)
before the pressure maximum. We compute the axisymmetric fold; for lambda_B > ~5.5 an
asymmetric bifurcation may come first in the real shell (Huang 1964).
"""

from __future__ import annotations

import math

import shellbvp
from shellbvp import ContinuationOptions, PressureResult, Scene, spherical_cap
from shellbvp.cache import atomic_write_text

__all__ = ["scene", "geometry", "pressure_scale", "branch", "critical_pressure",
           "PressureResult", "membrane_state", "pressure", "first_instability"]

#: the branch stops when the apex has gone this many rises down (past full inversion, -2 H)
W_STOP_RISES = 2.4
#: longest continuation step. The fold is located at prescribed apex deflection w, which
#: must be a coordinate of the branch around it; for lambda_B ~ 8 the apex turns back just
#: past the fold, and a longer step (ds_max = 100, the kappa_s default) brackets the fold
#: together with that turn (fold location then fails at lambda_B = 8, R/t = 100). With 20,
#: all of lambda_B = 3.5, 3.625, ..., 9 at R/t = 100 locate their fold; a failure is retried
#: with steps four times shorter.
DS_MAX = 20.0


def _options(ds_max: float) -> ContinuationOptions:
    """Long steps to the first fold, from a first step of 5 (the steps these scenes were
    validated with), without the fold probe: the apex deflection turns with the pressure
    at the fold, so a point with it prescribed does not bracket the fold."""
    return ContinuationOptions.to_first_fold().with_(ds=5.0, ds_max=ds_max, fold_probe=False)


def pressure(p):
    """The scene's parameter is the pressure itself, in mu* h0 / R0."""
    return p


def _elastic_constants(material, nu, lam):
    """(E / mu*, nu) of the material (the 3D constants for cg and nh)."""
    if material == "koiter":
        return 2.0 * (1.0 + nu), nu
    if material == "cg":
        return (3.0 * lam + 2.0) / (lam + 1.0), lam / (2.0 * (lam + 1.0))
    return 3.0, 0.5


def _check(lambda_B, R_over_t, material, nu, lam):
    for name, v in (("lambda_B", lambda_B), ("R_over_t", R_over_t)):
        if not (isinstance(v, (int, float)) and math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a positive number, got {v!r}")
    if R_over_t <= 1:
        raise ValueError(f"R_over_t must exceed 1 (a shell thinner than its radius), got "
                         f"{R_over_t!r}")
    if material not in ("koiter", "cg", "nh"):
        raise ValueError(f"material must be one of ('koiter', 'cg', 'nh'), got {material!r}")
    if material == "koiter" and not (isinstance(nu, (int, float)) and -1.0 < nu < 1.0):
        raise ValueError(f"nu must lie in (-1, 1) (Poisson ratio), got {nu!r}")
    # the Poisson ratio of cg follows from lam, nh has none: a nu that changes nothing is
    # refused (the Koiter default 0.3 means "absent" there), and so is a lam for koiter/nh
    if material != "koiter" and nu != NU:
        raise ValueError(f"nu = {nu!r} does not apply to material={material!r} (its Poisson "
                         f"ratio follows from the material): leave nu at its default {NU}")
    if material != "cg" and lam != 1.0:
        raise ValueError(f"lam = {lam!r} does not apply to material={material!r}: leave lam "
                         f"at its default 1.0")


#: the default Poisson ratio of the Koiter shell (the classical tables' nu = 0.3)
NU = 0.3


def geometry(lambda_B, R_over_t=100.0, nu=0.3, *, material="koiter", lam=1.0):
    """(Theta, h) of the cap with geometric parameter lambda_B and radius-to-thickness ratio
    R/t: h = t/R and 1 - cos Theta = lambda_B^2 / (4 sqrt(3 (1 - nu^2)) R/t), nu the
    material's Poisson ratio. Raises ValueError for a cap that is not one (rise beyond a
    hemisphere)."""
    _check(lambda_B, R_over_t, material, nu, lam)
    _, nu_ = _elastic_constants(material, nu, lam)
    rise = lambda_B**2 / (4.0 * math.sqrt(3.0 * (1.0 - nu_**2)) * R_over_t)
    if rise >= 1.0:
        raise ValueError(f"lambda_B = {lambda_B!r} at R_over_t = {R_over_t!r} asks for a rise "
                         f"beyond a hemisphere (H/R = {rise:.3g} >= 1): lambda_B must be below "
                         f"{math.sqrt(4.0 * math.sqrt(3.0 * (1.0 - nu_**2)) * R_over_t):.4g}")
    return math.acos(1.0 - rise), 1.0 / R_over_t


def pressure_scale(h, nu=0.3, *, material="koiter", lam=1.0) -> float:
    """c = p0 R0 / (mu* h0): the scene's pressure P (in mu* h0 / R0) is (p / p0) c."""
    E, nu_ = _elastic_constants(material, nu, lam)
    return 2.0 * E * h / math.sqrt(3.0 * (1.0 - nu_**2))


def scene(lambda_B, R_over_t=100.0, nu=0.3, *, material="koiter", lam=1.0,
          model="relaxed") -> Scene:
    """The clamped cap of geometric parameter lambda_B under external pressure (module
    docstring); its parameter is the pressure P = p R0 / (mu* h0)."""
    theta, h = geometry(lambda_B, R_over_t, nu, material=material, lam=lam)
    # only the parameter the material uses goes to the scene (which refuses the others); no
    # stimulus: the target is the reference sphere
    return Scene(geometry=spherical_cap(theta), h=h, lam=lam,
                 nu=nu if material == "koiter" else 0.5, model=model, material=material,
                 ends=("pole", "clamped"), parameter="pressure",
                 parameter_unit="R0_over_mu_h0", pressure=pressure)


def branch(lambda_B, R_over_t=100.0, nu=0.3, *, material="koiter", lam=1.0,
           model="relaxed", n_folds=1, method="spectral", tol=1e-8, csv_path=None,
           options: ContinuationOptions | None = None) -> shellbvp.Branch:
    """The branch from p = 0 (a :class:`shellbvp.Branch`, ``p`` the pressure in mu* h0 / R0,
    ``w`` the apex displacement in R0), by pseudo-arclength continuation, until ``n_folds``
    folds (default: the snap) or the apex has gone ``W_STOP_RISES`` rises down. Folds are
    refined until p / p0 changes by at most ``tol``. ``csv_path``: write p / p0 against the
    apex deflection w / t (and w / H), with the folds marked, atomically."""
    sc = scene(lambda_B, R_over_t, nu, material=material, lam=lam, model=model)
    c = pressure_scale(sc.h, nu, material=material, lam=lam)
    H = sc.geometry.rise
    options = _options(DS_MAX).with_(fold_tol=tol * c) if options is None \
        else options.with_fold_tol(tol * c, scale=c)
    b = shellbvp.follow(sc, method=method, p0=0.0, n_folds=n_folds,
                        w_stop=(-W_STOP_RISES * H, math.inf), options=options)
    if csv_path is not None:
        lines = ["p_over_p0,w_apex_over_t,w_apex_over_H,is_fold"]
        for p, w, _, _, _, _, fold in b.rows():
            lines.append(f"{p / c!r},{w / sc.h!r},{w / H!r},{int(fold)}")
        atomic_write_text(csv_path, "\n".join(lines) + "\n")
    return b


def critical_pressure(lambda_B, *, R_over_t=100.0, nu=0.3, material="koiter", lam=1.0,
                      model="relaxed", tol=1e-8, method="spectral",
                      options: ContinuationOptions | None = None) -> PressureResult:
    """p_cr / p0: the first pressure maximum of the branch from p = 0 (:func:`branch`),
    refined on the method's ladder until it changes by at most ``tol``."""
    if not (isinstance(tol, (int, float)) and 0 < tol < 1):
        raise ValueError(f"tol must lie in (0, 1), got {tol!r}")
    try:
        b = branch(lambda_B, R_over_t, nu, material=material, lam=lam, model=model,
                   method=method, tol=tol, options=options)
    except shellbvp.ConvergenceError:
        if options is not None:
            raise
        # the apex turned back next to the fold within one step: shorter steps separate them
        b = branch(lambda_B, R_over_t, nu, material=material, lam=lam, model=model,
                   method=method, tol=tol,
                   options=_options(DS_MAX / 4))
    sc = b.scene
    c = pressure_scale(sc.h, nu, material=material, lam=lam)
    if not b.folds:
        if b.stop:
            raise shellbvp.ConvergenceError(f"critical_pressure: the branch ended before a "
                                            f"fold: {b.stop}")
        return PressureResult(float(lambda_B), float(R_over_t), nu, material, sc.length, sc.h,
                              False, math.nan, math.nan, math.nan, None, b)
    f = b.folds[0]
    return PressureResult(float(lambda_B), float(R_over_t), nu, material, sc.length, sc.h,
                          True, float(f.p) / c, float(f.error_estimate) / c, float(f.w), f, b)


def membrane_state(p_over_p0, lambda_B, R_over_t=100.0, nu=0.3, *, material="koiter",
                   lam=1.0):
    """The membrane solution of a sphere under small uniform external pressure, away from the
    edge layer: a uniform contraction r -> (1 - e) r with equal stresses N = p R / 2
    (compressive), i.e. strain e = N (1 - nu) / (E t) = (p/p0) c (1 - nu) / (2 E/mu*)
    (linear theory). Returns (e, P) with P the scene's pressure."""
    _, h = geometry(lambda_B, R_over_t, nu, material=material, lam=lam)
    E, nu_ = _elastic_constants(material, nu, lam)
    c = pressure_scale(h, nu, material=material, lam=lam)
    P = p_over_p0 * c
    return P / 2.0 * (1.0 - nu_) / E, P


def first_instability(lambda_B, R_over_t=100.0, nu=0.3, *, material="koiter", lam=1.0,
                      model="relaxed", tol: float = 1e-6,
                      degree: int | None = None) -> shellbvp.Instability:
    """The first instability of the clamped cap under pressure, p = p / p0: the axisymmetric
    snap (kind ``"fold"``) or a bifurcation into n circumferential waves before it
    (:func:`shellbvp.first_instability`; the follower pressure's stiffness included). The
    classical result (Huang 1964) is a bifurcation below the snap for lambda_B above
    ~5.5."""
    b = branch(lambda_B, R_over_t, nu, material=material, lam=lam, model=model,
               tol=min(tol, 1e-8))
    c = pressure_scale(b.scene.h, nu, material=material, lam=lam)
    return shellbvp.first_instability(b, tol=tol, degree=degree).scaled(c, "p_over_p0")
