"""Multiple shooting with diffrax: an independent check of the collocation methods.

Every piece is cut into the same number of equal segments (so interfaces are segment
boundaries and the fields are smooth inside every segment). The unknowns are the states at
the segment starts and the state at the edge, U = (U_0, ..., U_{n-1}, y_edge); the residual
collects the BVP's boundary conditions (pole and edge, 6 rows) and the continuity
flow_j(U_j) = U_{j+1} (6 n rows, which include the exact interfaces). The Jacobian is exact
and block-bidiagonal: the 6x6 sensitivity of each segment's flow map comes from forward-mode
differentiation through the ODE solver (``diffrax.ForwardMode``), vmapped over segments, so
one small program is compiled instead of one per segment.

ODE solver: ``diffrax.Tsit5`` (5th order) with a PID controller at rtol = atol = ``rtol``,
or a fixed number of steps per segment (``steps``) for convergence-order studies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import ConvergenceError

__all__ = ["Shooting", "ShootingSystem", "default_segments"]

#: save points per segment for the dense output (cubic Hermite between them)
SAVE_PER_SEGMENT = 17
#: ... and at least this many in all (the dense output's resolution must not fall with the
#: number of segments: cubic Hermite between saved points is 4th order)
SAVE_POINTS = 256
#: the refinement ladder divides rtol by this per rung
RTOL_STEP = 10.0
#: ODE tolerance of equilibria and branches where ``Shooting.rtol`` is not given
SOLVE_RTOL = 1e-10
#: the ODE tolerances a fold ladder may use (below 1e-14 Tsit5 meets round-off)
RTOL_RANGE = (1e-14, 1e-4)
#: an ODE solve with more steps than this on one segment is a failure, not a result
MAX_ODE_STEPS = 100_000


#: default segment length in units of sqrt(h) R0 (the bending boundary layer decays over
#: ~0.8 sqrt(h) R0 on a sphere, so the flow grows by ~e^2 per segment): enough to keep the
#: continuity equations well conditioned, few enough that the segments, solved side by side
#: and each paying for the slowest, are cheap. The default cap (T = 5.2) gets 4 segments:
#: a kappa_s at rtol 1e-8 took 2.1x less time than with 16, at the same accuracy.
SEGMENT_SQRT_H = 1.5
#: the default is at most this many segments (deep or thin caps)
MAX_DEFAULT_SEGMENTS = 16


def default_segments(bvp) -> int:
    """Segments for a BVP: its shallowness T = L / sqrt(h R_c) (:attr:`shellbvp.Scene.
    shallowness`) over ``SEGMENT_SQRT_H``, at least one per piece, at most
    ``MAX_DEFAULT_SEGMENTS`` (unless the pieces need more)."""
    T = bvp.scene.shallowness
    return max(bvp.P, min(MAX_DEFAULT_SEGMENTS, int(math.ceil(T / SEGMENT_SQRT_H))))


@dataclass(frozen=True)
class Shooting:
    """Multiple shooting.

    Attributes:
        segments: segments in all (at least one per piece; None: :func:`default_segments`).
        rtol: Tsit5's rtol = atol (adaptive steps). None: ``SOLVE_RTOL`` for equilibria and
            branches, and a fold ladder that starts at the fold tolerance itself (a fold
            wanted to 1e-8 is located at rtol 1e-8, then 1e-9, ...: the work follows the
            tolerance); a number: the ladder starts there whatever the fold tolerance.
        steps: fixed Tsit5 steps per segment instead of adaptive ones (then ``rtol`` and
            ``bracket_rtol`` mean nothing and must be None; the ladder doubles the steps).
        bracket_rtol: follow branches at this looser ODE tolerance, and locate folds from
            ``rtol`` (the branch only brackets them; None: everything at ``rtol``).
    """

    segments: int | None = None
    rtol: float | None = None
    steps: int | None = None
    bracket_rtol: float | None = None
    name = "shooting"

    def __post_init__(self):
        if self.segments is not None and not (isinstance(self.segments, (int, np.integer))
                                              and 1 <= self.segments <= 4096):
            raise ValueError(f"segments must be an integer in [1, 4096] or None, got "
                             f"{self.segments!r}")
        if self.rtol is not None and not (isinstance(self.rtol, float)
                                          and 1e-15 < self.rtol < 1e-2):
            raise ValueError(f"rtol must be None or a float in (1e-15, 1e-2), got {self.rtol!r}")
        low = SOLVE_RTOL if self.rtol is None else self.rtol
        if self.bracket_rtol is not None and not (
                isinstance(self.bracket_rtol, float) and low <= self.bracket_rtol < 1e-2):
            raise ValueError(f"bracket_rtol must be None or a float in [rtol, 1e-2), got "
                             f"{self.bracket_rtol!r}")
        if self.steps is not None:
            if not (isinstance(self.steps, (int, np.integer)) and self.steps >= 1):
                raise ValueError(f"steps must be a positive integer or None, got "
                                 f"{self.steps!r}")
            if self.rtol is not None or self.bracket_rtol is not None:
                raise ValueError("steps (fixed steps) and rtol / bracket_rtol (adaptive "
                                 "steps) exclude each other: give one")

    def discretise(self, bvp) -> "ShootingSystem":
        """The shooting system of ``bvp``; ValueError for a point load at a pole, which
        shooting does not resolve (the state diverges like log s there, and the integration
        starts at a fixed offset from the pole that no rung of its ladder refines: the
        error estimate would miss the offset's error)."""
        from ..mesh import loaded_poles

        if any(loaded_poles(bvp.scene)):
            raise ValueError("method 'shooting' cannot resolve a point load at a pole (the "
                             "state diverges like log s there); use method 'spectral' (the "
                             "default), 'collocation' or 'energy'")
        segments = default_segments(bvp) if self.segments is None else self.segments
        if self.steps is not None:
            return ShootingSystem(bvp, segments, steps=self.steps)
        rtol = SOLVE_RTOL if self.rtol is None else self.rtol
        if self.bracket_rtol is None:
            return ShootingSystem(bvp, segments, rtol, fold_rtol=self.rtol)
        return ShootingSystem(bvp, segments, self.bracket_rtol, fold_rtol=self.rtol)


@lru_cache(maxsize=32)
def _compiled(vector_field, adaptive):
    import diffrax

    from ..jaxsetup import jax, jit

    def solve_segment(piece, y0, s0, s1, p, lam, h, c, tol, saveat):
        # ``tol`` is the PID tolerance (adaptive) or the number of fixed steps (not adaptive);
        # both are traced, so changing them does not recompile.
        def vf(s, y, args):
            return vector_field(piece, s, y, p, lam, h, c)

        if adaptive:
            ctrl, dt0 = diffrax.PIDController(rtol=tol, atol=tol), (s1 - s0) / 8
        else:
            ctrl, dt0 = diffrax.ConstantStepSize(), (s1 - s0) / tol
        return diffrax.diffeqsolve(
            diffrax.ODETerm(vf), diffrax.Tsit5(), s0, s1, dt0, y0, stepsize_controller=ctrl,
            saveat=saveat, max_steps=MAX_ODE_STEPS, adjoint=diffrax.ForwardMode(),
            throw=False)

    def flow(y0, piece, s0, s1, p, lam, h, c, tol):
        return solve_segment(piece, y0, s0, s1, p, lam, h, c, tol,
                             diffrax.SaveAt(t1=True)).ys[-1]

    def flow_and_sens(piece, y0, s0, s1, p, lam, h, c, tol):
        # sensitivities to the initial state and to the parameter (forward mode)
        return (flow(y0, piece, s0, s1, p, lam, h, c, tol),
                *jax.jacfwd(flow, argnums=(0, 4))(y0, piece, s0, s1, p, lam, h, c, tol))

    def dense(piece, y0, s0, s1, p, lam, h, c, tol, unit):
        ts = s0 + (s1 - s0) * unit
        ys = solve_segment(piece, y0, s0, s1, p, lam, h, c, tol, diffrax.SaveAt(ts=ts)).ys
        fs = jax.vmap(lambda s, y: vector_field(piece, s, y, p, lam, h, c))(ts, ys)
        return ts, ys, fs

    ax = (0, 0, 0, 0, None, None, None, None, None)
    return (jit(jax.vmap(flow_and_sens, in_axes=ax)),
            jit(jax.vmap(dense, in_axes=ax + (None,))))


class ShootingSystem:
    """Multiple shooting of a BVP as a finite system R(U, p) = 0 (6 (n + 1) unknowns)."""

    #: a rung divides the ODE tolerance by RTOL_STEP, the error with it
    rung_ratio = 1.0 / RTOL_STEP

    def __init__(self, bvp, segments: int, rtol: float = 1e-10, steps: int | None = None,
                 fold_rtol: float | None = None):
        self.bvp = bvp
        #: the ODE tolerance the refinement ladder starts from (:meth:`for_tolerance`); None:
        #: from the fold tolerance
        self.fold_rtol = fold_rtol
        per_piece = max(1, int(math.ceil(segments / bvp.P)))
        edges = [np.linspace(bvp.a[i], bvp.b[i], per_piece + 1) for i in range(bvp.P)]
        self.s0 = np.concatenate([e[:-1] for e in edges])
        self.s1 = np.concatenate([e[1:] for e in edges])
        self.piece = np.repeat(np.arange(bvp.P), per_piece)
        #: the segment each interface ends (a piece's last): the state jumps there by the
        #: BVP's jump (:meth:`shellbvp.bvp.ShellBVP.jumps_at`), continuous elsewhere
        self.jump_segments = (np.arange(1, bvp.P) * per_piece - 1).astype(int)
        self.per_piece, self.n, self.segments = per_piece, self.s0.size, segments
        self.size = 6 * (self.n + 1)
        #: the component of every unknown (the continuation's norm scales each on its own)
        self.groups = np.tile(np.arange(6), self.n + 1)
        self.rtol, self.steps = rtol, steps
        self._tol = rtol if steps is None else float(steps)
        self._flow, self._dense = _compiled(bvp.vector_field(), steps is None)
        self._save = max(SAVE_PER_SEGMENT, int(math.ceil(SAVE_POINTS / self.n)) + 1)
        self.evaluations = 0

    def _args(self, p):
        return (float(p), self.bvp.scene.material_parameter, self.bvp.scene.h,
                self.bvp.field_parameters)

    def from_profile(self, profile) -> np.ndarray:
        y = np.asarray(profile(np.append(self.s0, self.bvp.b[-1])), dtype=float)
        return y.T.ravel()

    def evaluate(self, U, p):
        n = self.n
        Y = np.asarray(U, dtype=float).reshape(n + 1, 6)
        ends, sens, sens_p = (np.asarray(a) for a in self._flow(
            self.piece, Y[:-1], self.s0, self.s1, *self._args(p), self._tol))
        rb, Ja, Jb, Jpb = self.bvp.boundary(Y[0], Y[-1], p)
        self.evaluations += 1
        R = np.empty(self.size)
        J = np.zeros((self.size, self.size))
        Rp = np.zeros(self.size)
        R[:6], J[:6, :6], J[:6, -6:], Rp[:6] = rb, Ja, Jb, Jpb
        jumps, jumps_p = (np.zeros((n, 6)) for _ in range(2))
        if self.bvp.P > 1:                   # (one piece: no interface)
            jumps[self.jump_segments], jumps_p[self.jump_segments] = self.bvp.jumps_at(p)
        for j in range(n):  # continuity: flow_j(U_j) + jump_j - U_{j+1} (U_n = y_edge)
            rows = slice(6 + 6 * j, 12 + 6 * j)
            R[rows] = ends[j] + jumps[j] - Y[j + 1]
            J[rows, 6 * j:6 * j + 6] = sens[j]
            J[rows, 6 * j + 6:6 * j + 12] = -np.eye(6)
            Rp[rows] = sens_p[j] + jumps_p[j]
        if not (np.all(np.isfinite(R)) and np.all(np.isfinite(J)) and np.all(np.isfinite(Rp))):
            raise ConvergenceError(
                f"shooting: non-finite residual ({self.bvp.scene.quote(p)}); the ODE "
                f"solver or the inner Newton failed on a segment - use more segments or a "
                f"closer guess")
        return R, J, Rp

    def monitor(self, U):
        Y = np.asarray(U, dtype=float).reshape(self.n + 1, 6)
        m, ga, gb = self.bvp.monitor(Y[0], Y[-1])
        g = np.zeros((self.n + 1, 6))
        g[0] += ga
        g[-1] += gb
        return m, g.ravel()

    def dense(self, U, p):
        """Stacked (6 P, n) cubic Hermite interpolant in the piece coordinate t."""
        from scipy.interpolate import CubicHermiteSpline

        bvp = self.bvp
        Y = np.asarray(U, dtype=float).reshape(self.n + 1, 6)
        ts, ys, fs = (np.asarray(a) for a in self._dense(
            self.piece, Y[:-1], self.s0, self.s1, *self._args(p), self._tol,
            np.linspace(0.0, 1.0, self._save)))
        splines = []
        for i in range(bvp.P):
            sel = np.flatnonzero(self.piece == i)
            cat = lambda a: np.concatenate([a[j] if k == 0 else a[j][1:]  # noqa: E731
                                            for k, j in enumerate(sel)])
            splines.append(CubicHermiteSpline(cat(ts), cat(ys), cat(fs), axis=0))

        def dense_t(t):
            t = np.atleast_1d(np.asarray(t, dtype=float))
            return np.concatenate([splines[i](bvp.s_of(i, t)).T for i in range(bvp.P)])

        return dense_t

    def nodes(self, U, p):
        """Stacked values (6 P, n) at the saved points of every segment (piece coordinate)."""
        t = np.linspace(0.0, 1.0, self.per_piece * (self._save - 1) + 1)
        return t, self.dense(U, p)(t)

    def refined(self) -> "ShootingSystem":
        if self.steps is not None:
            return ShootingSystem(self.bvp, self.segments, steps=2 * self.steps)
        rtol = self.rtol / RTOL_STEP
        if rtol < RTOL_RANGE[0]:
            raise ValueError(f"cannot refine below rtol = {RTOL_RANGE[0]:g}")
        return ShootingSystem(self.bvp, self.segments, rtol, fold_rtol=rtol)

    def for_tolerance(self, tol: float) -> "ShootingSystem":
        """The first rung of the fold ladder for a fold tolerance ``tol``: the ODE tolerance
        ``fold_rtol``, or ``tol`` itself (within ``RTOL_RANGE``) where the method left it
        free (the branch may have been followed at a looser tolerance, only to bracket the
        folds). Fixed steps: this system."""
        if self.steps is not None:
            return self
        rtol = self.fold_rtol if self.fold_rtol is not None else \
            min(max(tol, RTOL_RANGE[0]), RTOL_RANGE[1])
        if rtol == self.rtol:
            return self
        return ShootingSystem(self.bvp, self.segments, rtol, fold_rtol=rtol)

    def transfer(self, U, p, other) -> np.ndarray:
        if other.n != self.n:
            return other.from_profile(self.bvp.profile(self.dense(U, p)))
        return np.array(U, dtype=float)

    def describe(self) -> dict:
        return {"method": "shooting", "segments": self.n,
                "rtol": self.rtol if self.steps is None else None, "steps": self.steps}
