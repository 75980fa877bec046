"""Axisymmetric equilibria: the multi-point BVP of a scene, its back-ends, and the result.

The meridian s in [eps, theta] is cut at the scene's interfaces into pieces [a_i, b_i]; each
piece is mapped to t in [0, 1] and the pieces' states are stacked, so that continuity of
y = (r, z, theta, m, f_r, f_z) at every interface is an ordinary boundary condition (exact
interfaces, no smoothing). Boundary conditions (DESIGN §4):

* pole, at s = eps (the pole is a regular singular point; the regular solution has
  lam1 = lam2 + O(s^2), k1 = k2 + O(s^2), z = z(0) - r theta / 2 + O(s^4)): lam1 = lam2,
  k1 = k2, and z(0) = 0 (apex held) or f_z = 0 (apex free); the O(eps^2) relative error of these
  conditions gives an O(eps^4) error in the solution (tested);
* edge: m = f_r = f_z = 0 (free) or r, z, theta at the reference sphere's values (clamped).

The reference mid-surface is r = sin s, z = cos s - 1, theta = s (apex at the origin).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.integrate import solve_bvp

from .axisym import AxisymmetricSystem, ConvergenceError
from .scene import Scene

__all__ = ["Equilibrium", "solve", "BACKENDS", "ConvergenceError", "reference_state"]

BACKENDS = ("collocation", "shooting", "spectral")


def reference_state(s):
    """The undeformed cap: (r, z, theta, m, f_r, f_z) = (sin s, cos s - 1, s, 0, 0, 0)."""
    s = np.asarray(s, dtype=float)
    z0 = np.zeros_like(s)
    return np.stack([np.sin(s), np.cos(s) - 1.0, s, z0, z0, z0])


@dataclass(frozen=True)
class Equilibrium:
    """An axisymmetric equilibrium (lengths in R0, energies per mu* h0 R0^2).

    Attributes:
        s: mesh nodes (meridional angle of the reference sphere, from the pole offset eps).
        r, z, theta: current meridian (z relative to the apex) and tangent angle.
        lam1, lam2: stretches relative to the target metric; k1, k2: principal curvatures (1/R0).
        eps11, eps22: elastic mid-surface strains (a_aa - abar_aa) / (2 abar_aa) = (lam_a^2 - 1)/2.
        M: meridional moment dL/dtheta'; F_r, F_z: multipliers of r' and z' (forces), all per
            mu* h0 R0 per radian of azimuth.
        energy, stretching_energy, bending_energy: E / (mu* h0 R0^2) = 2 pi int W dA_target
            split into int w_s and h^2/12 int w_b.
        w: vertical displacement of the edge relative to the apex, in R0 (the everted shape
            of a free cap has w = 2 (1 - cos theta)).
        error_estimate: max |change| of (r, z, theta) and of w when re-solved at 1/10 of the
            tolerance (``nan`` when not requested).
        stats: solver statistics (back-end, nodes, iterations, residual, wall time).
        success, message: convergence flag and message.
    """

    scene: Scene = field(repr=False)
    p: float
    s: np.ndarray = field(repr=False)
    r: np.ndarray = field(repr=False)
    z: np.ndarray = field(repr=False)
    theta: np.ndarray = field(repr=False)
    lam1: np.ndarray = field(repr=False)
    lam2: np.ndarray = field(repr=False)
    k1: np.ndarray = field(repr=False)
    k2: np.ndarray = field(repr=False)
    eps11: np.ndarray = field(repr=False)
    eps22: np.ndarray = field(repr=False)
    M: np.ndarray = field(repr=False)
    F_r: np.ndarray = field(repr=False)
    F_z: np.ndarray = field(repr=False)
    energy: float
    stretching_energy: float
    bending_energy: float
    w: float
    error_estimate: float
    stats: dict = field(repr=False)
    success: bool
    message: str
    _dense: Any = field(repr=False, compare=False)

    def __call__(self, s):
        """Dense (r, z, theta, m, f_r, f_z) at s (shape (6, len(s)); m, f scaled by 12/h^2)."""
        return self._dense(np.asarray(s, dtype=float))


# --- the stacked multi-point problem ---------------------------------------------------------
class _Problem:
    def __init__(self, scene: Scene, p: float, eps: float):
        self.scene, self.p, self.eps = scene, float(p), eps
        self.system = AxisymmetricSystem(scene, p)
        self.a = np.array((eps,) + scene.breaks)
        self.b = np.array(scene.breaks + (scene.theta,))
        self.P = scene.pieces

    def s_of(self, i, t):
        return self.a[i] + (self.b[i] - self.a[i]) * t

    def fun(self, t, Y, p=None):
        out = np.empty_like(Y)
        for i in range(self.P):
            out[6 * i:6 * i + 6] = (self.b[i] - self.a[i]) * self.system.rhs(
                i, self.s_of(i, t), Y[6 * i:6 * i + 6], p)
        return out

    def fun_jac(self, t, Y, p=None):
        n = Y.shape[1]
        J = np.zeros((6 * self.P, 6 * self.P, n))
        for i in range(self.P):
            _, Ji = self.system.rhs_and_jac(i, self.s_of(i, t), Y[6 * i:6 * i + 6], p)
            J[6 * i:6 * i + 6, 6 * i:6 * i + 6] = (self.b[i] - self.a[i]) * Ji
        return J

    def pole_residual(self, y0, p=None):
        X, _ = self.system.state(0, np.array([self.eps]), y0[:, None], p)
        lam1, lam2, k1, k2 = X[:, 0]
        third = (y0[1] + y0[0] * y0[2] / 2) if self.scene.apex == "held" else y0[5]
        return np.array([lam1 - lam2, k1 - k2, third])

    def edge_residual(self, y1):
        T = self.scene.theta
        if self.scene.edge == "free":
            return np.array([y1[3], y1[4], y1[5]])
        return np.array([y1[0] - math.sin(T), y1[1] - (math.cos(T) - 1.0), y1[2] - T])

    def bc(self, Ya, Yb, p=None):
        res = [self.pole_residual(Ya[:6], p)]
        for i in range(self.P - 1):
            res.append(Yb[6 * i:6 * i + 6] - Ya[6 * i + 6:6 * i + 12])
        res.append(self.edge_residual(Yb[6 * (self.P - 1):]))
        return np.concatenate(res)

    def monitor(self, Ya, Yb):
        """The branch's boundary functional, in units of the cap's rise H = 1 - cos theta:
        the edge displacement w relative to the apex (free edge), or the apex displacement
        relative to the edge (clamped edge)."""
        T = self.scene.theta
        z_apex = Ya[1] + Ya[0] * Ya[2] / 2
        rel = Yb[6 * (self.P - 1) + 1] - z_apex - (math.cos(T) - 1.0)
        return rel / (1.0 - math.cos(T))

    def monitor_gradient(self, ya, yb):
        """d monitor / d y at the pole (ya, first piece) and at the edge (yb, last piece)."""
        H = 1.0 - math.cos(self.scene.theta)
        ga, gb = np.zeros(6), np.zeros(6)
        ga[1], ga[0], ga[2] = -1.0 / H, -ya[2] / 2 / H, -ya[0] / 2 / H
        gb[1] = 1.0 / H
        return ga, gb

    def stack(self, t, profile):
        """Stacked Y(t) from a function profile(s) -> (6, n)."""
        return np.concatenate([profile(self.s_of(i, t)) for i in range(self.P)])

    def unstack(self, t, Y):
        s = np.concatenate([self.s_of(i, t) if i == 0 else self.s_of(i, t)[1:]
                            for i in range(self.P)])
        y = np.concatenate([Y[6 * i:6 * i + 6] if i == 0 else Y[6 * i:6 * i + 6, 1:]
                            for i in range(self.P)], axis=1)
        piece = np.concatenate([np.full(len(t), i) if i == 0 else np.full(len(t) - 1, i)
                                for i in range(self.P)])
        return s, y, piece


def _collocation(prob: _Problem, guess, tol, max_nodes, nodes):
    t = np.linspace(0.0, 1.0, nodes)
    Y0 = prob.stack(t, guess)
    res = solve_bvp(prob.fun, prob.bc, t, Y0, fun_jac=prob.fun_jac, tol=tol,
                    max_nodes=max_nodes, bc_tol=tol)
    stats = dict(backend="collocation", status=int(res.status), nodes=int(res.x.size),
                 niter=int(res.niter), max_rms_residual=float(np.max(res.rms_residuals)))
    sol = res.sol

    def dense(ti):
        return sol(ti)

    return res.success, res.message, res.x, res.y, dense, stats


def _spectral(prob: _Problem, guess, tol, nodes):
    from .discrete import newton
    from .spectral import SpectralSystem

    system = SpectralSystem(prob.scene, nodes, prob.eps)
    res = newton(system, system.from_profile(guess), prob.p, 0.0, 1.0, prob.p,
                 tol=min(tol, 1e-10), maxiter=40, contraction=None)
    Y = res.U.reshape(prob.P * 6, nodes + 1)
    stats = dict(backend="spectral", nodes=nodes, newton_iterations=res.iterations,
                 newton_history=res.history, chebyshev_tail=system.tail(res.U))
    msg = "converged" if res.ok else f"Newton did not converge: {res.history}"
    return res.ok, msg, system.t, Y, system.dense(res.U), stats


def _dense_in_s(prob: _Problem, dense_t):
    def ev(s):
        s = np.atleast_1d(s)
        out = np.empty((6, s.size))
        for i in range(prob.P):
            sel = (s >= prob.a[i]) & (s <= prob.b[i]) if i == prob.P - 1 else \
                (s >= (prob.a[i] if i else -np.inf)) & (s < prob.b[i])
            if np.any(sel):
                t = (s[sel] - prob.a[i]) / (prob.b[i] - prob.a[i])
                out[:, sel] = dense_t(t)[6 * i:6 * i + 6]
        return out

    return ev


def _energy(prob: _Problem, dense_t, p=None):
    """2 pi int W g1 g2 sin s ds by 4-point Gauss on 64 panels per piece, plus the pole cap."""
    from .energy import energy_terms

    sc = prob.scene
    xg, wg = np.polynomial.legendre.leggauss(4)
    Es = Eb = 0.0
    for i in range(prob.P):
        edges = np.linspace(0.0, 1.0, 65)
        t = ((edges[:-1, None] + edges[1:, None]) / 2 + (edges[1:, None] - edges[:-1, None]) / 2
             * xg[None, :]).ravel()
        wt = ((edges[1:, None] - edges[:-1, None]) / 2 * wg[None, :]).ravel()
        s = prob.s_of(i, t)
        y = dense_t(t)[6 * i:6 * i + 6]
        X, (g1, g2, kb1, kb2) = prob.system.state(i, s, y, p)
        ws, wb, _, _ = energy_terms(*X, kb1, kb2, lam=sc.lam, nu=sc.nu, model=sc.model,
                                    material=sc.material, rhob1=sc.rhob1)
        dA = g1 * g2 * np.sin(s) * (prob.b[i] - prob.a[i]) * wt
        Es += np.sum(ws * dA)
        Eb += sc.h**2 / 12 * np.sum(wb * dA)
        if i == 0:  # the polar cap [0, eps]: W is constant there to O(eps^2)
            cap = g1[0] * g2[0] * (1 - math.cos(prob.eps))
            Es += ws[0] * cap
            Eb += sc.h**2 / 12 * wb[0] * cap
    return 2 * math.pi * Es, 2 * math.pi * Eb


def _build(prob, ok, msg, tnodes, Y, dense_t, stats, err):
    sc = prob.scene
    s, y, piece = prob.unstack(tnodes, Y)
    X = np.empty((4, s.size))
    for i in range(prob.P):
        sel = piece == i
        X[:, sel], _ = prob.system.state(i, s[sel], y[:, sel])
    z_apex = y[1, 0] + y[0, 0] * y[2, 0] / 2
    w = (y[1, -1] - z_apex) - (math.cos(sc.theta) - 1.0)
    Es, Eb = _energy(prob, dense_t)
    scale = sc.h**2 / 12
    return Equilibrium(
        scene=sc, p=prob.p, s=s, r=y[0], z=y[1] - z_apex, theta=y[2], lam1=X[0], lam2=X[1],
        k1=X[2], k2=X[3], eps11=(X[0] ** 2 - 1) / 2, eps22=(X[1] ** 2 - 1) / 2,
        M=scale * y[3], F_r=scale * y[4], F_z=scale * y[5], energy=Es + Eb,
        stretching_energy=Es, bending_energy=Eb, w=float(w), error_estimate=err,
        stats=stats, success=bool(ok), message=msg, _dense=_dense_in_s(prob, dense_t))


def solve(scene: Scene, p: float, *, backend: str = "collocation", guess=None,
          tol: float = 1e-8, eps: float | None = None, nodes: int | None = None,
          max_nodes: int = 20000, estimate_error: bool = True, throw: bool = True,
          shooting_segments: int = 16, shooting_steps: int | None = None) -> Equilibrium:
    """Solve the axisymmetric equilibrium of ``scene`` at parameter value ``p``.

    Arguments:
        scene: the problem (geometry, stimulus, material, boundary conditions).
        p: value of ``scene.parameter`` (e.g. kappa, in 1/R0).
        backend: ``"collocation"`` (scipy.integrate.solve_bvp, 4th order, analytic Jacobian),
            ``"shooting"`` (multiple shooting with diffrax and Newton) or ``"spectral"``
            (Chebyshev collocation of degree ``nodes`` per piece, Newton; geometric
            convergence, :mod:`shellbvp.spectral`).
        guess: an :class:`Equilibrium` (e.g. the previous continuation step) or a callable
            s -> (6, n); default the undeformed cap.
        tol: solver tolerance (collocation: relative residual; shooting: ODE rtol and Newton).
        eps: pole offset (default 1e-4 theta).
        nodes: initial mesh size (collocation, default 41) or Chebyshev degree per piece
            (spectral, default :func:`shellbvp.branch.default_nodes`).
        estimate_error: re-solve at tol/10 (spectral: with degree + 8) from the
            solution and report the change.
        throw: raise :class:`ConvergenceError` on failure (else return ``success=False``).
        shooting_segments: number of shooting segments (at least one per piece).
        shooting_steps: fixed Tsit5 steps per segment (default: adaptive at rtol = tol).

    Raises:
        ValueError: bad arguments. ConvergenceError: no convergence (with diagnostics).
    """
    if backend not in BACKENDS:
        raise ValueError(f"backend must be one of {BACKENDS}, got {backend!r}")
    if not isinstance(scene, Scene):
        raise ValueError(f"scene must be a shellbvp.Scene, got {type(scene).__name__}")
    if not np.isfinite(p) or np.ndim(p) != 0:
        raise ValueError(f"{scene.parameter} must be a finite scalar, got {p!r}")
    if not (0 < tol < 1):
        raise ValueError(f"tol must lie in (0, 1), got {tol!r}")
    eps = 1e-4 * scene.theta if eps is None else float(eps)
    if not (0 < eps < (scene.breaks[0] if scene.breaks else scene.theta) / 10):
        raise ValueError(f"eps must lie in (0, first piece length / 10), got {eps!r}")
    if guess is not None and not callable(guess):
        raise ValueError(f"guess must be an Equilibrium or a callable s -> (6, n), got "
                         f"{type(guess).__name__}")
    prof = reference_state if guess is None else guess  # an Equilibrium is callable in s
    if nodes is None:
        from .branch import default_nodes

        nodes = default_nodes(scene) if backend == "spectral" else 41
    if not (isinstance(nodes, (int, np.integer)) and nodes >= 8):
        raise ValueError(f"nodes must be an integer >= 8, got {nodes!r}")
    t0 = time.perf_counter()
    prob = _Problem(scene, p, eps)
    try:
        if backend == "collocation":
            ok, msg, tn, Y, dense, stats = _collocation(prob, prof, tol, max_nodes, nodes)
        elif backend == "spectral":
            ok, msg, tn, Y, dense, stats = _spectral(prob, prof, tol, nodes)
        else:
            from .shooting import shoot

            ok, msg, tn, Y, dense, stats = shoot(prob, prof, tol, shooting_segments,
                                                 steps=shooting_steps)
    except ConvergenceError as exc:
        ok, msg = False, str(exc)
        if throw:
            raise
        tn, Y, dense, stats = None, None, None, {"backend": backend}
    stats["rhs_calls"] = prob.system.calls
    stats["wall_time"] = time.perf_counter() - t0
    if not ok:
        if throw:
            raise ConvergenceError(f"{backend} solve failed at {scene.parameter} = {p:g}: {msg} "
                                   f"(stats: {stats}); try a closer guess or a smaller step")
        return _failed(scene, p, msg, stats)
    eq = _build(prob, ok, msg, tn, Y, dense, stats, float("nan"))
    if estimate_error:
        finer = nodes + 8 if backend == "spectral" else max(nodes, eq.s.size)
        fine = solve(scene, p, backend=backend, guess=eq, tol=tol / 10, eps=eps,
                     nodes=finer, max_nodes=max_nodes, estimate_error=False,
                     throw=throw, shooting_segments=shooting_segments,
                     shooting_steps=shooting_steps)
        diff = np.abs(fine(eq.s)[:3] - eq(eq.s)[:3])
        err = max(float(np.max(diff)), abs(fine.w - eq.w))
        eq = _replace(eq, error_estimate=err)
    return eq


def _replace(eq, **kw):
    from dataclasses import replace

    return replace(eq, **kw)


def _failed(scene, p, msg, stats):
    nan = np.array([])
    return Equilibrium(scene=scene, p=float(p), s=nan, r=nan, z=nan, theta=nan, lam1=nan,
                       lam2=nan, k1=nan, k2=nan, eps11=nan, eps22=nan, M=nan, F_r=nan, F_z=nan,
                       energy=float("nan"), stretching_energy=float("nan"),
                       bending_energy=float("nan"), w=float("nan"), error_estimate=float("nan"),
                       stats=stats, success=False, message=msg, _dense=None)
