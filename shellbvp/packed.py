"""Compiled functions that talk to the host in one vector each way.

Each host-to-device argument costs ~15 us and each device-to-host output ~5 us with JAX on
CPU; a collocation evaluation of :mod:`shellbvp.bvp` has 11 arguments and 15 outputs, which
made the host overhead of a small system (Chebyshev N = 32) half of its evaluation.
"""

from __future__ import annotations

import math

import numpy as np

from .jaxsetup import jax

import jax.numpy as jnp  # noqa: E402

__all__ = ["Packed"]


class Packed:
    """A jitted function whose arguments go to the device as ONE float64 vector and whose
    outputs (a pytree of arrays) come back as ONE vector, unpacked into numpy views.

    Each host-to-device argument costs ~15 us and each device-to-host output ~5 us; a
    collocation evaluation has 11 arguments and 15 outputs, which made the host overhead of
    a small system (Chebyshev N = 32) half of its evaluation. Shapes and dtypes of the
    arguments fix the layouts, found once per shape (the output's by ``jax.eval_shape``).
    Integer arguments travel as float64 (exact below 2^53).
    """

    def __init__(self, fn):
        self._fn = fn
        self._programs = {}

    def _program(self, args):
        shapes = [np.shape(a) for a in args]
        dtypes = [np.asarray(a).dtype for a in args]
        sizes = [math.prod(sh) for sh in shapes]
        starts = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
        found = {}

        def unpack(flat):
            return [flat[a:a + n].reshape(sh).astype(dt) if sh else flat[a].astype(dt)
                    for a, n, sh, dt in zip(starts, sizes, shapes, dtypes)]

        def packed(flat):
            leaves, found["tree"] = jax.tree_util.tree_flatten(self._fn(*unpack(flat)))
            found["leaves"] = [(x.shape, x.dtype) for x in leaves]
            return jnp.concatenate([jnp.ravel(x).astype(jnp.float64) for x in leaves])

        # one trace gives both the program and the output layout (tracing the W-jet of a
        # relaxed model takes seconds: a second trace for the layout would double it)
        program = jax.jit(packed).trace(
            jax.ShapeDtypeStruct((int(starts[-1]),), np.float64)).lower().compile()
        ends = np.cumsum([math.prod(sh) for sh, _ in found["leaves"]])
        layout = [(e - math.prod(sh), e, sh, dt) for (sh, dt), e in zip(found["leaves"], ends)]
        return program, found["tree"], layout

    def dispatch(self, *args):
        """Start the computation (JAX dispatches asynchronously) and return a handle for
        :meth:`collect`: several calls can be in flight while the host prepares the next."""
        key = tuple(map(np.shape, args))    # a call site passes the same dtypes every time
        if key not in self._programs:
            self._programs[key] = self._program(args)
        program, tree, layout = self._programs[key]
        flat = np.concatenate(list(map(np.ravel, args)), dtype=np.float64)
        return program(flat), tree, layout

    def __call__(self, *args):
        return self.collect(self.dispatch(*args))

    @staticmethod
    def collect(handle):
        """The outputs of a :meth:`dispatch`, unpacked (waits for the computation)."""
        result, tree, layout = handle
        out = np.asarray(result)
        return jax.tree_util.tree_unflatten(tree, [
            out[a:b].reshape(shape) if dtype == np.float64 else
            out[a:b].reshape(shape).astype(dtype) for a, b, shape, dtype in layout])
