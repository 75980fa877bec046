"""Where the wave inverts Pleodorina's bowl: the map of outcomes in the thickness h (the
number of cells) and the wedging k h, and the boundary between stalling and inverting
waves (``shellbvp.problems.pleodorina.region_map``; docs/cell-sheets.md).

The hemispherical bowl, a band of two wedged cells, the Koiter shell with nu = 1/2. For
every thickness of the grid the wave is run at every wedging of the grid (outcome:
continuous inversion, inversion past a snap, stall, or a stopped continuation), and the
boundary is bisected to ``TOL`` in k h between the first inverting wedging and the
stalling one below it. The sweep runs one thickness per chunk on ``--jobs`` local
processes (``shellbvp.sweep``; a Dask executor takes the same chunks and gives the same
values). Its wall time is printed and written to the summary.

Refinement, tolerance fixed before the run: the boundary at the 256-cell thickness
bisected again at 1.5 times the Chebyshev degree (``nodes_per_step``) must overlap the
first bracket widened by ``TOL``.

The number of cells is our estimate N = 2 pi / h^2 (cuboidal cells on the hemisphere,
:func:`shellbvp.problems.pleodorina.thickness_for_cells`), not Tribet & Haas's allometry.

    python figures/cell_sheets_map.py [--quick] [--jobs N] [--out DIR]
"""

from __future__ import annotations

import math
import time

import numpy as np
from _cell_sheets import script_main
from _common import finish, pyplot, write_csv
from shellbvp.problems import pleodorina as P

STEM = "cell_sheets_map"
THICKNESSES = (0.1, 0.12, 0.14, P.thickness_for_cells(256), 0.2, 0.25,
               P.thickness_for_cells(64))
WEDGINGS = tuple(round(0.2 * k, 1) for k in range(1, 9))      # 0.2 ... 1.6
QUICK_THICKNESSES = (P.thickness_for_cells(256), P.thickness_for_cells(64))
QUICK_WEDGINGS = (0.4, 0.8, 1.2)
TOL = 0.02
MARKERS = {"continuous": ("o", "tab:green"), "snap": ("s", "tab:orange"),
           "stalls": ("x", "tab:red"), "stopped": ("^", "tab:gray"),
           "snaps, then stopped": ("v", "tab:purple")}


def kind_of(kind: str, folds: int) -> str:
    """The map's label of an outcome: a stopped branch that passed a fold first has
    snapped there (where the sheet lands is not followed)."""
    return "snaps, then stopped" if kind == "stopped" and folds else kind


def cells_of(h: float) -> float:
    return 2.0 * math.pi * (1.0 - math.cos(P.THETA)) / h**2


def run(quick: bool, jobs: int) -> dict:
    hs = QUICK_THICKNESSES if quick else THICKNESSES
    qs = QUICK_WEDGINGS if quick else WEDGINGS
    t = time.perf_counter()
    records = P.region_map(hs, qs, tol=TOL, jobs=jobs)
    seconds = time.perf_counter() - t
    out = {"records": records, "seconds": seconds, "jobs": jobs, "items": len(hs) * len(qs)}
    if not quick:
        h = P.thickness_for_cells(256)
        rec = next(r for r in records if abs(r.key - h) < 1e-12)
        lo, hi = rec.values["boundary"]
        if math.isfinite(lo):
            t = time.perf_counter()
            out["refined"] = P.boundary(h, lo - TOL, hi + TOL, tol=TOL,
                                        nodes_per_step=1.5 * P.NODES_PER_STEP)
            out["refined_seconds"] = time.perf_counter() - t
            out["refined_h"] = h
    return out


def refinement_check(res: dict):
    """(first bracket, refined bracket, pass): the brackets overlap once widened by TOL."""
    if "refined" not in res:
        return None
    h = res["refined_h"]
    rec = next(r for r in res["records"] if abs(r.key - h) < 1e-12)
    (a, b), (c, d) = rec.values["boundary"], res["refined"]
    return (a, b), (c, d), (c <= b + TOL and a - TOL <= d)


def write(res: dict, out) -> None:
    rows, edges = [], []
    for r in res["records"]:
        for q, kind, fold, w_end, sec, folds, stop in r.values.get("rows", ()):
            rows.append([r.key, cells_of(r.key), q, kind, fold, w_end, sec, folds, stop])
        lo, hi = r.values.get("boundary", (math.nan, math.nan))
        edges.append([r.key, cells_of(r.key), lo, hi, r.status, r.reason,
                      r.values.get("boundary_seconds", math.nan)])
    write_csv(out / f"{STEM}.csv", list(P.MAP_COLUMNS), rows)
    write_csv(out / f"{STEM}_boundary.csv",
              ["h", "cells", "wedging_stalls", "wedging_inverts", "status", "reason",
               "seconds"], edges)
    chk = refinement_check(res)
    summary = [["sweep", res["items"], res["jobs"], round(res["seconds"], 1), "", ""]]
    if chk:
        summary.append(["boundary at 1.5x degree (256 cells)", "", "",
                        round(res["refined_seconds"], 1), f"{chk[1][0]:.3f}-{chk[1][1]:.3f}",
                        "pass" if chk[2] else "miss"])
    write_csv(out / f"{STEM}_timing.csv",
              ["what", "waves", "jobs", "seconds", "bracket", "check"], summary)


def figure(res: dict, out) -> None:
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8.6, 5.0))
    seen = set()
    for r in res["records"]:
        for q, kind, _, _, _, folds, _ in r.values.get("rows", ()):
            kind = kind_of(kind, folds)
            m, c = MARKERS[kind]
            ax.plot(cells_of(r.key), q, m, color=c, ms=7, mfc="none" if m != "x" else c,
                    label=kind if kind not in seen else None)
            seen.add(kind)
    edge = sorted((cells_of(r.key), *r.values["boundary"]) for r in res["records"]
                  if math.isfinite(r.values.get("boundary", (math.nan,))[0]))
    if edge:
        n, lo, hi = (np.array(v) for v in zip(*edge))
        ax.fill_between(n, lo, hi, color="k", alpha=0.25, lw=0)
        ax.plot(n, 0.5 * (lo + hi), "k-", lw=1.2, label=f"boundary (bisected to {TOL})")
    for cells in (64, 256):
        ax.axvline(cells, color="tab:blue", ls=":", lw=1)
        ax.text(cells, max(WEDGINGS) + 0.02, f" {cells} cells", fontsize=8,
                color="tab:blue", va="bottom")
    ax.set_xscale("log")
    ax.set_xlabel("cells N = 2 pi / h^2 (h: cell height over the bowl's radius)")
    ax.set_ylabel("wedging k h of the band's cells")
    ax.set_title("Where the wave turns the bowl inside out (Koiter, nu = 1/2)", fontsize=10)
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8, loc="center left", bbox_to_anchor=(1.01, 0.5))
    finish(fig, out, STEM)


def report(res: dict) -> None:
    for r in res["records"]:
        kinds = " ".join(f"{q}:{kind_of(kind, folds)}"
                         for q, kind, _, _, _, folds, _ in r.values.get("rows", ()))
        lo, hi = r.values.get("boundary", (math.nan, math.nan))
        print(f"h = {r.key:.5f} (N = {cells_of(r.key):.0f}): {kinds}; boundary "
              f"{lo:.3f} .. {hi:.3f} {r.status} {r.reason}")
    print(f"sweep: {res['items']} waves on the grid plus the bisections, {res['jobs']} "
          f"job(s): {res['seconds']:.1f} s")
    chk = refinement_check(res)
    if chk:
        print(f"boundary at the 256-cell thickness: {chk[0][0]:.3f} .. {chk[0][1]:.3f}; at 1.5x "
              f"the degree {chk[1][0]:.3f} .. {chk[1][1]:.3f}: {'pass' if chk[2] else 'MISS'} "
              f"({res['refined_seconds']:.1f} s)")


def main(argv=None):
    def options(p):
        p.add_argument("--jobs", type=int, default=2, help="local worker processes")
    return script_main(__doc__, argv, lambda a: run(a.quick, a.jobs), write, report, figure,
                       options=options)


if __name__ == "__main__":
    main()
