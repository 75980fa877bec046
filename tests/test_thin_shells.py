"""Thin shells by the default method (problems/thin_shells.py): every expected value is a
closed form of the classical thin-shell literature (Reissner's point-loaded sphere, the
beam on an elastic foundation of a long cylinder's edge, Kirchhoff's plates), each within
its own theory's error, or the same computation refined (the degree per element, the
grading of the elements into the layers), or another method."""

import math

import numpy as np
import pytest

import shellbvp
from shellbvp import Chebyshev, Shooting
from shellbvp.bvp import ShellBVP
from shellbvp.continuation.newton import newton
from shellbvp.mesh import mesh_of
from shellbvp.methods.chebyshev import ChebyshevSystem
from shellbvp.problems import thin_shells as ts


def theory_error(R_over_t: float) -> float:
    """Reissner's shallow-shell result misses the deep shell's terms of relative order
    (t/R) ln(R/t) (problems/thin_shells.py); the bound with coefficient one."""
    return math.log(R_over_t) / R_over_t


def test_reissner_at_R_over_t_1e3_with_an_honest_estimate():
    """R/t = 1e3: P / w within (t/R) ln(R/t) of Reissner's; the point's error estimate
    bounds its change at twice the degree per element (an independent, much finer solve)."""
    k = ts.pole_stiffness(1e3)
    kR = ts.reissner_stiffness(1e3)
    assert abs(k.stiffness / kR - 1) <= theory_error(1e3)
    assert k.stats["elements"] > 1                     # graded into its layers
    sc = ts.hemisphere(1e3)
    P = kR * 1e-4 * sc.h
    fine = shellbvp.solve(sc, P, method=Chebyshev(nodes=32), estimate_error=False)
    w = P / k.stiffness
    assert abs(-fine.w - w) <= k.error_estimate / k.stiffness * w
    assert k.error_estimate / k.stiffness <= 1e-6


def test_clamped_plate_at_a_over_t_1e4():
    """A clamped plate of a/t = 1e4 at w/t = 1e-3: Kirchhoff's p a^4 / (64 D) to the
    membrane stiffening's (w/t)^2 ~ 1e-6 (a bound of 1e-5)."""
    w_lin = ts.plate_deflection(1.0, 1e4)
    h = 1e-4
    p = 1e-3 * h / w_lin
    eq = shellbvp.solve(ts.plate(1e4), p)
    assert -eq.w == pytest.approx(ts.plate_deflection(p, 1e4), rel=1e-5)


def test_shooting_refuses_a_point_loaded_pole_and_names_the_remedy():
    """The pole offset shooting starts from is not refined by its ladder: a point-loaded
    pole is refused, the message naming the methods that resolve it."""
    with pytest.raises(ValueError, match="spectral"):
        Shooting().discretise(ShellBVP(ts.hemisphere(1e3)))


@pytest.mark.slow
@pytest.mark.parametrize("R_over_t", [1e2, 1e3, 1e4, 1e5])
def test_reissner_from_R_over_t_1e2_to_1e5(R_over_t):
    """The clamped hemisphere's pole stiffness within (t/R) ln(R/t) of Reissner's at every
    thinness, solved by the default method, its estimate small beside that bound (at
    R/t = 1e5 the estimate is the round-off floor of a deflection of 1e-4 t: 1.8e-6)."""
    k = ts.pole_stiffness(R_over_t)
    kR = ts.reissner_stiffness(R_over_t)
    assert abs(k.stiffness / kR - 1) <= theory_error(R_over_t)
    assert k.error_estimate / kR <= 0.1 * theory_error(R_over_t)


@pytest.mark.slow
def test_observed_convergence_in_the_degree_at_R_over_t_1e4():
    """R/t = 1e4, w/t = 1e-2: w at degrees 8 .. 16 per element against degree 28: the error
    falls fast (at least 3x per two degrees) down to the round-off of coordinates of the
    shell's size (1e-14 R; w is 1e-6 R)."""
    sc = ts.hemisphere(1e4)
    P = ts.reissner_stiffness(1e4) * 1e-2 * sc.h
    ref = shellbvp.solve(sc, P, method=Chebyshev(nodes=28), estimate_error=False).w
    errors = [abs(shellbvp.solve(sc, P, method=Chebyshev(nodes=N),
                                 estimate_error=False).w - ref) / abs(ref)
              for N in (8, 10, 12, 14, 16)]
    floor = 1e-14 / abs(ref)
    for a, b in zip(errors, errors[1:]):
        assert b <= a / 3 or b <= floor, errors
    assert min(errors) <= floor, errors


@pytest.mark.slow
def test_the_grading_does_not_change_the_solution():
    """R/t = 1e4, degree 16: meshes graded by 2, 3 and 4 (more or fewer elements in the
    layers) give the same w to the round-off of coordinates of the shell's size (1e-14 R,
    45 units in the last place; w itself is 1e-6 R): the elements resolve the layers
    whatever their grading."""
    sc = ts.hemisphere(1e4)
    P = ts.reissner_stiffness(1e4) * 1e-2 * sc.h
    ws = []
    for grading in (2.0, 3.0, 4.0):
        bvp = ShellBVP(sc).on_mesh(mesh_of(sc, grading=grading))
        system = ChebyshevSystem(bvp, 16)
        res = newton(system, np.zeros(system.size), P, 0.0, 1.0, P, tol=1e-12, maxiter=30,
                     fail_fast=False)
        assert res.ok
        ws.append(system.monitor(res.U)[0])
    assert max(ws) - min(ws) <= 1e-14, ws


@pytest.mark.slow
def test_a_long_cylinder_edge_layer_at_L_of_1000_layer_widths():
    """L = 1000 sqrt(R t), R/t = 1000: the radial displacement along the edge zone equals the
    beam on an elastic foundation's to a few t/R of u_inf (its theory's error), and the
    far field is u_inf."""
    R_over_t, p = 1e3, 1e-6
    sc = ts.long_cylinder(1e3, R_over_t)
    eq = shellbvp.solve(sc, p)
    h = 1.0 / R_over_t
    x = np.linspace(0.0, 6.0, 61) * math.sqrt(h)
    r, _ = eq(x)[:2]
    u = r - 1.0
    u_bef = np.array([ts.cylinder_edge(xi, p, R_over_t) for xi in x])
    u_inf = ts.cylinder_edge(1e9, p, R_over_t)
    assert np.max(np.abs(u - u_bef)) <= 5 * h * u_inf
    assert eq.stats["elements"] < 60                   # graded, not uniform


@pytest.mark.slow
@pytest.mark.parametrize("R_over_t", [1e2, 1e3])
def test_the_methods_agree_within_their_estimates(R_over_t):
    """Spectral, energy (Ritz) and collocation give the pole stiffness at w/t = 1e-2 within
    the sum of their error estimates (two methods that disagree beyond them would be a
    bug); shooting refuses the point-loaded pole."""
    found = {m: ts.pole_stiffness(R_over_t, w_over_t=1e-2, method=m)
             for m in ("spectral", "energy", "collocation")}
    names = list(found)
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            ka, kb = found[a], found[b]
            assert abs(ka.stiffness - kb.stiffness) <= ka.error_estimate + kb.error_estimate, \
                (a, b, ka, kb)
    with pytest.raises(ValueError, match="point load at a pole"):
        ts.pole_stiffness(R_over_t, method="shooting")
