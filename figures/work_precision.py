"""Error against run time of kappa_s for every back-end, at the default cap and two stiff ones.

Back-ends and their accuracy knobs (``snap_curvature(..., method=..., tol=tol)``: the fold is
refined on the method's ladder until it changes by at most tol):

* spectral (Chebyshev, default): tol from 1e-4 to 1e-12 (the degree follows tol);
* collocation (scipy's solve_bvp scheme on a fixed clustered mesh, continued by the common
  machinery; its ladder halves every interval): tol 1e-4 ... 1e-8;
* shooting (diffrax Tsit5 multiple shooting, 16 segments; its ladder divides the ODE rtol by
  10): ODE rtol 1e-6 ... 1e-10 with tol = 10 rtol.

Caps: the default (Theta = pi/6, h0/R0 = 0.01, lam = 1, relaxed CG) and two stiff ones,
h0/R0 = 1e-3 (T = 16.6: a thin edge layer) and lam = 1e3 (nearly incompressible); shooting
and collocation, minutes per kappa_s, run at the default cap only unless ``--all``.
Errors are against a reference: the spectral value at the finest tolerance the cap's
round-off allows, located on degrees 24 above the cap's default (no timed row uses them);
at the default cap it equals the independent AUTO-07p model of the same equations to
~1e-12, and the finest collocation and shooting values agree with it within their own
estimates (printed). Times: every setting is called once first (``seconds_first_call``:
it compiles what it needs, in a process that has run the settings before it), then in
steady state: the median of ``--repeats`` calls (spectral) or of 3 (shooting,
collocation).

Writes work_precision.csv and work_precision.png.

    python figures/work_precision.py [--quick] [--all] [--repeats 5]
"""

from __future__ import annotations

import math
import statistics
import time

from _common import finish, parser, pyplot, write_csv

THETA = math.pi / 6
#: the caps and the tolerance of their references (the finest their round-off floor,
#: 5 eps (1 + kappa_s) / h, x lam / 100 above lam = 100, allows)
CAPS = {"default": dict(theta=THETA, h=0.01, lam=1.0, reference_tol=1e-12),
        "thin h=1e-3": dict(theta=THETA, h=1e-3, lam=1.0, reference_tol=1e-10),
        "stiff lam=1e3": dict(theta=THETA, h=0.01, lam=1e3, reference_tol=6e-12)}
SPECTRAL_TOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
COLLOCATION_TOLS = (1e-4, 1e-6, 1e-8)
SHOOTING_RTOLS = (1e-6, 1e-8, 1e-10)
#: the reference is located on degrees this far above the cap's default, which no timed
#: spectral row uses
REFERENCE_EXTRA_NODES = 24


def settings(backend, quick):
    from shellbvp import Collocation, Shooting

    if backend == "spectral":
        return [("spectral", tol, f"tol {tol:g}") for tol in
                ((1e-6, 1e-10) if quick else SPECTRAL_TOLS)]
    if backend == "collocation":
        return [(Collocation(), tol, f"tol {tol:g}") for tol in
                ((1e-4,) if quick else COLLOCATION_TOLS)]
    return [(Shooting(rtol=rtol), 10 * rtol, f"rtol {rtol:g}") for rtol in
            ((1e-6,) if quick else SHOOTING_RTOLS)]


def timed(cap, method, tol, repeats):
    """The result, the wall times of ``repeats`` calls, and that of a first call before
    them (which compiles what this setting needs: new Chebyshev degrees, meshes, ODE
    programs; in a process that has run the settings before it)."""
    from shellbvp.problems import cap_eversion as ce

    t0 = time.perf_counter()
    ce.snap_curvature(cap["theta"], cap["h"], cap["lam"], method=method, tol=tol)
    times, r, first = [], None, time.perf_counter() - t0
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = ce.snap_curvature(cap["theta"], cap["h"], cap["lam"], method=method, tol=tol)
        times.append(time.perf_counter() - t0)
    return r, times, first


def main():
    from tqdm import tqdm

    from shellbvp import Chebyshev, ConvergenceError
    from shellbvp.methods import default_nodes
    from shellbvp.problems import cap_eversion as ce

    p = parser(__doc__.splitlines()[0])
    p.add_argument("--all", action="store_true", help="shooting and collocation at every cap")
    p.add_argument("--repeats", type=int, default=5)
    args = p.parse_args()
    rows = []
    jobs = [(cap, b) for cap in CAPS for b in ("spectral", "collocation", "shooting")
            if b == "spectral" or cap == "default" or args.all]
    if args.quick:
        jobs = [j for j in jobs if j[0] == "default"]
    for cap_name, backend in tqdm(jobs, desc="work-precision", unit="back-end"):
        cap = CAPS[cap_name]
        scene = ce.scene(cap["theta"], cap["h"], cap["lam"])
        ref = ce.snap_curvature(cap["theta"], cap["h"], cap["lam"], tol=cap["reference_tol"],
                                method=Chebyshev(nodes=default_nodes(scene)
                                                 + REFERENCE_EXTRA_NODES))
        tqdm.write(f"{cap_name}: reference kappa_s {ref.kappa_s!r} (estimate "
                   f"{ref.error_estimate:.1e})")
        for method, tol, knob in settings(backend, args.quick):
            n = args.repeats if backend == "spectral" else 3
            try:
                r, times, first = timed(cap, method, tol, n)
            except ConvergenceError as exc:
                tqdm.write(f"{cap_name} {backend} {knob}: {str(exc)[:120]}")
                continue
            err = abs(r.kappa_s - ref.kappa_s)
            rows.append([cap_name, backend, knob, tol, r.kappa_s, r.error_estimate, err,
                         statistics.median(times), min(times), max(times), first])
            tqdm.write(f"{cap_name:14s} {backend:11s} {knob:11s} kappa_s {r.kappa_s:.13f} "
                       f"error {err:.1e} (estimate {r.error_estimate:.1e}) "
                       f"{statistics.median(times) * 1e3:9.1f} ms")
    header = ["cap", "backend", "knob", "tol", "kappa_s", "error_estimate", "error",
              "seconds_median", "seconds_min", "seconds_max", "seconds_first_call"]
    write_csv(args.out / "work_precision.csv", header, rows)

    plt = pyplot()
    fig, axes = plt.subplots(1, len(CAPS), figsize=(4.2 * len(CAPS), 3.8), sharex=True,
                             sharey=True)
    marks = {"spectral": "o-", "collocation": "s-", "shooting": "^-"}
    for ax, cap_name in zip(axes, CAPS):
        for backend, mark in marks.items():
            pts = [(r[7], max(r[6], 1e-16)) for r in rows if r[0] == cap_name and r[1] == backend]
            if pts:
                ax.loglog(*zip(*pts), mark, label=backend)
        ax.set_title(f"{cap_name}")
        ax.set_xlabel("wall time per kappa_s (s, steady state)")
        ax.set_xscale("log")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("|kappa_s - reference| R0")
    axes[0].legend()
    finish(fig, args.out, "work_precision")


if __name__ == "__main__":
    main()
