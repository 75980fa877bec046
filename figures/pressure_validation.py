"""External validation: the axisymmetric snap-through pressure of clamped spherical caps
(Koiter shell, nu = 0.3) against the classical tables.

p_cr/p0 against lambda_B = 2 [3 (1 - nu^2)]^(1/4) sqrt(H/t) from 3.5 to 9 at R/t = 100 and
1000 (p0 = 2 E t^2 / (R^2 sqrt(3 (1 - nu^2))), the classical buckling pressure of the
complete sphere), with the published values as points:

* Budiansky, B. (1959), "Buckling of clamped shallow spherical shells", Proc. IUTAM Symp.
  on the Theory of Thin Elastic Shells, Delft, 64-94 (shallow-shell theory);
* Dumir, P. C. & Nath, Y. (1984), "Axisymmetric static and dynamic buckling of orthotropic
  shallow spherical caps with flexible supports", Acta Mech. 52, 93-106 (shallow-shell theory);
* Teng, J. G. & Rotter, J. M. (1989), "Elastic-plastic large deflection analysis of
  axisymmetric shells", Comput. Struct. 31(2), 211-233: their Table 1, which lists all three
  (theirs a finite-element analysis at R/t = 100).

Right panel: the branches p/p0 against the apex deflection w/t for lambda_B = 4, 6, 8 at
R/t = 100 (for lambda_B >= 6 the apex turns back before the pressure maximum: the buckle
forms off the axis). Writes pressure_validation.png, pressure_validation.csv (every p_cr/p0
with its error estimate and w_apex at the fold), pressure_validation_table.csv (ours,
published, relative differences) and pressure_branches.csv.

    python figures/pressure_validation.py [--quick]
"""

from __future__ import annotations

import time

import numpy as np
from tqdm import tqdm

from _common import finish, parser, pyplot, write_csv
from shellbvp import ContinuationOptions
from shellbvp.problems import pressure_cap as pc

#: Table 1 of Teng & Rotter (1989): lambda_B, Budiansky (1959), Dumir & Nath (1984),
#: Teng & Rotter (1989, R/t = 100); p_cr / p0, nu = 0.3 (read from the transcription of that
#: table in the examples of AQUINAS, Filippidis & Sadowski, Imperial College, BSD-3)
PUBLISHED = ((4.0, 0.578, 0.580, 0.563), (5.0, 0.629, 0.630, 0.615),
             (5.5, 0.789, 0.785, 0.746), (6.0, 0.995, 0.986, 0.972),
             (7.0, 1.068, 1.042, 1.046), (8.0, 1.130, 1.115, 1.109))
R_OVER_T = (100.0, 1000.0)
TOL = 1e-8


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    lams = np.array([4.0, 6.0, 8.0]) if a.quick else np.round(np.arange(3.5, 9.001, 0.125), 6)
    lams = np.union1d(lams, [row[0] for row in PUBLISHED] if not a.quick else [])
    rows, ours = [], {}
    t0 = time.perf_counter()
    for Rt in R_OVER_T:
        tol = TOL if Rt <= 100 else 1e-7      # the round-off floor grows like R/t
        for lb in tqdm(lams, desc=f"p_cr, R/t = {Rt:g}", unit="cap"):
            r = pc.critical_pressure(float(lb), R_over_t=Rt, tol=tol)
            ours[(Rt, float(lb))] = r
            rows.append([Rt, float(lb), r.theta, int(r.snaps), r.p_cr_over_p0,
                         r.error_estimate, r.w_apex_over_t])
    elapsed = time.perf_counter() - t0
    print(f"{len(rows)} caps in {elapsed:.1f} s ({elapsed / len(rows):.2f} s per cap)")
    write_csv(a.out / "pressure_validation.csv",
              ["R_over_t", "lambda_B", "theta_rad", "snaps", "p_cr_over_p0",
               "p_cr_error", "w_apex_over_t_at_fold"], rows)

    table = []
    for lb, bud, dn, tr in PUBLISHED:
        if (100.0, lb) not in ours:
            continue
        o1, o2 = ours[(100.0, lb)], ours[(1000.0, lb)]
        table.append([lb, o1.p_cr_over_p0, o1.error_estimate, o2.p_cr_over_p0,
                      o2.error_estimate, bud, dn, tr, o1.p_cr_over_p0 / tr - 1,
                      o2.p_cr_over_p0 / bud - 1, o2.p_cr_over_p0 / dn - 1])
        print(f"lambda_B = {lb:4g}: R/t=100 {o1.p_cr_over_p0:.6f} (+-{o1.error_estimate:.0e}) "
              f"R/t=1000 {o2.p_cr_over_p0:.6f} (+-{o2.error_estimate:.0e}) | Budiansky "
              f"{bud:.3f}, Dumir-Nath {dn:.3f}, Teng-Rotter {tr:.3f}")
    if table:
        write_csv(a.out / "pressure_validation_table.csv",
                  ["lambda_B", "ours_R_over_t_100", "error_100", "ours_R_over_t_1000",
                   "error_1000", "Budiansky_1959", "Dumir_Nath_1984", "Teng_Rotter_1989",
                   "rel_diff_100_vs_Teng_Rotter", "rel_diff_1000_vs_Budiansky",
                   "rel_diff_1000_vs_Dumir_Nath"], table)

    branches = []
    for lb in (4.0, 6.0, 8.0):
        b = ours[(100.0, lb)].branch
        c = pc.pressure_scale(b.scene.h)
        # to the second fold (the lower limit point after the snap), in short steps to draw
        dense = pc.branch(lb, 100.0, n_folds=2, tol=TOL,
                          options=ContinuationOptions.to_first_fold().with_(
                              ds=2.0, ds_max=2.0, fold_probe=False))
        for p, w, *_, fold in dense.rows():
            branches.append([lb, p / c, w / b.scene.h, int(fold)])
    write_csv(a.out / "pressure_branches.csv",
              ["lambda_B", "p_over_p0", "w_apex_over_t", "is_fold"], branches)

    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.4))
    for Rt, style in zip(R_OVER_T, ("-", "--")):
        x = [lb for lb in lams if ours[(Rt, float(lb))].snaps]
        y = [ours[(Rt, float(lb))].p_cr_over_p0 for lb in x]
        ax.plot(x, y, "k" + style, lw=1.3, label=f"shellbvp, R/t = {Rt:g}")
    P = np.array(PUBLISHED)
    ax.plot(P[:, 0], P[:, 1], "^", ms=6, mfc="none", label="Budiansky (1959), shallow")
    ax.plot(P[:, 0], P[:, 2], "s", ms=6, mfc="none", label="Dumir & Nath (1984), shallow")
    ax.plot(P[:, 0], P[:, 3], "o", ms=5, label="Teng & Rotter (1989), R/t = 100")
    ax.set_xlabel(r"$\lambda_B = 2[3(1-\nu^2)]^{1/4}\sqrt{H/t}$")
    ax.set_ylabel(r"$p_{cr}/p_0$")
    ax.set_title("Axisymmetric snap pressure, clamped cap, $\\nu$ = 0.3")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    B = np.array(branches)
    for lb in (4.0, 6.0, 8.0):
        sel = (B[:, 0] == lb) & (B[:, 3] == 0)
        line, = bx.plot(-B[sel, 2], B[sel, 1], lw=1.2, label=rf"$\lambda_B$ = {lb:g}")
        f = ours[(100.0, lb)]
        bx.plot(-f.w_apex_over_t, f.p_cr_over_p0, "o", color=line.get_color(), ms=5)
    bx.set_xlabel("apex deflection $-w/t$ (downward)")
    bx.set_ylabel(r"$p/p_0$")
    bx.set_title("Branches at R/t = 100 (dots: the snap fold)")
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3)
    finish(fig, a.out, "pressure_validation")


if __name__ == "__main__":
    main()
