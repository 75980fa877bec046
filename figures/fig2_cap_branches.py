"""Fig. 2 of Taffetani & Pezzulla: branches kappa / kappa_s(Koiter) against the edge
displacement w/R0 of an everting cap, Theta = pi/6, h0/R0 = 0.01, lam in {0.01, 0.1, 1, 10},
(a) plane strain (rho1 = 1, rho2 = 0), (b) relaxed (rho1, rho2 minimising the energy).
kappa_s(Koiter) is the snap curvature of the morphoelastic Koiter shell (nu = 1/2) at the same
geometry; the maximum of each curve is its snap (marked). Writes fig2_cap_branches.png and
fig2_cap_branches.csv (every branch point, with energies; is_fold = 1 on the refined folds).

    python figures/fig2_cap_branches.py [--quick] [--h 0.01]
"""

from __future__ import annotations

import math

from tqdm import tqdm

from _common import finish, parser, pyplot, write_csv
from shellbvp.problems import cap_eversion as ce
import shellbvp

THETA = math.pi / 6
LAMS = (0.01, 0.1, 1.0, 10.0)


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--h", type=float, default=0.01, help="h0/R0 (default 0.01)")
    a = p.parse_args(argv)
    lams = (0.1, 10.0) if a.quick else LAMS
    koiter = ce.snap_curvature(THETA, a.h, material="koiter")
    H = 1.0 - math.cos(THETA)
    rows, folds = [], []
    cases = [(m, lam) for m in ("plane_strain", "relaxed") for lam in lams]
    for model, lam in tqdm(cases, desc="fig2 branches"):
        sc = ce.scene(THETA, a.h, lam, model=model)
        # Past the snap to w = 0.6 H, or until kappa falls back below 0.
        br = shellbvp.follow(sc, n_folds=1 if a.quick else None, p_stop=(0.0, math.inf),
                             w_stop=(-math.inf, 0.6 * H),
                             options=shellbvp.ContinuationOptions(ds=0.2, ds_max=2.0))
        for r in br.rows():
            rows.append([model, lam, *r, r[0] / koiter.kappa_s])
        folds += [(model, lam, f.p, f.w, f.error_estimate) for f in br.folds[:1]]
    write_csv(a.out / "fig2_cap_branches.csv",
              ["model", "lam", "kappa_R0", "w_over_R0", "energy", "stretching_energy",
               "bending_energy", "arclength", "is_fold", "kappa_over_kappa_s_koiter"], rows)

    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
    for ax, model, title in zip(axes, ("plane_strain", "relaxed"),
                                ("(a) plane strain", "(b) relaxed rho1, rho2")):
        for k, lam in enumerate(lams):
            sel = [r for r in rows if r[0] == model and r[1] == lam and not r[8]]
            ax.plot([r[3] for r in sel], [r[9] for r in sel], "-", color=f"C{k}",
                    label=f"lam = {lam:g}")
            for f in folds:
                if f[0] == model and f[1] == lam:
                    ax.plot(f[3], f[2] / koiter.kappa_s, "o", color=f"C{k}", ms=4)
        ax.axhline(1.0, color="k", lw=0.6, ls="--")
        ax.set_xlabel(r"$w / R_0$")
        ax.set_title(f"{title}, Theta = pi/6, h0/R0 = {a.h:g}", fontsize=9)
        ax.legend(fontsize=8)
    axes[0].set_ylabel(r"$\kappa / \kappa_s^{\rm Koiter}$"
                       f"  (kappa_s Koiter R0 = {koiter.kappa_s:.4f})")
    finish(fig, a.out, "fig2_cap_branches")
    for f in folds:
        print(f"{f[0]:>12s} lam = {f[1]:<5g} kappa_s R0 = {f[2]:.10f} +- {f[4]:.1e}  "
              f"w_s/R0 = {f[3]:.6f}  kappa_s/kappa_s(Koiter) = {f[2] / koiter.kappa_s:.4f}")
    print(f"Koiter (nu = 1/2): kappa_s R0 = {koiter.kappa_s:.10f} +- {koiter.error_estimate:.1e}")


if __name__ == "__main__":
    main()
