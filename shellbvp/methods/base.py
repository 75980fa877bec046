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
from typing import Callable, Protocol, runtime_checkable

import numpy as np

__all__ = ["DiscreteSystem", "Discretisation", "Transplantable", "SecondOrder", "InnerRoots",
           "Method", "DirectSolver", "NodalBVP", "ShellProblem", "NodalSystem", "MidSurface",
           "first_rung", "implements"]


@runtime_checkable
class DiscreteSystem(Protocol):
    """R(U, p) = 0: ``size`` unknowns U, one scalar parameter p, and the observable: all that
    bordered Newton and pseudo-arclength continuation need (:mod:`shellbvp.continuation`)."""

    size: int

    def evaluate(self, U, p):
        """(R (size,), dR/dU (size, size), dense or scipy.sparse, dR/dp (size,))."""

    def monitor(self, U):
        """(m, dm/dU): the BVP's observable (w / H) and its gradient."""


@runtime_checkable
class Discretisation(DiscreteSystem, Protocol):
    """A discrete system of a BVP, as every method's ``discretise`` returns: it can be
    started from a profile, interpolated, refined (the ladder that gives every fold its
    error estimate) and carried to another resolution.

    ``rung_ratio``: the factor by which the discretisation error shrinks from one rung to
    the next (0 where it converges exponentially: the finer point is then the exact one to
    leading order); an error estimate from the change c between two rungs is
    c / (1 - rung_ratio), the coarser point's error where the order holds."""

    bvp: object
    rung_ratio: float

    def from_profile(self, profile: Callable) -> np.ndarray:
        """U from a callable s -> (6, n) of the BVP's unknowns."""

    def dense(self, U, p) -> Callable:
        """t -> stacked (6 P, n) interpolant of the solution in the piece coordinate."""

    def refined(self) -> "Discretisation":
        """The next, finer system of the same method (for error estimates); ValueError where
        the method cannot refine further."""

    def for_tolerance(self, tol: float) -> "Discretisation":
        """The first rung of the fold ladder for a fold tolerance ``tol`` (this system, or a
        finer one of the same method)."""

    def transfer(self, U, p, other: "Discretisation") -> np.ndarray:
        """U carried onto ``other`` (same method and BVP, another resolution)."""

    def nodes(self, U, p):
        """(t, stacked (6 P, len(t)) values): the solution at the method's own points."""

    def describe(self) -> dict:
        """The resolution, for statistics (e.g. ``{"method": "spectral", "nodes": 32}``)."""


@runtime_checkable
class Transplantable(Protocol):
    """A nodal discretisation that can be laid on another BVP with the same pieces (the scene
    at a nearby shallowness, or the same BVP seen in another monitor), the unknowns at the
    same piece coordinates: fold curves, fold location in an end-state coordinate."""

    def on(self, bvp) -> "Transplantable":
        """The same discretisation of ``bvp``."""

    def split(self, U) -> np.ndarray:
        """U as (pieces, components, nodes)."""

    def states(self, U) -> np.ndarray:
        """The state at the nodes, (pieces, components, nodes)."""


@runtime_checkable
class SecondOrder(Transplantable, Protocol):
    """A discretisation with exact second derivatives and derivatives in the scene's data:
    what the minimally augmented fold system, the fold curve in theta and the fold's
    gradient need (:mod:`shellbvp.continuation.fold_curve`)."""

    def curvature_terms(self, U, p, w, v, dp) -> tuple:
        """The gradient in (U, p, theta) of the second directional derivative of
        w . (R, m) along (v, dp)."""

    def parameter_derivatives(self, U, p, names=("theta", "material", "h")) -> dict:
        """{x: (dR/dx, dm/dx)} for the scene's data x."""

    def at_tolerance(self, tol: float) -> "SecondOrder":
        """The first rung of the fold ladder for ``tol``, finer or coarser than this one."""


@runtime_checkable
class InnerRoots(Protocol):
    """A nodal discretisation that can report the inner constitutive roots (lam1, k1) at its
    nodes (starts for evaluating the state elsewhere)."""

    def inner_roots(self, U, p) -> np.ndarray:
        """(P, nodes, 2)."""


@runtime_checkable
class MidSurface(Protocol):
    """A discretisation of the mid-surface itself rather than of the first-order system
    (direct minimisation of the energy, :mod:`shellbvp.methods.ritz`): it reads the principal
    state from its unknowns (no inner constitutive inversion), integrates its own energy,
    and its Jacobian is the Hessian of that energy, whose spectrum is the discrete second
    variation."""

    def state_at(self, U, p, s) -> dict:
        """The state at points s > 0: ``s, r, z, theta, X`` (lam1, lam2, k1, k2), ``F``
        (g1, g2, kb1, kb2), ``M`` and ``F_r`` (per mu* h0 R0 per radian; F_z = 0),
        ``gw`` (n, 4) and ``Hw``
        (n, 4, 4) (gradient and Hessian of W in X)."""

    def output_points(self):
        """The points (s > 0) at which an equilibrium is reported."""

    def energies(self, U, p) -> tuple:
        """(E_s, E_b, E_p) per mu* h0 R0^2 by the method's own quadrature."""

    def spectrum(self, U, p, *, count: int = 4):
        """The smallest eigenvalues and modes of the Hessian at fixed parameter
        (:class:`shellbvp.stability.SecondVariation`)."""

    def profile(self, U, p):
        """s -> (6, n): the first-order system's unknowns (a guess for any method)."""


@runtime_checkable
class Method(Protocol):
    """A discretisation with named options (a small frozen dataclass)."""

    name: str

    def discretise(self, bvp) -> Discretisation:
        """The discrete system of ``bvp`` at this method's resolution."""


@runtime_checkable
class DirectSolver(Protocol):
    """A method that solves one equilibrium with its own adaptive solver (solve_bvp) rather
    than by Newton on its fixed discretisation."""

    def solve(self, bvp, p, profile) -> tuple:
        """(system on the solver's final mesh, U, stats); ConvergenceError on failure."""


@runtime_checkable
class NodalBVP(Protocol):
    """What a nodal discretisation needs of a BVP: ``n`` components on ``P`` pieces
    [a_i, b_i], the right-hand side at nodes with its exact Jacobians, the boundary
    conditions and the observable. A small problem of one's own (the tests' Bratu problem)
    provides just this."""

    n: int
    P: int
    lengths: np.ndarray

    def s_of(self, i: int, t): ...

    def rhs(self, s, Y, p, hint=None): ...

    def boundary(self, ya, yb, p): ...

    def monitor(self, ya, yb): ...


@runtime_checkable
class ShellProblem(NodalBVP, Protocol):
    """A nodal BVP that also evaluates rhs, boundary conditions and monitor in one compiled
    call, states the error of its derivatives and the round-off of its folds, and carries
    its inner roots to another discretisation (:class:`shellbvp.bvp.ShellBVP`)."""

    jacobian_error: float
    #: (P - 1, n): the unknowns' jumps across the interfaces
    jumps: np.ndarray

    def jumps_at(self, p): ...

    def collocate(self, s, Y, p, hint=None): ...

    def round_off(self, p: float) -> float: ...

    def carried_hint(self, hint, Y, Y_new, p, resample): ...

    def reference(self, s): ...

    def reference_rate(self, s): ...


def inside(s, i: int, P: int) -> np.ndarray:
    """The points s (increasing) of piece i of P as seen from that piece: a profile gives an
    interface to the next piece, so the piece's last point, where it is that interface, is
    taken a rounding unit inside (where the tangent of a shell with a kink jumps)."""
    s = np.array(s, dtype=float)
    if i < P - 1:
        s[-1] = np.nextafter(s[-1], -np.inf)
    return s


def implements(obj, protocol) -> bool:
    """Whether ``obj`` provides ``protocol`` (one of this module's capabilities), decided
    once per class: a capability is a property of a class (its methods, properties and the
    attributes its ``__init__`` sets), and a runtime protocol check costs 6-20 us, which
    on the paths of a continuation added ~1 ms per kappa_s."""
    key = (type(obj), protocol)
    known = _CAPABILITIES.get(key)
    if known is None:
        known = _CAPABILITIES[key] = isinstance(obj, protocol)
    return known


#: (class, protocol) -> whether instances of that class provide the protocol (a memo of
#: :func:`implements`, filled as classes are met)
_CAPABILITIES: dict = {}


def first_rung(system, tol: float, *, exact: bool = False):
    """The first rung of the fold ladder of ``system`` for a fold tolerance ``tol``:
    ``system.at_tolerance(tol)`` with ``exact`` (a :class:`SecondOrder` system, finer or
    coarser), else ``system.for_tolerance(tol)`` where the system is a
    :class:`Discretisation` (this one or finer), else the system itself (a hand-written
    system in the tests has one resolution)."""
    if exact and implements(system, SecondOrder):
        return system.at_tolerance(tol)
    if implements(system, Discretisation):
        return system.for_tolerance(tol)
    return system


class NodalSystem:
    """Unknowns at the same nodes t_0 = 0 < ... < t_M = 1 of every piece: U = Y - Y0
    (P, n, M + 1) flattened (piece, component, node), the state Y less the BVP's reference
    state Y0 at the nodes (a shell's undeformed meridian: U is the displacement, with the
    moment and forces; zero for a BVP without one, or where the class sets ``displaced``
    False). Rows: the n boundary conditions of the BVP, the interior equations of each piece
    (n M rows, from the subclass), and the n interface conditions y(b_i) + jump_i =
    y(a_{i+1}) at each interface (continuity, but for a shell's tangent angle at a kink of
    its geometry). Subclasses implement :meth:`interior`.

    Why a displacement: a thin shell's strains under a small load are tiny against its
    coordinates (1e-7 at R/t = 1e5 and a deflection of h/100), and a differentiation matrix
    on a short element (~ N^2 / length ~ 1e7) amplifies the round-off of coordinates of
    order one (1e-16) to ~1e-9 in their derivatives: the strains would carry 1 % of noise.
    The displacement's round-off is relative to itself; the reference's derivative enters
    exactly (:meth:`shellbvp.bvp.ShellBVP.reference_rate`), not differentiated numerically.
    """

    #: whether the unknowns are the state less the BVP's reference (else the state itself)
    displaced = True
    #: the error's factor per rung (:class:`Discretisation`): 0 for exponential convergence
    rung_ratio = 0.0

    def __init__(self, bvp, t):
        if not implements(bvp, NodalBVP):
            raise ValueError(f"a nodal discretisation needs a BVP with n, P, lengths, s_of, rhs, "
                             f"boundary and monitor, got {type(bvp).__name__}")
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
        #: the BVP's capabilities beyond the nodal ones, decided once
        self._shell = implements(bvp, ShellProblem)
        #: the jumps of the unknowns across the interfaces (P - 1, n): a shell's, else none
        self.jumps = np.asarray(bvp.jumps, dtype=float) if self._shell \
            else np.zeros((self.P - 1, n))
        #: the reference state Y0 and its s-derivative at the nodes (P, n, M + 1), each
        #: piece's from its own side of an interface; zero where there is none
        self.Y0 = np.zeros((self.P, n, self.M + 1))
        self.Y0_rate = np.zeros_like(self.Y0)
        if self._shell and self.displaced:
            for i in range(self.P):
                si = inside(self.s[i], i, self.P)
                self.Y0[i] = bvp.reference(si)
                self.Y0_rate[i] = bvp.reference_rate(si)
        #: the component of every unknown (the continuation's norm scales each component
        #: on its own, :func:`shellbvp.continuation.arclength.unknown_weights`)
        self.groups = np.repeat(np.tile(np.arange(n), self.P), self.M + 1)
        #: the reference's own mismatch across each interface, Y0(b_i) + jump - Y0(a_{i+1})
        #: (round-off): the interface rows in the displacement
        self._offsets = self.Y0[:-1, :, -1] - self.Y0[1:, :, 0]

    @property
    def jacobian_error(self) -> float:
        """The relative error of the Jacobian dR/dU: the BVP's ``jacobian_error`` (that of
        its derivatives, which the discretisation differentiates exactly), inf where the
        BVP does not state it."""
        return self.bvp.jacobian_error if self._shell else math.inf

    @property
    def round_off_step(self) -> float:
        """The relative Newton update at which the equations reach their round-off floor:
        the shell BVP's (a thin shell's grows like 1/h), 0 (the default floor) else."""
        return self.bvp.round_off_step if self._shell else 0.0

    # --- unknowns ----------------------------------------------------------------------------
    def split(self, U) -> np.ndarray:
        """U (or a direction or difference of unknowns) as (P, n, M + 1)."""
        return np.asarray(U, dtype=float).reshape(self.P, self.n, self.M + 1)

    def states(self, U) -> np.ndarray:
        """The state Y = Y0 + U at the nodes, (P, n, M + 1)."""
        return self.Y0 + self.split(U)

    def from_states(self, Y) -> np.ndarray:
        """U from states Y (P, n, M + 1) at the nodes."""
        return (np.asarray(Y, dtype=float) - self.Y0).ravel()

    def from_profile(self, profile) -> np.ndarray:
        """U from a profile s -> (n, len(s)), each piece from its own side of an interface
        (:func:`inside`)."""
        return self.from_states(np.stack([
            np.asarray(profile(inside(self.s[i], i, self.P)), dtype=float)
            for i in range(self.P)]))

    def nodes(self, U, p):
        """The nodes t (M + 1,) and the stacked states (n P, M + 1) there."""
        return self.t, self.states(U).reshape(self.n * self.P, self.M + 1)

    def transfer(self, U, p, other) -> np.ndarray:
        d = self.dense(U, p)
        return other.from_states(d(other.t).reshape(other.P, other.n, -1))

    def col(self, i, c):
        return (i * self.n + c) * (self.M + 1)

    def inner_roots(self, U, p) -> np.ndarray:
        """The inner roots (lam1, k1) at the nodes (P, M + 1, 2), the BVP's inner solve
        warm-started from this system's last evaluation (as during its solves): starts for
        evaluating the state elsewhere (:meth:`shellbvp.bvp.ShellBVP.state`). By the
        evaluation's own compiled call (:meth:`_collocate`), not a second program."""
        nodal, _, _ = self._collocate(self.states(U), p)
        return np.asarray(nodal.hint.q).reshape(self.P, self.M + 1, 2)

    # --- the system --------------------------------------------------------------------------
    def interior(self, Y, p, nodal, into=None):
        """Per piece: (R_i (n M,), dR_i/dY_i (n M, n (M + 1)), dense or sparse, dR_i/dp),
        given the unknowns Y = U as (P, n, M + 1) (:meth:`split`: the displacement where the
        system is ``displaced``, whose equations are y' - Y0' = f(Y0 + U) - Y0' with the
        reference's rate ``Y0_rate``) and ``nodal``, the BVP's right-hand side at the
        states (:class:`shellbvp.bvp.Nodal`).
        ``into``: given to methods whose ``dense_jacobian`` is True: per piece, the view of
        the Jacobian that dR_i/dY_i occupies; the method writes the block there and returns
        that view (no copy of the largest array of an evaluation)."""
        raise NotImplementedError

    def _collocate(self, Y, p):
        """The BVP's nodal rhs, boundary conditions and monitor at Y (one compiled call when
        the BVP offers it), with the inner Newton warm-started from the last evaluation."""
        bvp = self.bvp
        if self._shell:
            nodal, bc, mon = bvp.collocate(self.s, Y, p, self._hint)
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

    def _interior_slots(self):
        """(first row, first column) of each piece's interior block in the Jacobian: the
        rows after the n boundary rows and the n continuity rows of every interface before."""
        n, M = self.n, self.M
        return [(n + i * (n * M + n), self.col(i, 0)) for i in range(self.P)]

    def _columns(self, i, node):
        """The columns of all n components of piece i at ``node``: a strided slice."""
        start = self.col(i, 0) + node
        return slice(start, start + self.n * (self.M + 1), self.M + 1)

    def evaluate(self, U, p):
        V = self.split(U)
        P, M, n = self.P, self.M, self.n
        nodal, (rb, Ja, Jb, Jpb), mon = self._collocate(self.Y0 + V, p)
        self._monitor = (np.array(U, dtype=float), mon)   # Newton asks for it at the same U
        J = into = None
        if self.dense_jacobian:
            J = np.zeros((self.size, self.size))
            into = [J[r0:r0 + n * M, c0:c0 + n * (M + 1)] for r0, c0 in self._interior_slots()]
        blocks = self.interior(V, p, nodal, into=into)
        self.evaluations += 1
        R, Rp = [rb], [Jpb]
        eye = np.eye(n) if P > 1 else None
        jumps, jumps_p = self.bvp.jumps_at(p) if self._shell \
            else (self.jumps, np.zeros_like(self.jumps))
        # (row offset, columns, block) triplets, then one assembly: an n x n block on the
        # n columns of one node (a strided slice), or a block on consecutive columns (not
        # where the method wrote it in place already)
        parts = [(0, self._columns(0, 0), Ja), (0, self._columns(P - 1, M), Jb)]
        row = n
        for i, (Ri, Ji, Rpi) in enumerate(blocks):
            R.append(Ri)
            Rp.append(Rpi)
            if into is None or Ji is not into[i]:
                parts.append((row, self.col(i, 0), Ji))
            row += n * M
            if i < P - 1:   # the interface b_i = a_{i+1}: y(b_i) + jump_i = y(a_{i+1})
                R.append(V[i, :, -1] - V[i + 1, :, 0] + (jumps[i] + self._offsets[i]))
                Rp.append(jumps_p[i])
                parts.append((row, self._columns(i, M), eye))
                parts.append((row, self._columns(i + 1, 0), -eye))
                row += n
        if self.dense_jacobian:
            for r0, c0, B in parts:
                if isinstance(c0, slice):
                    J[r0:r0 + n, c0] += B
                else:
                    J[r0:r0 + B.shape[0], c0:c0 + B.shape[1]] = B
        else:
            import scipy.sparse as sps

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
        Y = self.states(U)
        if self._monitor is not None and np.array_equal(self._monitor[0], U):
            m, ga, gb = self._monitor[1]
        else:
            m, ga, gb = self.bvp.monitor(Y[0, :, 0], Y[-1, :, -1])
        g = np.zeros((self.P, self.n, self.M + 1))
        g[0, :, 0] += ga
        g[-1, :, -1] += gb
        return m, g.ravel()
