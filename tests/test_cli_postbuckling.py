"""``shellbvp postbuckling``: bad input exits 2 with one line before anything is computed;
the printing, the bounds and the CSV against stand-ins of the two computations (fast); and
one real run on the default cap against shellbvp.problems.cap_eversion.first_instability
(slow: the axisymmetric solver and the per-harmonic stability, another discretisation than
the lobed states')."""

import math
import re

import numpy as np
import pytest

from shellbvp import cli
from shellbvp.instability import Instability
from shellbvp.postbuckling import Koiter, LobedBranch, LobedFold


@pytest.mark.parametrize("argv,needle", [
    (["--K", "0"], "argument --K: expected an integer in [1, 8], got '0'"),
    (["--K", "9"], "argument --K: expected an integer in [1, 8]"),
    (["--K", "1.5"], "argument --K: expected an integer in [1, 8], got '1.5'"),
    (["--degree", "7"], "argument --degree: expected an integer in [8, 152]"),
    (["--degree", "153"], "argument --degree: expected an integer in [8, 152]"),
    (["--n-folds", "-1"], "argument --n-folds: expected an integer >= 0, got '-1'"),
    (["--amplitude-max", "0"], "argument --amplitude-max: expected a number > 0"),
    (["--amplitude-max", "nan"], "argument --amplitude-max: expected a number > 0"),
    (["--kappa-max", "nan"], "argument --p-max/--kappa-max: expected a number"),
    (["--p-min", "x"], "argument --p-min/--kappa-min: expected a number"),
    (["--kappa-min", "5", "--kappa-max", "4"], "--kappa-min 5 must lie below --kappa-max 4"),
    (["--p-min=5", "--kappa-max=5"], "--p-min 5 must lie below --kappa-max 5"),
    # the cap's default lower bound is kappa = 0, where its branch starts
    (["--kappa-max=-1"], "--kappa-max -1 must lie above 0, the default lower bound"),
    (["--h", "2"], "h must lie in (1e-06, 1)"),
    (["--theta", "4"], "theta must lie in (0.001, 3.14159)"),
    (["--lam", "-1"], "lam must lie in (0, 1e+08)"),
    (["--tol", "0"], "--tol must lie in (0, 1)"),
    (["--material", "foo"], "invalid choice"),
    (["--method", "shooting"], "unrecognized arguments"),
    (["everting-cap", "--h", "0.02"], "--h sets the built-in cap"),
    (["everting-cap", "--p-min", "7"], ("--p-min 7 must lie below 6, the default upper bound "
                                        "(the file's range)")),
    (["everting-cap", "--p-max=-1"], "--p-max -1 must lie above 0, the default lower bound"),
    (["no-such-example"], "no example scene 'no-such-example'"),
])
def test_bad_arguments_exit_2_with_one_line(argv, needle, capsys):
    with pytest.raises(SystemExit) as e:
        cli.main(["postbuckling", *argv])
    assert e.value.code == 2
    out = capsys.readouterr()
    err = out.err.strip().splitlines()
    assert len(err) == 1 and needle in err[0] and "Traceback" not in out.err, err
    assert out.out == ""


def test_help_lists_the_command_and_its_options(capsys):
    for argv in (["--help"], ["postbuckling", "--help"]):
        with pytest.raises(SystemExit) as e:
            cli.main(argv)
        assert e.value.code == 0
    out = capsys.readouterr().out
    assert "postbuckling" in out
    for option in ("--K", "--degree", "--n-folds", "--kappa-max", "--p-min", "--csv",
                   "--amplitude-max", "--theta"):
        assert option in out
    assert "shellbvp postbuckling" in cli.__doc__


# --- stand-ins for the computations: what is printed and written of their results ----------
def _instability(kind, p, n=3, parameter="kappa"):
    return Instability(kind, n if kind != "none" else -1, p, 0.25, 1e-8, parameter)


def _lobed(p_c, p2, folds, stop, parameter="kappa", direction=1.0):
    k = Koiter(n=3, p_c=p_c, parameter=parameter, p2=p2, b=0.5 * p2, mu_p=1.0, w_max=1.0,
               h=0.01, direction=direction, E3=0.0, E4=0.0)
    a = np.array([1e-3, 2e-3, 4e-3])
    return LobedBranch(n=3, K=2, degree=24, parameter=parameter, koiter=k, p_c=p_c,
                       p_c_error=2e-9, p=p_c + p2 * a**2, amplitude=a,
                       harmonics=np.column_stack([a**2, a, 0.1 * a**2]),
                       folds=tuple(LobedFold(p, 5e-3, 3e-8, 1) for p in folds), stop=stop)


@pytest.fixture
def stand_ins(monkeypatch):
    """The cap's first instability and follow_bifurcation replaced; the latter records its
    arguments."""
    from shellbvp import postbuckling
    from shellbvp.problems import cap_eversion

    calls = {}

    def use(instability, lobed=None):
        monkeypatch.setattr(cap_eversion, "first_instability",
                            lambda *args, **kw: instability)

        def follow(ins, **kw):
            calls.update(kw, instability=ins)
            return lobed(kw) if callable(lobed) else lobed
        monkeypatch.setattr(postbuckling, "follow_bifurcation", follow)
        return calls
    return use


@pytest.mark.parametrize("kind, says", [
    ("fold", ("first instability: the axisymmetric snap (fold) at kappa R0 = 5.12340000 "
              "+- 1.0e-08, w / R0 = 0.250000: no bifurcation to follow")),
    # none: the scan's end, which is no longer full eversion (it runs to kappa R0 = 6)
    ("none", "first instability: none up to kappa R0 = 5.1234: no bifurcation to follow")])
def test_a_fold_or_none_has_nothing_to_follow(kind, says, stand_ins, capsys):
    calls = stand_ins(_instability(kind, 5.1234))
    assert cli.main(["postbuckling"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("Theta = 0.523599 rad") and out[1] == says and len(out) == 2
    assert calls == {}                     # nothing followed


def test_supercritical_snaps_at_the_lobed_fold_and_the_csv(stand_ins, tmp_path, capsys):
    """A supercritical bifurcation (p2 along the loading): the snap is the lobed branch's
    first fold; the CSV holds LobedBranch.columns() with the parameter's column named as
    the branch command's (kappa_R0), every number exactly."""
    br = _lobed(4.0, 50.0, folds=(4.3, 4.6), stop="after 2 fold(s)")
    calls = stand_ins(_instability("bifurcation", 4.0), br)
    path = tmp_path / "lobed.csv"
    assert cli.main(["postbuckling", "--K", "3", "--degree", "40", "--n-folds", "2",
                     "--amplitude-max", "0.5", "--csv", str(path)]) == 0
    assert (calls["K"], calls["degree"], calls["n_folds"], calls["amplitude_max"]) == \
        (3, 40, 2, 0.5)
    assert calls["p_stop"] == (0.0, math.inf)          # the cap's default bound
    out = capsys.readouterr().out.splitlines()
    assert out[1] == ("bifurcation: n = 3 at kappa R0 = 4 +- 2.0e-09 (harmonics 0..6 step 3, "
                      "degree 24)")
    assert out[2].startswith("Koiter: p2 = 50, b = 25: supercritical")
    assert out[3] == "lobed fold 1: kappa R0 = 4.3 +- 3.0e-08, amplitude 0.005"
    assert out[4] == "lobed fold 2: kappa R0 = 4.6 +- 3.0e-08, amplitude 0.005"
    assert out[5] == f"lobed branch: 3 points, 2 fold(s); stop: after 2 fold(s) -> {path}"
    assert out[6] == "snap: at the first lobed fold, kappa R0 = 4.3 +- 3.0e-08 (supercritical)"
    rows = [line.split(",") for line in path.read_text().splitlines()]
    assert rows[0] == ["kappa_R0", "amplitude", "harmonic_0", "harmonic_3", "harmonic_6"]
    got = np.array(rows[1:], dtype=float)
    cols = br.columns()
    want = np.column_stack([cols[k] for k in ("kappa", "amplitude", "harmonic_0",
                                              "harmonic_3", "harmonic_6")])
    assert np.array_equal(got, want)


def test_supercritical_without_a_fold_has_no_snap(stand_ins, capsys):
    stand_ins(_instability("bifurcation", 4.0),
              _lobed(4.0, 50.0, folds=(), stop="amplitude beyond 0.01"))
    assert cli.main(["postbuckling", "--kappa-min=-inf", "--amplitude-max", "0.01"]) == 0
    out = capsys.readouterr().out
    assert "lobed folds: none before the stop" in out
    assert "snap: not found (supercritical, and no lobed fold before the stop)" in out


def test_bounds_are_passed_and_must_contain_the_bifurcation(stand_ins, capsys):
    calls = stand_ins(_instability("bifurcation", 4.0),
                      lambda kw: _lobed(4.0, -100.0, (), "max_steps" if kw["p_stop"] is None
                                        else "kappa left [{:g}, {:g}]".format(*kw["p_stop"])))
    assert cli.main(["postbuckling", "--kappa-min", "3.5", "--kappa-max", "4.5"]) == 0
    assert calls["p_stop"] == (3.5, 4.5)
    out = capsys.readouterr().out
    assert "Koiter: p2 = -100, b = -50: subcritical" in out
    assert "stop: kappa R0 left [3.5, 4.5]" in out
    assert "snap: at the bifurcation, kappa R0 = 4 +- 2.0e-09 (subcritical" in out
    calls.clear()
    assert cli.main(["postbuckling", "--kappa-min=-inf"]) == 0
    assert calls["p_stop"] is None                      # unbounded both ways
    capsys.readouterr()
    calls.clear()
    with pytest.raises(SystemExit) as e:
        cli.main(["postbuckling", "--kappa-max", "3"])
    assert e.value.code == 2 and calls == {}
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [("shellbvp: error: --kappa-max 3 excludes the bifurcation at kappa R0 = 4, "
                    "where the lobed branch starts: --kappa-max must lie above it")]


def test_a_scene_file_in_its_own_units(monkeypatch, tmp_path, capsys):
    """The engine's parameter is t = kappa / 10 for the everting cap's file (its range 0..6):
    bounds go in as t, and p_c, its error, p2, the folds, the stop and the CSV come out in
    kappa."""
    from shellbvp import postbuckling
    from shellbvp.scenefile import SceneFile, SceneInstability

    ins = _instability("bifurcation", 0.41758, parameter="t_kappa")
    monkeypatch.setattr(SceneFile, "first_instability", lambda self, tol, **kw: SceneInstability(
        "bifurcation", 3, 4.1758, 1e-7, instability=ins))
    calls = {}

    def follow(i, **kw):
        calls.update(kw, instability=i)
        return _lobed(0.41758, -600.0, (0.3,), f"t_kappa left [{kw['p_stop'][0]:g}, "
                                               f"{kw['p_stop'][1]:g}]", parameter="t_kappa")
    monkeypatch.setattr(postbuckling, "follow_bifurcation", follow)
    path = tmp_path / "f.csv"
    assert cli.main(["postbuckling", "everting-cap", "--p-min", "2", "--csv", str(path)]) == 0
    assert calls["instability"] is ins and calls["p_stop"] == (0.2, 0.6)
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("everting spherical cap") and "kappa from 0 to 6" in out[0]
    assert out[1].startswith("bifurcation: n = 3 at kappa = 4.1758 +- 2.0e-08")
    assert out[2].startswith("Koiter: p2 = -6000, b = -300: subcritical")
    assert out[3] == "lobed fold 1: kappa = 3 +- 3.0e-07, amplitude 0.005"
    assert out[4].endswith("stop: kappa left [2, 6] -> " + str(path))
    assert out[5].startswith("snap: at the bifurcation, kappa = 4.1758 +- 2.0e-08")
    rows = [line.split(",") for line in path.read_text().splitlines()]
    assert rows[0][:2] == ["kappa", "amplitude"]
    assert float(rows[1][0]) == pytest.approx(10 * (0.41758 - 600.0 * 1e-6), rel=1e-15)


# --- the real thing ---------------------------------------------------------------------------
@pytest.mark.slow
def test_default_cap_bifurcates_subcritically_into_three_lobes(tmp_path, capsys):
    """Theta = pi/6, h = 0.01, lam = 1: a subcritical bifurcation into n = 3 at kappa R0 =
    4.1758. The printed p_c (located in the lobed states' discretisation) against
    cap_eversion.first_instability's (the axisymmetric solver and the per-harmonic second
    variation), within the latter's error estimate; Koiter's p2 (about -6143) against the
    first point of the CSV (a lobed equilibrium, on Koiter's parabola to 2 % of p2 a^2);
    the snap is the bifurcation; the lobed branch is cut at kappa R0 = 4 by the bound."""
    from shellbvp.problems import cap_eversion as ce

    path = tmp_path / "lobed.csv"
    assert cli.main(["postbuckling", "--kappa-min", "4", "--csv", str(path)]) == 0
    out = capsys.readouterr().out
    m = re.search(r"^bifurcation: n = (\d+) at kappa R0 = ([0-9.]+) \+- ([0-9.e+-]+)", out,
                  re.MULTILINE)
    assert m, out
    n, p_c, p_c_error = int(m.group(1)), float(m.group(2)), float(m.group(3))
    ref = ce.first_instability(math.pi / 6, 0.01, 1.0)
    assert ref.kind == "bifurcation" and n == ref.n == 3
    assert abs(p_c - ref.p) <= ref.error_estimate, (p_c, ref.p, ref.error_estimate)
    assert p_c_error < ref.error_estimate and abs(p_c - 4.1758) < 1e-4
    k = re.search(r"^Koiter: p2 = ([0-9.e+-]+), b = ([0-9.e+-]+): (\w+)", out, re.MULTILINE)
    assert k and k.group(3) == "subcritical", out
    p2 = float(k.group(1))
    assert abs(p2 / -6143 - 1) < 2e-3 and float(k.group(2)) < 0
    snap = re.search(r"^snap: at the bifurcation, kappa R0 = ([0-9.]+) ", out, re.MULTILINE)
    assert snap and float(snap.group(1)) == p_c
    pts = re.search(r"^lobed branch: (\d+) points, (\d+) fold\(s\); stop: kappa R0 left "
                    r"\[4, inf\] -> ", out, re.MULTILINE)
    assert pts, out
    rows = [line.split(",") for line in path.read_text().splitlines()]
    assert rows[0] == ["kappa_R0", "amplitude", "harmonic_0", "harmonic_3", "harmonic_6"]
    data = np.array(rows[1:], dtype=float)
    assert len(data) == int(pts.group(1))
    kappa, a = data[:, 0], data[:, 1]
    # to the bound: the continuation lands its last point on it
    assert np.all(np.diff(kappa) < 0) and abs(kappa[-1] - 4.0) <= 1e-9 < kappa[-2] - 4.0
    assert abs(kappa[0] - (p_c + p2 * a[0] ** 2)) < 0.02 * abs(p2) * a[0] ** 2
    assert data[0, 3] == pytest.approx(a[0], rel=1e-3)      # harmonic n carries the mode


@pytest.mark.slow
def test_a_scene_of_three_pieces_the_growing_ring_on_a_cylinder(capsys):
    """The example scene cylinder-growing-ring.toml: three pieces (the ring's ramp is
    bounded by two breaks of the stimulus, each a rigid joint imposed at finite amplitude
    with multipliers). Its bifurcation into n = 7 in the lobed states' discretisation
    against ``first_instability``'s (the axisymmetric solver and the per-harmonic second
    variation with the linearised joints: another discretisation), within the sum of the
    two error estimates; the bifurcation is subcritical, as a cylinder's in axial
    compression is (the classical imperfection-sensitive shell: Hutchinson & Koiter 1970)."""
    from shellbvp.scenefile import example, load_scene

    path = example("cylinder-growing-ring")
    assert cli.main(["postbuckling", str(path)]) == 0
    out = capsys.readouterr().out
    m = re.search(r"^bifurcation: n = (\d+) at g = ([0-9.]+) \+- ([0-9.e+-]+)", out,
                  re.MULTILINE)
    assert m, out
    n, p_c, p_c_error = int(m.group(1)), float(m.group(2)), float(m.group(3))
    ref = load_scene(path).first_instability()
    assert ref.kind == "bifurcation" and n == ref.n == 7
    assert abs(p_c - ref.p) <= ref.error_estimate + p_c_error, (p_c, ref.p, p_c_error)
    k = re.search(r"^Koiter: p2 = ([0-9.e+-]+), b = ([0-9.e+-]+): (\w+)", out, re.MULTILINE)
    assert k and k.group(3) == "subcritical" and float(k.group(2)) < 0, out
