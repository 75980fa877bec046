"""Stability of an equilibrium: the second variation of the reduced energy, discretised on its
own, independently of the Euler-Lagrange system the equilibrium was solved from.

The energy of the axisymmetric shell is a functional of the meridian's tangent angle theta(s)
and meridional stretch lam1(s) (relative to the target metric); r follows from
r' = g1 lam1 cos(theta) with the regular apex r ~ g1 lam1 s, and

    E = 2 pi int W(lam1, r / (g2 sin s), -theta' / (g1 lam1), -sin(theta) / r) g1 g2 sin s ds
        + pi P int r^2 g1 lam1 sin(theta) ds                     (P: the pressure, if any)

(:mod:`shellbvp.euler_lagrange`). Here theta and lam1 are the unknowns at the Chebyshev points
of every piece (lam1 may jump at an interface, theta may not), E is evaluated by
Clenshaw-Curtis quadrature with r from spectral integration, and its Hessian is taken by JAX.
The constraints (regular apex theta = s theta', continuity of theta at interfaces, and for a
clamped edge theta(Theta) = Theta and r(Theta) = sin Theta) enter through the Hessian of the
Lagrangian on their tangent space, with multipliers from the gradient (least squares). The
eigenvalues of that reduced Hessian against the quadrature mass of the surface are the
discrete second variation: all positive at a stable equilibrium, one crossing zero at a fold
or bifurcation. Where the reduced energy loses ellipticity (the Legendre condition,
:mod:`shellbvp.ellipticity`) the continuum second variation is unbounded below: a negative
eigenvalue appears whose value grows and whose mode narrows as the resolution grows.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .results import Equilibrium


__all__ = ["SecondVariation", "second_variation", "stable_point", "modes", "Modes",
           "HarmonicSpectrum"]


@dataclass(frozen=True)
class SecondVariation:
    """The smallest eigenvalues of the discrete second variation at an equilibrium.

    Attributes:
        eigenvalues: the ``count`` smallest, increasing (energy per mu* h0 R0^2 per unit
            squared amplitude of (theta, lam1) in the quadrature norm).
        s: the nodes (meridional angle, per piece concatenated).
        theta_modes, lam1_modes: the modes' theta and lam1 components at ``s`` (one row per
            eigenvalue, each mode scaled to unit norm).
        nodes: Chebyshev degree per piece.
        projected_gradient: the norm of the discrete energy's gradient on the constraints'
            tangent space at the given state: not zero, because the state was solved from
            the Euler-Lagrange equations on another discretisation (the quadrature of the
            nonlinear energy is not that collocation); the state is about
            projected_gradient / eigenvalue away from this discretisation's stationary
            point along each mode (1e-7 / 1e-2 at kappa = 2 on the default cap, N = 24).
    """

    eigenvalues: np.ndarray
    s: np.ndarray = field(repr=False)
    theta_modes: np.ndarray = field(repr=False)
    lam1_modes: np.ndarray = field(repr=False)
    nodes: int = 0
    projected_gradient: float = math.nan

    @property
    def stable(self) -> bool:
        return bool(self.eigenvalues[0] > 0)


def _clenshaw_curtis(N):
    """Quadrature weights on [0, 1] at the Chebyshev points of the second kind."""
    from .methods.chebyshev import chebyshev_points

    x = 1.0 - 2.0 * chebyshev_points(N)
    V = np.polynomial.chebyshev.chebvander(x, N)          # V[j, k] = T_k(x_j)
    k = np.arange(N + 1)
    moments = np.where(k % 2 == 0, 2.0 / (1.0 - k.astype(float) ** 2 + (k == 1)), 0.0)
    return np.linalg.solve(V.T, moments) / 2.0


def _cumulative(N):
    """Q with (Q f)(t_j) = int_0^t_j f dt for the interpolant of f at the Chebyshev points."""
    from .methods.chebyshev import chebyshev_points

    x = 1.0 - 2.0 * chebyshev_points(N)
    V = np.polynomial.chebyshev.chebvander(x, N)
    Q = np.empty((N + 1, N + 1))
    for j in range(N + 1):
        coef = np.linalg.solve(V, np.eye(N + 1)[j])
        F = np.polynomial.chebyshev.chebint(coef, lbnd=1.0)   # F(1) = 0, t = 0 at x = 1
        Q[:, j] = -np.polynomial.chebyshev.chebval(x, F) / 2.0
    return Q


def second_variation(eq, *, nodes: int | None = None, count: int = 4) -> SecondVariation:
    """The ``count`` smallest eigenvalues and modes of the discrete second variation of the
    reduced energy at the equilibrium ``eq`` (module docstring), with ``nodes`` Chebyshev
    points per piece (default: the scene's :func:`shellbvp.default_nodes`).

    Raises ValueError for an equilibrium that did not converge or bad arguments, and
    ConvergenceError where the state cannot be evaluated at these points (no elliptic
    inner root, e.g. next to where a branch lost ellipticity).
    """
    # JAX only here: ``import shellbvp`` stays light
    from .jaxsetup import jax
    import jax.numpy as jnp

    from .bvp import ShellBVP
    from .compiled import energy_function
    from .methods.chebyshev import chebyshev_points, default_nodes, differentiation_matrix

    if not (isinstance(eq, Equilibrium) and eq.success):
        raise ValueError("second_variation needs a converged Equilibrium")
    sc = eq.scene
    N = default_nodes(sc) if nodes is None else nodes
    if not (isinstance(N, (int, np.integer)) and 8 <= N <= 128):
        raise ValueError(f"nodes must be an integer in [8, 128], got {nodes!r}")
    if not (isinstance(count, (int, np.integer)) and count >= 1):
        raise ValueError(f"count must be a positive integer, got {count!r}")
    bvp = ShellBVP(sc)
    P, t = bvp.P, chebyshev_points(N)
    L = bvp.lengths
    s = np.stack([bvp.s_of(i, t) for i in range(P)])                   # (P, N + 1)
    F = np.stack([np.broadcast_to(np.asarray(sc.field_values(i, s[i], eq.p), float), (4, N + 1))
                  for i in range(P)])                                     # (P, 4, N + 1)
    g1, g2, kb1, kb2 = (jnp.asarray(F[:, k]) for k in range(4))
    pressure = 0.0 if sc.pressure is None else float(sc.pressure(eq.p))
    D, Q, w = differentiation_matrix(N), _cumulative(N), _clenshaw_curtis(N)
    W = energy_function(sc.model, sc.material, sc.rhob1)
    mat, h, eps, clamped = sc.material_parameter, sc.h, bvp.eps, sc.edge == "clamped"
    sin_s = jnp.asarray(np.sin(s))
    n = P * (N + 1)

    def shape(v):
        th, l1 = v[:n].reshape(P, N + 1), v[n:].reshape(P, N + 1)
        r_start = g1[0, 0] * l1[0, 0] * math.sin(eps)
        rs = []
        for i in range(P):
            r_i = r_start + L[i] * (Q @ (g1[i] * l1[i] * jnp.cos(th[i])))
            rs.append(r_i)
            r_start = r_i[-1]
        return th, l1, jnp.stack(rs)

    def energy(v):
        th, l1, r = shape(v)
        dth = jnp.stack([D @ th[i] / L[i] for i in range(P)])
        dens = W(l1, r / (g2 * sin_s), -dth / (g1 * l1), -jnp.sin(th) / r, kb1, kb2, mat, h)
        E = 2 * math.pi * jnp.sum(jnp.asarray(L)[:, None] * w * dens * g1 * g2 * sin_s)
        load = math.pi * pressure * jnp.sum(jnp.asarray(L)[:, None] * w * r**2 * g1 * l1
                                            * jnp.sin(th))
        return E + load

    def constraints(v):
        th, _, r = shape(v)
        rows = [th[0, 0] - s[0, 0] * (D[0] @ th[0]) / L[0]]           # regular apex
        rows += [th[i, -1] - th[i + 1, 0] for i in range(P - 1)]      # interfaces
        if clamped:
            rows += [th[-1, -1] - sc.theta, r[-1, -1] - math.sin(sc.theta)]
        return jnp.stack(rows)

    # the state at the nodes, from the equilibrium's own interpolant and inner roots
    Y = np.stack([eq.unknowns(s[i]) for i in range(P)])                 # (P, 6, N + 1)
    # the equilibrium's inner roots, interpolated, start the inner solves at these points
    hint = np.stack([np.stack([np.interp(s[i], eq.s, eq.lam1), np.interp(s[i], eq.s, eq.k1)],
                              axis=-1) for i in range(P)])
    X, _ = bvp.state(s, Y, eq.p, hint)
    v0 = jnp.asarray(np.concatenate([Y[:, 2].ravel(), X[:, 0].ravel()]))
    grad = np.asarray(jax.grad(energy)(v0))
    A = np.asarray(jax.jacfwd(constraints)(v0))
    mu = np.linalg.lstsq(A.T, grad, rcond=None)[0]
    lagrangian = lambda v: energy(v) - jnp.dot(jnp.asarray(mu), constraints(v))  # noqa: E731
    Hess = np.asarray(jax.hessian(lagrangian)(v0))
    from scipy.linalg import eigh, null_space

    Z = null_space(A)
    # the mass of the surface's L2 norm (area element g1 g2 sin s): with plain quadrature
    # weights a mode crowded onto the apex costs energy ~ s but keeps full mass, and the
    # smallest eigenvalue falls with the resolution for no physical reason
    mass = np.tile((L[:, None] * w[None, :] * F[:, 0] * F[:, 1] * np.sin(s)).ravel(), 2)
    K = Z.T @ Hess @ Z
    M = Z.T @ (mass[:, None] * Z)
    vals, vecs = eigh((K + K.T) / 2, M, subset_by_index=[0, min(count, K.shape[0]) - 1])
    modes = Z @ vecs
    modes /= np.sqrt(np.sum(mass[:, None] * modes**2, axis=0))
    return SecondVariation(eigenvalues=vals, s=s.ravel(), theta_modes=modes[:n].T,
                           lam1_modes=modes[n:].T, nodes=int(N),
                           projected_gradient=float(np.linalg.norm(Z.T @ grad)))


def stable_point(system, pt) -> str:
    """"" if the Hessian of a mid-surface method's energy at point ``pt`` (fixed parameter,
    :meth:`shellbvp.methods.base.MidSurface.spectrum`) is positive definite, else why not,
    with where its softest mode lives and the Legendre condition there: the veto that ends
    a branch followed with ``follow(..., check_stability=True)``. The Legendre condition
    tells the two kinds of loss apart: where it has fallen to ~0 (below ``LEGENDRE_LOST``
    of its value on the undeformed shell) the reduced energy stops being elliptic and the
    discrete Hessian turns indefinite at a parameter value that moves with the resolution
    (a limit of the model); elsewhere a zero eigenvalue is a fold or bifurcation of the
    axisymmetric shell."""
    from .ellipticity import LEGENDRE_LOST, legendre_along

    sv = system.spectrum(pt.U, pt.p, count=1)
    lam = float(sv.eigenvalues[0])
    if lam > 0:
        return ""
    s_mode = float(sv.s[int(np.argmax(np.abs(sv.theta_modes[0])))])
    L, s_L = legendre_along(system, pt.U, pt.p)
    L0, _ = legendre_along(system, system.from_profile(system.bvp.reference), 0.0)
    name = system.scene.parameter
    lost = L <= LEGENDRE_LOST * L0
    verdict = ("the reduced energy is (nearly) not elliptic there: its loss of stability is "
               "ill-posed and its parameter value depends on the resolution (a limit of the "
               "reduced model, not a buckling load)" if lost else
               "the reduced energy is elliptic: a fold or bifurcation of the axisymmetric "
               "shell")
    where = ", ".join(f"{k} {v}" for k, v in system.describe().items())
    return (f"the discrete energy's Hessian at fixed {name} loses positive definiteness "
            f"before {name} = {pt.p:.6g} (smallest eigenvalue {lam:.3g}, its mode largest at "
            f"s = {s_mode:.4g}; Legendre condition min {L:.3g} at s = {s_L:.4g}, {L0:.3g} on "
            f"the undeformed shell): {verdict} ({where})")


# beyond axisymmetry (the second variation per circumferential harmonic): the same question,
# asked of the full 2D shell
# (the first instability along a branch: shellbvp.first_instability)
from .harmonics import HarmonicSpectrum, Modes, modes  # noqa: E402
