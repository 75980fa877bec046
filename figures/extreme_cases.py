"""Stiff and extreme caps: kappa_s across material, thickness and depth, or a clear failure.

Every case is one ``snap_curvature`` of the cap-eversion scene (Ciarlet-Geymonat, apex held,
free edge), at the default tol 1e-9, under a time limit. Per case the table gives kappa_s
R0, w_s, the error estimate, the wall time, the final Chebyshev degree and the number of
Newton evaluations, or the failure's class and first line. The estimate is then checked
against a second computation of the same case at tol 1e-11 (1e-10 where 1e-11 is beyond
the case's resolution or round-off; a finer rung of the ladder, its own fold location): the case is ``honest`` when the difference is within the estimate,
``WRONG`` otherwise. Cases that do not snap say so (below the onset of snapping, T ~ 1.9 at lam = 1).

Grid (issue #10):
* material: lam in {1e-3, 0.1, 1, 10, 1e2, 1e3, 1e4, 1e6}, relaxed and plane strain,
  Theta = pi/6, h0/R0 = 0.01;
* thickness: h0/R0 in {1e-4, 1e-3, 1e-2, 0.1, 0.2}, Theta = pi/6, lam = 1, both models;
* depth: Theta / pi in {0.05, 0.15, ..., 0.95}, h0/R0 = 0.01, lam = 1, relaxed
  (T = Theta / sqrt(h) from 1.6 to 29.8).

Writes extreme_cases.csv (the docs' validation page reads it) and extreme_cases.png, and
prints the table as Markdown.

    python figures/extreme_cases.py [--quick] [--timeout 300] [--replot]
"""

from __future__ import annotations

import math
import re
import signal
import time

from _common import finish, parser, pyplot, write_csv

THETA, H0, LAM = math.pi / 6, 0.01, 1.0
TOL, CHECK_TOLS = 1e-9, (1e-11, 1e-10)
LAMS = (1e-3, 0.1, 1.0, 10.0, 1e2, 1e3, 1e4, 1e6)
HS = (1e-4, 1e-3, 1e-2, 0.1, 0.2)
DEPTHS = tuple(round(0.05 + 0.1 * k, 2) for k in range(10))
#: the incompressible neo-Hookean kappa_s of the same cap (material="nh", tol 1e-9), the
#: relaxed model's limit as lam -> infinity (the docs' validation page)
NH_LIMIT = 3.5093951206
HEADER = ["group", "model", "theta", "h", "lam", "T", "status", "kappa_s", "w_s",
          "error_estimate", "check_difference", "seconds", "nodes", "evaluations", "reason"]


def cases(quick: bool):
    out = []
    for model in ("relaxed", "plane_strain"):
        for lam in ((1.0, 1e4) if quick else LAMS):
            out.append(("material", model, THETA, H0, lam))
        for h in ((0.2,) if quick else HS):
            out.append(("thickness", model, THETA, h, LAM))
    for d in ((0.95,) if quick else DEPTHS):
        out.append(("depth", "relaxed", d * math.pi, H0, LAM))
    return out


class _Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise _Timeout


def _timed(seconds, f, *args, **kw):
    """f(*args, **kw) or _Timeout after ``seconds`` (SIGALRM: raised between host steps,
    so a compiled call in flight finishes first)."""
    signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(int(seconds))
    try:
        return f(*args, **kw)
    finally:
        signal.alarm(0)


def _short(exc) -> str:
    """The message without the Newton history it may carry."""
    return re.split(r";? *(?:Newton )?history", str(exc).splitlines()[0])[0]


def run_case(group, model, theta, h, lam, timeout):
    from shellbvp import ConvergenceError
    from shellbvp.problems import cap_eversion as ce

    T = theta / math.sqrt(h)
    row = dict(group=group, model=model, theta=theta, h=h, lam=lam, T=T, kappa_s=math.nan,
               w_s=math.nan, error_estimate=math.nan, check_difference=math.nan,
               seconds=math.nan, nodes="", evaluations="", reason="")
    t0 = time.perf_counter()
    try:
        r = _timed(timeout, ce.snap_curvature, theta, h, lam, model=model, tol=TOL)
    except _Timeout:
        return dict(row, status="timeout", seconds=time.perf_counter() - t0,
                    reason=f"no answer within {timeout:g} s")
    except (ConvergenceError, ValueError) as exc:
        return dict(row, status="failed", seconds=time.perf_counter() - t0,
                    reason=f"{type(exc).__name__}: {_short(exc)}")
    row.update(seconds=time.perf_counter() - t0, evaluations=r.stats.get("evaluations", ""))
    if not r.snaps:
        return dict(row, status="no snap", reason="no fold before full eversion")
    row.update(kappa_s=r.kappa_s, w_s=r.w_s, error_estimate=r.error_estimate,
               nodes=r.fold.system.describe().get("nodes", ""))
    check, why = None, ""
    for check_tol in CHECK_TOLS:      # the finest check the case allows
        try:
            check = _timed(timeout, ce.snap_curvature, theta, h, lam, model=model,
                           tol=check_tol)
            break
        except (_Timeout, ConvergenceError, ValueError) as exc:
            why += f"check at tol {check_tol:g}: {type(exc).__name__}: {_short(exc)}; "
    if check is None:
        return dict(row, status="unchecked", reason=why)
    diff = abs(check.kappa_s - r.kappa_s) if check.snaps else math.inf
    return dict(row, check_difference=diff,
                status="honest" if diff <= r.error_estimate else "WRONG")


def markdown(rows) -> str:
    def g(x, fmt):
        return "" if isinstance(x, str) or not math.isfinite(x) else format(x, fmt)

    lines = ["| group | model | Theta/pi | h | lam | T | status | kappa_s R0 | estimate | "
             "check diff | s | N | reason |", "|" + "---|" * 13]
    for r in rows:
        lines.append(
            f"| {r['group']} | {r['model']} | {r['theta'] / math.pi:.3g} | {r['h']:g} | "
            f"{r['lam']:g} | {r['T']:.3g} | {r['status']} | {g(r['kappa_s'], '.10g')} | "
            f"{g(r['error_estimate'], '.1e')} | {g(r['check_difference'], '.1e')} | "
            f"{g(r['seconds'], '.1f')} | {r['nodes']} | {r['reason']} |")
    return "\n".join(lines)


def plot(rows, out):
    """Three panels (material, thickness, depth): kappa_s with its status; the material
    panel with the incompressible neo-Hookean limit of the relaxed model."""
    plt = pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.9))
    spec = [("material", "lam", "lam = lambda*/mu*  (Theta = pi/6, h0/R0 = 0.01)", True),
            ("thickness", "h", "h0/R0  (Theta = pi/6, lam = 1)", True),
            ("depth", "T", "T = Theta sqrt(R0/h0)  (h0/R0 = 0.01, lam = 1)", False)]
    colors = {"relaxed": "C0", "plane_strain": "C1"}
    for ax, (group, x, label, logx) in zip(axes, spec):
        for model, color in colors.items():
            sel = [r for r in rows if r["group"] == group and r["model"] == model]
            if not sel:
                continue
            ok = [r for r in sel if r["status"] in ("honest", "unchecked")]
            ax.plot([r[x] for r in ok], [r["kappa_s"] for r in ok], "o-", color=color,
                    label=model.replace("_", " "))
            none = [r for r in sel if r["status"] == "no snap"]
            bad = [r for r in sel if r["status"] in ("failed", "timeout", "WRONG")]
            if none:
                ax.plot([r[x] for r in none], [0.0] * len(none), "x", color=color, ms=9,
                        label=f"{model.replace('_', ' ')}: no snap")
            if bad:
                ax.plot([r[x] for r in bad], [0.0] * len(bad), "s", color=color, mfc="none",
                        ms=9, label=f"{model.replace('_', ' ')}: clear failure")
        if group == "material":
            ax.axhline(NH_LIMIT, color="k", lw=0.8, ls=":", label="neo-Hookean (lam -> inf)")
        if logx:
            ax.set_xscale("log")
        ax.set_xlabel(label)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("kappa_s R0 (0: no snap / failure)")
    finish(fig, out, "extreme_cases")


def _read(path):
    import csv

    rows = []
    for r in csv.DictReader(open(path)):
        for k in ("theta", "h", "lam", "T", "kappa_s", "w_s", "error_estimate",
                  "check_difference", "seconds"):
            r[k] = float(r[k]) if r[k] not in ("", "nan") else math.nan
        rows.append(r)
    return rows


def main():
    from tqdm import tqdm

    p = parser(__doc__.splitlines()[0])
    p.add_argument("--timeout", type=float, default=300.0, help="seconds per case")
    p.add_argument("--replot", action="store_true",
                   help="draw the figure from extreme_cases.csv without computing")
    args = p.parse_args()
    if args.replot:
        plot(_read(args.out / "extreme_cases.csv"), args.out)
        return
    rows = []
    for c in tqdm(cases(args.quick), desc="extreme caps", unit="case"):
        rows.append(run_case(*c, args.timeout))
        tqdm.write(f"{c[0]} {c[1]} Theta/pi={c[2] / math.pi:.3g} h={c[3]:g} lam={c[4]:g}: "
                   f"{rows[-1]['status']} kappa_s={rows[-1]['kappa_s']:.10g} "
                   f"({rows[-1]['seconds']:.1f} s) {rows[-1]['reason']}")
    write_csv(args.out / "extreme_cases.csv", HEADER, [[r[k] for k in HEADER] for r in rows])
    plot(rows, args.out)
    print(markdown(rows))
    counts = {s: sum(r["status"] == s for r in rows) for s in
              ("honest", "no snap", "failed", "timeout", "unchecked", "WRONG")}
    print("counts:", counts)


if __name__ == "__main__":
    main()
