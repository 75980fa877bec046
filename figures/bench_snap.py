"""Benchmark: wall time per snap curvature kappa_s against its accuracy, and start-up cost.

Cap: Theta = pi/6, h0/R0 = 0.01, lam = 1, Ciarlet-Geymonat, relaxed and plane strain.
For every model and tolerance it reports the steady-state wall time of one
``snap_curvature(..., tol=tol)`` (median, min and max of repeats in one process after a first
call; the rows run in turn, one call each per round, so that the machine's slow spells fall
on all of them alike), the error of kappa_s against a reference (tol 1e-12 on degrees from
56 up), next to the error estimate the call returns, the final Chebyshev degree and the
number of Newton evaluations. Start-up: the wall time of the whole command ``shellbvp snap --model M`` in a
fresh process, with an empty cache folder (``cold``: symbolic derivation, tracing, XLA
compilation) and again with that folder filled (``warm``).

The peer is AUTO-07p on the same equations (analytic Jacobians, NCOL = 4, 22 continuation
steps), measured on this machine type (issue #9): relaxed 32 / 58 / 111 ms at errors 7e-9 /
8e-11 / 1e-13 (NTST 10 / 20 / 40); plane strain 26 / 45 / 87 ms at the same NTST (errors not
recorded; drawn at the accuracy class 1e-8 / 1e-10 / 1e-12 they were measured for).

Also the Fig. 3 set (relaxed, h0/R0 = 0.01, lam in {0.01, 0.1, 1, 10}, T = 2:0.25:10, 132
caps, tol 1e-10) in steady state: one ``snap_curve`` sweep per lam (caps found along the fold
curve) against the same caps each continued from kappa = 0 (AUTO-07p: 13-16 s at NTST = 40).

Pinned to one core (sched_setaffinity, single-threaded BLAS and XLA), as AUTO was.
Writes bench_snap.csv (steady state), bench_snap_startup.csv, bench_snap_fig3.csv and
bench_snap.png.

    python figures/bench_snap.py [--quick] [--repeats 15] [--no-startup]
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
os.environ.setdefault("XLA_FLAGS", "--xla_cpu_multi_thread_eigen=false "
                                   "intra_op_parallelism_threads=1")
try:
    os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
except (AttributeError, OSError):   # not Linux: run unpinned, say so below
    pass

import math  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from _common import finish, parser, pyplot, write_csv  # noqa: E402

THETA, H0, LAM = math.pi / 6, 0.01, 1.0
MODELS = ("relaxed", "plane_strain")
TOLS = (1e-6, 1e-8, 1e-9, 1e-10, 1e-12)
REFERENCE_TOL = 1e-12
#: the reference fold is located on degrees from 56 up, which none of the timed rows uses
#: (tol 1e-12 is the finest the round-off floor of this cap allows, ~6e-13)
REFERENCE_NODES = 56
#: AUTO-07p on this machine type (issue #9): (ms, error) per model; plane strain errors were
#: not recorded, so its points stand at the accuracy class they were measured for
AUTO = {"relaxed": [(32, 7e-9), (58, 8e-11), (111, 1e-13)],
        "plane_strain": [(26, 1e-8), (45, 1e-10), (87, 1e-12)]}


def steady(cases, repeats):
    """{(model, tol): (times (repeats,), last result)}, in steady state. The cases are run
    in turn, one call each per round (after one call each to compile and warm the caches),
    so that a slow spell of the machine falls on every row alike, not on one."""
    from shellbvp.problems import cap_eversion as ce

    for model, tol in cases:
        ce.snap_curvature(THETA, H0, LAM, model=model, tol=tol)
    times = {case: [] for case in cases}
    last = {}
    for _ in range(repeats):
        for model, tol in cases:
            t = time.perf_counter()
            last[model, tol] = ce.snap_curvature(THETA, H0, LAM, model=model, tol=tol)
            times[model, tol].append(time.perf_counter() - t)
    return {case: (np.array(times[case]), last[case]) for case in cases}


def startup(model, cache_dir):
    """Wall time (s) of the whole command in a fresh process, and its kappa_s line."""
    env = dict(os.environ, SHELLBVP_CACHE_DIR=str(cache_dir))
    exe = shutil.which("shellbvp")
    cmd = [exe] if exe else [sys.executable, "-m", "shellbvp.cli"]
    t = time.perf_counter()
    out = subprocess.run(cmd + ["snap", "--model", model], env=env, check=True,
                         capture_output=True, text=True)
    wall = time.perf_counter() - t
    line = next((x for x in out.stdout.splitlines() if x.startswith("kappa_s")), "")
    return wall, line


def fig3_set(tol=1e-10, quick=False):
    """The Fig. 3 caps (relaxed, h = 0.01, lam in {0.01, 0.1, 1, 10}, T = 2:0.25:10) in
    steady state: one snap_curve sweep per lam (along the fold curve) against the same caps
    each continued from kappa = 0 (restarts). Returns rows (lam, caps, along_s, restarts_s,
    along_fold_curve, max |difference|)."""
    from shellbvp.problems import cap_eversion as ce

    T = np.arange(2.0, 10.001, 1.0 if quick else 0.25)
    rows = []
    for lam in ((1.0,) if quick else (0.01, 0.1, 1.0, 10.0)):
        ce.snap_curve(T, 0.01, lam, tol=tol, progress=False)          # compile, warm
        t = time.perf_counter()
        out = ce.snap_curve(T, 0.01, lam, tol=tol, progress=False)
        along = time.perf_counter() - t
        t = time.perf_counter()
        ks = [ce.snap_curvature(x * 0.1, 0.01, lam, tol=tol).kappa_s for x in T]
        restarts = time.perf_counter() - t
        diff = np.nanmax(np.abs(np.array(ks) - out["kappa_s"]))
        rows.append([lam, T.size, along, restarts, int(out["along_fold_curve"].sum()), diff])
        print(f"Fig. 3 caps, lam = {lam:<5g}: {along:.2f} s along the fold curve "
              f"({rows[-1][4]} of {T.size}), {restarts:.2f} s by restarts (ratio "
              f"{restarts / along:.1f}); max difference {diff:.1e}")
    print(f"Fig. 3 set ({sum(r[1] for r in rows)} caps, tol {tol:g}): "
          f"{sum(r[2] for r in rows):.2f} s along the fold curve, "
          f"{sum(r[3] for r in rows):.2f} s by restarts")
    return rows


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=15, help="steady-state repetitions (default 15)")
    p.add_argument("--no-startup", action="store_true", help="skip the fresh-process timings")
    a = p.parse_args(argv)
    repeats = 3 if a.quick else a.repeats
    tols = (1e-6, 1e-9, 1e-12) if a.quick else TOLS
    from shellbvp.problems import cap_eversion as ce

    pinned = len(os.sched_getaffinity(0)) == 1 if hasattr(os, "sched_getaffinity") else False
    print(f"one core pinned: {pinned}; median of {repeats} repeats per entry")
    from shellbvp import Chebyshev

    refs = {}
    for model in MODELS:
        refs[model] = ref = ce.snap_curvature(THETA, H0, LAM, model=model, tol=REFERENCE_TOL,
                                              method=Chebyshev(nodes=REFERENCE_NODES))
        print(f"{model}: reference kappa_s R0 = {ref.kappa_s!r} (tol {REFERENCE_TOL:g}, "
              f"estimate {ref.error_estimate:.1e}, N = "
              f"{ref.stats['fold']['resolution']['nodes']})")
    timed = steady([(model, tol) for model in MODELS for tol in tols], repeats)
    rows = []
    for model in MODELS:
        ref = refs[model]
        print(model)
        for tol in tols:
            times, r = timed[model, tol]
            err = abs(r.kappa_s - ref.kappa_s)
            rows.append([model, tol, 1e3 * float(np.median(times)), 1e3 * float(times.min()),
                         1e3 * float(times.max()), repeats, r.kappa_s, r.error_estimate, err,
                         r.stats["fold"]["resolution"]["nodes"], r.stats["evaluations"]])
            print(f"  tol {tol:.0e}: median {rows[-1][2]:6.1f} ms (min {rows[-1][3]:.1f}, max "
                  f"{rows[-1][4]:.1f}); error {err:.1e} (estimate {r.error_estimate:.1e}); "
                  f"N = {rows[-1][9]}, {rows[-1][10]} evaluations")
    write_csv(a.out / "bench_snap.csv",
              ["model", "tol", "median_ms", "min_ms", "max_ms", "repeats", "kappa_s_R0",
               "error_estimate", "error_vs_reference", "final_nodes", "evaluations"], rows)

    if not a.no_startup:
        srows = []
        for model in MODELS:
            with tempfile.TemporaryDirectory() as d:
                for cache in ("cold", "warm"):
                    wall, line = startup(model, d)
                    srows.append([model, cache, wall])
                    print(f"start-up {model:>12s}, {cache} cache: {wall:5.1f} s  ({line})")
        write_csv(a.out / "bench_snap_startup.csv", ["model", "cache", "command_wall_s"], srows)

    write_csv(a.out / "bench_snap_fig3.csv",
              ["lam", "caps", "along_fold_curve_s", "restarts_s", "caps_along_fold_curve",
               "max_abs_difference"], fig3_set(quick=a.quick))

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for model, color in zip(MODELS, ("C0", "C1")):
        sel = [r for r in rows if r[0] == model]
        ax.loglog([r[2] for r in sel], [max(r[8], 1e-16) for r in sel], "o-", color=color,
                  label=f"shellbvp, {model} (error)")
        ax.loglog([r[2] for r in sel], [max(r[7], 1e-16) for r in sel], "s:", color=color,
                  mfc="none", label=f"shellbvp, {model} (estimate)")
        for r in sel:
            ax.annotate(f"tol {r[1]:.0e}", (r[2], max(r[8], 1e-16)), fontsize=6,
                        xytext=(3, -8), textcoords="offset points")
        t, e = zip(*AUTO[model])
        ax.loglog(t, e, "x", color=color, ms=9, mew=2,
                  label=f"AUTO-07p, this machine type, {model}")
    ax.set_xlabel("wall time per kappa_s [ms] (one core, steady state, median)")
    ax.set_ylabel("|kappa_s R0 error|")
    ax.set_title("Theta = pi/6, h0/R0 = 0.01, lam = 1, CG", fontsize=9)
    ax.legend(fontsize=6.5, loc="upper right")
    finish(fig, a.out, "bench_snap")


if __name__ == "__main__":
    main()
