"""Fig. 7 of Taffetani & Pezzulla: budding under curvature and metric stimuli, eta_b = 1 and
eta_a = 0.5, 1, 2 at the paper's kbar = 200, 200, 76 (clamped cap R0 = 0.25, h0 = 0.005,
Theta = pi/8, CG lam = 7.5, relaxed model): shapes (a-c, the stimulated patch drawn thick)
and elastic strains eps11 (solid), eps22 (dashed) against s (d-f, patch shaded). Where a
branch ends before the paper's kbar, the last valid state is drawn and the title says so.
Writes fig7_budding_metric.png and .csv.

    python figures/fig7_budding_metric.py [--quick]
"""

from __future__ import annotations

from _budding import panels

CASES = ((0.5, 1.0), (1.0, 1.0), (2.0, 1.0))


def main(argv=None):
    panels(CASES, "fig7_budding_metric", argv, __doc__)


if __name__ == "__main__":
    main()
