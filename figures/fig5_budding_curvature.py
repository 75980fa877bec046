"""Fig. 5 of Taffetani & Pezzulla: budding under a curvature stimulus only (eta_a = 0) on the
patch s < Theta/4 of a clamped cap (R0 = 0.25, h0 = 0.005, Theta = pi/8, CG lam = 7.5,
relaxed model), eta_b = 0.5, 1, 2 at the paper's kbar = 300, 300, 128: shapes (a-c, the
stimulated patch drawn thick) and elastic strains eps11 (solid), eps22 (dashed) against s
(d-f, patch shaded). Where a branch ends before the paper's kbar (loss of ellipticity of the
reduced energy, or the solver's limit), the last valid state is drawn and the title says so.
Writes fig5_budding_curvature.png and .csv (every meridian drawn).

    python figures/fig5_budding_curvature.py [--quick]
"""

from __future__ import annotations

import time

from _budding import HEADER, PAPER_KBAR, case, draw_shape, draw_strains, rows_of, title_of, w_table
from _common import finish, parser, pyplot, write_csv

CASES = ((0.0, 0.5), (0.0, 1.0), (0.0, 2.0))


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    t0 = time.perf_counter()
    plt = pyplot()
    fig, axes = plt.subplots(2, 3, figsize=(13, 7))
    rows = []
    for k, (ea, eb) in enumerate(CASES):
        kbar = PAPER_KBAR[(ea, eb)]
        b, ((_, eq, reached),) = case(ea, eb, [kbar], quick=a.quick)
        rows += rows_of(ea, eb, kbar, eq, reached)
        draw_shape(axes[0, k], eq, None, f"C{k}")
        axes[0, k].set_title(f"({'abc'[k]}) " + title_of(ea, eb, kbar, eq, reached, b.p[-1]), fontsize=9)
        draw_strains(axes[1, k], eq, f"C{k}")
        axes[1, k].set_title(f"({'def'[k]}) strains", fontsize=9)
        print(f"   w_apex/R0 at kbar = 10, 20, 64: {w_table(b)}")
    write_csv(a.out / "fig5_budding_curvature.csv", HEADER, rows)
    finish(fig, a.out, "fig5_budding_curvature")
    print(f"total {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
