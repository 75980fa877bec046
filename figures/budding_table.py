"""Budding (Section 5.4): how far each of the paper's six cases gets, why it ends, and w_apex
at the paper's kbar values with error estimates; the stop's dependence on the resolution;
the two gamma conventions compared.

For every case (eta_a, eta_b): the branch with the package's default method for it
(budding.method_for), its last kbar and Branch.stop; w_apex at kbar = 10, 20, 64, 76, 128,
200, 300 where reached, each solved at exactly that kbar with its error estimate (the
change on the method's next finer discretisation); the last kbar again at two other
resolutions (a stop that converges is a property of the reduced model, one that drifts is
a property of the discretisation); and at kbar = 20 the change of w between the paper's
printed gammas (0.63/1.26) and the exact equal-norm ones. Writes budding_table.csv,
budding_stops.csv and budding_gammas.csv.

    python figures/budding_table.py [--quick]
"""

from __future__ import annotations

import math
import time

import numpy as np

import shellbvp
from shellbvp.problems import budding as bd

from _common import parser, write_csv

CASES = ((0.0, 0.5), (0.0, 1.0), (0.0, 2.0), (0.5, 1.0), (1.0, 1.0), (2.0, 1.0))
PAPER_KBAR = {(0.0, 0.5): 300.0, (0.0, 1.0): 300.0, (0.0, 2.0): 128.0,
              (0.5, 1.0): 200.0, (1.0, 1.0): 200.0, (2.0, 1.0): 76.0}
KBARS = (10.0, 20.0, 64.0, 76.0, 128.0, 200.0, 300.0)


def resolutions(m):
    """The default resolution and two others of the same method, for the stop study."""
    if isinstance(m, shellbvp.Ritz):
        return [shellbvp.Ritz(degree=q) for q in (12, 16, 20)]
    return [shellbvp.Chebyshev(nodes=n) for n in (24, 32, 48)]


def at(b, k, **kw):
    i = int(np.argmin(np.abs(b.p - k)))
    return shellbvp.solve(b.scene, k, method=b.method, guess=b.equilibrium(i), **kw)


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    t0 = time.perf_counter()
    table, stops, gam = [], [], []
    for ea, eb in CASES:
        m = bd.method_for(ea, eb, quick=a.quick)
        b = bd.branch(ea, eb, PAPER_KBAR[(ea, eb)], method=m)
        reason = b.stop or f"reached the paper's kbar = {PAPER_KBAR[(ea, eb)]:g}"
        row = [ea, eb, PAPER_KBAR[(ea, eb)], b.stats["method"], float(b.p[-1]), reason]
        ws = []
        for k in KBARS:
            if k <= b.p[-1] + 1e-9:
                eq = at(b, k)
                ws += [eq.w, eq.error_estimate]
            else:
                ws += [math.nan, math.nan]
        table.append(row[:5] + ws + [reason])
        print(f"eta = ({ea:g}, {eb:g}) [{b.stats['method']}]: last kbar {b.p[-1]:.4f}; "
              f"{reason[:300]}", flush=True)
        print("   w_apex at " + ", ".join(f"{k:g}: {w:.9f} +- {e:.1e}" for k, w, e in
                                          zip(KBARS, ws[::2], ws[1::2]) if math.isfinite(w)))
        if not a.quick:
            for r in resolutions(m):
                br = bd.branch(ea, eb, PAPER_KBAR[(ea, eb)], method=r)
                res = ", ".join(f"{k} {v}" for k, v in br.stats.items()
                                if k in ("degree", "nodes", "elements", "layers"))
                stops.append([ea, eb, br.stats["method"], res, float(br.p[-1]),
                              br.stop.split(";")[0][:200]])
                print(f"   {res}: last kbar {br.p[-1]:.4f}", flush=True)
        if b.p[-1] >= 20.0 and ea != 1.0 and (ea, eb) != (0.0, 1.0):
            exact = bd.branch(ea, eb, 20.0, method=m, gammas="equal-norm")
            w_p, w_e = at(b, 20.0, estimate_error=False).w, at(exact, 20.0,
                                                               estimate_error=False).w
            gam.append([ea, eb, 20.0, w_p, w_e, w_e - w_p, (w_e - w_p) / w_p])
            print(f"   gammas at kbar = 20: paper {w_p:.9f}, equal-norm {w_e:.9f} "
                  f"(relative {(w_e - w_p) / w_p:.2e})")
    head = ["eta_a", "eta_b", "paper_kbar", "method", "last_kbar"]
    for k in KBARS:
        head += [f"w_over_R0_at_{k:g}", f"w_error_at_{k:g}"]
    write_csv(a.out / "budding_table.csv", head + ["why_it_ends"], table)
    if stops:
        write_csv(a.out / "budding_stops.csv", ["eta_a", "eta_b", "method", "resolution",
                                                "last_kbar", "why_it_ends"], stops)
    write_csv(a.out / "budding_gammas.csv", ["eta_a", "eta_b", "kbar", "w_paper_gammas",
                                             "w_equal_norm_gammas", "difference",
                                             "relative"], gam)
    print(f"total {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
