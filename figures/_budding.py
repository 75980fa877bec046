"""What Figs. 5-7 share: follow a budding branch to the paper's kbar (or to where it ends),
take the equilibria at the requested kbar, and draw shapes and strains.

Strains are the elastic mid-surface strains relative to the target metric,
eps_aa = (a_aa - abar_aa) / (2 abar_aa) = (lam_a^2 - 1) / 2 (Green-Lagrange; a = 1
meridional, 2 azimuthal): zero where the shell takes its target metric.
"""

from __future__ import annotations

import time

import numpy as np

from shellbvp.problems import budding as bd

#: the paper's last kbar per case (Section 5.4)
PAPER_KBAR = {(0.0, 0.5): 300.0, (0.0, 1.0): 300.0, (0.0, 2.0): 128.0,
              (0.5, 1.0): 200.0, (1.0, 1.0): 200.0, (2.0, 1.0): 76.0}


def case(eta_a, eta_b, kbars, quick=False):
    """Branch to max(kbars) and the equilibria at each kbar reached (the last point of the
    branch stands in for the kbars past its end). Returns (branch, [(kbar, eq, reached)])."""
    t0 = time.perf_counter()
    b = bd.branch(eta_a, eta_b, max(kbars), method=bd.method_for(eta_a, eta_b, quick=quick))
    out = []
    for k in kbars:
        if k <= b.p[-1]:
            i = int(np.argmin(np.abs(b.p - k)))
            eq = bd.equilibrium_near(b, i, k)
            out.append((k, eq, True))
        else:
            out.append((k, last_valid(b), False))
    print(f"eta_a = {eta_a:g}, eta_b = {eta_b:g}: branch to kbar = {b.p[-1]:.4f} "
          f"({len(b.p)} points, {time.perf_counter() - t0:.1f} s)"
          + (f"; stops: {b.stop}" if b.stop else ""))
    return b, out


def last_valid(b):
    """The equilibrium at the last branch point whose state can be evaluated (every point
    can since the continuation's inner roots start the evaluation; kept as a guard)."""
    from shellbvp import ConvergenceError

    for i in range(len(b.p) - 1, -1, -1):
        try:
            return b.equilibrium(i)
        except ConvergenceError:
            continue
    raise ConvergenceError("no point of the branch can be evaluated")


def rows_of(eta_a, eta_b, kbar, eq, reached):
    """CSV rows: the meridian of one equilibrium."""
    return [[eta_a, eta_b, kbar, eq.p, int(reached), s, r, z, e1, e2, l1, l2, k1, k2]
            for s, r, z, e1, e2, l1, l2, k1, k2 in zip(eq.s, eq.r, eq.z, eq.eps11, eq.eps22,
                                                        eq.lam1, eq.lam2, eq.k1, eq.k2)]


HEADER = ["eta_a", "eta_b", "kbar_requested", "kbar", "reached", "s_over_R0", "r_over_R0",
          "z_over_R0", "eps11", "eps22", "lam1", "lam2", "k1_R0", "k2_R0"]


def method_note(b) -> str:
    """The method a branch was followed with and the gammas convention, for captions."""
    return f"{b.stats['method']} method, paper's gammas (0.63/1.26)"


def shade_core(ax):
    """Hatch s < 2 h0: the apex core the reduced 2D energy does not resolve (budding's
    module docstring), whose strains depend on how it is treated."""
    ax.axvspan(0.0, 2 * bd.H, facecolor="none", edgecolor="0.4", hatch="///", lw=0.0,
               label=r"apex core ($s < 2h_0$)")
    ax.legend(fontsize=8)


def title_of(eta_a, eta_b, kbar, eq, reached, end=None):
    t = rf"$\eta_a$ = {eta_a:g}, $\eta_b$ = {eta_b:g}, $\bar\kappa$ = {kbar:g}"
    if not reached:
        t += (f"\nbranch ends at {end:.1f}; " if end is not None else "\n") + \
            rf"last valid shape, $\bar\kappa$ = {eq.p:.1f}"
    return t


def panels(cases, stem, argv=None, doc=""):
    """Figs. 5 and 7: for each (eta_a, eta_b) the shape at the paper's kbar (top row) and
    the strains (bottom row), or the last valid state where the branch ends first; writes
    ``stem``.png and .csv."""
    from _common import finish, parser, pyplot, write_csv

    a = parser(doc.splitlines()[0]).parse_args(argv)
    t0 = time.perf_counter()
    plt = pyplot()
    fig, axes = plt.subplots(2, len(cases), figsize=(13, 7))
    rows = []
    for k, (ea, eb) in enumerate(cases):
        kbar = PAPER_KBAR[(ea, eb)]
        b, ((_, eq, reached),) = case(ea, eb, [kbar], quick=a.quick)
        rows += rows_of(ea, eb, kbar, eq, reached)
        eq.plot(ax=(axes[0, k], axes[1, k]), origin="edge", color=f"C{k}")
        axes[0, k].set_title(f"({'abc'[k]}) " + title_of(ea, eb, kbar, eq, reached, b.p[-1])
                             + f"\n{method_note(b)}", fontsize=8)
        axes[1, k].set_title(f"({'def'[k]}) strains", fontsize=9)
        if "core" in b.stats:
            shade_core(axes[1, k])
    write_csv(a.out / f"{stem}.csv", HEADER, rows)
    finish(fig, a.out, stem)
    print(f"total {time.perf_counter() - t0:.1f} s")
