"""JAX set-up for the compiled modules: float64, and (opt-in) the persistent compilation cache.

Double precision is required (continuation and fold refinement work at 1e-10); importing
any compiled part of shellbvp turns on ``jax_enable_x64``, the one global JAX setting the
package changes by default.

JAX's persistent compilation cache (compiled XLA programs kept on disk, so that a new process
skips compilation) is off by default: with jax/jaxlib 0.10.2 on CPU, loading a cached
executable aborted a test process (``Fatal Python error: Aborted`` inside
``compilation_cache.get_executable_and_time``) after it had compiled several hundred
programs; the cause is not isolated, and a crash is worse than a recompile. ``SHELLBVP_JAX_CACHE=on`` turns it on (in
``$SHELLBVP_CACHE_DIR/jax``) for users whose JAX loads its cache safely; a cache the user
configured in JAX itself is left alone.
"""

from __future__ import annotations

import os

import jax

from .cache import cache_dir

#: compile times below this (s) are not worth a disk entry
PERSISTENT_CACHE_MIN_SECONDS = 0.5

jax.config.update("jax_enable_x64", True)


def _use_persistent_cache() -> None:
    folder = cache_dir()
    if (os.environ.get("SHELLBVP_JAX_CACHE", "off").strip().lower() not in {"on", "1", "yes"}
            or folder is None or getattr(jax.config, "jax_compilation_cache_dir", None)):
        return
    try:
        jax.config.update("jax_compilation_cache_dir", str(folder / "jax"))
        jax.config.update("jax_persistent_cache_min_compile_time_secs",
                          PERSISTENT_CACHE_MIN_SECONDS)
    except AttributeError:  # a JAX without these options: in-process caching only
        pass


_use_persistent_cache()

__all__ = ["jax"]
