"""Beyond the paper: where everting caps leave axisymmetry.

For the caps of Fig. 3 (h = 0.01, relaxed CG with lam = 0.01, 0.1, 1, 10, and the Koiter
reference shell with nu = 1/2) and T = Theta sqrt(R0/h0) from 1.5 to 10: the first
instability along the branch from kappa = 0 (``cap_eversion.first_instability``): the
axisymmetric snap (a fold, kappa_s) or a bifurcation into n circumferential waves before it,
with kappa R0 and n. The cap is free: its rigid motions are excluded, not held. Drawn as a
phase diagram in (T, kappa R0): the first instability of every cap, marked by its kind and
n; caps with no instability up to full eversion are marked on the T axis.

Writes symmetry_breaking.png and symmetry_breaking.csv.

    python figures/symmetry_breaking.py [--quick]
"""

from __future__ import annotations

import math
import time

from tqdm import tqdm

from _common import finish, parser, pyplot, write_csv
import shellbvp
from shellbvp.problems import cap_eversion as ce

H0 = 0.01
CURVES = (("koiter", 1.0), ("cg", 0.01), ("cg", 0.1), ("cg", 1.0), ("cg", 10.0))
T_VALUES = (1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0, 6.0, 8.0, 10.0)


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    curves = (("cg", 1.0),) if a.quick else CURVES
    Ts = (2.5, 3.0) if a.quick else T_VALUES
    rows, t0 = [], time.perf_counter()
    for material, lam in curves:
        kw = dict(material="koiter") if material == "koiter" else dict(lam=lam)
        for T in tqdm(Ts, desc=f"{material} lam={lam:g}", unit="cap"):
            try:
                inst = ce.first_instability(T * math.sqrt(H0), H0, **kw)
                rows.append([material, lam, T, inst.kind, inst.n, inst.p, inst.error_estimate,
                             inst.w, inst.cutoff, ""])
            except shellbvp.ConvergenceError as exc:
                rows.append([material, lam, T, "failed", -1, math.nan, math.nan, math.nan, -1,
                             str(exc).splitlines()[0][:200]])
            r = rows[-1]
            print(f"{material} lam={lam:g} T={T:g}: {r[3]} n={r[4]} kappa={r[5]:.6g} "
                  f"+- {r[6]:.1e} {r[9]}")
    print(f"{len(rows)} caps in {time.perf_counter() - t0:.0f} s")
    write_csv(a.out / "symmetry_breaking.csv",
              ["material", "lam", "T", "kind", "n", "kappa_R0", "kappa_error", "w_over_R0",
               "harmonics_scanned_to", "reason"], rows)

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for k, (material, lam) in enumerate(curves):
        sel = [r for r in rows if r[0] == material and r[1] == lam]
        label = "Koiter" if material == "koiter" else f"relaxed CG, lam = {lam:g}"
        col = f"C{k}"
        ax.plot([r[2] for r in sel if r[3] in ("fold", "bifurcation")],
                [r[5] for r in sel if r[3] in ("fold", "bifurcation")], "-", color=col, lw=0.8,
                label=label)
        for r in sel:
            if r[3] == "fold":
                ax.plot(r[2], r[5], "o", mfc="none", color=col)
            elif r[3] == "bifurcation":
                ax.plot(r[2], r[5], "s", color=col)
                ax.annotate(str(r[4]), (r[2], r[5]), textcoords="offset points",
                            xytext=(4, 3), fontsize=7, color=col)
            elif r[3] == "none":
                ax.plot(r[2], 0.0, "x", color=col)
    ax.plot([], [], "ks", label="bifurcation (n marked)")
    ax.plot([], [], "ko", mfc="none", label="axisymmetric snap first")
    ax.plot([], [], "kx", label="none up to full eversion")
    ax.set_xlabel(r"$T = \Theta\sqrt{R_0/h_0}$")
    ax.set_ylabel(r"first instability $\kappa R_0$")
    ax.set_title(f"everting free caps, h = {H0:g}: first instability", fontsize=10)
    ax.legend(fontsize=7)
    finish(fig, a.out, "symmetry_breaking")


if __name__ == "__main__":
    main()
