"""Zoelly's sphere under external pressure (figures/gallery_zoelly_sphere.py): its first
bifurcation against the classical p_cl; the 1 % tolerance and its reasons are stated in the
case's docstring."""

import math
import os
import sys

import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

import gallery_zoelly_sphere as case  # noqa: E402


def test_scene_is_the_stated_sphere():
    """The file's sphere: R/t = 100, nu = 0.3, the upper half, p_cl = 25.4196 MPa (from the
    formula), its range past p_cl; the whole-number degree l = 18 at p_l / p_cl = 1.0006
    (l (l + 1) = 342 nearest sqrt(12 (1 - nu^2)) R/t = 330.5)."""
    g = case.shell()
    assert g["R"] / g["t"] == pytest.approx(100.0)
    assert g["nu"] == 0.3 and g["angle"] == pytest.approx([0.0, math.pi / 2], abs=1e-15)
    p_cl = case.classical(g["R"], g["t"], g["E"], g["nu"])
    assert p_cl == pytest.approx(2 * 210000.0 * 1e-4 / math.sqrt(2.73), rel=1e-12)
    assert p_cl == pytest.approx(25.4196, abs=1e-4)
    assert g["to"] > 1.5 * p_cl
    l, ratio = case.discrete(100.0, 0.3)
    assert l == 18 and ratio == pytest.approx(1.0006, abs=1e-4)


@pytest.mark.slow  # the branch and the harmonics' root searches: ~20-40 s
def test_gallery_zoelly_sphere():
    r = case.run()
    assert r["ok"], [c for c in r["checks"] if not c["ok"]]


@pytest.mark.slow  # ~20-60 s: the branch to p_cl and the root searches of a fine spectrum
def test_zoelly_sphere_at_R_over_t_1000(tmp_path):
    """The same file at t = 1 mm (R/t = 1000, its range scaled with p_cl): the first
    bifurcation within the case's 1 % of Zoelly's p_cl (the reasons shrink with t/R: the
    prebuckling compression is ~0.04 % here, the nearest whole spherical degree closer), its
    error estimate small beside that bound (measured: n = 49 at 0.99954 p_cl +- 1.4e-4)."""
    import shellbvp

    g = case.shell()
    p_cl = case.classical(g["R"], 1.0, g["E"], g["nu"])
    from _common import scene_copy

    sf = shellbvp.load_scene(scene_copy(case.SCENE, tmp_path, [
        ("thickness = 10.0", "thickness = 1.0"), ("to = 40.0 ", f"to = {1.6 * p_cl!r} ")]))
    ins = sf.first_instability()
    assert ins.kind == "bifurcation"
    assert abs(ins.p / p_cl - 1) <= case.TOLERANCE
    assert ins.error_estimate <= 0.1 * case.TOLERANCE * ins.p   # small beside the bound



#: a complete sphere under uniform pressure is symmetric under every rotation, so all
#: bifurcation modes of one spherical degree l (here l = 18: the harmonics n = 0, 2, ..., 18
#: even about the equator) buckle at exactly one load: the symmetry is an independent check
#: of the roots' error estimates, each root located on its own perturbation discretisation
@pytest.fixture(scope="module")
def at_tight_tolerance():
    import shellbvp

    return shellbvp.load_scene(case.SCENE).first_instability(tol=1e-9)


@pytest.mark.slow  # ~30-60 s: the branch and the root searches of the multiplet at tol 1e-9
def test_the_cluster_is_listed_at_the_command_lines_tolerance(at_tight_tolerance):
    """At tol 1e-9 (the command line's) ``nearby`` lists five harmonics of l = 18, and the
    critical one's estimate covers each root it is listed with. It once listed only the
    critical harmonic: the eigenvalue's slope, taken between the root search's last two
    evaluations ~1e-10 apart, carried their round-off, and the estimates were 5 to 50
    times short of the multiplet's spread."""
    ins = at_tight_tolerance
    assert ins.kind == "bifurcation" and len(ins.nearby) == 5, ins.nearby
    for n, p, e in ins.nearby:
        assert n % 2 == 0 and n <= 18, n
        assert abs(p - ins.p) <= e + ins.error_estimate, (n, p, e, ins.p)


@pytest.mark.slow
def test_every_pair_of_the_multiplet_agrees_within_its_estimates(at_tight_tolerance):
    """The multiplet's roots pairwise within their summed estimates (the symmetry above).
    It failed (up to 1.5 times the summed estimates for n = 10, 14, 18) while a root's
    degree error was the eigenvalue's change on a finer degree alone: the high harmonics'
    eigenvalues wander by their round-off floor from one degree to the next, which the
    estimate now includes (HarmonicSpectrum.roundoff)."""
    near = at_tight_tolerance.nearby
    for n, p, e in near:
        for m, q, f in near:
            assert abs(p - q) <= e + f, ((n, p, e), (m, q, f))
