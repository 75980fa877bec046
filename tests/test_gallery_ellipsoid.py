"""The ellipsoidal vessel gallery case (figures/gallery_ellipsoid.py): a closed oblate spheroid
(a/b = 2) under internal pressure against the membrane theory of shells of revolution; the
tolerance (t / r1_min) and its reason are stated there."""

import math
import os
import sys

import numpy as np
import pytest

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

import gallery_ellipsoid as case  # noqa: E402


def test_published_table_is_the_membrane_solution():
    """The CSV holds the closed form; at the equator N_phi = p a / 2, N_theta = -p a."""
    pub = case.read_published()
    r1, r2, n1, n2 = case.membrane(pub["u[rad]"])
    assert np.allclose(pub["N_phi[N/mm]"], n1, rtol=1e-12)
    assert np.allclose(pub["N_theta[N/mm]"], n2, rtol=1e-12)
    assert np.allclose(case.parameter_of_arclength(pub["s[mm]"]), pub["u[rad]"], atol=1e-9)
    _, _, n1, n2 = case.membrane(math.pi / 2)
    assert n1 == pytest.approx(case.P * case.A / 2) and n2 == pytest.approx(-case.P * case.A)


@pytest.mark.slow
def test_gallery_ellipsoid():
    r = case.run()
    assert r["ok"], {k: r[k] for k in ("shellbvp", "tolerance", "deviation_by_a_over_t")}
