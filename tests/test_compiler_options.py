"""The XLA options every compiled program of the package gets (shellbvp.jaxsetup): given
exactly where this jaxlib knows them, and then received by the programs compiled through
``jaxsetup.jit`` and ``Packed``; refused options are left out rather than failing at a
solver's first call; and the options do not change the numbers (XLA:CPU's two code
generators compute the same arithmetic: the relaxed energy's jet agrees to round-off); and
the conditional that keeps a W-jet out of XLA's fusion (shellbvp.compiled.materialised)
returns the values of the function it wraps.

Whether this jaxlib knows an option is decided apart from ``supported_options``' own probe
(a compilation with the options as ``compiler_options``, which XLA checks against the fields
of its DebugOptions): by XLA's command-line flags, ``XLA_FLAGS``, which XLA parses in a
fresh process and refuses, aborting, where a flag is not one it registers. What a program
received is read from XLA's own dump of it (``--xla_dump_to``): the compile options of the
executable and the options its module was compiled with.
"""

import json
import os
import re
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np

from shellbvp import jaxsetup
from shellbvp.compiled import energy_function
from shellbvp.jaxsetup import jax

ROOT = Path(__file__).resolve().parents[1]


def _run(code: str, **env) -> subprocess.CompletedProcess:
    """``python -c code`` in a fresh process (XLA reads XLA_FLAGS once, at its start), with
    no compilation cache (a program loaded from disk is not compiled, hence not dumped)."""
    env = dict(os.environ, SHELLBVP_JAX_CACHE="off", JAX_ENABLE_COMPILATION_CACHE="false",
               **env)
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          env=env, cwd=ROOT)


def _flag(value) -> str:
    """An option's value as XLA_FLAGS writes it."""
    return str(value).lower() if isinstance(value, bool) else str(value)


def _text(value) -> str:
    """An option's value as XLA's text dumps write it (true, 3, "a string")."""
    return json.dumps(value)


def xla_accepts(options) -> bool:
    """Whether XLA takes ``options`` ((name, value) pairs) as its flags: a process started
    with them in XLA_FLAGS runs, or XLA's flag parser refuses them (an unknown name or a
    value of the wrong type) and aborts. Anything else is an error of this check."""
    flags = " ".join(f"--{name}={_flag(value)}" for name, value in options)
    out = _run("import jax; jax.devices()", XLA_FLAGS=flags)
    if out.returncode == 0:
        return True
    assert re.search(r"Unknown flag in XLA_FLAGS|Flag parsing failed", out.stderr), \
        f"XLA_FLAGS={flags}: the process failed for another reason\n{out.stderr[-2000:]}"
    return False


@lru_cache(maxsize=None)
def expected_options() -> dict:
    """The package's options where XLA accepts them all as flags, else none."""
    known = xla_accepts(jaxsetup.COMPILER_OPTIONS)
    return dict(jaxsetup.COMPILER_OPTIONS) if known else {}


def test_xla_flags_tell_a_known_option_from_an_unknown_one():
    """The route the tests below rely on can answer both ways on this jaxlib."""
    assert xla_accepts((("xla_cpu_enable_fast_math", False),))
    assert not xla_accepts((("xla_no_such_option_of_any_jaxlib", True),))


def test_an_unknown_option_is_left_out():
    assert jaxsetup.supported_options((("xla_no_such_option_of_any_jaxlib", True),)) == {}
    assert jaxsetup.supported_options(()) == {}


def test_the_package_options_are_given_where_this_jaxlib_knows_them():
    """supported_options() is the package's options exactly where XLA's own flags know them
    (so neither dropped on this jaxlib nor given to one that refuses them)."""
    assert jaxsetup.supported_options() == expected_options()


PROGRAMS = """
import re
import numpy as np
from shellbvp import jaxsetup
from shellbvp.packed import Packed
from shellbvp.jaxsetup import jax

def through_jit(x):
    return jax.numpy.sin(x) * 2.0

def without_options(x):
    return jax.numpy.tan(x) * 2.0

x = np.linspace(0.0, 1.0, 8)
jaxsetup.jit(through_jit)(x)
jax.jit(without_options)(x)
program = Packed(lambda x: jax.numpy.cos(x) * 2.0).prepare(x)[0]
print(re.match(r"HloModule (\\w+)", program.as_text()).group(1))
"""


def _dumped(folder: Path, module: str) -> list[tuple[dict, dict]]:
    """(options the module was compiled with where they differ from XLA's defaults, the
    executable's env_option_overrides), both as XLA's text, of every dump of ``module``."""
    out = []
    for path in sorted(folder.glob(f"module_*.{module}.debug_options")):
        debug = dict(re.findall(r"^(\w+): (.*)$", path.read_text(), re.M))
        compile_options = (path.with_suffix("") / "compile_options.textproto").read_text()
        overrides = dict(re.findall(
            r'env_option_overrides \{\s*key: "(\w+)"\s*value \{\s*\w+: (\S+)\s*\}',
            compile_options))
        out.append((debug, overrides))
    assert out, f"XLA dumped no program {module} (was it compiled?)"
    return out


def test_compiled_programs_receive_the_options(tmp_path):
    """A program compiled through jaxsetup.jit and one through Packed are built with the
    expected options (XLA's flags decide which, not supported_options): the compile options
    of the executable carry them as overrides, and the module is compiled with them; a
    program compiled by plain jax.jit in the same process carries none of them (so the dump
    tells one from the other). XLA's dump lists a module's options where they differ from
    XLA's defaults only: an option of the package at its default value would fail here."""
    out = _run(PROGRAMS, XLA_FLAGS=f"--xla_dump_to={tmp_path}")
    assert out.returncode == 0, out.stderr[-2000:]
    packed = out.stdout.split()[-1]
    expected = {name: _text(value) for name, value in expected_options().items()}
    for module in ("jit_through_jit", packed):
        for debug, overrides in _dumped(tmp_path, module):
            assert overrides == expected, f"{module}: overrides {overrides}"
            for name, value in expected.items():
                assert debug.get(name) == value, f"{module}: {name} = {debug.get(name)}"
    for debug, overrides in _dumped(tmp_path, "jit_without_options"):
        assert overrides == {}
        assert not set(debug) & set(expected), debug


def test_options_leave_the_energy_jet_unchanged():
    W = energy_function("relaxed", "cg")

    def jet(X, kb, lam, h):
        def w(x):
            return W(x[0], x[1], x[2], x[3], kb[0], kb[1], lam, h, 1.0, 0.0, 0.0)
        return jax.grad(w)(X), jax.hessian(w)(X)

    f = jax.vmap(jet, in_axes=(0, 0, None, None))
    rng = np.random.default_rng(3)
    X = np.column_stack([rng.uniform(0.8, 1.2, 40), rng.uniform(0.8, 1.2, 40),
                         rng.uniform(-2, 2, 40), rng.uniform(-2, 2, 40)])
    kb = rng.uniform(-2, 2, (40, 2))
    default = jax.jit(f)(X, kb, 1.0, 0.01)
    chosen = jaxsetup.jit(f)(X, kb, 1.0, 0.01)
    for a, b in zip(default, chosen):
        a, b = np.asarray(a), np.asarray(b)
        assert np.all(np.isfinite(a))
        np.testing.assert_allclose(b, a, rtol=1e-12, atol=1e-12 * np.abs(a).max())


def test_materialised_values_are_the_function_values():
    # shellbvp.compiled.materialised keeps a result out of XLA's fusion by computing it in
    # a conditional on a run-time scalar: the values must be fn()'s, whether that scalar is
    # shared by every lane of a vmap (a conditional) or batched (JAX then selects)
    from shellbvp.compiled import materialised

    def fn(x, lam):
        return materialised(lambda: (jax.numpy.sin(x) * lam, jax.numpy.outer(x, x)), lam)

    x = np.linspace(0.1, 1.0, 12).reshape(3, 4)
    plain = [(np.sin(r) * 2.5, np.outer(r, r)) for r in x]
    for lam, axes in ((2.5, (0, None)), (np.full(3, 2.5), (0, 0))):
        a, b = jaxsetup.jit(jax.vmap(fn, in_axes=axes))(x, lam)
        np.testing.assert_allclose(np.asarray(a), np.stack([p[0] for p in plain]),
                                   rtol=1e-14)
        np.testing.assert_allclose(np.asarray(b), np.stack([p[1] for p in plain]),
                                   rtol=1e-14)
    a, _ = jaxsetup.jit(fn)(x[0], np.nan)      # a non-finite scalar: nan, as fn would give
    assert np.all(np.isnan(np.asarray(a)))
