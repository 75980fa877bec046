"""The ring-loaded cap gallery case (figures/gallery_cap_ring_load.py): a clamped shallow
spherical cap under an axial ring load at r = 0.42 a against Teng & Rotter (1989), Fig. 12
(its limit load), and the linear shallow-shell theory; the tolerances and their reasons are
stated there."""

import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

import gallery_cap_apex_load as apex  # noqa: E402
import gallery_cap_ring_load as case  # noqa: E402


def test_ring_flexibility_limits():
    """The closed form the engine is checked against reproduces its two limits: the
    Kirchhoff plate under a ring load (R -> infinity; Timoshenko & Woinowsky-Krieger,
    Sec. 19: w(0) = P / (8 pi D) [(a^2 - b^2) / 2 + b^2 ln(b / a)]) and the apex load's
    closed form (the ring shrunk to the pole; the difference is O(b^2 ln b))."""
    D = case.E * case.T**3 / (12 * (1 - case.NU**2))
    a, b = case.A, case.B
    plate = ((a * a - b * b) / 2 + b * b * math.log(b / a)) / (8 * math.pi * D)
    assert case.ring_flexibility(R=1e6)[0] == pytest.approx(plate, rel=1e-8)
    assert case.ring_flexibility(b=1e-4)[0] * apex.reissner_stiffness() == pytest.approx(
        1.0, rel=1e-5)


def test_scene_file_ring_and_linear_flexibility():
    """The scene file puts one dead axial ring of total force -P on the circle r = 0.42 a
    of the sphere; at a small load the spectral method's interface rows and the energy
    method's potential on a mesh node (independent routes) agree to 1e-6 (observed 1.3e-7),
    and both lie within (a/R)^2 of linear shallow-shell theory (observed +2.24 %, falling
    as (a/R)^2 with R at fixed lambda: the shallow approximation's own error)."""
    import shellbvp

    sf = shellbvp.load_scene(case.SCENE)
    L = sf.units.length
    (ring,) = sf.scene.rings
    assert ring.radial is None
    assert ring.s * L == pytest.approx(case.S_RING, rel=1e-12)
    r0 = float(sf.scene.geometry.evaluate(ring.s)[0]) * L
    assert r0 == pytest.approx(0.42 * case.A, rel=1e-9)
    assert ring.axial(0.5) * sf.units.point_force == pytest.approx(-0.5 * sf.scale, rel=1e-12)
    assert sf.folds == 1

    P = case.P_LINEAR
    spectral = case.initial_flexibility(sf, P)
    energy = -shellbvp.solve(sf.scene, P / sf.scale, method="energy").w * L / P
    assert abs(energy / spectral - 1) < 1e-6, (spectral, energy)
    assert abs(spectral / case.ring_flexibility()[0] - 1) <= case.FLEX_TOLERANCE


@pytest.mark.slow
def test_gallery_cap_ring_load():
    r = case.run()
    assert r["load_minimum"] is not None              # through the snap: two folds
    assert r["ok"], {k: r[k] for k in ("published", "shellbvp", "difference", "tolerance",
                                       "initial_flexibility")}
