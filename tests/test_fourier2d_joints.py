"""The 2D discretisation of a shell of several pieces (:mod:`shellbvp.fourier2d`): the joint
between two pieces is rigid at finite amplitude, imposed with multipliers per harmonic.

Independent routes: the per-harmonic second variation of :func:`shellbvp.harmonics.modes`
(the linearised joint condition plus its interface term from a least-squares multiplier,
assembled by hand) for the spectrum; jax.grad and a jvp of the Lagrangian against the
chain-rule assembly for the gradient and Hessian; the angle between the tangents measured
on the synthesised surface for the joint condition."""

import numpy as np
import pytest

from shellbvp import harmonics as H
from shellbvp.fourier2d import Fourier2D


@pytest.fixture(scope="module")
def bud():
    """Budding's curvature-only patch at kbar = 4 (two pieces: the patch edge is a break of
    the stimulus where the curvature and the stretch jump) on the class of n = 2, K = 1."""
    from shellbvp.problems import budding

    eq = budding.equilibrium(0.0, 1.0, 4.0)
    return eq, Fourier2D(eq, 2, 1)


def test_the_joint_adds_one_multiplier_per_harmonic_and_the_base_is_stationary(bud):
    eq, f = bud
    assert eq.scene.pieces == 2 and f.joints == 1 and f.size == f.ny + 2
    assert list(f.indices(2)[-1:]) == [f.ny + 1]
    U = f.origin
    # the base holds the joint at every omega (its reference angle: zero, the sphere does
    # not turn); with the multipliers of the least-squares fit the joint's moment (|dE/dy|
    # = 59 without them) is balanced to the axisymmetric solver's residual (1e-8); the
    # harmonic 2 multiplier vanishes by symmetry
    assert f._joints[0]["angle"] == 0.0 and np.max(np.abs(f.joint_angles(U))) < 1e-12
    g = f.gradient(U)
    assert np.linalg.norm(g) < 1e-8 * np.linalg.norm(f.gradient(np.zeros(f.size)))
    assert abs(U[f.multipliers(2)][0]) < 1e-12 * abs(U[f.multipliers(0)][0]) + 1e-15


@pytest.mark.slow
def test_the_lagrangians_chain_rule_hessian_is_jaxs(bud):
    """At a state off the base (a random displacement in both harmonics and random
    multipliers): the assembled gradient and Hessian against jax.grad and a jvp."""
    _, f = bud
    rng = np.random.default_rng(3)
    U = f.origin + 1e-3 * rng.standard_normal(f.size)
    g, Hm = f.hessian(U, gradient=True)
    ga = f.gradient(U)
    assert np.max(np.abs(g - ga)) < 1e-9 * np.max(np.abs(ga))
    v = rng.standard_normal(f.size)
    hv = f.hvp(U, v)
    assert np.max(np.abs(Hm @ v - hv)) < 1e-9 * np.max(np.abs(hv))


def test_the_spectrum_at_the_base_is_the_harmonics_second_variation(bud):
    """Block k's eigenvalues on the linearised joint's null space (the Lagrangian's Hessian
    there) against :func:`shellbvp.harmonics.modes` (harmonic 0 without its twist modes,
    which the class excludes). The two estimate the joint's moment differently from a base
    stationary to ~1e-8, hence 1e-7."""
    eq, f = bud
    ref = H.modes(eq, [0, 2], count=3).spectra
    assert np.allclose(f.block_eigenvalues(2, count=3), ref[1].eigenvalues, rtol=1e-7)
    assert f.block_eigenvalues(0, count=1)[0] == pytest.approx(ref[0].eigenvalues[0],
                                                               rel=1e-7)
    # the whole class at once (eigenvalues): the lowest of both harmonics, in order
    lowest = sorted([ref[0].eigenvalues[0], ref[1].eigenvalues[0]])
    assert np.allclose(f.eigenvalues(f.origin, count=2), lowest, rtol=1e-7)
