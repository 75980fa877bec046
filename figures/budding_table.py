"""Budding (Section 5.4): how far each of the paper's six cases gets, why it ends, and w_apex
at kbar = 10 ... 300 with error estimates that include the apex-core modelling choice; the
stop's dependence on the resolution; the two gamma conventions compared.

For every case (eta_a, eta_b): the branch with the package's default method for it
(budding.method_for) to kbar = 300, its last kbar and Branch.stop; w_apex at every kbar of
KBARS it reaches, solved at exactly that kbar. Each case is followed again on the variants
of its method (``variants``): the degree 12 and 20 (the Chebyshev degree 24 and 48 for the
spectral method) and, where the apex has a core (budding.CORE: a singular apex the 2D
energy does not resolve), the core at 0.5 and 2 thicknesses, a factor 4 apart. The error
estimate of w is its spread over the variants that reach that kbar (the degree 20 is the
next finer discretisation of the default, so the spread holds the change on refinement and,
with a core, what the core's length does); the last kbar of every variant
tells a stop that converges (a property of the reduced model) from one that drifts (of the
discretisation). Where the apex has a core, the shape (r, z, theta) and the hoop strain
beyond twice the larger core of the two compared (2 h0 for cores 0.5 and 1 h0, 4 h0 for 1
and 2 h0) are compared between the core lengths, each from its method's own interpolant.
Observed orders: of w in the degree (differences 12 -> 16 -> 20) and in the core length
(0.5 -> 1 -> 2 h0).
At kbar = 20 the change of w between the paper's printed gammas (0.63/1.26) and the exact
equal-norm ones. Writes budding_table.csv, budding_summary.csv (the docs' view),
budding_stops.csv, budding_core.csv and budding_gammas.csv.

    python figures/budding_table.py [--quick]
"""

from __future__ import annotations

import math
import time
from dataclasses import replace

import numpy as np

import shellbvp
from shellbvp.problems import budding as bd

from _common import parser, write_csv

CASES = ((0.0, 0.5), (0.0, 1.0), (0.0, 2.0), (0.5, 1.0), (1.0, 1.0), (2.0, 1.0))
PAPER_KBAR = {(0.0, 0.5): 300.0, (0.0, 1.0): 300.0, (0.0, 2.0): 128.0,
              (0.5, 1.0): 200.0, (1.0, 1.0): 200.0, (2.0, 1.0): 76.0}
KBARS = (10.0, 20.0, 30.0, 40.0, 64.0, 76.0, 100.0, 128.0, 160.0, 200.0, 300.0)
KBAR_MAX = 300.0
#: kbar values of the core study (strains beyond 2 h0)
CORE_KBARS = (20.0, 76.0, 200.0)


def variants(m) -> dict:
    """The default method m and its variants, by name: degree (nodes) down and up and, with
    an apex core, the core length halved and doubled."""
    if isinstance(m, shellbvp.Chebyshev):
        return {"default": m, "nodes 24": replace(m, nodes=24), "nodes 48": replace(m, nodes=48)}
    out = {"default": m, "degree 12": replace(m, degree=12), "degree 20": replace(m, degree=20)}
    if m.core is not None:
        out.update({"core 0.5 h0": replace(m, core=m.core / 2),
                    "core 2 h0": replace(m, core=m.core * 2)})
    return out


def at(b, k, **kw):
    i = int(np.argmin(np.abs(b.p - k)))
    return shellbvp.solve(b.scene, k, method=b.method, guess=b.equilibrium(i), **kw)


def order(d1, d2, ratio):
    """Observed order from two successive differences of a refinement by ``ratio``."""
    if not (d1 > 0 and d2 > 0):
        return math.nan
    return math.log(d1 / d2) / math.log(ratio)


def beyond_core(eq, start):
    """(r, z, theta, eps22) of ``eq`` beyond ``start``, from its own interpolant (the
    method's: no resampling of strains with steep edge layers), on each side of the patch
    edge apart; eps22 = ((r / (g2 r0))^2 - 1) / 2 with the target g2 and r0 = sin s."""
    out = []
    for piece, (lo, hi) in enumerate(((start, bd.PATCH), (bd.PATCH, bd.THETA))):
        s = np.linspace(lo, hi, 200)[1:-1]
        r, z, th = eq(s)[:3]
        g2 = eq.scene.field_values(piece, s, eq.p)[1]
        out.append(np.stack([r, z, th, ((r / (g2 * np.sin(s))) ** 2 - 1) / 2]))
    return np.concatenate(out, axis=1)


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    t0 = time.perf_counter()
    table, stops, gam, core_rows = [], [], [], []
    for ea, eb in CASES:
        m = bd.method_for(ea, eb, quick=a.quick)
        runs = variants(m) if not a.quick else {"default": m}
        branches, ws = {}, {}
        for name, v in runs.items():
            b = bd.branch(ea, eb, KBAR_MAX, method=v)
            branches[name] = b
            ws[name] = {k: at(b, k, estimate_error=False) for k in KBARS
                        if k <= b.p[-1] + 1e-9}
            res = ", ".join(f"{k} {x}" for k, x in b.stats.items()
                            if k in ("degree", "nodes", "elements", "layers", "core",
                                     "core_degree"))
            stops.append([ea, eb, name, res, float(b.p[-1]), b.stop.split(";")[0][:300]])
            print(f"eta = ({ea:g}, {eb:g}) {name} [{res}]: last kbar {b.p[-1]:.4f} "
                  f"({b.stats['wall_time']:.1f} s)", flush=True)
        b = branches["default"]
        paper = PAPER_KBAR[(ea, eb)]
        reason = b.stop or f"reached kbar = {KBAR_MAX:g}"
        row = [ea, eb, paper, b.stats["method"], float(b.p[-1]),
               min(float(x.p[-1]) for x in branches.values()),
               max(float(x.p[-1]) for x in branches.values())]
        for k in KBARS:
            eq = ws["default"].get(k)
            if eq is None:
                row += [math.nan] * 3
                continue
            others = [w[k].w for w in ws.values() if k in w]
            row += [eq.w, max(others) - min(others) if len(others) > 1 else math.nan,
                    len(others)]
        # observed orders in the degree and in the core length, at the last common kbar
        common = [k for k in KBARS if all(k in w for w in ws.values())]
        k_ord = common[-1] if common else math.nan
        orders = [math.nan, math.nan]
        if common and "degree 12" in ws:
            w12, w16, w20 = (ws[n][k_ord].w for n in ("degree 12", "default", "degree 20"))
            orders[0] = order(abs(w16 - w12), abs(w20 - w16), 20 / 16)
        if common and "core 2 h0" in ws:
            wa, wb, wc = (ws[n][k_ord].w for n in ("core 0.5 h0", "default", "core 2 h0"))
            orders[1] = order(abs(wc - wb), abs(wb - wa), 2.0)
            for k in CORE_KBARS:
                if k not in common:
                    continue
                for n in ("core 0.5 h0", "core 2 h0"):
                    # beyond twice the larger of the two cores compared
                    start = 2 * max(runs[n].core, m.core) * bd.H
                    ref = beyond_core(ws["default"][k], start)
                    d = np.max(np.abs(beyond_core(ws[n][k], start) - ref), axis=1)
                    core_rows.append([ea, eb, k, n, start / bd.H, ws[n][k].w,
                                      ws["default"][k].w, *map(float, d),
                                      float(np.max(np.abs(ref[3])))])
        table.append(row + [k_ord, *orders, "unstable" if "Hessian" in b.stop else
                            "", reason])
        print(f"   reached {b.p[-1]:.4f} (variants {row[5]:.4f} - {row[6]:.4f}); {reason[:200]}")
        print("   w_apex at " + ", ".join(
            f"{k:g}: {w:.6f} +- {e:.1e}" for k, w, e in zip(KBARS, row[7::3], row[8::3])
            if math.isfinite(w)))
        print(f"   observed order at kbar {k_ord:g}: degree {orders[0]:.2f}, core {orders[1]:.2f}",
              flush=True)
        if b.p[-1] >= 20.0 and ea != 1.0 and (ea, eb) != (0.0, 1.0):
            exact = bd.branch(ea, eb, 20.0, method=m, gammas="equal-norm")
            w_p, w_e = at(b, 20.0, estimate_error=False).w, at(exact, 20.0,
                                                               estimate_error=False).w
            gam.append([ea, eb, 20.0, w_p, w_e, w_e - w_p, (w_e - w_p) / w_p])
            print(f"   gammas at kbar = 20: paper {w_p:.9f}, equal-norm {w_e:.9f} "
                  f"(relative {(w_e - w_p) / w_p:.2e})")
    head = ["eta_a", "eta_b", "paper_kbar", "method", "last_kbar", "last_kbar_min_variants",
            "last_kbar_max_variants"]
    for k in KBARS:
        head += [f"w_over_R0_at_{k:g}", f"w_error_at_{k:g}", f"variants_at_{k:g}"]
    head += ["order_kbar", "order_in_degree", "order_in_core", "ends_unstable", "why_it_ends"]
    write_csv(a.out / "budding_table.csv", head, table)
    # the docs' compact view: w +- its error as text at three kbar
    cols = {k: head.index(f"w_over_R0_at_{k:g}") for k in (20.0, 76.0, 200.0)}
    summary = [[f"({r[0]:g}, {r[1]:g})", f"{r[2]:g}", f"{r[4]:.2f}"]
               + [f"{r[c]:.5f} ± {r[c + 1]:.0e}" if math.isfinite(r[c]) else "–"
                  for c in cols.values()] for r in table]
    write_csv(a.out / "budding_summary.csv", ["eta", "paper kbar", "last kbar",
                                              "w/R0 at 20", "w/R0 at 76", "w/R0 at 200"],
              summary)
    write_csv(a.out / "budding_stops.csv", ["eta_a", "eta_b", "variant", "resolution",
                                            "last_kbar", "why_it_ends"], stops)
    write_csv(a.out / "budding_core.csv",
              ["eta_a", "eta_b", "kbar", "variant", "beyond_s_over_h0", "w_variant",
               "w_default", "max_d_r_beyond", "max_d_z_beyond", "max_d_theta_beyond",
               "max_d_eps22_beyond", "max_eps22"], core_rows)
    write_csv(a.out / "budding_gammas.csv", ["eta_a", "eta_b", "kbar", "w_paper_gammas",
                                             "w_equal_norm_gammas", "difference",
                                             "relative"], gam)
    print(f"total {time.perf_counter() - t0:.1f} s")


if __name__ == "__main__":
    main()
