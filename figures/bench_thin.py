"""Benchmark: the default method's solve time and size against the thinness R/t.

Issue 55 asks that thin shells solve with the default method at a cost that does not grow
with R/t (target: time(R/t = 1e5) within 3x time(R/t = 1e2)). Cases
(``problems/thin_shells``, engine units), each one ``shellbvp.follow`` from the unloaded
state to a small load, with the default options (every point with its error estimate from
the next finer discretisation, energies off):

* ``hemisphere``: the clamped hemisphere under a pole force deflecting it by w/t = 1e-4
  (:func:`thin_shells.hemisphere`, P = 1e-4 t k_Reissner);
* ``cylinder L=1e2``, ``cylinder L=1e3``: the long cylinder clamped at one end, symmetry at
  the other, L / sqrt(R t) = 100 and 1000, under the internal pressure whose membrane
  displacement is 1e-5 t (:func:`thin_shells.long_cylinder`);

at R/t = 1e2, 1e3, 1e4, 1e5. Reported apart, as ``bench_snap.py`` does:

* steady state: the median of ``--repeats`` calls on one scene object in one process after
  one untimed call (its programs compiled and in memory). One object: a scene built again
  by ``thin_shells.hemisphere`` (a new lambda for its load) is compiled again, ~12 s on
  this machine, even at the same R/t (the compiled programs are found by the identity of
  the load functions; a scene file's loads compare by their expressions and are found);
* first call: the same call in a fresh process, its time inside the process (imports
  excluded) and the whole process' wall time, with an empty cache folder
  (``SHELLBVP_CACHE_DIR``; cold: tracing and XLA compilation) and again with the folder the
  cold run filled (warm: JAX's persistent cache on, ``SHELLBVP_JAX_CACHE=on``, in both).

Size: the spectral elements' nodes per element and elements (``Branch.stats``), and their
product (collocation nodes of the mesh; six unknowns each). Pinned to one core
(sched_setaffinity; single-threaded BLAS, XLA and OpenMP) where the system allows. Writes
bench_thin.csv and bench_thin.png and prints the ratios time(1e5) / time(1e2).

    python figures/bench_thin.py [--quick] [--repeats 5] [--no-first-call]
"""

from __future__ import annotations

from _pinned import PINNED  # first: before numpy reads its threads

import os  # noqa: E402

import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from _common import HERE, finish, parser, pyplot, wall_times, write_csv  # noqa: E402

ROOT = HERE.parent
R_OVER_T = (1e2, 1e3, 1e4, 1e5)
#: (name, kind, L / sqrt(R t)) of each case
CASES = (("hemisphere", "hemisphere", None), ("cylinder L=1e2", "cylinder", 1e2),
         ("cylinder L=1e3", "cylinder", 1e3))
W_OVER_T = 1e-4          # the hemisphere's pole deflection
U_OVER_T = 1e-5          # the cylinder's membrane displacement
#: the issue's target for time(1e5) / time(1e2)
TARGET_RATIO = 3.0


def problem(kind: str, R_over_t: float, L_over_sqrt_Rt=None):
    """(scene, p_stop) of one case (engine units, :mod:`problems.thin_shells`)."""
    from shellbvp.problems import thin_shells as ts

    if kind == "hemisphere":
        sc = ts.hemisphere(R_over_t)
        return sc, ts.reissner_stiffness(R_over_t) * W_OVER_T * sc.h
    sc = ts.long_cylinder(L_over_sqrt_Rt, R_over_t)
    u_inf_per_p = ts.cylinder_edge(1e3, 1.0, R_over_t)     # the membrane state: x >> 1/beta
    return sc, U_OVER_T * sc.h / u_inf_per_p


def solve(scene, P):
    """One default ``follow`` of ``scene`` from 0 to its load P; its Branch."""
    import shellbvp

    b = shellbvp.follow(scene, p_stop=(0.0, P), energies=False)
    if b.stop or b.p[-1] != P:
        raise shellbvp.ConvergenceError(f"h = {scene.h:g}: stopped before {P:g}: {b.stop}")
    return b


#: the fresh process of :func:`first_call`: imports, then one timed solve
CHILD = """
import sys, time
sys.path[:0] = [sys.argv[1], sys.argv[2]]
import bench_thin as B
kind, rt, lam = sys.argv[3], float(sys.argv[4]), sys.argv[5]
t = time.perf_counter()
b = B.solve(*B.problem(kind, rt, None if lam == "-" else float(lam)))
print("FIRST", time.perf_counter() - t, b.stats["nodes"], b.stats["elements"])
"""


def first_call(kind, R_over_t, lam, cache_dir) -> tuple[float, float]:
    """(the solve's time, the whole process' wall time) in a fresh process whose cache
    folder is ``cache_dir``."""
    env = dict(os.environ, SHELLBVP_CACHE_DIR=str(cache_dir), SHELLBVP_JAX_CACHE="on")
    t = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", CHILD, str(ROOT), str(HERE), kind,
                          repr(R_over_t), "-" if lam is None else repr(lam)], env=env,
                         check=True, capture_output=True, text=True).stdout
    wall = time.perf_counter() - t
    line = next(x for x in out.splitlines() if x.startswith("FIRST"))
    return float(line.split()[1]), wall


def steady(kind, R_over_t, lam, repeats: int) -> dict:
    """The median (and spread) of ``repeats`` calls on one scene object after one untimed
    call; the size. (One object: the compiled programs are found again by the identity of
    the scene's load functions, and thin_shells' scenes carry a new lambda each.)"""
    sc, P = problem(kind, R_over_t, lam)
    b = solve(sc, P)
    times = wall_times(lambda: solve(sc, P), repeat=repeats)
    return {"median": statistics.median(times), "min": min(times), "max": max(times),
            "nodes": b.stats["nodes"], "elements": b.stats["elements"],
            "points": b.stats["points"], "w_error_relative": abs(b.w_error[-1] / b.w[-1])}


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--repeats", type=int, default=5, help="steady-state calls per row")
    p.add_argument("--no-first-call", action="store_true", help="skip the fresh processes")
    a = p.parse_args(argv)
    rts = (1e2, 1e5) if a.quick else R_OVER_T
    cases = CASES[:2] if a.quick else CASES
    repeats = 2 if a.quick else a.repeats
    rows = []
    for name, kind, lam in cases:
        for rt in rts:
            s = steady(kind, rt, lam, repeats)
            row = {"case": name, "R_over_t": rt, **s, "first_cold": np.nan,
                   "process_cold": np.nan, "first_warm": np.nan, "process_warm": np.nan}
            rows.append(row)
            print(f"{name:15s} R/t = {rt:7.0e}: steady {s['median']:.3f} s (median of "
                  f"{repeats}, {s['min']:.3f}-{s['max']:.3f}), {s['nodes']} nodes x "
                  f"{s['elements']} elements, {s['points']} points, w error "
                  f"{s['w_error_relative']:.1e}", flush=True)
    if not a.no_first_call:
        for row, (name, kind, lam) in zip(rows, [c for c in cases for _ in rts]):
            with tempfile.TemporaryDirectory() as d:
                row["first_cold"], row["process_cold"] = first_call(kind, row["R_over_t"],
                                                                    lam, d)
                row["first_warm"], row["process_warm"] = first_call(kind, row["R_over_t"],
                                                                    lam, d)
            print(f"{name:15s} R/t = {row['R_over_t']:7.0e}: first call cold "
                  f"{row['first_cold']:.2f} s (process {row['process_cold']:.2f} s), warm "
                  f"{row['first_warm']:.2f} s (process {row['process_warm']:.2f} s)",
                  flush=True)
    write_csv(a.out / "bench_thin.csv",
              ["case", "R_over_t", "steady_median[s]", "steady_min[s]", "steady_max[s]",
               "repeats", "nodes", "elements", "nodes_x_elements", "points",
               "w_error_relative", "first_call_cold[s]", "process_cold[s]",
               "first_call_warm[s]", "process_warm[s]", "pinned"],
              [[r["case"], r["R_over_t"], r["median"], r["min"], r["max"], repeats,
                r["nodes"], r["elements"], r["nodes"] * r["elements"], r["points"],
                r["w_error_relative"], r["first_cold"], r["process_cold"], r["first_warm"],
                r["process_warm"], PINNED] for r in rows])

    print(f"time(R/t = {rts[-1]:.0e}) / time(R/t = {rts[0]:.0e}) (target <= {TARGET_RATIO:g}):")
    for name, _, _ in cases:
        mine = {r["R_over_t"]: r for r in rows if r["case"] == name}
        lo, hi = mine[rts[0]], mine[rts[-1]]
        parts = [f"steady {hi['median'] / lo['median']:.2f}"]
        if not a.no_first_call:
            parts += [f"first call cold {hi['first_cold'] / lo['first_cold']:.2f}",
                      f"warm {hi['first_warm'] / lo['first_warm']:.2f}"]
        print(f"  {name:15s} " + ", ".join(parts)
              + f"; size {hi['nodes'] * hi['elements']} / {lo['nodes'] * lo['elements']}")

    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 5.4))
    for i, (name, _, _) in enumerate(cases):
        mine = [r for r in rows if r["case"] == name]
        x = np.array([r["R_over_t"] for r in mine])
        ax.plot(x, [r["median"] for r in mine], "o-", color=f"C{i}",
                label=f"{name}: steady state (median)")
        if not a.no_first_call:
            ax.plot(x, [r["first_cold"] for r in mine], "s:", color=f"C{i}", ms=4,
                    label=f"{name}: first call, cold cache")
            ax.plot(x, [r["first_warm"] for r in mine], "^--", color=f"C{i}", ms=4,
                    alpha=0.6, label=f"{name}: first call, warm cache")
        bx.plot(x, [r["nodes"] * r["elements"] for r in mine], "o-", color=f"C{i}",
                label=name)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("R / t")
    ax.set_ylabel("wall time of one follow (s)")
    ax.set_title("default method, one branch to a small load" + ("" if PINNED else
                                                                  " (unpinned)"),
                 fontsize=10)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=3)
    ax.grid(alpha=0.3, which="both")
    bx.set_xscale("log")
    bx.set_xlabel("R / t")
    bx.set_ylabel("nodes x elements")
    bx.set_ylim(bottom=0)
    bx.set_title("size of the discretisation (16 nodes per element)", fontsize=10)
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3)
    fig.suptitle("Thin shells: cost against R/t (hemisphere under a pole force, w/t = 1e-4; "
                 "pressurised cylinder, u/t = 1e-5)", fontsize=10)
    finish(fig, a.out, "bench_thin")


if __name__ == "__main__":
    sys.exit(main())
