"""JAX set-up for the compiled modules: float64, and the persistent compilation cache.

Double precision is required (continuation and fold refinement work at 1e-10); importing
any compiled part of shellbvp turns on ``jax_enable_x64``, the one global JAX setting the
package changes on its own authority. Compiled XLA programs are also kept on disk, in
``$SHELLBVP_CACHE_DIR/jax`` (default ``~/.cache/shellbvp/jax``), so that the JIT cost is
paid once per machine rather than once per process; this is skipped when
``SHELLBVP_CACHE_DIR=off`` or when the user has already configured a JAX compilation cache
(their choice wins).
"""

from __future__ import annotations

import jax

from .cache import cache_dir

#: compile times below this (s) are not worth a disk entry
PERSISTENT_CACHE_MIN_SECONDS = 0.5

jax.config.update("jax_enable_x64", True)


def _use_persistent_cache() -> None:
    folder = cache_dir()
    if folder is None or getattr(jax.config, "jax_compilation_cache_dir", None):
        return
    try:
        jax.config.update("jax_compilation_cache_dir", str(folder / "jax"))
        jax.config.update("jax_persistent_cache_min_compile_time_secs",
                          PERSISTENT_CACHE_MIN_SECONDS)
    except AttributeError:  # a JAX without these options: in-process caching only
        pass


_use_persistent_cache()

__all__ = ["jax"]
