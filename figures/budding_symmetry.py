"""Beyond the paper: do the buds of Figs. 5-7 leave axisymmetry before their branches stop?

For the six budding cases (eta_a, eta_b) = (0, 0.5), (0, 1), (0, 2), (0.5, 1), (1, 1),
(2, 1) (paper's gammas): the first instability along the branch from kbar = 0
(``budding.first_instability``: harmonics 0..20 and beyond at every point, a bifurcation
located by Brent's method, clamped edge), or "none" up to the last point checked with the
branch's stop reason. Where a mode is found: its n, kbar, and where it lives (s of the
largest normal displacement, against the patch edge Theta/4).

Writes budding_symmetry.csv.

    python figures/budding_symmetry.py [--quick]
"""

from __future__ import annotations

import math
import time

import numpy as np
from tqdm import tqdm

from _common import parser, write_csv
import shellbvp
from shellbvp.problems import budding

CASES = ((0.0, 0.5), (0.0, 1.0), (0.0, 2.0), (0.5, 1.0), (1.0, 1.0), (2.0, 1.0))


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    cases = CASES[:1] if a.quick else CASES
    rows, t0 = [], time.perf_counter()
    for ea, eb in tqdm(cases, desc="budding", unit="case"):
        t = time.perf_counter()
        try:
            inst = budding.first_instability(ea, eb)
            s_mode = math.nan if inst.mode is None else \
                float(inst.mode.s[np.argmax(np.abs(inst.mode.w[0]))])
            rows.append([ea, eb, inst.kind, inst.n, inst.p, inst.error_estimate, s_mode,
                         inst.cutoff, inst.stop.splitlines()[0][:300] if inst.stop else ""])
        except shellbvp.ConvergenceError as exc:
            rows.append([ea, eb, "failed", -1, math.nan, math.nan, math.nan, -1,
                         str(exc).splitlines()[0][:300]])
        r = rows[-1]
        print(f"eta = ({ea:g}, {eb:g}): {r[2]} n = {r[3]} kbar = {r[4]:.6g} +- {r[5]:.1e}, "
              f"mode at s = {r[6]:.4g} (patch edge {budding.PATCH:.4g}); "
              f"{time.perf_counter() - t:.0f} s")
    print(f"{len(rows)} cases in {time.perf_counter() - t0:.0f} s")
    write_csv(a.out / "budding_symmetry.csv",
              ["eta_a", "eta_b", "kind", "n", "kbar", "kbar_error", "mode_s_max_w",
               "harmonics_scanned_to", "stop"], rows)


if __name__ == "__main__":
    main()
