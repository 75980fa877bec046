"""Branch points of an axisymmetric branch (n = 0 without a fold): located on the discrete
system with an error estimate (shellbvp.continuation.branch_points), reported by
first_instability as an axisymmetric bifurcation.

Reference: the simply supported circular plate (radius a, free to slide radially: a roller
end) under the uniform radial edge compression q (force per unit edge length) buckles
axisymmetrically where x = sqrt(q a^2 / D) solves x J0(x) - (1 - nu) J1(x) = 0 (Timoshenko
& Gere, *Theory of Elastic Stability*, 2nd ed., Sec. 8.2: q_cr a^2 / D = 4.198 at
nu = 0.3). Kirchhoff's theory drops the membrane prebuckling strain, of relative order
(t/a)^2: the located value must approach the Bessel root like (t/a)^2.
"""

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from scipy.special import j0, j1

import shellbvp
from shellbvp import End, Scene
from shellbvp.continuation.branch_points import (locate_branch_point,
                                                 null_vectors, refine_branch_point,
                                                 test_function as bordered_test)
from shellbvp.errors import ConvergenceError
from shellbvp.geometry import disc

NU = 0.3


def bessel_root(nu=NU):
    """x^2 = q_cr a^2 / D of the simply supported plate (module docstring)."""
    x = brentq(lambda x: x * j0(x) - (1.0 - nu) * j1(x), 1.0, 3.0, xtol=1e-15)
    return x * x


def test_bessel_root_is_the_book_value():
    # mpmath at 30 digits: x = 2.048850203642126, x^2 = 4.197787156964382
    assert bessel_root() == pytest.approx(4.197787156964382, abs=1e-13)
    assert round(bessel_root(), 3) == 4.198


def plate_under_edge_compression(a_over_t, nu=NU):
    """The plate of radius 1 on a roller edge (z held, r free, no moment) under the inward
    radial line load q (per mu h): the parameter."""
    return Scene(geometry=disc(1.0), h=1.0 / a_over_t, material="koiter", nu=nu,
                 ends=("pole", End("roller", radial=lambda q: -q)), parameter="q")


def load_factor(a_over_t, nu=NU):
    """q a^2 / D per engine unit of q (q per mu h, D per mu a^3): 6 (1 - nu) (a/t)^2."""
    return 6.0 * (1.0 - nu) * a_over_t ** 2


# ---- a two-unknown pitchfork: R = (a - p^2, (a - 1) b + b^3) -----------------------------------
class Pitchfork:
    """The trivial branch a = p^2, b = 0 has a branch point at p = 1 (null vector (0, 1)); rows
    and unknowns scaled by ``scale`` to show that the borders do not depend on the scaling.
    ``stall``: Newton fails inside that interval of p (a solver that gives up)."""

    size = 2

    def __init__(self, scale=(1.0, 1.0), stall=None):
        self.scale, self.stall = np.asarray(scale, float), stall

    def evaluate(self, U, p):
        if self.stall is not None and self.stall[0] < p < self.stall[1]:
            raise ConvergenceError("a solver that gives up here")
        a, b = U / self.scale
        R = np.array([a - p * p, (a - 1.0) * b + b ** 3]) * self.scale[::-1] ** 3
        J = np.array([[1.0, 0.0], [b, a - 1.0 + 3 * b * b]]) * np.outer(
            self.scale[::-1] ** 3, 1.0 / self.scale)
        Rp = np.array([-2.0 * p, 0.0]) * self.scale[::-1] ** 3
        return R, J, Rp

    def monitor(self, U):
        return float(U[1] / self.scale[1]), np.array([0.0, 1.0 / self.scale[1]])


def test_pitchfork_located_to_round_off_with_its_null_vectors():
    sys = Pitchfork(scale=(1e-6, 1e4))
    U = lambda p: np.array([p * p * 1e-6, 0.0])          # noqa: E731
    bp = locate_branch_point(sys, 0.7, 1.2, known=[(0.7, U(0.7))], xtol=1e-13)
    assert bp.converged and bp.p == pytest.approx(1.0, abs=1e-12)
    assert bp.bracket[0] <= bp.p <= bp.bracket[1]
    assert bp.error_estimate <= 2e-13
    # the null vector is the b direction, whatever the scaling of the rows and unknowns
    assert abs(bp.null[0]) < 1e-12 and bp.null[1] == 1.0
    assert abs(bp.left[0]) < 1e-12 and abs(bp.left[1]) == 1.0


def test_borders_do_not_depend_on_the_scaling():
    # J = diag(1e12, p - 1) at p = 0.9: the smallest singular vector of J is the second one
    # only because of the scale; with the first row scaled down it would not be
    J = np.diag([1e-12, -0.1])
    dJ = np.diag([0.0, 1.0])
    right, left, delta = null_vectors(J, dJ)
    assert abs(right[1]) == pytest.approx(1.0) and abs(left[1]) == pytest.approx(1.0)
    assert delta == pytest.approx(0.1)
    g, v, w = bordered_test(np.diag([1.0, 0.0]), np.array([0.0, 1.0]), np.array([0.0, 1.0]))
    assert g == 0.0 and v @ [0, 1] == 1.0


def test_stalled_location_returns_its_bracket():
    sys = Pitchfork(stall=(1 - 1e-4, 1 + 1e-4))
    bp = locate_branch_point(sys, 0.5, 1.5, known=[(0.5, np.array([0.25, 0.0]))], xtol=1e-12)
    assert not bp.converged and "stopped on the bracket" in bp.stats["stall"]
    lo, hi = bp.bracket
    assert lo <= 1.0 <= hi and hi - lo < 0.05
    assert abs(bp.p - 1.0) <= bp.error_estimate


def test_no_sign_change_is_an_error():
    with pytest.raises(ConvergenceError, match="does not change sign"):
        locate_branch_point(Pitchfork(), 1.1, 1.5, known=[(1.1, np.array([1.21, 0.0]))],
                            xtol=1e-12)


# ---- the plate ---------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def coarse_branch():
    """The compressed plate (a/t = 100) on 12 Chebyshev nodes, past the Bessel load."""
    sc = plate_under_edge_compression(100)
    q_end = 1.3 * bessel_root() / load_factor(100)
    return shellbvp.follow(sc, method=shellbvp.Chebyshev(nodes=12), p_stop=(0.0, q_end),
                           energies=False)


def _bracket_index(branch, a_over_t):
    q = bessel_root() / load_factor(a_over_t)
    return next(i for i, pt in enumerate(branch.points) if pt.p > q)


def test_plate_branch_point_against_bessel_and_its_symmetry(coarse_branch):
    i = _bracket_index(coarse_branch, 100)
    a, b = coarse_branch.points[i - 1], coarse_branch.points[i]
    bp = locate_branch_point(coarse_branch.system, a.p, b.p, known=[(a.p, a.U)],
                             xtol=1e-12 * a.p)
    x2 = bp.p * load_factor(100)
    # Kirchhoff's value to the thin-plate theory's error, (t/a)^2 = 1e-4 (measured -2.69e-5)
    assert abs(x2 / bessel_root() - 1.0) < 1e-4
    assert bp.error_estimate <= 2e-12 * bp.p and bp.converged
    assert bp.bracket[0] <= bp.p <= bp.bracket[1]
    # the null vector breaks w -> -w: z, theta, M carry it; r and F_r (even under the
    # mirror) do not
    Y = np.abs(bp.system.split(bp.null)).max(axis=(0, 2))
    assert Y[2] > 0.1 and Y[3] > 0.1
    assert Y[0] < 1e-10 and Y[4] < 1e-10


def test_rungs_converge(coarse_branch):
    """The located value on rungs from 8 nodes: the changes fall geometrically (Chebyshev)
    and the estimate bounds the distance to the finest value."""
    from shellbvp.methods.chebyshev import ChebyshevSystem

    i = _bracket_index(coarse_branch, 100)
    a, b = coarse_branch.points[i - 1], coarse_branch.points[i]
    S = coarse_branch.system
    values = []
    for N in (6, 8, 10, 12, 16):
        first = ChebyshevSystem(S.bvp, N)
        known = [(q.p, S.transfer(q.U, q.p, first)) for q in (a, b)]
        bp = locate_branch_point(first, a.p, b.p, known=known, xtol=1e-16)
        values.append(bp.p * load_factor(100))
    changes = np.abs(np.diff(values))
    assert changes[0] > 10 * changes[1] > 0 and changes[1] > 10 * changes[2]
    est = refine_branch_point(S, a.p, b.p, known=[(a.p, a.U), (b.p, b.U)], tol=1e-9 * b.p,
                              first=ChebyshevSystem(S.bvp, 8))
    assert est.stats["rungs"] >= 3 and est.converged
    # every rung's change to the next bounds its distance to the finest value (within 2x)
    chain = []
    q = est
    while q is not None:
        chain.append(q.p)
        q = q.previous
    chain = chain[::-1]
    for k in range(len(chain) - 2):
        assert abs(chain[k] - chain[-1]) <= 2 * abs(chain[k] - chain[k + 1]) + 1e-15
    assert abs(est.p * load_factor(100) - values[-1]) <= est.error_estimate * load_factor(100) \
        + 1e-12


@pytest.mark.slow
@pytest.mark.parametrize("a_over_t", [100, 1000])
def test_first_instability_of_the_plate(a_over_t):
    sc = plate_under_edge_compression(a_over_t)
    q_end = 1.5 * bessel_root() / load_factor(a_over_t)
    b = shellbvp.follow(sc, p_stop=(0.0, q_end), energies=False)
    ins = shellbvp.first_instability(b)
    assert ins.kind == "bifurcation" and ins.n == 0
    x2 = ins.p * load_factor(a_over_t)
    # -2.69e-5 at a/t = 100 and -2.69e-7 at 1000: the thin-plate theory's (t/a)^2
    assert abs(x2 / bessel_root() - 1.0) < 0.5 * a_over_t ** -2
    assert ins.error_estimate < 1e-6 * ins.p
    assert ins.branch_point.converged
    assert ins.mode.n == 0 and ins.equilibrium is not None


# ---- the clamped plate free to slide radially: the "sliding" end ------------------------------
def test_sliding_end_holds_z_and_theta_and_takes_a_radial_load_only():
    end = End("sliding", radial=0.5)
    assert end.fixes_z and end.conjugate(0.0, 1.0)[0] == 0.5
    with pytest.raises(ValueError, match="takes no moment load"):
        End("sliding", moment=1.0)
    sc = Scene(geometry=disc(1.0), h=0.01, material="koiter", nu=NU,
               ends=("pole", End("sliding", radial=lambda q: -q)), parameter="q")
    b = shellbvp.follow(sc, method=shellbvp.Chebyshev(nodes=12), p_stop=(0.0, 1e-5),
                        energies=False, estimate_errors=False)
    S = b.system
    Y = S.states(b.points[-1].U)[-1, :, -1]             # (r, z, theta, m, f_r, f_z) at the edge
    assert abs(Y[2]) < 1e-14 and abs(Y[1]) < 1e-14      # theta, z held
    assert Y[0] < 1.0                                   # r free: the edge moves in
    # f_r = 12/h^2 times the line load per radian (r0 = 1), inward
    assert Y[4] == pytest.approx(-12.0 / 0.01 ** 2 * 1e-5, rel=1e-10)


@pytest.mark.slow
@pytest.mark.parametrize("a_over_t", [100, 1000])
def test_clamped_sliding_plate_buckles_at_j11_squared(a_over_t):
    from scipy.special import jn_zeros

    x2 = jn_zeros(1, 1)[0] ** 2                 # 14.681970642123895
    sc = Scene(geometry=disc(1.0), h=1.0 / a_over_t, material="koiter", nu=NU,
               ends=("pole", End("sliding", radial=lambda q: -q)), parameter="q")
    b = shellbvp.follow(sc, p_stop=(0.0, 1.3 * x2 / load_factor(a_over_t)), energies=False)
    ins = shellbvp.first_instability(b)
    assert ins.kind == "bifurcation" and ins.n == 0
    # -9.41e-5 at a/t = 100: the thin-plate theory's (t/a)^2
    assert abs(ins.p * load_factor(a_over_t) / x2 - 1.0) < 1.5 * a_over_t ** -2
    assert ins.error_estimate < 1e-6 * ins.p


# ---- past the branch point: the bifurcated axisymmetric branch and Koiter's a, b ---------------
def von_karman_b(edge="hinged", nu=NU, N=40):
    """Koiter's b of the thin limit, independently: the axisymmetric von Karman plate in
    Friedrichs & Stoker's form (a = D = 1, beta = w' / t, Phi = r N_r),
        r^2 beta'' + r beta' - beta = r Phi beta,
        r^2 Phi'' + r Phi' - Phi = -6 (1 - nu^2) r beta^2,
    beta(0) = Phi(0) = 0, Phi(1) = -q, and at the edge beta' + nu beta = 0 (simply
    supported) or beta = 0 (clamped, sliding), with the amplitude xi = -int beta dr =
    w_centre / t prescribed: Chebyshev collocation (N), Newton by fsolve, b = (q / q_cr - 1)
    / xi^2 at xi = 0.02 and 0.01, Richardson-extrapolated."""
    from scipy.optimize import fsolve
    from scipy.special import jn_zeros

    k = np.arange(N + 1)
    x = np.cos(np.pi * k / N)
    c = np.hstack([2.0, np.ones(N - 1), 2.0]) * (-1.0) ** k
    X = np.tile(x, (N + 1, 1)).T
    D = np.outer(c, 1 / c) / (X - X.T + np.eye(N + 1))
    D = 2.0 * (D - np.diag(D.sum(1)))                     # on r = (x + 1) / 2
    r = (x + 1) / 2
    th = np.pi * k / N                                    # Clenshaw-Curtis weights on [0, 1]
    w = np.zeros(N + 1)
    v = np.ones(N - 1)
    for j in range(1, N // 2):
        v -= 2 * np.cos(2 * j * th[1:-1]) / (4 * j * j - 1)
    v -= np.cos(N * th[1:-1]) / (N * N - 1)
    w[0] = w[N] = 1 / (N * N - 1)
    w[1:-1] = 2 * v / N
    w /= 2
    D2 = D @ D
    q_cr = bessel_root(nu) if edge == "hinged" else jn_zeros(1, 1)[0] ** 2

    def F(z, xi):
        b, P, q = z[:N + 1], z[N + 1:2 * N + 2], z[-1]
        Rb = r ** 2 * (D2 @ b) + r * (D @ b) - b - r * P * b
        RP = r ** 2 * (D2 @ P) + r * (D @ P) - P + 6 * (1 - nu ** 2) * r * b ** 2
        Rb[N], RP[N] = b[N], P[N]                           # the centre, r = 0
        Rb[0] = (D @ b)[0] + nu * b[0] if edge == "hinged" else b[0]
        RP[0] = P[0] + q
        return np.concatenate([Rb, RP, [w @ b - xi]])

    from scipy.special import j1

    beta = j1(math.sqrt(q_cr) * r)
    z = np.concatenate([beta, -q_cr * r, [q_cr]])
    out = []
    for xi in (0.02, 0.01):
        z[:N + 1] *= xi / (w @ z[:N + 1])
        z = fsolve(F, z, args=(xi,), xtol=1e-13)
        assert np.abs(F(z, xi)).max() < 1e-8
        out.append((z[-1] / q_cr - 1) / xi ** 2)
    return (4 * out[1] - out[0]) / 3


def test_von_karman_reference():
    # the thin limit: 0.270379 simply supported, 0.203009 clamped (N = 40 and 60 agree)
    assert von_karman_b("hinged") == pytest.approx(0.270379, abs=2e-6)
    assert von_karman_b("clamped") == pytest.approx(0.203009, abs=2e-6)


@pytest.fixture(scope="module")
def plate_branch_point(coarse_branch):
    i = _bracket_index(coarse_branch, 100)
    a, b = coarse_branch.points[i - 1], coarse_branch.points[i]
    return locate_branch_point(coarse_branch.system, a.p, b.p, known=[(a.p, a.U)],
                               xtol=1e-13 * a.p)


def test_koiter_of_the_plate_is_a_supercritical_symmetric_pitchfork(plate_branch_point):
    from shellbvp.pitchfork import axisymmetric_koiter

    kc = axisymmetric_koiter(plate_branch_point)
    # measured: a = 4e-12, b = 0.270294 +- 5e-7 (nu = 0.3, xi = w_max / t)
    assert abs(kc.a) < 1e-8 and kc.kind == "supercritical"
    assert kc.b > 0 and kc.b_error < 1e-4 * kc.b
    # von Karman's thin limit, 0.270379, to the (t/a)^2 of the shell theory (measured
    # 0.270294 at a/t = 100, 0.270379 at a/t = 1000)
    assert kc.b == pytest.approx(von_karman_b("hinged"), rel=1e-3)
    # the two halves of the pitchfork: the same p at +-xi (the plate's w -> -w)
    (x1, p1), (x2, p2) = kc.samples[:2]
    assert x1 == pytest.approx(-x2, rel=1e-9) and p1 == pytest.approx(p2, rel=1e-12)


def buckled(bp, p_factor=1.05):
    """The bifurcated (axisymmetrically buckled) branch from the branch point ``bp`` of a
    plate's flat branch, to ``p_factor`` times its load (w up to the thickness)."""
    from shellbvp.instability import Instability

    ins = Instability("bifurcation", 0, bp.p, bp.w, bp.error_estimate, "q",
                      scan=((0.0, 0.0, {}),), branch_point=bp)
    return shellbvp.follow_bifurcation(ins, p_stop=(0.0, p_factor * bp.p), amplitude_max=1.0)


@pytest.fixture(scope="module")
def buckled_plate(plate_branch_point):
    return buckled(plate_branch_point)


def test_follow_bifurcation_at_n0_switches_onto_the_buckled_branch(plate_branch_point,
                                                                   buckled_plate):
    from shellbvp.pitchfork import BifurcatedBranch

    bp, out = plate_branch_point, buckled_plate
    h = 0.01
    assert isinstance(out, BifurcatedBranch) and out.n == 0
    br = out.branch
    assert len(br.p) >= 3 and np.all(np.diff(br.p) > 0) and br.w[-1] > 0.3 * h
    # the branch's points near the branch point follow Koiter's parabola in xi = w / t
    # (the centre deflection is the largest normal displacement of the plate)
    xi = br.w / h
    small = xi < 0.3
    pred = 1 + out.koiter.b * xi[small] ** 2
    assert np.allclose(br.p[small] / bp.p, pred, rtol=0, atol=2e-3 * xi[small] ** 2 + 1e-9)
    # off the flat state: the last point is bent (theta), not only compressed
    Y = br.system.split(br.points[-1].U)
    assert np.abs(Y[:, 2]).max() > 1e-3


# (phi, dphi, psi) = (delta theta, its derivative, delta lam1) on the unit disc (L = 1),
# phi = O(s^2) at the pole (tests/quadrature.py)
EDGE_MOVES = (lambda s: 0 * s, lambda s: 0 * s, lambda s: 1 + 0 * s)   # delta r(L) = int cos th
EDGE_TURNS = (lambda s: s**2, lambda s: 2 * s, lambda s: 0 * s)          # delta theta(L) = 1
# bends with the edge's slope held (phi(L) = 0), and inside
BENDS_HELD = (lambda s: s**2 * (1 - s), lambda s: 2 * s - 3 * s**2, lambda s: 0 * s)
BENDS_INSIDE = (lambda s: np.sin(2 * np.pi * s) ** 2,
                lambda s: 2 * np.pi * np.sin(4 * np.pi * s), lambda s: 0 * s)
MIXED = (lambda s: s**2 * (1 - s) ** 2, lambda s: 2 * s * (1 - s) ** 2 - 2 * s**2 * (1 - s),
         lambda s: np.cos(3 * s))


def assert_stationary(branch, directions):
    """The first variation of the total potential Pi (membrane + bending energy of the
    reduced energy, less the edge load's work) by the independent quadrature of
    tests/quadrature.py vanishes at the branch's last point relative to its value at
    states that are not equilibria of that load: another point of the branch (another
    shape; every direction sees it) and the same state under 1 % more load (only the edge
    load's work changes: the first direction, which moves the edge, sees it). Returns the
    three lists."""
    from dataclasses import replace

    from quadrature import first_variation

    eq = branch.equilibrium(-1, energies=False)
    off = replace(branch.equilibrium(1, energies=False), p=eq.p)
    heavier = replace(eq, p=1.01 * eq.p)
    at_eq, at_off = first_variation(eq, directions), first_variation(off, directions)
    at_heavier = first_variation(heavier, directions[:1])
    # not round-off: above a millionth of the edge load's work per unit edge displacement
    floor = 1e-6 * 2 * math.pi * eq.p
    for a, b in zip(at_eq, at_off):
        assert abs(b) > floor and abs(a) <= 1e-6 * abs(b), (a, b)
    assert abs(at_heavier[0]) > floor and abs(at_eq[0]) <= 1e-6 * abs(at_heavier[0])
    return at_eq, at_off, at_heavier


def test_buckled_plate_is_stationary_in_an_independent_quadrature(buckled_plate):
    """Issue 56: the bifurcated branch is stationary in an independent quadrature.

    The simply supported plate (roller edge: z held, r and theta free, the radial line
    load -q; a/t = 100) on its buckled branch at q = 1.05 q_c, w = 0.43 t. The quadrature
    (tests/quadrature.py): Pi = 2 pi int W g1 g2 r0 ds - 2 pi r0(L) f_r r(L), W the
    reduced energy by energy_density, by Simpson's rule on 6000 intervals, a complex step
    in each direction's amplitude, delta r and delta z integrated from the pole through the
    kinematic constraint, the work from End's definition of the line load (per unit
    reference edge length). It is independent of what the solver makes vanish: the
    Euler-Lagrange equations as a first-order system, its inner inversion of the moment,
    the pole's series, the natural edge conditions (f_r the load, m = 0) and the Chebyshev
    collocation of all that. Directions: a uniform stretch (moves the edge radially), s^2
    (bends and turns the edge), sin^2(2 pi s) (bends inside), and a stretch with a bend.

    Bounds. Near the equilibrium dPi is linear in the state, so |dPi(eq)| / |dPi(off)|
    is the state's error over its distance from the off state: the 12-node discretisation's
    (w moves by 3e-11 relative on 16 nodes) predicts ~1e-10; a 1e-6 error in the state or in
    the load (1 % more load gives 0.3 of the off value on the edge direction) would reach
    1e-6, the criterion of the same quadrature in test_budding and test_energy_method.
    Measured: <= 2.3e-9 (the bend inside; 1.1e-11 on the edge direction), and against the
    heavier load 4e-11; the same point solved on 10 and 8 nodes gives 2.7e-8 and 2.2e-5
    (the test sees a discretisation error). The floor: the off values (>= 2.3e-8) are
    not round-off (the equilibrium's are <= 3e-16)."""
    assert 0.3 < buckled_plate.branch.w[-1] / 0.01 < 1.0
    assert_stationary(buckled_plate.branch, [EDGE_MOVES, EDGE_TURNS, BENDS_INSIDE, MIXED])


@pytest.mark.slow
def test_buckled_clamped_sliding_plate_is_stationary_in_an_independent_quadrature():
    """As above for the clamped plate free to slide radially (sliding edge: z and theta
    held, r free, the radial line load -q; a/t = 100), its buckled branch at 1.05 q_c
    (w = 0.50 t); every phi vanishes at the edge. Measured: <= 1.6e-8 (the bend inside;
    1.8e-9 on the edge direction), the 12-node discretisation's (it is 1.3e-9 on 16)."""
    from scipy.special import jn_zeros

    x2 = jn_zeros(1, 1)[0] ** 2
    sc = Scene(geometry=disc(1.0), h=0.01, material="koiter", nu=NU,
               ends=("pole", End("sliding", radial=lambda q: -q)), parameter="q")
    flat = shellbvp.follow(sc, method=shellbvp.Chebyshev(nodes=12),
                           p_stop=(0.0, 1.3 * x2 / load_factor(100)), energies=False)
    i = next(k for k, pt in enumerate(flat.points) if pt.p * load_factor(100) > x2)
    a, b = flat.points[i - 1], flat.points[i]
    out = buckled(locate_branch_point(flat.system, a.p, b.p, known=[(a.p, a.U)],
                                      xtol=1e-13 * a.p))
    assert 0.3 < out.branch.w[-1] / 0.01 < 1.0
    assert_stationary(out.branch, [EDGE_MOVES, BENDS_HELD, BENDS_INSIDE, MIXED])


@pytest.mark.slow
@pytest.mark.parametrize("edge, end", [("hinged", "roller"), ("clamped", "sliding")])
def test_koiter_b_of_thin_plates_is_von_karmans(edge, end):
    from scipy.special import jn_zeros

    from shellbvp.continuation.branch_points import branch_point_on
    from shellbvp.pitchfork import axisymmetric_koiter

    x2 = bessel_root() if edge == "hinged" else jn_zeros(1, 1)[0] ** 2
    sc = Scene(geometry=disc(1.0), h=1e-3, material="koiter", nu=NU,
               ends=("pole", End(end, radial=lambda q: -q)), parameter="q")
    b = shellbvp.follow(sc, p_stop=(0.0, 1.3 * x2 / load_factor(1000)), energies=False,
                        estimate_errors=False)
    i = next(k for k, pt in enumerate(b.points) if pt.p * load_factor(1000) > x2)
    kc = axisymmetric_koiter(branch_point_on(b, i, tol=1e-9))
    # measured: 0.270379 +- 1.2e-6 and 0.203009 +- 1.1e-6 against 0.270379, 0.203009
    assert kc.kind == "supercritical"
    assert kc.b == pytest.approx(von_karman_b(edge), abs=max(5 * kc.b_error, 5e-6))


@pytest.mark.slow
@pytest.mark.parametrize("end, spectral", [("roller", 4.1976741976434795),
                                           ("sliding", 14.680588780537317)])
def test_the_energy_method_locates_the_same_branch_points(end, spectral):
    """Another discretisation (direct minimisation, its own ends and unknowns): the same
    branch point at a/t = 100 (measured: 4.1976741975580, 14.680588780426)."""
    from shellbvp.continuation.branch_points import branch_point_on

    sc = Scene(geometry=disc(1.0), h=0.01, material="koiter", nu=NU,
               ends=("pole", End(end, radial=lambda q: -q)), parameter="q")
    b = shellbvp.follow(sc, method="energy", p_stop=(0.0, 1.3 * spectral / load_factor(100)),
                        energies=False, estimate_errors=False)
    i = next(k for k, pt in enumerate(b.points) if pt.p * load_factor(100) > spectral)
    bp = branch_point_on(b, i, tol=1e-9)
    assert bp.converged
    assert bp.p * load_factor(100) == pytest.approx(spectral, rel=1e-9)
