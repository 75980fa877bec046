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

from _budding import panels

CASES = ((0.0, 0.5), (0.0, 1.0), (0.0, 2.0))


def main(argv=None):
    panels(CASES, "fig5_budding_curvature", argv, __doc__)


if __name__ == "__main__":
    main()
