"""Stability beyond axisymmetry (shellbvp.harmonics, shellbvp.instability): the second
variation per circumferential harmonic against what it must be.

References: the axisymmetric fold found by the Euler-Lagrange continuation (dp/dw = 0,
another computation) is a zero of the n = 0 eigenvalue, whose sign agrees with the
independent axisymmetric second variation (shellbvp.stability.second_variation) before and
after it; the free cap's rigid motions (translations, rotations: closed forms) are zero
modes of n = 0 and 1 at every stimulus, the clamped cap has none; the reflection symmetry of
the base state decouples the cos and sin components exactly; spectral convergence with the
degree; and the published bifurcation of the clamped cap under pressure at lambda_B = 6
(Huang 1964; Teng & Rotter 1989b, Table 3: p/p0 = 0.775-0.777, n = 2, Koiter, nu = 1/3,
R/t = 100).
"""

import math
from functools import lru_cache

import numpy as np
import pytest

import shellbvp
from shellbvp import harmonics as H
from shellbvp.problems import cap_eversion as ce
from shellbvp.problems import pressure_cap as pc
from shellbvp.stability import second_variation
from test_stability import snap_branch      # the same branch, followed once per test process

THETA, H0 = math.pi / 6, 0.01


@lru_cache(maxsize=None)
def cap_at(kappa):
    return ce.equilibrium(kappa, THETA, H0)


def test_n0_vanishes_at_the_fold_and_agrees_in_sign_with_the_axisymmetric_analysis():
    b = snap_branch()
    fold = b.folds[0].equilibrium
    mu_fold = H.modes(fold, [0], count=2)[0].eigenvalues
    assert abs(mu_fold[0]) < 1e-6 * mu_fold[1]
    before, after = cap_at(2.0), b.equilibrium(len(b.points) - 1)      # after: past the fold
    for eq in (before, after):
        mine = H.modes(eq, [0])[0].lowest
        theirs = second_variation(eq).eigenvalues[0]
        assert np.sign(mine) == np.sign(theirs) != 0
    assert after.p < b.folds[0].p and H.modes(after, [0])[0].lowest < 0


def test_free_cap_has_its_rigid_modes_at_every_stimulus_clamped_cap_none():
    for kappa in (0.0, 2.0):
        M = H.modes(cap_at(kappa), [0, 1, 2])
        scale = min(sp.lowest for sp in M.spectra)
        assert scale > 0                                   # stable, rigid modes excluded
        names = [name for sp in M.spectra[:2] for name, _ in sp.rigid]
        assert names == ["axial translation", "rotation about the axis",
                         "lateral translation", "tilt"]
        for sp in M.spectra[:2]:
            for _, q in sp.rigid:
                assert abs(q) < 1e-8 * scale
        assert M[2].rigid == ()
    clamped = pc.branch(6, 100.0, 1 / 3).equilibrium(0)
    M = H.modes(clamped, [0, 1, 2])
    assert all(sp.rigid == () and sp.lowest > 0 for sp in M.spectra)


def test_cos_and_sin_components_decouple_and_the_form_is_symmetric():
    base = H._base(cap_at(2.0), 16)
    even = [0, 2, 3, 5, 7, 9, 11, 13, 15, 17]        # r, z of x, x_s, x_ss, x_oo; o of x_o, x_so
    odd = [k for k in range(18) if k not in even]
    Hq = base.H.reshape(-1, 18, 18)
    assert np.max(np.abs(Hq[:, even][:, :, odd])) < 1e-10 * np.max(np.abs(Hq))
    assert np.allclose(Hq, np.transpose(Hq, (0, 2, 1)), rtol=0, atol=1e-9 * np.max(np.abs(Hq)))


def test_eigenvalues_converge_with_the_degree():
    eq = cap_at(2.0)
    ref = np.array([sp.lowest for sp in H.modes(eq, [0, 2, 3, 8], degree=24).spectra])
    err = [np.max(np.abs(np.array([sp.lowest for sp in H.modes(eq, [0, 2, 3, 8],
                                                                  degree=d).spectra]) - ref)
                  / np.abs(ref)) for d in (8, 12, 16)]
    assert err[0] > err[1] > err[2] and err[2] < 1e-6, err


def test_bad_input_is_named():
    eq = cap_at(2.0)
    for n in (-1, 1.5, [], [0, 999]):
        with pytest.raises(ValueError, match="n must"):
            H.modes(eq, n)
    with pytest.raises(ValueError, match="count"):
        H.modes(eq, [0], count=0)
    with pytest.raises(ValueError, match="degree"):
        H.modes(eq, [0], degree=4)
    failed = shellbvp.solve(eq.scene, 2.0, guess=lambda s: np.full((6, np.size(s)), np.nan),
                            throw=False)
    with pytest.raises(ValueError, match="converged"):
        H.modes(failed, [0])
    with pytest.raises(ValueError, match="n_scan"):
        shellbvp.first_instability(snap_branch(), n_scan=1)


def test_clamped_cap_under_pressure_bifurcates_as_published_at_lambda_6():
    inst = pc.first_instability(6, 100.0, 1 / 3)
    assert inst.kind == "bifurcation" and inst.n == 2
    assert inst.p == pytest.approx(0.776, rel=0.01)          # published 0.775-0.777
    assert inst.cutoff >= 20 and "rises" in inst.cutoff_reason
    snap = pc.critical_pressure(6, nu=1 / 3).p_cr_over_p0
    assert inst.p < 0.8 * snap


@pytest.mark.slow
def test_a_stimulus_interface_converges_with_the_degree():
    """Budding's patch edge, where the curvature and the stretch jump: the tangent-plane
    condition is not linear there, and only the Lagrangian's second variation converges
    (without its interface term the n = 2 eigenvalue fell 7.35, 7.17, 6.51 at degree 16,
    24, 40 at this state)."""
    from shellbvp.problems import budding

    eq = budding.equilibrium(0.0, 1.0, 4.0)
    lo, hi = (np.array([sp.eigenvalues for sp in H.modes(eq, [0, 2], degree=d,
                                                       count=2).spectra]) for d in (16, 32))
    assert np.max(np.abs(lo - hi) / np.abs(hi)) < 1e-5


@pytest.mark.slow
def test_clamped_cap_under_pressure_bifurcates_as_published_at_lambda_16():
    """lambda_B = 16: published p/p0 = 0.790-0.792 with n = 11 (Huang 1964; Teng & Rotter
    1989b). The harmonics next to the critical one are nearly degenerate there (their
    eigenvalues within 0.07 of zero at p_cr), so n is compared to within one wave."""
    inst = pc.first_instability(16, 100.0, 1 / 3)
    assert inst.kind == "bifurcation" and abs(inst.n - 11) <= 1
    assert inst.p == pytest.approx(0.791, rel=0.01)


@pytest.mark.slow
def test_budding_bifurcation_converges_with_the_degree():
    """The (1, 1) bud's first instability at two perturbation degrees (the reference is the
    refinement itself): the same kind and n, and kbar within the reported error estimates
    of each other."""
    from shellbvp.problems import budding

    a = budding.first_instability(1.0, 1.0)
    b = budding.first_instability(1.0, 1.0, degree=32)
    assert a.kind == b.kind == "bifurcation" and a.n == b.n
    assert abs(a.p - b.p) <= a.error_estimate + b.error_estimate


@lru_cache(maxsize=None)
def _sphere_spectra(ends, centre_z=0.0):
    """Modes n = 0..3 (degree 48) of a pressurised Koiter sphere (R = 1, h = 0.01): the
    closed sphere (two poles) or its upper half with a symmetry end at the equator, the
    sphere's centre at ``centre_z``."""
    from shellbvp.geometry import Meridian, Sphere

    angle = (0.0, math.pi) if ends == ("pole", "pole") else (0.0, math.pi / 2)
    geo = Meridian((Sphere(1.0, centre_z=centre_z, angle=angle),))
    sc = shellbvp.Scene(geo, 0.01, material="koiter", nu=0.3, ends=ends,
                        pressure=lambda p: p)
    return H.modes(shellbvp.solve(sc, 0.02), n=range(4), count=3, degree=48)


@pytest.mark.slow
def test_pressurised_sphere_spectrum_is_degenerate_and_the_half_sphere_shares_it():
    """A pressurised sphere is rotation invariant, so the eigenvalues of its second variation
    depend on the spherical-harmonic degree only: every level of the closed sphere recurs
    for every n it allows (exact symmetry). The half sphere with a mirror end at the equator
    has the closed sphere's modes that are symmetric about it: each of its eigenvalues is
    one of the closed sphere's. Its rim moves radially in the mirror plane, where the
    pressure's potential needs the flat lid that closes it: without it the spectrum
    depended on where the origin is (centre_z 0 against 0.7: 7e-3 on the rigid rotation's
    quotient, 4e-3 on eigenvalues); with it, rigid motions cost nothing and the origin
    drops out."""
    closed = _sphere_spectra(("pole", "pole"))
    levels = np.concatenate([sp.eigenvalues for sp in closed.spectra])
    for lo in (closed.spectra[0].eigenvalues[0], closed.spectra[0].eigenvalues[1]):
        for sp in closed.spectra[:3]:
            assert np.min(np.abs(sp.eigenvalues - lo)) < 1e-8 * lo
    for centre_z in (0.0, 0.7):
        half = _sphere_spectra(("pole", "symmetry"), centre_z)
        for sp in half.spectra:
            for mu in sp.eigenvalues[:2]:
                assert np.min(np.abs(levels - mu)) < 1e-8 * mu, (sp.n, mu)
            for name, quotient in sp.rigid:
                assert abs(quotient) < 1e-10 * sp.eigenvalues[0], (sp.n, name, quotient)
    a, b = (_sphere_spectra(("pole", "symmetry"), cz) for cz in (0.0, 0.7))
    for sa, sb in zip(a.spectra, b.spectra):
        # the two equilibria are solved apart, each to ~1e-10
        np.testing.assert_allclose(sa.eigenvalues, sb.eigenvalues, rtol=1e-8)


def test_pressure_with_a_free_end_is_refused_beyond_axisymmetry():
    """A rim that leaves its plane has no lid that closes it: the follower pressure has no
    potential there, and modes says so rather than return a second variation of nothing."""
    from shellbvp.geometry import annulus

    sc = shellbvp.Scene(annulus(0.5, 1.0), 0.01, material="koiter", nu=0.3,
                        ends=("free", "clamped"), pressure=lambda p: p)
    eq = shellbvp.solve(sc, 1e-6)
    with pytest.raises(ValueError, match="first end is free"):
        H.modes(eq, n=[2])


@pytest.mark.slow
def test_a_bifurcation_just_before_the_fold_is_located_in_the_monitor():
    """Relaxed CG, lam = 1, T = 4.5 (Theta = 0.45): n = 2 loses stability 4e-5 before the
    axisymmetric fold, inside the continuation step that holds the fold. A solve at
    prescribed kappa that close to the fold is ill-conditioned (it used to fail there); the
    root search runs in the monitor instead. Checked: the fold (located by the continuation,
    dp/dm = 0) comes after the bifurcation, the n = 2 eigenvalue is zero at the located root
    (relative to its value at half that curvature) and positive at the axisymmetric
    equilibrium solved independently (natural parameter) 2e-3 before it."""
    ins = ce.first_instability(0.45, H0, 1.0, material="cg")
    assert ins.kind == "bifurcation" and ins.n == 2
    fold = ce.snap_curvature(0.45, H0, 1.0, material="cg")
    assert 0 < fold.kappa_s - ins.p < 1e-3
    mu = H.modes(ins.equilibrium, [2], count=1)[2].lowest
    mu0 = H.modes(ce.equilibrium(0.5 * ins.p, 0.45, H0, 1.0, material="cg"), [2],
                  count=1)[2].lowest
    assert mu0 > 0 and abs(mu) < 1e-6 * mu0
    before = ce.equilibrium(ins.p - 2e-3, 0.45, H0, 1.0, material="cg")
    assert H.modes(before, [2], count=1)[2].lowest > 0


def test_a_cap_that_does_not_snap_is_scanned_as_far_as_asked():
    """T = 1.5, below the onset of snapping: no instability along the branch. With
    kappa_max = 2 the scan ends at the first branch point past it and says so; by default it
    runs well past full eversion (apex displacement 2 H, H the rise: the everted mirror
    image), to kappa R0 = 6."""
    theta = 0.15
    rise = 1 - math.cos(theta)
    short = ce.first_instability(theta, H0, 1.0, kappa_max=2.0)
    assert short.kind == "none" and "kappa_max = 2" in short.stop
    assert 2.0 <= short.p < 2.5 and short.scan[-2][0] < 2.0
    full = ce.first_instability(theta, H0, 1.0)
    # by default past full eversion, to kappa R0 = 6 (the old bound, w = 1.2 times full
    # eversion, stopped at kappa R0 ~ 2.4)
    assert full.p > 2.4 and full.w > 2 * rise
    if full.kind == "none":
        assert "default bound" in full.stop and "--kappa-max" in full.stop
    with pytest.raises(ValueError, match="kappa_max must be"):
        ce.first_instability(theta, H0, 1.0, kappa_max=-1.0)
