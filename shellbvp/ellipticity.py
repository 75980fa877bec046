"""Ellipticity of the reduced energy: the Legendre condition along a solution, and why a
branch ends where it fails.

The first-order system solves for (lam1, k1) from y at every point; that inversion is
regular, and the root the physical one, exactly where the Hessian of W in the meridian's
highest derivatives is positive definite (the Legendre condition of the axisymmetric energy).
"""

from __future__ import annotations

import math

import numpy as np

from .errors import ConvergenceError

__all__ = ["legendre_form", "ellipticity", "legendre_along", "elliptic_point", "stall_reason",
           "LEGENDRE_LOST"]


def legendre_form(X, g, H):
    """(L00, L01, L11): the Hessian of W in (lam1, kappa = lam1 k1) at fixed (lam2, k2),
    from the gradient g and Hessian H of W in X = (lam1, lam2, k1, k2) (last axes).
    k1 = kappa / lam1, so it is J^T H_(lam1, k1) J plus the moment W_k1 times the Hessian
    of k1. Arithmetic and indexing only: the compiled inner solve (JAX) and the host
    (numpy) use this one expression."""
    lam1, kap = X[..., 0], X[..., 0] * X[..., 2]
    a11, a13, a33 = H[..., 0, 0], H[..., 0, 2], H[..., 2, 2]
    d = -kap / lam1**2                     # dk1/dlam1; dk1/dkappa = 1/lam1
    L00 = a11 + 2 * a13 * d + a33 * d * d + g[..., 2] * 2 * kap / lam1**3
    L01 = (a13 + a33 * d) / lam1 - g[..., 2] / lam1**2
    L11 = a33 / lam1**2
    return L00, L01, L11


def ellipticity(X, g, H, h):
    """Ellipticity of the reduced energy at states X (..., 4) = (lam1, lam2, k1, k2), from
    the gradient g (..., 4) and Hessian H (..., 4, 4) of W in X.

    Returns (legendre, block, full), smallest eigenvalues of:

    * ``legendre``: the Hessian of W in the meridian's highest derivatives, the stretch
      lam1 and kappa = lam1 k1 = -theta' / g1 (the rotation per reference length), at fixed
      lower-order state (lam2, k2). This is the Legendre condition of the axisymmetric
      energy, and exactly the condition under which the first-order formulation can solve
      for (lam1, k1) (its inner Jacobian is this Hessian times a regular change of
      variables). Because k1 = kappa / lam1 it is the (lam1, k1) block plus the moment term
      W_k1 d^2 k1: a large moment can break it while the block is still definite;
    * ``block``: the (lam1, k1) block of H;
    * ``full``: the whole H (at the pole, where lam2 = lam1 and k2 = k1 are tied).

    k and kappa are scaled by h / sqrt(12) first, so that bending and stretching eigenvalues
    are both O(1); definiteness does not depend on the scaling (Sylvester).
    """
    X, g, H = np.asarray(X), np.asarray(g), np.asarray(H)
    c = math.sqrt(12) / h
    d = np.array([1.0, 1.0, c, c])
    full = np.linalg.eigvalsh(H * d[:, None] * d[None, :])[..., 0]
    blk = H[..., [0, 2], :][..., :, [0, 2]]
    block = np.linalg.eigvalsh(blk * np.array([1.0, c])[:, None] * np.array([1.0, c]))[..., 0]
    L00, L01, L11 = legendre_form(X, g, H)
    L = np.stack([np.stack([L00, L01], -1), np.stack([L01, L11], -1)], -2)
    legendre = np.linalg.eigvalsh(L * np.array([1.0, c])[:, None] * np.array([1.0, c]))[..., 0]
    return legendre, block, full


#: a stall is put down to a loss of ellipticity when the Legendre condition at the last
#: point has fallen below this fraction of its value at the start of the branch
LEGENDRE_LOST = 0.02


def legendre_along(system, U, p):
    """(min over the nodes of the Legendre condition, s where): see
    :func:`ellipticity`."""
    from .methods.base import MidSurface, implements

    if implements(system, MidSurface):          # the state read from the mid-surface
        st = system.state_at(U, p, system.output_points())
        leg, _, _ = ellipticity(st["X"].T, st["gw"], st["Hw"], system.scene.h)
        j = int(np.argmin(leg))
        return float(leg[j]), float(st["s"][j])
    bvp = system.bvp
    t, Ys = system.nodes(U, p)
    s_all = np.stack([bvp.s_of(i, t) for i in range(bvp.P)])
    X, _, g, H = bvp.state_and_hessian(s_all, Ys.reshape(bvp.P, bvp.n, t.size), p)
    leg, _, _ = ellipticity(np.moveaxis(X, 1, -1), np.moveaxis(g, 1, -1),
                            np.moveaxis(H, (1, 2), (-2, -1)), bvp.scene.h)
    j = np.unravel_index(int(np.argmin(leg)), leg.shape)
    return float(leg[j]), float(s_all[j])


def elliptic_point(system, pt) -> str:
    """"" if the Legendre condition holds at every node of point pt, else why not."""
    try:
        L, s = legendre_along(system, pt.U, pt.p)
    except ConvergenceError as exc:
        return f"the state at {system.bvp.scene.quote(pt.p)} cannot be evaluated: {exc}"
    if L > 0:
        return ""
    sc = system.bvp.scene
    return (f"the reduced energy loses ellipticity before {sc.quote(pt.p)}: its Legendre "
            f"condition (Hessian of W in the stretch lam1 and the rotation rate lam1 k1) is "
            f"{L:.3g} < 0 at {sc.quote_s(s)} there; past this the "
            f"equations admit solutions that depend on the discretisation (not physics)")


def stall_reason(system, pts, message) -> str:
    """The reason of a continuation stall: a loss of ellipticity of the reduced energy when
    the Legendre condition falls to ~0 along the branch (then no formulation in the
    meridian's derivatives has a smooth solution beyond), else the solver's message (a
    mid-surface method's own message, which says what its Hessian found)."""
    from .methods.base import MidSurface, implements

    if implements(system, MidSurface):
        return _surface_stall(system, pts, message)
    if len(pts) < 3:
        return message
    try:
        L0, _ = legendre_along(system, pts[0].U, pts[0].p)
        (L1, _), (L2, s2) = (legendre_along(system, q.U, q.p) for q in pts[-2:])
    except ConvergenceError:
        return message
    if not (L0 > 0 and L2 < LEGENDRE_LOST * L0):
        return message
    p1, p2 = pts[-2].p, pts[-1].p
    p_star = p2 - L2 * (p2 - p1) / (L2 - L1) if L2 != L1 else p2
    sc = system.bvp.scene
    if system.bvp.anisotropic_apex and s2 < 2 * system.bvp.eps:
        return (f"the reduced energy loses ellipticity at the pole offset {sc.quote_s(s2)} as "
                f"{sc.quote(p_star)} (Legendre condition {L0:.3g} -> {L2:.3g}): the "
                f"target curvature is anisotropic at the apex, where the curvatures diverge "
                f"like log s, so this stop moves with the pole offset eps; a limit of the "
                f"formulation at the apex, not a property of the shell at finite s")
    return (f"the reduced energy loses ellipticity at {sc.quote_s(s2)}: its Legendre "
            f"condition (Hessian of W in the stretch lam1 and the rotation rate lam1 k1) falls "
            f"from {L0:.3g} at the start to {L2:.3g} at {sc.quote(p2)}, extrapolating to zero "
            f"at {sc.quote(p_star)}; the first-order system has no solution past it and "
            f"the reduced model no smooth one (solver: {message.splitlines()[0][:160]})")


def _surface_stall(system, pts, message) -> str:
    """A mid-surface method's stall: its own message (a Hessian veto says what it found),
    or the solver's with what the Hessian and the Legendre condition are at the last point
    (a stall where both are ~0 is a singular point of the reduced model)."""
    if message.startswith("the discrete energy's Hessian") or not pts:
        return message
    last = pts[-1]
    try:
        sv = system.spectrum(last.U, last.p, count=1)
        L, s_L = legendre_along(system, last.U, last.p)
    except ConvergenceError:
        return message
    s_mode = float(sv.s[int(np.argmax(np.abs(sv.theta_modes[0])))])
    sc = system.scene
    return (f"{message.splitlines()[0][:160]}; at the last point ({sc.quote(last.p)}) the "
            f"discrete energy's Hessian has its smallest eigenvalue {sv.eigenvalues[0]:.3g} "
            f"(mode largest at {sc.quote_s(s_mode)}) and the Legendre condition its minimum "
            f"{L:.3g} at {sc.quote_s(s_L)}")
