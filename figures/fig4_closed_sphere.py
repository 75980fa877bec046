"""Fig. 4 of Taffetani & Pezzulla: homogeneous radius change w_R/R0 of a closed sphere
against the curvature stimulus kappa R0 — plane strain for lam = 100 (deflates) and lam = 0.1
(inflates), plus the relaxed model; numerical roots (markers/lines) and the symbolic series
(dashed). Writes fig4_closed_sphere.png and fig4_closed_sphere.csv.

    python figures/fig4_closed_sphere.py [--quick] [--h 0.01]
"""

from __future__ import annotations

import numpy as np
from tqdm import tqdm

from _common import finish, parser, pyplot, write_csv
from shellbvp.problems import closed_sphere as cs


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--h", type=float, default=0.01, help="h0/R0 (default 0.01)")
    a = p.parse_args(argv)
    kappas = np.linspace(0.0, 2.0, 5 if a.quick else 41)
    cases = [(m, lam) for m in ("plane_strain", "relaxed") for lam in (100.0, 0.1)]
    rows = []
    for model, lam in tqdm(cases, desc="fig4 cases"):
        w = 0.0
        for k in kappas:
            r = cs.equilibrium(k, h=a.h, lam=lam, model=model, guess=w)
            w = r.w_over_R0
            rows.append([k, lam, model, w, cs.series_value(k, h=a.h, lam=lam, model=model),
                         r.error_estimate])
    write_csv(a.out / "fig4_closed_sphere.csv",
              ["kappa_R0", "lam", "model", "w_over_R0", "w_series_over_R0", "w_error_estimate"],
              rows)

    plt = pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(10, 4))
    for ax, model, title in zip(axes, ("plane_strain", "relaxed"),
                                ("(a) plane strain: rho1 = 1, rho2 = 0", "(b) relaxed: rho1, rho2 minimising w_s, w_b")):
        for lam, color in ((100.0, "C0"), (0.1, "C3")):
            sel = [r for r in rows if r[2] == model and r[1] == lam]
            k = np.array([r[0] for r in sel])
            ax.plot(k, [r[3] for r in sel], "-", color=color, label=f"lam = {lam:g} (root of dW/dw)")
            ax.plot(k, [r[4] for r in sel], "--", color="k", lw=0.8)
        ax.plot([], [], "--", color="k", lw=0.8, label="symbolic series, order 2")
        ax.axhline(0, color="0.7", lw=0.5)
        ax.set_xlabel(r"$\kappa R_0$")
        ax.set_ylabel(r"$w_R / R_0$")
        ax.set_title(f"{title}, h0/R0 = {a.h:g}", fontsize=9)
        ax.legend(fontsize=8)
    finish(fig, a.out, "fig4_closed_sphere")


if __name__ == "__main__":
    main()
