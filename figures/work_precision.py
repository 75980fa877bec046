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
Errors are against a reference established by agreement of two back-ends: the spectral
value at tol 1e-12 (at the default cap it equals the independent AUTO-07p model of the same
equations to ~1e-12) checked against the finest collocation or shooting value.
Times: the first call of each back-end includes compilation and is repeated; steady state is
the median of ``--repeats`` calls (spectral) or one call (shooting, collocation).

Writes work_precision.csv and work_precision.png.

    python figures/work_precision.py [--quick] [--all] [--repeats 5]
"""

from __future__ import annotations

import math
import statistics
import time

from _common import HERE, finish, parser, pyplot, write_csv

THETA = math.pi / 6
CAPS = {"default": dict(theta=THETA, h=0.01, lam=1.0),
        "thin h=1e-3": dict(theta=THETA, h=1e-3, lam=1.0),
        "stiff lam=1e3": dict(theta=THETA, h=0.01, lam=1e3)}
SPECTRAL_TOLS = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
COLLOCATION_TOLS = (1e-4, 1e-6, 1e-8)
SHOOTING_RTOLS = (1e-6, 1e-8, 1e-10)
REFERENCE_TOL = 1e-12


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
    from shellbvp.problems import cap_eversion as ce

    times, r = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        r = ce.snap_curvature(cap["theta"], cap["h"], cap["lam"], method=method, tol=tol)
        times.append(time.perf_counter() - t0)
    return r, times


def main():
    from tqdm import tqdm

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
        ref = ce.snap_curvature(cap["theta"], cap["h"], cap["lam"], tol=REFERENCE_TOL)
        first = True
        for method, tol, knob in settings(backend, args.quick):
            n = args.repeats if backend == "spectral" else 1
            if first:      # compilation: timed once, not in the steady-state numbers
                r, t_first = timed(cap, method, tol, 1)
                first = False
            r, times = timed(cap, method, tol, n)
            err = abs(r.kappa_s - ref.kappa_s)
            rows.append([cap_name, backend, knob, tol, r.kappa_s, r.error_estimate, err,
                         statistics.median(times), min(times), max(times), t_first[0]])
            tqdm.write(f"{cap_name:14s} {backend:11s} {knob:11s} kappa_s {r.kappa_s:.13f} "
                       f"error {err:.1e} (estimate {r.error_estimate:.1e}) "
                       f"{statistics.median(times) * 1e3:9.1f} ms")
    header = ["cap", "backend", "knob", "tol", "kappa_s", "error_estimate", "error",
              "seconds_median", "seconds_min", "seconds_max", "seconds_first_call"]
    write_csv(args.out / "work_precision.csv", header, rows)

    plt = pyplot()
    fig, axes = plt.subplots(1, len(CAPS), figsize=(4.2 * len(CAPS), 3.8), sharey=True)
    marks = {"spectral": "o-", "collocation": "s-", "shooting": "^-"}
    for ax, cap_name in zip(axes, CAPS):
        for backend, mark in marks.items():
            pts = [(r[7], max(r[6], 1e-16)) for r in rows if r[0] == cap_name and r[1] == backend]
            if pts:
                ax.loglog(*zip(*pts), mark, label=backend)
        ax.set_title(f"{cap_name}")
        ax.set_xlabel("wall time per kappa_s (s, steady state)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("|kappa_s - reference| R0")
    axes[0].legend()
    finish(fig, args.out, "work_precision")


if __name__ == "__main__":
    main()
