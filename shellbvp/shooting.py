"""Multiple-shooting back-end: diffrax integration of the compiled system and Newton's method.

Every piece of the stimulus is cut into the same number of equal segments (so interfaces are
segment boundaries, the fields are smooth inside every segment, and all pieces share one grid
in the piece coordinate t). The unknowns are the states U_j at the segment starts; the
residual collects the pole conditions, the continuity of y across every segment boundary
(exact interfaces) and the edge conditions. The Jacobian is exact and block-bidiagonal: the
6x6 sensitivity of each segment's flow map comes from forward-mode differentiation through
the ODE solver (``diffrax.ForwardMode``), vmapped over segments, so one small program is
compiled instead of one per segment. Newton's method runs on the host (it reports the
residual and step per iteration, and stops with a diagnosis when the residual stops falling).

ODE solver: ``diffrax.Tsit5`` (5th order) with a PID controller at rtol = atol = tol, or a
fixed number of steps per segment (``steps=``) for convergence-order studies.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from ._jax import jax
from .axisym import ConvergenceError, point_functions

import diffrax  # noqa: E402
import jax.numpy as jnp  # noqa: E402

__all__ = ["shoot"]

NEWTON_MAXITER = 30
SAVE_PER_SEGMENT = 17


@lru_cache(maxsize=32)
def _compiled(model, material, rhob1, metric, fields, n_pieces, adaptive):
    pf = point_functions(model, material, rhob1, metric)

    def F_of(piece, s, p):
        branches = [lambda s, p, i=i: jnp.stack([jnp.asarray(v, dtype=jnp.float64)
                                                 for v in fields(i, s, p)])
                    for i in range(n_pieces)]
        return jax.lax.switch(piece, branches, s, p) if n_pieces > 1 else branches[0](s, p)

    def solve_segment(piece, y0, s0, s1, p, lam, h, tol, saveat):
        # ``tol`` is the PID tolerance (adaptive) or the number of fixed steps (not adaptive);
        # both are traced, so changing them does not recompile.
        def vf(s, y, args):
            return pf["rhs"](y, s, F_of(piece, s, p), lam, h)[0]

        if adaptive:
            ctrl, dt0 = diffrax.PIDController(rtol=tol, atol=tol), (s1 - s0) / 8
        else:
            ctrl, dt0 = diffrax.ConstantStepSize(), (s1 - s0) / tol
        return diffrax.diffeqsolve(
            diffrax.ODETerm(vf), diffrax.Tsit5(), s0, s1, dt0, y0, stepsize_controller=ctrl,
            saveat=saveat, max_steps=100_000, adjoint=diffrax.ForwardMode(), throw=False)

    def flow(y0, piece, s0, s1, p, lam, h, tol):
        return solve_segment(piece, y0, s0, s1, p, lam, h, tol, diffrax.SaveAt(t1=True)).ys[-1]

    def flow_and_sens(piece, y0, s0, s1, p, lam, h, tol):
        # Sensitivities to the initial state and to the parameter (forward mode).
        return (flow(y0, piece, s0, s1, p, lam, h, tol),
                *jax.jacfwd(flow, argnums=(0, 4))(y0, piece, s0, s1, p, lam, h, tol))

    def pole(y0, eps, p, lam, h, held):
        q, X, ok = pf["algebraic"](y0, eps, F_of(0, eps, p), lam, h)
        third = jnp.where(held, y0[1] + y0[0] * y0[2] / 2, y0[5])
        return jnp.stack([X[0] - X[1], X[2] - X[3], third])

    def pole_and_jac(y0, eps, p, lam, h, held):
        return (pole(y0, eps, p, lam, h, held),
                *jax.jacfwd(pole, argnums=(0, 2))(y0, eps, p, lam, h, held))

    def dense(piece, y0, s0, s1, p, lam, h, tol):
        ts = s0 + (s1 - s0) * jnp.linspace(0.0, 1.0, SAVE_PER_SEGMENT)
        ys = solve_segment(piece, y0, s0, s1, p, lam, h, tol, diffrax.SaveAt(ts=ts)).ys
        fs = jax.vmap(lambda s, y: pf["rhs"](y, s, F_of(piece, s, p), lam, h)[0])(ts, ys)
        return ts, ys, fs

    seg_axes = (0, 0, 0, 0, None, None, None, None)
    return (jax.jit(jax.vmap(flow_and_sens, in_axes=seg_axes)), jax.jit(pole_and_jac),
            jax.jit(jax.vmap(dense, in_axes=seg_axes)))


class ShootingSystem:
    """Multiple shooting of a scene as a finite system R(U, p) = 0 (the
    :class:`shellbvp.discrete.DiscreteSystem` protocol).

    Unknowns: the states at the segment starts and the state at the edge, U = (U_0, ...,
    U_{n-1}, y_edge) (6 (n + 1) values). Equations: pole conditions (3), continuity
    flow_j(U_j) = U_{j+1} and flow_{n-1}(U_{n-1}) = y_edge (6 n), edge conditions (3). dR/dU
    and dR/dp are exact (forward-mode sensitivities through Tsit5).

    Arguments:
        scene: the problem; segments: total number of segments (at least one per piece);
        eps: pole offset; ode_tol: Tsit5 PID tolerance, or ``steps`` fixed steps per segment.
    """

    def __init__(self, scene, segments: int = 16, eps: float | None = None,
                 ode_tol: float = 1e-10, steps: int | None = None):
        from .equilibrium import _Problem

        eps = 1e-4 * scene.theta if eps is None else float(eps)
        self.scene, self.eps = scene, eps
        self.problem = prob = _Problem(scene, 0.0, eps)
        per_piece = max(1, int(math.ceil(segments / prob.P)))
        edges = [np.linspace(prob.a[i], prob.b[i], per_piece + 1) for i in range(prob.P)]
        self.s0 = np.concatenate([e[:-1] for e in edges])
        self.s1 = np.concatenate([e[1:] for e in edges])
        self.piece = np.repeat(np.arange(prob.P), per_piece)
        self.per_piece = per_piece
        self.n = self.s0.size
        self.size = 6 * (self.n + 1)
        self.ode_tol = ode_tol if steps is None else float(steps)
        self._flow, self._pole, self._dense = _compiled(
            scene.model, scene.material, float(scene.rhob1), bool(scene.metric), scene.fields,
            prob.P, steps is None)
        self.evaluations = 0

    def _args(self, p):
        return (float(p), self.scene.material_parameter, self.scene.h)

    def from_profile(self, profile) -> np.ndarray:
        y = np.asarray(profile(np.append(self.s0, self.scene.theta)), dtype=float)
        return y.T.ravel()

    def evaluate(self, U, p):
        sc, n = self.scene, self.n
        Y = np.asarray(U, dtype=float).reshape(n + 1, 6)
        ends, sens, sens_p = (np.asarray(a) for a in self._flow(
            self.piece, Y[:-1], self.s0, self.s1, *self._args(p), self.ode_tol))
        rp, Jp, Jpp = (np.asarray(a) for a in self._pole(Y[0], self.eps, *self._args(p),
                                                          sc.apex == "held"))
        self.evaluations += 1
        R = np.empty(self.size)
        J = np.zeros((self.size, self.size))
        Rp = np.zeros(self.size)
        R[:3], J[:3, :6], Rp[:3] = rp, Jp, Jpp
        for j in range(n):  # continuity: flow_j(U_j) - U_{j+1} (U_n = y_edge)
            rows = slice(3 + 6 * j, 9 + 6 * j)
            R[rows] = ends[j] - Y[j + 1]
            J[rows, 6 * j:6 * j + 6] = sens[j]
            J[rows, 6 * j + 6:6 * j + 12] = -np.eye(6)
            Rp[rows] = sens_p[j]
        e = Y[-1]
        T = sc.theta
        if sc.edge == "free":
            R[-3:], comps = e[3:6], (3, 4, 5)
        else:
            R[-3:], comps = [e[0] - math.sin(T), e[1] - (math.cos(T) - 1.0), e[2] - T], (0, 1, 2)
        for k, c in enumerate(comps):
            J[self.size - 3 + k, 6 * n + c] = 1.0
        if not (np.all(np.isfinite(R)) and np.all(np.isfinite(J)) and np.all(np.isfinite(Rp))):
            raise ConvergenceError(
                f"shooting: non-finite residual ({sc.parameter} = {p:g}); the ODE solver or the "
                f"inner Newton failed on a segment - use more segments or a closer guess")
        return R, J, Rp

    def monitor(self, U):
        Y = np.asarray(U, dtype=float).reshape(self.n + 1, 6)
        m = float(self.problem.monitor(Y[0], Y[-1]))
        g = np.zeros((self.n + 1, 6))
        g[0], g[-1] = self.problem.monitor_gradient(Y[0], Y[-1])
        return m, g.ravel()

    @property
    def output_nodes(self):
        """The t nodes at which :meth:`dense` saves the solution (per piece)."""
        return np.linspace(0.0, 1.0, self.per_piece * (SAVE_PER_SEGMENT - 1) + 1)

    def dense(self, U, p):
        """Stacked (6 P, n) cubic Hermite interpolant in the piece coordinate t."""
        prob = self.problem
        Y = np.asarray(U, dtype=float).reshape(self.n + 1, 6)
        ts, ys, fs = (np.asarray(a) for a in self._dense(
            self.piece, Y[:-1], self.s0, self.s1, *self._args(p), self.ode_tol))
        splines = []
        for i in range(prob.P):
            sel = np.flatnonzero(self.piece == i)
            cat = lambda a: np.concatenate([a[j] if k == 0 else a[j][1:]  # noqa: E731
                                            for k, j in enumerate(sel)])
            splines.append(CubicHermiteSpline(cat(ts), cat(ys), cat(fs), axis=0))

        def dense_t(t):
            t = np.asarray(t, dtype=float)
            return np.concatenate([splines[i](prob.s_of(i, t)).T for i in range(prob.P)])

        return dense_t


def shoot(prob, guess, tol, n_segments, steps=None, newton_tol=None):
    """Solve the stacked problem ``prob`` by multiple shooting (Newton on
    :class:`ShootingSystem` at fixed p); same returns as the collocation back-end."""
    from .discrete import newton

    system = ShootingSystem(prob.scene, n_segments, prob.eps, ode_tol=tol, steps=steps)
    newton_tol = 10 * tol if newton_tol is None else newton_tol
    res = newton(system, system.from_profile(guess), prob.p, 0.0, 1.0, prob.p,
                 tol=newton_tol, maxiter=NEWTON_MAXITER, contraction=None)
    history = res.history
    tn = system.output_nodes
    stats = dict(backend="shooting", segments=system.n, newton_iterations=len(history),
                 newton_history=history, nodes=int(tn.size) * prob.P,
                 max_abs_residual=history[-1][0] if history and
                 isinstance(history[-1][0], float) else float("nan"))
    if not res.ok:
        return False, f"Newton did not converge: (|residual|, |step|) = {history}", None, \
            None, None, stats
    dense_t = system.dense(res.U, prob.p)
    return True, "converged", tn, dense_t(tn), dense_t, stats
