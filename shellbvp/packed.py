"""Compiled functions that talk to the host in one vector each way.

Each host-to-device argument costs ~15 us and each device-to-host output ~5 us with JAX on
CPU; a collocation evaluation of :mod:`shellbvp.bvp` has 11 arguments and 15 outputs, which
made the host overhead of a small system (Chebyshev N = 32) half of its evaluation.
"""

from __future__ import annotations

import math
import os
from functools import lru_cache

import numpy as np

from .jaxsetup import jax

import jax.numpy as jnp  # noqa: E402

__all__ = ["Packed"]


@lru_cache(maxsize=None)
def _host_processor() -> str:
    """The host's processor as XLA compiles for it: its model and feature flags where the
    system states them (Linux), else the platform's description."""
    import platform

    try:
        with open("/proc/cpuinfo") as f:
            lines = [x for x in f if x.startswith(("model name", "flags"))]
        if lines:
            return "".join(sorted(set(lines)))
    except OSError:
        pass
    return f"{platform.machine()} {platform.processor()}"


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
    skips tracing (~1.2 s of a relaxed energy's W-jet). Where JAX's persistent compilation
    cache is on (the command line), the compiled program itself is kept too, as XLA's
    serialised executable (:meth:`_load_executable`): a later process then neither traces,
    lowers nor compiles, and only XLA's loading of the program remains.
    """

    def __init__(self, fn, key: str | None = None):
        self._fn = fn
        self._key = key
        self._programs = {}

    def _exported(self, n, shapes, dtypes):
        """(jax.export.Exported, leaves [(shape, dtype)], skeleton of the output tree with
        leaf indices as leaves), from disk when the key allows."""
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
            return trace()
        from . import cache

        def stored():
            ex, leaves, skeleton = trace()
            return ex.serialize(), leaves, skeleton

        k = cache.key("exported", self._key, shapes, [str(d) for d in dtypes],
                      jax.__version__)
        blob, leaves, skeleton = cache.memo(k, stored)
        return export.deserialize(blob), leaves, skeleton

    def _program(self, args):
        shapes = [tuple(np.shape(a)) for a in args]
        dtypes = [np.asarray(a).dtype for a in args]
        n = int(sum(math.prod(sh) for sh in shapes))
        loaded = self._load_executable(shapes, dtypes)
        if loaded is not None:
            program, leaves, skeleton = loaded
        else:
            exported, leaves, skeleton = self._exported(n, shapes, dtypes)
            program = jax.jit(exported.call).trace(
                jax.ShapeDtypeStruct((n,), np.float64)).lower().compile()
            self._store_executable(shapes, dtypes, program, leaves, skeleton)
        tree = jax.tree_util.tree_structure(skeleton)
        ends = np.cumsum([math.prod(sh) for sh, _ in leaves])
        layout = [(e - math.prod(sh), e, tuple(sh), np.dtype(dt))
                  for (sh, dt), e in zip(leaves, ends)]
        return program, tree, layout

    def _executable_path(self, shapes, dtypes):
        """Where the compiled program of these argument shapes is kept, or None: only with
        a key, and only where JAX's persistent compilation cache is on (the same decision,
        :func:`shellbvp.jaxsetup.use_persistent_cache`: loading a compiled program is the
        step that is not safe in every process). The key holds the package's code (through
        ``key``), JAX's and jaxlib's versions, the XLA flags and the host's processor, for
        which the program was compiled."""
        if self._key is None or not getattr(jax.config, "jax_compilation_cache_dir", None):
            return None
        from . import cache

        folder = cache.cache_dir()
        if folder is None:
            return None
        import jaxlib

        k = cache.key("executable", self._key, shapes, [str(d) for d in dtypes],
                      jax.__version__, jaxlib.__version__, os.environ.get("XLA_FLAGS", ""),
                      _host_processor())
        return folder / "executables" / f"{k}.pkl"

    def _load_executable(self, shapes, dtypes):
        """(program, leaves, skeleton) read back from :meth:`_executable_path`, or None
        (absent, damaged, or refused by this JAX). Skips tracing, lowering and the
        compilation cache's key of a warm process (~0.25 s of the default cap's 0.75 s; the
        rest is XLA deserialising the program). The bytes are checked against their
        SHA-256 before XLA sees them: a damaged entry is recompiled, never loaded."""
        path = self._executable_path(shapes, dtypes)
        if path is None or not path.exists():
            return None
        import hashlib
        import pickle

        from jax.experimental import serialize_executable

        try:
            with open(path, "rb") as f:
                digest, blob, in_tree, out_tree, leaves, skeleton = pickle.load(f)
            if hashlib.sha256(blob).hexdigest() != digest:
                return None
            program = serialize_executable.deserialize_and_load(blob, in_tree, out_tree)
        except Exception:  # damaged or from another JAX: compile as if absent
            return None
        return program, leaves, skeleton

    def _store_executable(self, shapes, dtypes, program, leaves, skeleton):
        """Keep the compiled ``program`` at :meth:`_executable_path` (atomically; nothing
        where the program cannot be serialised or the folder cannot be written)."""
        path = self._executable_path(shapes, dtypes)
        if path is None:
            return
        import hashlib
        import pickle

        from jax.experimental import serialize_executable

        from .cache import atomic_write_bytes

        try:
            blob, in_tree, out_tree = serialize_executable.serialize(program)
            data = pickle.dumps((hashlib.sha256(blob).hexdigest(), blob, in_tree, out_tree,
                                 leaves, skeleton), protocol=pickle.HIGHEST_PROTOCOL)
            path.parent.mkdir(parents=True, exist_ok=True)
            atomic_write_bytes(path, data)
        except Exception:   # not serialisable, or a read-only folder: in memory only
            pass

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
