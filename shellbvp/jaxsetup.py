"""JAX set-up for the compiled modules: float64, the XLA options of every program, and the
persistent compilation cache (CLI).

Double precision is required (continuation and fold refinement work at 1e-10); importing
any compiled part of shellbvp turns on ``jax_enable_x64``, the one global JAX setting the
package changes by default.

JAX's persistent compilation cache (compiled XLA programs kept on disk in
``$SHELLBVP_CACHE_DIR/jax``, so that a new process skips compilation) is on for the command
line (:func:`use_persistent_cache` with ``default=True``: it compiles a handful of programs,
and a later ``shellbvp snap`` starts in seconds instead of ~15 s) and off by default for the
library. A test process once aborted while loading a cached program (jax/jaxlib 0.10.2 on
CPU, ``Fatal Python error: Aborted`` inside ``compilation_cache.get_executable_and_time``,
after several hundred programs). It was not reproduced: 400 programs written and reloaded
in one process; two processes writing one empty cache at once; a reload from entries
truncated or overwritten with garbage (recompiled, JAX checks every entry); the test
suite's own programs (590 entries, 26 MB) written by one run of the whole default suite and
reloaded by a second (tests/test_jax_cache.py repeats the first three). Reports elsewhere
point at deserialisation itself: jaxlib < 0.10 crashing on large cached executables on
Linux and macOS (LLVM's object linking recursing on a fixed stack), and CPU executables
rejected on reload where the host's features differ (a recompile, not a crash). A library
call can run in any process (a notebook, a cluster worker) with programs far larger than
the command line's, so the library keeps the cache off by default: a crash is worse than a
recompile. ``SHELLBVP_JAX_CACHE=on`` / ``off`` overrides both defaults; a cache the user
configured in JAX itself is left alone. Where the cache is on, the package's own compiled
programs are also kept as executables (:mod:`shellbvp.executables`), which a later process
loads without lowering them.
"""

from __future__ import annotations

import os
from functools import lru_cache

import jax

from .cache import cache_dir

#: compile times below this (s) are not worth a disk entry
PERSISTENT_CACHE_MIN_SECONDS = 0.5
#: XLA options of every program the package compiles (:func:`jit`, :class:`shellbvp.packed.
#: Packed`): XLA:CPU's older code generator (fusion emitters off). On the default cap it
#: compiles the programs of a first kappa_s in 0.63 of the default's time relaxed (2.2
#: against 3.5 s) and 0.51 in plane strain (1.1 against 2.1 s), and the collocation
#: program runs in 0.66 and 0.86 of the default's time (150 against 227 us relaxed;
#: kappa_s equal to 3e-14; figures/bench_codegen.py, one pinned core, jaxlib 0.10.2,
#: medians of 5 fresh processes)
COMPILER_OPTIONS = (("xla_cpu_use_fusion_emitters", False),)

jax.config.update("jax_enable_x64", True)


def use_persistent_cache(default: bool = False) -> bool:
    """Turn on JAX's persistent compilation cache in the package's cache folder if
    ``SHELLBVP_JAX_CACHE`` says so (on / off), else if ``default``; returns whether it is on.
    Nothing changes when the cache folder is off or JAX already has a cache folder."""
    setting = os.environ.get("SHELLBVP_JAX_CACHE", "").strip().lower()
    wanted = setting in {"on", "1", "yes"} or (default and setting not in {"off", "0", "no"})
    folder = cache_dir()
    if getattr(jax.config, "jax_compilation_cache_dir", None):
        return True
    if not wanted or folder is None:
        return False
    try:
        jax.config.update("jax_compilation_cache_dir", str(folder / "jax"))
        jax.config.update("jax_persistent_cache_min_compile_time_secs",
                          PERSISTENT_CACHE_MIN_SECONDS)
    except AttributeError:  # a JAX without these options: in-process caching only
        return False
    return True


@lru_cache(maxsize=None)
def supported_options(options: tuple = COMPILER_OPTIONS) -> dict:
    """``options`` ((name, value) pairs) as the ``compiler_options`` of a compilation, or {}
    where this jaxlib does not know one of them (probed once, on a one-operation program:
    XLA refuses an unknown option with an error, which would otherwise surface at a
    solver's first call). The verdict is kept in the cache folder per jaxlib version, so
    that a later process does not compile the probe."""
    if not options:
        return {}
    import jaxlib

    from .cache import key, memo

    def probe():
        try:
            jax.jit(lambda x: x + 1.0).lower(1.0).compile(compiler_options=dict(options))
        except Exception:   # JaxRuntimeError "No such compile option", or an older signature
            return False
        return True

    known = memo(key("xla-options", options, jax.__version__, jaxlib.__version__), probe)
    return dict(options) if known else {}


def jit(fn, **kwargs):
    """``jax.jit`` with the package's XLA options (:data:`COMPILER_OPTIONS`, where known)."""
    return jax.jit(fn, compiler_options=supported_options(), **kwargs)


use_persistent_cache()

__all__ = ["jax", "jit", "use_persistent_cache", "supported_options", "COMPILER_OPTIONS"]
