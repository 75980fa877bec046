"""Cost of following a bifurcation past axisymmetry (shellbvp.postbuckling) on the default cap
(Theta = pi/6, h = 0.01, lam = 1: n = 3 at kappa 4.17576, subcritical):

* setup: ``Fourier2D(eq, 3, 2)`` + ``critical_point`` + ``koiter`` (the bifurcation in the
  2D discretisation and Koiter's coefficients);
* branch: ``follow_bifurcation(ins, n_folds=1, estimate_error=False)``, the lobed branch from
  the bifurcation to its first fold (kappa = -2.034, where it is nearly axisymmetric again,
  passed by a fold probe: docs/postbuckling.md; its own setup included).

The first call of each (tracing and compiling the JAX programs; JAX's disk cache off) is
timed in a fresh process of its own; the steady state is the median (and min, max) of
repeated calls in one process after a warm-up call. For the steady state the script also
says where the time goes (the last columns, from the median run): the Hessian's assembly
(``Fourier2D.hessian``; of it the density's Hessian kernel and the synthesis of the local
numbers), ``parameter_gradient`` (of it the fields' p-rates, ``Fourier2D._rates``), the
bordered LU of the continuation's Newton; the evaluations are calls of
``LobedSystem.evaluate`` (one per Newton iteration). The instability itself
(``first_instability``, timed in bench_stability.py) is computed once, untimed.

Run on one pinned core (as the CSV was measured), with nothing else on that core:

    taskset -c 0 python figures/bench_postbuckling.py [--quick] [--repeat R]

(``--quick``: one repeat, the branch cut at 40 points). Writes bench_postbuckling.csv.
"""

from __future__ import annotations

import importlib
import json
import math
import os
import statistics
import subprocess
import sys
import time

os.environ["SHELLBVP_JAX_CACHE"] = "off"       # a first call compiles: no disk cache

from _common import HERE, clock, parser, write_csv
import shellbvp
from shellbvp import harmonics as _H
from shellbvp import postbuckling as pb
from shellbvp.fourier2d import Fourier2D
from shellbvp.problems import cap_eversion as ce

#: the module (the package's ``newton`` is its function)
_newton = importlib.import_module("shellbvp.continuation.newton")

THETA, H0, LAM = math.pi / 6, 0.01, 1.0
QUICK_STEPS = 40
BREAKDOWN = ("hessian", "kernel", "synthesis", "parameter_gradient", "field_rates", "lu")


def instability():
    return ce.first_instability(THETA, H0, LAM)


def setup(ins):
    f = Fourier2D(ins.equilibrium, ins.n, 2)
    crit = pb.critical_point(f, ins.p)
    return pb.koiter(f, crit, direction=1.0)


def branch(ins, quick=False):
    options = pb.LOBED_OPTIONS.with_(max_steps=QUICK_STEPS) if quick else pb.LOBED_OPTIONS
    return shellbvp.follow_bifurcation(ins, n_folds=1, estimate_error=False, options=options)


TASKS = {"setup": lambda ins, quick: setup(ins), "branch": branch}


def instrument(spent: dict, counts: dict):
    """Clocks around the parts named in BREAKDOWN (spent[name] += wall time) and a count of
    the system's evaluations; returns a function that removes them."""
    import jax

    restore = [(Fourier2D, name, clock(Fourier2D, name, spent, key)) for name, key in
               (("hessian", "hessian"), ("state", "synthesis"),
                ("parameter_gradient", "parameter_gradient"), ("_rates", "field_rates"))]
    restore.append((_newton, "bordered_lu", clock(_newton, "bordered_lu", spent, "lu")))
    kernel_of = _H._hessian_kernel

    def timed_kernel(*args, **kwargs):
        k = kernel_of(*args, **kwargs)

        def run(*args):
            t = time.perf_counter()
            out = jax.block_until_ready(k(*args))
            spent["kernel"] = spent.get("kernel", 0.0) + time.perf_counter() - t
            return out
        return run
    _H._hessian_kernel = timed_kernel
    restore.append((_H, "_hessian_kernel", kernel_of))
    evaluate = pb.LobedSystem.evaluate

    def counted(self, y, p):
        counts["evaluations"] = counts.get("evaluations", 0) + 1
        return evaluate(self, y, p)
    pb.LobedSystem.evaluate = counted
    restore.append((pb.LobedSystem, "evaluate", evaluate))

    def undo():
        for owner, name, original in reversed(restore):
            setattr(owner, name, original)
    return undo


def first_call(task: str, quick: bool) -> float:
    """The task's first call in a fresh process (this script with --first task), pinned as
    this one is."""
    cmd = [sys.executable, str(HERE / "bench_postbuckling.py"), "--first", task]
    if quick:
        cmd.append("--quick")
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, cwd=HERE).stdout
    return json.loads(out.strip().splitlines()[-1])["seconds"]


def steady(task: str, ins, repeat: int, quick: bool):
    """(times, breakdowns, results) of ``repeat`` calls after one warm-up call."""
    TASKS[task](ins, quick)
    times, parts, results = [], [], []
    for _ in range(repeat):
        spent, counts = {}, {}
        undo = instrument(spent, counts)
        try:
            t = time.perf_counter()
            results.append(TASKS[task](ins, quick))
            times.append(time.perf_counter() - t)
        finally:
            undo()
        parts.append((spent, counts))
    return times, parts, results


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--repeat", type=int, default=3, help="steady-state calls (default 3)")
    p.add_argument("--first", choices=tuple(TASKS), help=argparse_hidden())
    a = p.parse_args(argv)
    ins = instability()
    if a.first:
        t = time.perf_counter()
        TASKS[a.first](ins, a.quick)
        print(json.dumps({"seconds": time.perf_counter() - t}))
        return
    repeat = 1 if a.quick else a.repeat
    affinity = sorted(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else []
    print(f"cores {affinity}, load average {os.getloadavg()[0]:.2f}")
    header = ["task", "first_call_s", "median_s", "min_s", "max_s", "runs", "points",
              "evaluations", *(f"{k}_s" for k in BREAKDOWN), "other_s", "stop"]
    rows = []
    for task, label in (("setup", "Fourier2D + critical_point + koiter"),
                        ("branch", "follow_bifurcation, lobed branch"
                                   + (f" ({QUICK_STEPS} points)" if a.quick else ""))):
        first = first_call(task, a.quick)
        times, parts, results = steady(task, ins, repeat, a.quick)
        i = sorted(range(len(times)), key=times.__getitem__)[len(times) // 2]
        spent, counts = parts[i]
        r = results[i]
        points = len(r.p) if task == "branch" else ""
        stop = r.stop if task == "branch" else ""
        measured = spent.get("hessian", 0.0) + spent.get("parameter_gradient", 0.0) + \
            spent.get("lu", 0.0)
        rows.append([label, first, statistics.median(times), min(times), max(times),
                     len(times), points, counts.get("evaluations", ""),
                     *(spent.get(k, 0.0) for k in BREAKDOWN), times[i] - measured, stop])
        print(f"{label}: first call {first:.2f} s, median {statistics.median(times):.2f} s "
              f"(min {min(times):.2f}, max {max(times):.2f}, {len(times)} runs)"
              + (f", {points} points, {counts.get('evaluations')} evaluations" if points
                 else ""))
        print("   " + ", ".join(f"{k} {spent.get(k, 0.0):.2f} s" for k in BREAKDOWN)
              + f", other {times[i] - measured:.2f} s" + (f"; stop: {stop}" if stop else ""))
    write_csv(a.out / "bench_postbuckling.csv", header, rows)
    print(f"wrote {a.out / 'bench_postbuckling.csv'}")


def argparse_hidden():
    import argparse

    return argparse.SUPPRESS


if __name__ == "__main__":
    main()
