"""The compiled programs of a scene: the single-node functions of its model
(:func:`shellbvp.compiled.point_functions`) closed over the scene's stimulus fields, pressure,
pieces, pole and edge conditions and observable, vmapped and compiled (JAX), each kept on disk
where its code is covered by the package's source hash (:class:`shellbvp.packed.Packed`).
The BVP (:class:`shellbvp.bvp.ShellBVP`, whose module docstring states the equations) calls
them; nothing else does.
"""

from __future__ import annotations

from functools import lru_cache, partial
from typing import Callable, NamedTuple

from .compiled import point_functions, solve_2x2
from .jaxsetup import jax
from .packed import Packed
from .scene import call_fields

import jax.numpy as jnp  # noqa: E402

__all__ = ["Kernels", "kernels", "disk_key", "package_source", "untraceable", "INTERFACE_STEPS",
           "observable_and_gradient"]

#: steps in which the inner root is carried across an interface as the fields jump
#: (post-processing only; the methods carry it from their previous iterate)
INTERFACE_STEPS = 16


def observable_and_gradient(ya, yb, theta, free_edge: bool, xp):
    """The branch monitor w / H (:mod:`shellbvp.bvp`) from the states at the pole ya = y(eps)
    and the edge yb = y(theta), and its gradients in ya and yb, in closed form with the array
    module ``xp`` (jax.numpy inside the compiled kernels, numpy on the host: a Newton
    solve asks for the monitor at its converged iterate, where a call of a compiled
    program of its own cost ~150 us against ~10 us in numpy). The apex height z(0) comes
    from the regular series at eps, z(0) = z(eps) + r(eps) phi(eps) / 2 (y = (r, z, phi,
    ...)); for a free edge w is the edge's height over the apex's, for a clamped one the
    apex's over the edge's, both relative to the reference and in units of H = 1 - cos
    theta. (Checked against JAX's gradient of the value in the tests.)"""
    H = 1.0 - xp.cos(theta)
    sign = (1.0 if free_edge else -1.0) / H
    rel = yb[1] - (ya[1] + ya[0] * ya[2] / 2) - (xp.cos(theta) - 1.0)
    zero = 0.0 * ya[0]
    # asarray, not stack: numpy's stack of six scalars took 10 of this function's 14 us
    ga = -sign * xp.asarray([ya[2] / 2, 1.0 + zero, ya[0] / 2, zero, zero, zero])
    gb = sign * xp.asarray([zero, 1.0 + zero, zero, zero, zero, zero])
    return sign * rel, (ga, gb)


@lru_cache(maxsize=None)
def package_source() -> str:
    """A hash of the package's source (every .py file): part of every disk key of code."""
    from pathlib import Path

    from .cache import files_digest

    return files_digest(sorted(Path(__file__).parent.rglob("*.py")))


def disk_key(functions, *parts) -> str | None:
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
    return repr((package_source(), tuple(names), parts))


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
def kernels(model, material, rhob1, metric, fields, P, apex, edge, log_apex=False,
             pressure=None, n_field_parameters=0):
    """The scene's compiled functions (see :class:`ShellBVP`). Every function of the
    fields takes the scene's field parameters c (an array of ``n_field_parameters``) as an
    argument after h: scenes that differ in c only share these programs."""
    pf = point_functions(model, material, rhob1, metric)
    base = disk_key((fields, pressure), model, material, rhob1, metric, P, apex, edge,
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
        return observable_and_gradient(ya, yb, theta, edge == "free", jnp)[0]

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
                observable_and_gradient(ya, yb, theta, edge == "free", jnp))

    return Kernels(
        collocate=packed(collocate, "collocate"),
        nodal=packed(nodal, "nodal"),
        state=packed(state_along, "state"),
        boundary=packed(boundary_jac, "boundary"),
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


@lru_cache(maxsize=64)
def untraceable(fields, P, pressure=None, n_field_parameters=0) -> str:
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
