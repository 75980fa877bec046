"""The shellbvp command line: bad input exits 2 with one line; the commands run."""

import math

import pytest

from shellbvp import cli


@pytest.mark.parametrize("argv,needle", [
    (["snap", "--h", "2"], "h must lie in (1e-06, 1)"),
    (["snap", "--lam", "-1"], "lam must lie in (0, 1e+08)"),
    (["snap", "--theta", "4"], "theta must lie in (0.001, 3.14159)"),
    # extremes a user tried (they ended in ZeroDivisionError, a message about a parameter
    # never given, and a solver failure)
    (["snap", "--theta", "1e-12"], "theta must lie in (0.001, 3.14159)"),
    (["snap", "--h", "1e-12"], "h must lie in (1e-06, 1)"),
    (["snap", "--lam", "1e300"], "lam must lie in (0, 1e+08)"),
    (["snap", "--model", "foo"], "invalid choice"),
    (["sweep", "--T", "3:1:1", "--csv", "x.csv"], "0 < START <= STOP"),
    (["sweep", "--T", "a:b", "--csv", "x.csv"], "START:STOP:STEP"),
    (["branch", "--theta", "0.5"], "--csv"),
    (["stability", "--h", "2"], "h must lie in (1e-06, 1)"),
    (["stability", "--method", "shooting"], "unrecognized arguments"),
    ([], "command"),
    # a --vtk folder that cannot be written: refused before anything is computed
    (["follow", "disc-spring", "--vtk", "{file}"], "not a folder"),
    (["follow", "disc-spring", "--vtk", "{file}/sub"], "cannot write there"),
    (["postbuckling", "--vtk", "{file}/sub"], "cannot write there"),
])
def test_bad_arguments_exit_2_with_one_line(argv, needle, capsys, tmp_path):
    (tmp_path / "a-file").write_text("x")
    argv = [a.format(file=tmp_path / "a-file") for a in argv]
    with pytest.raises(SystemExit) as e:
        cli.main(argv)
    assert e.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0], err


def test_help_everywhere(capsys):
    for argv in (["--help"], ["snap", "--help"], ["branch", "--help"], ["sweep", "--help"],
                 ["stability", "--help"], ["follow", "--help"], ["postbuckling", "--help"]):
        with pytest.raises(SystemExit) as e:
            cli.main(argv)
        assert e.value.code == 0
    out = capsys.readouterr().out
    assert "--theta" in out and "--vtk DIR" in out and "--quiet" in out


def test_help_says_what_it_is_and_version(capsys):
    """The top-level help describes any shell of revolution and scene files, not only the
    everting caps; --version prints the installed version."""
    import shellbvp

    with pytest.raises(SystemExit):
        cli.main(["--help"])
    out = " ".join(capsys.readouterr().out.split())
    assert "shells of revolution" in out and "scene file" in out
    for command in ("follow", "stability", "postbuckling", "snap", "branch", "sweep"):
        assert command in out
    with pytest.raises(SystemExit) as e:
        cli.main(["--version"])
    assert e.value.code == 0
    assert capsys.readouterr().out.strip() == f"shellbvp {shellbvp.__version__}"


def test_progress_counts_points_and_folds_and_is_quiet_off_a_terminal(monkeypatch):
    """The bar of a continuation: a fold each time the parameter turns back; no bar with
    --quiet or where stderr is not a terminal (then standard output is the results
    alone)."""
    import argparse
    import io
    import sys

    class Terminal(io.StringIO):
        def isatty(self):
            return True

    for quiet, tty, shown in ((False, True, True), (True, True, False),
                              (False, False, False)):
        err = Terminal() if tty else io.StringIO()
        monkeypatch.setattr(sys, "stderr", err)
        with cli._Progress(argparse.Namespace(quiet=quiet), "branch", "q", " N/mm") as bar:
            for p in (0.0, 1.0, 2.0, 1.5, 1.0, 1.2):      # up, back (a fold), up (another)
                bar(p)
        assert bar.folds == 2
        if shown:
            assert bar.bar.n == 6 and bar.bar.postfix == "q = 1.2 N/mm, 2 fold(s)"
            assert "shellbvp: branch" in err.getvalue()
        else:
            assert bar.bar.disable and err.getvalue() == ""


def test_branch_command_writes_csv(tmp_path, capsys):
    out = tmp_path / "b.csv"
    assert cli.main(["branch", "--theta", str(math.pi / 6), "--kappa-max", "0.4",
                     "--csv", str(out)]) == 0
    assert out.read_text().startswith("kappa_R0,w_over_R0,energy")
    assert "points" in capsys.readouterr().out


@pytest.mark.parametrize("argv,code", [
    (["shellbvp", "snap", "--tol", "0"], 2),
    (["shellbvp", "branch", "--theta", str(math.pi / 6), "--kappa-max", "0.4", "--csv",
      "{tmp}/b.csv"], 0),
])
def test_console_command_exits_with_the_status_of_main(argv, code, tmp_path, monkeypatch,
                                                       capsys):
    """``shellbvp`` (cli.run) is main on sys.argv, exiting with its status, bad input and
    success alike; it freezes the garbage collector's objects on the way out (undone here,
    where the test process goes on)."""
    import gc
    import sys

    monkeypatch.setattr(sys, "argv", [a.format(tmp=tmp_path) for a in argv])
    try:
        with pytest.raises(SystemExit) as e:
            cli.run()
        assert gc.get_freeze_count() > 0
    finally:
        gc.unfreeze()
    assert e.value.code == code


def test_snap_command_prints_kappa_s(capsys):
    from shellbvp.problems import cap_eversion as ce

    assert cli.main(["snap", "--theta", "0.25", "--h", "0.01"]) == 0
    out = capsys.readouterr().out
    r = ce.snap_curvature(0.25, 0.01)
    assert f"kappa_s R0 = {r.kappa_s:.10f}" in out and "w_s / R0" in out


def test_sweep_command_csv_round_trip(tmp_path, capsys):
    """The six columns as before, then status and reason; every number written exactly (as
    the API's sweep returns it; a sweep computes with one BLAS thread, so a lone
    snap_curvature agrees within its estimate, not necessarily to the bit)."""
    from shellbvp.problems import cap_eversion as ce

    out = tmp_path / "s.csv"
    assert cli.main(["sweep", "--T", "1.5:2.5:1", "--h", "0.01", "--csv", str(out)]) == 0
    rows = [line.split(",") for line in out.read_text().splitlines()]
    assert rows[0] == ["T", "theta_rad", "kappa_s_R0", "w_s_over_R0", "kappa_s_error", "snaps",
                       "status", "reason"]
    (T1, *r1), (T2, *r2) = rows[1:]
    assert float(T1) == 1.5 and r1[4:] == ["0", "no snap", ""] and r1[1] == "nan"  # below onset
    assert float(T2) == 2.5 and r2[4:] == ["1", "ok", ""]
    assert float(r2[1]) == ce.snap_curve([2.5], 0.01, progress=False)["kappa_s"][0]  # exact
    alone = ce.snap_curvature(0.25, 0.01)
    assert abs(float(r2[1]) - alone.kappa_s) <= float(r2[3]) + alone.error_estimate
    assert "2 caps: 1 snap, 1 no snap, 0 failed" in capsys.readouterr().out


def test_bad_tol_exits_2(capsys):
    with pytest.raises(SystemExit) as e:
        cli.main(["snap", "--tol", "0"])
    assert e.value.code == 2
    assert "--tol must lie in (0, 1)" in capsys.readouterr().err


def test_written_files_have_ordinary_permissions(tmp_path):
    """CSV files are written atomically but with the user's normal permissions (0666 less
    the umask), like open(path, "w"), not the 0600 of a temporary file."""
    import os

    from shellbvp.cache import atomic_write_text
    from shellbvp.cache import atomic_write_bytes      # the figures' PNG files

    old = os.umask(0o022)
    try:
        atomic_write_text(tmp_path / "a.csv", "x\n")
        atomic_write_bytes(tmp_path / "c.png", b"x")
        with open(tmp_path / "b.csv", "w") as f:
            f.write("x\n")
    finally:
        os.umask(old)
    mode = lambda name: os.stat(tmp_path / name).st_mode & 0o777  # noqa: E731
    assert mode("a.csv") == mode("b.csv") == mode("c.png") == 0o644


@pytest.mark.slow
def test_stability_command_prints_the_first_instability(capsys):
    """The default cap leaves axisymmetry before it snaps: the printed bifurcation lies below
    kappa_s of the axisymmetric fold (the snap command's computation, independent of the
    harmonics), and n >= 1 (tests/test_harmonics.py checks the pieces)."""
    import re

    assert cli.main(["stability", "--theta", str(math.pi / 6), "--h", "0.01"]) == 0
    out = capsys.readouterr().out
    m = re.search(r"bifurcation into n = (\d+) .* kappa R0 = ([0-9.]+)", out)
    assert m, out
    from shellbvp.problems import cap_eversion as ce

    assert int(m.group(1)) >= 1
    assert float(m.group(2)) < ce.snap_curvature(math.pi / 6, 0.01).kappa_s


@pytest.mark.slow
def test_stability_of_a_cap_that_does_not_snap_stops_at_kappa_max(capsys):
    """T = 1.5 (below the onset of snapping): nothing up to --kappa-max 2, and the line
    says the bound ended the scan (the Python route: tests/test_harmonics.py)."""
    assert cli.main(["stability", "--theta", "0.15", "--h", "0.01", "--kappa-max", "2"]) == 0
    out = capsys.readouterr().out
    assert "first instability: none up to kappa R0 = 2." in out
    assert "kappa R0 passed kappa_max = 2" in out


@pytest.mark.parametrize("argv, message", [
    (["stability", "--kappa-max", "-1"], "expected a number > 0"),
    (["stability", "everting-cap", "--kappa-max", "2"], "--kappa-max applies to a cap")])
def test_stability_kappa_max_is_checked(argv, message, capsys):
    with pytest.raises(SystemExit) as exc:
        cli.main(argv)
    assert exc.value.code == 2
    assert message in capsys.readouterr().err
