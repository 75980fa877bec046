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
        return (flow(y0, piece, s0, s1, p, lam, h, tol),
                jax.jacfwd(flow)(y0, piece, s0, s1, p, lam, h, tol))

    def pole(y0, eps, p, lam, h, held):
        q, X, ok = pf["algebraic"](y0, eps, F_of(0, eps, p), lam, h)
        third = jnp.where(held, y0[1] + y0[0] * y0[2] / 2, y0[5])
        return jnp.stack([X[0] - X[1], X[2] - X[3], third])

    def pole_and_jac(y0, eps, p, lam, h, held):
        return pole(y0, eps, p, lam, h, held), jax.jacfwd(pole)(y0, eps, p, lam, h, held)

    def dense(piece, y0, s0, s1, p, lam, h, tol):
        ts = s0 + (s1 - s0) * jnp.linspace(0.0, 1.0, SAVE_PER_SEGMENT)
        ys = solve_segment(piece, y0, s0, s1, p, lam, h, tol, diffrax.SaveAt(ts=ts)).ys
        fs = jax.vmap(lambda s, y: pf["rhs"](y, s, F_of(piece, s, p), lam, h)[0])(ts, ys)
        return ts, ys, fs

    seg_axes = (0, 0, 0, 0, None, None, None, None)
    return (jax.jit(jax.vmap(flow_and_sens, in_axes=seg_axes)), jax.jit(pole_and_jac),
            jax.jit(jax.vmap(dense, in_axes=seg_axes)))


def shoot(prob, guess, tol, n_segments, steps=None, newton_tol=None):
    """Solve the stacked problem ``prob`` by multiple shooting; same returns as collocation."""
    sc = prob.scene
    per_piece = max(1, int(math.ceil(n_segments / prob.P)))
    edges = [np.linspace(prob.a[i], prob.b[i], per_piece + 1) for i in range(prob.P)]
    s0 = np.concatenate([e[:-1] for e in edges])
    s1 = np.concatenate([e[1:] for e in edges])
    piece = np.repeat(np.arange(prob.P), per_piece)
    N = s0.size
    flow_and_sens, pole_and_jac, dense = _compiled(
        sc.model, sc.material, float(sc.rhob1), bool(sc.metric), sc.fields, prob.P,
        steps is None)
    ode_tol = tol if steps is None else float(steps)
    U = np.asarray(guess(s0), dtype=float).T.copy()  # (N, 6)
    newton_tol = 10 * tol if newton_tol is None else newton_tol
    T = sc.theta
    history, ok = [], False
    args = (prob.p, sc.material_parameter, sc.h)
    for it in range(NEWTON_MAXITER):
        ends, sens = (np.asarray(a) for a in flow_and_sens(piece, U, s0, s1, *args, ode_tol))
        rp, Jp = (np.asarray(a) for a in pole_and_jac(U[0], prob.eps, *args, sc.apex == "held"))
        n = 6 * N
        r = np.empty(n)
        J = np.zeros((n, n))
        r[:3], J[:3, :6] = rp, Jp
        for j in range(N - 1):  # continuity: flow_j(U_j) - U_{j+1}
            rows = slice(3 + 6 * j, 9 + 6 * j)
            r[rows] = ends[j] - U[j + 1]
            J[rows, 6 * j:6 * j + 6] = sens[j]
            J[rows, 6 * j + 6:6 * j + 12] = -np.eye(6)
        e, S = ends[-1], sens[-1]
        if sc.edge == "free":
            r[-3:], J[-3:, -6:] = e[3:6], S[3:6]
        else:
            r[-3:] = [e[0] - math.sin(T), e[1] - (math.cos(T) - 1.0), e[2] - T]
            J[-3:, -6:] = S[0:3]
        if not (np.all(np.isfinite(r)) and np.all(np.isfinite(J))):
            raise ConvergenceError(
                f"shooting: non-finite residual at Newton iteration {it} "
                f"({sc.parameter} = {prob.p:g}); the ODE solver or the inner Newton failed "
                f"on a segment - use more segments or a closer guess")
        dU = np.linalg.solve(J, r).reshape(N, 6)
        U = U - dU
        history.append((float(np.max(np.abs(r))), float(np.max(np.abs(dU)))))
        # Quadratic convergence: after a step of size d the error is O(d^2).
        if history[-1][1] <= newton_tol * (1 + np.max(np.abs(U))) and it >= 1:
            ok = True
            break
        if it >= 3 and history[-1][0] > history[-3][0]:
            break
    msg = "converged" if ok else f"Newton did not converge: (|residual|, |step|) = {history}"
    ts, ys, fs = (np.asarray(a) for a in dense(piece, U, s0, s1, *args, ode_tol))
    splines = []
    for i in range(prob.P):
        sel = np.flatnonzero(piece == i)
        cat = lambda a: np.concatenate([a[j] if k == 0 else a[j][1:]  # noqa: E731
                                        for k, j in enumerate(sel)])
        splines.append(CubicHermiteSpline(cat(ts), cat(ys), cat(fs), axis=0))

    def dense_t(t):
        t = np.asarray(t, dtype=float)
        return np.concatenate([splines[i](prob.s_of(i, t)).T for i in range(prob.P)])

    tn = np.linspace(0.0, 1.0, per_piece * (SAVE_PER_SEGMENT - 1) + 1)  # the saved points
    stats = dict(backend="shooting", segments=N, newton_iterations=len(history),
                 newton_history=history, nodes=int(tn.size) * prob.P,
                 max_abs_residual=history[-1][0] if history else float("nan"))
    return ok, msg, tn, dense_t(tn), dense_t, stats
