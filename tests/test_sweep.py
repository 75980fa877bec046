"""Sweeps keep every cap (shellbvp.sweep, cap_eversion.snap_curve, ``shellbvp sweep``):

* a cap that fails gets a row with its reason and the sweep goes on (API, CLI exit code 1);
* a sweep interrupted by a signal at a random point leaves the finished caps (CSV marked
  incomplete, journal), and ``--resume`` gives the same CSV as an uninterrupted run, byte
  for byte (Ctrl-C here; a SIGKILL, which nothing can catch, in the slow suite);
* the values do not depend on who runs the chunks: two local processes, a Dask cluster;
* the journal refuses to resume another sweep.
The reference of every comparison is the serial, uninterrupted sweep of the same caps.
"""

import math
import os
import random
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from shellbvp import cli
from shellbvp.problems import cap_eversion as ce
from shellbvp.sweep import Journal, Record

H = 0.01
#: 14 caps in chunks of 5: three chunks, the first starting below the onset (no snap). The
#: sweeps that run in other processes use the Koiter shell, whose programs compile in ~10 s
#: (a relaxed CG cap ~30 s), and JAX's compilation cache, as the command line does
T_VALUES = np.round(np.arange(1.5, 8.01, 0.5), 10)
CHUNK = 5
MATERIAL = "koiter"


@pytest.fixture(scope="module")
def serial():
    return ce.snap_curve(T_VALUES, H, 1.0, material=MATERIAL, progress=False,
                         chunk_size=CHUNK)


@pytest.fixture
def workers_cache(monkeypatch):
    """Worker processes with JAX's compilation cache (this process keeps it off)."""
    monkeypatch.setenv("SHELLBVP_JAX_CACHE", "on")


def _rows(curve):
    """The records, value for value (repr: nan equals nan)."""
    return [repr(r) for r in curve.records]


def _no_fold_curve_at(monkeypatch, T_fail):
    """Make the cap at T_fail go through snap_curvature (not found along the fold curve)."""
    real = ce._along_fold_curve

    def along(T, *args):
        return None if abs(T - T_fail) < 1e-9 else real(T, *args)

    monkeypatch.setattr(ce, "_along_fold_curve", along)


def test_every_cap_gets_a_row_and_a_failure_does_not_stop_the_sweep(monkeypatch):
    real = ce.snap_curvature

    def flaky(theta, h, *args, **kw):
        if abs(theta / math.sqrt(h) - 2.5) < 1e-9:
            raise ce.shellbvp.ConvergenceError("fold polishing: no convergence in 12 steps "
                                               "(a made-up failure)\nsecond line")
        return real(theta, h, *args, **kw)

    monkeypatch.setattr(ce, "snap_curvature", flaky)
    _no_fold_curve_at(monkeypatch, 2.5)
    curve = ce.snap_curve([1.5, 2.0, 2.5, 3.0], H, 1.0, progress=False)
    assert list(curve["status"]) == ["no snap", "ok", "failed", "ok"]
    assert curve["reason"][2] == "fold polishing: no convergence in 12 steps (a made-up failure)"
    assert np.isnan(curve["kappa_s"][2]) and np.isfinite(curve["kappa_s"][3])
    assert curve.counts() == {"ok": 2, "no snap": 1, "failed": 1}


def test_cli_sweep_with_a_failed_cap_writes_every_row_and_exits_1(monkeypatch, tmp_path,
                                                                   capsys):
    real = ce.snap_curvature

    def flaky(theta, h, *args, **kw):
        if abs(theta / math.sqrt(h) - 3.0) < 1e-9:
            raise ce.shellbvp.ConvergenceError("made-up failure, with a comma")
        return real(theta, h, *args, **kw)

    monkeypatch.setattr(ce, "snap_curvature", flaky)
    _no_fold_curve_at(monkeypatch, 3.0)
    out = tmp_path / "s.csv"
    code = cli.main(["sweep", "--T", "2:3:0.5", "--csv", str(out)])
    assert code == 1
    text = capsys.readouterr()
    assert "3 caps: 2 snap, 0 no snap, 1 failed" in text.out
    assert "failed at T = 3: made-up failure, with a comma" in text.err
    import csv

    rows = list(csv.DictReader(out.open()))
    assert [r["status"] for r in rows] == ["ok", "ok", "failed"]
    assert rows[2]["reason"] == "made-up failure, with a comma"
    assert not (tmp_path / "s.csv.journal").exists()


def test_bad_sweep_arguments_are_named(tmp_path):
    for kw, name in [(dict(jobs=0), "jobs"), (dict(chunk_size=0), "chunk_size"),
                     (dict(resume=True), "csv_path"), (dict(executor=object()), "executor")]:
        with pytest.raises(ValueError, match=name):
            ce.snap_curve([2.0], H, progress=False, **kw)
    with pytest.raises(SystemExit) as e:
        cli.main(["sweep", "--T", "2:3:0.5", "--csv", str(tmp_path / "x.csv"), "--jobs", "0"])
    assert e.value.code == 2


def test_journal_of_another_sweep_is_refused(tmp_path):
    path = tmp_path / "j"
    Journal(path).start({"keys": [1.0]}, resume=False)
    Journal(path).append(Record(0, 1.0, "ok", "", {"x": 1.0}))
    assert list(Journal(path).start({"keys": [1.0]}, resume=True)) == [0]
    with pytest.raises(ValueError, match="another sweep"):
        Journal(path).start({"keys": [2.0]}, resume=True)


def test_two_processes_give_the_serial_values(serial, workers_cache):
    parallel = ce.snap_curve(T_VALUES, H, 1.0, material=MATERIAL, progress=False,
                             chunk_size=CHUNK, jobs=2)
    assert _rows(parallel) == _rows(serial)
    assert serial.counts() == {"ok": 12, "no snap": 2, "failed": 0}


def test_a_dask_cluster_gives_the_serial_values(serial, workers_cache):
    """Dask's workers as they come (BLAS pinned to one thread by Dask's default
    environment): the tasks compute with one BLAS thread everywhere, so the values are the
    serial sweep's to the last bit."""
    distributed = pytest.importorskip("dask.distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, \
            distributed.Client(cluster) as client:
        curve = ce.snap_curve(T_VALUES, H, 1.0, material=MATERIAL, progress=False,
                              chunk_size=CHUNK, executor=client.get_executor())
    assert _rows(curve) == _rows(serial)


def _sweep_command(csv, *extra):
    code = ("import sys; from shellbvp import cli; sys.exit(cli.main(sys.argv[1:]))")
    return [sys.executable, "-c", code, "sweep", "--T", "1.5:8:0.5", "--h", str(H),
            "--material", MATERIAL, "--csv", str(csv), "--chunk-size", str(CHUNK), *extra]


def _interrupted_then_resumed(tmp_path, sig, seed):
    """Run the sweep, stop it by ``sig`` once a random number of caps is journaled, resume
    it; returns (exit code, stderr, CSV of the stopped run, CSV of the resumed run)."""
    env = dict(os.environ, SHELLBVP_JAX_CACHE="on")
    csv = tmp_path / "sweep.csv"
    journal = tmp_path / "sweep.csv.journal"
    wanted = random.Random(seed).randint(1, len(T_VALUES) - 2)
    # SIGINT handled, not ignored, while the child starts (exec resets a handled signal to
    # its default, but keeps an ignored one ignored): a shell starts a background job
    # (``bash .ci/run &``) with SIGINT ignored, and a Python started so installs no
    # KeyboardInterrupt handler (it honours Ctrl-C only in the foreground)
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        proc = subprocess.Popen(_sweep_command(csv), env=env, stdout=subprocess.PIPE,
                                stderr=subprocess.PIPE, text=True)
    finally:
        signal.signal(signal.SIGINT, previous)
    deadline = time.time() + 300
    while time.time() < deadline and proc.poll() is None:
        if journal.exists() and len(journal.read_text().splitlines()) - 1 >= wanted:
            break
        time.sleep(0.002)
    proc.send_signal(sig)
    _, err = proc.communicate(timeout=300)
    stopped = csv.read_text() if csv.exists() else ""
    resumed = subprocess.run(_sweep_command(csv, "--resume"), env=env, capture_output=True,
                             text=True, timeout=600)
    assert resumed.returncode == 0, resumed.stderr
    assert not journal.exists()
    return proc.returncode, err, stopped, csv.read_text()


def _reference_csv(tmp_path, serial):
    ref = tmp_path / "ref.csv"
    ce._write_curve(ref, serial.records)
    return ref.read_text()


def test_ctrl_c_leaves_the_finished_caps_and_resume_completes_them(tmp_path, serial):
    code, err, stopped, final = _interrupted_then_resumed(tmp_path, signal.SIGINT, seed=1)
    assert code == 130
    line, = [ln for ln in err.splitlines() if ln.strip()]
    assert line.startswith("shellbvp: interrupted after ") and "--resume continues" in line
    rows = stopped.splitlines()
    assert rows[0].startswith("T,theta_rad,kappa_s_R0") and rows[-1].startswith("# incomplete")
    assert 1 <= len(rows) - 2 < len(T_VALUES)
    # the stopped run's rows are those of the uninterrupted run, and so is the final CSV
    ref = _reference_csv(tmp_path, serial)
    assert set(rows[1:-1]) <= set(ref.splitlines())
    assert final == ref


def test_a_kill_loses_at_most_the_unfinished_caps(tmp_path, serial):
    code, _, _, final = _interrupted_then_resumed(tmp_path, signal.SIGKILL, seed=7)
    assert code == -signal.SIGKILL
    assert final == _reference_csv(tmp_path, serial)
