"""Pleodorina's bowl turned inside out by a travelling wave of cell wedging
(``shellbvp.problems.pleodorina``; docs/cell-sheets.md).

Cases (the scene's own parameters; none could be read from Tribet & Haas, see the scene's
docstring): the hemispherical bowl of N = 64 cells (h = 0.31333 R) and of N = 256 cells
(h = 0.15666 R), a band of two wedged cells, wedging k h = 1 and 0.7; the Koiter shell with
nu = 1/2 (the classical law) and, for the 64-cell bowl at k h = 1, the reduced energies
derived from 3D: incompressible neo-Hookean (``nh``) and Ciarlet-Geymonat (``cg``, relaxed,
lam = 1). Each branch is followed from the bowl (stage 0) past the pole (stage 1); folds
are located to 1e-8 in the stage with their refinement-ladder error estimate; where the
first-order method stops (the reduced energy's constitutive inversion folds) the energy
method (``method="energy"``) takes the branch as far as its Hessian and the Legendre
condition allow, at two resolutions. Beyond axisymmetry: ``first_instability`` along every
Koiter branch, and ``follow_bifurcation`` (K = 2) from the first bifurcation found.

Checks, tolerances fixed before the run:

* the bowl at stage 0 (the band outside the rim, its steps' tails 6e-6 of the amplitude
  there): |w| <= 1e-4 H, H = 2 (1 - cos Theta) R;
* the end state past the pole: the inverted bowl, the mirror image of the reference, is
  stress-free: |w - H| <= 1e-4 H and energy <= 1e-6 mu h R^2;
* refinement: ``solve`` at stages 0.2, 0.4, 0.6, 0.8 of the 64-cell Koiter branch reports
  the change of w on the next finer Chebyshev degree; each <= 1e-6 R.

Wall times are measured per case (the first case includes the compilation of the scene's
programs; scenes that differ in h or the wedging share them). Run on one core with
``taskset -c 0``.

    python figures/cell_sheets_pleodorina.py [--quick] [--out DIR]
"""

from __future__ import annotations

import math
import time

import numpy as np
from _cell_sheets import (Clock, equal_3d, instability_record, plot_branch, report_checks,
                          report_details, script_main, surface, write_checks)
from _common import finish, pyplot, write_csv
import shellbvp
from shellbvp.problems import pleodorina as P

STEM = "cell_sheets_pleodorina"
#: the stages at which the shapes are drawn and the refinement is checked
SHAPE_STAGES = (0.0, 0.2, 0.35, 0.5, 0.65, 0.8, 1.0)
CHECK_STAGES = (0.2, 0.4, 0.6, 0.8)
TOL_REST, TOL_END, TOL_ENERGY, TOL_REFINE = 1e-4, 1e-4, 1e-6, 1e-6
H64, H256 = P.thickness_for_cells(64), P.thickness_for_cells(256)
#: label -> (cells, wedging, material, method)
CASES = {
    "64 cells, k h = 1, koiter": (64, 1.0, "koiter", None),
    "64 cells, k h = 1, nh": (64, 1.0, "nh", None),
    "64 cells, k h = 1, nh (energy method)": (64, 1.0, "nh", "energy"),
    "64 cells, k h = 1, cg": (64, 1.0, "cg", None),
    "64 cells, k h = 0.7, koiter": (64, 0.7, "koiter", None),
    "256 cells, k h = 0.7, koiter": (256, 0.7, "koiter", None),
    "256 cells, k h = 1, koiter": (256, 1.0, "koiter", None),
}
QUICK = ("64 cells, k h = 1, koiter",)
MAIN = "64 cells, k h = 1, koiter"


def _scene(cells, wedging, material):
    return P.scene(P.thickness_for_cells(cells), wedging, material=material)


def run_case(label, *, instability: bool) -> dict:
    cells, wedging, material, method = CASES[label]
    sc = _scene(cells, wedging, material)
    clock = Clock()
    # the energies along the main branch only: their evaluation on the dense grid fails at
    # the last points of the nh branch, next to where its constitutive inversion folds
    b = clock("branch", P.branch, sc, method=method, energies=label == MAIN)
    H = 2.0 * sc.geometry.rise
    r = {"label": label, "cells": cells, "h": sc.h, "wedging": wedging,
         "material": material, "method": method or f"spectral ({P.wave_nodes(sc)})",
         "outcome": P.outcome(b),
         "stop": b.stop, "stage": b.p.tolist(), "w_over_H": (b.w / H).tolist(),
         "energy": b.energy.tolist(),
         "energy_end": float(b.energy[-1]),
         "folds": [(float(f.p), float(f.w / H), float(f.error_estimate)) for f in b.folds],
         "last_stage": float(b.p[-1]), "w_end_over_H": float(b.w[-1] / H),
         "w_start_over_H": float(b.w[0] / H),
         "thin_shell": max(b.equilibrium(i).thin_shell[1] for i in range(len(b.p)))}
    if method == "energy":
        # the same branch on a finer discretisation: where it stops is the model's limit
        # only if it does not move with the resolution
        fine = shellbvp.Ritz(elements=2 * shellbvp.Ritz().elements)
        b2 = clock("branch (finer)", P.branch, sc, method=fine, energies=False)
        r["last_stage_finer"] = float(b2.p[-1])
        r["stop_finer"] = b2.stop
    if instability and method is None and not b.stop:
        r["instability"] = instability_record(clock, b, H, p_stop=(0.0, 1.0))
    if label == MAIN:
        r["shapes"] = {}
        for st in SHAPE_STAGES:
            i = int(np.argmin(abs(b.p - st)))
            eq = b.equilibrium(i)
            r["shapes"][float(b.p[i])] = (eq.r.tolist(), eq.z.tolist())
        r["refinement"] = []
        for st in CHECK_STAGES:
            i = int(np.argmin(abs(b.p - st)))
            eq = clock("refinement", shellbvp.solve, sc, st, guess=b.equilibrium(i),
                       method=P.method_for(sc))
            r["refinement"].append((st, float(eq.w / H), float(eq.error_estimate)))
    r["seconds"] = clock.seconds
    return r


def run(quick: bool = False) -> dict:
    labels = QUICK if quick else tuple(CASES)
    return {label: run_case(label, instability=not quick) for label in labels}


def checks(res: dict) -> list:
    """(check, value, tolerance, pass) rows of the main case (module docstring)."""
    m = res[MAIN]
    rows = [("|w(stage 0)| / H", abs(m["w_start_over_H"]), TOL_REST),
            ("|w(end) - H| / H", abs(m["w_end_over_H"] - 1.0), TOL_END),
            ("energy at the end (mu h R^2)", abs(m["energy_end"]), TOL_ENERGY)]
    for st, _, err in m.get("refinement", ()):
        rows.append((f"refinement: change of w at stage {st} (R)", err, TOL_REFINE))
    return [(name, v, tol, v <= tol) for name, v, tol in rows]


def write(res: dict, out) -> None:
    rows = []
    for label, r in res.items():
        for st, w, e in zip(r["stage"], r["w_over_H"], r["energy"]):
            rows.append([label, st, w, e, "", ""])
        for st, w, err in r["folds"]:
            rows.append([label, st, w, "", "fold", err])
    write_csv(out / f"{STEM}.csv", ["case", "stage", "w_over_H", "energy_mu_h_R2", "event",
                                    "error_estimate"], rows)
    summary = []
    for label, r in res.items():
        ins = r.get("instability", {})
        lob = ins.get("lobed", {})
        first = r["folds"][0] if r["folds"] else (math.nan, math.nan, math.nan)
        summary.append([label, r["cells"], r["h"], r["wedging"], r["material"], r["method"],
                        r["outcome"], len(r["folds"]), first[0], first[2], r["last_stage"],
                        r["w_end_over_H"], r["thin_shell"], ins.get("kind", ""),
                        ins.get("n", ""), ins.get("p", ""), ins.get("error_estimate", ""),
                        lob.get("kind", ""),
                        round(sum(r["seconds"].values()), 2), r["stop"][:160]])
    write_csv(out / f"{STEM}_summary.csv",
              ["case", "cells", "h_over_R", "wedging_kh", "material", "method", "outcome",
               "folds", "first_fold_stage", "first_fold_error", "last_stage", "w_end_over_H",
               "max_h_kbar", "instability", "n", "instability_stage", "instability_error",
               "lobed_branch", "seconds", "stop"], summary)
    write_checks(out, STEM, checks(res))


def figure(res: dict, out) -> None:
    plt = pyplot()
    fig = plt.figure(figsize=(11, 7.6))
    ax = fig.add_subplot(2, 2, 1)
    for r in res.values():
        plot_branch(ax, r, "w_over_H", fold_size=4)
    ax.set_xlabel("stage of the wave (0: at the rim, 1: past the pole)")
    ax.set_ylabel("rim rise w / H (1: inverted)")
    ax.set_xlim(0, 1.05)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6.5, loc="center right")
    ax.set_title("The bowl's rim against the wave (o fold, D bifurcation, x stop)",
                 fontsize=9.5)

    m = res[MAIN]
    bx = fig.add_subplot(2, 2, 2)
    cmap = plt.get_cmap("viridis")
    stages = sorted(m["shapes"])
    for k, st in enumerate(stages):
        rr, zz = (np.asarray(v) for v in m["shapes"][st])
        c = cmap(k / max(1, len(stages) - 1))
        bx.plot(rr, zz, color=c, label=f"stage {st:.2f}")
        bx.plot(-rr, zz, color=c)
    bx.set_aspect("equal")
    bx.grid(alpha=0.3)
    bx.legend(fontsize=6.5, loc="lower center", ncol=2)
    bx.set_title(f"{MAIN}: meridians (R)", fontsize=9.5)
    picks = [stages[i] for i in (0, 2, 4, len(stages) - 1)] if len(stages) >= 5 else stages
    for k, st in enumerate(picks):
        cx = fig.add_subplot(2, len(picks), len(picks) + k + 1, projection="3d")
        rr, zz = (np.asarray(v) for v in m["shapes"][st])
        surface(cx, rr, zz, color=cmap(stages.index(st) / max(1, len(stages) - 1)))
        equal_3d(cx, 1.1, zmid=float(np.mean([zz.min(), zz.max()])))
        cx.view_init(elev=18, azim=-60)
        cx.set_title(f"stage {st:.2f}", fontsize=9)
    finish(fig, out, STEM)


def report(res: dict) -> None:
    for label, r in res.items():
        folds = ", ".join(f"{st:.6f} +- {err:.1e}" for st, _, err in r["folds"]) or "none"
        print(f"{label}: {r['outcome']}; folds at stage {folds}; last stage "
              f"{r['last_stage']:.4f}, w/H {r['w_end_over_H']:.6f}; max h|kbar| "
              f"{r['thin_shell']:.2f}; {sum(r['seconds'].values()):.1f} s")
        report_details(r)
    report_checks(checks(res))


def main(argv=None):
    return script_main(__doc__, argv, lambda a: run(a.quick), write, report, figure)


if __name__ == "__main__":
    main()
