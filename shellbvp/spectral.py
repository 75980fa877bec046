"""Chebyshev spectral collocation of a scene's multi-point BVP: a finite system R(U, p) = 0.

Every piece [a_i, b_i] of the meridian (pole offset eps, then the scene's interfaces) carries
the state y = (r, z, theta, m, f_r, f_z) at the N + 1 Chebyshev points of the second kind,
t_k = (1 - cos(pi k / N)) / 2 in the piece coordinate t in [0, 1] (they cluster at both ends,
where the pole and the edge boundary layer of width ~ sqrt(h R0) live). The ODE
y' = (b_i - a_i) f(s, y) is imposed by rectangular collocation (Driscoll & Hale, IMA J. Numer.
Anal. 36, 2016): the residual D y - (b - a) f is resampled by barycentric interpolation onto
the N Chebyshev points of the first kind, which leaves exactly one row per component and
piece for the boundary and interface conditions (same conditions as the collocation
back-end: pole, continuity of y at interfaces, edge). For a smooth (analytic) solution the
error falls geometrically with N; the resolution is checked by the decay of the Chebyshev
coefficients (:meth:`SpectralSystem.tail`).

The Jacobian dR/dU is exact and assembled from the per-node blocks df/dy (implicit
differentiation of the constitutive equations, :mod:`shellbvp.axisym`); dR/dp comes from
forward-mode differentiation of the fields. The result is a :class:`shellbvp.discrete`
system: dense, of size 6 P (N + 1), solved by LU.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from .axisym import ConvergenceError
from ._jax import jax

import jax.numpy as jnp  # noqa: E402

__all__ = ["SpectralSystem", "chebyshev_points", "differentiation_matrix", "coefficients"]


@lru_cache(maxsize=None)
def chebyshev_points(N: int) -> np.ndarray:
    """The N + 1 Chebyshev points of the second kind on [0, 1], increasing."""
    return (1.0 - np.cos(np.pi * np.arange(N + 1) / N)) / 2.0


@lru_cache(maxsize=None)
def differentiation_matrix(N: int) -> np.ndarray:
    """d/dt on :func:`chebyshev_points` (Trefethen, Spectral Methods in MATLAB, cheb.m, mapped
    from x = cos(pi k / N) in [-1, 1] to t = (1 - x) / 2, so d/dt = -2 d/dx)."""
    x = np.cos(np.pi * np.arange(N + 1) / N)
    c = np.ones(N + 1)
    c[0] = c[-1] = 2.0
    c *= (-1.0) ** np.arange(N + 1)
    dX = x[:, None] - x[None, :]
    D = np.outer(c, 1.0 / c) / (dX + np.eye(N + 1))
    D -= np.diag(D.sum(axis=1))  # negative-sum trick: exact derivative of constants
    return -2.0 * D


@lru_cache(maxsize=None)
def _resampling_matrix(N: int) -> np.ndarray:
    """Barycentric interpolation from the N + 1 second-kind points to the N first-kind points
    (1 - cos(pi (j + 1/2) / N)) / 2 (no node coincides, so no special case)."""
    t = chebyshev_points(N)
    tau = (1.0 - np.cos(np.pi * (np.arange(N) + 0.5) / N)) / 2.0
    w = (-1.0) ** np.arange(N + 1)
    w[0] *= 0.5
    w[-1] *= 0.5
    C = w[None, :] / (tau[:, None] - t[None, :])
    return C / C.sum(axis=1, keepdims=True)


def coefficients(values: np.ndarray) -> np.ndarray:
    """Chebyshev coefficients (along the last axis) of the interpolant through values at
    :func:`chebyshev_points` (a DCT-I; coefficient k multiplies T_k(1 - 2 t))."""
    from scipy.fft import dct

    N = values.shape[-1] - 1
    c = dct(values, type=1, axis=-1) / N
    c[..., 0] /= 2.0
    c[..., -1] /= 2.0
    return c


def _evaluate(coef: np.ndarray, t: np.ndarray) -> np.ndarray:
    """The interpolant with coefficients ``coef`` (..., N + 1) at t: shape (..., len(t))."""
    return np.polynomial.chebyshev.chebval(1.0 - 2.0 * np.asarray(t, dtype=float), coef.T)


@lru_cache(maxsize=16)
def _kernel(model, material, rhob1, metric, fields, P, N):
    """One compiled program per (model, scene fields, P, N): the fields and their parameter
    derivative (forward mode), f, df/dy, df/dp at every node, and the pole conditions with
    their derivatives in y(eps) and p (one dispatch per evaluation)."""
    from .axisym import point_functions

    pf = point_functions(model, material, rhob1, metric)
    rjp = jax.vmap(pf["rhs_jac_p"], in_axes=(1, 0, 1, 1, None, None, 0))

    def fields_all(s, p):
        return jnp.stack([jnp.stack([jnp.asarray(v, dtype=jnp.float64) + 0.0 * s[i]
                                     for v in fields(i, s[i], p)]) for i in range(P)])

    def pole(y0, F0, eps, lam, h, held):
        _, X, _ = pf["algebraic"](y0, eps, F0, lam, h)
        third = jnp.where(held, y0[1] + y0[0] * y0[2] / 2, y0[5])
        return jnp.stack([X[0] - X[1], X[2] - X[3], third])

    def kernel(s, Y, p, eps, lam, h, held, q_init):
        F, dF = jax.jvp(lambda p_: fields_all(s, p_), (p,), (jnp.ones_like(p),))  # (P, 4, N1)
        out = [rjp(Y[i], s[i], F[i], dF[i], lam, h, q_init[i]) for i in range(P)]
        f, J, fp, ok, q = (jnp.stack([o[k] for o in out]) for k in range(5))
        F0 = F[0, :, 0]
        r0 = pole(Y[0, :, 0], F0, eps, lam, h, held)
        Jy, JF = jax.jacfwd(pole, argnums=(0, 1))(Y[0, :, 0], F0, eps, lam, h, held)
        return F, f, J, fp, ok, r0, Jy, JF @ dF[0, :, 0], q

    return jax.jit(kernel)


class SpectralSystem:
    """R(U, p) = 0 for a scene on N + 1 Chebyshev points per piece.

    U is the state y at the nodes, shape (P, 6, N + 1) flattened (m and f scaled by 12/h^2 as
    everywhere). Implements the :class:`shellbvp.discrete.DiscreteSystem` protocol.

    Arguments:
        scene: the problem.
        nodes: N, the polynomial degree per piece (>= 8).
        eps: pole offset (default 1e-4 theta, as the collocation back-end).
    """

    def __init__(self, scene, nodes: int = 48, eps: float | None = None):
        from .equilibrium import _Problem

        if not (isinstance(nodes, (int, np.integer)) and 8 <= nodes <= 400):
            raise ValueError(f"nodes must be an integer in [8, 400], got {nodes!r}")
        eps = 1e-4 * scene.theta if eps is None else float(eps)
        self.scene, self.N, self.eps = scene, int(nodes), eps
        self.problem = _Problem(scene, 0.0, eps)
        self.P = self.problem.P
        self.t = chebyshev_points(self.N)
        self.s = np.stack([self.problem.s_of(i, self.t) for i in range(self.P)])  # (P, N+1)
        self.L = self.problem.b - self.problem.a
        self.size = 6 * self.P * (self.N + 1)
        D, Pm = differentiation_matrix(self.N), _resampling_matrix(self.N)
        self._PD = Pm @ D
        self._Pm = Pm
        self._kernel = _kernel(scene.model, scene.material, float(scene.rhob1),
                               bool(scene.metric), scene.fields, self.P, self.N)
        self._q = np.full((self.P, self.N + 1, 2), np.nan)
        self.evaluations = 0

    # --- unknowns ----------------------------------------------------------------------------
    def _split(self, U):
        return np.asarray(U, dtype=float).reshape(self.P, 6, self.N + 1)

    def from_profile(self, profile) -> np.ndarray:
        """U from a callable s -> (6, n) (e.g. an Equilibrium, or the reference state)."""
        return np.stack([np.asarray(profile(self.s[i]), dtype=float)
                         for i in range(self.P)]).ravel()

    def resample(self, U, nodes: int) -> np.ndarray:
        """U interpolated onto another degree N' (the same pieces)."""
        c = coefficients(self._split(U))
        t = chebyshev_points(nodes)
        return np.stack([_evaluate(c[i], t) for i in range(self.P)]).ravel()

    def dense(self, U, p=None):
        """Stacked (6 P, n) interpolant in the piece coordinate t (the collocation layout)."""
        c = coefficients(self._split(U))
        return lambda t: np.concatenate([_evaluate(c[i], np.atleast_1d(t))
                                         for i in range(self.P)])

    def tail(self, U) -> float:
        """Resolution: max over pieces and components of the last three Chebyshev coefficients,
        relative to the component's largest coefficient (~ the interpolation error)."""
        c = np.abs(coefficients(self._split(U)))
        scale = np.maximum(c.max(axis=-1), 1e-300)
        return float(np.max(c[..., -3:].max(axis=-1) / scale))

    # --- the system --------------------------------------------------------------------------
    def evaluate(self, U, p):
        """Residual R (n,), Jacobian dR/dU (n, n) and dR/dp (n,) at (U, p)."""
        Y = self._split(U)
        N1, P, n = self.N + 1, self.P, self.size
        R = np.empty(n)
        J = np.zeros((n, n))
        Rp = np.zeros(n)
        row = 0

        def col(i, c):
            return (i * 6 + c) * N1

        sc = self.scene
        args = (self.s, Y, float(p), self.eps, sc.material_parameter, sc.h, sc.apex == "held")
        out = [np.asarray(a) for a in self._kernel(*args, self._q)]
        if not np.all(out[4]) and np.all(np.isfinite(self._q)):  # retry without warm start
            out = [np.asarray(a) for a in self._kernel(*args, np.full_like(self._q, np.nan))]
        F, f, Jn, fp, ok, r0, Jy, Jp, q = out
        if np.all(ok):
            # Warm start of the inner (lam1, k1) Newton at the next evaluation: a cache that
            # changes cost only (the inner Newton converges to 1e-13 from either start).
            self._q = q
        self.evaluations += 1
        for i in range(P):
            sc.check_fields(F[i], i, p)
        if not np.all(ok):
            i, k = np.unravel_index(np.argmin(ok), ok.shape)
            raise ConvergenceError(
                f"inner Newton for (lam1, k1) did not converge at s = {self.s[i, k]:.6g} "
                f"({sc.parameter} = {p:g}): the state is far from admissible")
        R[:3], Rp[:3] = r0, Jp
        J[:3, [col(0, c) for c in range(6)]] = Jy
        row = 3
        for i in range(P):
            fi, Ji, fpi = f[i].T, np.moveaxis(Jn[i], 0, -1), fp[i].T   # (6,N1) (6,6,N1) (6,N1)
            res = Y[i] @ self._PD.T - self.L[i] * (fi @ self._Pm.T)      # (6, N)
            R[row:row + 6 * self.N] = res.ravel()
            Rp[row:row + 6 * self.N] = (-self.L[i] * (fpi @ self._Pm.T)).ravel()
            # d res[c, j] / d Y[c', k] = delta_cc' PD[j, k] - L Pm[j, k] Jn[c, c', k]
            blk = -self.L[i] * self._Pm[None, None, :, :] * Ji[:, :, None, :]  # (6,6,N,N1)
            for c in range(6):
                blk[c, c] += self._PD
            J[row:row + 6 * self.N, col(i, 0):col(i, 0) + 6 * N1] = \
                blk.transpose(0, 2, 1, 3).reshape(6 * self.N, 6 * N1)
            row += 6 * self.N
            if i < P - 1:  # continuity of y at the interface b_i = a_{i+1}
                for c in range(6):
                    R[row + c] = Y[i, c, -1] - Y[i + 1, c, 0]
                    J[row + c, col(i, c) + N1 - 1] = 1.0
                    J[row + c, col(i + 1, c)] = -1.0
                row += 6
        # Edge conditions (3 rows).
        ye = Y[-1, :, -1]
        T = self.scene.theta
        if self.scene.edge == "free":
            R[row:] = ye[3:6]
            comps = (3, 4, 5)
        else:
            R[row:] = [ye[0] - math.sin(T), ye[1] - (math.cos(T) - 1.0), ye[2] - T]
            comps = (0, 1, 2)
        for k, c in enumerate(comps):
            J[row + k, col(P - 1, c) + N1 - 1] = 1.0
        return R, J, Rp

    def monitor(self, U):
        """The branch observable w / H (see :meth:`equilibrium._Problem.monitor`) and its
        gradient in U."""
        Y = self._split(U)
        m = float(self.problem.monitor(Y[0, :, 0], Y[-1, :, -1]))
        g = np.zeros((self.P, 6, self.N + 1))
        g[0, :, 0], g[-1, :, -1] = self.problem.monitor_gradient(Y[0, :, 0], Y[-1, :, -1])
        return m, g.ravel()
