"""Fig. 6 of Taffetani & Pezzulla: evolution of the bud under a curvature stimulus,
eta_a = 0, eta_b = 0.5, at kbar = 64, 160, 300 (clamped cap R0 = 0.25, h0 = 0.005,
Theta = pi/8, CG lam = 7.5, relaxed model); the stimulated patch drawn thick. Where the
branch ends before a requested kbar, the evolution is drawn instead at a quarter and a half
of the branch's reach and at 99% of it, and the title says so.
Writes fig6_budding_evolution.png and .csv.

    python figures/fig6_budding_evolution.py [--quick]
"""

from __future__ import annotations

import time

from _budding import HEADER, case, method_note, rows_of
from _common import finish, parser, pyplot, write_csv

KBARS = (64.0, 160.0, 300.0)


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    t0 = time.perf_counter()
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.5))
    b, states = case(0.0, 0.5, list(KBARS), quick=a.quick)
    title = r"$\eta_a$ = 0, $\eta_b$ = 0.5"
    if not all(reached for _, _, reached in states):
        end = b.p[-1]
        title += (rf": the branch ends at $\bar\kappa$ = {end:.1f} < {KBARS[0]:g} "
                  f"(loss of ellipticity);\nshapes at a quarter, a half and 99% of it")
        _, states = case(0.0, 0.5, [round(end / 4, 1), round(end / 2, 1), round(0.99 * end, 1)],
                         quick=a.quick)
    rows = []
    for k, (kbar, eq, reached) in enumerate(states):
        rows += rows_of(0.0, 0.5, kbar, eq, reached)
        label = (rf"$\bar\kappa$ = {kbar:g}" if reached else
                 rf"$\bar\kappa$ = {kbar:g}: branch ends at {eq.p:.1f} (last valid shape)")
        eq.plot(ax=ax, strains=False, origin="edge", label=label, color=f"C{k}")
    ax.legend(fontsize=7)
    ax.set_title(title + f"\n{method_note(b)}", fontsize=9)
    write_csv(a.out / "fig6_budding_evolution.csv", HEADER, rows)
    finish(fig, a.out, "fig6_budding_evolution")
    print(f"total {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
