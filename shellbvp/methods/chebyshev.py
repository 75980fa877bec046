"""Chebyshev spectral collocation: the fast method (default).

Every piece carries the state at the N + 1 Chebyshev points of the second kind,
t_k = (1 - cos(pi k / N)) / 2 (they cluster at both ends, where the pole and the edge
boundary layer of width ~ sqrt(h R0) live). The ODE dy/dt = (b_i - a_i) f(s, y) is imposed
by rectangular collocation (Driscoll & Hale, IMA J. Numer. Anal. 36, 2016): the residual
D y - (b - a) f is resampled by barycentric interpolation onto the N Chebyshev points of the
first kind, which leaves exactly one row per component and piece for the boundary and
interface conditions. For an analytic solution the error falls geometrically with N; the
resolution is checked by the refinement ladder (a fold's change with the next degrees).
The Jacobian is exact, assembled from the per-node blocks df/dy of the BVP.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .base import NodalSystem

__all__ = ["Chebyshev", "ChebyshevSystem", "chebyshev_points", "differentiation_matrix",
           "regridding_matrix", "coefficients", "default_nodes", "bracketing_nodes",
           "fold_nodes", "MIN_NODES", "MAX_NODES", "REFINE_STEP", "refine_step"]

#: the smallest degree that resolves a pole region and an edge layer at all
MIN_NODES = 8
#: beyond this the dense LU (size 6 P (N + 1)) costs more than it gains: use a thicker
#: shell, a smaller tolerance, or the collocation method
MAX_NODES = 400
#: degree added per rung of the refinement ladder at N <= 32 (kappa_s of the default cap
#: converges by ~1.5 decades per 4 degrees from N = 16 to 40: a rung is a clear step, not
#: noise); see :func:`refine_step` for larger degrees
REFINE_STEP = 4
#: decades of fold accuracy gained per rung at the degrees where tolerances live
#: (measured on the default cap, T = 5.2: errors 5e-7, 1.5e-8, 9e-11, 6.5e-11, 4.6e-12,
#: 2.7e-13 at N = 20 ... 40)
DECADES_PER_RUNG = 1.5


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


def _barycentric(N: int, tau: np.ndarray) -> np.ndarray:
    """Values at :func:`chebyshev_points` (N) -> the interpolant's values at the points tau:
    the (len(tau), N + 1) matrix of barycentric interpolation (second-kind weights (-1)^k,
    halved at both ends; Berrut & Trefethen, SIAM Rev. 46, 2004), with exact rows where a
    point of tau coincides with a node. Read-only (its callers cache it)."""
    t = chebyshev_points(N)
    w = (-1.0) ** np.arange(N + 1)
    w[0] *= 0.5
    w[-1] *= 0.5
    diff = tau[:, None] - t[None, :]
    same = np.isclose(diff, 0.0, rtol=0.0, atol=4 * np.finfo(float).eps)
    C = w[None, :] / np.where(same, 1.0, diff)
    C /= C.sum(axis=1, keepdims=True)
    hit = same.any(axis=1)
    C[hit] = same[hit].astype(float)
    C.flags.writeable = False
    return C


@lru_cache(maxsize=None)
def resampling_matrix(N: int) -> np.ndarray:
    """Barycentric interpolation from the N + 1 second-kind points to the N first-kind points
    (1 - cos(pi (j + 1/2) / N)) / 2 (no node coincides)."""
    return _barycentric(N, (1.0 - np.cos(np.pi * (np.arange(N) + 0.5) / N)) / 2.0)


@lru_cache(maxsize=None)
def regridding_matrix(N: int, M: int) -> np.ndarray:
    """Values at :func:`chebyshev_points` (N) -> the interpolant's values at those of degree
    M (:func:`_barycentric`, exact rows where points coincide). The same polynomial as
    :func:`coefficients` and :func:`evaluate` give, as one product instead of a DCT and a
    Clenshaw recurrence per row (1.3 instead of 65 us for the six components at N = 24; a
    carry between rungs of the fold ladder takes two, the state and the inner roots)."""
    return _barycentric(N, chebyshev_points(M))


@lru_cache(maxsize=None)
def _resampled_derivative(N: int) -> np.ndarray:
    """d/dt resampled onto the first-kind points: the interior rows' operator (read-only)."""
    PD = resampling_matrix(N) @ differentiation_matrix(N)
    PD.flags.writeable = False
    return PD


def coefficients(values: np.ndarray) -> np.ndarray:
    """Chebyshev coefficients (along the last axis) of the interpolant through values at
    :func:`chebyshev_points` (a DCT-I; coefficient k multiplies T_k(1 - 2 t))."""
    from scipy.fft import dct

    N = values.shape[-1] - 1
    c = dct(values, type=1, axis=-1) / N
    c[..., 0] /= 2.0
    c[..., -1] /= 2.0
    return c


def evaluate(coef: np.ndarray, t) -> np.ndarray:
    """The interpolant with coefficients ``coef`` (..., N + 1) at t: shape (..., len(t))."""
    return np.polynomial.chebyshev.chebval(1.0 - 2.0 * np.asarray(t, dtype=float), coef.T)


def _interpolant(values: np.ndarray):
    """t -> the interpolants of values (P, k, N + 1) at :func:`chebyshev_points` of every
    piece, evaluated at t: (P, k, len(t))."""
    c = coefficients(values)
    return lambda t: np.stack([evaluate(ci, t) for ci in c])


def refine_step(N: int) -> int:
    """Degrees added per rung at degree N: ``REFINE_STEP`` per 32 degrees. The error falls
    like rho^-N with ln rho ~ sqrt(h) / Theta (the edge layer's width over the meridian's
    length), and the degree a cap needs grows like Theta / sqrt(h) too: a rung in
    proportion to N gains the same ~1.5 decades at every depth. With fixed rungs of 4 a deep
    cap (Theta = 0.95 pi, h = 0.01, N = 180) gained a factor ~0.6 per rung, and one change
    between rungs (3e-10) understated the error (1e-9)."""
    return REFINE_STEP * max(1, round(N / 32))


def default_nodes(scene) -> int:
    """Degree per piece for a scene: the bending layer at an edge has width ~ sqrt(h R_c), so
    the degree grows with the shallowness T = L / sqrt(h R_c) (:attr:`shellbvp.Scene.
    shallowness`; Theta / sqrt(h) for a cap of the unit sphere): 24 at T <= 4, +8 per 4/3
    of T."""
    T = scene.shallowness
    return int(8 * math.ceil(max(3.0, 0.75 * T)))


def _resolvable(scene) -> int:
    """:func:`default_nodes`, or ValueError if that is beyond ``MAX_NODES``."""
    N = default_nodes(scene)
    if N > MAX_NODES:
        raise ValueError(
            f"the scene needs Chebyshev degree {N} > {MAX_NODES}: its shallowness "
            f"T = L / sqrt(h R_c) = {scene.shallowness:.4g} is "
            f"beyond what this method resolves (T <= {MAX_NODES / 6:.0f}); raise h")
    return N


def bracketing_nodes(scene) -> int:
    """Degree at which a branch is followed only to bracket its folds: 16 below
    :func:`default_nodes` (at least 16); every fold is then re-located on the ladder from
    :func:`fold_nodes`, so the coarse branch costs no accuracy (on the 132 caps of the
    paper's Fig. 3 set, T = 2 ... 10, kappa_s so found agrees with Newton on the fold system
    to 1.1e-13 at tol 1e-10). On the default cap, 16 instead of 24 took 10-14 % off a
    kappa_s (a smaller dense LU on the eight evaluations that bracket)."""
    return max(16, _resolvable(scene) - 16)


def fold_nodes(scene, tol: float) -> int:
    """The first rung of the ladder that refines a fold to ``tol``: the degree whose fold
    error is expected below tol (from the convergence rate ``DECADES_PER_RUNG``), so that the
    next rung confirms it; the ladder goes on by itself where the expectation is wrong."""
    rungs = math.ceil((-math.log10(tol) - 6.0) / DECADES_PER_RUNG)
    N = default_nodes(scene)
    step = refine_step(N)
    return min(MAX_NODES, max(MIN_NODES * 2, N - 3 * step + step * rungs))


@dataclass(frozen=True)
class Chebyshev:
    """Chebyshev collocation of degree ``nodes`` per piece (default: :func:`default_nodes`
    of the scene, which resolves kappa_s of a cap to ~1e-8; the refinement ladder adds
    :func:`refine_step` degrees until a fold is converged to its tolerance)."""

    nodes: int | None = None
    name = "spectral"

    def __post_init__(self):
        if self.nodes is not None and not (isinstance(self.nodes, (int, np.integer))
                                           and MIN_NODES <= self.nodes <= MAX_NODES):
            raise ValueError(f"nodes must be an integer in [{MIN_NODES}, {MAX_NODES}] "
                             f"(Chebyshev degree per piece), got {self.nodes!r}")

    def discretise(self, bvp) -> "ChebyshevSystem":
        N = _resolvable(bvp.scene) if self.nodes is None else int(self.nodes)
        return ChebyshevSystem(bvp, N)


class ChebyshevSystem(NodalSystem):
    """R(U, p) = 0 on N + 1 Chebyshev points per piece (U as in :class:`NodalSystem`)."""

    def __init__(self, bvp, N: int):
        super().__init__(bvp, chebyshev_points(N))
        self.N = N
        self._PD = _resampled_derivative(N)
        self._Pm = resampling_matrix(N)
        self._scaled = {}

    def interior(self, Y, p, nod, into=None):
        n, N = self.n, self.N
        L = self.bvp.lengths
        out = []
        for i in range(self.P):
            res = Y[i] @ self._PD.T - L[i] * (nod.f[i] @ self._Pm.T)             # (n, N)
            # d res[c, j] / d Y[c', k] = delta_cc' PD[j, k] - L Pm[j, k] J[c, c', k], built
            # in its final (c, j, (c', k)) layout (no transposed copy), in place where the
            # Jacobian's block is given (a reshape that only splits axes is always a view):
            # one product whose inner axis runs over all n (N + 1) columns of a row, then PD
            # added on the diagonal blocks c = c' through one strided view of them (13 us
            # at N = 24, where the 4-d broadcast over (c, j, c', k) and six block additions
            # took 24 us)
            blk = None if into is None else into[i].reshape(n, N, n * (N + 1))
            blk = np.multiply(self._scaled_resampling(L[i]),
                              nod.J[i].reshape(n, 1, n * (N + 1)), out=blk)
            diagonal = np.einsum("cjck->cjk", blk.reshape(n, N, n, N + 1))   # a view
            diagonal += self._PD
            out.append((res.ravel(), into[i] if into is not None else
                        blk.reshape(n * N, n * (N + 1)),
                        (-L[i] * (nod.fp[i] @ self._Pm.T)).ravel()))
        return out

    def _scaled_resampling(self, length: float) -> np.ndarray:
        """-length * Pm repeated once per component along the columns, (N, n (N + 1)): the
        factor of column (c', k) in every row j of a piece's block (cached per length)."""
        found = self._scaled.get(length)
        if found is None:
            found = self._scaled[length] = np.tile(-length * self._Pm, (1, self.n))
        return found

    def parameter_derivatives(self, U, p, names=("length", "material", "h")) -> dict:
        """dR/dx and dm/dx at (U, p) for the scene's x = ``"length"`` (the meridian's length
        L: the second end moves, the pole offsets with it when they are the default;
        interfaces stay; Theta for a cap of the unit sphere), ``"h"`` and ``"material"``
        (lam, or nu of a Koiter shell), with the unknowns held at the same piece
        coordinates: {x: (dR (size,), dm)}. Exact: the BVP's derivatives come from JAX with
        the inner root differentiated implicitly. The interior residual
        Y D' - L_i f(s(t), Y) P' is linear in L_i f, whose derivative in L is
        L_i' f + L_i f_s s'(t) with s(t) = a_i + L_i t. ``names``: the x wanted (the length
        alone compiles ~5x faster: no derivative of the energy in its material and h)."""
        bvp, n, P = self.bvp, self.n, self.P
        Y = self.split(U)
        geometry_only = set(names) <= {"length"}
        f, df = bvp.sensitivities(self.s, Y, p, self._hint, geometry_only=geometry_only)
        dr, dm_length = bvp.boundary_sensitivities(Y[0, :, 0], Y[-1, :, -1], p,
                                                   geometry_only=geometry_only)
        da, db = self._end_motion()
        L = bvp.lengths
        t = self.t
        dLf = {"length": [(db[i] - da[i]) * f[i] + L[i] * df[i, ..., 0]
                          * (da[i] + (db[i] - da[i]) * t) for i in range(P)],
               "material": [L[i] * df[i, ..., 1] for i in range(P)],
               "h": [L[i] * df[i, ..., 2] for i in range(P)]}
        rb = {"length": dr[:, 0], "material": dr[:, 1], "h": dr[:, 2]}
        # the interface rows: the rings' jumps -(12/h^2) Q scale like 1/h^2 (the rings stay
        # at their s as the length changes)
        ring = bvp.ring_jumps(p) if bvp.scene.rings else np.zeros((P - 1, n))
        dJ = {"length": 0.0 * ring, "material": 0.0 * ring, "h": -2.0 / bvp.scene.h * ring}
        out = {}
        for x, parts in ((x, dLf[x]) for x in names):
            rows = [rb[x]]
            for i in range(P):
                rows.append(-(parts[i] @ self._Pm.T).ravel())
                if i < P - 1:
                    rows.append(dJ[x][i])
            out[x] = (np.concatenate(rows), dm_length if x == "length" else 0.0)
        return out

    def _end_motion(self):
        """(da, db) (P,): how each piece's ends move with the meridian's length (only the
        domain's ends do, as :attr:`shellbvp.bvp.ShellBVP.ends_per_length` says)."""
        da, db = np.zeros(self.P), np.zeros(self.P)
        da[0], db[-1] = self.bvp.ends_per_length
        return da, db

    def curvature_terms(self, U, p, w, v, dp) -> tuple:
        """The gradient in (U, p, L) of the second directional derivative
        d/de [w_R . R(U + e v, p + e dp) + w_m m(U + e v)] at e = 0, w = (w_R, w_m): with
        (v, dp) and w the right and left null vectors of the bordered matrix
        [[dR/dU, dR/dp], [dm/dU, 0]], it is minus the gradient of the fold test function
        dp/dm (:mod:`shellbvp.continuation.fold_curve`). Returns (dU (size,), dp, dL),
        exact: the BVP's second derivatives from JAX along the inner root (implicit), L the
        meridian's length moving the second end (and the default pole offsets) with the
        interfaces fixed, as in :meth:`parameter_derivatives`."""
        bvp, n, P, N = self.bvp, self.n, self.P, self.N
        Y, V = self.split(U), self.split(v)
        wR, w0 = np.asarray(w[:-1], dtype=float), float(w[-1])
        Wn, row = [], n
        for i in range(P):
            Wn.append(wR[row:row + n * N].reshape(n, N) @ self._Pm)   # weights at the nodes
            row += n * N + (n if i < P - 1 else 0)
        L = bvp.lengths
        # the pole rows enter as part of the end nodes' phi, scaled as the interior's -L f
        wb = np.stack([-wR[:3] / L[0], -wR[3:6] / L[-1]])
        dphi, dgy, dgp, dgs = bvp.fold_terms(self.s, Y, p, np.stack(Wn), wb, V, dp,
                                             self._hint)
        da, db = self._end_motion()
        gU = -L[:, None, None] * dgy
        g_p = -float(np.sum(L * dgp.sum(axis=1)))
        if bvp.scene.rings:                      # the interface rows' second p-derivative
            rows = [n + (i + 1) * n * N + i * n for i in range(P - 1)]
            g_p += dp * float(sum(wR[r:r + n] @ J for r, J in zip(rows, bvp.ring_jumps(p, 2))))
        g_L = -float(sum((db[i] - da[i]) * dphi[i, :, 0].sum()
                         + L[i] * np.sum((da[i] + (db[i] - da[i]) * self.t) * dgs[i])
                         for i in range(P)))
        mya, myb, mth = bvp.monitor_curvature(Y[0, :, 0], Y[-1, :, -1], V[0, :, 0],
                                              V[-1, :, -1])
        gU[0, :, 0] += w0 * mya
        gU[-1, :, -1] += w0 * myb
        return gU.ravel(), g_p, g_L + w0 * float(mth)

    def dense(self, U, p=None):
        at = _interpolant(self.split(U))
        return lambda t: at(np.atleast_1d(t)).reshape(self.P * self.n, -1)

    def transfer(self, U, p, other) -> np.ndarray:
        """U carried onto ``other``; on another degree of the same BVP the inner roots of
        the last evaluation go along where it was at (nearly) U, so that the first
        evaluation there starts the inner Newton next to its roots, as the next one on this
        degree would (fewer inner steps; the result is the same from any start). Onto
        another Chebyshev degree by :func:`regridding_matrix`."""
        if not isinstance(other, ChebyshevSystem):
            return super().transfer(U, p, other)
        regrid = regridding_matrix(self.N, other.N).T
        V = (self.split(U) @ regrid).ravel()
        if self._shell and other.bvp is self.bvp and other is not self \
                and self._hint is not None:
            other._hint = self.bvp.carried_hint(self._hint, self.split(U), other.split(V), p,
                                                lambda a: a @ regrid)
        return V

    def on(self, bvp) -> "ChebyshevSystem":
        """The same discretisation of another BVP with the same pieces (e.g. the scene at
        a nearby parameter): unknowns at the same piece coordinates."""
        return ChebyshevSystem(bvp, self.N)

    def at_tolerance(self, tol: float) -> "ChebyshevSystem":
        """The first rung of the fold ladder for ``tol`` (:func:`fold_nodes`), finer or
        coarser than this system (this one if its BVP is not a shell problem)."""
        if not self._shell:
            return self
        return ChebyshevSystem(self.bvp, fold_nodes(self.bvp.scene, tol))

    def for_tolerance(self, tol: float) -> "ChebyshevSystem":
        """:meth:`at_tolerance`, or this system if it is finer."""
        first = self.at_tolerance(tol)
        return self if first.N <= self.N else first

    def refined(self) -> "ChebyshevSystem":
        N = self.N + refine_step(self.N)
        if N > MAX_NODES:
            raise ValueError(f"cannot refine beyond {MAX_NODES} Chebyshev nodes")
        return ChebyshevSystem(self.bvp, N)

    def describe(self) -> dict:
        return {"method": "spectral", "nodes": self.N}
