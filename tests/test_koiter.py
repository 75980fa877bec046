"""The morphoelastic Koiter reference model (Efrati et al. 2009): checked against classical linear
plate theory with Poisson ratio nu, the stress-free state, and the incompressible limit of
the derived neo-Hookean energy; and it runs through the equilibrium solver."""

import math

import numpy as np
import pytest

import shellbvp


@pytest.mark.parametrize("nu", [0.0, 0.3, 0.5])
def test_flat_plate_is_classical_plane_stress(nu):
    """Classical plate: bending energy per area D/2 [(k1 + k2)^2 - 2 (1 - nu) k1 k2],
    D = Y h^3/(12 (1 - nu^2)), Y = 2 mu (1 + nu): per mu and unit thickness
    h^2/12 * [(k1 + k2)^2 - 2 (1 - nu) k1 k2] / (1 - nu)."""
    k1, k2 = 0.3, -0.7
    ws, wb, rho1, rho2 = shellbvp.energy_terms(1.0, 1.0, k1, k2, 0.0, 0.0, material="koiter",
                                               nu=nu)
    assert ws == 0 and rho1 == 1 and rho2 == 0
    assert wb == pytest.approx(((k1 + k2) ** 2 - 2 * (1 - nu) * k1 * k2) / (1 - nu), rel=1e-14)


def test_incompressible_koiter_matches_nh_to_leading_order():
    """At nu = 1/2 and small strains Koiter and the derived NH energy agree to leading order."""
    eps = 1e-4
    a = shellbvp.energy_density(1 + 0.3 * eps, 1 - 0.5 * eps, -1 + eps, -1 - 2 * eps, -1.0, -1.0,
                                h=0.02, material="koiter")
    b = shellbvp.energy_density(1 + 0.3 * eps, 1 - 0.5 * eps, -1 + eps, -1 - 2 * eps, -1.0, -1.0,
                                h=0.02, material="nh")
    assert a == pytest.approx(b, rel=1e-3)


def test_stress_free_and_bad_nu():
    assert shellbvp.energy_density(1, 1, 0.4, -0.2, 0.4, -0.2, h=0.1, material="koiter") == 0
    with pytest.raises(ValueError, match="nu must lie in"):
        shellbvp.energy_density(1, 1, 0, 0, 0, 0, h=0.1, material="koiter", nu=1.0)
    with pytest.raises(ValueError, match="exact=True"):
        shellbvp.energy_density(1, 1, 0, 0, 0, 0, h=0.1, material="koiter", exact=True)
    with pytest.raises(ValueError, match="nu"):
        shellbvp.cap(0.5, 0.01, material="koiter", nu=-1.5)


def test_koiter_cap_solves_and_is_undeformed_at_zero_stimulus():
    from shellbvp.problems import cap_eversion as ce

    sc = ce.scene(math.pi / 6, 0.01, material="koiter")
    eq = shellbvp.solve(sc, 0.0, estimate_error=False)
    assert np.max(np.abs(eq.theta - eq.s)) <= 1e-10
    eq1 = shellbvp.solve(sc, 1.0, guess=eq, estimate_error=False)
    assert eq1.success and eq1.w > 0
