"""The ``shellbvp`` command line: snap curvature, continuation diagrams and sweeps of caps,
and scene files.

    shellbvp snap   --theta 0.5236 --h 0.01 --lam 1 --model relaxed
    shellbvp branch --theta 0.5236 --h 0.01 --lam 1 --csv branch.csv
    shellbvp sweep  --T 2:10:0.25 --h 0.01 --lam 1 --csv sweep.csv [--jobs 2] [--resume]
    shellbvp stability --theta 0.5236 --h 0.01 --lam 1 [--json]
    shellbvp follow FILE [--csv OUT.csv] [--json]
    shellbvp stability FILE [--json]

FILE is a scene file (TOML, :mod:`shellbvp.scenefile`), or the name of an example installed
with the package (``shellbvp follow everting-cap``; :func:`shellbvp.scenefile.examples`).
``--json`` prints one JSON object instead of the text: ``follow`` ``{"folds": [{"p",
"error_estimate", <observables>}], "last": {"p", <observables>}, "stop"}``, ``stability``
``{"kind", "n", "p", "error_estimate"}`` (and ``"stop"`` for none), in the file's units
(null for what is undefined).

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

import numpy as np

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
                              progress=sys.stderr.isatty(), **opts)
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


def _material(a) -> str:
    """The material and only the parameters it uses."""
    return {"cg": f"material = cg, lam = {a.lam:g}, model = {a.model}",
            "nh": "material = nh (incompressible)",
            "koiter": f"material = koiter, nu = {a.nu:g}"}[a.material]


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (exit code 2), as the project's CLIs promise."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message}\n")


def parser():
    p = _Parser(prog="shellbvp", description="Snap-through of everting "
                                "spherical caps (Taffetani & Pezzulla, Section 5.2).")
    sub = p.add_subparsers(dest="command", required=True)
    s = sub.add_parser("snap", help="snap curvature kappa_s of one cap")
    _common(s)
    b = sub.add_parser("branch", help="continuation diagram kappa(w) to the first fold")
    _common(b)
    b.add_argument("--csv", required=True, help="output CSV file")
    b.add_argument("--kappa-max", type=float, default=None, help="stop at this kappa R0")
    w = sub.add_parser("sweep", help="kappa_s against T = Theta sqrt(R0/h0)")
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
                                          "bifurcation into n waves")
    st.add_argument("file", nargs="?", default=None, metavar="FILE",
                    help="a scene file (TOML) or an installed example's name; without it, "
                         "the cap of the options below")
    _common(st, method=False)
    st.add_argument("--json", action="store_true", help="print one JSON object")
    f = sub.add_parser("follow", help="continue a scene file from its parameter's 'from' to "
                                      "'to', observing its named observables")
    f.add_argument("file", metavar="FILE", help="a scene file (TOML) or an installed "
                                                "example's name")
    f.add_argument("--csv", default=None, help="write every point and fold to this CSV")
    f.add_argument("--json", action="store_true", help="print one JSON object")
    return p


#: the options of the built-in cap, which a scene file states itself
CAP_OPTIONS = ("--theta", "--h", "--lam", "--model", "--material", "--nu")


def _scene_file(p, a, argv):
    """The scene file FILE names (a path, else an installed example), or exit 2 with one
    line."""
    from pathlib import Path

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


def _follow_file(sf, a) -> None:
    run = sf.follow()
    if a.csv:
        run.to_csv(a.csv)
    if a.json:
        print(json.dumps(run.summary()))
        return
    unit = f" {sf.units.parameter_label}" if sf.units.parameter_label else ""
    print(f"{sf.title or sf.source}: {sf.parameter} from {sf.start:g} to {sf.stop:g}{unit}")
    for k, fold in enumerate(run.folds, 1):
        print(f"fold {k}: " + _values(fold, sf))
    print("last: " + _values(run.last, sf))
    print(f"{len(run.branch.points)} points, {len(run.folds)} fold(s); stop: {run.stop}"
          + (f" -> {a.csv}" if a.csv else ""))


def _values(d: dict, sf) -> str:
    """A row of a scene file's results: the parameter (with its error estimate) and the
    observables, each with its unit."""
    unit = sf.units.parameter_label
    head = f"{sf.parameter} = {d['p']:.10g}"
    if "error_estimate" in d:
        head += f" +- {d['error_estimate']:.1e}"
    head += f" {unit}" if unit else ""
    units = {ob.name: ob.unit for ob in sf.observables}
    return ", ".join([head] + [f"{n} = {d[n]:.8g} {units[n]}" for n in units])


def _stability_file(sf, a) -> None:
    found = sf.first_instability(tol=a.tol)
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


def main(argv=None) -> int:
    p = parser()
    a = p.parse_args(argv)
    from . import ConvergenceError
    from .jaxsetup import use_persistent_cache
    from .problems import cap_eversion as ce

    use_persistent_cache(default=True)   # a later command starts in seconds

    if hasattr(a, "tol") and not (0 < a.tol < 1):
        p.exit(2, f"shellbvp: error: --tol must lie in (0, 1), got {a.tol!r}\n")
    if getattr(a, "file", None) is not None:
        sf = _scene_file(p, a, argv)
        try:
            (_follow_file if a.command == "follow" else _stability_file)(sf, a)
        except ValueError as exc:
            p.exit(2, f"shellbvp: error: {a.file}: {exc}\n")
        except ConvergenceError as exc:
            p.exit(1, f"shellbvp: solver failure: {exc}\n")
        return 0

    opts = dict(model=a.model, material=a.material, nu=a.nu)
    if a.command != "stability":
        opts["method"] = a.method
    try:
        if a.command != "sweep":
            ce.scene(a.theta, a.h, a.lam, model=a.model, material=a.material, nu=a.nu)
        if sys.stderr.isatty():    # bad input has been reported above, in one line
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
            r = ce.first_instability(a.theta, a.h, a.lam, tol=a.tol, **opts)
            if a.json:
                from .scenefile import SceneInstability

                print(json.dumps(SceneInstability(
                    r.kind, None if r.kind == "none" else int(r.n), float(r.p),
                    float(r.error_estimate)).summary()))
                return 0
            print(f"Theta = {a.theta:g} rad, h0/R0 = {a.h:g}, {_material(a)}, "
                  f"T = Theta sqrt(R0/h0) = {a.theta / math.sqrt(a.h):.4g}")
            what = {"fold": "the axisymmetric snap (fold)",
                    "bifurcation": f"a bifurcation into n = {r.n} circumferential waves",
                    "none": "none up to full eversion"}[r.kind]
            print(f"first instability: {what}" + (
                f" at kappa R0 = {r.p:.8f} +- {r.error_estimate:.1e}, w / R0 = {r.w:.6f}"
                if r.kind != "none" else ""))
            print(f"harmonics n = 0..{r.cutoff} checked ({r.cutoff_reason})")
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
