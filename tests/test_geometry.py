"""The reference meridian as data (shellbvp.geometry).

References, all independent of the code under test: closed forms of the curvatures of the
sphere, cylinder, plate, cone, torus and ellipse (with the signs of DESIGN.md section 12);
the complete elliptic integral E(m) for an ellipse's arclength (scipy.special.ellipe);
finite differences of (r0, z0) and theta0 (5-point stencil, error bounded by its truncation
h^4 |f^(5)| / 30 and its rounding 3 eps |f| / (2 h)); JAX's derivatives of the same code
(jax.jvp), for the unit speed to round-off; the known circle and ellipse behind sampled
points, for the observed order of the curvature of Points.
"""

import math

import numpy as np
import pytest

from shellbvp.geometry import (Cone, Cylinder, Ellipse, Meridian, Plate, Points, Segment,
                               Sphere, Torus, annulus, closed_sphere, cylinder, disc,
                               spherical_cap)

PI = math.pi
EPS = np.finfo(float).eps


@pytest.fixture(scope="module")
def jax():
    import jax

    jax.config.update("jax_enable_x64", True)
    return jax


def ellipse_points(p, q, a, centre_z=0.0):
    return p * np.sin(a), centre_z + q * np.cos(a)


#: one segment of every type (both directions where the formula has one), for the checks
#: that hold for all
SEGMENTS = {
    "plate out": Plate((0.5, 2.0), 1.0),
    "plate in": Plate((2.0, 0.5)),
    "cylinder up": Cylinder(1.5, (0.0, 2.0)),
    "cylinder down": Cylinder(1.5, (2.0, -1.0)),
    "cone": Cone((1.0, 0.0), (2.0, 1.5)),
    "sphere down": Sphere(1.3, 0.2, angle=(0.2, 2.9)),
    "sphere up": Sphere(0.7, angle=(3.0, 0.4)),
    "torus": Torus(2.0, 0.5, angle=(-2.0, 3.5)),
    "torus back": Torus(2.0, 0.5, angle=(3.0, 0.5)),
    "ellipse oblate": Ellipse(1.0, 0.4, 0.3, angle=(0.1, 3.0)),
    "ellipse prolate back": Ellipse(0.5, 2.0, angle=(2.8, 0.2)),
    "points": Points(*ellipse_points(1.0, 0.6, np.linspace(0.2, 2.8, 15))),
    "points pole": Points(*ellipse_points(2.0, 0.5, np.linspace(0.0, 2.0, 12))),
}


def derivative(f, u, h):
    """The 5-point central difference of f at u."""
    return (f(u - 2 * h) - 8 * f(u - h) + 8 * f(u + h) - f(u + 2 * h)) / (12 * h)


def assert_derivative(f, u, want, h, scale):
    """The 5-point difference of f at step h/2 equals ``want`` to within its error bound:
    the truncation error, ~ h^4, is ~ |D(h) - D(h/2)| / 15 (bounded here by |D(h) - D(h/2)|),
    plus rounding 3 eps |f| / h (18/12 eps |f| per step h/2), taken 4 times."""
    coarse, fine = derivative(f, u, h), derivative(f, u, h / 2)
    np.testing.assert_array_less(np.abs(fine - want), np.abs(coarse - fine)
                                 + 12 * EPS * scale / h)


# --------------------------------------------------------------------------- signs

def test_unit_sphere_from_its_top_pole():
    """r0 = sin s, z0 = cos s, theta0 = s, k1 = k2 = -1 (DESIGN.md section 12), the pole
    limit at both poles."""
    m = closed_sphere()
    s = np.linspace(0.0, PI, 41)
    r, z, theta, k1 = m.evaluate(s)
    np.testing.assert_allclose(r, np.sin(s), atol=1e-15)
    np.testing.assert_allclose(z, np.cos(s), atol=1e-15)
    np.testing.assert_allclose(theta, s, atol=1e-15)
    np.testing.assert_allclose(m.curvatures(s), -np.ones((2, len(s))), atol=1e-14)
    assert m.poles == (True, True) and m.length == pytest.approx(PI, abs=1e-15)
    assert m.at_end("first") == (0.0, 1.0, 0.0)
    assert m.at_end("second") == pytest.approx((0.0, -1.0, PI), abs=1e-15)


@pytest.mark.parametrize("radius", [0.5, 3.0])
def test_cylinder_both_ways(radius):
    """Upward theta0 = -pi/2, k1 = 0, k2 = +1/R (n0 points to the axis); downward
    theta0 = pi/2, k2 = -1/R."""
    for z, theta, k2 in (((0.0, 2.0), -PI / 2, 1.0 / radius), ((2.0, 0.0), PI / 2, -1.0 / radius)):
        m = Meridian(Cylinder(radius, z))
        s = np.linspace(0.0, 2.0, 9)
        r, zz, th, _ = m.evaluate(s)
        np.testing.assert_allclose(r, radius, rtol=1e-15)
        np.testing.assert_allclose(zz, z[0] + np.sign(z[1] - z[0]) * s, atol=1e-15)
        np.testing.assert_allclose(th, theta, rtol=1e-15)
        k1, kk2 = m.curvatures(s)
        np.testing.assert_allclose(k1, 0.0, atol=0.0)
        np.testing.assert_allclose(kk2, k2, rtol=1e-15)
        assert m.poles == (False, False) and m.rise == 2.0
    assert cylinder(radius, 2.0) == Meridian(Cylinder(radius, (0.0, 2.0)))


def test_plate_both_ways():
    """theta0 = 0 traced outward, pi inward; k1 = k2 = 0; a disc's centre is a pole."""
    out, inward = disc(2.0), Meridian(Plate((2.0, 0.0), z=0.5))
    s = np.linspace(0.0, 2.0, 9)
    for m, theta, r in ((out, 0.0, s), (inward, PI, 2.0 - s)):
        rr, z, th, _ = m.evaluate(s)
        np.testing.assert_allclose(rr, r, atol=1e-15)
        np.testing.assert_array_equal(z, m.at_end("first")[1])
        np.testing.assert_array_equal(th, theta)
        np.testing.assert_allclose(m.curvatures(s), 0.0, atol=1e-15)   # sin(pi) = 1.2e-16
    assert out.poles == (True, False) and inward.poles == (False, True)
    assert annulus(0.5, 1.0).poles == (False, False) and annulus(0.5, 1.0).length == 0.5


def test_bowl_opening_upward():
    """A sphere traced upward from its bottom pole: theta0 = -s/R, n0 = (sin theta0,
    cos theta0) points into the bowl, toward the centre: k1 = k2 = +1/R."""
    R = 2.0
    m = Meridian(Sphere(R, centre_z=R, angle=(PI, PI / 2)))
    s = np.linspace(0.0, m.length, 11)
    r, z, theta, _ = m.evaluate(s)
    np.testing.assert_allclose(r, R * np.sin(s / R), atol=1e-15)
    np.testing.assert_allclose(z, R - R * np.cos(s / R), atol=1e-15)
    np.testing.assert_allclose(theta, -s / R, atol=1e-15)      # turning up: dz/ds > 0
    np.testing.assert_allclose(m.curvatures(s), 1.0 / R, rtol=1e-14)
    assert m.poles == (True, False) and m.at_end("first")[2] == 0.0


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_torus_equators(sign):
    """Traced with a increasing: k1 = -1/rho, k2 = -sin(a)/(c + rho sin a): outer equator
    -1/(c + rho), inner +1/(c - rho) (a saddle); both change sign traced the other way."""
    c, rho = 3.0, 1.0
    a = np.array([PI / 2, 3 * PI / 2, 0.4, 2.0, 4.0, 5.5])
    seg = Torus(c, rho, angle=(0.0, 2 * PI) if sign > 0 else (2 * PI, 0.0))
    u = a * rho if sign > 0 else (2 * PI - a) * rho
    m = Meridian(seg)
    r, z, _, _ = m.evaluate(u)
    np.testing.assert_allclose(r, c + rho * np.sin(a), rtol=1e-15)
    np.testing.assert_allclose(z, rho * np.cos(a), atol=1e-15)
    k1, k2 = m.curvatures(u)
    np.testing.assert_allclose(k1, -sign / rho, rtol=1e-15)
    np.testing.assert_allclose(k2, -sign * np.sin(a) / (c + rho * np.sin(a)), atol=1e-15)
    assert k2[0] == pytest.approx(-sign / (c + rho), rel=1e-15)
    assert k2[1] == pytest.approx(sign / (c - rho), rel=1e-15)


@pytest.mark.parametrize("p, q", [(1.0, 0.6), (0.5, 2.0), (1.0, 1.0)])
def test_ellipse_curvatures_and_arclength(p, q):
    """k1 = -p q / N^3 and k2 = -q / (p N), N = sqrt(p^2 cos^2 a + q^2 sin^2 a), a read
    back from the point; the quarter arc p E(1 - q^2/p^2) (complete elliptic integral)."""
    from scipy.special import ellipe

    seg = Ellipse(p, q, 0.5, angle=(0.0, PI))
    m = Meridian(seg)
    quarter = p * ellipe(1 - q**2 / p**2) if p >= q else q * ellipe(1 - p**2 / q**2)
    assert seg.length == pytest.approx(2 * quarter, rel=1e-15)
    s = np.linspace(0.0, seg.length, 201)
    r, z, _, _ = m.evaluate(s)
    a = np.arctan2(r / p, (z - 0.5) / q)
    N = np.hypot(p * np.cos(a), q * np.sin(a))
    k1, k2 = m.curvatures(s)
    np.testing.assert_allclose(k1, -p * q / N**3, rtol=1e-14)
    np.testing.assert_allclose(k2, -q / (p * N), rtol=1e-13)
    assert m.poles == (True, True)
    assert k2[0] == k1[0] == pytest.approx(-q / p**2, rel=1e-15)


def test_cone():
    """k1 = 0, k2 = -sin(theta0)/r0 = (dz/ds)/r0 with dz/ds = (z_b - z_a)/l: a frustum of
    half-angle alpha (from the axis) has k2 = cos(alpha)/r0 traced upward."""
    alpha = 0.3
    start = (1.0, 0.0)
    end = (1.0 + 2 * math.sin(alpha), 2 * math.cos(alpha))
    m = Meridian(Cone(start, end))
    s = np.linspace(0.0, 2.0, 9)
    r, z, theta, _ = m.evaluate(s)
    np.testing.assert_allclose(r, 1.0 + s * math.sin(alpha), rtol=1e-15)
    np.testing.assert_allclose(theta, alpha - PI / 2, rtol=1e-15)
    k1, k2 = m.curvatures(s)
    np.testing.assert_array_equal(k1, 0.0)
    np.testing.assert_allclose(k2, math.cos(alpha) / r, rtol=1e-15)
    assert m.length == pytest.approx(2.0, rel=1e-15)


# --------------------------------------------------------------------------- consistency

@pytest.mark.parametrize("name", SEGMENTS)
def test_unit_speed_and_curvature_by_finite_differences(name):
    """(dr0/ds, dz0/ds) = (cos theta0, -sin theta0) and dtheta0/ds = -k1 by 5-point
    differences (:func:`assert_derivative`: steps h = 1e-3 and h/2)."""
    seg = SEGMENTS[name]
    ell, h = seg.length, 1e-3
    u = np.linspace(2 * h, ell - 2 * h, 97)
    r, z, theta, k1 = seg.evaluate(u)
    scale = max(np.max(np.abs(r)), np.max(np.abs(z)), np.max(np.abs(theta)), 1.0)
    f = lambda k: (lambda v: seg.evaluate(v)[k])  # noqa: E731
    assert_derivative(f(0), u, np.cos(theta), h, scale)
    assert_derivative(f(1), u, -np.sin(theta), h, scale)
    assert_derivative(f(2), u, -k1, h, scale)


@pytest.mark.parametrize("name", SEGMENTS)
def test_unit_speed_to_round_off_by_jax(name, jax):
    """JAX's derivative of the same evaluation in u: |d(r0, z0)/ds| = 1 to 1e-12 (the
    tables' tolerance), the tangent is (cos theta0, -sin theta0) and dtheta0/ds = -k1 to
    round-off; jax.jit's values equal numpy's to round-off, jax.grad the finite difference."""
    jnp = jax.numpy
    seg = SEGMENTS[name]
    u = np.linspace(0.0, seg.length, 501)
    ref = seg.evaluate(u)
    values, tangents = jax.jit(lambda v: jax.jvp(lambda w: seg.evaluate(w, jnp), (v,),
                                                 (jnp.ones_like(v),)))(jnp.asarray(u))
    scale = max(np.max(np.abs(ref[1])), np.max(np.abs(ref[2])), 1.0)
    for got, want in zip(values, ref):
        np.testing.assert_allclose(np.asarray(got), want, rtol=0, atol=8 * EPS * scale
                                   * max(1.0, np.max(np.abs(ref[3]))))
    dr, dz, dtheta, _ = (np.asarray(t) for t in tangents)
    assert np.max(np.abs(np.hypot(dr, dz) - 1.0)) <= 1e-12
    np.testing.assert_allclose(dr, np.cos(ref[2]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(dz, -np.sin(ref[2]), rtol=0, atol=1e-12)
    np.testing.assert_allclose(dtheta, -ref[3], rtol=1e-12, atol=1e-12)
    grad = jax.grad(lambda v: seg.evaluate(v, jnp)[0])
    v = 0.37 * seg.length
    h = 1e-3
    assert float(grad(v)) == pytest.approx(derivative(lambda w: seg.evaluate(w)[0], v, h),
                                           abs=1e-9)


@pytest.mark.parametrize("ratio", [1e-3, 0.05, 0.5, 4.0, 1e3])
def test_ellipse_unit_speed_across_aspect_ratios(ratio, jax):
    """The table's claim, |d(r0, z0)/ds| - 1 <= 1e-12, on 10^4 points of elongated
    ellipses (JAX's derivative of the evaluation: the interpolant's own derivative)."""
    jnp = jax.numpy
    seg = Ellipse(1.0, ratio, angle=(0.0, PI))
    u = jnp.linspace(0.0, seg.length, 10_001)
    _, (dr, dz, _, _) = jax.jvp(lambda w: seg.evaluate(w, jnp), (u,), (jnp.ones_like(u),))
    assert float(jnp.max(jnp.abs(jnp.hypot(dr, dz) - 1.0))) <= 1e-12


def test_segment_continues_beyond_its_ends():
    """evaluate beyond [0, length] is the same curve: what with_length(longer) gives."""
    for name in ("sphere down", "torus", "cone", "ellipse oblate", "cylinder up"):
        seg = SEGMENTS[name]
        longer = seg.with_length(1.05 * seg.length)
        u = np.linspace(0.95, 1.05, 11) * seg.length
        for a, b in zip(seg.evaluate(u), longer.evaluate(u)):
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-13)
        assert longer.length == pytest.approx(1.05 * seg.length, rel=1e-14)
        # equal keys but for a cone's direction, recomputed from its new end (round-off)
        assert longer.trace_key()[0] == seg.trace_key()[0]
        np.testing.assert_allclose(longer.trace_key()[1:], seg.trace_key()[1:], rtol=1e-15)


# --------------------------------------------------------------------------- Points

def curvature_error(n, p, q, lo, hi):
    """The largest |k1 - k1_exact| of Points through n samples of the ellipse arc, at 2001
    points of the curve (a read back from each point)."""
    seg = Points(*ellipse_points(p, q, np.linspace(lo, hi, n)))
    s = np.linspace(0.0, seg.length, 2001)
    r, z, _, k1 = seg.evaluate(s)
    a = np.arctan2(r / p, z / q)
    return np.max(np.abs(k1 + p * q / np.hypot(p * np.cos(a), q * np.sin(a)) ** 3))


@pytest.mark.parametrize("p, q, lo, hi", [(1.0, 1.0, 0.2, 2.5), (1.0, 0.6, 0.2, 2.5),
                                          (1.0, 0.6, 0.0, 2.5), (1.0, 0.6, 0.0, PI)])
def test_points_curvature_converges_at_fourth_order(p, q, lo, hi):
    """A quintic spline: the curve O(h^6), its curvature O(h^4). Observed orders between
    n = 20, 40, 80, 160 samples of a circle and of an ellipse (with a pole at one or both
    ends: the mirrored fit) are all > 3.5."""
    errors = [curvature_error(n, p, q, lo, hi) for n in (20, 40, 80, 160)]
    orders = [math.log2(a / b) for a, b in zip(errors, errors[1:])]
    assert min(orders) > 3.5, (errors, orders)
    assert errors[-1] < 1e-6


def test_points_pass_through_the_points():
    """The curve passes through every point (at ``nodes``) to round-off, 1e-14 x extent."""
    rng = np.random.default_rng(7)
    a = np.sort(rng.uniform(0.05, 3.0, 25))
    r, z = ellipse_points(3.0, 1.0, a, centre_z=2.0)
    seg = Points(r, z)
    rr, zz, _, _ = seg.evaluate(np.array(seg.nodes))
    assert np.max(np.hypot(rr - r, zz - z)) <= 1e-14 * 3.0
    assert len(seg.nodes) == 25 and seg.nodes[0] == 0.0
    assert seg.nodes[-1] == pytest.approx(seg.length, rel=1e-15)
    assert all(0.0 < b < seg.length for b in seg.breaks)


def test_points_pole_is_a_right_angle_and_umbilic():
    """A first point on the axis: the mirrored fit meets it at theta0 = 0 (round-off) with
    k2 -> k1; with both ends on the axis theta0(L) = pi (a closed sphere from points)."""
    a = np.linspace(0.0, PI, 13)
    m = Meridian(Points(np.sin(a), np.cos(a)))
    assert m.poles == (True, True)
    assert abs(m.at_end("first")[2]) < 1e-14 and abs(m.at_end("second")[2] - PI) < 1e-14
    k1, k2 = m.curvatures(np.array([0.0, 1e-6, m.length - 1e-6, m.length]))
    np.testing.assert_allclose(k2, k1, rtol=1e-5)
    np.testing.assert_allclose(k1, -1.0, rtol=1e-3)
    half = Meridian(Points(np.sin(a[:8]), np.cos(a[:8])))
    assert half.poles == (True, False) and abs(half.at_end("first")[2]) < 1e-14


def test_points_refusals():
    a = np.linspace(0.2, 2.0, 6)
    r, z = np.sin(a), np.cos(a)
    for args, words in (((r[:3], z[:3]), "Points.r and Points.z"),
                        ((-r, z), "Points.r must be >= 0"),
                        ((np.r_[r, r[2]], np.r_[z, z[2]]), "distinct"),
                        ((r[[0, 3, 1, 4, 2, 5]], z[[0, 3, 1, 4, 2, 5]]), "order")):
        with pytest.raises(ValueError, match=words):
            Points(*args)
    with pytest.raises(ValueError, match="Points: .*with_length"):
        Points(r, z).with_length(1.0)


# --------------------------------------------------------------------------- the meridian

def capsule(R=1.0, H=2.0):
    """A closed capsule: a hemisphere, a cylinder downward, a hemisphere (smooth joints)."""
    return Meridian((Sphere(R, H / 2, angle=(0.0, PI / 2)), Cylinder(R, (H / 2, -H / 2)),
                     Sphere(R, -H / 2, angle=(PI / 2, PI))))


def test_joints_kinks_and_pieces():
    """A smooth capsule has zero kinks and a continuous theta0 from 0 to pi; a lidded
    cylinder turns by -pi/2 at its rim (up, then inward), its theta0 continuous but for it
    and its lid's centre a second-end pole at theta0 = -pi (= pi mod 2 pi)."""
    m = capsule()
    assert m.joints == pytest.approx((PI / 2, PI / 2 + 2.0))
    assert m.kinks == pytest.approx((0.0, 0.0), abs=1e-15)
    s = np.linspace(0.0, m.length, 1001)
    theta = m.evaluate(s)[2]
    assert np.max(np.abs(np.diff(theta))) < 2 * (s[1] - s[0])
    assert theta[0] == 0.0 and theta[-1] == pytest.approx(PI, abs=1e-15)
    assert m.rise == pytest.approx(4.0) and m.size == pytest.approx(4.0)
    lid = Meridian((Cylinder(1.0, (0.0, 1.0)), Plate((1.0, 0.0), 1.0)))
    assert lid.kinks == pytest.approx((-PI / 2,)) and lid.poles == (False, True)
    assert lid.theta_offsets == (0.0, -2 * PI)
    assert lid.at_end("second")[2] == pytest.approx(-PI)
    # a joint belongs to the next segment
    assert lid.evaluate(1.0)[2] == pytest.approx(-PI)
    assert lid.evaluate(1.0 - 1e-12)[2] == pytest.approx(-PI / 2)
    assert m.pieces() == ((0.0, PI / 2, 0), (PI / 2, PI / 2 + 2, 1), (PI / 2 + 2, m.length, 2))
    pieces = m.pieces([0.5, 2.0, 4.0])
    assert [p[2] for p in pieces] == [0, 0, 1, 1, 2, 2]
    assert all(a < b for a, b, _ in pieces) and pieces[-1][1] == m.length


@pytest.mark.parametrize("cuts, words", [([0.0], "strictly inside"), ([10.0], "strictly inside"),
                                         ([PI / 2], "on the joint"), ([2.0, 1.0], "increasing")])
def test_pieces_refuse_bad_cuts(cuts, words):
    with pytest.raises(ValueError, match=words):
        capsule().pieces(cuts)


def test_meridian_evaluate_under_jit(jax):
    """The meridian's evaluation (all segments, selected by position) with jax.numpy under
    jax.jit equals numpy's."""
    m = Meridian((Sphere(1.0, 0.5, angle=(0.0, 1.2)),
                  Ellipse(math.sin(1.2), 0.3, 0.5 + math.cos(1.2), angle=(PI / 2, 2.0))))
    s = np.linspace(0.0, m.length, 301)
    got = jax.jit(lambda v: m.evaluate(v, jax.numpy))(jax.numpy.asarray(s))
    for a, b in zip(got, m.evaluate(s)):
        np.testing.assert_allclose(np.asarray(a), b, rtol=0, atol=1e-14)
    np.testing.assert_allclose(np.asarray(m.curvatures(s, jax.numpy)[1]), m.curvatures(s)[1],
                               rtol=1e-14)


def test_spherical_cap_is_the_engine_cap_and_with_length():
    """spherical_cap(theta): r0 = sin s, z0 = cos s - 1, theta0 = s (the cap of the existing
    engine); with_length equals the cap of that length, continuously."""
    cap = spherical_cap(1.0)
    s = np.linspace(0.0, 1.0, 11)
    r, z, theta, _ = cap.evaluate(s)
    np.testing.assert_allclose((r, z, theta), (np.sin(s), np.cos(s) - 1.0, s), atol=1e-15)
    longer = cap.with_length(1.3)
    assert longer == spherical_cap(1.3)
    for a, b in zip(cap.evaluate(s), longer.evaluate(s)):
        np.testing.assert_array_equal(a, b)
    assert spherical_cap(0.5, radius=2.0).length == pytest.approx(1.0)
    with pytest.raises(ValueError, match="Sphere.angle"):
        cap.with_length(4.0)                   # beyond the bottom pole
    with pytest.raises(ValueError, match="with_length: length must exceed"):
        capsule().with_length(PI / 2 + 2.0)


def test_trace_keys():
    """Caps of different opening angle share their key (and so their compiled programs);
    radius, centre, start or direction change it; the key is hashable."""
    keys = {spherical_cap(t).segments[0].trace_key() for t in (0.3, 1.0, 2.0)}
    assert len(keys) == 1
    assert spherical_cap(1.0, 2.0).segments[0].trace_key() not in keys
    assert Sphere(1.0, angle=(0.1, 1.0)).trace_key() != Sphere(1.0, angle=(1.0, 0.1)).trace_key()
    assert Sphere(1.0, angle=(0.0, 1.0)).trace_key() != Sphere(1.0, 0.1, angle=(0.0, 1.0)) \
        .trace_key()
    assert Ellipse(1.0, 2.0, angle=(0.0, 1.0)).trace_key() == \
        Ellipse(1.0, 2.0, angle=(0.0, 2.5)).trace_key()
    assert Cylinder(1.0, (0.0, 1.0)).trace_key() == Cylinder(1.0, (0.0, 3.0)).trace_key()
    assert Plate((0.0, 1.0)).trace_key() == Cone((0.0, 0.0), (2.0, 0.0)).trace_key()
    a = np.linspace(0.1, 1.0, 5)
    assert Points(a, a**2).trace_key() != Points(a, a**2 + 1).trace_key()
    assert len({seg.trace_key() for seg in SEGMENTS.values()}) == len(SEGMENTS)


# --------------------------------------------------------------------------- refusals

@pytest.mark.parametrize("make, words", [
    (lambda: Cylinder(1.0, (0.0, 0.0)), r"Cylinder.z .*z_a != z_b"),
    (lambda: Plate((1.0, 1.0)), r"Plate.r .*r_a != r_b"),
    (lambda: Plate((-1.0, 1.0)), r"Plate.r .*>= 0"),
    (lambda: Cone((1.0, 1.0), (1.0, 1.0)), "Cone: start and end must differ"),
    (lambda: Sphere(1.0, angle=(0.5, 0.5)), r"Sphere.angle .*a0 != a1"),
    (lambda: Sphere(-1.0, angle=(0.0, 1.0)), r"Sphere.radius must be > 0"),
    (lambda: Sphere(1.0, angle=(-0.5, 1.0)), r"Sphere.angle .*\[0, pi\]"),
    (lambda: Torus(1.0, 0.0, angle=(0.0, 1.0)), "Torus.tube_radius must be > 0"),
    (lambda: Torus(-1.0, 1.0, angle=(0.0, 1.0)), "Torus.centre_radius must be >= 0"),
    (lambda: Torus(2.0, 1.0, angle=(0.0, 7.0)), r"Torus.angle .*2 pi"),
    (lambda: Ellipse(1.0, 0.0, angle=(0.0, 1.0)), "Ellipse.semi_z must be > 0"),
    (lambda: Ellipse(1.0, 1.0, angle=(0.0, 4.0)), r"Ellipse.angle .*\[0, pi\]"),
    (lambda: Cone((0.0, 1.0), (1.0, 0.0)), "Cone: start .* apex .*frustum or round it"),
])
def test_segments_refuse_bad_parameters(make, words):
    """Zero length, out-of-range parameters and a cone's apex: the segment and the
    parameter named."""
    with pytest.raises(ValueError, match=words):
        make()


@pytest.mark.parametrize("segments, words", [
    ((Sphere(1.0, angle=(0.0, 1.0)), Cylinder(1.0, (0.0, -1.0))),
     r"segment 1 \(Cylinder\) does not meet segment 0 \(Sphere\)"),
    ((Torus(0.5, 1.0, angle=(0.0, 4.0)),), r"segment 0 \(Torus\) reaches r0 = .* < 0"),
    ((Torus(1.0, 1.0, angle=(PI, 2 * PI)),),
     r"a pole inside the meridian: segment 0 \(Torus\) touches the axis"),
    ((Sphere(1.0, angle=(0.0, PI)), Sphere(1.0, -2.0, angle=(0.0, PI / 2))),
     r"a pole inside the meridian: the joint of segment 0 \(Sphere\) and segment 1"),
    ((Torus(1.0, 1.0, angle=(1.5 * PI, 2 * PI)),),
     r"segment 0 \(Torus\) meets the axis at the meridian's first end .* not at a right "
     r"angle .*frustum or round it"),
    ((Cylinder(1.0, (0.0, -1.0)), Torus(1.0, 1.0, angle=(PI, 1.5 * PI))),
     r"segment 1 \(Torus\) meets the axis at the meridian's second end"),
])
def test_meridian_refusals(segments, words):
    """Segments that do not meet, r0 < 0, a point or a joint on the axis inside, a pole
    at an oblique angle: the segment's index and type named."""
    with pytest.raises(ValueError, match=words):
        Meridian(segments)


def test_meridian_refuses_non_segments_and_at_end_names():
    with pytest.raises(TypeError, match="segment 0 is a tuple"):
        Meridian(((0.0, 1.0),))
    with pytest.raises(ValueError, match="at least one segment"):
        Meridian(())
    with pytest.raises(ValueError, match="'first' or 'second'"):
        capsule().at_end("top")


def test_segment_interface_is_checked_when_a_class_is_defined():
    """A segment type that lacks a member of the interface is a TypeError at its
    definition, not at its first use."""
    with pytest.raises(TypeError, match=r"does not implement \['end', 'trace_key'"):
        class Incomplete(Segment):          # noqa: F841 (the definition is the test)
            start = (0.0, 0.0)

            @property
            def length(self):
                return 1.0

            def evaluate(self, u, xp=np):
                return u, u, u, u
