"""Budding and vesiculation under a localized stimulus (paper Section 5.4, Figs. 5-7).

Geometry: a clamped spherical cap of radius R0 = 0.25 and thickness h0 = 0.005, so
h = h0/R0 = 0.02, opening half-angle Theta = pi/8 (lengths below in R0).
Material and model: Ciarlet-Geymonat, lam = lambda*/mu* = 7.5, ``relaxed`` (rho1, rho2
minimising the energy, the paper's eqs. (a), (b)); no through-thickness stimulus (rhob1 = 1).
Stimulus (eq. (stimulusII)): on the patch s < Theta/4 around the apex, zero outside, with an
exact interface at s = Theta/4:

    abar_aa = (1 + gamma_a,a kbar / 5) a°_aa,   bbar_aa = (1 + gamma_b,a kbar) b°_aa,

(a = 1 meridional, 2 azimuthal), so that the target stretch factors are
g_a^2 = 1 + gamma_a,a kbar / 5 and the target curvatures kb_a = bbar_aa / abar_aa
= -(1 + gamma_b,a kbar) / g_a^2 (the reference sphere has b°_aa / a°_aa = -1/R0 in our
orientation). The anisotropy ratios eta = gamma_1 / gamma_2 are taken at equal L2 norm,
gamma_1^2 + gamma_2^2 = 2, either as the paper prints them (``gammas="paper"``, the default:
0.63/1.26, 1/1 and 1.26/0.63, the equal-norm values rounded to two decimals) or exactly
(``gammas="equal-norm"``: sqrt(2 / (1 + eta^2)) (eta, 1), 0.632.../1.264...); w differs by
~1e-3 relative between the two. ``eta_a = 0`` means no metric stimulus.
Boundary conditions: edge clamped (r, z, theta at their reference values), apex free of point
force (F_z = 0).
Observable: w, the vertical displacement of the apex relative to the clamped edge, in R0,
positive along +z (the cap's axis, outward at the apex): a bud grows with w > 0.
Parameter: kbar, continued from 0 by pseudo-arclength.

Method: the energy method (:class:`shellbvp.Ritz`, direct minimisation of the discrete
energy, as the paper's COMSOL computation) wherever the first-order system meets a limit of
its own formulation: a singular apex (a conical target, eta_a not 0 or 1, or an anisotropic
target curvature, eta_b != 1) or a metric stimulus (whose inner inversion folds before the
energy stops being elliptic); the spectral method, faster, for the curvature-only isotropic
case, where both end at the same kbar (:func:`method_for`; ``Branch.stats["method"]``).

The apex core (a modelling choice). At a singular apex the target is a cone (g1 != g2 on
the axis: an excess angle for eta_a < 1, a deficit for eta_a > 1) or its curvatures differ
(eta_b != 1); the reduced 2D energy, an expansion in the thickness, then has a solution
whose curvatures grow without bound toward the apex and says nothing inside a disc of
radius ~ h0 there (h|k| >~ 1). A discretisation that resolves that disc finds its energy
non-elliptic there and stops at a kbar that moves with the resolution, inside a region far
smaller than the thickness. :func:`method_for` does not resolve it: the innermost element
spans ``CORE`` thicknesses, and where the target is a cone it is of degree ``CORE_DEGREE``,
which carries the cone's rotation across the core without its singular field (a core of
degree 6 or more resolves it again and loses stability inside it: eta = (2, 1) at kbar
118.6 on a mode at s = 0.08 h0). What this choice does to the result is measured, not
assumed: ``figures/budding_table.py`` varies the core over 0.5-2 h0 and the degree over
12-20 and reports the spread of w_apex, which is part of its error estimate; the strains
beyond ~2 h0 of the apex do not depend on it.

Stability. The energy method ends a branch where the smallest eigenvalue of its discrete
Hessian at fixed kbar crosses zero (:func:`shellbvp.stability.stable_point`); the crossings
that end the paper's cases are shown to converge under refinement (degree and core) in
``figures/budding_table.py``. The Legendre condition of the reduced energy is reported, not
used as a stop: :func:`diagnose` gives its minimum inside the apex core (s < 2 h0) and
beyond it. Past the crossings that end the anisotropic curvature-only cases the branch,
followed without the check, turns back within ~1 in kbar (eta_b = 2: at 37.04; 0.5: 38.40),
so that the paper's kbar is not on this branch.

Where the branch cannot be continued, :func:`branch` stops at the last converged point and
says why (``Branch.stop``); :func:`diagnose` reads the thin-shell validity and the
ellipticity of the reduced energy along the branch, which tell a loss of the model's
validity from a limit of the numerical formulation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

import shellbvp
from shellbvp import Chebyshev, ContinuationOptions, Ritz, Scene, spherical_cap

__all__ = ["THETA", "H", "LAM", "PATCH", "GAMMAS", "scene", "patch", "gammas", "method_for",
           "branch", "equilibrium", "equilibrium_near", "diagnose", "Diagnosis",
           "first_instability"]

THETA = math.pi / 8          # opening half-angle
H = 0.005 / 0.25             # h0 / R0
LAM = 7.5                    # lambda* / mu*
PATCH = THETA / 4            # the stimulated patch is s < PATCH
#: default Chebyshev degree per piece (each of the two pieces)
NODES = 32
#: continuation steps (arclength in the (w / H_rise, kbar) plane, mostly kbar): the branch
#: is smooth in kbar over tens of units
OPTIONS = ContinuationOptions(ds=2.0, ds_max=20.0, max_steps=400)


#: the conventions for the gammas of an anisotropy ratio (:func:`gammas`)
GAMMAS = ("paper", "equal-norm")


def gammas(eta, convention: str = "paper") -> tuple:
    """(gamma_1, gamma_2) of the anisotropy ratio eta = gamma_1 / gamma_2 at
    gamma_1^2 + gamma_2^2 = 2: ``"equal-norm"`` exactly, sqrt(2 / (1 + eta^2)) (eta, 1);
    ``"paper"`` rounded to two decimals as the paper prints them (eta = 0.5: 0.63 / 1.26,
    whose ratio is still exactly 0.5). eta = 0 gives (0, 0), no stimulus of that kind."""
    if not (isinstance(eta, (int, float, np.floating)) and math.isfinite(eta) and eta >= 0):
        raise ValueError(f"eta must be a finite number >= 0 (0: no stimulus of that kind), "
                         f"got {eta!r}")
    if convention not in GAMMAS:
        raise ValueError(f"gammas must be one of {GAMMAS}, got {convention!r}")
    if eta == 0:
        return 0.0, 0.0
    g2 = math.sqrt(2.0 / (1.0 + eta * eta))
    if convention == "paper":
        return round(eta * g2, 2), round(g2, 2)
    return eta * g2, g2


def patch(x, kbar, c):
    """The stimulus fields of eq. (stimulusII) at the reference point x, c = (gamma_a1,
    gamma_a2, gamma_b1, gamma_b2): on the patch (piece 0) g_a^2 = 1 + gamma_a,a kbar / 5
    and kb_a = (1 + gamma_b,a kbar) k_a / g_a^2 (k_a the reference's curvatures, -1/R0);
    outside it (piece 1) the reference cap. The gammas are the scene's field parameters,
    arguments of the compiled programs: every case shares them."""
    one = 0.0 * x.s + 1.0
    if x.piece == 1:                     # outside the patch: the reference cap
        return one, one, x.k1 * one, x.k2 * one
    G1, G2 = 1.0 + c[0] * kbar / 5.0, 1.0 + c[1] * kbar / 5.0
    return (G1 ** 0.5 * one, G2 ** 0.5 * one, (1.0 + c[2] * kbar) * x.k1 / G1,
            (1.0 + c[3] * kbar) * x.k2 / G2)


def scene(eta_a, eta_b, gammas: str = "paper") -> Scene:
    """The budding scene with metric anisotropy eta_a (0: curvature stimulus only) and
    curvature anisotropy eta_b (> 0); ``gammas``: ``"paper"`` (the printed 0.63 / 1.26,
    default) or ``"equal-norm"`` (exact), see :func:`gammas`."""
    ga, gb = _gammas(eta_a, gammas), _gammas(eta_b, gammas)
    if eta_b == 0:
        raise ValueError("eta_b must be > 0 (the curvature stimulus drives the bud), got 0")
    return Scene(geometry=spherical_cap(THETA), h=H, lam=LAM, model="relaxed", material="cg",
                 ends=("pole", "clamped"), fields=patch, field_parameters=(*ga, *gb),
                 breaks=(PATCH,), metric=eta_a > 0, parameter="kbar", parameter_unit="")


_gammas = gammas


#: the energy method's degree per element (its elements: two per piece, and the apex
#: layers where the apex is singular)
DEGREE = 16
#: the innermost element at a singular apex, in thicknesses h0 (module docstring: the apex
#: core), where the default grading's stop drifts with the resolution
CORE = 1.0
#: that element's degree where the target is a cone (a metric stimulus, eta_a not 0 or 1)
CORE_DEGREE = 3


def method_for(eta_a, eta_b, *, quick: bool = False):
    """The method that follows case (eta_a, eta_b) furthest correctly (module docstring):

    * eta_a = 0, eta_b = 1 (regular apex, curvature only): :class:`shellbvp.Chebyshev`
      (degree 32 per piece, 24 with ``quick``);
    * a conical target (eta_a not 0 or 1): :class:`shellbvp.Ritz` with the apex core,
      ``CORE`` h0 at degree ``CORE_DEGREE``;
    * an anisotropic target curvature with eta_b > 1 (the Legendre condition fails first
      near the apex): Ritz with a ``CORE`` h0 innermost element of the full degree;
    * otherwise (a regular apex, or eta_b < 1, whose stop at the patch edge converges on
      the default apex layers: kbar 37.48 / 37.45 / 37.43 at degree 12 / 16 / 20): Ritz.

    Every Ritz at degree 16 (12 with ``quick``)."""
    scene(eta_a, eta_b)                  # checks the anisotropy ratios
    if eta_a == 0 and eta_b == 1:
        return Chebyshev(nodes=24 if quick else NODES)
    degree = 12 if quick else DEGREE
    if eta_a not in (0, 1):
        return Ritz(degree=degree, core=CORE, core_degree=CORE_DEGREE)
    if eta_b > 1:
        return Ritz(degree=degree, core=CORE)
    return Ritz(degree=degree)


def _method(eta_a, eta_b, nodes, method):
    if method is not None and nodes is not None:
        raise ValueError("give nodes (the spectral method's degree) or method, not both")
    if method is not None:
        return shellbvp.as_method(method)
    if nodes is not None:
        return Chebyshev(nodes=nodes)
    return method_for(eta_a, eta_b)


def branch(eta_a, eta_b, kbar_max=300.0, *, nodes=None, method=None, gammas="paper",
           options: ContinuationOptions | None = None, progress=None,
           energies=False) -> shellbvp.Branch:
    """The branch kbar(w) from the undeformed cap up to ``kbar_max``.

    ``w``: the apex displacement relative to the clamped edge (R0, positive along +z).
    Folds passed are located and refined (``Branch.folds``). If the continuation stalls
    before kbar_max, the branch ends at its last converged point and ``Branch.stop`` says
    why. ``method``: default :func:`method_for` the case; ``nodes``: the spectral method at
    that Chebyshev degree per piece instead. The branch ends where the state stops being
    admissible: for the spectral method where the Legendre condition fails at a node, for
    the energy method where its Hessian at fixed kbar stops being positive definite
    (:func:`shellbvp.stability.stable_point`, which says whether the reduced energy is
    still elliptic there). ``gammas``: see :func:`scene`.
    """
    if not (isinstance(kbar_max, (int, float)) and math.isfinite(kbar_max) and kbar_max > 0):
        raise ValueError(f"kbar_max must be a finite number > 0, got {kbar_max!r}")
    m = _method(eta_a, eta_b, nodes, method)
    surface = isinstance(m, Ritz)
    return shellbvp.follow(scene(eta_a, eta_b, gammas), method=m, p0=0.0,
                           p_stop=(0.0, float(kbar_max)), options=options or OPTIONS,
                           progress=progress, energies=energies, on_stall="stop",
                           check_ellipticity=not surface, check_stability=surface)


def equilibrium(eta_a, eta_b, kbar, *, nodes=None, method=None,
                gammas="paper") -> shellbvp.Equilibrium:
    """The equilibrium at exactly ``kbar``, continued from the undeformed cap (raises
    ConvergenceError if the branch stops before); arguments as in :func:`branch`."""
    if not (isinstance(kbar, (int, float)) and math.isfinite(kbar) and kbar >= 0):
        raise ValueError(f"kbar must be a finite number >= 0, got {kbar!r}")
    m = _method(eta_a, eta_b, nodes, method)
    if kbar == 0:
        return shellbvp.solve(scene(eta_a, eta_b, gammas), 0.0, method=m)
    b = branch(eta_a, eta_b, kbar, method=m, gammas=gammas)
    if b.p[-1] < kbar:
        raise shellbvp.ConvergenceError(f"the branch stops at kbar = {b.p[-1]:.6g} < {kbar:g}: "
                                        f"{b.stop}")
    return equilibrium_near(b, int(np.argmin(np.abs(b.p - kbar))), kbar)


def equilibrium_near(b: shellbvp.Branch, i: int, kbar, *,
                     estimate_error: bool = False) -> shellbvp.Equilibrium:
    """The equilibrium at exactly ``kbar``, solved with the branch's method (``b.method``)
    from its point i (which should be the nearest)."""
    return shellbvp.solve(b.scene, float(kbar), method=b.method,
                          guess=b.equilibrium(i), estimate_error=estimate_error)


@dataclass(frozen=True)
class Diagnosis:
    """Validity and ellipticity along a branch, per point.

    Attributes:
        kbar, w: the branch points.
        h_k, h_kb: max over the meridian of h |k_a| and h |kb_a| (thin-shell validity).
        legendre: min over the meridian of the Legendre condition (smallest eigenvalue of the
            scaled Hessian of W in (lam1, lam1 k1), :attr:`shellbvp.Equilibrium.legendre`);
            s_legendre where.
        block: min over the meridian of the same for the (lam1, k1) block of the Hessian.
        pole: smallest eigenvalue of the whole scaled Hessian at the apex.
        legendre_core, legendre_beyond: min of the Legendre condition within ``2 h0`` of
            the apex (the core the reduced energy does not resolve, module docstring) and
            beyond it.
    """

    kbar: np.ndarray
    w: np.ndarray
    h_k: np.ndarray
    h_kb: np.ndarray
    legendre: np.ndarray
    s_legendre: np.ndarray
    block: np.ndarray
    pole: np.ndarray
    legendre_core: np.ndarray
    legendre_beyond: np.ndarray


def diagnose(b: shellbvp.Branch, every: int = 1) -> Diagnosis:
    """:class:`Diagnosis` of every ``every``-th point of branch ``b`` (and its last)."""
    idx = sorted(set(range(0, len(b.p), max(1, int(every)))) | {len(b.p) - 1})
    rows = []
    for i in idx:
        try:
            eq = b.equilibrium(i)
        except shellbvp.ConvergenceError:   # the state cannot be evaluated: say nan
            rows.append((b.p[i], b.w[i]) + (math.nan,) * 8)
            continue
        j = int(np.argmin(eq.legendre))
        core = eq.s < 2 * H
        rows.append((eq.p, eq.w, *eq.thin_shell, eq.legendre[j], eq.s[j],
                     eq.hessian_block.min(), eq.pole_hessian_min,
                     eq.legendre[core].min() if core.any() else math.nan,
                     eq.legendre[~core].min()))
    a = np.array(rows).T
    return Diagnosis(*a)


def first_instability(eta_a, eta_b, kbar_max=300.0, *, gammas="paper", tol: float = 1e-6,
                      degree: int | None = None) -> shellbvp.Instability:
    """The first non-axisymmetric bifurcation (or fold) along the budding branch
    (:func:`branch`, p = kbar), or kind ``"none"`` with the branch's last kbar and its
    stop reason when the branch ends first (:func:`shellbvp.first_instability`)."""
    b = branch(eta_a, eta_b, kbar_max, gammas=gammas)
    return shellbvp.first_instability(b, tol=tol, degree=degree)
