"""The elements of a thin shell (:mod:`shellbvp.mesh`): graded into every layer, their number
growing like the logarithm of the shell's length in layer widths, never like R/t (no solve:
the mesh is the scene's data)."""

import math

import numpy as np
import pytest

import shellbvp
from shellbvp.mesh import (CORE_ELEMENTS, GRADING, POLE_CORE, SINGLE_T, layer_width, mesh_of,
                           single_mesh)
from shellbvp.problems import thin_shells as ts


def test_a_thick_shell_is_one_element_per_piece():
    sc = shellbvp.cap(math.pi / 6, 0.01)                  # the default cap, T = 5.2
    assert sc.shallowness <= SINGLE_T
    assert mesh_of(sc) == single_mesh(sc) and not mesh_of(sc).graded


@pytest.mark.parametrize("R_over_t", [1e2, 1e3, 1e4, 1e5])
def test_the_hemisphere_is_graded_into_its_edge_and_its_loaded_pole(R_over_t):
    """Clamped equator: the innermost element one layer width sqrt(h R) / LAYER_FACTOR; the
    loaded pole: POLE_CORE thicknesses; consecutive elements differ by GRADING at most."""
    sc = ts.hemisphere(R_over_t)
    m = mesh_of(sc)
    L = np.asarray(m.lengths)
    assert m.graded and m.ends[0] == 0.0 and m.ends[-1] == sc.length
    assert L[0] == pytest.approx(POLE_CORE * sc.h, rel=1e-12)
    edge = CORE_ELEMENTS * layer_width(sc, 0, sc.length)
    assert L[-1] == pytest.approx(edge, rel=1e-12)
    assert edge == pytest.approx(math.sqrt(sc.h) / 1.3, rel=1e-12)      # R = 1, t = 1
    ratio = L[1:] / L[:-1]
    assert np.all(ratio <= GRADING * (1 + 1e-9)) and np.all(ratio >= 1 / GRADING - 1e-9)


def test_the_elements_grow_like_the_logarithm_of_R_over_t():
    """From R/t = 1e2 to 1e5 the layer narrows 32x (sqrt(h)) and the pole's core 1000x
    (h): log2 of them, ~5 and ~10 more elements, not the 32x or 1000x a uniform mesh
    would need."""
    counts = [mesh_of(ts.hemisphere(rt)).elements for rt in (1e2, 1e5)]
    assert counts[1] - counts[0] <= math.log2(32) + math.log2(1000) + 2
    assert counts[1] < 2.5 * counts[0]


def test_a_long_cylinder_costs_the_logarithm_of_its_length():
    """L / sqrt(R t) from 10 to 1000: a few elements more (the middle is one membrane
    stretch, graded from both ends), not a hundred times more."""
    counts = [mesh_of(ts.long_cylinder(L, 100)).elements for L in (20, 1000)]
    assert counts[1] - counts[0] <= 2 * math.log2(1000 / 20) + 2


def test_every_interface_of_the_scene_is_an_element_boundary():
    """Joints, breaks and rings stay interfaces (the unknowns may jump there) and each
    is graded into from both sides."""
    geo = shellbvp.geometry.Meridian((shellbvp.geometry.Cylinder(1.0, (0.0, 3.0)),))
    sc = shellbvp.Scene(geometry=geo, h=1e-4, material="koiter", nu=0.3,
                        ends=("clamped", "free"), breaks=(1.0,),
                        rings=(shellbvp.Ring(2.0, radial=1.0),))
    m = mesh_of(sc)
    for x in (1.0, 2.0):
        k = int(np.argmin(np.abs(np.asarray(m.ends) - x)))
        assert m.ends[k] == x
        assert m.lengths[k - 1] == pytest.approx(m.lengths[k], rel=1e-12)   # both sides
        assert m.lengths[k] == pytest.approx(CORE_ELEMENTS * layer_width(sc, 1, x),
                                             rel=1e-12)
    assert int(np.sum(m.interfaces())) == sc.pieces - 1
    assert list(m.pieces) == sorted(m.pieces)


def test_bad_grading_is_refused():
    sc = ts.hemisphere(1e4)
    with pytest.raises(ValueError, match="grading must be a number in"):
        mesh_of(sc, grading=1.0)
    with pytest.raises(ValueError, match="core must be a number in"):
        mesh_of(sc, core=0.0)
