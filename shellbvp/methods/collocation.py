"""Collocation with scipy's ``solve_bvp``: the method a scipy user knows, as a check.

Two uses of the same scheme (the 4th-order Lobatto IIIA collocation of ``solve_bvp``, i.e.
cubic C1 splines with the ODE imposed at the nodes and at the interval midpoints):

* :meth:`Collocation.solve` hands the stacked multi-point problem (pieces mapped to
  t in [0, 1] and stacked, interfaces as ordinary boundary conditions) to
  ``scipy.integrate.solve_bvp`` with analytic Jacobians; solve_bvp adapts its own mesh to
  ``tol`` and the result is returned on that mesh;
* for continuation and folds the same discrete equations on a fixed mesh form a system
  R(U, p) = 0 with an exact sparse Jacobian (:class:`CollocationSystem`), continued by the
  common machinery; its refinement ladder halves every interval (4th order: the change of
  a fold under halving bounds the error of the coarser value).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ConvergenceError
from .base import NodalSystem, ShellProblem, implements, inside

__all__ = ["Collocation", "CollocationSystem"]

#: nodes added at the ends by the clustered initial mesh, relative to a uniform one:
#: the pole region and the edge boundary layer need them most
_CLUSTER = 0.5
#: solve_bvp's tolerance where ``Collocation.tol`` is not given
SOLVE_TOL = 1e-8


def clustered_mesh(nodes: int) -> np.ndarray:
    """``nodes`` points on [0, 1], half uniform and half Chebyshev-clustered at both ends."""
    u = np.linspace(0.0, 1.0, nodes)
    return (1 - _CLUSTER) * u + _CLUSTER * (1 - np.cos(np.pi * u)) / 2


@dataclass(frozen=True)
class Collocation:
    """solve_bvp's collocation.

    Attributes:
        tol: solve_bvp's relative residual tolerance, for one equilibrium
            (:func:`shellbvp.solve`; None: ``SOLVE_TOL``). Continuation and folds solve the
            same equations on a fixed mesh and refine folds to their own tolerance
            (``ContinuationOptions.fold_tol``, a scene's ``tol``): there a ``tol`` given here
            would do nothing, and :func:`shellbvp.follow` refuses it.
        nodes: the size of the initial (clustered) mesh, which is also the continuation mesh.
        max_nodes: the largest mesh: it bounds solve_bvp's adaptive mesh and the fold
            ladder's halvings (a fold that needs more raises ConvergenceError).
    """

    tol: float | None = None
    nodes: int = 81
    max_nodes: int = 20000
    name = "collocation"

    def __post_init__(self):
        if self.tol is not None and not (isinstance(self.tol, float) and 1e-14 < self.tol < 1):
            raise ValueError(f"tol must be None or a float in (1e-14, 1), got {self.tol!r}")
        if not (isinstance(self.nodes, (int, np.integer)) and 8 <= self.nodes <= self.max_nodes):
            raise ValueError(f"nodes must be an integer in [8, max_nodes], got {self.nodes!r}")

    def discretise(self, bvp) -> "CollocationSystem":
        return CollocationSystem(_on_elements(bvp), clustered_mesh(self.nodes),
                                 self.max_nodes)

    def solve(self, bvp, p, profile):
        """solve_bvp on the stacked problem from ``profile`` (s -> (6, n)); returns
        (system on solve_bvp's final mesh, U, stats). Raises ConvergenceError on failure."""
        from scipy.integrate import solve_bvp

        bvp = _on_elements(bvp)
        n, P, L = bvp.n, bvp.P, bvp.lengths
        memo = {}

        def nodal(t, Ys):
            key = (t.tobytes(), Ys.tobytes())
            if key not in memo:
                memo.clear()
                s = np.stack([bvp.s_of(i, t) for i in range(P)])
                memo[key] = bvp.rhs(s, Ys.reshape(P, n, t.size), p)
            return memo[key]

        def fun(t, Ys):
            return (L[:, None, None] * nodal(t, Ys).f).reshape(n * P, t.size)

        def fun_jac(t, Ys):
            J = np.zeros((n * P, n * P, t.size))
            nod = nodal(t, Ys)
            for i in range(P):
                J[n * i:n * i + n, n * i:n * i + n] = L[i] * nod.J[i]
            return J

        jumps = bvp.jumps_at(p)[0] if P > 1 else None      # (one piece: no interface)

        def bc(ya, yb):
            return np.concatenate([bvp.boundary(ya[:n], yb[-n:], p)[0]]
                                  + [yb[n * i:n * i + n] + jumps[i]
                                     - ya[n * i + n:n * i + 2 * n] for i in range(P - 1)])

        def bc_jac(ya, yb):
            _, Ja, Jb, _ = bvp.boundary(ya[:n], yb[-n:], p)
            Ba, Bb = np.zeros((n * P, n * P)), np.zeros((n * P, n * P))
            Ba[:n, :n], Bb[:n, -n:] = Ja, Jb
            for i in range(P - 1):
                r = n + n * i
                Bb[r:r + n, n * i:n * i + n] = np.eye(n)
                Ba[r:r + n, n * i + n:n * i + 2 * n] = -np.eye(n)
            return Ba, Bb

        t0 = clustered_mesh(self.nodes)
        Y0 = np.concatenate([np.asarray(profile(inside(bvp.s_of(i, t0), i, P)), dtype=float)
                             for i in range(P)])
        try:
            tol = SOLVE_TOL if self.tol is None else self.tol
            res = solve_bvp(fun, bc, t0, Y0, fun_jac=fun_jac, bc_jac=bc_jac, tol=tol,
                            bc_tol=tol, max_nodes=self.max_nodes)
        except ConvergenceError as exc:
            raise ConvergenceError(f"solve_bvp at {bvp.scene.quote(p)}: {exc}") \
                from None
        stats = dict(method="collocation", status=int(res.status), nodes=int(res.x.size),
                     niter=int(res.niter), max_rms_residual=float(np.max(res.rms_residuals)))
        if not res.success:
            raise ConvergenceError(f"solve_bvp did not converge at {bvp.scene.quote(p)}: "
                                   f"{res.message} ({stats}); try a closer guess")
        system = CollocationSystem(bvp, res.x, self.max_nodes)
        return system, res.y.ravel(), stats


def _on_elements(bvp):
    """A shell's BVP on the elements of its mesh (:func:`shellbvp.mesh.mesh_of`: graded into
    the layers of a thin shell, each element then meshed as a piece is): the same mesh of
    ``nodes`` points in every element resolves a layer at any thinness."""
    if not implements(bvp, ShellProblem):
        return bvp
    from ..mesh import mesh_of

    mesh = mesh_of(bvp.scene)
    return bvp if mesh == bvp.mesh else bvp.on_mesh(mesh)


class CollocationSystem(NodalSystem):
    """solve_bvp's Lobatto IIIA equations on a fixed mesh t (same in every piece):
    R_j = y_{j+1} - y_j - h_j/6 (F_j + 4 F(y_mid) + F_{j+1}),
    y_mid = (y_j + y_{j+1})/2 - h_j/8 (F_{j+1} - F_j), with F = (b - a) f."""

    dense_jacobian = False
    #: the unknowns are the state itself (its equations difference neighbouring nodes)
    displaced = False
    #: a rung halves every interval of a 4th-order scheme
    rung_ratio = 1.0 / 16.0

    def __init__(self, bvp, t, max_nodes: int = 20000):
        super().__init__(bvp, t)
        self.max_nodes = max_nodes
        self.hstep = np.diff(self.t)
        self.s_mid = np.stack([bvp.s_of(i, self.t[:-1] + self.hstep / 2)
                               for i in range(self.P)])
        self._mid_hint = None
        # sparsity pattern of a piece's block, fixed by the mesh: rows (component a of
        # interval j at a M + j) and columns (component b of node k at b (M + 1) + k, the
        # layout of NodalSystem) for the blocks dR_j/dy_j and dR_j/dy_{j+1}
        n, M = self.n, self.M
        j, a, b = np.meshgrid(np.arange(M), np.arange(n), np.arange(n), indexing="ij")
        self._rows = np.concatenate([(a * M + j).ravel()] * 2)
        self._cols = np.concatenate([(b * (M + 1) + j).ravel(), (b * (M + 1) + j + 1).ravel()])

    def interior(self, Y, p, nod, into=None):     # into: never given (sparse Jacobian)
        import scipy.sparse as sps

        n, M, L = self.n, self.M, self.bvp.lengths
        h = self.hstep
        F = L[:, None, None] * nod.f                                   # (P, n, M + 1)
        Fp = L[:, None, None] * nod.fp
        JF = L[:, None, None, None] * nod.J                            # (P, n, n, M + 1)
        Ym = (Y[:, :, :-1] + Y[:, :, 1:]) / 2 - h / 8 * (F[:, :, 1:] - F[:, :, :-1])
        mid = self.bvp.rhs(self.s_mid, Ym, p, self._mid_hint)
        self._mid_hint = mid.hint
        Fm = L[:, None, None] * mid.f
        JFm = L[:, None, None, None] * mid.J
        eye = np.eye(n)
        out = []
        for i in range(self.P):
            Jn = np.moveaxis(JF[i], -1, 0)                              # (M + 1, n, n)
            Jm = np.moveaxis(JFm[i], -1, 0)                             # (M, n, n)
            hh = h[:, None, None]
            R = Y[i, :, 1:] - Y[i, :, :-1] - h / 6 * (F[i, :, :-1] + 4 * Fm[i] + F[i, :, 1:])
            A = -eye - hh / 6 * (Jn[:-1] + 4 * Jm @ (eye / 2 + hh / 8 * Jn[:-1]))
            B = eye - hh / 6 * (Jn[1:] + 4 * Jm @ (eye / 2 - hh / 8 * Jn[1:]))
            dym = -h / 8 * (Fp[i, :, 1:] - Fp[i, :, :-1])              # d y_mid / dp (n, M)
            Fpm = L[i] * mid.fp[i] + np.einsum("jab,bj->aj", Jm, dym)
            Rp = -h / 6 * (Fp[i, :, :-1] + 4 * Fpm + Fp[i, :, 1:])
            vals = np.concatenate([A.ravel(), B.ravel()])
            Ji = sps.coo_matrix((vals, (self._rows, self._cols)), shape=(n * M, n * (M + 1)))
            out.append((R.ravel(), Ji, Rp.ravel()))
        return out

    def dense(self, U, p):
        """Stacked cubic Hermite interpolant (solve_bvp's own interpolant) in t."""
        from scipy.interpolate import CubicHermiteSpline

        Y = self.states(U)
        F = self.bvp.lengths[:, None, None] * self.bvp.rhs(self.s, Y, p).f
        splines = [CubicHermiteSpline(self.t, Y[i].T, F[i].T, axis=0) for i in range(self.P)]
        return lambda t: np.concatenate([splines[i](np.atleast_1d(t)).T
                                         for i in range(self.P)])

    def refined(self) -> "CollocationSystem":
        t = np.sort(np.concatenate([self.t, self.t[:-1] + self.hstep / 2]))
        if t.size > self.max_nodes:
            raise ValueError(f"cannot refine beyond max_nodes = {self.max_nodes} "
                             f"(the next mesh has {t.size} nodes)")
        return CollocationSystem(self.bvp, t, self.max_nodes)

    def for_tolerance(self, tol: float) -> "CollocationSystem":
        """This mesh: the ladder halves it from here until a fold changes by at most tol."""
        return self

    def describe(self) -> dict:
        return {"method": "collocation", "nodes": int(self.t.size)}
