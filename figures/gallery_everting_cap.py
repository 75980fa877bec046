"""Gallery: the paper's everting spherical cap, the shallowness below which it does not snap,
against what Taffetani & Pezzulla state: "no snapping for Theta sqrt(R0/h0) <~ 3.1".

The shell (the paper's Section 5.2, "Eversion of a cap"): a spherical cap of radius R0,
opening half-angle Theta, thickness h0, apex held, edge free, everted by a uniform curvature
stimulus kappa (paper eq. (stimulus): abar = a°, bbar = b° + kappa a°, no through-thickness
stimulus); it snaps at the first fold kappa_s of its branch from kappa = 0. Dimensionless as
the paper: lengths in R0, moduli in mu* (no physical units enter). Material: the paper's
Ciarlet-Geymonat reduction, relaxed (rho1, rho2 minimising the energy: the model of its
Fig. 2(b) and Fig. 3), lam = lambda*/mu* = 0.01, 0.1, 1, 10 (Fig. 3's curves). The
morphoelastic Koiter shell with nu = 1/2 (Fig. 3's solid line, Pezzulla et al. 2018) is
drawn beside it from ``figures/fig3_onset.csv`` and ``fig3_snap_curve.csv`` (computed
there by the same functions; not recomputed here, where its compilation would add ~10 s). Thickness uniform, h0/R0 = 0.01: the paper does not state h0/R0 for
Section 5.2 (the value is that of this repository's Fig. 2 and Fig. 3 scripts); the
rescaled shallowness T = Theta sqrt(R0/h0) is the paper's own variable because it removes
h0 in the shallow limit, and the onset below moves by 2e-3 between h0/R0 = 0.01 and 1e-3
(1.9243 and 1.9224, lam = 1, measured once while writing this case; not part of the run).

Published (``figures/gallery/everting-cap_published.csv``), the paper's only stated number
for the cap: Section 5.2, the paragraph on Fig. 3 (``fig:cap_abgeneral``): "our model (i)
recovers the absence of snapping for shallow shells, in rescaled form,
Theta (h0^-1 R0)^(1/2) <~ 3.1". The figures' data are not in the paper's source (its
includegraphics are empty), so no kappa_s value can be read from Fig. 2 or Fig. 3; the two
qualitative statements of the section are checked and reported too (not part of ``ok``):
relaxed caps with Theta = pi/6 snap for every lam (Fig. 2(b)), and "snap-through requires a
larger natural curvature in more compressible material" (Fig. 3: kappa_s decreasing in lam).

Quantity: the onset of snapping T_c, the smallest T at which the branch has a fold, computed
by ``shellbvp.problems.cap_eversion.onset`` (the cusp of the fold curve, where the snap fold
and its mirror meet at the flat state w = H; the fold system solved with T unknown). That
is why the script uses the problems module and not a scene file: in a scene file the
geometry is data and T cannot be an unknown. The headline is lam = 1 (the paper's Fig. 2
material); ``ok`` asks all four relaxed curves to be within tolerance, since the paper
states one threshold for the model. The scene file ``problems/gallery/everting-cap.toml``
is the direct test of the statement: the relaxed lam = 1 cap at T = 2.5 (Theta = 0.25),
inside the range where the paper says there is no snap, followed from kappa = 0 through its
first two folds; ``snaps_below_3_1`` reports whether it has them.

Tolerance: 0.05 in T, half a unit of the last digit the paper prints (relative 0.05 / 3.1 =
1.6 %), fixed from the statement alone. The paper states no mesh or resolution for its
COMSOL computations, nor how the threshold was read (the "<~" says it is approximate), so
its digits are the only precision it gives; a looser reading (anywhere in 3.0-3.2) would not
change the verdict. Ours carry error estimates of ~1e-6 (the change with the next Chebyshev
degree plus the solver tolerance).

Cost: 48 to 80 s of one core on this machine (the four onsets about two thirds of it, most
of that compiling the fold-curve system; the scene file ~15 s; the Theta = pi/6 checks
< 1 s), up to 110 s measured while other jobs shared the two cores: over the gallery's
~60 s aim, kept because the four onsets are the paper's claim; ``--quick`` (lam = 1 and the
scene file) ~35 s.

    python figures/gallery_everting_cap.py [--quick]
"""

from __future__ import annotations

import csv
import math
import sys
import time

import numpy as np
from _common import HERE, finish, parser, print_summary, pyplot, write_csv

ROOT = HERE.parent
SCENE = ROOT / "problems" / "gallery" / "everting-cap.toml"
PUBLISHED = HERE / "gallery" / "everting-cap_published.csv"
FIG3_CSV = HERE / "fig3_snap_curve.csv"          # context curves only (fig3_snap_curve.py)
ONSET_CSV = HERE / "fig3_onset.csv"               # context: the Koiter shell's onset
H0 = 0.01                                         # h0 / R0
LAMS = (0.01, 0.1, 1.0, 10.0)                     # Fig. 3's relaxed curves
HEAD_LAM = 1.0
THETA_SCENE, T_SCENE = 0.25, 2.5                  # the scene file's cap
SOURCE = ("Taffetani & Pezzulla, Section 5.2 (text on Fig. 3): no snapping for "
          "Theta sqrt(R0/h0) <~ 3.1")


def read_published() -> dict:
    """{item: row} from the published CSV."""
    with open(PUBLISHED, newline="") as f:
        return {r["item"]: r for r in csv.DictReader(f)}


def tolerance(T_pub: float) -> float:
    """Half a unit of the printed last digit (0.05 in T), relative to the printed value."""
    return 0.05 / T_pub


def follow_scene():
    """The scene file's branch (a SceneBranch) through its first two folds."""
    import shellbvp

    sf = shellbvp.load_scene(SCENE)
    return sf, sf.follow()


def flat_state(sf):
    """kappa R0 and dkappa/dw at the flat state w = H of the scene file's cap (the edge level
    with the apex), by continuation from kappa = 0 with w prescribed there
    (:func:`shellbvp.at_monitor`): by the mirror symmetry (kappa, w) -> (2 - kappa, 2H - w)
    kappa is exactly 1 there, and dkappa/dw < 0 means the branch has a fold pair around it."""
    import shellbvp

    H = 1.0 - math.cos(THETA_SCENE)
    m = shellbvp.at_monitor(sf.scene, H / sf.units.length)
    return float(m.p * sf.scale), float(m.dp_dw * sf.scale / sf.units.length)


def run(quick: bool = False) -> dict:
    """The onsets (lam = 1 only if ``quick``), the scene file's branch, the qualitative
    checks; the summary and curves."""
    from shellbvp.problems import cap_eversion as ce

    t0 = time.perf_counter()
    pub = read_published()
    T_pub = float(pub["T_onset"]["value"])
    tol = tolerance(T_pub)

    onsets = {}
    for lam in ((HEAD_LAM,) if quick else LAMS):
        o = ce.onset(H0, lam)
        onsets[f"cg lam={lam:g}"] = {"lam": lam, "T_c": o.T, "error_estimate": o.error_estimate,
                                     "kappa_at_cusp": o.kappa,
                                     "difference": o.T / T_pub - 1}
    koiter = read_koiter_onset(T_pub)
    head = onsets[f"cg lam={HEAD_LAM:g}"]
    ok = all(abs(v["difference"]) <= tol for v in onsets.values())

    # the direct test: the scene file's cap at T = 2.5 < 3.1
    sf, b = follow_scene()
    ik, iw = (b.columns.index(c) for c in ("kappa", "w_edge[length]"))
    branch = np.array([[r[ik], r[iw]] for r in b.rows])     # points and folds, in order
    folds = [{"kappa_R0": f["p"], "w_edge_over_R0": f["w_edge"],
              "error_estimate": f["p_error"]} for f in b.folds]
    snaps = len(b.folds) >= 1
    H = 1.0 - math.cos(THETA_SCENE)
    scene_check = {"T": T_SCENE, "theta": THETA_SCENE, "h0_over_R0": sf.units.thickness,
                   "lam": HEAD_LAM, "folds": folds, "snaps": snaps, "stop": b.stop}
    if len(b.folds) >= 2:
        scene_check["fold_sum_minus_2"] = b.folds[0]["p"] + b.folds[1]["p"] - 2.0

    statements = None
    if not quick:
        # the paper's qualitative statements at Theta = pi/6 (Fig. 2(b), Fig. 3 text)
        ks = {lam: ce.snap_curvature(math.pi / 6, H0, lam, tol=1e-8) for lam in LAMS}
        values = [ks[lam].kappa_s for lam in LAMS]
        statements = {
            "kappa_s_R0_theta_pi_6": {f"cg lam={lam:g}": ks[lam].kappa_s for lam in LAMS},
            "relaxed_snaps_every_lam": all(ks[lam].snaps for lam in LAMS),
            "kappa_s_decreasing_in_lam": bool(np.all(np.diff(values) < 0)),
        }

    return {"case": "everting-cap", "source": SOURCE,
            "quantity": "onset of snapping T_c = Theta sqrt(R0/h0), relaxed CG lam = 1, "
                        "h0/R0 = 0.01 " + ("(quick: lam = 1 only)" if quick
                                           else "(lam = 0.01, 0.1, 10 also in ok)"),
            "published": T_pub, "shellbvp": head["T_c"], "difference": head["difference"],
            "tolerance": tol, "ok": bool(ok), "seconds": time.perf_counter() - t0,
            "onsets": onsets, "koiter_onset": koiter,
            "snaps_below_3_1": scene_check, "paper_statements": statements,
            "curves": {"branch_kappa": branch[:, 0].tolist(),
                       "branch_w_over_H": (branch[:, 1] / H).tolist(),
                       "folds": folds, "H": H}}


def read_koiter_onset(T_pub: float) -> dict | None:
    """Context: the Koiter shell's onset (Fig. 3's solid line) as figures/fig3_onset.csv
    gives it (computed there by the same ``onset``; not recomputed here, to keep the case
    short), or None if the file is absent."""
    if not ONSET_CSV.exists():
        return None
    with open(ONSET_CSV, newline="") as f:
        for r in csv.DictReader(f):
            if r["material"] == "koiter":
                T = float(r["T_onset"])
                return {"T_c": T, "error_estimate": float(r["T_onset_error"]),
                        "difference": T / T_pub - 1, "from": ONSET_CSV.name}
    return None


def read_fig3() -> dict:
    """Context: the kappa_s(T) curves of figures/fig3_snap_curve.csv, {label: (T, kappa_s)}
    ({} if the file is absent)."""
    if not FIG3_CSV.exists():
        return {}
    out = {}
    with open(FIG3_CSV, newline="") as f:
        for r in csv.DictReader(f):
            if r["snaps"] != "1":
                continue
            key = "koiter" if r["material"] == "koiter" else f"cg lam={float(r['lam']):g}"
            T, k = out.setdefault(key, ([], []))
            T.append(float(r["T"]))
            k.append(float(r["kappa_s_R0"]))
    return out


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    r = run(a.quick)
    c = r["curves"]
    rows = [["onset", k, v["lam"], v["T_c"], v["error_estimate"], r["published"],
             v["difference"], r["tolerance"]] for k, v in r["onsets"].items()]
    if r["koiter_onset"]:
        ko = r["koiter_onset"]
        rows.append(["onset", "koiter nu=0.5", "", ko["T_c"], ko["error_estimate"],
                     r["published"], ko["difference"], ""])
    for f in c["folds"]:
        rows.append(["fold at T=2.5 (scene file)", "cg lam=1", 1.0, f["kappa_R0"],
                     f["p_error"], "", "", ""])
    if r["paper_statements"]:
        for k, v in r["paper_statements"]["kappa_s_R0_theta_pi_6"].items():
            rows.append(["kappa_s at Theta=pi/6", k, "", v, "", "", "", ""])
    rows += [["branch T=2.5 (kappa, w/H)", "cg lam=1", 1.0, k, w, "", "", ""]
             for k, w in zip(c["branch_kappa"], c["branch_w_over_H"])]
    write_csv(a.out / "gallery_everting_cap.csv",
              ["row", "model", "lam", "value", "error_or_w_over_H", "published_T_onset",
               "relative_difference", "tolerance"], rows)

    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11.5, 4.6))
    T_pub = r["published"]
    ax.axvspan(0, T_pub, color="C3", alpha=0.07)
    ax.axvspan(T_pub - 0.05, T_pub + 0.05, color="C3", alpha=0.25,
               label=f"paper: no snap for T <~ {T_pub:g} (+-0.05)")
    fig3 = read_fig3()
    colours = {f"cg lam={lam:g}": f"C{k}" for k, lam in enumerate(LAMS)} | {"koiter": "k"}
    for key, (T, k) in fig3.items():
        ax.plot(T, k, "-", color=colours.get(key, "gray"), lw=1.0 if key != "koiter" else 1.4,
                alpha=0.8)
    onsets = dict(r["onsets"])
    if r["koiter_onset"]:
        onsets["koiter"] = r["koiter_onset"]
    for key, v in onsets.items():
        label = ("Koiter nu = 1/2 (fig3_onset.csv)" if key == "koiter"
                 else key.replace("cg ", "relaxed CG, ")) + f": T_c = {v['T_c']:.3f}"
        ax.plot([v["T_c"]], [1.0], "o", color=colours.get(key, "gray"), ms=6, mfc="white",
                mew=1.5, label=label)
    f1 = c["folds"][0] if c["folds"] else None
    if f1:
        ax.plot([T_SCENE], [f1["kappa_R0"]], "*", color="C2", ms=13, mec="k",
                label=f"scene file, T = {T_SCENE:g}: snaps at kappa R0 = {f1['kappa_R0']:.4f}")
    ax.set_xlim(1.5, 6.0)
    ax.set_ylim(0.5, 5.0)
    ax.set_xlabel(r"shallowness $T = \Theta\sqrt{R_0/h_0}$")
    ax.set_ylabel(r"snap curvature $\kappa_s R_0$")
    ax.set_title("onset of snapping (circles, at the cusp kappa R0 = 1); lines: "
                 "fig3_snap_curve.csv", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    ax.grid(alpha=0.3)

    bx.plot(c["branch_w_over_H"], c["branch_kappa"], "-", color="k", lw=1.5,
            label="shellbvp, scene file (relaxed CG, lam = 1)")
    for k, f in enumerate(c["folds"]):
        bx.plot([f["w_edge_over_R0"] / c["H"]], [f["kappa_R0"]], "o", color="C3", ms=6,
                label="folds" if k == 0 else None)
        bx.annotate(f"{('snap', 'return fold')[min(k, 1)]}: kappa R0 = {f['kappa_R0']:.6f}",
                    (f["w_edge_over_R0"] / c["H"], f["kappa_R0"]), textcoords="offset points",
                    xytext=(8, 6) if k == 0 else (-40, -16), fontsize=8)
    bx.set_ylim(-0.05, 1.75)
    bx.axhline(1.0, color="gray", lw=0.6, ls=":")
    bx.axvline(1.0, color="gray", lw=0.6, ls=":")
    bx.set_xlabel("edge displacement $w / H$ (H the rise; 1: flat, 2: everted)")
    bx.set_ylabel(r"curvature stimulus $\kappa R_0$")
    bx.set_title(f"the cap at T = {T_SCENE:g} (Theta = {THETA_SCENE:g}, h0/R0 = {H0:g}): "
                 "a fold pair, a snap", fontsize=9)
    bx.legend(fontsize=8, loc="lower center")
    bx.grid(alpha=0.3)
    fig.suptitle(f"Everting cap (Taffetani & Pezzulla, Section 5.2): onset of snapping, "
                 f"paper <~ {T_pub:g}, shellbvp {r['shellbvp']:.4f} (lam = 1)", fontsize=10)
    finish(fig, a.out, "gallery_everting_cap")
    print_summary(r)


if __name__ == "__main__":
    sys.exit(main())
