"""The XLA options every compiled program of the package gets (shellbvp.jaxsetup): refused
options are left out rather than failing at a solver's first call, and the options do not
change the numbers (XLA:CPU's two code generators compute the same arithmetic: the relaxed
energy's jet agrees to round-off); and the conditional that keeps a W-jet out of XLA's
fusion (shellbvp.compiled.materialised) returns the values of the function it wraps."""

import numpy as np

from shellbvp import jaxsetup
from shellbvp.compiled import energy_function
from shellbvp.jaxsetup import jax


def test_an_unknown_option_is_left_out():
    assert jaxsetup.supported_options((("xla_no_such_option_of_any_jaxlib", True),)) == {}
    assert jaxsetup.supported_options(()) == {}


def test_the_package_options_are_given_where_this_jaxlib_knows_them():
    options = jaxsetup.supported_options()
    assert options in ({}, dict(jaxsetup.COMPILER_OPTIONS))
    # every key a real option: compiling with them must succeed
    jax.jit(lambda x: 2.0 * x).lower(1.0).compile(compiler_options=options)


def test_options_leave_the_energy_jet_unchanged():
    W = energy_function("relaxed", "cg", 1.0)

    def jet(X, kb, lam, h):
        def w(x):
            return W(x[0], x[1], x[2], x[3], kb[0], kb[1], lam, h)
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
