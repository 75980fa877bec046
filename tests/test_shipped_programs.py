"""The exported programs shipped with the package (shellbvp.shipped_programs): the file
holds every program ``shellbvp snap`` asks for at this source (a stale file fails here, with
the command that regenerates it), a shipped program gives the command's output digit for
digit as a freshly traced one (the independent route: tracing), and an entry this JAX
cannot read is traced instead."""

import os
import subprocess
import sys

import numpy as np
import pytest

from shellbvp import shipped_programs


def snap(cache, model, **env):
    env = dict(os.environ, SHELLBVP_CACHE_DIR=str(cache), **env)
    env.pop("JAX_COMPILATION_CACHE_DIR", None)
    out = subprocess.run([sys.executable, "-m", "shellbvp.cli", "snap", "--model", model],
                         env=env, capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stderr[-2000:]
    return out.stdout


@pytest.mark.parametrize("model", shipped_programs.SNAP_MODELS)
def test_the_shipped_programs_are_the_ones_snap_asks_for(tmp_path, model):
    snap(tmp_path, model)
    asked = shipped_programs.collect(tmp_path)
    missing = set(asked) - set(shipped_programs._entries())
    assert asked and not missing, (
        f"shellbvp snap --model {model} traced {len(missing)} of its {len(asked)} programs: "
        f"the shipped file is stale; run `python -m shellbvp.shipped_programs`")


@pytest.mark.slow
@pytest.mark.parametrize("model", shipped_programs.SNAP_MODELS)
def test_a_shipped_program_gives_the_output_of_a_traced_one(tmp_path, model):
    shipped = snap(tmp_path / "shipped", model)
    traced = snap(tmp_path / "traced", model, SHELLBVP_SHIPPED="off")
    assert "kappa_s" in shipped and shipped == traced


def test_an_entry_this_jax_cannot_read_is_traced(tmp_path, monkeypatch):
    from shellbvp.jaxsetup import jax
    from shellbvp.packed import Packed

    import jax.numpy as jnp

    monkeypatch.setenv("SHELLBVP_CACHE_DIR", str(tmp_path))
    monkeypatch.setattr(shipped_programs, "program", lambda key: (b"not a program", [], 0))
    x = np.array([0.3, -1.2, 2.0])
    out = Packed(lambda x, k: jnp.sin(x) * k, key="tests.test_shipped_programs")(x, 2.0)
    assert np.allclose(out, np.sin(x) * 2.0, rtol=1e-15)
    assert jax.tree_util.tree_structure(out).num_leaves == 1
