"""The ``shellbvp`` command line: any shell of revolution written as a scene file (its
branch, first instability and post-buckling), and the paper's everting caps built in (snap
curvature, continuation diagrams, sweeps, stability and post-buckling).

    shellbvp follow FILE [--csv OUT.csv] [--vtk DIR] [--json] [--at P1,P2,...]
    shellbvp stability FILE [--json]
    shellbvp postbuckling FILE [--n-folds 1] [--p-min P] [--p-max P] [--csv OUT.csv] [--vtk DIR]
    shellbvp snap   --theta 0.5236 --h 0.01 --lam 1 --model relaxed
    shellbvp branch --theta 0.5236 --h 0.01 --lam 1 --csv branch.csv
    shellbvp sweep  --T 2:10:0.25 --h 0.01 --lam 1 --csv sweep.csv [--jobs 2] [--resume]
    shellbvp stability --theta 0.5236 --h 0.01 --lam 1 [--json]
    shellbvp postbuckling --theta 0.5236 --h 0.01 --lam 1 [--K 2] [--csv lobed.csv]
    shellbvp --version

``--vtk DIR`` writes every point of the branch (``follow``) or of the lobed branch
(``postbuckling``) as a ParaView file in DIR with their collection (``branch.pvd``,
``lobed.pvd``; :mod:`shellbvp.paraview`), in the scene file's units. Long runs show their
progress on stderr (the parameter reached, the points, the folds passed: tqdm), only when
stderr is a terminal and not with ``--quiet``; standard output (``--json``) never holds it.

FILE is a scene file (TOML, :mod:`shellbvp.scenefile`), or the name of an example installed
with the package (``shellbvp follow everting-cap``; :func:`shellbvp.scenefile.examples`).
``--json`` prints one JSON object instead of the text: ``follow`` ``{"folds": [...],
"at": [...], "last": {...}, "stop", "complete", "missing"}``, each point ``{"p", "p_error",
<observable>, <observable>_error}`` (every value with its error estimate; ``at``: the states
at the values of ``--at`` or the file's ``[parameter] at``; ``complete`` false and exit
status 1 where the continuation stalled, the points before it reported), ``stability``
``{"kind", "n", "p", "error_estimate"}`` (and ``"stop"`` for none), in the file's units
(null for what is undefined).

``postbuckling`` finds the first instability as ``stability`` does; a fold (or none) has no
bifurcation to follow and is printed as such. At a bifurcation into n waves it prints the
bifurcation located again in the discretisation of the lobed states
(:func:`shellbvp.follow_bifurcation`: harmonics 0, n, ..., K n), Koiter's p2 and b and
whether it is sub- or supercritical, the folds of the branch of n-lobed equilibria followed
from it (to the ``--n-folds``-th, or a bound: ``--p-min``/``--p-max``, for a cap also
spelled ``--kappa-min``/``--kappa-max``, by default kappa >= 0 for a cap, where its branch
starts, and a scene file's range from ``from`` to ``to``; ``--amplitude-max``), why it
stopped, and the snap (the bifurcation when subcritical, else the lobed branch's first
fold). ``--csv`` writes the lobed branch: the parameter, the critical mode's amplitude and
each harmonic's norm per point.

Bad arguments or a bad scene file exit with code 2 and one line on stderr (a file's line
starts with its key); a solver failure exits with 1. A
sweep never stops on one cap: every cap gets a row (status ok / no snap / failed, and the
reason), it prints a summary and exits 0 when every cap is ok or does not snap, 1 when some
failed (the CSV complete all the same). Ctrl-C or SIGTERM stops it with one line and exit
code 130, leaving the finished caps in the CSV (marked incomplete) and in its journal, from
which ``--resume`` continues.
"""

from __future__ import annotations

import argparse
import gc
import json
import math
import signal
import sys
from pathlib import Path

import numpy as np

from .harmonics import DEGREE as HARMONICS_DEGREE
from .postbuckling import DEGREE_STEP
from .sweep import CHUNK_SIZE


def _range(text):
    try:
        a, b, step = (float(v) for v in text.split(":"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected START:STOP:STEP, got {text!r}") from None
    if not (step > 0 and b >= a > 0):
        raise argparse.ArgumentTypeError(f"need 0 < START <= STOP and STEP > 0, got {text!r}")
    return np.arange(a, b + 0.5 * step, step)


def _common(p, theta=True, method=True):
    if theta:
        p.add_argument("--theta", type=float, default=math.pi / 6,
                       help="opening half-angle Theta in radians, in (0, pi) (default pi/6)")
    p.add_argument("--h", type=float, default=0.01, help="thickness h0/R0 in (0, 1) (default 0.01)")
    p.add_argument("--lam", type=float, default=1.0,
                   help="lambda*/mu* > 0, material cg only (default 1)")
    p.add_argument("--model", default="relaxed", choices=["plane_strain", "relaxed"],
                   help="reduced model, material cg only (default relaxed)")
    p.add_argument("--material", default="cg", choices=["cg", "nh", "koiter"])
    p.add_argument("--nu", type=float, default=0.5,
                   help="Poisson ratio, material koiter only (default 0.5)")
    p.add_argument("--tol", type=float, default=1e-9,
                   help="target accuracy of kappa_s, in (0, 1) (default 1e-9)")
    if method:
        p.add_argument("--method", default="spectral",
                       choices=["spectral", "shooting", "collocation", "energy"],
                       help="discretisation (default spectral: Chebyshev collocation; "
                            "energy: direct minimisation of the discrete energy)")


def _sweep(a, ce, opts) -> int:
    """The sweep command: a summary line, exit 0 / 1 (some caps failed) / 130 (stopped)."""
    from .sweep import SweepInterrupted

    def stop(signum, frame):        # a cluster's time limit is a SIGTERM: stop like Ctrl-C
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGTERM, stop)
    try:
        curve = ce.snap_curve(a.T, a.h, a.lam, tol=a.tol, csv_path=a.csv, jobs=a.jobs,
                              resume=a.resume, chunk_size=a.chunk_size,
                              progress=not _quiet(a), **opts)
    except SweepInterrupted as exc:
        print(f"shellbvp: interrupted after {len(exc.records)} of {exc.total} caps; results "
              f"so far in {a.csv}; --resume continues", file=sys.stderr)
        return 130
    finally:
        signal.signal(signal.SIGTERM, previous)
    c = curve.counts()
    print(f"{len(curve.records)} caps: {c['ok']} snap, {c['no snap']} no snap, "
          f"{c['failed']} failed -> {a.csv}")
    for r in curve.records:
        if r.status == "failed":
            print(f"  failed at T = {r.key:g}: {r.reason}", file=sys.stderr)
    return 1 if c["failed"] else 0


def _int_in(lo, hi=None):
    """An argparse type: an integer in [lo, hi] (no upper bound for hi None)."""
    allowed = f"in [{lo}, {hi}]" if hi is not None else f">= {lo}"

    def parse(text):
        try:
            v = int(text)
        except ValueError:
            v = None
        if v is None or v < lo or (hi is not None and v > hi):
            raise argparse.ArgumentTypeError(f"expected an integer {allowed}, got {text!r}")
        return v
    return parse


def _number(accept, expected: str):
    """An argparse type: a float (inf allowed, never nan) for which ``accept`` holds."""
    def parse(text):
        try:
            v = float(text)
        except ValueError:
            v = math.nan
        if math.isnan(v) or not accept(v):
            raise argparse.ArgumentTypeError(f"expected {expected}, got {text!r}")
        return v
    return parse


#: a number, -inf or inf (no bound), not nan
_bound = _number(lambda v: True, "a number (or -inf, inf: no bound)")
#: a positive number (inf allowed: no bound)
_positive = _number(lambda v: v > 0, "a number > 0")


def _material(a) -> str:
    """The material and only the parameters it uses."""
    return {"cg": f"material = cg, lam = {a.lam:g}, model = {a.model}",
            "nh": "material = nh (incompressible)",
            "koiter": f"material = koiter, nu = {a.nu:g}"}[a.material]


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit code 2), as the project's CLIs promise."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


DESCRIPTION = """\
Equilibria, folds, stability and post-buckling of elastic shells of revolution: any
meridian (plates, cones, cylinders, spheres, tori, ellipses, measured curves, joined with
kinks), ends, loads and stimuli, written as a scene file (TOML, in your own units), with
reduced shell energies derived from 3D (Taffetani & Pezzulla). The everting spherical
caps of the paper are built in (snap, branch, sweep)."""

EPILOG = """\
examples:
  shellbvp follow everting-cap             an installed example scene file, by name
  shellbvp follow my-shell.toml --csv out.csv --vtk out/   branch, folds; ParaView files
  shellbvp stability disc-spring --json    first instability: fold or n circumferential waves
  shellbvp postbuckling my-shell.toml      Koiter's coefficients, the lobed branch, the snap
  shellbvp snap --theta 0.5236 --h 0.01    snap curvature of one everting cap
Every command has its own --help. Documentation: docs/ (mkdocs build), README.md."""


def parser():
    import shellbvp
    from .scenefile import examples

    p = _Parser(prog="shellbvp", description=DESCRIPTION,
                epilog=f"{EPILOG}\ninstalled examples: {', '.join(examples())}",
                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--version", action="version", version=f"shellbvp {shellbvp.__version__}")
    common = argparse.ArgumentParser(add_help=False)
    common.add_argument("--quiet", "-q", action="store_true",
                        help="no progress bars or status lines on stderr")
    sub = p.add_subparsers(dest="command", required=True, metavar="command")
    s = sub.add_parser("snap", help="snap curvature kappa_s of one cap", parents=[common])
    _common(s)
    b = sub.add_parser("branch", help="continuation diagram kappa(w) to the first fold",
                       parents=[common])
    _common(b)
    b.add_argument("--csv", required=True, help="output CSV file")
    b.add_argument("--kappa-max", type=float, default=None, help="stop at this kappa R0")
    w = sub.add_parser("sweep", help="kappa_s against T = Theta sqrt(R0/h0)", parents=[common])
    _common(w, theta=False)
    w.add_argument("--T", type=_range, required=True, help="START:STOP:STEP of T")
    w.add_argument("--csv", required=True, help="output CSV file")
    w.add_argument("--jobs", type=int, default=1,
                   help="local processes (default 1); the values do not depend on it")
    w.add_argument("--chunk-size", type=int, default=CHUNK_SIZE,
                   help=f"caps per chunk, each following its own fold curve (default "
                        f"{CHUNK_SIZE})")
    w.add_argument("--resume", action="store_true",
                   help="continue an interrupted sweep from its journal (CSV.journal)")
    st = sub.add_parser("stability", help="first instability beyond axisymmetry of one cap or "
                                          "of a scene file's branch: the fold or a "
                                          "bifurcation into n waves", parents=[common])
    st.add_argument("file", nargs="?", default=None, metavar="FILE",
                    help="a scene file (TOML) or an installed example's name; without it, "
                         "the cap of the options below")
    _common(st, method=False)
    st.add_argument("--kappa-max", type=_positive, default=None,
                    help="a cap: scan the branch up to this kappa R0, > 0 (default 6, three "
                         "times the stimulus of full eversion)")
    st.add_argument("--json", action="store_true", help="print one JSON object")
    pb = sub.add_parser("postbuckling", help="past the first bifurcation of one cap or of a "
                                             "scene file's branch: Koiter's coefficients, the "
                                             "branch of n-lobed equilibria and the snap",
                        parents=[common])
    pb.add_argument("file", nargs="?", default=None, metavar="FILE",
                    help="a scene file (TOML) or an installed example's name; without it, "
                         "the cap of the options below")
    _common(pb, method=False)
    pb.add_argument("--K", type=_int_in(1, 8), default=2,
                    help="harmonics 0, n, ..., K n of the lobed states, in [1, 8] (default 2)")
    pb.add_argument("--degree", type=_int_in(8, 160 - DEGREE_STEP), default=None,
                    help=f"Chebyshev degree of the lobed states, in [8, {160 - DEGREE_STEP}] "
                         f"(default {HARMONICS_DEGREE}; the error estimates use "
                         f"degree + {DEGREE_STEP})")
    pb.add_argument("--n-folds", type=_int_in(0), default=1,
                    help="stop after this many folds of the lobed branch, >= 0 (0: at a "
                         "bound or max_steps only; default 1)")
    pb.add_argument("--p-min", "--kappa-min", dest="p_min", type=_bound, default=None,
                    help="stop the lobed branch below this parameter value (a cap: kappa R0, "
                         "default 0, where its branch starts; a scene file: its parameter "
                         "in its units, default the bottom of its range; --p-min=-inf: none)")
    pb.add_argument("--p-max", "--kappa-max", dest="p_max", type=_bound, default=None,
                    help="stop the lobed branch above this parameter value (a cap: default "
                         "none; a scene file: default the top of its range; --p-max=inf: none)")
    pb.add_argument("--amplitude-max", type=_positive, default=math.inf,
                    help="stop once the critical mode's (mass-norm) amplitude exceeds this, > 0 "
                         "(default none)")
    pb.add_argument("--csv", default=None, help="write the lobed branch to this CSV")
    _vtk(pb, "every lobed state")
    f = sub.add_parser("follow", help="continue a scene file from its parameter's 'from' to "
                                      "'to', observing its named observables",
                       parents=[common])
    f.add_argument("file", metavar="FILE", help="a scene file (TOML) or an installed "
                                                "example's name")
    f.add_argument("--csv", default=None, help="write every point and fold to this CSV")
    _vtk(f, "every point of the branch")
    f.add_argument("--json", action="store_true", help="print one JSON object")
    f.add_argument("--at", type=_number_list, default=None, metavar="P1,P2,...",
                   help="report the states at these parameter values exactly (in its "
                        "units, inside the file's range; replaces its [parameter] at)")
    return p


def _vtk(p, what: str) -> None:
    p.add_argument("--vtk", default=None, metavar="DIR",
                   help=f"write {what} as a ParaView file in DIR, and their collection "
                        f"(.pvd), in the scene file's units")


#: the options of the built-in cap, which a scene file states itself
CAP_OPTIONS = ("--theta", "--h", "--lam", "--model", "--material", "--nu")


def _scene_file(p, a, argv):
    """The scene file FILE names (a path, else an installed example), or exit 2 with one
    line."""
    from .scenefile import example, load_scene

    given = [o for o in CAP_OPTIONS for x in (argv if argv is not None else sys.argv[1:])
             if x == o or x.startswith(o + "=")]
    if given:
        p.exit(2, f"shellbvp: error: {given[0]} sets the built-in cap; a scene file states "
                  f"its own shell\n")
    path = Path(a.file)
    try:
        if not path.exists() and path.suffix == "" and len(path.parts) == 1:
            path = example(a.file)
        return load_scene(path)
    except ValueError as exc:
        p.exit(2, f"shellbvp: error: {a.file}: {exc}\n")


def _number_list(text):
    """``--at 1,2.5,3``: the numbers, or a usage error naming the option."""
    try:
        values = [float(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected numbers separated by commas, got "
                                         f"{text!r}") from None
    if not values or not all(math.isfinite(v) for v in values):
        raise argparse.ArgumentTypeError(f"expected finite numbers separated by commas, got "
                                         f"{text!r}")
    return values


def _quiet(a) -> bool:
    """No progress or status lines: ``--quiet``, or stderr is not a terminal."""
    return getattr(a, "quiet", False) or not sys.stderr.isatty()


class _Progress:
    """A progress bar on stderr (tqdm) of a continuation, called with the parameter of
    every point: the points so far, the parameter reached and the folds passed (where the
    parameter turned back); nothing where :func:`_quiet`. A context manager."""

    def __init__(self, a, what: str, name: str, unit: str = ""):
        from tqdm import tqdm

        self.name, self.unit = name, unit
        self.bar = tqdm(desc=f"shellbvp: {what}", unit=" points", file=sys.stderr,
                        disable=_quiet(a), leave=False,
                        bar_format="{desc}: {n_fmt}{unit} [{elapsed}]{postfix}")
        self.last, self.direction, self.folds = None, 0, 0

    def __call__(self, p, extra: str = "") -> None:
        if self.last is not None and p != self.last:
            direction = 1 if p > self.last else -1
            self.folds += self.direction * direction < 0
            self.direction = direction
        self.last = p
        self.bar.set_postfix_str(f"{self.name} = {p:.6g}{self.unit}, {self.folds} fold(s)"
                                 + extra, refresh=False)
        self.bar.update(1)

    def close(self) -> None:
        self.bar.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def _counter(a, what: str):
    """A progress report ``(done, total)`` on stderr (a tqdm bar, made at the first call),
    nothing where :func:`_quiet`; returns (report, close)."""
    from tqdm import tqdm

    bars = []

    def report(done, total):
        if not bars:
            bars.append(tqdm(total=total, desc=f"shellbvp: {what}", unit=" points",
                             file=sys.stderr, disable=_quiet(a), leave=False))
        bars[0].update(done - bars[0].n)

    return report, (lambda: bars and bars[0].close())


def _first_instability(sf, a):
    """The scene file's first instability, with its progress: the branch, then the
    harmonics checked point by point."""
    unit = f" {sf.units.parameter_label}" if sf.units.parameter_label else ""
    report, close = _counter(a, "checking harmonics n at each point")
    bar = _Progress(a, "branch", sf.parameter, unit)

    def checked(done, total):
        bar.close()                 # the branch is done: one bar at a time
        report(done, total)

    try:
        return sf.first_instability(tol=a.tol, progress=bar, checked=checked)
    finally:
        bar.close()
        close()


def _vtk_folder(a) -> None:
    """Refuse a ``--vtk`` folder that cannot be written, before anything is computed
    (_BadOption): an existing path that is not a folder, or a folder that cannot be made
    or written."""
    import os

    if getattr(a, "vtk", None) is None:
        return
    path = Path(a.vtk)
    if path.exists() and not path.is_dir():
        raise _BadOption(f"--vtk {a.vtk}: not a folder")
    up = path
    while not up.exists():
        up = up.parent
    if not up.is_dir() or not os.access(up, os.W_OK | os.X_OK):
        raise _BadOption(f"--vtk {a.vtk}: cannot write there ({up} is not a writable "
                         f"folder)")


def _write_vtk(a, write, p) -> str:
    """Write the ParaView files of a branch whose parameter takes the values p with
    ``write(folder, progress)`` (a bar on stderr); the line that names them. An unwritable
    folder is bad input (_BadOption)."""
    from .paraview import collection_times

    report, close = _counter(a, f"writing ParaView files to {a.vtk}")
    try:
        pvd = write(a.vtk, report)
    except OSError as exc:
        raise _BadOption(f"--vtk {a.vtk}: {exc.strerror or exc}") from None
    finally:
        close()
    kind = collection_times(p)[1]
    return (f"ParaView: {pvd}, {len(p)} files, time = " +
            ("the parameter" if kind == "parameter" else
             "the point's index (the parameter turns back along the branch)"))


def _follow_file(sf, a) -> int:
    """``follow FILE``: every point that converged is printed and written (CSV, ParaView),
    also where the continuation stalls (then with the reason, and exit status 1)."""
    from .surface import OutputUnits

    unit = f" {sf.units.parameter_label}" if sf.units.parameter_label else ""
    with _Progress(a, "branch", sf.parameter, unit) as bar:
        run = sf.follow(progress=bar, at=a.at)
    if a.csv:
        run.to_csv(a.csv)
    vtk = _write_vtk(a, lambda folder, report: run.branch.to_vtk(
        folder, units=OutputUnits.of(sf), progress=report), run.branch.p) if a.vtk else None
    if a.json:
        print(json.dumps(run.summary()))
    else:
        print(f"{sf.title or sf.source}: {sf.parameter} from {sf.start:g} to "
              f"{sf.stop:g}{unit}")
        for k, fold in enumerate(run.folds, 1):
            print(f"fold {k}: " + _values(fold, sf))
        for state in run.at:
            print("at: " + _values(state, sf))
        for v in run.missing:
            print(f"at: {sf.parameter} = {v:.10g}{unit} not reached")
        print("last: " + _values(run.last, sf))
        if run.error_note:
            print(f"error estimates: {run.error_note}")
        print(f"{len(run.branch.points)} points, {len(run.folds)} fold(s); stop: {run.stop}"
              + (f" -> {a.csv}" if a.csv else ""))
        if vtk:
            print(vtk)
    if not run.complete:
        print(f"shellbvp: the continuation stalled: {run.stop}", file=sys.stderr)
        return 1
    return 0


def _values(d: dict, sf) -> str:
    """A row of a scene file's results: the parameter and the observables, each with its
    error estimate and unit."""
    unit = sf.units.parameter_label
    units = {"p": unit, **{ob.name: ob.unit for ob in sf.observables}}

    def one(name, label):
        err = d.get(f"{name}_error", math.nan)
        text = f"{label} = {d[name]:.10g}" + (f" +- {err:.1e}" if math.isfinite(err)
                                              else " +- nan")
        return text + (f" {units[name]}" if units[name] else "")

    return ", ".join([one("p", sf.parameter)] + [one(n, n) for n in units if n != "p"])


def _stability_file(sf, a) -> None:
    found = _first_instability(sf, a)
    if a.json:
        print(json.dumps(found.summary()))
        return
    unit = f" {sf.units.parameter_label}" if sf.units.parameter_label else ""
    what = {"fold": "the axisymmetric fold",
            "bifurcation": f"a bifurcation into n = {found.n} circumferential waves",
            "none": f"none up to {sf.parameter} = {found.p:.10g}{unit}"}[found.kind]
    print(f"{sf.title or sf.source}: first instability: {what}" + (
        f" at {sf.parameter} = {found.p:.10g}{unit} +- {found.error_estimate:.1e}"
        if found.kind != "none" else f" (the branch ended: {found.stop})"))
    _print_nearby(found.nearby, sf.parameter, unit)
    if getattr(found.instability, "note", ""):
        print(f"note: {found.instability.note}")


def _print_nearby(nearby, name, unit) -> None:
    """The line of a bifurcation's cluster (:attr:`shellbvp.Instability.nearby`), if it
    has more than the critical harmonic."""
    if len(nearby) > 1:
        print(f"nearby (harmonics crossing within 1 % of {name}): " + "; ".join(
            f"n = {n} at {p:.10g}{unit} +- {e:.1e}" for n, p, e in nearby))


def _bounds(a, default, origin) -> tuple:
    """(low, high): the lobed branch's bounds on the parameter, ``--p-min`` / ``--p-max``
    where given, else ``default``'s (None: unbounded; ``origin`` says where the default
    comes from); a low not below high is bad input (_BadOption, before anything is
    computed)."""
    lo = a.p_min if a.p_min is not None else default[0]
    hi = a.p_max if a.p_max is not None else default[1]
    lo = -math.inf if lo is None else lo
    hi = math.inf if hi is None else hi
    if not lo < hi:
        if a.p_min is not None and a.p_max is not None:
            msg = f"{a.p_min_name} {lo:g} must lie below {a.p_max_name} {hi:g}"
        elif a.p_min is not None:
            msg = f"{a.p_min_name} {lo:g} must lie below {hi:g}, the default upper bound " \
                  f"({origin})"
        else:
            msg = f"{a.p_max_name} {hi:g} must lie above {lo:g}, the default lower bound " \
                  f"({origin})"
        raise _BadOption(msg)
    return lo, hi


def _postbuckling_file(sf, a) -> None:
    from .surface import OutputUnits

    label = f"[{sf.units.parameter_label}]" if sf.units.parameter_label else ""
    bounds = _bounds(a, sorted((sf.start, sf.stop)), "the file's range")
    found = _first_instability(sf, a)
    unit = f" {sf.units.parameter_label}" if sf.units.parameter_label else ""
    head = f"{sf.title or sf.source}: first instability: "
    if found.kind != "bifurcation":
        print(head + ("the axisymmetric fold at "
                      f"{sf.parameter} = {found.p:.10g}{unit} +- {found.error_estimate:.1e}"
                      if found.kind == "fold" else
                      f"none up to {sf.parameter} = {found.p:.10g}{unit} (the branch ended: "
                      f"{found.stop})") + ": no bifurcation to follow")
        return
    print(f"{sf.title or sf.source}: {sf.parameter} from {sf.start:g} to {sf.stop:g}{unit}")
    _postbuckling(a, found.instability, name=sf.parameter, unit=unit, scale=sf.scale,
                  bounds=bounds, column=f"{sf.parameter}{label}", units=OutputUnits.of(sf))


def _postbuckling(a, ins, *, name, unit, scale, bounds, column, units=None) -> None:
    """Follow the lobed branch from the bifurcation ``ins`` (the engine's
    :class:`shellbvp.Instability`, parameter t) and print it in the parameter's own units, p
    = scale t (a cap: kappa R0, scale 1). ``bounds``: (low, high) in those units (from
    :func:`_bounds`, infinite for none); ``units``: the ParaView files' (``--vtk``;
    :class:`shellbvp.surface.OutputUnits`, None: the engine's)."""
    from .postbuckling import follow_bifurcation

    lo, hi = bounds

    def show(t):
        return f"{name} = {scale * t:.12g}{unit}"

    p_ins = scale * ins.p
    if not lo < p_ins < hi:       # the lobed branch starts there: a bound must not exclude it
        low = p_ins <= lo
        opt = (a.p_min_name if a.p_min is not None else None) if low else \
            (a.p_max_name if a.p_max is not None else None)
        what = f"{opt} {lo if low else hi:g}" if opt else \
            f"the default bounds [{lo:g}, {hi:g}]"
        raise _BadOption(f"{what} excludes the bifurcation at {show(ins.p)}, where the lobed "
                         f"branch starts" + (f": {opt} must lie {'below' if low else 'above'} "
                                             f"it" if opt else ""))
    t_stop = tuple(sorted((lo / scale, hi / scale)))
    if not _quiet(a):
        print(f"shellbvp: a bifurcation into n = {ins.n} at {show(ins.p)}: Koiter's "
              f"coefficients and the lobed branch (K = {a.K}), then the error estimates on "
              f"a finer discretisation (~1-2 min)...", file=sys.stderr, flush=True)
    with _Progress(a, "lobed branch", name, unit) as bar:
        br = follow_bifurcation(
            ins, K=a.K, degree=a.degree, n_folds=a.n_folds, amplitude_max=a.amplitude_max,
            p_stop=None if lo == -hi == -math.inf else t_stop,
            progress=lambda pt: bar(scale * pt.p, f", amplitude {pt.monitor:.4g}"))
    if a.csv:
        _lobed_csv(br, a.csv, column, scale)
    vtk = _write_vtk(a, lambda folder, report: br.to_vtk(folder, units=units,
                                                         progress=report),
                     br.p) if a.vtk else None
    k = br.koiter
    stop = br.stop
    if br.stop == f"{br.parameter} left [{t_stop[0]:g}, {t_stop[1]:g}]":
        stop = f"{name} left [{lo:g}, {hi:g}]{unit}"   # in the parameter's own units
    print(f"bifurcation: n = {br.n} at {show(br.p_c)} +- {abs(scale) * br.p_c_error:.1e} "
          f"(harmonics 0..{br.K * br.n} step {br.n}, degree {br.degree})")
    print(f"Koiter: p2 = {scale * k.p2:.6g}{unit}, b = {k.b:.6g}: {k.kind} (p = p_c + p2 a^2 "
          f"= p_c (1 + b xi^2), a the mode's mass-norm amplitude, xi = a w_max / h)")
    for j, fo in enumerate(br.folds, 1):
        err = f"+- {abs(scale) * fo.error_estimate:.1e}" if math.isfinite(fo.error_estimate) \
            else f"(no error estimate: {fo.error_note or 'not computed'})"
        print(f"lobed fold {j}: {show(fo.p)} {err}, amplitude {fo.amplitude:.6g}")
    if not br.folds:
        print("lobed folds: none before the stop")
    print(f"lobed branch: {len(br.p)} points, {len(br.folds)} fold(s); stop: {stop}"
          + (f" -> {a.csv}" if a.csv else ""))
    if k.kind == "subcritical":
        print(f"snap: at the bifurcation, {show(br.p_c)} +- {abs(scale) * br.p_c_error:.1e} "
              f"(subcritical: the lobed branch turns back)")
    elif br.folds:
        fo = br.folds[0]
        err = f" +- {abs(scale) * fo.error_estimate:.1e}" if math.isfinite(fo.error_estimate) \
            else ""
        print(f"snap: at the first lobed fold, {show(fo.p)}{err} (supercritical)")
    else:
        print("snap: not found (supercritical, and no lobed fold before the stop)")
    if vtk:
        print(vtk)


def _lobed_csv(br, path, column, scale) -> None:
    """The lobed branch's columns (:meth:`shellbvp.LobedBranch.columns`) written atomically,
    the parameter's column named and valued as the other commands' CSVs have it."""
    import csv
    import io

    from .cache import atomic_write_text

    cols = br.columns()
    cols = {column: scale * np.asarray(cols.pop(br.parameter)), **cols}
    buf = io.StringIO()
    wr = csv.writer(buf, lineterminator="\n")
    wr.writerow(cols)
    for row in zip(*cols.values()):
        wr.writerow([repr(float(v)) for v in row])
    atomic_write_text(path, buf.getvalue())


class _BadOption(ValueError):
    """An option that does not fit what was computed: exit 2, without a file's prefix."""


def main(argv=None) -> int:
    p = parser()
    a = p.parse_args(argv)
    from . import ConvergenceError
    from .jaxsetup import use_persistent_cache
    from .problems import cap_eversion as ce

    use_persistent_cache(default=True)   # a later command starts in seconds

    if hasattr(a, "tol") and not (0 < a.tol < 1):
        p.exit(2, f"shellbvp: error: --tol must lie in (0, 1), got {a.tol!r}\n")
    try:
        _vtk_folder(a)
    except _BadOption as exc:
        p.exit(2, f"shellbvp: error: {exc}\n")
    if a.command == "postbuckling":       # the spellings given, for the messages
        given = argv if argv is not None else sys.argv[1:]
        for dest, names in (("p_min", ("--p-min", "--kappa-min")),
                            ("p_max", ("--p-max", "--kappa-max"))):
            spelled = [n for x in given for n in names if x == n or x.startswith(n + "=")]
            setattr(a, dest + "_name", spelled[-1] if spelled else
                    names[1 if a.file is None else 0])
    if getattr(a, "file", None) is not None:
        if getattr(a, "kappa_max", None) is not None and a.command == "stability":
            p.exit(2, "shellbvp: error: --kappa-max applies to a cap; a scene file's branch "
                      "runs over its own range (from, to)\n")
        sf = _scene_file(p, a, argv)
        try:
            return {"follow": _follow_file, "stability": _stability_file,
                    "postbuckling": _postbuckling_file}[a.command](sf, a) or 0
        except _BadOption as exc:
            p.exit(2, f"shellbvp: error: {exc}\n")
        except (ValueError, NotImplementedError) as exc:
            # NotImplementedError: a shell the lobed discretisation does not handle yet
            p.exit(2, f"shellbvp: error: {a.file}: {exc}\n")
        except ConvergenceError as exc:
            p.exit(1, f"shellbvp: solver failure: {exc}\n")
        return 0

    opts = dict(model=a.model, material=a.material, nu=a.nu)
    if hasattr(a, "method"):
        opts["method"] = a.method
    try:
        if a.command != "sweep":
            sc = ce.scene(a.theta, a.h, a.lam, model=a.model, material=a.material, nu=a.nu)
        if a.command == "postbuckling":
            bounds = _bounds(a, (0.0, None), f"where the cap's branch starts; "
                                             f"{a.p_min_name}=-inf removes it")
        if not _quiet(a):    # bad input has been reported above, in one line
            print("shellbvp: preparing the solver (tracing and compiling it for this model "
                  "takes ~10-30 s once per process)...", file=sys.stderr, flush=True)
        if a.command == "snap":
            r = ce.snap_curvature(a.theta, a.h, a.lam, tol=a.tol, **opts)
            print(f"Theta = {a.theta:g} rad, h0/R0 = {a.h:g}, {_material(a)}, "
                  f"T = Theta sqrt(R0/h0) = {r.T:.4g}")
            if r.snaps:
                print(f"kappa_s R0 = {r.kappa_s:.10f} +- {r.error_estimate:.1e}")
                print(f"w_s / R0   = {r.w_s:.10f}")
            else:
                print("no snap: the cap everts without a fold (kappa_s undefined)")
        elif a.command == "stability":
            r = ce.first_instability(a.theta, a.h, a.lam, tol=a.tol, kappa_max=a.kappa_max,
                                     **opts)
            if a.json:
                from .scenefile import SceneInstability

                print(json.dumps(SceneInstability(
                    r.kind, None if r.kind == "none" else int(r.n), float(r.p),
                    float(r.error_estimate), r.stop, r, r.nearby).summary()))
                return 0
            print(f"Theta = {a.theta:g} rad, h0/R0 = {a.h:g}, {_material(a)}, "
                  f"T = Theta sqrt(R0/h0) = {a.theta / math.sqrt(a.h):.4g}")
            what = {"fold": "the axisymmetric snap (fold)",
                    "bifurcation": f"a bifurcation into n = {r.n} circumferential waves",
                    "none": f"none up to kappa R0 = {r.p:.6g} ({r.stop})"}[r.kind]
            print(f"first instability: {what}" + (
                f" at kappa R0 = {r.p:.8f} +- {r.error_estimate:.1e}, w / R0 = {r.w:.6f}"
                if r.kind != "none" else ""))
            _print_nearby(r.nearby, "kappa R0", "")
            if r.note:
                print(f"note: {r.note}")
            print(f"harmonics n = 0..{r.cutoff} checked ({r.cutoff_reason})")
        elif a.command == "postbuckling":
            r = ce.first_instability(a.theta, a.h, a.lam, tol=a.tol, **opts)
            print(f"Theta = {a.theta:g} rad, h0/R0 = {a.h:g}, {_material(a)}, "
                  f"T = Theta sqrt(R0/h0) = {a.theta / math.sqrt(a.h):.4g}")
            if r.kind != "bifurcation":
                print("first instability: " + (
                    f"the axisymmetric snap (fold) at kappa R0 = {r.p:.8f} +- "
                    f"{r.error_estimate:.1e}, w / R0 = {r.w:.6f}" if r.kind == "fold" else
                    f"none up to kappa R0 = {r.p:.6g}" + (f" ({r.stop})" if r.stop else "")) +
                    ": no bifurcation to follow")
                return 0
            _postbuckling(a, r, name="kappa R0", unit="", scale=1.0,
                          bounds=bounds, column=sc.parameter_column)
        elif a.command == "branch":
            br = ce.branch(a.theta, a.h, a.lam, kappa_max=a.kappa_max, tol=a.tol, **opts)
            br.to_csv(a.csv)
            print(f"{br.p.size} points, {len(br.folds)} fold(s) -> {a.csv}")
        else:
            return _sweep(a, ce, opts)
    except ValueError as exc:
        p.exit(2, f"shellbvp: error: {exc}\n")
    except ConvergenceError as exc:
        p.exit(1, f"shellbvp: solver failure: {exc}\n")
    return 0


def run() -> None:
    """The console command ``shellbvp``: :func:`main` on ``sys.argv``, exiting with its
    status. The objects left are first frozen out of the garbage collector (``gc.freeze``):
    otherwise the interpreter's shutdown spends ~0.25 s of a ~1.6 s warm ``shellbvp snap``
    traversing JAX's and SciPy's object graphs, which the ending process drops anyway
    (every file the command writes is closed by then, and the standard streams are
    flushed at exit as always)."""
    try:
        code = main()
    finally:
        gc.freeze()
    sys.exit(code)


if __name__ == "__main__":
    run()
