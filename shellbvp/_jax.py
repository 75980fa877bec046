"""JAX set-up shared by the compiled modules: float64, and the persistent compilation cache.

Double precision is required (continuation and fold refinement work at 1e-10); shellbvp
turns it on when imported, as scipy users expect float64. Compiled XLA programs are cached
on disk beside the symbolic cache (``$SHELLBVP_CACHE_DIR/jax``), so the JIT cost is paid
once per machine, not per process.
"""

from __future__ import annotations

import jax

from .cache import cache_dir

jax.config.update("jax_enable_x64", True)
_dir = cache_dir()
if _dir is not None:
    try:
        jax.config.update("jax_compilation_cache_dir", str(_dir / "jax"))
        jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.5)
    except Exception:  # older/newer JAX without these options: in-process caching only
        pass

__all__ = ["jax"]
