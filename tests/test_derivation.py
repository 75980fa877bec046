"""The reduced energy against independent routes: 3D quadrature, stress-free states,
classical linear plate theory, and the variational properties the derivation claims."""

import numpy as np
import pytest
import sympy as sp

import shellbvp
from shellbvp import reduction as R
from conftest import random_states

CASES = [
    ("plane_strain", "cg", (1.0, 0.0, 0.0)),
    ("relaxed", "cg", (1.0, 0.0, 0.0)),
    ("relaxed", "nh", (1.0, 0.0, 0.0)),
    ("plane_strain", "cg", (1.15, 0.4, -0.6)),
    ("relaxed", "cg", (1.15, 0.4, -0.6)),
    ("relaxed", "nh", (0.9, -0.3, 0.5)),
]


def complex_step_grad(fun, x, eps=1e-30):
    """Gradient by the complex step (exact to round-off: no subtraction)."""
    x = np.asarray(x, dtype=complex)
    g = np.empty(len(x))
    for i in range(len(x)):
        xp = x.copy()
        xp[i] += 1j * eps
        g[i] = np.imag(fun(xp)) / eps
    return g


@pytest.mark.parametrize("model,material,rhob", CASES)
def test_truncation_error_is_fourth_order_in_h(model, material, rhob):
    """W (reduced) - W (Gauss-Legendre through the thickness, no truncation) = O(h^4):
    the reduction keeps Z^0 and Z^2, and the odd terms integrate to zero."""
    hs = np.logspace(-1, -3, 5)
    for st in random_states(7, n=4):
        opts = dict(lam=1.7, model=model, material=material,
                    rhob1=rhob[0], rhob2=rhob[1], rhob3=rhob[2])
        err = [abs(shellbvp.energy_density(*st, h=h, **opts)
                   - shellbvp.energy_density(*st, h=h, exact=True, **opts)) for h in hs]
        slope = np.polyfit(np.log(hs), np.log(err), 1)[0]
        assert 3.7 <= slope <= 4.3, (st, err, slope)


@pytest.mark.parametrize("model,material", [("plane_strain", "cg"), ("relaxed", "cg"),
                                            ("relaxed", "nh")])
def test_stress_free_state_has_zero_energy_and_gradient(model, material):
    """lam1 = lam2 = 1, k = kb (no through-thickness stimulus): the current 3D metric equals
    the target one, so W = 0 and it is stationary in (lam1, lam2, k1, k2)."""
    for _, _, c1, c2, *_ in random_states(11, n=5):
        for lam in (0.1, 1.0, 10.0):
            fun = lambda x: shellbvp.energy_density(  # noqa: E731
                *x, c1, c2, h=0.05, lam=lam, model=model, material=material)
            assert abs(fun([1.0, 1.0, c1, c2])) < 1e-14
            assert np.max(np.abs(complex_step_grad(fun, [1.0, 1.0, c1, c2]))) < 1e-13
            exact = shellbvp.energy_density(1.0, 1.0, c1, c2, c1, c2, h=0.05, lam=lam,
                                            model=model, material=material, exact=True)
            assert abs(exact) < 1e-14


# Classical linear theory (independent: small-strain elasticity with Lame moduli mu* = 1 and
# lambda* = lam; the Ciarlet-Geymonat density linearises to tr(E^2) + lam/2 tr(E)^2).
# Plate strain through the thickness E_aa = -Z k_a; stretching E_aa = e_a.
#   plane strain (E33 = 0):              q(e) = e1^2 + e2^2 + lam/2 (e1 + e2)^2
#   plane stress (E33 free, 'relaxed'):  q(e) = e1^2 + e2^2 + lam/(lam + 2) (e1 + e2)^2
#   incompressible (E33 = -(e1 + e2)):   q(e) = 2 (e1^2 + e2^2 + e1 e2)
# w_s = q(e) and w_b = q(k) (the mean of Z^2 over the thickness is h^2/12).
def classical(model, material, lam, a, b):
    if material == "nh":
        return 2 * (a * a + b * b + a * b)
    coef = lam / 2 if model == "plane_strain" else lam / (lam + 2)
    return a * a + b * b + coef * (a + b) ** 2


@pytest.mark.parametrize("model,material", [("plane_strain", "cg"), ("relaxed", "cg"),
                                            ("relaxed", "nh")])
@pytest.mark.parametrize("lam", [0.1, 1.0, 10.0])
def test_flat_plate_limit_is_classical_linear_plate(model, material, lam):
    rng = np.random.default_rng(5)
    for _ in range(3):
        a, b = rng.uniform(-1, 1, 2)
        ratios = []
        for eps in (1e-3, 1e-4):
            ws, wb, _, _ = shellbvp.energy_terms(1.0, 1.0, eps * a, eps * b, 0.0, 0.0,
                                                 lam=lam, model=model, material=material)
            ratios.append(wb / eps**2)
            assert abs(ws) < 1e-15
        ref = classical(model, material, lam, a, b)
        assert abs(ratios[-1] - ref) <= 1e-3 * abs(ref)
        # O(eps) correction: it shrinks tenfold from eps = 1e-3 to 1e-4.
        assert abs(ratios[-1] - ref) <= 0.2 * abs(ratios[0] - ref) + 1e-12
        ws, *_ = shellbvp.energy_terms(1 + 1e-4 * a, 1 + 1e-4 * b, 0.0, 0.0, 0.0, 0.0,
                                       lam=lam, model=model, material=material)
        assert ws / 1e-8 == pytest.approx(ref, rel=2e-3)


def test_relaxed_rho1_and_rho2_are_minimisers(states):
    """rho1 minimises w_s and rho2 minimises w_b (second derivatives positive, first zero)."""
    red = R.derive("relaxed", "cg")
    for st in states:
        sub = dict(zip(R.STATE, st)) | {R.lam: 2.0, R.rhob1: 1.1, R.rhob2: 0.2, R.rhob3: -0.3}
        r1 = float(red.rho1.subs(sub))
        d1 = sp.diff(red.w_s, R.rho1).subs(sub | {R.rho1: r1})
        dd1 = sp.diff(red.w_s, R.rho1, 2).subs(sub | {R.rho1: r1})
        assert abs(float(d1)) < 1e-12 and float(dd1) > 0
        r2 = float(red.rho2.subs(sub | {R.rho1: r1}))
        wb = red.w_b.subs(sub | {R.rho1: r1, R.rho3: 0})
        assert abs(float(sp.diff(wb, R.rho2).subs(R.rho2, r2))) < 1e-10
        assert float(sp.diff(wb, R.rho2, 2)) > 0


def test_rho3_drops_out_of_relaxed_bending_energy(states):
    """The coefficient of rho3 in w_b is proportional to dw_s/drho1, zero at the optimum
    (why the relaxed model may set rho3 = 0; the paper's Section 4.2 remark)."""
    red = R.derive("relaxed", "cg")
    for st in states:
        sub = dict(zip(R.STATE, st)) | {R.lam: 0.7, R.rhob1: 0.9, R.rhob2: -0.1, R.rhob3: 0.2}
        r1 = float(red.rho1.subs(sub))
        c3 = sp.diff(red.w_b, R.rho3).subs(sub | {R.rho1: r1, R.rho2: 0.37, R.rho3: 0.5})
        assert abs(float(c3)) < 1e-12


def test_nh_thickness_map_is_isochoric():
    """J(Z) = 1 through the thickness: exactly for the quadrature map (to round-off), and
    to O(Z^3) for the reduced series phi = rho1 Z + rho2 Z^2 + rho3 Z^3 (its error is O(Z^4)
    in phi, so O(Z^3) in phi')."""
    st = (1.1, 0.93, 0.7, -1.3, 0.4, -0.6)
    rb = (1.1, 0.2, -0.3)
    l1, l2, c1, c2, cb1, cb2 = st
    red = R.derive("relaxed", "nh")
    sub = dict(zip(R.STATE, st)) | dict(zip(R.STIMULUS, rb))
    r1 = float(red.rho1.subs(sub))
    r2 = float(red.rho2.subs(sub))
    r3 = float(red.rho3.subs(sub))

    def J(phi, dphi, phib, dphib):
        return (l1 * l2 * (1 - phi * c1) * (1 - phi * c2) * dphi
                / ((1 - phib * cb1) * (1 - phib * cb2) * dphib))

    Zs = np.array([0.04, 0.02, 0.01])
    phi, dphi, phib, dphib = shellbvp.energy.thickness_map(Zs, *st, material="nh", rhob1=rb[0],
                                                    rhob2=rb[1], rhob3=rb[2])
    assert np.max(np.abs(J(phi, dphi, phib, dphib) - 1)) < 1e-14
    ser = J(r1 * Zs + r2 * Zs**2 + r3 * Zs**3, r1 + 2 * r2 * Zs + 3 * r3 * Zs**2, phib, dphib)
    slope = np.polyfit(np.log(Zs), np.log(np.abs(ser - 1)), 1)[0]
    assert 2.7 < slope < 3.3


def test_derivation_is_cached_on_disk(tmp_path, monkeypatch):
    """A second process-level derivation loads the pickle instead of recomputing."""
    from shellbvp import cache

    monkeypatch.setenv("SHELLBVP_CACHE_DIR", str(tmp_path))
    calls = []
    value = cache.memo("k", lambda: calls.append(1) or {"x": sp.Symbol("x") + 1})
    again = cache.memo("k", lambda: calls.append(1) or None)
    assert calls == [1] and again == value
    assert len(list(tmp_path.glob("*.pkl"))) == 1


def test_generated_code_reloads_from_disk_without_sympy(tmp_path, monkeypatch):
    """Code that is not shipped (here under a label of its own) is lambdified once, kept on
    disk as source and exec'd with jax.numpy in a later process (no sympy): the reloaded
    function is the same function. Reference: the freshly lambdified one, on random
    states."""
    import numpy as np

    from shellbvp import codegen

    monkeypatch.setenv("SHELLBVP_CACHE_DIR", str(tmp_path))
    calls = []

    def build():
        calls.append(1)
        return codegen._build_energy("relaxed", "cg", "through-thickness")

    def refuse():
        raise AssertionError("the disk entry was not used")

    label = "test-energy/relaxed/cg/through-thickness"
    codegen._functions(label, build)                       # generates, keeps the source
    reloaded = codegen._functions(label, refuse)["W"]      # a later process: disk only
    # the generated source is the disk entry read back (the sympy derivation that build()
    # ran may keep entries of its own beside it, or not where it ran earlier in-process)
    from shellbvp import cache

    entry = tmp_path / f"{cache.key('generated-jax', codegen.derivation_digest(), label)}.pkl"
    assert calls == [1] and entry.exists()
    fresh = build()["W"]
    rng = np.random.default_rng(3)
    for _ in range(5):
        x = (*rng.uniform(0.8, 1.2, 2), *rng.uniform(-2, 2, 4), 1.0, 0.01, 0.75, 0.1, -0.2)
        assert float(reloaded(*x)) == float(fresh(*x))


def test_exported_kernels_reload_from_disk_without_tracing(tmp_path, monkeypatch):
    """A compiled kernel is traced once, by jax.export, and kept on disk: a later Packed with
    the same key deserialises it instead of tracing (tracing is refused here) and computes
    the same numbers. Reference: the freshly traced program."""
    import numpy as np
    from jax import export

    from shellbvp.jaxsetup import jax
    from shellbvp.packed import Packed

    import jax.numpy as jnp

    monkeypatch.setenv("SHELLBVP_CACHE_DIR", str(tmp_path))

    def fn(x, k):
        return jnp.sin(x) * k, (jnp.sum(x) > 0, jnp.linalg.solve(jnp.eye(2) * k, x[:2]))

    x = np.array([0.3, -1.2, 2.0])
    fresh = Packed(fn, key="test-kernel")(x, 2.0)

    def refuse(*args, **kwargs):
        raise AssertionError("traced again instead of reading the disk entry")

    monkeypatch.setattr(export, "export", refuse)
    reloaded = Packed(fn, key="test-kernel")(x, 2.0)
    for a, b in zip(jax.tree_util.tree_leaves(fresh), jax.tree_util.tree_leaves(reloaded)):
        assert np.asarray(a).dtype == np.asarray(b).dtype
        assert np.array_equal(a, b)


def test_kernel_disk_keys_cover_only_code_the_package_hashes():
    """Kernels go to disk only when the scene's functions are the package's own code (a
    module-level function); a user's closure keeps its programs in memory (its code is not
    in the package's hash). The budding cases differ only in their field parameters,
    arguments of the programs, not code: one key."""
    from shellbvp.kernels import disk_key
    from shellbvp.problems import budding, pressure_cap

    a = disk_key((budding.scene(0.0, 1.0).fields, None), "x")
    b = disk_key((budding.scene(0.0, 0.5).fields, None), "x")
    c = disk_key((None, pressure_cap.pressure), "x")
    assert a and c and a == b and a != c
    assert disk_key((lambda x, p: (1.0, 1.0, -1.0, -1.0), None), "x") is None
