"""Chebyshev spectral collocation on elements: the fast method (default).

The meridian is cut into elements (:mod:`shellbvp.mesh`: one per piece of the scene where
its bending layers are wide, else graded geometrically into every layer, so that the cost
does not grow with R/t or a shell's length), and every element carries the unknowns at
the N + 1 Chebyshev points of the second kind, t_k = (1 - cos(pi k / N)) / 2. The unknowns
are the displacement from the reference state (:class:`shellbvp.methods.base.NodalSystem`).
The ODE dy/dt = (b_i - a_i) f(s, y) is imposed by rectangular collocation (Driscoll & Hale,
IMA J. Numer. Anal. 36, 2016): the residual D u - (b - a) (f - y0') is resampled by
barycentric interpolation onto the N Chebyshev points of the first kind, which leaves
exactly one row per component and element for the boundary and interface conditions. For
an analytic solution the error falls geometrically with N; the resolution is checked by the
refinement ladder (a fold's change with the next degrees). The Jacobian is exact, assembled
from the per-node blocks df/dy of the BVP: dense for a few elements, block-sparse beyond.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .base import NodalSystem, ShellProblem, implements

__all__ = ["Chebyshev", "ChebyshevSystem", "chebyshev_points", "differentiation_matrix",
           "regridding_matrix", "coefficients", "default_nodes", "bracketing_nodes",
           "fold_nodes", "MIN_NODES", "MAX_NODES", "REFINE_STEP", "refine_step"]

#: the smallest degree that resolves a pole region and an edge layer at all
MIN_NODES = 8
#: the largest degree per element (a single-domain scene needs at most
#: ``default_nodes`` at :data:`shellbvp.mesh.SINGLE_T`; beyond, the dense LU of size
#: 6 (N + 1) per element costs more than more elements would)
MAX_NODES = 400
#: degree added per rung of the refinement ladder at N <= 32 (kappa_s of the default cap
#: converges by ~1.5 decades per 4 degrees from N = 16 to 40: a rung is a clear step, not
#: noise); see :func:`refine_step` for larger degrees
REFINE_STEP = 4
#: decades of fold accuracy gained per rung at the degrees where tolerances live
#: (measured on the default cap, T = 5.2: errors 5e-7, 1.5e-8, 9e-11, 6.5e-11, 4.6e-12,
#: 2.7e-13 at N = 20 ... 40)
DECADES_PER_RUNG = 1.5
#: degree per element of a graded mesh (:mod:`shellbvp.mesh`): an element [x, 3 x] from a
#: layer, or from a pole's s log s, holds functions analytic in a Bernstein ellipse of
#: parameter 2 + sqrt(3), resolved by degree 16 to ~1e-9 of their size (the hemisphere's
#: pole deflection under a point force: 5e-6, 4e-7, 1.3e-8, 3e-10 at degree 8, 10, 12, 16,
#: R/t = 1e4)
ELEMENT_DEGREE = 16
#: unknowns above which the Jacobian is assembled block-sparse (a banded LU), not dense
DENSE_MAX = 1200


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
    """Degree per piece of a single-domain scene: the bending layer at an edge has width
    ~ sqrt(h R_c), so the degree grows with the shallowness T = L / sqrt(h R_c)
    (:attr:`shellbvp.Scene.shallowness`; Theta / sqrt(h) for a cap of the unit sphere): 24
    at T <= 4, +8 per 4/3 of T. A graded mesh's elements have ``ELEMENT_DEGREE``
    (:func:`default_degree`)."""
    T = scene.shallowness
    return int(8 * math.ceil(max(3.0, 0.75 * T)))


def default_degree(mesh, scene) -> int:
    """The degree per element of ``mesh`` (:func:`shellbvp.mesh.mesh_of` of ``scene``):
    :func:`default_nodes` where the mesh is one element per piece, ``ELEMENT_DEGREE`` where
    it is graded."""
    return ELEMENT_DEGREE if mesh.graded else min(MAX_NODES, default_nodes(scene))


def bracketing_nodes(scene) -> int:
    """Degree at which a branch is followed only to bracket its folds: 16 below
    :func:`default_nodes` (at least 16; 8 below ``ELEMENT_DEGREE`` on a graded mesh);
    every fold is then re-located on the ladder from :func:`fold_nodes`, so the coarse
    branch costs no accuracy (on the 132 caps of the paper's Fig. 3 set, T = 2 ... 10,
    kappa_s so found agrees with Newton on the fold system to 1.1e-13 at tol 1e-10). On
    the default cap, 16 instead of 24 took 10-14 % off a kappa_s (a smaller dense LU on the
    eight evaluations that bracket)."""
    from ..mesh import mesh_of

    mesh = mesh_of(scene)
    if mesh.graded:
        return ELEMENT_DEGREE - 8
    return max(16, default_degree(mesh, scene) - 16)


def fold_nodes(scene, tol: float, N: int | None = None) -> int:
    """The first rung of the ladder that refines a fold to ``tol``: the degree whose fold
    error is expected below tol (from the convergence rate ``DECADES_PER_RUNG``), so that the
    next rung confirms it; the ladder goes on by itself where the expectation is wrong.
    ``N``: the default degree of the scene's mesh (:func:`default_degree`)."""
    from ..mesh import mesh_of

    rungs = math.ceil((-math.log10(tol) - 6.0) / DECADES_PER_RUNG)
    if N is None:
        N = default_degree(mesh_of(scene), scene)
    step = refine_step(N)
    return min(MAX_NODES, max(MIN_NODES * 2, N - 3 * step + step * rungs))


@dataclass(frozen=True)
class Chebyshev:
    """Chebyshev collocation of degree ``nodes`` per element (default:
    :func:`default_degree` of the scene's mesh, :func:`shellbvp.mesh.mesh_of`: one element
    per piece of degree :func:`default_nodes` where the scene's layers are wide, graded
    elements of degree ``ELEMENT_DEGREE`` where they are thin; the refinement ladder adds
    :func:`refine_step` degrees until a fold is converged to its tolerance)."""

    nodes: int | None = None
    name = "spectral"

    def __post_init__(self):
        if self.nodes is not None and not (isinstance(self.nodes, (int, np.integer))
                                           and MIN_NODES <= self.nodes <= MAX_NODES):
            raise ValueError(f"nodes must be an integer in [{MIN_NODES}, {MAX_NODES}] "
                             f"(Chebyshev degree per element), got {self.nodes!r}")

    def discretise(self, bvp) -> "ChebyshevSystem":
        from ..mesh import mesh_of

        if not implements(bvp, ShellProblem):      # a hand-written BVP: its own pieces
            return ChebyshevSystem(bvp, MIN_NODES * 3 if self.nodes is None else self.nodes)
        mesh = mesh_of(bvp.scene)
        N = default_degree(mesh, bvp.scene) if self.nodes is None else int(self.nodes)
        return ChebyshevSystem(bvp if mesh == bvp.mesh else bvp.on_mesh(mesh), N)


class ChebyshevSystem(NodalSystem):
    """R(U, p) = 0 on N + 1 Chebyshev points per element (U as in :class:`NodalSystem`: the
    displacement from the reference; the elements are the BVP's pieces, :mod:`shellbvp.mesh`).
    """

    def __init__(self, bvp, N: int):
        super().__init__(bvp, chebyshev_points(N))
        self.N = N
        self._PD = _resampled_derivative(N)
        self._Pm = resampling_matrix(N)
        self._scaled = {}
        #: many elements: a block-sparse Jacobian (one dense block per element, the
        #: interfaces between them), factored by a sparse LU
        self.dense_jacobian = self.size <= DENSE_MAX
        #: the reference's rate less the BVP's right-hand side is resampled once per
        #: evaluation: Y0' P' per element (P, n, N)
        self._rate_resampled = self.Y0_rate @ self._Pm.T

    def interior(self, Y, p, nod, into=None):
        n, N = self.n, self.N
        L = self.bvp.lengths
        out = []
        for i in range(self.P):
            res = Y[i] @ self._PD.T - L[i] * (nod.f[i] @ self._Pm.T
                                              - self._rate_resampled[i])    # (n, N)
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

    def _reference_motion(self):
        """dY0/dL at the nodes (P, n, N + 1), the unknowns held: the reference state moves
        with the nodes where the meridian's length moves them (:meth:`_end_motion`)."""
        da, db = self._end_motion()
        sigma = da[:, None] + (db - da)[:, None] * self.t[None, :]          # ds/dL (P, N + 1)
        return self.Y0_rate * sigma[:, None, :], sigma

    def parameter_derivatives(self, U, p, names=("length", "material", "h")) -> dict:
        """dR/dx and dm/dx at (U, p) for the scene's x = ``"length"`` (the meridian's length
        L: the second end moves, the pole offsets with it when they are the default;
        interfaces and the cuts of a mesh stay; Theta for a cap of the unit sphere), ``"h"``
        and ``"material"`` (lam, or nu of a Koiter shell), with the unknowns (the
        displacement) held at the same element coordinates: {x: (dR (size,), dm)}. Exact:
        the BVP's derivatives come from JAX with the inner root differentiated implicitly.
        The interior residual U D' - L_i (f(s(t), Y0(s(t)) + U) - Y0'(s(t))) P' has, with
        s(t) = a_i + L_i t and sigma = ds/dL, the L-derivative
        -[(L_i' (f - Y0') + L_i sigma (f_s + f_y Y0' - Y0'')] P'. ``names``: the x wanted
        (the length alone compiles ~5x faster: no derivative of the energy in its material
        and h)."""
        bvp, n, P = self.bvp, self.n, self.P
        Y = self.states(U)
        geometry_only = set(names) <= {"length"}
        f, df = bvp.sensitivities(self.s, Y, p, self._hint, geometry_only=geometry_only)
        dr, dm_length = bvp.boundary_sensitivities(Y[0, :, 0], Y[-1, :, -1], p,
                                                   geometry_only=geometry_only)
        da, db = self._end_motion()
        L = bvp.lengths
        dLf = {"material": [L[i] * df[i, ..., 1] for i in range(P)],
               "h": [L[i] * df[i, ..., 2] for i in range(P)]}
        if "length" in names:
            dY0, sigma = self._reference_motion()
            nodal, (_, Ja, Jb, _), (_, ga, gb) = self._collocate(Y, p)
            fy_rate = np.einsum("icdk,idk->ick", nodal.J, self.Y0_rate)
            rate2 = np.stack([self.bvp.reference_rate(si, order=2) for si in self.s]) \
                if self.displaced else np.zeros_like(self.Y0)
            dLf["length"] = [(db[i] - da[i]) * (f[i] - self.Y0_rate[i])
                             + L[i] * sigma[i] * (df[i, ..., 0] + fy_rate[i] - rate2[i])
                             for i in range(P)]
            dya, dyb = dY0[0, :, 0], dY0[-1, :, -1]
            dr_length = dr[:, 0] + Ja @ dya + Jb @ dyb
            dm_length = dm_length + float(ga @ dya + gb @ dyb)
        rb = {"length": dr_length if "length" in names else None, "material": dr[:, 1],
              "h": dr[:, 2]}
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
        interfaces fixed, as in :meth:`parameter_derivatives` (the displacement held: the
        state moves with the reference, which adds dU . dY0/dL)."""
        bvp, n, P, N = self.bvp, self.n, self.P, self.N
        Y, V = self.states(U), self.split(v)
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
        g_L += w0 * float(mth) + float(np.sum(gU * self._reference_motion()[0]))
        return gU.ravel(), g_p, g_L

    def _reference_at(self, t):
        """The reference state at element coordinates t, stacked (P n, len(t)) (the last
        point of an element from its own side of an interface)."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        if not self.displaced:
            return np.zeros((self.P * self.n, t.size))
        out = []
        for i in range(self.P):
            s = self.bvp.s_of(i, t)
            if i < self.P - 1:
                s = np.where(t >= 1.0, np.nextafter(s, -np.inf), s)
            out.append(self.bvp.reference(s))
        return np.concatenate(out)

    def dense(self, U, p=None):
        """t -> the state at element coordinates t, stacked (6 P, len(t)): the reference
        (exact) plus the interpolant of the displacement."""
        at = _interpolant(self.split(U))
        return lambda t: at(np.atleast_1d(t)).reshape(self.P * self.n, -1) \
            + self._reference_at(t)

    def transfer(self, U, p, other) -> np.ndarray:
        """U carried onto ``other``; on another degree of the same BVP the inner roots of
        the last evaluation go along where it was at (nearly) U, so that the first
        evaluation there starts the inner Newton next to its roots, as the next one on this
        degree would (fewer inner steps; the result is the same from any start). Onto
        another Chebyshev degree on the same elements by :func:`regridding_matrix` of the
        displacement, at the same element coordinates (a displacement carried to a scene
        of another length, as :meth:`on` lays a discretisation on it); onto a mesh of
        other elements through the meridian's profile."""
        if not isinstance(other, ChebyshevSystem):
            return super().transfer(U, p, other)
        if other.P != self.P:       # other elements: through the meridian's profile
            return other.from_profile(self.bvp.profile(self.dense(U, p)))
        regrid = regridding_matrix(self.N, other.N).T
        V = (self.split(U) @ regrid).ravel()
        if self._shell and other.bvp is self.bvp and other is not self \
                and self._hint is not None:
            other._hint = self.bvp.carried_hint(self._hint, self.states(U), other.states(V),
                                                p, lambda a: a @ regrid)
        return V

    def on(self, bvp) -> "ChebyshevSystem":
        """The same discretisation of another BVP of a scene with the same pieces (e.g. the
        scene at a nearby parameter or length): unknowns at the same element coordinates,
        the cuts of a graded mesh where they were (the last element's end at the new
        length)."""
        from ..mesh import Mesh, single_mesh

        mesh = self.bvp.mesh
        if not mesh.graded:
            mesh = single_mesh(bvp.scene)
        else:
            ends = list(mesh.ends[:-1]) + [bvp.scene.length]
            mesh = Mesh(tuple(ends), mesh.pieces)
        return ChebyshevSystem(bvp if bvp.mesh == mesh else bvp.on_mesh(mesh), self.N)

    def at_tolerance(self, tol: float) -> "ChebyshevSystem":
        """The first rung of the fold ladder for ``tol`` (:func:`fold_nodes`), finer or
        coarser than this system, on the same elements (this one if its BVP is not a shell
        problem)."""
        if not self._shell:
            return self
        scene = self.bvp.scene
        return ChebyshevSystem(self.bvp, fold_nodes(scene, tol,
                                                    default_degree(self.bvp.mesh, scene)))

    def for_tolerance(self, tol: float) -> "ChebyshevSystem":
        """:meth:`at_tolerance`, or this system if it is finer."""
        first = self.at_tolerance(tol)
        return self if first.N <= self.N else first

    @property
    def rung_ratio(self) -> float:
        """The error's factor per rung (:class:`~.base.Discretisation`): 0 (exponential
        convergence in the degree), but algebraic at a point-loaded pole
        (:func:`shellbvp.mesh.loaded_pole_ratio`)."""
        if not implements(self.bvp, ShellProblem):
            return 0.0
        from ..mesh import loaded_pole_ratio

        return loaded_pole_ratio(self.bvp.scene, self.N, refine_step(self.N))

    def refined(self) -> "ChebyshevSystem":
        N = self.N + refine_step(self.N)
        if N > MAX_NODES:
            raise ValueError(f"cannot refine beyond {MAX_NODES} Chebyshev nodes")
        return ChebyshevSystem(self.bvp, N)

    def describe(self) -> dict:
        return {"method": "spectral", "nodes": self.N, "elements": self.P}
