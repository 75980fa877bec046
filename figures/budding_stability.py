"""Stability along the budding branches (paper Section 5.4): the smallest eigenvalue of the
discrete second variation of the reduced energy (:func:`shellbvp.second_variation`, an
energy Hessian built independently of the Euler-Lagrange equations the branch was solved
from) against kbar, at three resolutions (Chebyshev degree 24, 32, 48 per piece), for the six
cases of Figs. 5 and 7. A converged positive eigenvalue is a stable state; an eigenvalue that
crosses zero at a kbar that moves with the resolution, with its mode crowded at the apex, is
the mark of the loss of ellipticity (an ill-posed continuum problem), not of a bifurcation.
Writes budding_stability.png and budding_stability.csv (every eigenvalue with the location
of its mode's largest theta component).

    python figures/budding_stability.py [--quick]
"""

from __future__ import annotations

import time

import numpy as np
from tqdm import tqdm

from _budding import PAPER_KBAR
from _common import finish, parser, pyplot, write_csv
from shellbvp import ConvergenceError, second_variation
from shellbvp.problems import budding as bd

CASES = ((0.0, 0.5), (0.0, 1.0), (0.0, 2.0), (0.5, 1.0), (1.0, 1.0), (2.0, 1.0))
RESOLUTIONS = (24, 32, 48)


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    cases = CASES[1:2] + CASES[4:5] if a.quick else CASES
    t0 = time.perf_counter()
    rows, data = [], {}
    for ea, eb in cases:
        # the first-order system's branches (the energy method's carry their own Hessian)
        b = bd.branch(ea, eb, PAPER_KBAR[(ea, eb)], nodes=bd.NODES)
        # every point, and the last eight (where the branch ends) all of them
        idx = sorted(set(range(0, len(b.p), 3)) | set(range(max(0, len(b.p) - 8), len(b.p))))
        pts = []
        for i in tqdm(idx, desc=f"eta_a = {ea:g}, eta_b = {eb:g}", unit="point"):
            try:
                eq = b.equilibrium(i)
            except ConvergenceError:
                continue          # the very last point: see _budding.last_valid
            for N in RESOLUTIONS:
                try:
                    sv = second_variation(eq, nodes=N, count=1)
                except ConvergenceError:
                    continue      # no elliptic inner root at this degree's points

                where = float(sv.s[int(np.argmax(np.abs(sv.theta_modes[0])))])
                rows.append([ea, eb, float(b.p[i]), N, float(sv.eigenvalues[0]), where,
                             float(np.min(eq.legendre))])
                pts.append((float(b.p[i]), N, float(sv.eigenvalues[0]), where))
        data[(ea, eb)] = (pts, b)
    print(f"{len(rows)} eigenvalue problems in {time.perf_counter() - t0:.1f} s")
    write_csv(a.out / "budding_stability.csv",
              ["eta_a", "eta_b", "kbar", "nodes", "smallest_eigenvalue", "mode_at_s_over_R0",
               "legendre_min"], rows)

    plt = pyplot()
    n = len(cases)
    fig, axes = plt.subplots(2, (n + 1) // 2, figsize=(4.2 * ((n + 1) // 2), 7), squeeze=False)
    for k, (ea, eb) in enumerate(cases):
        ax = axes.flat[k]
        pts, b = data[(ea, eb)]
        for N, style in zip(RESOLUTIONS, ("o:", "s--", "^-")):
            P = np.array([(kb, lam) for kb, NN, lam, _ in pts if NN == N])
            if P.size:
                ax.plot(P[:, 0], P[:, 1], style, ms=3, lw=0.8, label=f"degree {N}")
        ax.axhline(0, color="k", lw=0.6)
        ax.set_yscale("symlog", linthresh=1e-2)
        ax.set_xlabel(r"$\bar\kappa$")
        ax.set_ylabel("smallest eigenvalue")
        ax.set_title(rf"$\eta_a$ = {ea:g}, $\eta_b$ = {eb:g} (branch ends at {b.p[-1]:.1f})",
                     fontsize=9)
        ax.grid(alpha=0.3)
        if k == 0:
            ax.legend(fontsize=8)
    for ax in list(axes.flat)[n:]:
        ax.axis("off")
    finish(fig, a.out, "budding_stability")


if __name__ == "__main__":
    main()
