"""Benchmark: wall time per snap curvature kappa_s, per back-end, on one core.

Cap: Theta = pi/6, h0/R0 = 0.01, lam = 1, relaxed Ciarlet-Geymonat (issue #4, item 8).
For every back-end it reports
  * the first-call cost in a fresh process: ``cold`` (empty cache folder: symbolic derivation
    + tracing + XLA compilation) and ``warm disk`` (derivations and XLA programs cached on
    disk, tracing only), each minus the process' import time;
  * the steady-state cost: median (and min/max) of repeated snap_curvature calls in one
    process after the first;
  * the error of kappa_s against a reference (spectral, tol 1e-12), next to the estimate.
The spectral back-end is also timed against its accuracy (start degree N0 = 8 ... 32, the
fold re-located at N0 + 8, and the adaptive default): error against run time goes to
bench_snap.csv and bench_snap.png.

Pinned to one core (sched_setaffinity, single-threaded BLAS and XLA), as the target
(<= 0.1 s per fold at error <= 1e-8 on one core) is stated.

    python figures/bench_snap.py [--quick] [--repeats 7] [--backends spectral,shooting]
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

import json  # noqa: E402
import math  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from _common import HERE, finish, parser, pyplot, write_csv  # noqa: E402

THETA, H0, LAM = math.pi / 6, 0.01, 1.0

_CHILD = """
import json, math, sys, time
t0 = time.perf_counter()
from shellbvp.problems import cap_eversion as ce
t1 = time.perf_counter()
r = ce.snap_curvature(math.pi / 6, 0.01, 1.0, method=sys.argv[1])
t2 = time.perf_counter()
print(json.dumps(dict(import_s=t1 - t0, first_call_s=t2 - t1, kappa_s=r.kappa_s)))
"""


def first_call(backend, cache_dir=None):
    env = dict(os.environ)
    if cache_dir is not None:
        env["SHELLBVP_CACHE_DIR"] = str(cache_dir)
    env["PYTHONPATH"] = os.pathsep.join([str(HERE.parent), env.get("PYTHONPATH", "")])
    out = subprocess.run([sys.executable, "-c", _CHILD, backend], env=env, check=True,
                         capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def steady(backend, repeats, tol=1e-9, nodes=None):
    import shellbvp
    from shellbvp.problems import cap_eversion as ce

    method = shellbvp.Chebyshev(nodes=nodes) if backend == "spectral" else backend
    kw = dict(method=method, tol=tol)
    ce.snap_curvature(THETA, H0, LAM, **kw)   # compile, warm caches
    times, r = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        r = ce.snap_curvature(THETA, H0, LAM, **kw)
        times.append(time.perf_counter() - t)
    return np.array(times), r


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=7, help="steady-state repetitions (default 7)")
    p.add_argument("--backends", default="spectral,shooting",
                   help="comma-separated back-ends (collocation takes minutes per fold)")
    p.add_argument("--no-cold", action="store_true", help="skip the cold-cache first call")
    a = p.parse_args(argv)
    backends = a.backends.split(",")
    repeats = 3 if a.quick else a.repeats
    from shellbvp.problems import cap_eversion as ce

    pinned = len(os.sched_getaffinity(0)) == 1 if hasattr(os, "sched_getaffinity") else False
    ref = ce.snap_curvature(THETA, H0, LAM, tol=1e-12)
    print(f"reference kappa_s R0 = {ref.kappa_s!r} (spectral, tol 1e-12, estimate "
          f"{ref.error_estimate:.1e}); one core pinned: {pinned}")
    summary = []
    for backend in backends:
        warm = first_call(backend)
        cold = None
        if not a.no_cold and not a.quick:
            with tempfile.TemporaryDirectory() as d:
                cold = first_call(backend, d)
        times, r = steady(backend, {"collocation": 1, "shooting": min(repeats, 3)}.get(
            backend, repeats))
        err = abs(r.kappa_s - ref.kappa_s)
        summary.append((backend, np.median(times), times.min(), times.max(), len(times),
                        warm["first_call_s"], cold["first_call_s"] if cold else math.nan,
                        r.kappa_s, r.error_estimate, err))
        print(f"{backend:>11s}: steady median {np.median(times) * 1e3:8.1f} ms "
              f"(min {times.min() * 1e3:.1f}, max {times.max() * 1e3:.1f}, n = {len(times)}); "
              f"first call {warm['first_call_s']:.1f} s warm disk"
              + (f", {cold['first_call_s']:.1f} s cold" if cold else "")
              + f"; kappa_s = {r.kappa_s:.12f}, estimate {r.error_estimate:.1e}, "
                f"error {err:.1e}")
    if len(summary) > 1:
        base = summary[0][1]
        for s in summary[1:]:
            print(f"steady-state ratio {s[0]} / {summary[0][0]} = {s[1] / base:.1f}")

    write_csv(a.out / "bench_snap_backends.csv",
              ["backend", "median_s", "min_s", "max_s", "repeats", "first_call_warm_disk_s",
               "first_call_cold_s", "kappa_s_R0", "error_estimate", "error_vs_reference"],
              summary)

    # Error against run time, spectral: continuation at N0 nodes, the fold re-located once at
    # N0 + 8 (tol = 0.5 stops there), and the default adaptive run at tol = 1e-12.
    cases = [(12, 0.5), (20, 0.5), (32, 1e-12)] if a.quick else \
        [(12, 0.5), (16, 0.5), (20, 0.5), (24, 0.5), (32, 1e-8), (32, 1e-12)]
    rows = []
    for n0, tol in cases:
        times, r = steady("spectral", repeats, tol=tol, nodes=n0)
        rows.append([n0, tol, float(np.median(times)), float(times.min()), float(times.max()),
                     r.kappa_s, r.error_estimate, abs(r.kappa_s - ref.kappa_s),
                     r.stats["fold"]["resolution"].get("nodes")])
        print(f"spectral N0 = {n0:2d}, tol {tol:.0e}: median {np.median(times) * 1e3:7.1f} ms, "
              f"final N = {rows[-1][8]}, kappa_s error {rows[-1][7]:.1e} "
              f"(estimate {r.error_estimate:.1e})")
    write_csv(a.out / "bench_snap.csv",
              ["start_nodes", "tol", "median_s", "min_s", "max_s", "kappa_s_R0",
               "error_estimate", "error_vs_reference", "final_nodes"], rows)

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(5.5, 4))
    t = np.array([r[2] for r in rows])
    ax.loglog(t, [max(r[7], 1e-16) for r in rows], "o-", label="error vs reference")
    ax.loglog(t, [max(r[6], 1e-16) for r in rows], "s--", label="error estimate")
    for r in rows:
        ax.annotate(f"N = {r[8]}", (r[2], max(r[7], 1e-16)), fontsize=7)
    ax.axvline(0.1, color="k", lw=0.6, ls=":")
    ax.axhline(1e-8, color="k", lw=0.6, ls=":")
    ax.set_xlabel("median wall time per kappa_s [s] (one core)")
    ax.set_ylabel("|kappa_s R0 error|")
    ax.set_title("spectral back-end, Theta = pi/6, h0/R0 = 0.01, lam = 1", fontsize=9)
    ax.legend(fontsize=8)
    finish(fig, a.out, "bench_snap")


if __name__ == "__main__":
    main()
