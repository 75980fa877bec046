"""The compiled programs of a scene: the single-node functions of its model
(:func:`shellbvp.compiled.point_functions`) closed over the scene's fields (reference
geometry, stimulus, thickness, pressure: :mod:`shellbvp.fields`), pieces, end conditions and
monitor, vmapped and compiled (JAX), each kept on disk where its code is covered by the
package's source hash (:class:`shellbvp.packed.Packed`). The BVP
(:class:`shellbvp.bvp.ShellBVP`, whose module docstring states the equations) calls them;
nothing else does.
"""

from __future__ import annotations

from collections import OrderedDict
from functools import lru_cache, partial
from typing import Callable, NamedTuple

import numpy as np

from . import kinematics as K
from .compiled import point_functions, solve_2x2
from .fields import parameter_fields, point_fields
from .scene import LOAD_NAMES, per_scene
from .jaxsetup import jax
from .packed import Packed
from .fields import call_fields

import jax.numpy as jnp  # noqa: E402

__all__ = ["Kernels", "kernels", "kernel_key", "disk_key", "package_source", "untraceable",
           "INTERFACE_STEPS", "monitor_and_gradient", "end_value"]

#: steps in which the inner root is carried across an interface as the fields jump
#: (post-processing only; the methods carry it from their previous iterate)
INTERFACE_STEPS = 16
#: compiled kernels kept in memory (each set holds a handful of XLA programs)
KERNELS_KEPT = 32
#: the rows of a pole: regularity (equal actual stretches, equal curvatures) and the
#: axial condition (z held where the pole is pinned, else no point force)


def end_value(y, component, pole, theta_pole, xp):
    """The value of ``component`` (``"r"``, ``"z"``, ``"theta"``) of the unknowns y at an
    end of the BVP's domain; at a pole (y at the pole offset eps from it) z is the pole's own
    height from the regular series, z(pole) = z(eps) + r (theta - theta_pole) / 2
    (theta_pole = 0 at a first end, pi at a second: the tangent meets the axis at a right
    angle), and r and theta those at eps (their values at the pole, 0 and theta_pole, are
    fixed)."""
    if component == "z":
        return y[1] + y[0] * (y[2] - theta_pole) / 2 if pole else y[1]
    return y[0] if component == "r" else y[2]


def monitor_and_gradient(ya, yb, terms, poles, refs, scale, xp):
    """The branch monitor (:attr:`shellbvp.Scene.monitor_terms`) from the states at the
    domain's ends ya, yb, and its gradients in ya and yb, in closed form with the array
    module ``xp`` (jax.numpy inside the compiled kernels, numpy on the host: a Newton
    solve asks for the monitor at its converged iterate, where a call of a compiled program
    of its own cost ~150 us against ~10 us in numpy): sum of coefficient x (end value -
    its reference value) over the terms, over ``scale``. ``refs[end][component]`` the
    reference values, ``poles`` whether each end is a pole. (Checked against JAX's
    gradient of the value in the tests.)"""
    ys = (ya, yb)
    value = 0.0 * ya[0]
    ref = 0.0
    grads = [[0.0 * ya[0]] * 6, [0.0 * ya[0]] * 6]
    theta_pole = (0.0, np.pi)
    for coef, comp, end in terms:
        y, pole = ys[end], poles[end]
        value = value + coef * end_value(y, comp, pole, theta_pole[end], xp)
        ref = ref + coef * refs[end][comp]
        g = grads[end]
        if comp == "z":
            g[1] = g[1] + coef
            if pole:
                g[0] = g[0] + coef * (y[2] - theta_pole[end]) / 2
                g[2] = g[2] + coef * y[0] / 2
        else:
            k = 0 if comp == "r" else 2
            g[k] = g[k] + coef
    inv = 1.0 / scale
    # asarray, not stack: numpy's stack of six scalars took 10 of this function's 14 us
    return inv * (value - ref), (inv * xp.asarray(grads[0]), inv * xp.asarray(grads[1]))


@lru_cache(maxsize=None)
def package_source() -> str:
    """A hash of the package's source (every .py file): part of every disk key of code.

    The scenes (``shellbvp.problems``) are left out: they live outside the package folder in
    a checkout and inside it in an installed wheel, and the digest must be the same in both
    (a scene's functions enter a key by their own file's digest, :func:`_function_key`)."""
    from pathlib import Path

    from .cache import files_digest

    root = Path(__file__).parent
    return files_digest(p for p in sorted(root.rglob("*.py"))
                        if p.relative_to(root).parts[0] != "problems")


def _function_key(fn):
    """What identifies the code of a scene's function for a disk key: its module, qualname
    and the digest of its file (a module-level function of shellbvp or of its scenes), its
    ``cache_key`` (a function made from data, e.g. a scene file's expressions), or None
    where neither exists (a user's function, a closure: its code is not covered)."""
    import sys

    from .cache import files_digest

    if fn is None:
        return ("none",)
    key = getattr(fn, "cache_key", None)
    if isinstance(key, str):
        return ("data", key)
    module = getattr(fn, "__module__", "") or ""
    qualname = getattr(fn, "__qualname__", "") or ""
    if not module.startswith("shellbvp") or "<" in qualname or \
            getattr(sys.modules.get(module), qualname, None) is not fn:
        return None
    # the scenes (shellbvp.problems) live outside the package folder: hash their module
    return (module, qualname, files_digest([sys.modules[module].__file__]))


def disk_key(functions, *parts) -> str | None:
    """A disk key for compiled kernels of the scene's ``functions`` (fields, pressure, ...)
    and ``parts``, or None when one of them is not covered (:func:`_function_key`: its
    programs stay in memory). Numbers the functions depend on are the scene's field
    parameters, arguments of the programs, not part of their code."""
    names = [_function_key(fn) for fn in functions]
    if any(n is None for n in names):
        return None
    return repr((package_source(), tuple(names), parts))


@per_scene
def kernel_key(scene, log_poles) -> tuple:
    """Everything the traced code of a scene depends on (so that scenes equal in it share
    programs): the model, the functions of its fields and loads (by identity), the segments
    its pieces lie on (their trace keys and starts, not their extents), its ends, monitor
    and number of field parameters."""
    geo = scene.geometry
    segs = scene.piece_segments
    geometry = tuple((type(geo.segments[k]).__name__, geo.segments[k].trace_key(),
                      float(geo.segment_starts[k]), float(geo.theta_offsets[k])) for k in segs)
    ends = tuple((e.kind, e.loads) for e in scene.ends)
    return (scene.model, scene.material, scene.through_thickness_stimulus,
            bool(scene.metric), scene.varying_thickness, scene.fields,
            scene.through_thickness, scene.thickness, scene.pressure, geometry, ends,
            scene.pinned, tuple(scene.monitor_terms), tuple(bool(x) for x in log_poles),
            len(scene.field_parameters))


class Kernels(NamedTuple):
    """The compiled programs of a scene (:func:`kernels`), each a :class:`Packed` (kept
    on disk) except the traceable ``vector_field``."""

    #: rhs, boundary conditions and monitor at one iterate, in one dispatch
    collocate: Packed
    #: the rhs and its Jacobians at nodes
    nodal: Packed
    #: the principal state and W's jet along a meridian (inner roots followed node to node)
    state: Packed
    #: end rows with their Jacobians
    boundary: Packed
    #: derivatives of f and of the end rows in the meridian's length, the material and h ...
    sensitivity: Packed
    boundary_sensitivity: Packed
    #: ... and in the length alone (compiles ~5x faster)
    geometry_sensitivity: Packed
    boundary_geometry_sensitivity: Packed
    #: the fold system's second derivatives at nodes, and the monitor's
    fold_nodal: Packed
    observable_curvature: Packed
    #: (piece, s, y, p, material parameter, h, c) -> f (6,), traceable (shooting)
    vector_field: Callable


_KEPT: "OrderedDict[tuple, Kernels]" = OrderedDict()


def kernels(scene, log_poles=(False, False)) -> Kernels:
    """The scene's compiled functions (see :class:`ShellBVP`), shared by every scene with
    the same :func:`kernel_key`. Every function of the fields takes the scene's field
    parameters c (an array) as an argument after h: scenes that differ in c only share these
    programs. ``log_poles``: per end, whether it is a pole with an anisotropic target
    curvature (the condition k1 - k2 = A of :mod:`shellbvp.bvp`)."""
    key = kernel_key(scene, log_poles)
    found = _KEPT.get(key)
    if found is None:
        found = _KEPT[key] = _build(scene, tuple(bool(x) for x in log_poles), key)
        while len(_KEPT) > KERNELS_KEPT:
            _KEPT.popitem(last=False)
    else:
        _KEPT.move_to_end(key)
    return found


def _build(scene, log_poles, key) -> Kernels:
    pf = point_functions(scene.model, scene.material, scene.through_thickness_stimulus,
                         bool(scene.metric), scene.varying_thickness)
    functions = (scene.fields, scene.through_thickness, scene.thickness, scene.pressure,
                 *[f for e in scene.ends for f in e.loads])
    base = disk_key(functions, *key[:5], *key[9:])
    P = scene.pieces
    geo = scene.geometry
    segs = scene.piece_segments
    poles = tuple(e.kind == "pole" for e in scene.ends)
    kinds = tuple(e.kind for e in scene.ends)
    terms = tuple(scene.monitor_terms)
    pinned = scene.pinned
    loads = tuple(e.loads for e in scene.ends)
    end_piece = (0, P - 1)
    end_segment = (geo.segments[segs[0]], geo.segments[segs[-1]])
    end_start = (float(geo.segment_starts[segs[0]]), float(geo.segment_starts[segs[-1]]))
    end_offset = (float(geo.theta_offsets[segs[0]]), float(geo.theta_offsets[segs[-1]]))
    theta_pole = (0.0, np.pi)
    rise_scale = scene.monitor_scale != scene.h      # the monitor in rises, else in h
    moving = parameter_fields(scene)

    def packed(fn, name):
        return Packed(fn, None if base is None else f"{name}:{base}")

    branches = [partial(point_fields, scene, i, xp=jnp) for i in range(P)]

    def fields_at(piece, s, p, c):
        return jax.lax.switch(piece, branches, s, p, c) if P > 1 else branches[0](s, p, c)

    def reference_at(end, s):
        # the reference meridian at the end's domain coordinate s (its position moves with
        # the meridian's length for the second end)
        r0, z0, th0, _ = end_segment[end].evaluate(s - end_start[end], jnp)
        return {"r": r0, "z": z0, "theta": th0 + end_offset[end]}

    def pole_reference(end, length):
        # the pole itself, not the offset point: r = 0, theta at a right angle, its z
        at = 0.0 if end == 0 else length
        return {"r": 0.0, "z": reference_at(end, at)["z"], "theta": theta_pole[end]}

    def nodal_one(piece, s, y, p, lam, h, c, q_init):
        F, dF = jax.jvp(lambda p_: fields_at(piece, s, p_, c), (p,), (jnp.ones_like(p),))
        f, J, fp, ok, q, dq = pf.rhs_jac(y, F, dF, lam, h, q_init, moving)
        return F, f, J, fp, ok, q, dq

    def state_along(piece, s, y, p, lam, h, c, q_start, q_hints):
        # Each node from the previous node's (lam1, k1) (nodes in order along the meridian:
        # the state is continuous in s within a piece). Across an interface y is continuous
        # but (lam1, k1) jump with the fields: there the root is followed from the previous
        # node's while the fields move from their old to their new values in
        # INTERFACE_STEPS steps. Where these fail (no elliptic root), from the pole-like guess.
        def across(q, y_, F_prev, F):
            def sub(i, q_):
                t = (i + 1.0) / INTERFACE_STEPS
                q_new, _, ok = pf.algebraic(y_, (1 - t) * F_prev + t * F, lam, h, q_)
                return jnp.where(ok, q_new, jnp.nan)
            return pf.algebraic(y_, F, lam, h, jax.lax.fori_loop(0, INTERFACE_STEPS, sub, q))

        def step(carry, args):
            q, F_prev = carry
            piece_, s_, y_, q_hint = args
            F = fields_at(piece_, s_, p, c)
            # a given hint (the root a solver converged to there) comes first: near a loss
            # of ellipticity the previous node's root may lead to no elliptic one
            hinted = jnp.all(jnp.isfinite(q_hint))
            warm = pf.algebraic(y_, F, lam, h, jnp.where(hinted, q_hint, q))
            carried = jax.lax.cond(warm[2] | ~hinted, lambda: warm,
                                   lambda: pf.algebraic(y_, F, lam, h, q))
            second = jax.lax.cond(carried[2], lambda: carried,
                                  lambda: across(q, y_, F_prev, F))
            q_new, X, ok = jax.lax.cond(second[2], lambda: second,
                                        lambda: pf.algebraic(y_, F, lam, h))
            gw, Hw = pf.hessian(y_, q_new, F, lam, h)
            return (jnp.where(ok, q_new, q), F), (X, F, ok, gw, Hw)

        F0 = fields_at(piece[0], s[0], p, c)
        (q_end, _), (X, F, ok, gw, Hw) = jax.lax.scan(step, (q_start, F0),
                                                      (piece, s, y, q_hints))
        return X, F, ok, gw, Hw, q_end

    def pole_rows(end, y, q, F, lam, h, z_ref, p, fns=pf):
        # regularity of the deformed surface at a pole: equal actual stretches
        # g1 lam1 = g2 lam2 (r ~ g1 lam1 r0 and lam2 = r / (g2 r0)) and k1 = k2; the third
        # row holds the pole's height where it is pinned, else asks for the given point
        # force (F(second) = Q, F(first) = -Q, Q the force per radian)
        X = fns.X(y, q, F, h)
        if pinned == end:
            third = end_value(y, "z", True, theta_pole[end], jnp) - z_ref
        elif loads[end][LOAD_NAMES.index("displacement")] is not None:
            third = (end_value(y, "z", True, theta_pole[end], jnp) - z_ref
                     - loads[end][LOAD_NAMES.index("displacement")](p))
        else:                          # the point force, per radian: force / (2 pi)
            Q = natural(end, "force", p, 1.0 / (2.0 * np.pi))
            third = y[5] if isinstance(Q, float) and Q == 0.0 else y[5] - 12.0 / (h * h) * Q
        dk = jnp.zeros(())
        if log_poles[end]:
            # anisotropic target curvature at the pole: the finite-energy local solution has
            # k1 - k2 -> A = (1 - nu) (k*1 - k*2) / 2 (curvatures ~ A log s), nu = W_k1k2 /
            # W_k1k1 and k* the curvatures that make the moments vanish (W is quadratic in
            # k); k1 - k2 = A at eps excludes the 1/s mode exactly as k1 = k2 does for a
            # regular pole, where A = 0
            g, H = fns.hessian(y, q, F, lam, h)
            kstar = X[2:] - solve_2x2(H[2:, 2:], g[2:])
            dk = (1.0 - H[2, 3] / H[2, 2]) * (kstar[0] - kstar[1]) / 2.0
        return jnp.stack([F[K.G1] * X[0] - F[K.G2] * X[1], X[2] - X[3] - dk, third])

    def natural(end, name, p, r_ref):
        # a given line load per unit reference length, as the conjugate force per radian
        # scaled like the unknowns (m, f = 12/h^2 M, F); the natural condition is
        # F(second) = Q and F(first) = -Q for a load Q doing work on the end
        load = loads[end][LOAD_NAMES.index(name)]
        if load is None:
            return 0.0
        Q = load(p) * r_ref
        if name == "moment":           # counterclockwise in (r, z): conjugate to -theta
            Q = -Q
        return Q if end == 1 else -Q

    def edge_rows(end, y, p, s_end, h):
        ref = reference_at(end, s_end)
        scale = 12.0 / (h * h)
        r, z, th, m, fr, fz = (y[k] for k in range(6))
        z_row = z - ref["z"]

        def given(v, name):
            Q = natural(end, name, p, ref["r"])
            return v if isinstance(Q, float) and Q == 0.0 else v - scale * Q

        fz_row = z_row if pinned == end else given(fz, "axial")
        kind = kinds[end]
        if kind == "free":
            rows = (given(m, "moment"), given(fr, "radial"), fz_row)
        elif kind == "clamped":
            rows = (r - ref["r"], z_row, th - ref["theta"])
        elif kind == "hinged":
            rows = (r - ref["r"], z_row, given(m, "moment"))
        elif kind == "roller":
            rows = (z_row, given(fr, "radial"), given(m, "moment"))
        elif kind == "sliding":
            rows = (z_row, given(fr, "radial"), th - ref["theta"])
        elif kind == "diaphragm":
            rows = (r - ref["r"], fz_row, given(m, "moment"))
        else:                                   # symmetry
            rows = (th - ref["theta"], fr, fz_row)
        return jnp.stack(rows)

    def end_rows(end, y, p, s_end, length, lam, h, c, q_root, dq):
        """The three rows of one end, at its domain coordinate s_end (with the inner root
        there where it is a pole: q(y, p) with the value of the root and the derivative of
        implicit differentiation, dq = [dq/dy, dq/dp] (2, 7), so that the rows
        differentiate only kinematics)."""
        if not poles[end]:
            return edge_rows(end, y, p, s_end, h), fields_at(end_piece[end], s_end, p, c)
        F = fields_at(end_piece[end], s_end, p, c)
        q = (q_root + dq[:, :6] @ (y - jax.lax.stop_gradient(y))
             + dq[:, 6] * (p - jax.lax.stop_gradient(p)))
        z_ref = pole_reference(end, length)["z"]
        return pole_rows(end, y, q, F, lam, h, z_ref, p), F

    def boundary_jac(ya, yb, p, s_a, s_b, length, lam, h, c, roots=None):
        # each end's rows depend on its own state (and p) only: differentiate each in its own
        # variables. The inner roots at the poles and their implicit derivatives come from
        # the nodal function at the end nodes (given when they are nodes, as in collocation),
        # so no derivative runs through the inner Newton loop.
        rows, Ja, Jb, Jp = [], [], [], []
        ok_all = jnp.array(True)
        z = jnp.zeros((3, 6))
        F0 = None
        for end, (y, s_end) in enumerate(((ya, s_a), (yb, s_b))):
            if roots is None or roots[end] is None:
                _, _, _, _, ok, q_root, dq = nodal_one(end_piece[end], s_end, y, p, lam, h,
                                                       c, jnp.full(2, jnp.nan))
            else:
                ok, q_root, dq = roots[end]
            ok_all = ok_all & (ok if poles[end] else True)

            def rows_of(y_, p_, end=end, s_end=s_end, q_root=q_root, dq=dq):
                r, F = end_rows(end, y_, p_, s_end, length, lam, h, c, q_root, dq)
                return r, (r, F)

            (Jy, Jpe), (r, F) = jax.jacfwd(rows_of, argnums=(0, 1), has_aux=True)(y, p)
            rows.append(r)
            Ja.append(Jy if end == 0 else z)
            Jb.append(Jy if end == 1 else z)
            Jp.append(Jpe)
            F0 = F if end == 0 else F0
        return (jnp.concatenate(rows), jnp.vstack(Ja), jnp.vstack(Jb), jnp.concatenate(Jp),
                ok_all, F0)

    def refs_of(s_a, s_b, length):
        return [pole_reference(end, length) if poles[end] else reference_at(end, s_end)
                for end, s_end in ((0, s_a), (1, s_b))]

    def scale_of(length, h):
        # the monitor's unit (Scene.monitor_scale): the rise |z0(L) - z0(0)|, a function of
        # the meridian's length (its derivatives in L are exact), or the thickness
        if not rise_scale:
            return h
        return jnp.abs(reference_at(1, length)["z"] - reference_at(0, 0.0)["z"])

    def observable(ya, yb, s_a, s_b, length, h):
        return monitor_and_gradient(ya, yb, terms, poles, refs_of(s_a, s_b, length),
                                    scale_of(length, h), jnp)[0]

    def vector_field(piece, s, y, p, lam, h, c):
        # f with the inner root found on values only (no tangent runs through its Newton
        # loop) and differentiated implicitly (f_linear): the first derivatives a solver
        # takes of f (forward-mode sensitivities in shooting) are exact, at the cost of one
        # linear solve per direction instead of every inner iteration (2.7x less time per
        # shooting evaluation, 0.59 -> 0.22 s at rtol 1e-8; Jacobians equal to 2e-12)
        F = fields_at(piece, s, p, c)
        stop = jax.lax.stop_gradient
        q_root, _, _ = pf.root(stop(y), stop(F), stop(lam), stop(h))
        return pf.f_linear(y, F, lam, h, q_root)

    ax = (0, 0, 0, None, None, None, None, 0)
    nodal = jax.vmap(nodal_one, in_axes=ax)

    def sensitivity_one(piece, s, y, p, lam, h, c, q_init, geometry_only=False):
        # f and its derivatives in (s, material parameter, h) at fixed y and p, the fields
        # included (they depend on s), by implicit differentiation of the inner root; with
        # geometry_only, in s alone (zeros for the others): a derivative of the relaxed
        # energy in lam and h costs ~20 s of compilation that a length derivative does not
        q_root, _, _ = pf.root(y, fields_at(piece, s, p, c), lam, h, q_init)

        def f(s_, lam_, h_):
            return pf.f_linear(y, fields_at(piece, s_, p, c), lam_, h_, q_root)

        if geometry_only:
            value, ds = jax.jvp(lambda s_: f(s_, lam, h), (s,), (jnp.ones_like(s),))
            return value, jnp.stack([ds, jnp.zeros_like(ds), jnp.zeros_like(ds)], axis=-1)
        return f(s, lam, h), jnp.stack(jax.jacfwd(f, argnums=(0, 1, 2))(s, lam, h), axis=-1)

    def boundary_sensitivity(ya, yb, p, s_a, s_b, length, lam, h, c, geometry_only=False):
        # the end rows' derivatives in (s_a, s_b, length, material parameter, h) and the
        # monitor's in (s_a, s_b, length), at fixed ya, yb and p (geometry_only: zeros for
        # lam, h)
        roots = []
        for end, (y, s_end) in enumerate(((ya, s_a), (yb, s_b))):
            roots.append(pf.root(y, fields_at(end_piece[end], s_end, p, c), lam, h)[0]
                         if poles[end] else None)

        def rows(sa_, sb_, len_, lam_, h_):
            out = []
            for end, (y, s_end) in enumerate(((ya, sa_), (yb, sb_))):
                if poles[end]:
                    F = fields_at(end_piece[end], s_end, p, c)
                    q = pf.q_linear(y, F, lam_, h_, roots[end])
                    out.append(pole_rows(end, y, q, F, lam_, h_,
                                         pole_reference(end, len_)["z"], p))
                else:
                    out.append(edge_rows(end, y, p, s_end, h_))
            return jnp.concatenate(out)

        if geometry_only:
            d = jax.jacfwd(lambda a, b, L: rows(a, b, L, lam, h), argnums=(0, 1, 2))(
                s_a, s_b, length)
            d = (*d, jnp.zeros_like(d[0]), jnp.zeros_like(d[0]))
        else:
            d = jax.jacfwd(rows, argnums=(0, 1, 2, 3, 4))(s_a, s_b, length, lam, h)
        dm = jax.grad(observable, argnums=(2, 3, 4))(ya, yb, s_a, s_b, length, h)
        return jnp.stack(d, axis=-1), jnp.stack(dm)

    def fold_node(piece, s, y, p, lam, h, c, q, dq, wn, wb, v, dp, length):
        # phi = wn . f + wb . (pole rows of the first and second end) at one node (wb = 0
        # but at the end nodes), along the inner root q (derivative dq): the derivative of
        # phi along (v, dp) and that of its gradient in (y, p, s), exact (``curvature`` of
        # :func:`point_functions`)
        def phi(fns, y_, q_, F_):
            parts = [wn @ fns.f(y_, q_, F_, lam, h)]
            pole = 0.0 * y_[0]
            for end in (0, 1):
                if poles[end]:
                    z_ref = pole_reference(end, length)["z"]
                    # (a point force enters at fixed p here: its second derivative in p,
                    # nonzero only for a force nonlinear in p, is left out)
                    pole = pole + wb[3 * end:3 * end + 3] @ pole_rows(end, y_, q_, F_, lam, h,
                                                                      z_ref, p, fns)
            return jnp.stack(parts + [pole])

        return pf.curvature(phi, (y, p, s), (v, dp, jnp.zeros_like(s)), lam, h, q, dq,
                            lambda s_, p_: fields_at(piece, s_, p_, c))

    def observable_curvature(ya, yb, s_a, s_b, length, h, va, vb):
        # the gradient in (ya, yb, s_a, s_b, length) of the monitor's derivative along
        # (va, vb)
        return jax.jvp(lambda a, b: jax.grad(observable, argnums=(0, 1, 2, 3, 4))(
            a, b, s_a, s_b, length, h), (ya, yb), (va, vb))[1]

    def collocate(piece, s, y, p, lam, h, c, q_init, ya, yb, s_a, s_b, length):
        # everything a collocation method needs at one iterate, in one dispatch; the first
        # node is the first end (s = s_a, y = ya) and the last the second (padding repeats
        # it), whose inner roots the pole rows reuse
        nod = nodal(piece, s, y, p, lam, h, c, q_init)
        roots = ((nod[4][0], nod[5][0], nod[6][0]), (nod[4][-1], nod[5][-1], nod[6][-1]))
        return (nod, boundary_jac(ya, yb, p, s_a, s_b, length, lam, h, c, roots),
                monitor_and_gradient(ya, yb, terms, poles, refs_of(s_a, s_b, length),
                                     scale_of(length, h), jnp))

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
                                                      0, 0, 0, 0, None, None)),
                          "fold_nodal"),
        observable_curvature=packed(observable_curvature, "observable_curvature"),
        vector_field=vector_field,
    )


#: :func:`untraceable`'s verdicts, per scene structure (:func:`kernel_key`)
_TRACEABLE: "OrderedDict[tuple, str]" = OrderedDict()


def untraceable(scene) -> str:
    """Why JAX cannot trace the scene's fields (every method traces them), or "" if it can;
    one trace per piece, once per scene structure (:func:`kernel_key`)."""
    key = kernel_key(scene, (False, False))
    found = _TRACEABLE.get(key)
    if found is None:
        found = _TRACEABLE[key] = _untraceable(scene)
        while len(_TRACEABLE) > 4 * KERNELS_KEPT:
            _TRACEABLE.popitem(last=False)
    return found


def _untraceable(scene) -> str:
    n_c = len(scene.field_parameters)
    # abstract arguments: eval_shape traces without running anything (a concrete scalar
    # would compile a conversion program eagerly)
    s = p = jax.ShapeDtypeStruct((), jnp.float64)
    for i in range(scene.pieces):
        for name in ("fields", "through_thickness", "thickness"):
            fn = getattr(scene, name)
            if fn is None:
                continue
            from .fields import reference_point

            want = {"fields": 4, "through_thickness": 3, "thickness": None}[name]

            def trace(s, p, fn=fn, name=name):
                x = reference_point(scene, i, s, jnp)
                values = fn(x) if name == "thickness" else call_fields(fn, x, p,
                                                                        jnp.zeros(n_c))
                if want is None:
                    return jnp.asarray(values, dtype=jnp.float64) + 0.0 * s
                return jnp.stack([jnp.asarray(v, dtype=jnp.float64) + 0.0 * s
                                  for v in values])

            try:
                out = jax.eval_shape(trace, s, p)
            except Exception as exc:  # any tracing failure is the user's function
                return (f"scene {name} must be written with array arithmetic or jax.numpy "
                        f"(it is traced by JAX); {name}(piece={i}, ...) failed: "
                        f"{type(exc).__name__}: {str(exc).splitlines()[0]}")
            shape = () if want is None else (want,)
            if out.shape != shape:
                what = "a scalar" if want is None else f"{want} values"
                return f"scene {name} must return {what}, got shape {out.shape}"
    if scene.pressure is not None:
        try:
            out = jax.eval_shape(lambda p: jnp.asarray(scene.pressure(p), jnp.float64), p)
        except Exception as exc:
            return (f"scene pressure must be written with array arithmetic or jax.numpy (it "
                    f"is traced by JAX); pressure(p) failed: {type(exc).__name__}: "
                    f"{str(exc).splitlines()[0]}")
        if out.shape != ():
            return f"scene pressure(p) must return a scalar, got shape {out.shape}"
    return ""
