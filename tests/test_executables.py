"""Compiled programs kept on disk (shellbvp.executables), each case in fresh processes as
the command line meets them: a later process loads the program instead of lowering and
compiling it, and gets the same numbers (checked against NumPy, an independent route); an
entry that is corrupt is compiled again and replaced; a program JAX's own cache already
holds is compiled afresh before it is kept (an executable JAX loaded from its cache and
serialised again failed at run time in the next process, the failure this design avoids);
and nothing is kept where the persistent caches are off (the library's default)."""

import os
import subprocess
import sys
import textwrap

#: one keyed Packed program, its result against NumPy, and how it was obtained
SCRIPT = textwrap.dedent("""
    import sys
    import numpy as np
    from shellbvp import executables
    from shellbvp.jaxsetup import jax, use_persistent_cache
    import jax.numpy as jnp
    from shellbvp.packed import Packed
    use_persistent_cache(default=sys.argv[1] == "on")
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    compiled = []
    real = executables._compile
    executables._compile = lambda *a: compiled.append(1) or real(*a)

    def f(x, a):
        return {"y": jnp.sin(x) * a + jnp.cumsum(x), "n": jnp.sum(x > 0.5)}

    p = Packed(f, key="tests.test_executables.f")
    x = np.linspace(0.1, 1.0, 7)
    out = p(x, 2.5)
    assert np.allclose(out["y"], np.sin(x) * 2.5 + np.cumsum(x), rtol=1e-14, atol=1e-14)
    assert int(out["n"]) == 4 and out["n"].dtype.kind == "i", out["n"]
    print("compiled" if compiled else "loaded")
""")


def run(cache, jax_cache="on"):
    env = dict(os.environ, SHELLBVP_CACHE_DIR=str(cache))
    env.pop("SHELLBVP_JAX_CACHE", None)
    env.pop("JAX_COMPILATION_CACHE_DIR", None)
    out = subprocess.run([sys.executable, "-c", SCRIPT, jax_cache], env=env,
                         capture_output=True, text=True, timeout=600)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout.strip()


def kept(cache):
    folder = cache / "executables"
    return sorted(folder.iterdir()) if folder.exists() else []


def test_a_later_process_loads_the_program_and_gets_the_same_numbers(tmp_path):
    assert run(tmp_path) == "compiled"
    assert len(kept(tmp_path)) == 1
    assert run(tmp_path) == "loaded"
    assert run(tmp_path) == "loaded"


def test_a_corrupt_entry_is_compiled_again_and_replaced(tmp_path):
    run(tmp_path)
    (entry,) = kept(tmp_path)
    for damage in (entry.read_bytes()[:1000], b"garbage"):
        entry.write_bytes(damage)
        assert run(tmp_path) == "compiled"
        assert run(tmp_path) == "loaded"


def test_a_program_in_jax_cache_is_compiled_afresh_before_it_is_kept(tmp_path):
    """JAX's cache holds the program (first process), ours does not (removed): the second
    process compiles it with JAX's cache bypassed and keeps it; a third loads and runs it."""
    run(tmp_path)
    assert os.listdir(tmp_path / "jax")
    for entry in kept(tmp_path):
        entry.unlink()
    assert run(tmp_path) == "compiled"
    assert run(tmp_path) == "loaded"


def test_nothing_is_kept_where_the_persistent_caches_are_off(tmp_path):
    assert run(tmp_path, jax_cache="off") == "compiled"
    assert kept(tmp_path) == []
    assert run(tmp_path, jax_cache="off") == "compiled"
