"""Fig. 7 of Taffetani & Pezzulla: budding under curvature and metric stimuli, eta_b = 1 and
eta_a = 0.5, 1, 2 at the paper's kbar = 200, 200, 76 (clamped cap R0 = 0.25, h0 = 0.005,
Theta = pi/8, CG lam = 7.5, relaxed model): shapes (a-c, the stimulated patch drawn thick)
and elastic strains eps11 (solid), eps22 (dashed) against s (d-f, patch shaded). Where a
branch ends before the paper's kbar, the last valid state is drawn and the title says so.
Writes fig7_budding_metric.png and .csv.

    python figures/fig7_budding_metric.py [--quick]
"""

from __future__ import annotations

import time

from _budding import HEADER, PAPER_KBAR, case, draw_shape, draw_strains, rows_of, title_of, w_table
from _common import finish, parser, pyplot, write_csv

CASES = ((0.5, 1.0), (1.0, 1.0), (2.0, 1.0))


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
    write_csv(a.out / "fig7_budding_metric.csv", HEADER, rows)
    finish(fig, a.out, "fig7_budding_metric")
    print(f"total {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
