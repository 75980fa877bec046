"""Benchmark: one snap curvature kappa_s beside AUTO-07p, timed in the same run, and start-up.

Cap: Theta = pi/6, h0/R0 = 0.01, lam = 1, Ciarlet-Geymonat, relaxed and plane strain.
The peer is AUTO-07p on the same equations (the executables of this cap model in
the folder ``$SHELLBVP_AUTO07P``, default ``shared/peers/auto07p`` beside the checkout, with
its runner ``run_auto.py`` and ``bin/``: analytic
Jacobians, NCOL = 4, pseudo-arclength from kappa = 0 to the first limit point). For every
model and accuracy class tol in {1e-6, 1e-8, 1e-10, 1e-12}:

* shellbvp: ``snap_curvature(..., tol=tol)`` in steady state (after one call to compile),
  twice per round: the first call (the figure of merit) after AUTO's process and the other
  rows, the second straight after it (warm: the caches hold its programs, as in a sweep);
* AUTO-07p: the whole process (start, read its constants, continue, write its files; AUTO
  has no warm-up) at the smallest NTST of ``NTST_CANDIDATES`` whose error is at most tol
  (NTST 8 / 10 / 20 / 40 relaxed here), errors against the same reference;

alternating, one call of each per round over all rows, so that the machine's slow spells
fall on both; the medians' ratio is the figure of merit (absolute times differ by 1.5x
between machines of one kind), with its 95 % bootstrap interval over the rounds: the goal
is "met" where the whole interval is at most 0.5, "missed" where it is all above, and
"within noise" where it straddles 0.5. The reference is shellbvp at tol 1e-12 on degrees
from 56 up, which no timed row uses; AUTO at NTST 40 agrees with it to ~2e-13.

Start-up: the whole command ``shellbvp snap --model M`` in fresh processes, each with an
empty cache folder (cold: tracing and XLA compilation; the symbolic derivation ships with
the package), and again with one filled (warm), ``STARTUP_RUNS`` of each, and the time of
each phase in a cold and a warm process.

Pinned to one core (sched_setaffinity, inherited by AUTO's process; single-threaded BLAS,
XLA and OpenMP). Writes bench_snap.csv, bench_snap_breakdown.csv (where the steady-state
time goes: compiled kernel, LU, host work; :func:`breakdown`), bench_snap_kernel.csv (the
kernel's calls replayed: :func:`kernel_anatomy`), bench_snap_host.csv (one Newton iteration
layer by layer: :func:`host_layers`), bench_snap_pause.csv (one call after a pause of the
process: :func:`after_pause`), bench_snap_matched.csv (AUTO-07p at the accuracy each
shellbvp call delivers: :func:`matched`), bench_snap_startup.csv, bench_snap_fig3.csv and
bench_snap.png. Where AUTO-07p or its runtime libraries are
missing, says how to install them and times shellbvp alone.

    python figures/bench_snap.py [--quick] [--repeats 11] [--no-startup] [--no-fig3]
"""

from __future__ import annotations

import os

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("MKL_NUM_THREADS", "1")
os.environ.setdefault("XLA_FLAGS", "--xla_cpu_multi_thread_eigen=false "
                                   "intra_op_parallelism_threads=1")
try:
    os.sched_setaffinity(0, {max(os.sched_getaffinity(0))})
except (AttributeError, OSError):   # not Linux: run unpinned, say so below
    pass

import importlib.util  # noqa: E402
import math  # noqa: E402
import shutil  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from _common import HERE, clock, finish, parser, pyplot, wall_times, write_csv  # noqa: E402

THETA, H0, LAM = math.pi / 6, 0.01, 1.0
MODELS = ("relaxed", "plane_strain")
TOLS = (1e-6, 1e-8, 1e-10, 1e-12)
REFERENCE_TOL = 1e-12
#: the reference fold is located on degrees from 56 up, which none of the timed rows uses
REFERENCE_NODES = 56
#: AUTO-07p's meshes tried per accuracy class (the smallest whose error meets tol is timed;
#: its error is not monotone in NTST: the adaptive mesh moves)
NTST_CANDIDATES = (6, 7, 8, 9, 10, 12, 14, 16, 20, 24, 30, 40)
#: the goal of the speed issue: shellbvp's median at most this fraction of AUTO's
GOAL = 0.5
#: the interval of a ratio of medians: this central fraction of its bootstrap over the
#: rounds, each round resampled whole (shellbvp's and AUTO's calls of one round together)
LEVEL, RESAMPLES = 0.95, 4000
#: fresh processes per model and cache state in the start-up timings (one with --quick)
STARTUP_RUNS = 3
INSTALL = ("AUTO-07p's runtime libraries: apt-get install -y libgfortran5 libgomp1 "
           "(Debian/Ubuntu); the executables: set SHELLBVP_AUTO07P to the folder holding "
           "run_auto.py and bin/")


def auto_runner():
    """The AUTO-07p runner module, or (None, why) where it or its libraries are missing."""
    folder = Path(os.environ.get("SHELLBVP_AUTO07P",
                                 HERE.parent.parent / "shared" / "peers" / "auto07p"))
    path = folder / "run_auto.py"
    if not path.exists():
        return None, f"no AUTO-07p runner at {path}"
    spec = importlib.util.spec_from_file_location("run_auto", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    probe = mod.run("relaxed", theta=THETA, lam=LAM, h=H0, ntst=10)
    if not probe.get("ok"):
        return None, f"AUTO-07p did not run ({probe.get('tail', '')[-200:].strip()!r})"
    return mod, ""


def auto_errors(auto, refs):
    """{(model, ntst): AUTO-07p's error in kappa_s against the reference} for every NTST of
    NTST_CANDIDATES (inf where AUTO failed)."""
    errors = {}
    for model in MODELS:
        for ntst in NTST_CANDIDATES:
            r = auto.run(model, theta=THETA, lam=LAM, h=H0, ntst=ntst)
            errors[model, ntst] = abs(r["kappa_s"] - refs[model].kappa_s) if r["ok"] \
                else math.inf
    return errors


def auto_meshes(errors, bounds):
    """{(model, tol): (ntst, error)}: per row the smallest NTST of NTST_CANDIDATES whose error
    (:func:`auto_errors`) is at most ``bounds[model, tol]``: the accuracy class tol itself,
    or the error a shellbvp call delivers (:func:`matched`)."""
    chosen = {}
    for (model, tol), bound in bounds.items():
        ntst = next((n for n in NTST_CANDIDATES if errors[model, n] <= bound), None)
        chosen[model, tol] = (ntst, errors.get((model, ntst), math.nan))
    return chosen


def matched(auto, errors, delivered, repeats):
    """Rows of bench_snap_matched.csv: each row of the side-by-side against AUTO-07p at the
    smallest NTST whose error is at most the error that row's shellbvp call delivers, timed
    in a second alternating pass (:func:`side_by_side`). tol is what the error estimate
    promises, and the delivered error is often far below it (~1e-10 at tol 1e-6 here): this
    compares the two at the same accuracy (work against precision), beside the figure of
    merit, which compares them at the same accuracy class. A row more accurate than every
    NTST tried has no peer (empty NTST and ratio)."""
    meshes = auto_meshes(errors, delivered)
    rows = [row for row in delivered if meshes[row][0] is not None]
    timed = side_by_side(rows, repeats, auto, meshes)
    out = []
    for row in delivered:
        ntst, auto_err = meshes[row]
        if ntst is None:
            out.append([*row, delivered[row], "", math.nan, math.nan, math.nan, math.nan,
                        math.nan, math.nan, f"no NTST <= {NTST_CANDIDATES[-1]} as accurate"])
            continue
        ours, _, peer, _ = timed[row]
        low, high = ratio_interval(ours, peer)
        ms, auto_ms = 1e3 * float(np.median(ours)), 1e3 * float(np.median(peer))
        out.append([*row, delivered[row], ntst, auto_err, ms, auto_ms, ms / auto_ms, low,
                    high, verdict(low, high)])
    return out


def ratio_interval(ours, peer, level=LEVEL, resamples=RESAMPLES, seed=0):
    """(low, high): the central ``level`` interval of median(ours) / median(peer) under the
    bootstrap of the rounds (a round's two times drawn together: they shared the machine's
    spell). Deterministic (``seed``)."""
    ours, peer = np.asarray(ours, float), np.asarray(peer, float)
    idx = np.random.default_rng(seed).integers(0, ours.size, (resamples, ours.size))
    ratios = np.median(ours[idx], axis=1) / np.median(peer[idx], axis=1)
    tail = 50.0 * (1.0 - level)
    return tuple(float(x) for x in np.percentile(ratios, [tail, 100.0 - tail]))


def verdict(low, high, goal=GOAL) -> str:
    """'met' where the whole interval of the ratio is at most ``goal``, 'missed' where it is
    all above, 'within noise' where it straddles the goal (the rounds cannot tell)."""
    if not (math.isfinite(low) and math.isfinite(high)):
        return ""
    return "met" if high <= goal else "missed" if low > goal else "within noise"


def side_by_side(rows, repeats, auto, meshes):
    """{(model, tol): (shellbvp times, its warm times, AUTO times, last result)}: per round
    and row, shellbvp, then AUTO, alternating, after one shellbvp call per row to compile.
    The first are the figure of merit: each call follows AUTO's process and another row's
    programs, which have taken the processor's caches. The warm times are a second call
    straight after the first, as in a loop of kappa_s (a sweep): the same work with the
    caches holding its own programs and data."""
    from shellbvp.problems import cap_eversion as ce

    for model, tol in rows:
        ce.snap_curvature(THETA, H0, LAM, model=model, tol=tol)
    ours = {row: [] for row in rows}
    warm = {row: [] for row in rows}
    peer = {row: [] for row in rows}
    last = {}
    for _ in range(repeats):
        for model, tol in rows:
            for times in (ours, warm):
                t = time.perf_counter()
                last[model, tol] = ce.snap_curvature(THETA, H0, LAM, model=model, tol=tol)
                times[model, tol].append(time.perf_counter() - t)
            ntst = meshes.get((model, tol), (None,))[0]     # none without AUTO
            if ntst is not None:
                r = auto.run(model, theta=THETA, lam=LAM, h=H0, ntst=ntst)
                peer[model, tol].append(r["wall_s"] if r["ok"] else math.nan)
    return {row: (np.array(ours[row]), np.array(warm[row]), np.array(peer[row]), last[row])
            for row in rows}


def breakdown(rows, repeats):
    """{(model, tol): (total, kernel, LU) medians in ms per kappa_s}: where the steady-state
    time of one kappa_s goes, in separate rounds (the clocks around the calls cost a few us
    each, so the side-by-side rows are timed without them). Kernel: every call of a compiled
    program (:class:`shellbvp.packed.Packed`: the packing of its arguments, XLA's run and
    the unpacking); LU: every factorisation of a bordered matrix (LAPACK dgetrf, with the
    copy into the bordered matrix); the rest is host work in Python and numpy (assembly,
    Newton, continuation and fold bookkeeping)."""
    from shellbvp import packed
    from shellbvp.problems import cap_eversion as ce

    # the module (the package shellbvp.continuation exports its function of the same name)
    newton_module = importlib.import_module("shellbvp.continuation.newton")
    spent = {"kernel": 0.0, "LU": 0.0}
    kept = [(packed.Packed, "__call__", clock(packed.Packed, "__call__", spent, "kernel")),
            (newton_module, "bordered_lu", clock(newton_module, "bordered_lu", spent, "LU"))]
    try:
        out = {}
        for model, tol in rows:
            samples = []
            for _ in range(repeats):
                spent.update(kernel=0.0, LU=0.0)
                t = time.perf_counter()
                ce.snap_curvature(THETA, H0, LAM, model=model, tol=tol)
                samples.append((time.perf_counter() - t, spent["kernel"], spent["LU"]))
            out[model, tol] = tuple(1e3 * float(np.median(x)) for x in zip(*samples))
        return out
    finally:
        for owner, name, f in kept:
            setattr(owner, name, f)


def median_us(f, repeats, warmup):
    """Median wall time of f() in us over ``repeats`` calls after ``warmup``."""
    return 1e6 * float(np.median(wall_times(f, repeats, warmup=warmup)))


def packed_calls(run):
    """[(program, args, outputs)]: every call of a compiled program
    (:class:`shellbvp.packed.Packed`) that ``run()`` makes, recorded for replay."""
    from shellbvp import packed

    calls = []
    original = packed.Packed.__call__

    def recording(self, *args):
        out = original(self, *args)
        calls.append((self, args, out))
        return out

    packed.Packed.__call__ = recording
    try:
        run()
    finally:
        packed.Packed.__call__ = original
    return calls


#: the argument of the collocation program that starts the inner (lam1, k1) Newton at every
#: node (:meth:`shellbvp.bvp.ShellBVP.collocate`), and where its roots come back
INNER_START, NODAL_OUT, ROOTS = 7, 0, 5


def kernel_anatomy(tol=1e-8, repeats=50):
    """{model: (calls, as recorded ms, exact start ms, trivial us)}: the kernel calls of one
    kappa_s replayed in steady state (medians of ``repeats`` per call), as recorded and
    with the inner Newton started at its own roots (one inner step at every node: the
    difference is the cost of the further inner steps), and a trivial compiled program
    with the same input and output sizes (what calling XLA costs at all)."""
    import jax
    import jax.numpy as jnp

    from shellbvp.problems import cap_eversion as ce

    out = {}
    for model in MODELS:
        ce.snap_curvature(THETA, H0, LAM, model=model, tol=tol)
        calls = packed_calls(lambda: ce.snap_curvature(THETA, H0, LAM, model=model, tol=tol))
        recorded = exact = 0.0
        for owner, args, res in calls:
            at_roots = list(args)
            at_roots[INNER_START] = np.array(res[NODAL_OUT][ROOTS])
            recorded += median_us(lambda: owner(*args), repeats, 5)
            exact += median_us(lambda: owner(*at_roots), repeats, 5)
        owner, args, res = calls[0]
        n_in = sum(np.size(x) for x in args)
        n_out = sum(np.size(x) for x in jax.tree_util.tree_leaves(res))
        trivial = jax.jit(lambda x: jnp.zeros(n_out) + x[0]).lower(
            jax.ShapeDtypeStruct((n_in,), np.float64)).compile()
        x = np.zeros(n_in)
        out[model] = (len(calls), 1e-3 * recorded, 1e-3 * exact,
                      median_us(lambda: np.asarray(trivial(x)), repeats, 5))
    return out


#: what runs between two shellbvp calls in :func:`after_pause` (AUTO's process is added
#: where it runs): the calls back to back, a trivial process, and the process off the core
PAUSES = (("back to back", lambda: None),
          ("/bin/true", lambda: subprocess.run(["/bin/true"], check=False)),
          ("sleep 20 ms", lambda: time.sleep(0.02)),
          ("sleep 100 ms", lambda: time.sleep(0.1)))
#: the accuracy class of those calls
PAUSE_TOL = 1e-6


def after_pause(auto, meshes, tol=PAUSE_TOL, repeats=15):
    """{(model, what ran before): median ms of one kappa_s at ``tol``}: why the first call
    of a round is slower than the warm one. Per round and model, one call after each of
    ``PAUSES`` and after AUTO's process at the row's NTST, in turn: if a pause alone
    (nothing else on the core) costs as much as AUTO's process, the first call's penalty is
    the processor's caches and predictors refilled after the process was off the core, not
    AUTO's use of them."""
    from shellbvp.problems import cap_eversion as ce

    times = {}
    for model in MODELS:
        ntst = meshes.get((model, tol), (None,))[0]
        befores = list(PAUSES)
        if ntst is not None:
            befores.append(("AUTO-07p process", lambda: auto.run(
                model, theta=THETA, lam=LAM, h=H0, ntst=ntst)))
        for what, _ in befores:
            times[model, what] = []
        ce.snap_curvature(THETA, H0, LAM, model=model, tol=tol)
        for _ in range(repeats):
            for what, pause in befores:
                pause()
                t = time.perf_counter()
                ce.snap_curvature(THETA, H0, LAM, model=model, tol=tol)
                times[model, what].append(time.perf_counter() - t)
    return {k: 1e3 * float(np.median(v)) for k, v in times.items()}


def host_layers(nodes=(20, 32), repeats=200):
    """{(model, N): {layer: us}}: one Newton iteration at the default cap's fold on degree
    N, replayed in steady state (medians of ``repeats``), timed layer by layer from the
    inside out: the compiled program alone on its packed vector (``program``), its call
    with the packing of the arguments and unpacking of the outputs (``Packed``), the BVP's
    collocation call (warm start of the inner Newton, admissibility checks, nodal arrays:
    ``collocate``), the discrete system's evaluation (collocation blocks, assembly of R, J,
    dR/dp: ``evaluate``), the bordered LU alone (``LU``) and the whole iteration
    (``newton``: evaluation, LU, solve and the iteration's bookkeeping). Their differences
    are the host work of each layer."""
    from shellbvp.methods.chebyshev import ChebyshevSystem
    from shellbvp.problems import cap_eversion as ce

    newton_module = importlib.import_module("shellbvp.continuation.newton")
    out = {}
    for model in MODELS:
        fold = ce.snap_curvature(THETA, H0, LAM, model=model, tol=1e-8).fold
        for N in nodes:
            system = ChebyshevSystem(fold.system.bvp, N)
            res = newton_module.newton(system, fold.system.transfer(fold.U, fold.p, system),
                                       fold.p, 1.0, 0.0, fold.monitor, tol=1e-12)
            U, p, m = res.U, res.p, res.m
            Y, bvp = system.states(U), system.bvp
            owner, args, _ = packed_calls(
                lambda: bvp.collocate(system.s, Y, p, system._hint))[-1]
            program, _, _, flat = owner.prepare(*args)
            R, J, Rp = system.evaluate(U, p)
            _, gm = system.monitor(U)

            def median(f):
                return median_us(f, repeats, 20)

            out[model, N] = {
                "program": median(lambda: np.asarray(program(flat))),
                "Packed": median(lambda: owner(*args)),
                "collocate": median(lambda: bvp.collocate(system.s, Y, p, system._hint)),
                "evaluate": median(lambda: system.evaluate(U, p)),
                "LU": median(lambda: newton_module.bordered_lu(J, Rp, gm, 0.0)),
                # a tolerance the first update meets: one evaluation, one LU
                "newton": median(lambda: newton_module.newton(system, U, p, 1.0, 0.0, m,
                                                              tol=1e-3))}
    return out


def _command():
    exe = shutil.which("shellbvp")
    return [exe] if exe else [sys.executable, "-m", "shellbvp.cli"]


def startup(model, cache_dir):
    """Wall time (s) of the whole command in a fresh process, and its kappa_s line."""
    env = dict(os.environ, SHELLBVP_CACHE_DIR=str(cache_dir))
    t = time.perf_counter()
    out = subprocess.run(_command() + ["snap", "--model", model], env=env, check=True,
                         capture_output=True, text=True)
    wall = time.perf_counter() - t
    line = next((x for x in out.stdout.splitlines() if x.startswith("kappa_s")), "")
    return wall, line


#: the child process of :func:`phases`: times each phase with wall clocks around the
#: functions that hold it (the symbolic work: derivation and code generation, or the
#: generated source read back; tracing: jax.export, or the exported program read back;
#: lowering and XLA compilation, or the compiled program loaded from JAX's cache: the
#: program phases are nested)
PHASE_SCRIPT = """
import sys, time
t = time.perf_counter()
import jax
spent = {"import jax": time.perf_counter() - t}
t = time.perf_counter()
import shellbvp, shellbvp.cli, shellbvp.codegen as G, shellbvp.packed as P
spent["import shellbvp"] = time.perf_counter() - t
sys.path.insert(0, sys.argv[2])
from _common import clock

clock(G, "_functions", spent, "generated code (shipped, or derived by sympy)")
clock(P.Packed, "_exported", spent, "tracing (jax.export)")
clock(P.Packed, "_program", spent, "tracing, lowering + XLA compilation (or cache load)")
t = time.perf_counter()
try:
    shellbvp.cli.main(["snap", "--model", sys.argv[1]])
except SystemExit:
    pass
spent["the whole snap command"] = time.perf_counter() - t
for k, v in spent.items():
    print("PHASE", v, k)
"""


def phases(model, cache_dir):
    """{phase: seconds} of ``shellbvp snap`` in a fresh process (:data:`PHASE_SCRIPT`; the
    program phases are nested in the command's), and the process' wall time."""
    env = dict(os.environ, SHELLBVP_CACHE_DIR=str(cache_dir))
    t = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", PHASE_SCRIPT, model, str(HERE)], env=env,
                         check=True, capture_output=True, text=True).stdout
    total = time.perf_counter() - t
    shares = {}
    for line in out.splitlines():
        if line.startswith("PHASE"):
            _, seconds, name = line.split(" ", 2)
            shares[name] = float(seconds)
    return shares, total


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
    p.add_argument("--repeats", type=int, default=11, help="rounds per row (default 11)")
    p.add_argument("--no-startup", action="store_true", help="skip the fresh-process timings")
    p.add_argument("--no-fig3", action="store_true", help="skip the Fig. 3 set")
    a = p.parse_args(argv)
    repeats = 3 if a.quick else a.repeats
    tols = (1e-6, 1e-10) if a.quick else TOLS
    from shellbvp import Chebyshev
    from shellbvp.problems import cap_eversion as ce

    pinned = len(os.sched_getaffinity(0)) == 1 if hasattr(os, "sched_getaffinity") else False
    print(f"one core pinned: {pinned}; median of {repeats} rounds per row")
    refs = {}
    for model in MODELS:
        refs[model] = ref = ce.snap_curvature(THETA, H0, LAM, model=model, tol=REFERENCE_TOL,
                                              method=Chebyshev(nodes=REFERENCE_NODES))
        print(f"{model}: reference kappa_s R0 = {ref.kappa_s!r} (estimate "
              f"{ref.error_estimate:.1e}, N = {ref.stats['fold']['resolution']['nodes']})")
    auto, why = auto_runner()
    if auto is None:
        print(f"AUTO-07p skipped: {why}. {INSTALL}")
        meshes = {}
    else:
        errors = auto_errors(auto, refs)
        meshes = auto_meshes(errors, {(m, t): t for m in MODELS for t in tols})
    timed = side_by_side([(m, t) for m in MODELS for t in tols], repeats, auto, meshes)
    rows = []
    for model in MODELS:
        print(model)
        for tol in tols:
            ours, warm, peer, r = timed[model, tol]
            ntst, auto_err = meshes.get((model, tol), (None, math.nan))
            err = abs(r.kappa_s - refs[model].kappa_s)
            ms, warm_ms, auto_ms = 1e3 * float(np.median(ours)), 1e3 * float(np.median(warm)), \
                (1e3 * float(np.median(peer)) if peer.size else math.nan)
            ratio = ms / auto_ms
            low, high = ratio_interval(ours, peer) if peer.size else (math.nan, math.nan)
            rows.append([model, tol, ms, 1e3 * ours.min(), 1e3 * ours.max(), r.error_estimate,
                         err, r.stats["fold"]["resolution"]["nodes"], r.stats["evaluations"],
                         ntst if ntst else "", auto_ms, auto_err, ratio, verdict(low, high),
                         repeats, r.kappa_s, warm_ms, warm_ms / auto_ms, low, high])
            print(f"  tol {tol:.0e}: shellbvp {ms:6.1f} ms (warm {warm_ms:4.1f}), error "
                  f"{err:.1e} (estimate {r.error_estimate:.1e}), N = {rows[-1][7]}, "
                  f"{rows[-1][8]} evaluations | AUTO-07p NTST {ntst}: {auto_ms:6.1f} ms, "
                  f"error {auto_err:.1e} | ratio {ratio:.2f} ({low:.2f}-{high:.2f}: "
                  f"{rows[-1][13] or 'no peer'}; warm {warm_ms / auto_ms:.2f})")
    if auto is not None:
        mrows = matched(auto, errors, {(row[0], row[1]): row[6] for row in rows}, repeats)
        print("at the same accuracy: AUTO-07p at the smallest NTST whose error is at most "
              "the error shellbvp delivers (second pass)")
        for row in mrows:
            head = f"  {row[0]:>12s} tol {row[1]:.0e}: shellbvp error {row[2]:.1e}"
            if row[3] == "":
                print(f"{head} | AUTO-07p: {row[10]}")
                continue
            print(f"{head}, {row[5]:5.1f} ms | AUTO NTST {row[3]} error {row[4]:.1e}, "
                  f"{row[6]:5.1f} ms | ratio {row[7]:.2f} ({row[8]:.2f}-{row[9]:.2f}: "
                  f"{row[10]})")
        write_csv(a.out / "bench_snap_matched.csv",
                  ["model", "tol", "error_vs_reference", "auto_ntst", "auto_error_vs_reference",
                   "median_ms", "auto_median_ms", "ratio", "ratio_low", "ratio_high",
                   "goal_0.5"], mrows)
    parts = breakdown([(m, t) for m in MODELS for t in tols], repeats)
    brows = []
    print("where the time of one kappa_s goes (ms, medians; the floor is kernel + LU, "
          "over AUTO-07p's time)")
    for row in rows:
        total, kernel, lu = parts[row[0], row[1]]
        floor = (kernel + lu) / row[10]
        brows.append([row[0], row[1], total, kernel, lu, total - kernel - lu, row[10], floor])
        print(f"  {row[0]:>12s} tol {row[1]:.0e}: {total:5.1f} = kernel {kernel:4.1f} + LU "
              f"{lu:4.1f} + host {total - kernel - lu:4.1f}; floor / AUTO {floor:.2f}")
    anatomy = kernel_anatomy(repeats=20 if a.quick else 50)
    print("the kernel calls of one kappa_s at tol 1e-8, replayed (ms; medians per call)")
    arows = []
    for model, (calls, recorded, exact, trivial) in anatomy.items():
        arows.append([model, 1e-8, calls, recorded, exact, recorded - exact,
                      1e3 * exact / calls, trivial])
        print(f"  {model:>12s}: {calls} calls, {recorded:.2f} as recorded, {exact:.2f} with "
              f"the inner Newton started at its roots (further inner steps "
              f"{recorded - exact:.2f}); {1e3 * exact / calls:.0f} us a call at its roots; "
              f"a trivial program of the same sizes {trivial:.0f} us")
    layers = host_layers(repeats=50 if a.quick else 200)
    print("one Newton iteration at the fold, layer by layer (us, medians; the host work of "
          "a layer is its time less the layer inside it)")
    lrows = []
    for (model, N), t in layers.items():
        host = {"Packed": t["Packed"] - t["program"],
                "collocate": t["collocate"] - t["Packed"],
                "evaluate": t["evaluate"] - t["collocate"],
                "newton": t["newton"] - t["evaluate"] - t["LU"]}
        lrows.append([model, N, t["program"], t["LU"], host["Packed"], host["collocate"],
                      host["evaluate"], host["newton"], t["newton"]])
        print(f"  {model:>12s} N = {N}: {t['newton']:.0f} = program {t['program']:.0f} + LU "
              f"{t['LU']:.0f} + host " + " + ".join(f"{k} {v:.0f}" for k, v in host.items()))
    paused = after_pause(auto, meshes, repeats=5 if a.quick else 15)
    print(f"one kappa_s at tol {PAUSE_TOL:.0e} after a pause (ms, medians): what the first "
          f"call's penalty is")
    prow = []
    for (model, what), ms in paused.items():
        base = paused[model, "back to back"]
        prow.append([model, PAUSE_TOL, what, ms, ms / base])
        print(f"  {model:>12s} after {what:>16s}: {ms:5.2f} ({ms / base:.2f}x back to back)")
    write_csv(a.out / "bench_snap_pause.csv",
              ["model", "tol", "before", "median_ms", "over_back_to_back"], prow)
    write_csv(a.out / "bench_snap_host.csv",
              ["model", "nodes", "program_us", "lu_us", "packed_host_us", "collocate_host_us",
               "evaluate_host_us", "newton_host_us", "iteration_us"], lrows)
    write_csv(a.out / "bench_snap_kernel.csv",
              ["model", "tol", "calls", "recorded_ms", "exact_start_ms", "further_inner_ms",
               "exact_start_us_per_call", "trivial_program_us"], arows)
    write_csv(a.out / "bench_snap_breakdown.csv",
              ["model", "tol", "total_ms", "kernel_ms", "lu_ms", "host_ms", "auto_median_ms",
               "floor_ratio"], brows)
    write_csv(a.out / "bench_snap.csv",
              ["model", "tol", "median_ms", "min_ms", "max_ms", "error_estimate",
               "error_vs_reference", "final_nodes", "evaluations", "auto_ntst",
               "auto_median_ms", "auto_error_vs_reference", "ratio", "goal_0.5", "rounds",
               "kappa_s_R0", "warm_median_ms", "warm_ratio", "ratio_low", "ratio_high"], rows)

    if not a.no_startup:
        srows = []
        runs = 1 if a.quick else STARTUP_RUNS
        for model in MODELS:
            walls = {"cold": [], "warm": []}
            for _ in range(runs):   # each cold process with an empty cache folder of its own
                with tempfile.TemporaryDirectory() as d:
                    wall, line = startup(model, d)
                    walls["cold"].append(wall)
            with tempfile.TemporaryDirectory() as d:      # warm: a folder filled once
                startup(model, d)
                for _ in range(runs):
                    wall, line = startup(model, d)
                    walls["warm"].append(wall)
            for cache, w in walls.items():
                srows += [[model, cache, "command", x] for x in w]
                print(f"start-up {model:>12s}, {cache} cache: median {np.median(w):5.1f} s of "
                      f"{len(w)} processes ({min(w):.1f}-{max(w):.1f} s)  ({line})")
            for cache in ("cold", "warm"):
                with tempfile.TemporaryDirectory() as d:
                    if cache == "warm":
                        startup(model, d)
                    shares, total = phases(model, d)
                print(f"  {cache} process, phases: {total:.1f} s in all; " + "; ".join(
                    f"{k} {v:.2f} s" for k, v in shares.items()))
                srows += [[model, cache, k, v] for k, v in shares.items()]
        write_csv(a.out / "bench_snap_startup.csv", ["model", "cache", "phase", "seconds"],
                  srows)

    if not a.no_fig3:
        write_csv(a.out / "bench_snap_fig3.csv",
                  ["lam", "caps", "along_fold_curve_s", "restarts_s", "caps_along_fold_curve",
                   "max_abs_difference"], fig3_set(quick=a.quick))

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.2))
    # the tol labels of the first model to the right of its points, of the second (the
    # faster, so further left) to the left of its own: where errors match they would overlap
    for model, color, side in zip(MODELS, ("C0", "C1"), (1, -1)):
        sel = [r for r in rows if r[0] == model]
        ax.loglog([r[2] for r in sel], [max(r[6], 1e-16) for r in sel], "o-", color=color,
                  label=f"shellbvp, {model} (error)")
        ax.loglog([r[2] for r in sel], [max(r[5], 1e-16) for r in sel], "s:", color=color,
                  mfc="none", label=f"shellbvp, {model} (estimate)")
        for r in sel:
            ax.annotate(f"tol {r[1]:.0e}", (r[2], max(r[6], 1e-16)), fontsize=6,
                        xytext=(4 * side, -8), textcoords="offset points",
                        ha="left" if side > 0 else "right")
        peer = [r for r in sel if math.isfinite(r[10])]
        if peer:
            ax.loglog([r[10] for r in peer], [max(r[11], 1e-16) for r in peer], "x--",
                      color=color, ms=8, mew=2, label=f"AUTO-07p, same run, {model}")
            for r in peer:
                ax.annotate(f"NTST {r[9]}", (r[10], max(r[11], 1e-16)), fontsize=6,
                            xytext=(3, 3), textcoords="offset points")
    # room on the left for the second model's labels
    ax.set_xlim(left=0.75 * min(r[2] for r in rows))
    ax.set_xlabel("wall time per kappa_s [ms] (one pinned core, median)")
    ax.set_ylabel("|kappa_s R0 error|")
    ax.set_title("Theta = pi/6, h0/R0 = 0.01, lam = 1, CG: shellbvp (steady state) and "
                 "AUTO-07p (whole process)", fontsize=8)
    ax.legend(fontsize=6.5, loc="upper right")
    finish(fig, a.out, "bench_snap")


if __name__ == "__main__":
    main()
