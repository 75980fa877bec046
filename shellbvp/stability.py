"""Stability of an equilibrium: the second variation of the reduced energy, discretised on its
own, independently of the Euler-Lagrange system the equilibrium was solved from.

The energy of the axisymmetric shell is a functional of the meridian's tangent angle theta(s)
and meridional stretch lam1(s) (relative to the target metric); r follows from
r' = g1 lam1 cos(theta) (from the regular pole r ~ g1 lam1 r0, or from its value r_a at a
first end off the axis, then an unknown too), and

    E = 2 pi int t W(lam1, r / (g2 r0), -theta' / (g1 lam1), -sin(theta) / r) g1 g2 r0 ds
        + pi P int r^2 g1 lam1 sin(theta) ds - (work of the end loads)

(:mod:`shellbvp.kinematics`; P the pressure, if any). Here theta and lam1 are the unknowns
at the Chebyshev points of every piece (lam1 may jump at an interface, theta may not but
for a kink of the geometry, where it turns by the reference's angle), E is evaluated by
Clenshaw-Curtis quadrature with r from spectral integration, and its Hessian is taken by
JAX. The constraints (regular poles theta - theta_pole = (s - s_pole) theta', the
interfaces, and the ends' fixed values: r and theta at a clamped end, r at a hinged or
diaphragm one, theta at a sliding or symmetry end, and where both ends hold z their distance int g1 lam1 sin(theta)
ds) enter through the Hessian of the Lagrangian on their tangent space, with multipliers
from the gradient (least squares). The eigenvalues of that reduced Hessian against the
quadrature mass of the surface are the discrete second variation: all positive at a stable
equilibrium, one crossing zero at a fold or bifurcation. Where the reduced energy loses
ellipticity (the Legendre condition, :mod:`shellbvp.ellipticity`) the continuum second
variation is unbounded below: a negative eigenvalue appears whose value grows and whose
mode narrows as the resolution grows.
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

    from . import kinematics as K
    from .bvp import ShellBVP
    from .compiled import energy_function
    from .fields import point_fields
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
    c = np.asarray(sc.field_parameters, dtype=float)
    F = jnp.asarray(np.stack([point_fields(sc, i, s[i], eq.p, c, np) for i in range(P)],
                             axis=1))                                # (fields, P, N + 1)
    pressure = 0.0 if sc.pressure is None else float(sc.pressure(eq.p))
    D, Q, w = differentiation_matrix(N), _cumulative(N), _clenshaw_curtis(N)
    W = energy_function(sc.model, sc.material, sc.through_thickness_stimulus)
    mat, h = sc.material_parameter, sc.h
    n = P * (N + 1)
    geo = sc.geometry
    ref = [geo.at_end(which) for which in ("first", "second")]
    kinds = tuple(e.kind for e in sc.ends)
    pole_first = kinds[0] == "pole"
    loads = [end.conjugate(eq.p, float(r[0])) for end, r in zip(sc.ends, ref)]
    # the rings: (the piece they end, (Q_r, Q_z)) at p
    rings = [(i, ring.conjugate(eq.p)) for ring, i in zip(sc.rings, sc.ring_interfaces)]
    anchor = sc.z_anchor          # the end whose z stays at its reference's
    moved = [0.0 if e.displacement is None else float(e.displacement(eq.p)) for e in sc.ends]

    def shape(v):
        th, l1 = v[:n].reshape(P, N + 1), v[n:2 * n].reshape(P, N + 1)
        lam = F[K.G1] * l1
        r_start = lam[0, 0] * F[K.R0][0, 0] if pole_first else v[2 * n]
        rs = []
        for i in range(P):
            r_i = r_start + L[i] * (Q @ (lam[i] * jnp.cos(th[i])))
            rs.append(r_i)
            r_start = r_i[-1]
        return th, l1, jnp.stack(rs)

    def heights(th, l1):
        """z at the pieces' ends (P + 1,) less the anchoring end's: z' = -g1 lam1 sin(theta)
        integrated piece by piece."""
        d = jnp.sum(jnp.asarray(L)[:, None] * w * F[K.G1] * l1 * jnp.sin(th), axis=1)
        drop = jnp.concatenate([jnp.zeros(1), jnp.cumsum(d)])       # int_0^s Lambda sin
        return -drop if anchor == 0 else drop[-1] - drop

    def drop(th, l1):
        z = heights(th, l1)
        return z[0] - z[-1]

    def energy(v):
        th, l1, r = shape(v)
        dth = jnp.stack([D @ th[i] / L[i] for i in range(P)])
        X = K.principal_state(r, th, F[K.G1] * l1, dth, F[K.R0], F[K.G1], F[K.G2], jnp)
        dens = K.energy_per_length(W, X, F, mat, h)
        E = 2 * math.pi * jnp.sum(jnp.asarray(L)[:, None] * w * dens)
        load = math.pi * pressure * jnp.sum(jnp.asarray(L)[:, None] * w * r**2 * F[K.G1]
                                            * l1 * jnp.sin(th))
        # the dead loads' work Q . (r, z, theta) on the ends and the rings' circles, z
        # relative to the anchoring end's (a constant there)
        z = heights(th, l1)
        ends = ((r[0, 0], z[0], th[0, 0]), (r[-1, -1], z[-1], th[-1, -1]))
        work = sum(Q[0] * x[0] + Q[1] * x[1] + Q[2] * x[2] for Q, x in zip(loads, ends))
        work = work + sum(Q[0] * r[i, -1] + Q[1] * z[i + 1] for i, Q in rings)
        return E + load - 2 * math.pi * work

    def constraints(v):
        th, l1, r = shape(v)
        rows = []
        if pole_first:
            rows.append(th[0, 0] - (s[0, 0] - 0.0) * (D[0] @ th[0]) / L[0])
        if kinds[1] == "pole":
            # the meridian closes on the axis: regular (r ~ g1 lam1 r0), tangent at a right
            # angle to it
            rows.append(th[-1, -1] - math.pi - (s[-1, -1] - sc.length) * (D[-1] @ th[-1])
                        / L[-1])
            rows.append(r[-1, -1] - F[K.G1][-1, -1] * l1[-1, -1] * F[K.R0][-1, -1])
        rows += [th[i + 1, 0] - th[i, -1] - bvp.jumps[i, 2] for i in range(P - 1)]
        for k, (i, j) in enumerate(((0, 0), (-1, -1))):
            r0, _, th0 = ref[k]
            if kinds[k] in ("clamped", "symmetry", "sliding"):
                rows.append(th[i, j] - th0)
            if kinds[k] in ("clamped", "hinged", "diaphragm"):
                rows.append(r[i, j] - r0)
        if all(e.fixes_z for e in sc.ends):
            rows.append(drop(th, l1) - (ref[0][1] + moved[0] - ref[1][1] - moved[1]))
        # (none: a single piece whose ends hold nothing but z at one of them)
        return jnp.stack(rows) if rows else jnp.zeros(0)

    # the state at the nodes, from the equilibrium's own interpolant and inner roots
    Y = np.stack([eq.unknowns(s[i]) for i in range(P)])                 # (P, 6, N + 1)
    # the equilibrium's inner roots, interpolated, start the inner solves at these points
    hint = np.stack([np.stack([np.interp(s[i], eq.s, eq.lam1), np.interp(s[i], eq.s, eq.k1)],
                              axis=-1) for i in range(P)])
    X0, _ = bvp.state(s, Y, eq.p, hint)
    parts = [Y[:, 2].ravel(), X0[:, 0].ravel()]
    if not pole_first:
        parts.append([Y[0, 0, 0]])
    v0 = jnp.asarray(np.concatenate(parts))
    grad = np.asarray(jax.grad(energy)(v0))
    A = np.asarray(jax.jacfwd(constraints)(v0))
    mu = np.linalg.lstsq(A.T, grad, rcond=None)[0] if A.shape[0] else np.zeros(0)
    lagrangian = lambda v: energy(v) - jnp.dot(jnp.asarray(mu), constraints(v))  # noqa: E731
    Hess = np.asarray(jax.hessian(lagrangian)(v0))
    from scipy.linalg import eigh, null_space

    Z = null_space(A) if A.shape[0] else np.eye(v0.size)
    # the mass of the surface's L2 norm (area element g1 g2 r0): with plain quadrature
    # weights a mode crowded onto a pole costs energy ~ s but keeps full mass, and the
    # smallest eigenvalue falls with the resolution for no physical reason; the first
    # end's radius (off the axis) weighs as its end's area
    area = np.asarray(F[K.G1] * F[K.G2] * F[K.R0])
    mass = np.tile((L[:, None] * w[None, :] * area).ravel(), 2)
    if not pole_first:
        mass = np.append(mass, L[0] * w[0] * area[0, 0])
    K_ = Z.T @ Hess @ Z
    M = Z.T @ (mass[:, None] * Z)
    vals, vecs = eigh((K_ + K_.T) / 2, M, subset_by_index=[0, min(count, K_.shape[0]) - 1])
    modes = Z @ vecs
    modes /= np.sqrt(np.sum(mass[:, None] * modes**2, axis=0))
    return SecondVariation(eigenvalues=vals, s=s.ravel(), theta_modes=modes[:n].T,
                           lam1_modes=modes[n:2 * n].T, nodes=int(N),
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
    sc = system.scene
    return (f"the discrete energy's Hessian at fixed {name} loses positive definiteness "
            f"before {sc.quote(pt.p)} (smallest eigenvalue {lam:.3g}, its mode largest at "
            f"{sc.quote_s(s_mode)}; Legendre condition min {L:.3g} at {sc.quote_s(s_L)}, "
            f"{L0:.3g} on "
            f"the undeformed shell): {verdict} ({where})")


# beyond axisymmetry (the second variation per circumferential harmonic): the same question,
# asked of the full 2D shell
# (the first instability along a branch: shellbvp.first_instability)
from .harmonics import HarmonicSpectrum, Modes, modes  # noqa: E402
