"""Axisymmetric equilibria of the shell BVP with each method (Chebyshev, shooting, collocation).

References are independent of the solvers: the undeformed cap (closed form), the other
method, the first variation of the energy computed by quadrature (not from the ODEs), the
mirror symmetry of the free cap about the flat state, mesh/step refinement, and the limit of
smoothed stimuli for exact interfaces.
"""

import math
from functools import lru_cache

import jax.numpy as jnp
import numpy as np
import pytest

import shellbvp
from shellbvp import Chebyshev, Collocation, Shooting, cap, solve
from shellbvp.bvp import ShellBVP

THETA = math.pi / 6
CAP = cap(THETA, 0.01, lam=1.0, model="relaxed", material="cg")


METHODS = {"collocation": Collocation(tol=1e-8), "shooting": Shooting(rtol=1e-10),
           "spectral": Chebyshev(nodes=24)}


@lru_cache(maxsize=None)
def branch(method, kappa_max=3.0):
    """Natural continuation in kappa from the undeformed cap, steps of 1."""
    out, guess = {}, None
    for k in np.arange(1.0, kappa_max + 0.5, 1.0):
        guess = solve(CAP, k, method=METHODS[method], guess=guess, estimate_error=False)
        out[float(k)] = guess
    return out


@pytest.mark.parametrize("method", [pytest.param(m, marks=pytest.mark.slow) if m == "shooting"
                                    else m for m in sorted(METHODS)])
def test_zero_stimulus_recovers_undeformed_cap(method):
    eq = solve(CAP, 0.0, method=METHODS[method], estimate_error=False)
    assert eq.success
    s = eq.s
    assert np.max(np.abs(eq.r - np.sin(s))) <= 1e-10
    assert np.max(np.abs(eq.z - (np.cos(s) - 1))) <= 1e-10
    assert np.max(np.abs(eq.theta - s)) <= 1e-10
    assert abs(eq.w) <= 1e-10 and abs(eq.energy) <= 1e-15


@pytest.mark.slow
def test_methods_agree_at_strongly_deformed_state():
    """Theta = pi/6, h = 0.01, lam = 1, kappa R0 = 3, relaxed CG: (r, z, theta) to 1e-7."""
    a, b, c = branch("collocation")[3.0], branch("shooting")[3.0], branch("spectral")[3.0]
    grid = np.linspace(a.s[0], THETA, 400)
    assert np.max(np.abs(a(grid)[:3] - b(grid)[:3])) <= 1e-7
    assert np.max(np.abs(c(grid)[:3] - b(grid)[:3])) <= 1e-7
    assert abs(a.w - b.w) <= 1e-7 and abs(c.w - b.w) <= 1e-7
    assert a.w > 0.01  # strongly deformed: the edge moved by more than 1% of R0


def first_variation(eq, kappa, phi, dphi, psi, n=4000):
    """d/d delta of E[theta + delta phi, lam1 + delta psi] at delta = 0, by the complex step,
    with E = 2 pi int W(lam1, r/sin s, -theta'/lam1, -sin(theta)/r) sin s ds computed by
    Gauss-Legendre quadrature and r = r(eps) + int lam1 cos(theta) ds."""
    from scipy.integrate import cumulative_simpson

    sc = eq.scene
    s = np.linspace(eq.s[0], sc.length, 2 * n + 1)
    y = eq.unknowns(s)
    X, _ = ShellBVP(sc).state(s[None, :], y[None], eq.p)
    lam1, k1 = X[0, 0], X[0, 2]
    th, r = y[2], y[0]
    dth = -lam1 * k1
    d = 1e-20
    dr = cumulative_simpson(psi(s) * np.cos(th) - lam1 * np.sin(th) * phi(s), x=s, initial=0.0)
    l1c = lam1 + 1j * d * psi(s)
    thc = th + 1j * d * phi(s)
    rc = r + 1j * d * dr
    kb = kappa - 1.0
    W = shellbvp.energy_density(l1c, rc / np.sin(s), -(dth + 1j * d * dphi(s)) / l1c,
                                -np.sin(thc) / rc, kb, kb, h=sc.h, lam=sc.lam, model=sc.model,
                                material=sc.material)
    integrand = np.imag(W) / d * np.sin(s)
    from scipy.integrate import simpson

    return 2 * math.pi * simpson(integrand, x=s)


def test_equilibrium_is_stationary_for_the_energy():
    eq = branch("collocation")[3.0]
    off = branch("collocation")[2.0]  # a kappa = 2 equilibrium is not one at kappa = 3
    tests = [
        (lambda s: np.sin(math.pi * s / THETA), lambda s: math.pi / THETA * np.cos(math.pi * s / THETA),
         lambda s: 0 * s),
        (lambda s: s**2, lambda s: 2 * s, lambda s: np.cos(3 * s)),
        (lambda s: 0 * s, lambda s: 0 * s, lambda s: 1 + s),
    ]
    for phi, dphi, psi in tests:
        at_eq = first_variation(eq, 3.0, phi, dphi, psi)
        scale = abs(first_variation(off, 3.0, phi, dphi, psi))
        assert scale > 1e-6
        assert abs(at_eq) <= 1e-6 * scale, (at_eq, scale)


def test_mirror_symmetry_of_free_cap():
    """Reflection through the flat state with the thickness flipped maps kappa -> 2 - kappa:
    (r, z, theta) -> (r, -z, -theta), and w -> 2 (1 - cos Theta) - w."""
    a = solve(CAP, 0.5, estimate_error=False)

    def mirrored(e):
        return lambda s: e.unknowns(s) * np.array([1, -1, -1, -1, 1, -1])[:, None]

    b = solve(CAP, 1.5, guess=mirrored(a), estimate_error=False)
    grid = np.linspace(a.s[0], THETA, 300)
    ya, yb = a(grid), b(grid)
    assert np.max(np.abs(yb[0] - ya[0])) <= 1e-9
    assert np.max(np.abs(yb[1] + ya[1])) <= 1e-9
    assert np.max(np.abs(yb[2] + ya[2])) <= 1e-9
    assert abs(b.w - (2 * (1 - math.cos(THETA)) - a.w)) <= 1e-9


def test_result_does_not_depend_on_the_pole_offset():
    """The series hand-over at s = eps has error O(eps^4): w agrees over two decades of eps."""
    w = [solve(CAP, 2.0, eps=e * THETA, estimate_error=False).w for e in (1e-2, 1e-3, 1e-4)]
    assert abs(w[0] - w[2]) <= 1e-9 and abs(w[1] - w[2]) <= 1e-10


@pytest.mark.slow  # minutes; the default suite keeps a faster check of the same kind
def test_collocation_order_under_mesh_refinement():
    """solve_bvp is 4th-order collocation: error in w ~ nodes^-4 (fitted slope in [-5, -3])."""
    ref = solve(CAP, 2.0, method=Collocation(tol=1e-9), estimate_error=False)
    n, err = [], []
    for tol in (1e-4, 1e-5, 1e-6, 1e-7):
        e = solve(CAP, 2.0, method=Collocation(tol=tol, nodes=11), guess=ref,
                  estimate_error=False)
        n.append(e.stats["nodes"])
        err.append(abs(e.w - ref.w))
    slope = np.polyfit(np.log(n), np.log(err), 1)[0]
    assert -5.0 <= slope <= -3.0, (n, err, slope)


@pytest.mark.slow   # ~110 s: one compiled shooting program per step count
def test_shooting_order_under_step_refinement():
    """Tsit5 is 5th order: with fixed steps per segment (2 segments) the error in (r, z, theta)
    at the nodes falls like steps^-5 (measured slope ~ -5.6); reference: 256 steps."""
    guess = branch("collocation")[1.0]
    run = lambda k: solve(CAP, 1.0, method=Shooting(segments=2, steps=k), guess=guess,  # noqa: E731
                          estimate_error=False)
    ref = run(256)
    steps = (8, 16, 32)
    err = []
    for k in steps:
        e = run(k)
        err.append(np.max(np.abs([e.r - ref.r, e.z - ref.z, e.theta - ref.theta])))
    slope = np.polyfit(np.log(steps), np.log(err), 1)[0]
    assert -6.2 <= slope <= -4.5, (err, slope)


@pytest.mark.slow  # minutes; the default suite keeps a faster check of the same kind
def test_exact_interfaces_are_the_limit_of_smoothed_steps():
    """A patch stimulus s < Theta/4 (clamped edge, apex free): the two-piece solve with exact
    interface conditions is the limit of one-piece solves with tanh-smoothed steps."""
    sb = THETA / 4
    k_patch = 3.0

    def patch(x, p):
        one = 0.0 * x.s + 1.0
        kb = (p - 1.0) * one if x.piece == 0 else -one
        return one, one, kb, kb

    exact = cap(THETA, 0.01, ends=("pole", "clamped"), fields=patch, breaks=(sb,))
    coll = Collocation(tol=1e-8)
    ref = solve(exact, k_patch, method=coll, estimate_error=False)
    # the spectral method on the same two-piece scene agrees with solve_bvp's mesh
    spec = solve(exact, k_patch, method=Chebyshev(nodes=40), guess=ref)
    grid = np.linspace(ref.s[0], THETA, 500)
    assert np.max(np.abs(spec(grid)[:3] - ref(grid)[:3])) < 1e-7 and spec.error_estimate < 1e-9
    diffs = []
    for width in (0.02, 0.01, 0.005):
        def smooth(x, p, width=width):
            step = 0.5 * (1 - jnp.tanh((x.s - sb) / width))   # fields are traced by JAX
            one = 0.0 * x.s + 1.0
            kb = -one + p * step
            return one, one, kb, kb

        sm = solve(cap(THETA, 0.01, ends=("pole", "clamped"), fields=smooth),
                   k_patch, method=coll, estimate_error=False)
        grid = np.linspace(ref.s[0], THETA, 500)
        diffs.append(np.max(np.abs(sm(grid)[:3] - ref(grid)[:3])))
    assert diffs[0] > diffs[1] > diffs[2]
    order = np.polyfit(np.log([0.02, 0.01, 0.005]), np.log(diffs), 1)[0]
    assert order >= 0.9, (diffs, order)
    # The boundary conditions hold: clamped edge at the reference values, no apex force.
    assert abs(ref.r[-1] - math.sin(THETA)) < 1e-10 and abs(ref.theta[-1] - THETA) < 1e-10
    assert np.max(np.abs(ref.F_z)) < 1e-14


@pytest.mark.parametrize("kwargs,name", [
    (dict(theta=0.0, h=0.01), "theta"), (dict(theta=math.pi, h=0.01), "theta"),
    (dict(theta=0.5, h=0.0), "h"), (dict(theta=0.5, h=1.0), "h"),
    (dict(theta=0.5, h=0.01, lam=-1.0), "lam"),
    (dict(theta=0.5, h=0.01, ends=("pinned", "free")), "end kind"),
    (dict(theta=0.5, h=0.01, ends=("pole", "simply")), "end kind"),
    (dict(theta=0.5, h=0.01, ends=("free", "free")), "on the axis"),
    (dict(theta=0.5, h=0.01, ends=("pole", "pole")), "not on the axis"),
    (dict(theta=0.5, h=0.01, breaks=(0.7,)), "breaks"),
    (dict(theta=0.5, h=0.01, field_parameters=(math.nan,)), "field_parameters"),
    (dict(theta=0.5, h=0.01, field_parameters="1.0"), "field_parameters"),
    (dict(theta=0.5, h=0.01, field_parameters=((1.0, 2.0),)), "field_parameters"),
])
def test_bad_scene_is_named(kwargs, name):
    with pytest.raises(ValueError, match=name):
        cap(**kwargs)


def _scaled(x, kappa, c):
    """uniform_curvature with kappa scaled by the field parameter c[0]."""
    one = 0.0 * x.s + 1.0
    return one, one, (c[0] * kappa - 1.0) * one, (c[0] * kappa - 1.0) * one


def test_field_parameters_are_program_arguments():
    """A scene's field parameters reach the fields at run time: with kappa scaled by c,
    kappa = 2 at c = 1.5 and 0.5 is the plain cap (another program, the fields'
    own code) at kappa = 3 and 1; scenes that differ only in c share one set of compiled
    programs."""
    kw = dict(theta=THETA, h=0.01, lam=1.0, model="relaxed", material="cg")
    one = cap(fields=_scaled, field_parameters=(1.5,), **kw)
    other = cap(fields=_scaled, field_parameters=(0.5,), **kw)
    assert ShellBVP(one)._k is ShellBVP(other)._k
    for scene, kappa in ((one, 3.0), (other, 1.0)):
        a = solve(scene, 2.0, method=Chebyshev(nodes=24), estimate_error=False)
        b = solve(CAP, kappa, method=Chebyshev(nodes=24), estimate_error=False)
        assert a.w == pytest.approx(b.w, abs=1e-13)
        assert np.max(np.abs(a.r - b.r)) < 1e-13 and np.max(np.abs(a.z - b.z)) < 1e-13


def test_bad_solve_arguments_are_named():
    with pytest.raises(ValueError, match="method"):
        solve(CAP, 1.0, method="chebfun")
    with pytest.raises(ValueError, match="nodes"):
        solve(CAP, 1.0, method=Chebyshev(nodes=3))
    with pytest.raises(ValueError, match="guess"):
        solve(CAP, 1.0, guess=3.0)
    with pytest.raises(ValueError, match="kappa"):
        solve(CAP, float("nan"))
    bad = cap(0.5, 0.01, fields=lambda x, p: (1.0 + 0 * x.s, 1.0 + 0 * x.s, np.nan + x.s, x.s))
    with pytest.raises(ValueError, match="kb1 must be finite"):
        solve(bad, 1.0)
    numpy_only = cap(0.5, 0.01, fields=lambda x, p: (1.0, 1.0, np.tanh(x.s), p))
    with pytest.raises(ValueError, match="fields must be written with array arithmetic"):
        solve(numpy_only, 1.0)


def test_unconverged_solve_is_flagged_not_returned():
    """Far beyond the fold with no guess the corrector fails: it raises with diagnostics,
    or with throw=False returns success=False and NaN observables."""
    with pytest.raises(shellbvp.ConvergenceError, match="kappa"):
        solve(CAP, 40.0, estimate_error=False)
    eq = solve(CAP, 40.0, method=Collocation(max_nodes=300), estimate_error=False, throw=False)
    assert not eq.success and math.isnan(eq.w)
    with pytest.raises(shellbvp.ConvergenceError, match="did not converge"):
        eq(np.array([0.1]))     # a failed result has no shape to give
