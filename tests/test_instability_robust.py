"""The first instability where its location is hard (issue 56): a clustered spectrum (a
sphere under external pressure, many harmonics bifurcating at one load, together with an
axisymmetric bifurcation that makes solves at prescribed p next to it ill-conditioned),
the bracket as the answer where a root search stops, and the scan of a cap past full
eversion.

References: the classical (Zoelly) buckling pressure of a complete sphere,
p_cl = 2 E t^2 / (R^2 sqrt(3 (1 - nu^2))); in the engine's units (per mu h / R, E/mu =
2 (1 + nu)) p_cl = 2 (E/mu) (t/R) / sqrt(3 (1 - nu^2)). An independent per-harmonic
computation (issue 56): the free Koiter cap (nu = 1/2, h0/R0 = 0.01, T = 1.5) bifurcates
into n = 2 at kappa R0 = 3.5377.
"""

import math

import pytest

import shellbvp
from shellbvp import instability as I


def test_a_stopped_root_search_answers_with_its_narrowest_bracket():
    """(x, p, mu, eq) evaluations: the narrowest sign change, its linear root, its width."""
    evals = [(0.0, 0.0, 1.0, "a"), (2.0, 2.0, -1.0, "b"), (1.0, 1.0, 0.5, "c"),
             (1.5, 1.5, -0.5, "d")]
    n, p, err, eq, x, slope = I._bracketed(3, evals, RuntimeError("stopped"))
    assert (n, p, err, eq) == (3, 1.25, 0.5, "c") and slope == pytest.approx(-2.0)
    assert I._bracketed(3, evals[:1] + evals[2:3], RuntimeError()) is None


def test_nearby_is_the_critical_harmonic_first_within_the_window():
    """The default cap (n = 3 before the snap): nearby starts with (n, p, error) of the
    result itself, and every entry lies in [p - errors, p + 1 % of |p|] (before p by at
    most the two roots' errors), at most 5."""
    from shellbvp.problems import cap_eversion as ce

    ins = ce.first_instability(math.pi / 6, 0.01, 1.0)
    assert ins.kind == "bifurcation"
    assert ins.nearby[0] == (ins.n, ins.p, ins.error_estimate)
    assert 1 <= len(ins.nearby) <= I.NEARBY_COUNT
    for n, p, err in ins.nearby:
        assert n >= 1 and -(ins.error_estimate + err) <= p - ins.p <= I.NEARBY_FRACTION * ins.p


@pytest.mark.slow  # the branch and a cluster of five root searches: ~40 s
def test_sphere_under_pressure_buckles_at_the_classical_load_with_a_cluster():
    """The hemisphere (symmetry end at the equator) at R/t = 100, nu = 0.3. Expected:
    within 1 % of p_cl. The classical analysis takes a continuous wave number; the discrete
    spherical harmonics l(l + 1) ~ sqrt(12 (1 - nu^2)) R/t = 330.5 give l = 18 at
    p_l/p_cl = 1.0006; the prebuckling compression (1 - nu) p R / (2 E t) = 0.42 % at p_cl
    changes radius and thickness by O(t/R), and the shallow-shell terms dropped are of
    relative order 1/l^2 ~ t/R: together well inside 1 % (measured: -0.53 %). The modes of
    one l are degenerate in n (n = 0, 2, ..., 18 for l = 18, even about the equator), so
    several harmonics cross within a fraction of a percent: nearby lists five, whatever the
    tolerance of the location (1e-6, 1e-9: the multiplet's roots lie within their errors of
    one another, on either side of the critical one)."""
    from shellbvp.problems.thin_shells import hemisphere

    nu, Rt = 0.3, 100.0
    p_cl = 2 * 2 * (1 + nu) / Rt / math.sqrt(3 * (1 - nu * nu))
    sc = hemisphere(Rt, nu=nu, load="pressure")
    b = shellbvp.follow(sc, p_stop=(0.0, 1.6 * p_cl), n_folds=1, energies=False,
                        estimate_errors=False)
    for tol in (1e-6, 1e-9):
        ins = shellbvp.first_instability(b, tol=tol)
        assert ins.kind == "bifurcation" and ins.n >= 1
        assert abs(ins.p / p_cl - 1) < 0.01, ins.p / p_cl
        assert ins.error_estimate < 1e-4 * ins.p
        assert len(ins.nearby) == I.NEARBY_COUNT, (tol, ins.nearby)
        ns = [n for n, _, _ in ins.nearby]
        assert len(set(ns)) == len(ns)
        for n, p, err in ins.nearby:
            assert abs(p - ins.p) <= I.NEARBY_FRACTION * ins.p


@pytest.mark.slow  # three branches and their root searches at tol 1e-9: ~35 s
def test_three_methods_locate_the_sphere_within_their_estimates():
    """The hemisphere at R/t = 100 under pressure, located at the command line's tolerance
    by three discretisations of the state (spectral elements, the energy method,
    collocation): the roots pairwise within their summed error estimates, the independent
    check being that the continuum has one root. Before the state's determination was in
    the estimate, collocation's root lay 3.6e-8 from spectral's, 4.1 times their summed
    estimates: next to the axisymmetric bifurcation at the same load its chained solves
    drifted along the Jacobian's near-null vector."""
    from shellbvp.problems.thin_shells import hemisphere

    nu, Rt = 0.3, 100.0
    p_cl = 2 * 2 * (1 + nu) / Rt / math.sqrt(3 * (1 - nu * nu))
    sc = hemisphere(Rt, nu=nu, load="pressure")
    found = {}
    for method in ("spectral", "energy", "collocation"):
        b = shellbvp.follow(sc, method=method, p_stop=(0.0, 1.6 * p_cl), n_folds=1,
                            energies=False, estimate_errors=False)
        found[method] = shellbvp.first_instability(b, tol=1e-9)
    for a in found.values():
        assert a.kind == "bifurcation" and a.error_estimate < 1e-5 * a.p
        for b in found.values():
            assert abs(a.p - b.p) <= a.error_estimate + b.error_estimate, found


CYLINDER = "problems/gallery/cylinder-classical.toml"


def _scene(path):
    import os

    return shellbvp.load_scene(os.path.join(os.path.dirname(__file__), os.pardir, path))


@pytest.fixture(scope="module")
def short_cylinder():
    """The short cylinder's first instability (tol 1e-9)."""
    return _scene(CYLINDER).first_instability(tol=1e-9)


def test_an_axisymmetric_crossing_first_in_a_mixed_bracket_is_located_and_followed(
        short_cylinder):
    """The short cylinder between mirror planes (R/t = 100, L = 0.8 pi / k_c): n = 0, 1, 2
    turn unstable between the same two branch points, n = 0 first (the gallery case's own
    n = 0 root, from the n = 0 eigenvalue at solved states, 1326.47838 N/mm; T&G's closed
    form 1333.0 N/mm less 0.49 t/R). The solves at prescribed p fail next to the branch
    point (the discretisation breaks its symmetry), so its bracket is narrowed from outside
    (shellbvp.continuation.squeeze); it was 1.9e-3 wide, and n = 1 was reported first."""
    ins = short_cylinder
    assert ins.kind == "bifurcation" and ins.n == 0, ins
    # the reference: figures/gallery_cylinder_classical.n0_crossing (shellbvp.solve at loads
    # around T&G's N_0, the lowest n = 0 eigenvalue, a cubic through the four nearest its
    # sign change), given to 5 decimals: the 1e-5 is its rounding
    assert abs(ins.p - 1326.47838) <= ins.error_estimate + 1e-5, ins
    assert ins.error_estimate < 1e-6 * ins.p
    assert [n for n, _, _ in ins.nearby][:2] == [0, 1], ins.nearby


@pytest.mark.xfail(strict=True, reason="known limitation, not yet fixed: on a pitchfork whose "
                   "symmetry the discretisation breaks (this cylinder), Koiter's a comes out "
                   "1.73e-5 +- 1.62e-5 where the symmetry makes it 0 (such a branch point is "
                   "located on one discretisation only, so a's estimate lacks the "
                   "discretisation's error), and switching onto the buckled branch failed to "
                   "converge in one full-suite run of two")
def test_the_short_cylinder_is_followed_and_koiters_a_is_zero_within_its_error(
        short_cylinder):
    """The bifurcated branch followed from the branch point; the symmetry x -> L - x of the
    cylinder between mirror planes maps the mode to its negative: a = 0."""
    fb = shellbvp.follow_bifurcation(short_cylinder.instability)
    assert len(fb.branch.points) >= 3
    assert abs(fb.koiter.a) <= fb.koiter.a_error, fb.koiter


@pytest.mark.slow  # three branches, their scans and root searches: ~40 s
def test_three_methods_agree_on_the_short_cylinders_axisymmetric_crossing():
    """Spectral elements, the energy method and collocation on the short cylinder: each
    reports n = 0 first, pairwise within the summed estimates. Before the bracket was
    narrowed, the energy method's n = 0 search stopped on a bracket 1.6e-2 wide and n = 1
    was reported; spectral's branch point was a bracket 4.6e-4 wide."""
    sf = _scene(CYLINDER)
    found = {}
    for method in ("spectral", "energy", "collocation"):
        b = shellbvp.follow(sf.scene, method=method, p_stop=(0.0, 1.4), n_folds=1,
                            energies=False, estimate_errors=False)
        found[method] = shellbvp.first_instability(b, tol=1e-9)
    for a in found.values():
        assert a.kind == "bifurcation" and a.n == 0, found
        for b in found.values():
            assert abs(a.p - b.p) <= a.error_estimate + b.error_estimate, found


@pytest.mark.slow  # a branch to kappa R0 ~ 3.6 and the harmonics along it: ~1 min
def test_a_cap_that_does_not_snap_bifurcates_past_full_eversion():
    """The Koiter cap, nu = 1/2, h0/R0 = 0.01, T = 1.5 (Theta = 0.15): no snap; the scan
    runs past full eversion (kappa R0 = 2) by default and finds n = 2 at kappa R0 = 3.5377
    (the issue's independent computation, given to 4 decimals)."""
    from shellbvp.problems import cap_eversion as ce

    ins = ce.first_instability(0.15, 0.01, material="koiter", nu=0.5)
    assert ins.kind == "bifurcation" and ins.n == 2
    assert abs(ins.p - 3.5377) <= ins.error_estimate + 5e-5, (ins.p, ins.error_estimate)


def test_a_step_limit_names_a_remedy_the_user_has(tmp_path):
    """The engine's 'raise max_steps or ds_max' (ContinuationOptions, not file keys)
    becomes the scene file's [solver] points, a key that exists and is read."""
    from shellbvp.scenefile import FILE_STEP_REMEDY, example, file_remedy

    stop = "options.max_steps = 400 points reached at p = 1, w = 2 before any stop; " \
        "raise max_steps or ds_max"
    fixed = file_remedy(stop)
    assert "max_steps or ds_max" not in fixed and fixed.endswith(FILE_STEP_REMEDY)
    text = open(example("clamped-plate")).read() + "\n[solver]\npoints = 150\n"
    (tmp_path / "plate.toml").write_text(text)
    assert shellbvp.load_scene(tmp_path / "plate.toml").points == 150
