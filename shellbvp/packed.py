"""Compiled functions that talk to the host in one vector each way.

Each host-to-device argument costs ~15 us and each device-to-host output ~5 us with JAX on
CPU; a collocation evaluation of :mod:`shellbvp.bvp` has 11 arguments and 15 outputs, which
made the host overhead of a small system (Chebyshev N = 32) half of its evaluation.
"""

from __future__ import annotations

import math

import numpy as np

from .executables import compile_exported
from .jaxsetup import jax

import jax.numpy as jnp  # noqa: E402

__all__ = ["Packed"]


def _flat(a):
    """An argument as a sequence numpy concatenates: an array's flat view, a Python number
    as a 1-tuple (~3 us for the eleven arguments of a collocation call, against ~5 us
    through np.ravel), anything else through np.ravel."""
    if type(a) is np.ndarray:
        return a.ravel()
    return (a,) if type(a) in (float, int) else np.ravel(a)


class Packed:
    """A jitted function whose arguments go to the device as ONE float64 vector and whose
    outputs (a pytree of arrays) come back as ONE vector, unpacked into numpy views.

    Each host-to-device argument costs ~15 us and each device-to-host output ~5 us; a
    collocation evaluation has 11 arguments and 15 outputs, which made the host overhead of
    a small system (Chebyshev N = 32) half of its evaluation. Shapes and dtypes of the
    arguments fix the layouts, found once per shape. Integer arguments travel as float64
    (exact below 2^53).

    Each program is traced once, by ``jax.export`` (which also gives the output layout).
    With a ``key`` (a string that identifies ``fn`` and everything it closes over) the
    exported program is kept on disk (:func:`shellbvp.cache.memo`) and a later process
    skips tracing (~1.2 s of a relaxed energy's W-jet): with JAX's persistent compilation
    cache on as well, the compiled program is kept too (:mod:`shellbvp.executables`), and a
    later process neither traces, lowers nor compiles.
    """

    def __init__(self, fn, key: str | None = None):
        self._fn = fn
        self._key = key
        self._programs = {}

    def _exported(self, n, shapes, dtypes):
        """(jax.export.Exported, leaves [(shape, dtype)], skeleton of the output tree with
        leaf indices as leaves, the program's disk key or None), from disk when the key
        allows."""
        from jax import export

        sizes = [math.prod(sh) for sh in shapes]
        starts = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
        found = {}

        def unpack(flat):
            return [flat[a:a + m].reshape(sh).astype(dt) if sh else flat[a].astype(dt)
                    for a, m, sh, dt in zip(starts, sizes, shapes, dtypes)]

        def packed(flat):
            leaves, found["tree"] = jax.tree_util.tree_flatten(self._fn(*unpack(flat)))
            found["leaves"] = [(x.shape, str(x.dtype)) for x in leaves]
            return jnp.concatenate([jnp.ravel(x).astype(jnp.float64) for x in leaves])

        def trace():
            ex = export.export(jax.jit(packed))(jax.ShapeDtypeStruct((n,), np.float64))
            skeleton = jax.tree_util.tree_unflatten(found["tree"],
                                                    list(range(len(found["leaves"]))))
            return ex, found["leaves"], skeleton

        if self._key is None:
            return (*trace(), None)
        from . import cache, shipped_programs

        ship = shipped_programs.ship_key(self._key, shapes, dtypes)

        def stored():
            entry = shipped_programs.program(ship)
            if entry is not None:
                try:
                    export.deserialize(entry[0])
                except Exception:   # shipped from a JAX this one cannot read: traced
                    entry = None
            if entry is None:
                ex, leaves, skeleton = trace()
                entry = ex.serialize(), leaves, skeleton
            return (shipped_programs.MARK, ship, *entry)

        k = cache.key("exported", 2, self._key, shapes, [str(d) for d in dtypes],
                      jax.__version__)
        _, _, blob, leaves, skeleton = cache.memo(k, stored)
        return export.deserialize(blob), leaves, skeleton, k

    def _program(self, args):
        shapes = [tuple(np.shape(a)) for a in args]
        dtypes = [np.asarray(a).dtype for a in args]
        n = int(sum(math.prod(sh) for sh in shapes))
        exported, leaves, skeleton, k = self._exported(n, shapes, dtypes)
        program = compile_exported(exported, n, k)
        tree = jax.tree_util.tree_structure(skeleton)
        ends = np.cumsum([math.prod(sh) for sh, _ in leaves])
        # per output leaf: its slice of the output vector, its shape, and the dtype it is
        # cast back to (None for float64, which is the vector's own: a view, no copy)
        layout = [(slice(int(e) - math.prod(sh), int(e)), tuple(sh),
                   None if np.dtype(dt) == np.float64 else np.dtype(dt))
                  for (sh, dt), e in zip(leaves, ends)]
        return program, tree, layout

    def prepare(self, *args):
        """(compiled program, output tree, output layout, the arguments packed into one
        float64 vector): everything a call does before running the program (compiling it
        on the first call with these shapes)."""
        key = tuple(map(np.shape, args))    # a call site passes the same dtypes every time
        if key not in self._programs:
            self._programs[key] = self._program(args)
        program, tree, layout = self._programs[key]
        return program, tree, layout, np.concatenate([_flat(a) for a in args],
                                                     dtype=np.float64)

    def dispatch(self, *args):
        """Start the computation (JAX dispatches asynchronously) and return a handle for
        :meth:`collect`: several calls can be in flight while the host prepares the next."""
        program, tree, layout, flat = self.prepare(*args)
        return program(flat), tree, layout

    def __call__(self, *args):
        return self.collect(self.dispatch(*args))

    @staticmethod
    def collect(handle):
        """The outputs of a :meth:`dispatch`, unpacked (waits for the computation)."""
        result, tree, layout = handle
        out = np.asarray(result)
        return jax.tree_util.tree_unflatten(tree, [
            out[part].reshape(shape) if cast is None else out[part].reshape(shape).astype(cast)
            for part, shape, cast in layout])
