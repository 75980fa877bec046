"""The cell-sheet scenes (``shellbvp.problems.pleodorina``, ``volvox``; docs/cell-sheets.md).

Fast: the stimulus fields against their definitions (host numpy, nothing compiled): the
bowl untouched before the wave and inverted after it, the band's profile, the embryo's
regions and stages, the scene files equal to the Python scenes, bad input, and the figures'
self-contact test. Slow: the physical checks that solve (the bowl at rest and inverted, the
embryo's closed form and symmetry), the published claims the abstracts state (the wave
inverts the 64-cell bowl but not the 256-cell one at a wedging between their boundaries;
the posterior's contraction brings the embryo's snap forward), and the figure scripts'
quick runs.
"""

import math
import os
import sys

import numpy as np
import pytest

import shellbvp
from shellbvp.problems import pleodorina as P
from shellbvp.problems import volvox as V
from shellbvp.scenefile import example

sys.path.insert(0, os.path.join(os.path.dirname(__file__), os.pardir, "figures"))

from _cell_sheets import self_contact  # noqa: E402

#: the tanh tails of the band's steps at the bowl's ends (module docstring of pleodorina)
TAIL = 0.5 * (1 - math.tanh(P.SPAN_EDGES))


def _fields(sc, s, p):
    """(g1, g2, kb1, kb2) at arclength s (one piece: the bowl) and stage p."""
    return np.array(sc.field_values(0, np.asarray(s, float), p))


def test_thickness_for_cells():
    assert P.thickness_for_cells(64) == pytest.approx(math.sqrt(2 * math.pi / 64), rel=1e-14)
    assert P.thickness_for_cells(256) == pytest.approx(P.thickness_for_cells(64) / 2,
                                                       rel=1e-14)


def test_the_wave_leaves_the_bowl_before_and_inverts_it_after():
    sc = P.scene(P.thickness_for_cells(64), 1.0)
    s = np.linspace(0.0, sc.length, 41)
    k_band = 1.0 / sc.h
    amplitude = abs(k_band + 1.0) + abs(k_band - 1.0)
    g1, g2, kb1, kb2 = _fields(sc, s, 0.0)
    assert np.all(g1 == 1.0) and np.all(g2 == 1.0)
    assert np.max(abs(kb1 + 1.0)) <= TAIL * amplitude and np.max(abs(kb2 + 1.0)) <= TAIL * amplitude
    _, _, kb1, kb2 = _fields(sc, s, 1.0)
    assert np.max(abs(kb1 - 1.0)) <= TAIL * amplitude and np.max(abs(kb2 - 1.0)) <= TAIL * amplitude


def test_the_band_travels_from_the_rim_to_the_pole():
    sc = P.scene(P.thickness_for_cells(256), 0.8)
    theta, band, delta, k_band, k_after = sc.field_parameters
    for p in (0.3, 0.5, 0.7):
        sf = P.band_centre(p, theta, band, delta)
        assert sf == pytest.approx(theta + (band / 2 + 6 * delta) * (1 - 2 * p) - p * theta)
        # at the centre both steps stand at (1 +- tanh(W / (2 delta))) / 2 of their heights
        t = math.tanh(band / 2 / delta)
        k_ref = -1.0
        expected = k_ref + (k_band - k_ref) * (1 + t) / 2 + (k_after - k_band) * (1 - t) / 2
        _, _, kb1, kb2 = _fields(sc, [sf], p)
        assert kb1[0] == pytest.approx(expected, rel=1e-12) and kb2[0] == kb1[0]
        # ahead of the band (toward the pole) the bowl, behind it (toward the rim) inverted
        _, _, ahead, _ = _fields(sc, [max(sf - band / 2 - 8 * delta, 0.0)], p)
        _, _, behind, _ = _fields(sc, [min(sf + band / 2 + 8 * delta, sc.length)], p)
        if sf - band / 2 - 8 * delta > 0:
            assert ahead[0] == pytest.approx(-1.0, abs=1e-5 * k_band)
        if sf + band / 2 + 8 * delta < sc.length:
            assert behind[0] == pytest.approx(1.0, abs=1e-5 * k_band)


def test_the_embryo_s_regions_and_stages():
    sc = V.scene()
    s1, s2 = sc.breaks
    assert s1 == pytest.approx(math.pi / 2 - V.BEND_WIDTH / 2)
    assert s2 == pytest.approx(math.pi / 2 + V.BEND_WIDTH / 2)
    for piece, s in ((0, 0.5 * s1), (1, 0.5 * (s1 + s2)), (2, 0.5 * (s2 + math.pi))):
        assert np.allclose(sc.field_values(piece, np.array([s]), 0.0), [[1], [1], [-1], [-1]],
                           atol=0, rtol=0)
    g1, g2, kb1, kb2 = sc.field_values(1, np.array([1.5]), 1.0)
    assert (g1[0], g2[0], kb1[0], kb2[0]) == (1.0, 1.0, V.K_BEND, V.K_BEND)
    g1, g2, kb1, kb2 = sc.field_values(2, np.array([2.5]), 0.5)
    assert g1[0] == g2[0] == pytest.approx(1 + 0.5 * (V.G_POST - 1)) and kb1[0] == -1.0
    # the closed form's stimulus: a sphere of radius g in every region
    u = V.scene(g_ant=0.9, g_bend=0.9, g_post=0.9, k_ant=-1 / 0.9, k_bend=-1 / 0.9,
                k_post=-1 / 0.9)
    for piece in range(3):
        g1, g2, kb1, kb2 = u.field_values(piece, np.array([1.0]), 1.0)
        assert g1[0] == g2[0] == 0.9 and kb1[0] * g1[0] == pytest.approx(-1.0, rel=1e-15)


def test_the_scene_files_are_the_python_scenes():
    """problems/scenes/pleodorina.toml and volvox.toml hold the Python scenes' stimulus (to
    the digits they are written with), in their own units."""
    pf = shellbvp.load_scene(example("pleodorina"))
    ps = P.scene(P.thickness_for_cells(64), 1.0)
    assert pf.units.length == 1.0 and pf.scene.h == pytest.approx(ps.h, rel=1e-5)
    s = np.linspace(0.0, ps.length, 23)
    for p in (0.0, 0.25, 0.5, 0.75, 1.0):
        a = np.array(pf.scene.field_values(0, s, p / pf.scale))
        b = _fields(ps, s, p)
        assert np.allclose(a, b, rtol=0, atol=2e-5 * (1 / ps.h)), p
    vf = shellbvp.load_scene(example("volvox"))
    vs = V.scene()
    L = vf.units.length                         # the file's lengths over the engine's
    assert vf.scene.h * L == pytest.approx(vs.h)
    assert np.allclose(np.array(vf.scene.breaks) * L, vs.breaks, atol=1e-6)
    for piece, s in ((0, 0.7), (1, 1.5), (2, 2.5)):
        for p in (0.0, 0.6, 1.2):
            a = np.array(vf.scene.field_values(piece, np.array([s / L]), p / vf.scale)).ravel()
            b = np.array(vs.field_values(piece, np.array([s]), p)).ravel()
            assert np.allclose(a[:2], b[:2], rtol=0, atol=1e-12)
            assert np.allclose(a[2:] / L, b[2:], rtol=0, atol=1e-12)


def test_the_page_shows_the_scene_files():
    """docs/cell-sheets.md shows problems/scenes/pleodorina.toml and volvox.toml as they
    are, less their header comments."""
    from docs_blocks import ROOT, blocks

    shown = [code for language, code in blocks(ROOT / "docs" / "cell-sheets.md")
             if language == "toml"]
    for name in ("pleodorina", "volvox"):
        lines = example(name).read_text().splitlines(keepends=True)
        body = "".join(lines[next(i for i, x in enumerate(lines) if not x.startswith("#")):])
        assert body in shown, name


@pytest.mark.parametrize("call, match", [
    (lambda: P.scene(0.6, 1.0), "h must lie in"),
    (lambda: P.scene(0.2, 0.0), "wedging must lie in"),
    (lambda: P.scene(0.2, 1.0, theta=3.1), "theta must lie in"),
    (lambda: P.scene(0.2, 1.0, band_cells=20), "band_cells must lie in"),
    (lambda: P.scene(0.2, 1.0, material="steel"), "material must be one of"),
    (lambda: P.thickness_for_cells(2), "cells must be"),
    (lambda: V.scene(h=0.0), "h must lie in"),
    (lambda: V.scene(g_post=3.0), "g_post must lie in"),
    (lambda: V.scene(k_bend=-30.0), "k_bend must be a curvature"),
    (lambda: V.scene(bend=(2.0, 1.0)), "bend must be"),
])
def test_bad_input_is_named(call, match):
    with pytest.raises(ValueError, match=match):
        call()


def test_self_contact():
    t = np.linspace(0, 1, 200)
    assert not self_contact(np.sin(math.pi * t), np.cos(math.pi * t))     # a sphere
    # a meridian that loops back through itself
    r = 1 + 0.5 * np.sin(4 * math.pi * t)
    z = -t + 0.4 * np.cos(4 * math.pi * t)
    assert self_contact(r, z)
    assert self_contact(np.array([0.0, 1.0, -0.2, 1.0, 0.0]), np.array([1.0, 0.5, 0.0,
                                                                      -0.5, -1.0]))


# --- slow: solves ---------------------------------------------------------------------------

@pytest.mark.slow
def test_the_bowl_rests_before_the_wave_and_ends_inverted():
    """The bowl at stage 0 (the wave outside the rim) and the inverted bowl, its mirror
    image, which is stress-free, past the pole: tolerances of the figure script."""
    sc = P.scene(P.thickness_for_cells(64), 1.0)
    b = P.branch(sc)
    H = 2 * (1 - math.cos(P.THETA))
    assert abs(b.w[0]) <= 1e-4 * H
    assert P.outcome(b) == "continuous"
    assert abs(b.w[-1] - H) <= 1e-4 * H and abs(b.energy[-1]) <= 1e-6


@pytest.mark.slow
def test_the_wave_inverts_64_cells_but_not_256():
    """Tribet & Haas's abstract: inversion is possible for the parameters of the 64-cell
    species but not for those extrapolated to 256 cells. In this model (cells as tall as
    wide, the same wedging for both), a wedging between the two thicknesses' boundaries
    (figures/cell_sheets_map.py) shows the same: this is a model that can reproduce the
    claim, not a prediction of the paper's number."""
    q = 0.5
    b64 = P.branch(P.scene(P.thickness_for_cells(64), q), energies=False)
    b256 = P.branch(P.scene(P.thickness_for_cells(256), q), energies=False)
    assert P.outcome(b64) in ("continuous", "snap")
    assert P.outcome(b256) == "stalls"


@pytest.mark.slow
def test_the_embryo_closed_form_and_symmetry():
    u = V.scene(g_ant=0.9, g_bend=0.9, g_post=0.9, k_ant=-1 / 0.9, k_bend=-1 / 0.9,
                k_post=-1 / 0.9)
    eq = shellbvp.solve(u, 0.5)
    eq = shellbvp.solve(u, 1.0, guess=eq)
    assert float(eq(np.array([math.pi / 2]))[0][0]) == pytest.approx(0.9, abs=1e-8)
    assert abs(eq.energy) <= 1e-12
    eq = shellbvp.solve(V.scene(g_ant=0.9, g_post=0.9), 0.5)
    s = np.linspace(0.05, math.pi / 2 - 0.2, 30)
    assert np.max(abs(eq(s)[0] - eq(math.pi - s)[0])) <= 1e-8
    assert abs(shellbvp.solve(V.scene(), 0.0).w) <= 1e-12


@pytest.mark.slow
def test_the_contraction_brings_the_snap_forward():
    """Haas & Goldstein's abstract: appropriate local deformations overcome the global
    constraints. Here the posterior's contraction alone does not snap up to stage 1.5, the
    bend region alone snaps late (and loses axisymmetry before, figures/
    cell_sheets_volvox.py), and both together snap earlier than the bend region alone."""
    alone = V.branch(V.scene(g_post=1.0), energies=False)
    contraction = V.branch(V.scene(k_bend=-1.0), energies=False)
    both = V.branch(V.scene(), energies=False)
    assert not contraction.folds and not contraction.stop and contraction.p[-1] >= 1.5
    assert alone.folds and both.folds and both.folds[0].p < alone.folds[0].p


@pytest.mark.slow
@pytest.mark.parametrize("script", ["cell_sheets_pleodorina", "cell_sheets_volvox",
                                    "cell_sheets_map"])
def test_figure_scripts_quick(script, tmp_path):
    import importlib

    mod = importlib.import_module(script)
    args = ["--quick", "--out", str(tmp_path)] + (["--jobs", "1"] if script.endswith("map")
                                                   else [])
    mod.main(args)
    assert (tmp_path / f"{script}.png").is_file() and (tmp_path / f"{script}.csv").is_file()
