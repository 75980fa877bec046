"""Bad input to the energy functions: ValueError naming the parameter and the range."""

import numpy as np
import pytest

import shellbvp

GOOD = (1.0, 1.0, -1.0, -1.0, -1.0, -1.0)


@pytest.mark.parametrize("kwargs,match", [
    (dict(h=0.0), r"h must lie in \(0, 1\)"),
    (dict(h=1.0), r"h must lie in \(0, 1\)"),
    (dict(h=-0.1), r"h must lie in \(0, 1\)"),
    (dict(h=np.nan), "h must be finite"),
    (dict(h=0.01, lam=0.0), "lam must be > 0"),
    (dict(h=0.01, lam=-2.0), "lam must be > 0"),
    (dict(h=0.01, model="koiter_linear"), "model must be one of"),
    (dict(h=0.01, material="rubber"), "material must be one of"),
    (dict(h=0.01, rhob1=0.0), "rhob1 must be > 0"),
    (dict(h=0.01, rhob2=np.inf), "rhob2 must be finite"),
])
def test_bad_parameters(kwargs, match):
    with pytest.raises(ValueError, match=match):
        shellbvp.energy_density(*GOOD, **kwargs)


@pytest.mark.parametrize("i,name", [(0, "lam1"), (1, "lam2")])
@pytest.mark.parametrize("value", [0.0, -0.5])
def test_non_positive_stretch(i, name, value):
    state = list(GOOD)
    state[i] = value
    with pytest.raises(ValueError, match=f"{name} .*must be > 0"):
        shellbvp.energy_density(*state, h=0.01)


@pytest.mark.parametrize("i,name", list(enumerate(["lam1", "lam2", "k1", "k2", "kb1", "kb2"])))
def test_non_finite_state(i, name):
    state = list(GOOD)
    state[i] = np.nan
    with pytest.raises(ValueError, match=f"{name} must be finite"):
        shellbvp.energy_terms(*state)


def test_nh_ignores_lam():
    """For the incompressible material lam is not a parameter: any value, even 0, is fine."""
    a = shellbvp.energy_density(1.1, 0.9, 0.2, 0.3, 0.1, 0.0, h=0.05, material="nh", lam=0.0)
    b = shellbvp.energy_density(1.1, 0.9, 0.2, 0.3, 0.1, 0.0, h=0.05, material="nh", lam=5.0)
    assert a == b


def test_exact_rejects_folding_thickness_map():
    with pytest.raises(ValueError, match="h\\*max\\|k\\| < 2"):
        shellbvp.energy_density(1.0, 1.0, 30.0, 0.0, 0.0, 0.0, h=0.1, exact=True)


def test_broadcasting():
    l1 = np.linspace(0.9, 1.1, 5)[:, None]
    k = np.linspace(-1, 1, 3)[None, :]
    W = shellbvp.energy_density(l1, 1.0, k, -1.0, -1.0, -1.0, h=0.01)
    assert W.shape == (5, 3)
    assert W[2, 0] == shellbvp.energy_density(1.0, 1.0, -1.0, -1.0, -1.0, -1.0, h=0.01)
    We = shellbvp.energy_density(l1, 1.0, k, -1.0, -1.0, -1.0, h=0.01, exact=True)
    assert We.shape == (5, 3)
