"""Ring loads (shellbvp.Ring): dead forces on a circle of the meridian, an interface across
which the meridional force resultants jump. Checked against closed forms of linear plate and
cylinder theory (each formula in the test's docstring), between the methods (independent
discretisations: the first-order BVP's interface rows against the energy method's potential),
and by finite differences of the derivatives the continuation and fold machinery use.

Units as in tests/test_shells.py: lengths in R, a total ring force per mu* h R, the Koiter
shell's E = 2 mu* (1 + nu), so D / (mu* h R^2) = E h^2 / (12 (1 - nu^2)) and the membrane
stiffness E h / (mu* h) = E.
"""

import math

import numpy as np
import pytest

import shellbvp
from shellbvp import End, Ring, Scene
from shellbvp import geometry as g
from shellbvp.bvp import ShellBVP
from shellbvp.methods import as_method

NU = 0.3
YOUNG = 2 * (1 + NU)


def koiter(geometry, h, ends, **kw):
    return Scene(geometry=geometry, h=h, material="koiter", nu=NU, ends=ends, **kw)


def push_down(p):
    """A total force -p along z."""
    return -p


def outward(p):
    return p


def squared(p):
    """A load nonlinear in p (its p-derivatives are not constant)."""
    return p * p + 0.5 * p


def solve(scene, p, method="spectral"):
    eq = shellbvp.solve(scene, p, method=method, estimate_error=False)
    assert eq.success
    return eq


def plate_with_ring(b=0.4, h=0.01, load=push_down):
    return koiter(g.disc(1.0), h, ("pole", "clamped"), rings=(Ring(b, axial=load),))


@pytest.mark.parametrize("method", ["spectral", "energy",
                                    pytest.param("shooting", marks=pytest.mark.slow),
                                    "collocation"])
def test_clamped_plate_under_an_axial_ring_load(method):
    """Clamped circular plate (radius a = 1) under a total force P spread uniformly on the
    circle r = b (Timoshenko & Woinowsky-Krieger, Theory of Plates and Shells, Sec. 19,
    "circular plate loaded along a circle"; rederived with sympy, the point-load limit b -> 0
    giving P a^2 / (16 pi D)): w(0) = -P / (8 pi D) [(a^2 - b^2) / 2 + b^2 ln(b / a)].
    P = 1e-8 at h = 0.01 keeps w / h ~ 1e-5, so the geometric nonlinearity is ~1e-9; the
    tolerance 1e-6 covers the methods' default resolution (measured: 1.2e-7 spectral and
    energy, 1.1e-7 shooting, 5e-10 collocation). The axial force beyond the ring is the
    clamp's reaction, P (per radian P / 2 pi), zero inside it."""
    h, P, b = 0.01, 1e-8, 0.4
    D = YOUNG * h**2 / (12 * (1 - NU**2))
    eq = solve(plate_with_ring(b, h), P, method)
    expected = -P / (8 * math.pi * D) * ((1 - b**2) / 2 + b**2 * math.log(b))
    assert abs(eq.w / expected - 1) < 1e-6, eq.w / expected
    inner, outer = eq.s < b - 1e-9, eq.s > b + 1e-9
    assert np.max(np.abs(eq.F_z[inner])) < 1e-6 * P
    assert np.allclose(2 * math.pi * eq.F_z[outer], P, rtol=1e-6, atol=0)


def _cylinder_ring(h, method="spectral"):
    """A cylinder R = 1 clamped at z = 0, free at the other end, 40 sqrt(h) long, with a
    radial ring load at mid-length (both ends ~26 bending lengths 1/beta away)."""
    length = 40 * math.sqrt(h)
    sc = koiter(g.cylinder(1.0, length), h, ("clamped", "free"),
                rings=(Ring(length / 2, radial=outward),))
    Q = 1e-6 * h
    eq = solve(sc, Q, method)
    k = int(np.argmin(np.abs(eq.s - length / 2)))
    beta = (3 * (1 - NU**2)) ** 0.25 / math.sqrt(h)
    return eq, k, (eq.r[k] - 1.0) / (Q / (2 * math.pi) * beta / (2 * YOUNG)) - 1.0


def test_long_cylinder_under_a_radial_ring_load():
    """An infinite cylinder under a radial line load q per unit circumference (Timoshenko &
    Woinowsky-Krieger, Sec. 117, Donnell's equation): w = q R^2 beta / (2 E t) under the
    load, beta^4 = 3 (1 - nu^2) / (R t)^2. The free end leaves the axial force zero, as on
    the infinite cylinder. Koiter's shell differs from Donnell's by O(h / R): measured
    -4.6e-4 at h = 0.01 and -1.1e-4 at h = 0.0025, so the bound is 2e-4 at 0.0025 and the
    difference must fall by more than 3x when h falls 4x. The meridional force jumps by the
    load: F_r per radian from +Q/4 pi to -Q/4 pi across the ring, to round-off."""
    eq_a, _, dev_a = _cylinder_ring(0.01)
    eq_b, k, dev_b = _cylinder_ring(0.0025)
    assert abs(dev_b) < 2e-4 and abs(dev_a) > 3 * abs(dev_b), (dev_a, dev_b)
    Q, h, s = 1e-6 * 0.0025, 0.0025, eq_b.s[k]
    # f_r = 12/h^2 F_r on either side of the interface (each piece's own interpolant)
    left, right = h**2 / 12 * eq_b.unknowns(np.array([s - 1e-12, s + 1e-12]))[4]
    assert abs((left - right) - Q / (2 * math.pi)) < 1e-6 * Q


def test_cylinder_ring_load_by_the_energy_method():
    """The energy method's ring is a potential -Q r(s_k) on a node of its mesh, not an
    interface row: an independent route, equal to the spectral radius to 1e-6."""
    a, k, _ = _cylinder_ring(0.01, "spectral")
    b, j, _ = _cylinder_ring(0.01, "energy")
    assert abs((b.r[j] - 1) / (a.r[k] - 1) - 1) < 1e-6


def test_a_ring_on_a_kink_joint():
    """A ring at a joint with a kink (a cone on a cylinder) loads that interface: both
    methods agree (5e-6, their resolution at the kink) and the axial force jumps by the
    ring's load (F_z per radian, zero on the free cone, the ring's -P / 2 pi beyond)."""
    geo = g.Meridian((g.Cone((0.5, 0.3), (1.0, 0.0)), g.Cylinder(1.0, (0.0, -1.0))))
    joint = float(geo.joints[0])
    sc = koiter(geo, 0.01, ("free", "clamped"), rings=(Ring(joint, axial=push_down),))
    assert sc.pieces == 2                     # the joint is the ring's interface
    a, b = (solve(sc, 1e-6, m) for m in ("spectral", "energy"))
    assert abs(b.w / a.w - 1) < 5e-6, (a.w, b.w)
    cone, beyond = a.s < joint - 1e-9, a.s > joint + 1e-9
    assert np.max(np.abs(a.F_z[cone])) < 1e-9
    assert np.allclose(2 * math.pi * a.F_z[beyond], 1e-6, rtol=1e-9)


@pytest.mark.parametrize("method", ["spectral", "energy", "shooting"])
def test_the_p_derivative_of_a_ring_load(method):
    """dR/dp of the discrete system with a ring load nonlinear in p (p^2 + p/2), against
    central differences of R (step 1e-6: truncation ~1e-12 relative)."""
    sc = plate_with_ring(load=squared)
    eq = solve(sc, 1e-4)
    bvp = ShellBVP(sc)
    system = as_method(method).discretise(bvp)
    U = system.from_profile(eq.unknowns)
    p, d = 1e-4, 1e-6
    _, _, Rp = system.evaluate(U, p)
    fd = (system.evaluate(U, p + d)[0] - system.evaluate(U, p - d)[0]) / (2 * d)
    assert np.linalg.norm(Rp - fd) < 1e-6 * np.linalg.norm(fd)


def test_the_h_derivative_of_the_ring_jumps():
    """The spectral system's dR/dh (fold curves in h) holds the rings' interface rows,
    -(12/h^2) Q: against central differences of the residual of scenes at h -+ d."""
    p, h, d = 1e-4, 0.01, 1e-7
    sc = plate_with_ring(h=h)
    system = as_method("spectral").discretise(ShellBVP(sc))
    U = system.from_profile(solve(sc, p).unknowns)
    dR, _ = system.parameter_derivatives(U, p, names=("h",))["h"]

    def residual(hh):
        other = as_method("spectral").discretise(ShellBVP(plate_with_ring(h=hh)))
        return other.evaluate(U, p)[0]

    fd = (residual(h + d) - residual(h - d)) / (2 * d)
    rows = np.abs(fd) > 0
    assert np.linalg.norm(dR - fd) < 1e-5 * np.linalg.norm(fd)
    assert rows.any()


@pytest.mark.slow
def test_axisymmetric_second_variation_is_stationary_under_dead_loads():
    """The second variation's energy holds the dead loads' potential with the right sign: at
    an equilibrium (solved by the spectral method) its gradient on the constraints' tangent
    space is the difference of two discretisations, and falls as the second variation's
    nodes grow (measured 3.4e-6 -> 1.8e-7 from 16 to 48 nodes on the disc spring, 2.8e-8 ->
    1.3e-9 on the plate). A sign error in the work of an axial load (the free inner edge of
    the disc spring, the plate's ring) leaves a gradient of the load's order that does not
    fall (it did, before the fix: 7e-6 on a disc spring at every resolution)."""
    spring = Scene(geometry=g.Meridian(g.Cone((0.5, 0.05), (1.0, 0.0))), h=0.02,
                   material="koiter", nu=NU, ends=(End("free", axial=push_down), "roller"))
    plate = plate_with_ring()
    for sc, p in ((spring, 2e-3), (plate, 1e-4)):
        eq = solve(sc, p)
        coarse, fine = (shellbvp.second_variation(eq, count=1, nodes=N).projected_gradient
                        for N in (16, 48))
        assert fine < coarse / 8, (sc.ends, coarse, fine)


def test_a_ring_scene_beyond_axisymmetry():
    """A dead ring load has no load stiffness: the harmonics see it through the
    axisymmetric state only. A clamped plate pushed by a ring stays stable in every harmonic
    (the smallest level positive for n = 0..4)."""
    sc = plate_with_ring()
    eq = solve(sc, 1e-4)
    spectra = shellbvp.modes(eq, n=range(0, 5), count=1).spectra
    assert all(sp.eigenvalues[0] > 0 for sp in spectra), spectra


def test_bad_rings_are_refused():
    disc = g.disc(1.0)
    with pytest.raises(ValueError, match="outside the meridian"):
        koiter(disc, 0.01, ("pole", "clamped"), rings=(Ring(1.5, axial=1.0),))
    with pytest.raises(ValueError, match="outside the meridian"):
        koiter(disc, 0.01, ("pole", "clamped"), rings=(Ring(0.0, axial=1.0),))
    with pytest.raises(ValueError, match="on an end"):
        koiter(disc, 0.01, ("pole", "clamped"), rings=(Ring(1.0 - 1e-12, axial=1.0),))
    with pytest.raises(ValueError, match="two at s"):
        koiter(disc, 0.01, ("pole", "clamped"),
               rings=(Ring(0.5, axial=1.0), Ring(0.5, radial=1.0)))
    with pytest.raises(ValueError, match="carries no load"):
        Ring(0.5)
    with pytest.raises(ValueError, match="ring radial load must be a number or a function"):
        Ring(0.5, radial="1")
    with pytest.raises(ValueError, match="ring s"):
        Ring(float("nan"), axial=1.0)
    with pytest.raises(ValueError, match="rings must be a tuple of shellbvp.Ring"):
        koiter(disc, 0.01, ("pole", "clamped"), rings=(0.5,))


def test_rings_are_sorted_and_share_a_joint():
    geo = g.Meridian((g.Cone((0.5, 0.3), (1.0, 0.0)), g.Cylinder(1.0, (0.0, -1.0))))
    joint = float(geo.joints[0])
    sc = koiter(geo, 0.01, ("free", "clamped"),
                rings=(Ring(joint + 0.5, radial=1.0), Ring(joint * (1 + 1e-12), axial=1.0)))
    assert [r.s for r in sc.rings] == sorted(r.s for r in sc.rings)
    assert sc.pieces == 3 and sc.ring_interfaces == (0, 1)
