"""Compiled XLA programs kept on disk, loaded by a later process without lowering.

A :class:`shellbvp.packed.Packed` program is traced once into a ``jax.export`` program
(kept on disk by :mod:`shellbvp.cache`). A later process must still lower that program to
XLA's input and look it up in JAX's persistent compilation cache, which for the default
cap's collocation program is about as long as loading the compiled program itself. This
module keeps the compiled program (``jax.experimental.serialize_executable``) under a key of
everything it depends on: the exported program's key, the compiler options, the JAX and
jaxlib versions and this host's processor (XLA:CPU compiles for the host's instruction
set), so that a later process loads it directly.

It is on where JAX's persistent compilation cache is on (:func:`shellbvp.jaxsetup.
use_persistent_cache`: the command line by default, the library on request), in
``$SHELLBVP_CACHE_DIR/executables``. An executable JAX itself loaded from its cache cannot
be serialised again (it fails at run time in the next process, ``NOT_FOUND: Function ...``),
so a program stored here is compiled with JAX's cache bypassed. An entry that does not load
(truncated, overwritten, from another jaxlib build) is compiled again and replaced; where
this JAX lacks the API the module needs, programs are compiled as before.
"""

from __future__ import annotations

import hashlib
import pickle
import platform
from functools import lru_cache
from pathlib import Path

import numpy as np

from .cache import atomic_write_bytes, cache_dir, key
from .jaxsetup import jax, supported_options

__all__ = ["compile_exported", "executables_folder"]


@lru_cache(maxsize=1)
def _api():
    """(serialize, deserialize_and_load, a context that bypasses JAX's persistent cache), or
    None where this JAX lacks them."""
    try:
        from jax._src import config as jax_config
        from jax.experimental.serialize_executable import deserialize_and_load, serialize
        bypass = jax_config.enable_compilation_cache
        bypass(False)           # the context manager exists and takes a value
    except Exception:           # another JAX: compile as before, nothing kept here
        return None
    return serialize, deserialize_and_load, bypass


@lru_cache(maxsize=1)
def host() -> str:
    """What XLA:CPU's code depends on of this machine: its architecture and, on Linux, the
    processor's model and instruction-set flags (a digest)."""
    text = platform.machine() + platform.processor()
    try:
        with open("/proc/cpuinfo") as f:
            lines = [ln for ln in f if ln.startswith(("flags", "model name", "Features"))]
        text += "".join(sorted(set(lines)))
    except OSError:
        pass
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def executables_folder() -> Path | None:
    """The folder of kept executables, or None where none are kept: the package's cache
    folder is off, or JAX's persistent compilation cache is not on in this process."""
    folder = cache_dir()
    if folder is None or not getattr(jax.config, "jax_compilation_cache_dir", None):
        return None
    if _api() is None:
        return None
    return folder / "executables"


def _compile(exported, n):
    return jax.jit(exported.call).trace(jax.ShapeDtypeStruct((n,), np.float64)).lower() \
        .compile(compiler_options=supported_options())


def compile_exported(exported, n: int, program_key: str | None):
    """``exported`` (a ``jax.export`` program of one float64 vector of length ``n``)
    compiled for this host: loaded from :func:`executables_folder` where it was kept under
    ``program_key`` (a string naming the exported program exactly), else compiled (and kept
    there when the folder is on)."""
    folder = None if program_key is None else executables_folder()
    if folder is None:
        return _compile(exported, n)
    import jaxlib

    serialize, deserialize_and_load, bypass = _api()
    path = folder / (key("executable", program_key, n, sorted(supported_options().items()),
                         jax.__version__, jaxlib.__version__, host()) + ".pkl")
    if path.exists():
        try:
            with open(path, "rb") as f:
                blob, in_tree, out_tree = pickle.load(f)
            return deserialize_and_load(blob, in_tree, out_tree)
        except Exception:   # corrupt, truncated or foreign: compiled again and replaced below
            pass
    with bypass(False):
        program = _compile(exported, n)
    try:
        data = pickle.dumps(serialize(program), protocol=pickle.HIGHEST_PROTOCOL)
        atomic_write_bytes(path, data)
    except (OSError, ValueError, pickle.PicklingError):
        pass    # a read-only folder or a program JAX cannot serialise: used, not kept
    return program
