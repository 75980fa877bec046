"""Analytic derivatives against finite differences: the nodal df/dy (implicit
differentiation of the constitutive equations) and df/dp, the boundary conditions' Jacobians,
and the assembled dR/dU, dR/dp of every method. Reference: central differences of the same
functions' values (no derivative code involved), step 1e-6, so agreement to ~1e-7 relative."""

import math

import numpy as np
import pytest

from shellbvp import Chebyshev, Collocation, Shooting, cap, solve
from shellbvp.bvp import ShellBVP

THETA = math.pi / 6
CAP = cap(THETA, 0.01, lam=1.0, model="relaxed", material="cg")
STEP = 1e-6


@pytest.fixture(scope="module")
def state():
    """A strongly deformed equilibrium (kappa R0 = 3), perturbed so that nothing vanishes."""
    eq = solve(CAP, 3.0, estimate_error=False)
    bvp = ShellBVP(CAP)
    s = np.linspace(bvp.a[0], THETA, 9)[None, :]
    rng = np.random.default_rng(1)
    Y = eq.unknowns(s[0])[None] * (1 + 1e-3 * rng.standard_normal((1, 6, 9)))
    return bvp, s, Y, 3.0


def test_nodal_jacobian_and_parameter_derivative(state):
    bvp, s, Y, p = state
    nod = bvp.rhs(s, Y, p)
    # per row of df/dy and node: the entries span ~10 decades near the pole (1/sin s)
    scale = np.max(np.abs(nod.J), axis=2) + 1.0                       # (1, 6, nodes)
    for c in range(6):
        e = np.zeros_like(Y)
        e[:, c] = 1e-5 * np.abs(Y[:, c]) + 1e-9    # relative: r ~ 5e-5 at the pole offset
        fd = (bvp.rhs(s, Y + e, p).f - bvp.rhs(s, Y - e, p).f) / (2 * e[:, c][:, None, :])
        assert np.max(np.abs(nod.J[:, :, c] - fd) / scale) <= 1e-6, c
    dp = 1e-4    # f is smooth in p: truncation ~1e-8, round-off of the large m, f rows ~1e-10
    fdp = (bvp.rhs(s, Y, p + dp).f - bvp.rhs(s, Y, p - dp).f) / (2 * dp)
    row = np.max(np.abs(nod.fp), axis=-1, keepdims=True) + 1e-12
    assert np.max(np.abs(nod.fp - fdp) / row) <= 1e-6


@pytest.fixture(scope="module")
def budding_state():
    """The budding cap with eta = (0.5, 1): a metric stimulus and an anisotropic target
    curvature at the apex (the log-mode pole condition, which needs third derivatives of W),
    at kbar = 5 in a perturbed undeformed state."""
    from shellbvp.problems import budding

    bvp = ShellBVP(budding.scene(0.5, 1.0))
    assert bvp.anisotropic_apex
    s = np.concatenate([bvp.s_of(i, np.linspace(0, 1, 5)) for i in range(bvp.P)])[None, :]
    rng = np.random.default_rng(2)
    Y = bvp.reference(s[0])[None] * (1 + 1e-3 * rng.standard_normal((1, 6, s.size)))
    return bvp, s, Y, 5.0


@pytest.mark.parametrize("which", ["cap", "budding"])
def test_boundary_jacobians(which, request):
    bvp, s, Y, p = request.getfixturevalue("state" if which == "cap" else "budding_state")
    ya, yb = Y[0, :, 0], Y[0, :, -1]
    ya[3:] += 1e-3                 # nonzero moment and forces at the pole
    r, Ja, Jb, Jp = bvp.boundary(ya, yb, p)
    scale = np.max(np.abs(np.hstack([Ja, Jb])), axis=1) + 1.0
    for k in range(6):
        ea, eb = np.zeros(6), np.zeros(6)
        ea[k] = 1e-5 * abs(ya[k]) + 1e-9    # relative steps: r(eps) ~ 5e-5
        eb[k] = 1e-5 * abs(yb[k]) + 1e-9
        fa = (bvp.boundary(ya + ea, yb, p)[0] - bvp.boundary(ya - ea, yb, p)[0]) / (2 * ea[k])
        fb = (bvp.boundary(ya, yb + eb, p)[0] - bvp.boundary(ya, yb - eb, p)[0]) / (2 * eb[k])
        assert np.max(np.abs(Ja[:, k] - fa) / scale) <= 1e-6
        assert np.max(np.abs(Jb[:, k] - fb) / scale) <= 1e-6
    fp = (bvp.boundary(ya, yb, p + STEP)[0] - bvp.boundary(ya, yb, p - STEP)[0]) / (2 * STEP)
    assert np.max(np.abs(Jp - fp)) <= 1e-6


@pytest.mark.parametrize("method", [Chebyshev(nodes=12), Collocation(nodes=12),
                                    pytest.param(Shooting(segments=3, rtol=1e-12),
                                                 marks=pytest.mark.slow)],
                         ids=["spectral", "collocation", "shooting"])
def test_discrete_system_jacobians(state, method):
    bvp, _, _, p = state
    eq = solve(CAP, p, estimate_error=False)
    system = method.discretise(bvp)
    rng = np.random.default_rng(2)
    U = system.from_profile(eq.unknowns)
    U = U * (1 + 1e-4 * rng.standard_normal(U.size))
    R, J, Rp = system.evaluate(U, p)
    J = J.toarray() if hasattr(J, "toarray") else J
    cols = rng.choice(U.size, size=min(U.size, 12), replace=False)
    for k in cols:
        e = np.zeros_like(U)
        e[k] = STEP * (1 + abs(U[k]))
        fd = (system.evaluate(U + e, p)[0] - system.evaluate(U - e, p)[0]) / (2 * e[k])
        assert np.max(np.abs(J[:, k] - fd)) <= 1e-5 * (np.max(np.abs(J[:, k])) + 1.0), k
    fdp = (system.evaluate(U, p + STEP)[0] - system.evaluate(U, p - STEP)[0]) / (2 * STEP)
    assert np.max(np.abs(Rp - fdp)) <= 1e-5 * (np.max(np.abs(Rp)) + 1.0)


def test_explicit_2x2_solve_matches_lapack_and_differentiates():
    """The inner Newton's 2x2 solves (``solve_2x2``, the explicit inverse) against LAPACK's
    elimination with pivoting, for a vector and a matrix right-hand side, on matrices
    with condition numbers up to ~1e8 (error ~ cond eps), and its JAX derivative against
    central differences (the implicit derivatives of the roots go through it)."""
    import jax

    from shellbvp.compiled import solve_2x2

    rng = np.random.default_rng(3)
    for cond in (1.0, 1e4, 1e8):
        U, _ = np.linalg.qr(rng.standard_normal((2, 2)))
        V, _ = np.linalg.qr(rng.standard_normal((2, 2)))
        A = U @ np.diag([1.0, 1.0 / cond]) @ V * 10.0 ** rng.uniform(-3, 3)
        for b in (rng.standard_normal(2), rng.standard_normal((2, 7))):
            x = np.asarray(solve_2x2(A, b))
            ref = np.linalg.solve(A, b)
            assert np.max(np.abs(x - ref)) <= 50 * cond * 2.2e-16 * np.max(np.abs(ref))
    A, b = rng.standard_normal((2, 2)) + 3 * np.eye(2), rng.standard_normal(2)
    dA = rng.standard_normal((2, 2))
    _, jvp = jax.jvp(lambda M: solve_2x2(M, b), (A,), (dA,))
    fd = (np.linalg.solve(A + 1e-6 * dA, b) - np.linalg.solve(A - 1e-6 * dA, b)) / 2e-6
    assert np.max(np.abs(np.asarray(jvp) - fd)) <= 1e-8


@pytest.mark.parametrize("terms,poles", [
    (((1.0, "z", 1), (-1.0, "z", 0)), (True, False)),      # a cap with a free edge
    (((1.0, "z", 0), (-1.0, "z", 1)), (True, True)),       # a closed shell
    (((1.0, "r", 1), (-2.0, "theta", 0)), (False, False)),
])
def test_observable_gradient_in_closed_form_is_jax_gradient(terms, poles):
    """The monitor and its gradients, written once in closed form for numpy (the host) and
    jax.numpy (the kernels): the same values from both, and gradients equal to JAX's
    automatic gradient of the value (reference: autodiff, not the closed form)."""
    from shellbvp.jaxsetup import jax            # float64 on
    from shellbvp.kernels import monitor_and_gradient

    jnp = jax.numpy

    rng = np.random.default_rng(7)
    for _ in range(5):
        ya, yb = rng.normal(size=6), rng.normal(size=6)
        refs = [dict(zip(("r", "z", "theta"), rng.normal(size=3))) for _ in range(2)]
        scale = rng.uniform(0.1, 3.0)

        def mon(a, b, xp):
            return monitor_and_gradient(a, b, terms, poles, refs, scale, xp)

        m, (ga, gb) = mon(ya, yb, np)
        mj, (gaj, gbj) = mon(jnp.asarray(ya), jnp.asarray(yb), jnp)
        auto_a, auto_b = jax.grad(lambda a, b: mon(a, b, jnp)[0],
                                  argnums=(0, 1))(jnp.asarray(ya), jnp.asarray(yb))
        assert float(mj) == pytest.approx(float(m), rel=1e-14)
        np.testing.assert_allclose(ga, np.asarray(auto_a), rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(gb, np.asarray(auto_b), rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(np.asarray(gaj), ga, rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(np.asarray(gbj), gb, rtol=1e-14, atol=1e-15)
