"""Fig. 3 revisited: where the everting caps of Fig. 3 actually snap, once non-axisymmetric
deformations are allowed.

Fig. 3 of Taffetani & Pezzulla (``fig3_snap_curve.py``) plots the axisymmetric snap
curvature kappa_s R0 (a fold of the axisymmetric branch) against T = Theta sqrt(R0/h0),
h0/R0 = 0.01. For T >= about 5 a bifurcation into n circumferential waves comes before that
fold (``symmetry_breaking.py``). Here, for every cap (T = 4 .. 10 in steps of 0.5; curves
Koiter nu = 1/2 and relaxed CG lam = 1, with ``--all`` also relaxed CG lam = 0.01, 0.1, 10):

* the first instability along the branch from kappa = 0 (``cap_eversion.first_instability``):
  the axisymmetric fold or a bifurcation into n waves, kappa_first with its error estimate;
* at a bifurcation, the start of the lobed branch (``shellbvp.follow_bifurcation`` for two
  continuation steps): Koiter's p2 and b, the kind, and p_c in the 2D discretisation with
  its error (the change on the finer one). Subcritical: the cap snaps at the bifurcation,
  kappa_snap = p_c (its lobed branch is not followed further). Supercritical: the cap
  wrinkles into n lobes; the lobed branch is followed to its first fold, where it snaps
  (kappa_snap with its error); where the branch ends before a fold, its stop reason is
  recorded and there is no kappa_snap. Where the finer discretisation's relocation of that
  fold fails, the branch is followed again without it (status ``no error estimate``);
* where the axisymmetric fold comes first, kappa_snap is that fold.

kappa_s_axisymmetric is Fig. 3's value at the same T (``fig3_snap_curve.csv``, linear
interpolation between its caps where T is not one of them). A cap whose computation fails
is a row with status ``failed`` and the reason, not a crash. The CSV is rewritten after
every cap (an interrupted run keeps the caps finished).

Writes fig3_revisited.csv and fig3_revisited.png (top: kappa_s of Fig. 3 as lines, the
actual snap as markers by mechanism, annotated with n; bottom: kappa_snap / kappa_s).

    python figures/fig3_revisited.py [--quick] [--all] [--out DIR] [--plot-only]
"""

from __future__ import annotations

import csv
import math
import time

import numpy as np
from tqdm import tqdm

from _common import HERE, finish, parser, pyplot, write_csv
import shellbvp
from shellbvp import postbuckling as pb
from shellbvp.problems import cap_eversion as ce

H0 = 0.01
CURVES = (("koiter", 1.0), ("cg", 1.0))
MORE = (("cg", 0.01), ("cg", 0.1), ("cg", 10.0))
T_VALUES = tuple(np.round(np.arange(4.0, 10.001, 0.5), 10))
QUICK = ((("cg", 1.0),), (4.0, 6.0, 9.0))
SNAP_CSV = HERE / "fig3_snap_curve.csv"
#: the lobed branch's first points only: Koiter's kind, p_c and its error (a subcritical
#: cap snaps at p_c; its lobed branch is not needed)
START = pb.LOBED_OPTIONS.with_(max_steps=2)

HEADER = ["material", "lam", "T", "theta_rad", "first", "n", "kappa_first",
          "kappa_first_error", "kind", "p2", "b", "kappa_c_2d", "kappa_c_2d_error",
          "snap_via", "kappa_snap", "kappa_snap_error", "lobed_fold_amplitude", "lobed_points",
          "kappa_s_axisymmetric", "kappa_s_axisymmetric_error", "stop", "status", "reason",
          "seconds"]


def axisymmetric_snap(path=SNAP_CSV) -> dict:
    """{(material, lam): (T, kappa_s, error)} of Fig. 3's caps that snap."""
    out = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            if r["snaps"] != "1" or not math.isfinite(float(r["kappa_s_R0"])):
                continue
            out.setdefault((r["material"], float(r["lam"])), []).append(
                (float(r["T"]), float(r["kappa_s_R0"]), float(r["kappa_s_error"])))
    return {k: tuple(np.array(c) for c in zip(*sorted(v))) for k, v in out.items()}


def kappa_s_at(table, material, lam, T):
    """(kappa_s, error) of Fig. 3 at T: the cap itself, else linear interpolation (error
    NaN), NaN outside the curve."""
    if (material, lam) not in table:
        return math.nan, math.nan
    Ts, ks, es = table[(material, lam)]
    hit = np.flatnonzero(np.abs(Ts - T) < 1e-9)
    if hit.size:
        return float(ks[hit[0]]), float(es[hit[0]])
    if not Ts[0] <= T <= Ts[-1]:
        return math.nan, math.nan
    return float(np.interp(T, Ts, ks)), math.nan


def one_line(exc) -> str:
    return f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}"[:300]


def cap(material, lam, T, bar=None) -> dict:
    """The row of one cap (module docstring); failures are rows, not exceptions."""
    theta = T * math.sqrt(H0)
    r = {"material": material, "lam": lam, "T": T, "theta_rad": theta, "first": "",
         "n": -1, "kappa_first": math.nan, "kappa_first_error": math.nan, "kind": "",
         "p2": math.nan, "b": math.nan, "kappa_c_2d": math.nan, "kappa_c_2d_error": math.nan,
         "snap_via": "", "kappa_snap": math.nan, "kappa_snap_error": math.nan,
         "lobed_fold_amplitude": math.nan, "lobed_points": 0, "stop": "", "status": "ok",
         "reason": ""}
    stage = (lambda s: bar.set_postfix_str(f"{material} lam={lam:g} T={T:g}: {s}")) \
        if bar is not None else (lambda s: None)
    stage("first_instability")
    try:
        ins = ce.first_instability(theta, H0, lam, material=material)
    except Exception as exc:  # noqa: BLE001 - recorded, the sweep goes on
        r.update(first="failed", status="failed", reason=f"first_instability: {one_line(exc)}")
        return r
    r.update(first=ins.kind, n=ins.n, kappa_first=ins.p, kappa_first_error=ins.error_estimate)
    if ins.kind == "fold":
        r.update(snap_via="axisymmetric fold", kappa_snap=ins.p,
                 kappa_snap_error=ins.error_estimate)
        return r
    if ins.kind != "bifurcation":
        r.update(snap_via="none", stop=ins.stop, status="no instability")
        return r
    # Koiter's kind and p_c (with its error on the finer discretisation) from the lobed
    # branch's first points; only a supercritical cap's branch is followed on, to its fold
    stage(f"bifurcation n={ins.n}: Koiter")
    try:
        br = shellbvp.follow_bifurcation(ins, options=START)
    except Exception as exc:  # noqa: BLE001
        r.update(status="failed", reason=f"follow_bifurcation (start): {one_line(exc)}")
        return r
    k = br.koiter
    r.update(kind=k.kind, p2=k.p2, b=k.b, kappa_c_2d=br.p_c, kappa_c_2d_error=br.p_c_error,
             lobed_points=len(br.p))
    if k.kind == "subcritical":
        r.update(snap_via="subcritical bifurcation", kappa_snap=br.p_c,
                 kappa_snap_error=br.p_c_error,
                 stop="subcritical: snaps at the bifurcation, lobed branch not followed")
        return r
    stage(f"follow_bifurcation n={ins.n}")
    steps = [0]

    def progress(_pt):
        steps[0] += 1
        if steps[0] % 10 == 0:
            stage(f"follow_bifurcation n={ins.n}, {steps[0]} points")

    try:
        br = shellbvp.follow_bifurcation(ins, progress=progress)
    except Exception as exc:  # noqa: BLE001
        r.update(status="failed", reason=f"follow_bifurcation: {one_line(exc)}")
        # the error estimate (finer discretisation) may be what failed: the values without it
        stage(f"follow_bifurcation n={ins.n} again, no error estimate")
        try:
            br = shellbvp.follow_bifurcation(ins, estimate_error=False)
        except Exception as exc2:  # noqa: BLE001
            r["reason"] += f"; again without the error estimate: {one_line(exc2)}"
            return r
        r["status"] = "no error estimate"
    r.update(lobed_points=len(br.p), stop=br.stop)
    if br.folds:
        fo = br.folds[0]
        r.update(snap_via="lobed fold", kappa_snap=fo.p, kappa_snap_error=fo.error_estimate,
                 lobed_fold_amplitude=fo.amplitude)
    else:
        r.update(snap_via="lobed branch ends without a fold")
    return r


def read_rows(path) -> list:
    """The rows of a fig3_revisited.csv, typed as :func:`cap` makes them."""
    ints, texts = {"n", "lobed_points"}, {"material", "first", "kind", "snap_via", "stop",
                                          "status", "reason"}
    with open(path, newline="") as f:
        return [{k: (v if k in texts else int(v) if k in ints else float(v))
                 for k, v in r.items()} for r in csv.DictReader(f)]


def plot(rows, curves, out, title_extra=""):
    plt = pyplot()
    table = axisymmetric_snap()
    fig, (ax, ax2) = plt.subplots(2, 1, figsize=(7.5, 7.2), sharex=True,
                                  gridspec_kw={"height_ratios": (2.2, 1)})
    style = {"axisymmetric fold": {"marker": "o", "mfc": "none", "ms": 6},
             "subcritical bifurcation": {"marker": "v", "ms": 6},
             "lobed fold": {"marker": "s", "ms": 6}}
    T_lo = min(r["T"] for r in rows) - 0.5
    for k, (material, lam) in enumerate(curves):
        col = "k" if material == "koiter" else f"C{k}"
        label = "Koiter, nu = 1/2" if material == "koiter" else f"relaxed CG, lam = {lam:g}"
        if (material, lam) in table:
            Ts, ks, _ = table[(material, lam)]
            keep = Ts >= T_lo
            ax.plot(Ts[keep], ks[keep], "-", color=col, lw=1.2,
                    label=f"{label}: axisymmetric $\\kappa_s$ (Fig. 3)")
        sel = [r for r in rows if r["material"] == material and r["lam"] == lam]
        for r in sel:
            if r["snap_via"] in style and math.isfinite(r["kappa_snap"]):
                ax.plot(r["T"], r["kappa_snap"], ls="none", color=col, mec=col,
                        **style[r["snap_via"]])
                if r["n"] > 0:
                    ax.annotate(str(r["n"]), (r["T"], r["kappa_snap"]),
                                textcoords="offset points", xytext=(0, -14 if
                                material == "koiter" else 7), ha="center", fontsize=7,
                                color=col, bbox={"boxstyle": "square,pad=0.05", "fc": "w",
                                      "ec": "none", "alpha": 0.8})
                if math.isfinite(r["kappa_s_axisymmetric"]):
                    ax2.plot(r["T"], r["kappa_snap"] / r["kappa_s_axisymmetric"], ls="none",
                             color=col, mec=col, **style[r["snap_via"]])
            elif r["first"] == "bifurcation" and math.isfinite(r["kappa_first"]):
                # bifurcation known but no snap value (supercritical without a fold, failure)
                ax.plot(r["T"], r["kappa_first"], "x", color=col, ms=7)
            elif r["status"] == "failed" and math.isfinite(r["kappa_s_axisymmetric"]):
                ax.plot(r["T"], r["kappa_s_axisymmetric"], "x", color="r", ms=8, mew=1.5)
        ratio = [(r["T"], r["kappa_snap"] / r["kappa_s_axisymmetric"]) for r in sel
                 if r["snap_via"] in style and math.isfinite(r["kappa_snap"])
                 and math.isfinite(r["kappa_s_axisymmetric"])]
        if ratio:
            ax2.plot(*zip(*ratio), "-", color=col, lw=0.6)
    present = {r["snap_via"] for r in rows if math.isfinite(r["kappa_snap"])}
    for via, label in (("axisymmetric fold", "snap: axisymmetric fold first"),
                       ("subcritical bifurcation", "snap: subcritical bifurcation (n marked)"),
                       ("lobed fold", ("snap: fold of the supercritical n-lobed branch "
                                      "(n marked)"))):
        if via in present:
            ax.plot([], [], ls="none", color="k", label=label, **style[via])
    if any(r["first"] == "bifurcation" and not math.isfinite(r["kappa_snap"]) for r in rows):
        ax.plot([], [], "kx", label="bifurcation, no snap found (see CSV)")
    if any(r["status"] == "failed" and r["first"] != "bifurcation" for r in rows):
        ax.plot([], [], "rx", mew=1.5, label="computation failed (at Fig. 3's $\\kappa_s$; "
                                             "see CSV)")
    ax.set_ylabel(r"$\kappa R_0$")
    ax.set_title(f"everting caps, h0/R0 = {H0:g}: axisymmetric snap (lines) vs actual snap "
                 f"(markers){title_extra}", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(alpha=0.3)
    ax2.axhline(1.0, color="0.5", lw=0.6)
    ax2.set_ylabel(r"$\kappa_{snap} / \kappa_s$")
    ax2.set_xlabel(r"$T = \Theta\sqrt{R_0/h_0}$")
    ax2.grid(alpha=0.3)
    finish(fig, out, "fig3_revisited")


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--all", action="store_true",
                   help="also relaxed CG lam = 0.01, 0.1, 10 (Fig. 3's other curves)")
    p.add_argument("--plot-only", action="store_true",
                   help="redraw the PNG from the CSV in --out (no computation)")
    a = p.parse_args(argv)
    if a.plot_only:
        rows = read_rows(a.out / "fig3_revisited.csv")
        curves = tuple(dict.fromkeys((r["material"], r["lam"]) for r in rows))
        plot(rows, curves, a.out)
        return
    if a.quick:
        curves, Ts = QUICK
    else:
        curves, Ts = (CURVES + MORE if a.all else CURVES), T_VALUES
    table = axisymmetric_snap()
    jobs = [(m, lam, T) for m, lam in curves for T in Ts]
    rows, t0 = [], time.perf_counter()
    bar = tqdm(jobs, desc="fig3 revisited", unit="cap")
    for material, lam, T in bar:
        t = time.perf_counter()
        r = cap(material, lam, float(T), bar)
        r["kappa_s_axisymmetric"], r["kappa_s_axisymmetric_error"] = \
            kappa_s_at(table, material, lam, float(T))
        r["seconds"] = round(time.perf_counter() - t, 1)
        rows.append(r)
        tqdm.write(f"{material:>6s} lam={lam:<4g} T={T:<4g} {r['first']:<11s} n={r['n']:<2d} "
                   f"{r['kind'] or '-':<13s} snap {r['snap_via'] or '-'}: "
                   f"{r['kappa_snap']:.8g} +- {r['kappa_snap_error']:.1e} "
                   f"(axisym. {r['kappa_s_axisymmetric']:.8g}) {r['seconds']:.0f} s"
                   + (f" [{r['status']}: {r['reason']}]" if r["status"] != "ok" else ""))
        write_csv(a.out / "fig3_revisited.csv", HEADER, [[x[c] for c in HEADER] for x in rows])
    total = time.perf_counter() - t0
    plot(rows, curves, a.out)
    bad = [r for r in rows if r["status"] != "ok"]
    print(f"{len(rows)} caps in {total:.0f} s; {len(bad)} not ok")
    for r in bad:
        print(f"  {r['material']} lam={r['lam']:g} T={r['T']:g}: {r['status']}: {r['reason']}")


if __name__ == "__main__":
    main()
