"""The axisymmetric boundary-value problem of a scene, written once for every method.

A :class:`ShellBVP` turns a :class:`shellbvp.Scene` into a multi-point first-order BVP
for y = (r, z, theta, m, f_r, f_z) (m, f = 12/h^2 times the moment and forces, so that
bending and membrane unknowns have the same size):

* **pieces**: the meridian s in [eps, theta] is cut at the scene's interfaces into pieces
  [a_i, b_i], each mapped to the piece coordinate t in [0, 1] (dy/dt = (b_i - a_i) f). The
  methods keep one state per piece and impose continuity of all six components at every
  interface, so a jump of the stimulus is exact (the meridional stretch may jump there);
* **pole**, at s = eps = ``POLE_OFFSET`` theta: the pole is a regular singular point whose
  regular solution has g1 lam1 = g2 lam2 + O(s^2) (equal actual stretches: r ~ g1 lam1 s and
  lam2 = r / (g2 sin s); lam1 = lam2 only without a metric stimulus), k1 = k2 + O(s^2) and
  z(0) = z(eps) + r theta / 2 + O(eps^4); the conditions are g1 lam1 = g2 lam2, k1 = k2 and
  z(0) = 0 (apex ``held``) or f_z = 0 (apex ``free``). Their O(eps^2) relative error gives
  an O(eps^4) error in the solution. Where the target curvature is anisotropic at the apex
  (kb1 != kb2) the solution is not regular: k1 - k2 tends to a nonzero constant and both
  curvatures grow like log s (as for a plate with anisotropic natural curvature: the moment
  balance (s M1)' = M2 near s = 0 with M linear in k forces k1 - k2 = (1 - nu)(k*1 - k*2)/2,
  nu = W_k1k2 / W_k1k1, k* where the moments vanish). There the condition is k1 - k2 = A,
  which excludes the 1/s mode as k1 = k2 does at a regular apex: the shape and w converge,
  the apex curvatures do not (they diverge like log s). A target metric anisotropic at the
  apex (g1 != g2, a cone) would need the same treatment of the stretches; it keeps
  g1 lam1 = g2 lam2 at eps, which is exact only for a regular membrane state;
* **edge**, at s = theta: m = f_r = f_z = 0 (``free``) or r, z, theta at the reference
  sphere's values (``clamped``);
* **load**: a scene's uniform pressure (``Scene.pressure``) enters the compiled equations as a
  fifth field beside (g1, g2, kb1, kb2), through its potential P V
  (:mod:`shellbvp.euler_lagrange`);
* **observable** (the branch monitor), in units of the rise H = 1 - cos theta: for a free
  edge the vertical displacement of the edge relative to the apex, for a clamped edge that
  of the apex relative to the edge (positive along +z, the cap's axis at the apex).

The reference mid-surface is r = sin s, z = cos s - 1, theta = s (apex at the origin). All
of the above is JAX code compiled once per (model, material, fields, pieces, conditions); the
methods in :mod:`shellbvp.methods` only discretise it. The nodal right-hand side is
evaluated in chunks padded to one of a few sizes (``CHUNKS``), so that a change of
resolution reuses a compiled program instead of compiling a new one.
"""

from __future__ import annotations

import math
from functools import lru_cache, partial
from typing import Callable, NamedTuple

import numpy as np

from .compiled import point_functions, solve_2x2
from .packed import Packed
from .errors import ConvergenceError
from .jaxsetup import jax
from .scene import Scene, call_fields

import jax.numpy as jnp  # noqa: E402

__all__ = ["ShellBVP", "Nodal", "Collocated", "reference_state", "POLE_OFFSET", "CHUNKS"]

#: eps / theta. The pole conditions are exact to O(eps^2), so the solution is good to
#: O(eps^4) = 1e-16 relative: below every tolerance the solvers reach, while eps stays far
#: enough from s = 0 that lam2 = r / (g2 sin s) is evaluated without cancellation.
POLE_OFFSET = 1e-4
#: nodes are evaluated in chunks padded to one of these sizes (larger sets in chunks of the
#: last), so that a change of resolution mostly reuses a compiled program (each costs
#: seconds of compilation for a relaxed model): the Chebyshev degrees of a kappa_s at
#: tol 1e-6 ... 1e-10 on the default cap (N = 24 ... 36, 25 ... 37 nodes) share the program
#: of 40 (padding 25 nodes to 40 costs ~60 us per evaluation, a second program ~8 s once);
#: geometric above, so that solve_bvp's ever-changing meshes reuse ~a dozen programs.
#: (Fixed chunks of 16 or 24 nodes, dispatched together so that every degree runs on the
#: same programs, cost 30-50 % more per kappa_s: each compiled call has a fixed cost.)
CHUNKS = (8, 16, 24, 40, 56, 72, 96, 128, 192, 256, 384, 512)
#: nodes per compiled call of the fold system's second derivatives (:meth:`ShellBVP.fold_terms`)
FOLD_CHUNK = 24
#: nodes per compiled call of the state along the meridian (:meth:`ShellBVP.state`), at
#: every node count: its scan is sequential, so chunking costs only a dispatch per chunk,
#: and one program (~5-8 s to compile for a relaxed energy) serves the solvers' nodes and
#: the energy quadrature's (which needed a second one at its own size)
STATE_CHUNK = 72
#: largest relative distance between a state and the states of a warm start that is carried
#: to another discretisation with it (:meth:`ShellBVP.carried_hint`)
HINT_CARRY = 1e-3
#: steps in which the inner root is carried across an interface as the fields jump
#: (post-processing only; the methods carry it from their previous iterate)
INTERFACE_STEPS = 16
#: round-off scatter of a fold parameter, in eps (1 + |p|) / h (:meth:`ShellBVP.round_off`)
ROUND_OFF_PER_H = 5.0
#: Ciarlet-Geymonat lam above which that scatter grows like lam (the forces of the lam term
#: carry round-off ~ lam eps): scatter / (ROUND_OFF_PER_H eps (1 + |p|) / h) of folds located
#: at degrees 40-68 (relaxed, Theta = pi/6, h = 0.01) was 0.6-0.7 at lam = 1-100, 5.5 at
#: 1e3 and 52 at 1e4 (plane strain, which snaps up to lam = 100: 0.4-1.0)
ROUND_OFF_LAM = 100.0
#: Gauss-Legendre panels and points per panel of the energy quadrature (per piece)
ENERGY_PANELS, ENERGY_GAUSS = 64, 4


def reference_state(s):
    """The undeformed cap: (r, z, theta, m, f_r, f_z) = (sin s, cos s - 1, s, 0, 0, 0)."""
    s = np.asarray(s, dtype=float)
    z0 = np.zeros_like(s)
    return np.stack([np.sin(s), np.cos(s) - 1.0, s, z0, z0, z0])


class Collocated(NamedTuple):
    """What a collocation method needs at one iterate: the :class:`Nodal` right-hand side,
    the boundary residual with its Jacobians (r, d/dya, d/dyb, d/dp) and the monitor with
    its gradients (m, dm/dya, dm/dyb)."""

    nodal: "Nodal"
    boundary: tuple
    monitor: tuple


class Nodal(NamedTuple):
    """The right-hand side at nodes of every piece: f (P, 6, m), df/dy (P, 6, 6, m),
    df/dp (P, 6, m) and ``hint``, an opaque warm start for the next evaluation."""

    f: np.ndarray
    J: np.ndarray
    fp: np.ndarray
    hint: object = None


class _Hint(NamedTuple):
    """Warm start of the inner Newton: the nodal states y (nodes, 6) and parameter p of an
    evaluation, its roots q (nodes, 2) and their derivatives dq = [dq/dy, dq/dp] (nodes, 2, 7)."""

    y: np.ndarray
    p: float
    q: np.ndarray
    dq: np.ndarray


def _flat_nodes(Y):
    """Y (P, 6, m) -> (P m, 6), nodes piece-major."""
    return np.asarray(Y, dtype=float).transpose(0, 2, 1).reshape(-1, 6)


def _carried_roots(hint, y, p):
    """The roots of ``hint`` carried to the nodal states y (nodes, 6) and parameter p along
    their implicit derivative dq = [dq/dy, dq/dp]: O(|change|^2) from the roots there."""
    dq = hint.dq
    return hint.q + (dq[:, :, :6] @ (y - hint.y)[:, :, None])[:, :, 0] \
        + dq[:, :, 6] * (p - hint.p)


def _chunk(n: int) -> int:
    return next((c for c in CHUNKS if c >= n), CHUNKS[-1])


@lru_cache(maxsize=None)
def _package_source() -> str:
    """A hash of the package's source (every .py file): part of every disk key of code."""
    from pathlib import Path

    from .cache import files_digest

    return files_digest(sorted(Path(__file__).parent.rglob("*.py")))


def _disk_key(functions, *parts) -> str | None:
    """A disk key for compiled kernels of the scene's ``functions`` (fields, pressure) and
    ``parts``, or None when one of them is not a module-level function of this package (a
    user's function, a closure: their code is not covered by the package's source hash, so
    their programs stay in memory). Numbers the functions depend on are the scene's field
    parameters, arguments of the programs, not part of their code."""
    import sys

    from .cache import files_digest

    names = []
    for fn in functions:
        if fn is None:
            names.append(None)
            continue
        module = getattr(fn, "__module__", "") or ""
        qualname = getattr(fn, "__qualname__", "") or ""
        if not module.startswith("shellbvp") or "<" in qualname or \
                getattr(sys.modules.get(module), qualname, None) is not fn:
            return None
        # the scenes (shellbvp.problems) live outside the package folder: hash their module
        names.append((module, qualname, files_digest([sys.modules[module].__file__])))
    return repr((_package_source(), tuple(names), parts))


class Kernels(NamedTuple):
    """The compiled programs of a scene (:func:`_kernels`), each a :class:`Packed` (kept
    on disk) except the traceable ``vector_field``."""

    #: rhs, boundary conditions and monitor at one iterate, in one dispatch
    collocate: Packed
    #: the rhs and its Jacobians at nodes
    nodal: Packed
    #: the principal state and W's jet along a meridian (inner roots followed node to node)
    state: Packed
    #: boundary rows (pole series and edge) with their Jacobians
    boundary: Packed
    #: the observable and its gradient
    observable: Packed
    #: derivatives of f and of the boundary rows in theta, the material and h ...
    sensitivity: Packed
    boundary_sensitivity: Packed
    #: ... and in theta alone (compiles ~5x faster)
    geometry_sensitivity: Packed
    boundary_geometry_sensitivity: Packed
    #: the fold system's second derivatives at nodes, and the observable's
    fold_nodal: Packed
    observable_curvature: Packed
    #: (piece, s, y, p, material parameter, h, c) -> f (6,), traceable (shooting)
    vector_field: Callable


@lru_cache(maxsize=32)
def _kernels(model, material, rhob1, metric, fields, P, apex, edge, log_apex=False,
             pressure=None, n_field_parameters=0):
    """The scene's compiled functions (see :class:`ShellBVP`). Every function of the
    fields takes the scene's field parameters c (an array of ``n_field_parameters``) as an
    argument after h: scenes that differ in c only share these programs."""
    pf = point_functions(model, material, rhob1, metric)
    base = _disk_key((fields, pressure), model, material, rhob1, metric, P, apex, edge,
                     log_apex, n_field_parameters)

    def packed(fn, name):
        return Packed(fn, None if base is None else f"{name}:{base}")

    def field_piece(i):
        # the stimulus fields (g1, g2, kb1, kb2) and the pressure: the five "fields" of the
        # compiled equations (the pressure is uniform; a derivative in p reaches it too)
        def F(s, p, c):
            load = 0.0 if pressure is None else pressure(p)
            return jnp.stack([jnp.asarray(v, dtype=jnp.float64) + 0.0 * s
                              for v in (*call_fields(fields, i, s, p, c), load)])
        return F

    branches = [field_piece(i) for i in range(P)]

    def fields_at(piece, s, p, c):
        return jax.lax.switch(piece, branches, s, p, c) if P > 1 else branches[0](s, p, c)

    def nodal_one(piece, s, y, p, lam, h, c, q_init):
        F, dF = jax.jvp(lambda p_: fields_at(piece, s, p_, c), (p,), (jnp.ones_like(p),))
        f, J, fp, ok, q, dq = pf.rhs_jac(y, s, F, dF, lam, h, q_init)
        return F, f, J, fp, ok, q, dq

    def state_along(piece, s, y, p, lam, h, c, q_start, q_hints):
        # Each node from the previous node's (lam1, k1) (nodes in order along the meridian:
        # the state is continuous in s within a piece). Across an interface y is continuous
        # but (lam1, k1) jump with the fields: there the root is followed from the previous
        # node's while the fields move from their old to their new values in
        # INTERFACE_STEPS steps. Where these fail (no elliptic root), from the pole-like guess.
        def across(q, y_, s_, F_prev, F):
            def sub(i, q_):
                t = (i + 1.0) / INTERFACE_STEPS
                q_new, _, ok = pf.algebraic(y_, s_, (1 - t) * F_prev + t * F, lam, h, q_)
                return jnp.where(ok, q_new, jnp.nan)
            return pf.algebraic(y_, s_, F, lam, h,
                                   jax.lax.fori_loop(0, INTERFACE_STEPS, sub, q))

        def step(carry, args):
            q, F_prev = carry
            piece_, s_, y_, q_hint = args
            F = fields_at(piece_, s_, p, c)
            # a given hint (the root a solver converged to there) comes first: near a loss
            # of ellipticity the previous node's root may lead to no elliptic one
            hinted = jnp.all(jnp.isfinite(q_hint))
            warm = pf.algebraic(y_, s_, F, lam, h, jnp.where(hinted, q_hint, q))
            carried = jax.lax.cond(warm[2] | ~hinted, lambda: warm,
                                   lambda: pf.algebraic(y_, s_, F, lam, h, q))
            second = jax.lax.cond(carried[2], lambda: carried,
                                  lambda: across(q, y_, s_, F_prev, F))
            q_new, X, ok = jax.lax.cond(second[2], lambda: second,
                                        lambda: pf.algebraic(y_, s_, F, lam, h))
            gw, Hw = pf.hessian(y_, q_new, s_, F, lam, h)
            return (jnp.where(ok, q_new, q), F), (X, F, ok, gw, Hw)

        F0 = fields_at(piece[0], s[0], p, c)
        (q_end, _), (X, F, ok, gw, Hw) = jax.lax.scan(step, (q_start, F0),
                                                      (piece, s, y, q_hints))
        return X, F, ok, gw, Hw, q_end

    def pole_rows(ya, q, eps, F0, lam, h, fns=pf):
        X = fns.X(ya, q, eps, F0, h)
        third = ya[1] + ya[0] * ya[2] / 2 if apex == "held" else ya[5]
        # regularity of the deformed surface at the apex: equal actual stretches
        # g1 lam1 = g2 lam2 (r ~ g1 lam1 s and lam2 = r / (g2 sin s)) and k1 = k2
        dk = jnp.zeros(())
        if log_apex:
            # anisotropic target curvature at the apex: the finite-energy local solution has
            # k1 - k2 -> A = (1 - nu) (k*1 - k*2) / 2 (curvatures ~ A log s), nu = W_k1k2 /
            # W_k1k1 and k* the curvatures that make the moments vanish (W is quadratic in
            # k); k1 - k2 = A at eps excludes the 1/s mode exactly as k1 = k2 does for a
            # regular apex, where A = 0
            g, H = fns.hessian(ya, q, eps, F0, lam, h)
            kstar = X[2:] - solve_2x2(H[2:, 2:], g[2:])
            dk = (1.0 - H[2, 3] / H[2, 2]) * (kstar[0] - kstar[1]) / 2.0
        return jnp.stack([F0[0] * X[0] - F0[1] * X[1], X[2] - X[3] - dk, third])

    def pole(ya, p, eps, lam, h, c, q_root, dq):
        F0 = fields_at(0, eps, p, c)
        # q(ya, p) with the value of the root and the derivative of implicit differentiation,
        # dq = [dq/dy, dq/dp] (2, 7): the pole rows then differentiate only kinematics
        q = (q_root + dq[:, :6] @ (ya - jax.lax.stop_gradient(ya))
             + dq[:, 6] * (p - jax.lax.stop_gradient(p)))
        start = pole_rows(ya, q, eps, F0, lam, h)
        return start, (start, F0)

    def edge_conditions(yb, theta):
        if edge == "free":
            return yb[3:6]
        return jnp.stack([yb[0] - jnp.sin(theta), yb[1] - (jnp.cos(theta) - 1.0),
                          yb[2] - theta])

    def boundary_jac(ya, yb, p, eps, theta, lam, h, c, pole_root=None):
        # the pole rows depend on (ya, p) only, the edge rows on yb only: differentiate each
        # in its own variables. The inner root at the pole and its implicit derivatives come
        # from the nodal function at s = eps (given when node 0 of the first piece is the
        # pole, as in collocation), so no derivative runs through the inner Newton loop.
        if pole_root is None:
            _, _, _, _, ok, q_root, dq = nodal_one(0, eps, ya, p, lam, h, c,
                                                   jnp.full(2, jnp.nan))
        else:
            ok, q_root, dq = pole_root
        (Ja, Jp), (start, F0) = jax.jacfwd(pole, argnums=(0, 1), has_aux=True)(
            ya, p, eps, lam, h, c, q_root, dq)
        Jb = jax.jacfwd(edge_conditions)(yb, theta)
        z = jnp.zeros((3, 6))
        return (jnp.concatenate([start, edge_conditions(yb, theta)]), jnp.vstack([Ja, z]),
                jnp.vstack([z, Jb]), jnp.concatenate([Jp, jnp.zeros(3)]), ok, F0)

    def observable(ya, yb, theta):
        H = 1.0 - jnp.cos(theta)
        z_apex = ya[1] + ya[0] * ya[2] / 2       # z(0) from the regular series at eps
        rel = yb[1] - z_apex - (jnp.cos(theta) - 1.0)
        return (rel if edge == "free" else -rel) / H

    def vector_field(piece, s, y, p, lam, h, c):
        # f with the inner root found on values only (no tangent runs through its Newton
        # loop) and differentiated implicitly (f_linear): the first derivatives a solver
        # takes of f (forward-mode sensitivities in shooting) are exact, at the cost of one
        # linear solve per direction instead of every inner iteration (2.7x less time per
        # shooting evaluation, 0.59 -> 0.22 s at rtol 1e-8; Jacobians equal to 2e-12)
        F = fields_at(piece, s, p, c)
        stop = jax.lax.stop_gradient
        q_root, _, _ = pf.root(stop(y), stop(s), stop(F), stop(lam), stop(h))
        return pf.f_linear(y, s, F, lam, h, q_root)

    ax = (0, 0, 0, None, None, None, None, 0)
    nodal = jax.vmap(nodal_one, in_axes=ax)

    def sensitivity_one(piece, s, y, p, lam, h, c, q_init, geometry_only=False):
        # f and its derivatives in (s, material parameter, h) at fixed y and p, the fields
        # included (they depend on s), by implicit differentiation of the inner root; with
        # geometry_only, in s alone (zeros for the others): a derivative of the relaxed
        # energy in lam and h costs ~20 s of compilation that a theta derivative does not need
        q_root, _, _ = pf.root(y, s, fields_at(piece, s, p, c), lam, h, q_init)

        def f(s_, lam_, h_):
            return pf.f_linear(y, s_, fields_at(piece, s_, p, c), lam_, h_, q_root)

        if geometry_only:
            value, ds = jax.jvp(lambda s_: f(s_, lam, h), (s,), (jnp.ones_like(s),))
            return value, jnp.stack([ds, jnp.zeros_like(ds), jnp.zeros_like(ds)], axis=-1)
        return f(s, lam, h), jnp.stack(jax.jacfwd(f, argnums=(0, 1, 2))(s, lam, h), axis=-1)

    def boundary_sensitivity(ya, yb, p, eps, theta, lam, h, c, geometry_only=False):
        # the boundary rows' derivatives in (eps, theta, material parameter, h) and the
        # monitor's in theta, at fixed ya, yb and p (geometry_only: zeros for lam, h)
        q_root, _, _ = pf.root(ya, eps, fields_at(0, eps, p, c), lam, h)

        def rows(eps_, theta_, lam_, h_):
            F0 = fields_at(0, eps_, p, c)
            q = pf.q_linear(ya, eps_, F0, lam_, h_, q_root)
            return jnp.concatenate([pole_rows(ya, q, eps_, F0, lam_, h_),
                                    edge_conditions(yb, theta_)])

        if geometry_only:
            d = jax.jacfwd(lambda e, t: rows(e, t, lam, h), argnums=(0, 1))(eps, theta)
            d = (*d, jnp.zeros_like(d[0]), jnp.zeros_like(d[0]))
        else:
            d = jax.jacfwd(rows, argnums=(0, 1, 2, 3))(eps, theta, lam, h)
        return jnp.stack(d, axis=-1), jax.grad(observable, argnums=2)(ya, yb, theta)

    def fold_node(piece, s, y, p, lam, h, c, q, dq, wn, wb, v, dp):
        # phi = wn . f + wb . (pole rows) at one node (wb = 0 but at the pole), along the
        # inner root q (derivative dq): the derivative of phi along (v, dp) and that of its
        # gradient in (y, p, s), exact (``curvature`` of :func:`point_functions`)
        def phi(fns, y_, q_, s_, F_):
            return jnp.stack([wn @ fns.f(y_, q_, s_, F_, lam, h),
                              wb @ pole_rows(y_, q_, s_, F_, lam, h, fns)])

        return pf.curvature(phi, (y, p, s), (v, dp, jnp.zeros_like(s)), lam, h, q, dq,
                               lambda s_, p_: fields_at(piece, s_, p_, c))

    def observable_curvature(ya, yb, theta, va, vb):
        # the gradient in (ya, yb, theta) of the observable's derivative along (va, vb)
        return jax.jvp(lambda a, b: jax.grad(observable, argnums=(0, 1, 2))(a, b, theta),
                       (ya, yb), (va, vb))[1]

    def collocate(piece, s, y, p, lam, h, c, q_init, ya, yb, eps, theta):
        # everything a collocation method needs at one iterate, in one dispatch; the first
        # node is the pole (s = eps, y = ya), whose inner root the pole rows reuse
        nod = nodal(piece, s, y, p, lam, h, c, q_init)
        return (nod, boundary_jac(ya, yb, p, eps, theta, lam, h, c,
                                  (nod[4][0], nod[5][0], nod[6][0])),
                jax.value_and_grad(observable, argnums=(0, 1))(ya, yb, theta))

    return Kernels(
        collocate=packed(collocate, "collocate"),
        nodal=packed(nodal, "nodal"),
        state=packed(state_along, "state"),
        boundary=packed(boundary_jac, "boundary"),
        observable=packed(jax.value_and_grad(observable, argnums=(0, 1)), "observable"),
        sensitivity=packed(jax.vmap(sensitivity_one, in_axes=ax), "sensitivity"),
        boundary_sensitivity=packed(boundary_sensitivity, "boundary_sensitivity"),
        geometry_sensitivity=packed(jax.vmap(partial(sensitivity_one, geometry_only=True),
                                             in_axes=ax), "geometry_sensitivity"),
        boundary_geometry_sensitivity=packed(partial(boundary_sensitivity, geometry_only=True),
                                             "boundary_geometry_sensitivity"),
        fold_nodal=packed(jax.vmap(fold_node, in_axes=(0, 0, 0, None, None, None, None, 0,
                                                      0, 0, 0, 0, None)), "fold_nodal"),
        observable_curvature=packed(observable_curvature, "observable_curvature"),
        vector_field=vector_field,
    )


#: parameter values at which the fields are probed for anisotropy at the apex
APEX_PROBES = (0.0, 1.0, 10.0, 100.0)


def _anisotropic_apex(scene, eps) -> bool:
    """Whether the target curvature is anisotropic at the apex (kb1 != kb2 at s = eps for
    some probed parameter value): then the pole condition k1 = k2 becomes k1 - k2 = A
    (module docstring), which costs third derivatives of W in the compiled boundary rows."""
    for p in APEX_PROBES:
        F = [float(v) for v in scene.field_values(0, eps, p)]
        if F[2] != F[3] and all(math.isfinite(v) for v in F):
            return True
    return False


@lru_cache(maxsize=64)
def _untraceable(fields, P, pressure=None, n_field_parameters=0) -> str:
    """Why JAX cannot trace the scene's fields or pressure (every method traces them), or ""
    if it can; one trace per field function, not one per solve."""
    def trace(i):
        s, p = jnp.float64(0.5), jnp.float64(0.0)
        values = call_fields(fields, i, s, p, jnp.zeros(n_field_parameters))
        return jnp.stack([jnp.asarray(v, dtype=jnp.float64) + 0.0 * s for v in values])

    for i in range(P):
        try:
            out = jax.eval_shape(lambda: trace(i))
        except Exception as exc:  # any tracing failure is the user's field function
            return (f"scene fields must be written with array arithmetic or jax.numpy (they "
                    f"are traced by JAX); fields(piece={i}, ...) failed: "
                    f"{type(exc).__name__}: {str(exc).splitlines()[0]}")
        if out.shape != (4,):
            return (f"scene fields must return four values (g1, g2, kb1, kb2), got shape "
                    f"{out.shape}")
    if pressure is not None:
        try:
            out = jax.eval_shape(lambda: jnp.asarray(pressure(jnp.float64(0.0)), jnp.float64))
        except Exception as exc:
            return (f"scene pressure must be written with array arithmetic or jax.numpy (it "
                    f"is traced by JAX); pressure(p) failed: {type(exc).__name__}: "
                    f"{str(exc).splitlines()[0]}")
        if out.shape != ():
            return f"scene pressure(p) must return a scalar, got shape {out.shape}"
    return ""


class ShellBVP:
    """The multi-point BVP of ``scene`` (see the module docstring).

    Arguments:
        scene: the problem.
        eps: pole offset (default ``POLE_OFFSET * theta``); must be below a tenth of the
            first piece.

    Attributes:
        scene, eps, P (number of pieces), a, b (piece ends in s), rise (H = 1 - cos theta).
    """

    n = 6
    #: relative error of the derivatives :meth:`rhs` returns: round-off, for they are
    #: analytic and the inner roots' derivatives (implicit differentiation) are taken at
    #: the roots themselves, converged to round-off, never at an earlier iterate
    jacobian_error = 0.0

    def __init__(self, scene: Scene, eps: float | None = None):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a shellbvp.Scene, got {type(scene).__name__}")
        eps_given = eps
        eps = POLE_OFFSET * scene.theta if eps is None else float(eps)
        first = scene.breaks[0] if scene.breaks else scene.theta
        if not (0 < eps < first / 10):
            raise ValueError(f"eps must lie in (0, {first / 10:g}) (a tenth of the first "
                             f"piece), got {eps!r}")
        self.scene, self.eps = scene, eps
        #: d eps / d theta: the default pole offset scales with theta, a given one is fixed
        self.eps_per_theta = POLE_OFFSET if eps_given is None else 0.0
        self.a = np.array((eps,) + scene.breaks)
        self.b = np.array(scene.breaks + (scene.theta,))
        self.P = scene.pieces
        self.rise = 1.0 - math.cos(scene.theta)
        n_c = len(scene.field_parameters)
        problem = _untraceable(scene.fields, self.P, scene.pressure, n_c)
        if problem:
            raise ValueError(problem)
        self._layouts = {}
        #: kb1 != kb2 at the apex: curvatures diverge like log s there (module docstring)
        self.anisotropic_apex = _anisotropic_apex(scene, eps)
        self._k = _kernels(scene.model, scene.material, float(scene.rhob1),
                           bool(scene.metric), scene.fields, self.P, scene.apex, scene.edge,
                           self.anisotropic_apex, scene.pressure, n_c)
        #: the field parameters, an argument of every compiled function of the fields
        self.field_parameters = np.array(scene.field_parameters, dtype=float)
        self.evaluations = 0

    def round_off(self, p: float) -> float:
        """Round-off scatter of a fold's parameter value p: ``ROUND_OFF_PER_H`` eps (1 + |p|)
        / h, times lam / ``ROUND_OFF_LAM`` for a Ciarlet-Geymonat material stiffer than
        that. Measured on caps (values at converged degrees, different degrees and Newton
        paths): ~1e-13 relative at h = 0.01, 2e-13 at h = 1e-3, 1.3e-12 at h = 1e-4 (the
        moment and forces enter the equations scaled by 12 / h^2), and growing like lam
        above lam ~ 100 (7e-13 relative at lam = 1e3, 7e-12 at 1e4). A change between rungs
        of the ladder does not see it, so fold error estimates are at least this."""
        sc = self.scene
        stiff = max(1.0, sc.lam / ROUND_OFF_LAM) if sc.material == "cg" else 1.0
        return ROUND_OFF_PER_H * np.finfo(float).eps * (1.0 + abs(p)) / sc.h * stiff

    @property
    def lengths(self) -> np.ndarray:
        return self.b - self.a

    def s_of(self, i: int, t):
        """s on piece i at the piece coordinate t in [0, 1]."""
        return self.a[i] + (self.b[i] - self.a[i]) * np.asarray(t, dtype=float)

    def reference(self, s):
        """The undeformed state at s (the default guess)."""
        return reference_state(s)

    # --- nodal functions ----------------------------------------------------------------------
    def _layout(self, P, m, size=None):
        """Per node count: the piece of every flattened node and the padded chunks (of the
        size :func:`_chunk` picks, or of ``size``)."""
        key = (P, m, size)
        if key not in self._layouts:
            n = P * m
            size = _chunk(n) if size is None else size
            chunks = [(start, min(start + size, n),
                       np.minimum(np.arange(start, start + size), min(start + size, n) - 1))
                      for start in range(0, n, size)]          # padded with the last node
            self._layouts[key] = (np.repeat(np.arange(P), m), chunks)
        return self._layouts[key]

    def _flat(self, kernel, s, Y, p, extra=(), *, scalars=(), chunk=None):
        """Call the nodal ``kernel`` on every node of s (P, m), Y (P, 6, m), in padded chunks
        (of size ``chunk`` if given), with per-node ``extra`` arrays and trailing
        ``scalars``."""
        P, m = s.shape
        piece, chunks = self._layout(P, m, chunk)
        sf = s.reshape(-1)
        yf = _flat_nodes(Y)
        handles = [kernel.dispatch(piece[idx], sf[idx], yf[idx], float(p),
                                   self.scene.material_parameter, self.scene.h,
                                   self.field_parameters,
                                   *[e[idx] for e in extra], *scalars)
                   for _, _, idx in chunks]
        outs = [[np.asarray(o)[: stop - start] for o in kernel.collect(hd)]
                for (start, stop, _), hd in zip(chunks, handles)]
        return [np.concatenate(parts) for parts in zip(*outs)]

    def _check(self, F, ok, s, p):
        P, m = s.shape
        F = F.reshape(P, m, 5)
        if not self.scene.fields_admissible(F):     # all pieces at once; name the culprit
            for i in range(P):
                self.scene.check_fields(F[i].T, i, p)
        if not ok.all():
            k = int(np.argmin(ok))
            raise ConvergenceError(
                f"inner Newton for (lam1, k1) did not converge at s = {s.ravel()[k]:.6g} "
                f"({self.scene.parameter} = {p:g}): the state is far from admissible "
                f"(lam1 <= 0, or the constitutive inversion folds); take a smaller step")

    def rhs(self, s, Y, p, hint=None) -> Nodal:
        """f, df/dy and df/dp at nodes s (P, m) with states Y (P, 6, m) (piece-major).

        ``hint``: the ``hint`` of a previous evaluation at the same nodes (warm start of the
        inner Newton; changes cost only). Raises ConvergenceError where the inner Newton fails
        and ValueError for inadmissible stimulus fields.
        """
        s, Y, q0 = self._nodal_args(s, Y, hint, p)
        out = self._flat(self._k.nodal, s, Y, p, (q0,))
        if not np.all(out[4]):         # a stale warm start: restart along the meridian
            q0 = self._start(s, Y, p)
            out = self._flat(self._k.nodal, s, Y, p, (q0,))
        return self._nodal_result(s, Y, p, out)

    def _nodal_args(self, s, Y, hint, p):
        s, Y = np.asarray(s, dtype=float), np.asarray(Y, dtype=float)
        P, m = s.shape
        if isinstance(hint, _Hint) and hint.q.shape == (P * m, 2):
            # the previous root carried to the new iterate: the inner Newton then starts
            # O(|change|^2) from its root
            return s, Y, _carried_roots(hint, _flat_nodes(Y), p)
        return s, Y, self._start(s, Y, p)

    def _start(self, s, Y, p):
        """A start for the inner Newton at every node when no previous iterate is known:
        (lam1, k1) followed along the meridian from the pole (:meth:`state_and_hessian`;
        an independent start per node from (lam2, k2) misses the root where the fields jump
        at an interface); nan (the pole-like guess) where that fails. A one-piece scene has
        no interface: there the pole-like guess is the start at every node (it needs no
        sequential scan, which is one more program to compile)."""
        if self.P == 1:
            return np.full((s.size, 2), np.nan)
        X, _, ok, _, _ = self._scan(s, Y, p)
        return np.where(ok[:, None], X[:, [0, 2]], np.nan)

    def carried_hint(self, hint, Y, Y_new, p, resample):
        """A warm start for an evaluation at states Y_new (P, 6, m') on other nodes of the
        same pieces, from ``hint``, that of an evaluation at nodes (P, m) near the states Y
        (P, 6, m) there: its roots carried to Y along their derivatives and resampled
        (``resample`` maps arrays (P, k, m) to the new nodes; the roots are smooth along
        each piece). None unless Y is within HINT_CARRY of the hint's states (relative):
        from farther, e.g. a fold bracketed away from the last continuation step, the
        carried roots can be a worse start than the pole-like guess."""
        y = _flat_nodes(Y)
        if not isinstance(hint, _Hint) or hint.y.shape != y.shape or \
                np.max(np.abs(y - hint.y)) > HINT_CARRY * (1.0 + np.max(np.abs(y))):
            return None
        q = _carried_roots(hint, y, p)
        P = Y.shape[0]
        q_new = np.moveaxis(resample(np.moveaxis(q.reshape(P, -1, 2), 1, 2)), 2, 1)
        n = P * q_new.shape[1]
        return _Hint(_flat_nodes(Y_new), float(p), q_new.reshape(n, 2), np.zeros((n, 2, 7)))

    def _nodal_result(self, s, Y, p, out, yf=None) -> Nodal:
        F, f, J, fp, ok, q, dq = out
        P, m = s.shape
        self.evaluations += 1
        self._check(F, ok, s, p)
        f = f.reshape(P, m, 6).transpose(0, 2, 1)
        J = J.reshape(P, m, 6, 6).transpose(0, 2, 3, 1)
        fp = fp.reshape(P, m, 6).transpose(0, 2, 1)
        return Nodal(f, J, fp, _Hint(_flat_nodes(Y) if yf is None else yf, float(p), q, dq))

    def collocate(self, s, Y, p, hint=None) -> Collocated:
        """:meth:`rhs` at the nodes, :meth:`boundary` at y(eps) = Y[0, :, 0] and
        y(theta) = Y[-1, :, -1], and :meth:`monitor` there: the same values, in one compiled
        call when all nodes fit in one chunk."""
        s, Y, q0 = self._nodal_args(s, Y, hint, p)
        P, m = s.shape
        piece, chunks = self._layout(P, m)
        if len(chunks) > 1:
            return Collocated(self.rhs(s, Y, p, hint), self.boundary(Y[0, :, 0], Y[-1, :, -1], p),
                              self.monitor(Y[0, :, 0], Y[-1, :, -1]))
        sc = self.scene
        ((_, _, idx),) = chunks
        yf = _flat_nodes(Y)

        def call(q):
            nod, bc, mon = self._k.collocate(
                piece[idx], s.reshape(-1)[idx], yf[idx], float(p), self.scene.material_parameter,
                sc.h, self.field_parameters, q[idx], Y[0, :, 0], Y[-1, :, -1], self.eps,
                sc.theta)
            return [o[:P * m] for o in nod], bc, mon

        out, bc, mon = call(q0)
        if not out[4].all():           # a stale warm start: restart along the meridian
            q0 = self._start(s, Y, p)
            out, bc, mon = call(q0)
        nodal = self._nodal_result(s, Y, p, out, yf)
        m_, (ga, gb) = mon
        return Collocated(nodal, self._boundary_result(bc, p),
                          (float(m_), np.asarray(ga), np.asarray(gb)))

    def state(self, s, Y, p, q_hint=None):
        """Principal state X = (lam1, lam2, k1, k2) (P, 4, m) and fields (P, 4, m) at nodes;
        ``q_hint`` (P, m, 2): starts for the inner roots (lam1, k1), e.g. a solver's."""
        X, F, _, _ = self.state_and_hessian(s, Y, p, q_hint)
        return X, F

    def state_and_hessian(self, s, Y, p, q_hint=None):
        """:meth:`state` (fields (g1, g2, kb1, kb2)) and the gradient (P, 4, m) and Hessian
        (P, 4, 4, m) of W in X at every node: the ellipticity of the reduced energy is read
        from them (:func:`shellbvp.ellipticity.ellipticity`)."""
        s = np.asarray(s, dtype=float)
        P, m = s.shape
        X, F, ok, gw, Hw = self._scan(s, Y, p, q_hint)
        self._check(F, ok, s, p)
        F = F.reshape(P, m, 5)[:, :, :4]          # the stimulus fields (the pressure is p's)
        return (np.moveaxis(X.reshape(P, m, 4), -1, 1), np.moveaxis(F, -1, 1),
                np.moveaxis(gw.reshape(P, m, 4), -1, 1), np.moveaxis(Hw.reshape(P, m, 4, 4), 1, -1))

    def _scan(self, s, Y, p, q_hint=None):
        """The state along the meridian (flattened nodes, piece-major), each node's inner
        Newton started from ``q_hint`` there (P, m, 2) where given and finite, else from the
        previous node's root (see ``state_along`` in the kernels)."""
        P, m = s.shape
        piece, chunks = self._layout(P, m, STATE_CHUNK)
        sf, yf = s.reshape(-1), _flat_nodes(Y)
        qh = np.full((P * m, 2), np.nan) if q_hint is None else \
            np.asarray(q_hint, dtype=float).reshape(P * m, 2)
        q = np.full(2, np.nan)         # the first node starts from the pole-like guess
        outs = []
        for start, stop, idx in chunks:
            X, F, ok, gw, Hw, q = self._k.state(piece[idx], sf[idx], yf[idx], float(p),
                                                   self.scene.material_parameter, self.scene.h,
                                                   self.field_parameters, q,
                                                   qh[idx])
            n = stop - start
            outs.append((X[:n], F[:n], ok[:n], gw[:n], Hw[:n]))
        return tuple(np.concatenate(parts) for parts in zip(*outs))

    # --- boundary conditions and observable ---------------------------------------------------
    def boundary(self, ya, yb, p):
        """Residual (6,) of the pole (3 rows) and edge (3 rows) conditions, with its
        derivatives in ya = y(eps), yb = y(theta) and p. Interface continuity is imposed by
        the methods (all six components)."""
        sc = self.scene
        return self._boundary_result(self._k.boundary(
            np.asarray(ya, dtype=float), np.asarray(yb, dtype=float), float(p), self.eps,
            sc.theta, self.scene.material_parameter, sc.h, self.field_parameters), p)

    def sensitivities(self, s, Y, p, hint=None, geometry_only=False):
        """f and its derivatives in (s, material parameter, h) at nodes s (P, m), states
        Y (P, 6, m) and fixed p: (f (P, 6, m), df/d(s, mat, h) (P, 6, m, 3)), the inner root
        differentiated implicitly (no finite differences). With :meth:`boundary_sensitivities`
        this gives the derivative of a discrete system in the scene's theta, h and material.
        ``geometry_only``: the derivative in s alone (zeros in the others; compiles ~5x
        faster)."""
        s, Y, q0 = self._nodal_args(s, Y, hint, p)
        P, m = s.shape
        kernel = self._k.geometry_sensitivity if geometry_only else self._k.sensitivity
        f, df = self._flat(kernel, s, Y, p,
                           (q0,))
        if not np.all(np.isfinite(df)):
            raise ConvergenceError("parameter derivatives of the right-hand side are not "
                                   "finite (the inner root was not found)")
        return (np.moveaxis(f.reshape(P, m, 6), -1, 1),
                np.moveaxis(df.reshape(P, m, 6, 3), 1, 2))

    def boundary_sensitivities(self, ya, yb, p, geometry_only=False):
        """The derivatives of the boundary residual (6,) in (eps, theta, material parameter,
        h) as (6, 4), and of the monitor in theta, at fixed ya, yb and p (``geometry_only``:
        zeros for the material parameter and h)."""
        sc = self.scene
        kernel = (self._k.boundary_geometry_sensitivity if geometry_only
                  else self._k.boundary_sensitivity)
        dr, dm = kernel(
            np.asarray(ya, dtype=float), np.asarray(yb, dtype=float), float(p), self.eps,
            sc.theta, self.scene.material_parameter, sc.h, self.field_parameters)
        return np.asarray(dr), float(dm)

    def fold_terms(self, s, Y, p, Wn, wb, V, dp, hint=None):
        """Second-derivative terms of a fold system at nodes s (P, m), states Y (P, 6, m):
        for phi = Wn . f at every node (weights Wn (P, 6, m)) plus wb . (pole rows) at the
        first node (the pole, s = eps), the derivative of phi along (V (P, 6, m), dp) and
        that of its gradient in (y, p, s), exact (no finite differences): (dphi (P, m, 2),
        the parts wn . f and wb . (pole rows); dgrad_y (P, 6, m); dgrad_p (P, m); dgrad_s
        (P, m)). ``hint``: the BVP's nodal result at exactly these states (its roots and
        their derivatives), else computed."""
        s, Y = np.asarray(s, dtype=float), np.asarray(Y, dtype=float)
        P, m = s.shape
        if not (isinstance(hint, _Hint) and hint.q.shape == (P * m, 2) and hint.p == p
                and np.array_equal(hint.y, _flat_nodes(Y))):
            hint = self.rhs(s, Y, p, hint).hint
        WB = np.zeros((P * m, 3))
        WB[0] = wb
        # chunks of one size, FOLD_CHUNK: every resolution runs on one compiled program
        # (~13 s to compile for a relaxed energy, against ~0.1 ms per extra chunk)
        out = self._flat(self._k.fold_nodal, s, Y, p,
                         (hint.q, hint.dq, _flat_nodes(Wn), WB, _flat_nodes(V)),
                         scalars=(float(dp),), chunk=FOLD_CHUNK)
        dphi, dgy, dgp, dgs = out
        if not all(np.all(np.isfinite(o)) for o in out):
            raise ConvergenceError("fold system: second derivatives are not finite")
        return (dphi.reshape(P, m, 2), np.moveaxis(dgy.reshape(P, m, 6), -1, 1),
                dgp.reshape(P, m), dgs.reshape(P, m))

    def monitor_curvature(self, ya, yb, va, vb):
        """The gradient in (ya, yb, theta) of the monitor's derivative along (va, vb)."""
        out = self._k.observable_curvature(np.asarray(ya, float), np.asarray(yb, float),
                                              self.scene.theta, np.asarray(va, float),
                                              np.asarray(vb, float))
        return tuple(np.asarray(o) for o in out)

    def _boundary_result(self, out, p):
        r, Ja, Jb, Jp, ok, F0 = out
        if not self.scene.fields_admissible(F0):
            self.scene.check_fields(F0[:, None], 0, p)
        if not ok:
            raise ConvergenceError(f"inner Newton for (lam1, k1) did not converge at the pole "
                                   f"({self.scene.parameter} = {p:g})")
        return r, Ja, Jb, Jp

    def monitor(self, ya, yb):
        """The observable w / H (module docstring) and its gradients in ya and yb."""
        m, (ga, gb) = self._k.observable(np.asarray(ya, dtype=float),
                                            np.asarray(yb, dtype=float), self.scene.theta)
        return float(m), np.asarray(ga), np.asarray(gb)

    def vector_field(self):
        """The traceable point function (piece, s, y, p, material_parameter, h) -> f (6,),
        for methods that integrate the ODE themselves (shooting)."""
        return self._k.vector_field

    # --- post-processing ----------------------------------------------------------------------
    def profile(self, dense_t):
        """A callable s -> (6, n) from a stacked interpolant t -> (6 P, n) in the piece
        coordinate (each s evaluated on its own piece; an interface belongs to the next)."""
        def ev(s):
            s = np.atleast_1d(np.asarray(s, dtype=float))
            out = np.empty((6, s.size))
            for i in range(self.P):
                lo = self.a[i] if i else -np.inf
                sel = (s >= lo) & ((s < self.b[i]) if i < self.P - 1 else (s <= np.inf))
                if np.any(sel):
                    t = (s[sel] - self.a[i]) / (self.b[i] - self.a[i])
                    out[:, sel] = np.asarray(dense_t(t))[6 * i:6 * i + 6]
            return out

        return ev

    def energies(self, dense_t, p, roots=None):
        """(E_s, E_b, E_p) = 2 pi int (w_s, h^2/12 w_b) g1 g2 sin s ds and the pressure's
        potential E_p = P V = pi P int r^2 g1 lam1 sin(theta) ds (0 without a load), per
        mu* h0 R0^2, by Gauss-Legendre quadrature per piece plus the polar cap [0, eps] (W is
        constant there to O(eps^2); r^2 makes its E_p O(eps^4)). ``dense_t(t)`` is the
        stacked (6 P, n) solution in the piece coordinate; ``roots`` = (t (m,), q (P, m, 2)):
        the inner roots at a solver's nodes, interpolated as starts at the quadrature
        points."""
        from .energy import energy_terms

        sc = self.scene
        xg, wg = np.polynomial.legendre.leggauss(ENERGY_GAUSS)
        edges = np.linspace(0.0, 1.0, ENERGY_PANELS + 1)
        mid, half = (edges[:-1] + edges[1:]) / 2, (edges[1:] - edges[:-1]) / 2
        t = (mid[:, None] + half[:, None] * xg[None, :]).ravel()
        wt = (half[:, None] * wg[None, :]).ravel()
        s = np.stack([self.s_of(i, t) for i in range(self.P)])
        Y = np.asarray(dense_t(t)).reshape(self.P, 6, t.size)
        hint = None
        if roots is not None:
            tn, qn = roots
            hint = np.stack([np.stack([np.interp(t, tn, qn[i, :, c]) for c in range(2)], -1)
                             for i in range(self.P)])
        X, F = self.state(s, Y, p, hint)
        g1, g2, kb1, kb2 = np.moveaxis(F, 1, 0)
        ws, wb, _, _ = energy_terms(*np.moveaxis(X, 1, 0), kb1, kb2, lam=sc.lam, nu=sc.nu,
                                    model=sc.model, material=sc.material, rhob1=sc.rhob1)
        dA = g1 * g2 * np.sin(s) * self.lengths[:, None] * wt[None, :]
        Es, Eb = float(np.sum(ws * dA)), sc.h**2 / 12 * float(np.sum(wb * dA))
        cap = g1[0, 0] * g2[0, 0] * (1 - math.cos(self.eps))
        Es += ws[0, 0] * cap
        Eb += sc.h**2 / 12 * wb[0, 0] * cap
        Ep = 0.0
        if sc.pressure is not None:
            r, th = Y[:, 0], Y[:, 2]
            Ep = math.pi * float(sc.pressure(p)) * float(np.sum(
                r**2 * g1 * X[:, 0] * np.sin(th) * self.lengths[:, None] * wt[None, :]))
        return 2 * math.pi * Es, 2 * math.pi * Eb, Ep
