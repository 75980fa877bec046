"""External validation beyond axisymmetry: the first bifurcation of clamped spherical caps
under external pressure into n circumferential waves, against the classical results.

Koiter shell, nu = 1/3, R/t = 100, lambda_B = 6, 7, 8, 9, 10, 12, 14, 16 (lambda_B =
2 [3 (1 - nu^2)]^(1/4) sqrt(H/t)); pressure in units of p0 = 2 E t^2 / (R^2 sqrt(3 (1 - nu^2))).
For each cap: the first instability along the branch from p = 0
(``pressure_cap.first_instability``: the follower pressure's stiffness included, harmonics
0..20 and beyond until the lowest eigenvalue rises with n), its p/p0, n and error estimate,
and the axisymmetric snap (the pressure maximum) for comparison. Published:

* Huang, N. C. (1964), "Unsymmetrical buckling of thin shallow spherical shells", J. Appl.
  Mech. 31, 447-457;
* Teng, J. G. & Rotter, J. M. (1989b), "Non-symmetric bifurcation of geometrically nonlinear
  elastic-plastic axisymmetric shells under combined loads including torsion", Comput.
  Struct. 32, 453-475, Table 3.

Their values at lambda_B = 6 (p/p0 = 0.775-0.777, n = 2) and 16 (0.790-0.792, n = 11) are
the ones quoted here; the other rows of their Table 3 were not at hand and are left empty
rather than guessed. Also located: the lambda_B above which the bifurcation comes before the
axisymmetric snap (bisection on the kind of the first instability).

Writes asymmetric_pressure.png and asymmetric_pressure.csv.

    python figures/asymmetric_pressure.py [--quick]
"""

from __future__ import annotations

import math
import time

from tqdm import tqdm

from _common import finish, parser, pyplot, write_csv
from shellbvp.problems import pressure_cap as pc

NU, R_OVER_T = 1.0 / 3.0, 100.0
LAMBDAS = (6.0, 7.0, 8.0, 9.0, 10.0, 12.0, 14.0, 16.0)
#: lambda_B: (p/p0 low, high, n) of Huang (1964) and Teng & Rotter (1989b), as quoted
PUBLISHED = {6.0: (0.775, 0.777, 2), 16.0: (0.790, 0.792, 11)}


def _crossover(lo: float, hi: float, tol: float = 0.01) -> tuple:
    """The lambda_B in [lo, hi] where the first instability turns from the axisymmetric fold
    (at lo) to a bifurcation (at hi), by bisection, with the bracket's half-width."""
    kinds = {x: pc.first_instability(x, R_OVER_T, NU).kind for x in (lo, hi)}
    if not (kinds[lo] == "fold" and kinds[hi] == "bifurcation"):
        raise RuntimeError(f"no fold-to-bifurcation change in [{lo}, {hi}]: {kinds}")
    while hi - lo > tol:
        mid = (lo + hi) / 2
        if pc.first_instability(mid, R_OVER_T, NU).kind == "fold":
            lo = mid
        else:
            hi = mid
    return (lo + hi) / 2, (hi - lo) / 2


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    lams = (6.0, 16.0) if a.quick else LAMBDAS
    rows, t0 = [], time.perf_counter()
    for lb in tqdm(lams, desc="first instability", unit="cap"):
        inst = pc.first_instability(lb, R_OVER_T, NU)
        snap = pc.critical_pressure(lb, R_over_t=R_OVER_T, nu=NU)
        pub = PUBLISHED.get(lb, (math.nan, math.nan, -1))
        rows.append([lb, inst.kind, inst.n, inst.p, inst.error_estimate, inst.cutoff,
                     snap.p_cr_over_p0, snap.error_estimate, pub[0], pub[1], pub[2],
                     inst.p / snap.p_cr_over_p0])
        print(f"lambda_B = {lb:5.1f}: {inst.kind} n = {inst.n:2d} at p/p0 = {inst.p:.5f} +- "
              f"{inst.error_estimate:.1e} (axisymmetric snap {snap.p_cr_over_p0:.5f}; "
              f"published {pub[0]}-{pub[1]}, n = {pub[2]})")
    cross = (math.nan, math.nan) if a.quick else _crossover(5.0, 6.0)
    elapsed = time.perf_counter() - t0
    print(f"the bifurcation comes first above lambda_B = {cross[0]:.3f} +- {cross[1]:.3f}; "
          f"{elapsed:.0f} s")
    header = ["lambda_B", "kind", "n", "p_over_p0", "p_error", "harmonics_scanned_to",
              "snap_p_over_p0", "snap_error", "published_low", "published_high",
              "published_n", "bifurcation_over_snap"]
    trailer = [["# crossover_lambda_B", cross[0], "half_width", cross[1]]]
    write_csv(a.out / "asymmetric_pressure.csv", header, rows + trailer)

    plt = pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    L = [r[0] for r in rows]
    ax1.plot(L, [r[6] for r in rows], "s--", color="0.5", label="axisymmetric snap (ours)")
    ax1.plot(L, [r[3] for r in rows], "o-", color="C0", label="first bifurcation (ours)")
    for lb, (lo, hi, n) in PUBLISHED.items():
        if lb in L:
            ax1.errorbar([lb], [(lo + hi) / 2], yerr=[(hi - lo) / 2], fmt="D", color="C3",
                         capsize=4, label="Huang 1964 / Teng & Rotter 1989b"
                         if lb == min(PUBLISHED) else None)
    if math.isfinite(cross[0]):
        ax1.axvline(cross[0], color="0.7", lw=0.8)
        ax1.text(cross[0] + 0.1, 0.5, f"bifurcation first\nabove {cross[0]:.2f}", fontsize=8,
                 transform=ax1.get_xaxis_transform())
    ax1.set_xlabel(r"$\lambda_B$")
    ax1.set_ylabel(r"$p_{cr}/p_0$")
    ax1.set_title(r"clamped cap, Koiter, $\nu = 1/3$, $R/t = 100$", fontsize=10)
    ax1.legend(fontsize=8)
    ax2.plot(L, [r[2] for r in rows], "o-", color="C0", label="ours")
    ax2.plot([lb for lb in PUBLISHED if lb in L], [PUBLISHED[lb][2] for lb in PUBLISHED
                                                   if lb in L], "D", color="C3",
             label="published")
    ax2.set_xlabel(r"$\lambda_B$")
    ax2.set_ylabel("critical harmonic $n$")
    ax2.legend(fontsize=8)
    finish(fig, a.out, "asymmetric_pressure")


if __name__ == "__main__":
    main()
