"""JAX's persistent compilation cache as the command line uses it (shellbvp.jaxsetup): many
programs written, then reloaded by a later process, by two writers at once, and from a
cache whose entries are truncated or overwritten with garbage; every process must answer
and exit 0. (A test process once aborted while loading a cached program, jax 0.10.2; the
stress runs of the investigation, up to 400 programs and the whole test suite reloaded, are
described in shellbvp.jaxsetup.)"""

import os
import random
import subprocess
import sys
import textwrap

import pytest

#: compiles ``n`` distinct programs (shapes and bodies differ) with the package's cache
#: settings and checks their values against NumPy
SCRIPT = textwrap.dedent("""
    import sys
    import numpy as np
    from shellbvp.jaxsetup import jax, use_persistent_cache
    import jax.numpy as jnp
    assert use_persistent_cache(default=True)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.0)
    for k in range(int(sys.argv[1])):
        m = 4 + k % 9
        def f(x, k=k):
            y = jnp.sin(x) * (k + 1.0)
            return jax.jacfwd(lambda z: jnp.tanh(z) * y.sum())(x) + jnp.linalg.solve(
                jnp.eye(x.shape[0]) * (k + 2.0), y)
        x = np.linspace(0.1, 1.0, m)
        out = np.asarray(jax.jit(f)(x))
        y = np.sin(x) * (k + 1.0)
        expected = np.diag(1.0 - np.tanh(x) ** 2) * y.sum() + y / (k + 2.0)
        assert np.allclose(out, expected, rtol=1e-12, atol=1e-12), k
    print("ok")
""")


def run(cache, n, count=1):
    env = dict(os.environ, SHELLBVP_CACHE_DIR=str(cache), SHELLBVP_JAX_CACHE="on")
    env.pop("JAX_COMPILATION_CACHE_DIR", None)
    procs = [subprocess.Popen([sys.executable, "-c", SCRIPT, str(n)], env=env,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for _ in range(count)]
    for p in procs:
        out, err = p.communicate(timeout=900)
        assert p.returncode == 0 and out.strip() == "ok", (p.returncode, err[-2000:])


def entries(cache):
    folder = cache / "jax"
    return [folder / f for f in os.listdir(folder)] if folder.exists() else []


def _stress(tmp_path, n):
    run(tmp_path, n, count=2)              # two writers on one empty cache at once
    written = entries(tmp_path)
    assert len(written) >= n
    run(tmp_path, n)                       # a later process reloads every program
    rng = random.Random(0)
    for k, path in enumerate(sorted(written)):
        if path.is_file() and k % 3 != 2:  # truncate one in three, garble another
            data = path.read_bytes()
            path.write_bytes(data[:len(data) // 2] if k % 3 == 0
                             else bytes(rng.randrange(256) for _ in data))
    run(tmp_path, n)                       # damaged entries: recompiled, never a crash


def test_cache_survives_concurrent_writers_reloads_and_damaged_entries(tmp_path):
    _stress(tmp_path, 12)


@pytest.mark.slow
def test_cache_survives_hundreds_of_programs(tmp_path):
    _stress(tmp_path, 300)
