"""The reduced energy of general (non-diagonal) forms (shellbvp.forms) against independent
computations.

References: the principal-frame energy of shellbvp.energy (derived separately, in the lines
of curvature) for diagonal forms; scalar invariance (a change of surface coordinates
a -> P^T a P for all four forms leaves W unchanged); the 3D energy integrated through the
thickness by Gauss-Legendre quadrature with the exact thickness map, which the reduced W
must match to O(h^4) (error ratio 16 when h halves) at generic non-diagonal states.
"""

import numpy as np
import pytest

from shellbvp import energy_density
from shellbvp.forms import exact_energy, reduced_energy

CASES = [("relaxed", "cg", dict(lam=2.0)), ("plane_strain", "cg", dict(lam=2.0)),
         ("relaxed", "nh", {}), ("relaxed", "koiter", dict(nu=0.3))]


def _diag_forms(state, g=(1.1, 0.6)):
    l1, l2, k1, k2, kb1, kb2 = state
    abar = np.diag(g)
    a = np.diag([l1**2 * g[0], l2**2 * g[1]])
    return a, np.diag([k1 * a[0, 0], k2 * a[1, 1]]), abar, np.diag([kb1 * g[0], kb2 * g[1]])


@pytest.mark.parametrize("model,material,kw", CASES)
def test_diagonal_forms_give_the_principal_energy(model, material, kw, states):
    for st in states[:3]:
        W = float(reduced_energy(*_diag_forms(st), h=0.05, model=model, material=material,
                                 rhob=(1.1, 0.02, 0.0), **kw))
        ref = energy_density(*st, h=0.05, model=model, material=material, rhob1=1.1,
                             rhob2=0.02, **kw)
        assert W == pytest.approx(ref, rel=1e-12, abs=1e-15)


@pytest.mark.parametrize("model,material,kw", CASES)
def test_energy_is_a_scalar_under_a_change_of_coordinates(model, material, kw):
    rng = np.random.default_rng(7)
    sym = lambda m: (m + m.T) / 2  # noqa: E731
    a = np.eye(2) + 0.1 * sym(rng.normal(size=(2, 2)))
    abar = np.eye(2) + 0.1 * sym(rng.normal(size=(2, 2)))
    b, bbar = -a + 0.3 * sym(rng.normal(size=(2, 2))), -abar + 0.3 * sym(rng.normal(size=(2, 2)))
    P = np.array([[1.0, 0.3], [-0.4, 0.8]])
    tr = lambda m: P.T @ m @ P  # noqa: E731
    W = float(reduced_energy(a, b, abar, bbar, h=0.05, model=model, material=material, **kw))
    W2 = float(reduced_energy(tr(a), tr(b), tr(abar), tr(bbar), h=0.05, model=model,
                              material=material, **kw))
    assert W2 == pytest.approx(W, rel=1e-12)


@pytest.mark.parametrize("model,material", [("relaxed", "cg"), ("plane_strain", "cg"),
                                            ("relaxed", "nh")])
def test_reduction_error_is_fourth_order_at_non_diagonal_states(model, material):
    A = np.array([[1.1, 0.2], [0.2, 0.9]])
    B = np.array([[-1.2, 0.3], [0.3, -0.5]])
    Ab = np.array([[1.0, -0.1], [-0.1, 1.2]])
    Bb = np.array([[-0.7, 0.2], [0.2, -1.0]])
    err = [abs(float(reduced_energy(A, B, Ab, Bb, h=h, lam=3.0, model=model, material=material))
               - exact_energy(A, B, Ab, Bb, h=h, lam=3.0, model=model, material=material))
           for h in (0.1, 0.05, 0.025)]
    ratios = [err[0] / err[1], err[1] / err[2]]
    assert all(14.0 < r < 18.0 for r in ratios), (err, ratios)
