"""The protocol shared by every discretisation, and the nodal layout two of them share.

A *method* (a small frozen dataclass with named options, e.g. ``Chebyshev(nodes=32)``)
turns a :class:`shellbvp.bvp.ShellBVP` into a *discrete system* R(U, p) = 0 with exact
Jacobians, which is all that Newton, continuation and fold location need
(:mod:`shellbvp.continuation`). A discrete system also knows how to refine itself (the next
rung of the ladder that gives every fold its error estimate) and how to carry a solution to
another system of the same method.
"""

from __future__ import annotations

import math
from typing import Callable, Protocol

import numpy as np
import scipy.sparse as sps

__all__ = ["DiscreteSystem", "Method", "NodalSystem"]


class DiscreteSystem(Protocol):
    """R(U, p) = 0: ``size`` unknowns U, one scalar parameter p."""

    size: int
    bvp: object

    def evaluate(self, U, p):
        """(R (size,), dR/dU (size, size), dense or scipy.sparse, dR/dp (size,))."""

    def monitor(self, U):
        """(m, dm/dU): the BVP's observable (w / H) and its gradient."""

    def from_profile(self, profile: Callable) -> np.ndarray:
        """U from a callable s -> (6, n) of the BVP's unknowns."""

    def dense(self, U, p) -> Callable:
        """t -> stacked (6 P, n) interpolant of the solution in the piece coordinate."""

    def refined(self) -> "DiscreteSystem":
        """The next, finer system of the same method (for error estimates)."""

    def transfer(self, U, p, other: "DiscreteSystem") -> np.ndarray:
        """U carried onto ``other`` (same method and BVP, another resolution)."""

    def nodes(self, U, p):
        """(t, stacked (6 P, len(t)) values): the solution at the method's own points."""

    def describe(self) -> dict:
        """The resolution, for statistics (e.g. ``{"nodes": 32}``)."""


class Method(Protocol):
    """A discretisation with named options."""

    name: str

    def discretise(self, bvp) -> DiscreteSystem:
        """The discrete system of ``bvp`` at this method's resolution."""


class NodalSystem:
    """Unknowns at the same nodes t_0 = 0 < ... < t_M = 1 of every piece: U = Y (P, n, M + 1)
    flattened (piece, component, node). Rows: the n boundary conditions of the BVP, the
    interior equations of each piece (n M rows, from the subclass), and continuity of all
    n components at each interface. Subclasses implement :meth:`interior`.
    """

    def __init__(self, bvp, t):
        self.bvp = bvp
        self.n = n = bvp.n
        self.t = np.asarray(t, dtype=float)
        self.M = self.t.size - 1
        self.P = bvp.P
        self.s = np.stack([bvp.s_of(i, self.t) for i in range(self.P)])   # (P, M + 1)
        self.size = n * self.P * (self.M + 1)
        self.evaluations = 0
        self._hint = None       # warm start of the BVP's inner solve (cost only)
        self._monitor = None    # (U, monitor at U) of the last evaluation

    @property
    def jacobian_error(self) -> float:
        """The relative error of the Jacobian dR/dU: the BVP's ``jacobian_error`` (that of
        its derivatives, which the discretisation differentiates exactly), inf where the
        BVP does not state it."""
        return getattr(self.bvp, "jacobian_error", math.inf)

    # --- unknowns ----------------------------------------------------------------------------
    def split(self, U) -> np.ndarray:
        return np.asarray(U, dtype=float).reshape(self.P, self.n, self.M + 1)

    def from_profile(self, profile) -> np.ndarray:
        return np.stack([np.asarray(profile(self.s[i]), dtype=float)
                         for i in range(self.P)]).ravel()

    def nodes(self, U, p):
        """The nodes t (M + 1,) and the stacked values (n P, M + 1) there."""
        return self.t, self.split(U).reshape(self.n * self.P, self.M + 1)

    def transfer(self, U, p, other) -> np.ndarray:
        d = self.dense(U, p)
        return d(other.t).ravel()

    def col(self, i, c):
        return (i * self.n + c) * (self.M + 1)

    def inner_roots(self, U, p) -> np.ndarray:
        """The inner roots (lam1, k1) at the nodes (P, M + 1, 2), the BVP's inner solve
        warm-started from this system's last evaluation (as during its solves): starts for
        evaluating the state elsewhere (:meth:`shellbvp.bvp.ShellBVP.state`). By the
        evaluation's own compiled call (:meth:`_collocate`), not a second program."""
        nodal, _, _ = self._collocate(self.split(U), p)
        return np.asarray(nodal.hint.q).reshape(self.P, self.M + 1, 2)

    # --- the system --------------------------------------------------------------------------
    def interior(self, Y, p, nodal):
        """Per piece: (R_i (n M,), dR_i/dY_i (n M, n (M + 1)), dense or sparse, dR_i/dp),
        given ``nodal``, the BVP's right-hand side at the nodes (:class:`shellbvp.bvp.Nodal`)."""
        raise NotImplementedError

    def _collocate(self, Y, p):
        """The BVP's nodal rhs, boundary conditions and monitor at Y (one compiled call when
        the BVP offers it), with the inner Newton warm-started from the last evaluation."""
        bvp = self.bvp
        if hasattr(bvp, "collocate"):
            out = bvp.collocate(self.s, Y, p, self._hint)
            nodal, bc, mon = out
        else:
            nodal = bvp.rhs(self.s, Y, p, self._hint)
            bc = bvp.boundary(Y[0, :, 0], Y[-1, :, -1], p)
            mon = bvp.monitor(Y[0, :, 0], Y[-1, :, -1])
        # a warm start changes cost only: the inner Newton converges to round-off from any
        # start, and the derivatives are taken at its roots
        self._hint = nodal.hint
        return nodal, bc, mon

    #: assemble dR/dU as a dense array (small systems) or scipy.sparse CSC (large ones)
    dense_jacobian = True

    def _columns(self, i, node):
        """The columns of all n components of piece i at ``node``: a strided slice."""
        start = self.col(i, 0) + node
        return slice(start, start + self.n * (self.M + 1), self.M + 1)

    def evaluate(self, U, p):
        Y = self.split(U)
        P, M, n = self.P, self.M, self.n
        nodal, (rb, Ja, Jb, Jpb), mon = self._collocate(Y, p)
        self._monitor = (np.array(U, dtype=float), mon)   # Newton asks for it at the same U
        blocks = self.interior(Y, p, nodal)
        self.evaluations += 1
        R, Rp = [rb], [Jpb]
        eye = np.eye(n) if P > 1 else None
        # (row offset, columns, block) triplets, then one assembly: an n x n block on the
        # n columns of one node (a strided slice), or a block on consecutive columns
        parts = [(0, self._columns(0, 0), Ja), (0, self._columns(P - 1, M), Jb)]
        row = n
        for i, (Ri, Ji, Rpi) in enumerate(blocks):
            R.append(Ri)
            Rp.append(Rpi)
            parts.append((row, self.col(i, 0), Ji))
            row += n * M
            if i < P - 1:   # continuity of y at the interface b_i = a_{i+1}
                R.append(Y[i, :, -1] - Y[i + 1, :, 0])
                Rp.append(np.zeros(n))
                parts.append((row, self._columns(i, M), eye))
                parts.append((row, self._columns(i + 1, 0), -eye))
                row += n
        if self.dense_jacobian:
            J = np.zeros((self.size, self.size))
            for r0, c0, B in parts:
                if isinstance(c0, slice):
                    J[r0:r0 + n, c0] += B
                else:
                    J[r0:r0 + B.shape[0], c0:c0 + B.shape[1]] = B
        else:
            rows, cols, vals = [], [], []
            for r0, c0, B in parts:
                if isinstance(c0, slice):
                    rr, cc = np.nonzero(np.ones((n, n)))
                    rows.append(r0 + rr)
                    cols.append(np.arange(c0.start, c0.stop, c0.step)[cc])
                    vals.append(np.asarray(B)[rr, cc])
                else:
                    B = sps.coo_matrix(B)
                    rows.append(r0 + B.row)
                    cols.append(c0 + B.col)
                    vals.append(B.data)
            J = sps.csc_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                       np.concatenate(cols))),
                               shape=(self.size, self.size))
        return np.concatenate(R), J, np.concatenate(Rp)

    def monitor(self, U):
        Y = self.split(U)
        if self._monitor is not None and np.array_equal(self._monitor[0], U):
            m, ga, gb = self._monitor[1]
        else:
            m, ga, gb = self.bvp.monitor(Y[0, :, 0], Y[-1, :, -1])
        g = np.zeros((self.P, self.n, self.M + 1))
        g[0, :, 0] += ga
        g[-1, :, -1] += gb
        return m, g.ravel()
