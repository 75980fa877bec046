"""Volvox: the snap that starts inversion of a spherical embryo (``shellbvp.problems.volvox``;
docs/cell-sheets.md).

Cases (the scene's own parameters; none could be read from Höhn et al. or Haas & Goldstein,
see the scene's docstring): the closed sphere of thickness h = 0.1 R; the bend region (width
0.35 R on the equator) wedging to k_bend = -10/R and the posterior contracting to
g_post = 0.8 (the default), each of the two changes alone, and the default with the reduced
energies derived from 3D (``nh``; ``cg`` relaxed, lam = 1) beside the Koiter shell with
nu = 1/2. Each branch runs from the sphere (stage 0) to its first fold (the snap) or to
stage 1.5; the fold is located to 1e-8 with its refinement-ladder error estimate and again
on a Chebyshev degree 16 higher. Beyond axisymmetry: ``first_instability`` along the
Koiter branches.

Checks, tolerances fixed before the run:

* stage 0 (no stimulus): the sphere, |w| <= 1e-12 R;
* closed form: a uniform stretch g = 0.9 and curvature -1/0.9 in every region is a sphere of
  radius 0.9 R, stress-free: at stage 1, |r(equator) - 0.9| <= 1e-8 R, energy <= 1e-12;
* symmetry: with the same contraction 0.9 on both sides of the bend region (centred on the
  equator) the shape is symmetric about the equatorial plane: at stage 0.5,
  max |r(s) - r(pi - s)| <= 1e-8 R;
* refinement: the default's snap on the next finer degrees (the ladder) and on a degree 16
  higher agree to <= 1e-6 in the stage;
* no self-contact (the engine has none) along the branch up to the snap.

    python figures/cell_sheets_volvox.py [--quick] [--out DIR]
"""

from __future__ import annotations

import math
import time

import numpy as np
from _cell_sheets import (Clock, equal_3d, instability_record, plot_branch, report_checks,
                          report_details, script_main, self_contact, surface, write_checks)
from _common import finish, pyplot, write_csv
import shellbvp
from shellbvp.methods import default_nodes
from shellbvp.problems import volvox as V

STEM = "cell_sheets_volvox"
TOL_REST, TOL_SPHERE, TOL_ENERGY, TOL_SYMMETRY, TOL_FOLD = 1e-12, 1e-8, 1e-12, 1e-8, 1e-6
#: label -> the scene's keyword arguments
CASES = {
    "bend + posterior contraction, koiter": {},
    "bend region alone, koiter": dict(g_post=1.0),
    "posterior contraction alone, koiter": dict(k_bend=-1.0),
    "bend + posterior contraction, nh": dict(material="nh"),
    "bend + posterior contraction, cg": dict(material="cg"),
}
MAIN = "bend + posterior contraction, koiter"
QUICK = (MAIN,)
#: stages of the drawn shapes (the last: the snap)
SHAPE_STAGES = (0.0, 0.5, 0.8)
#: the lobed branches are followed up to this stage
STAGE_MAX = 1.6


def run_case(label, *, instability: bool) -> dict:
    kw = CASES[label]
    sc = V.scene(**kw)
    clock = Clock()
    b = clock("branch", V.branch, sc)
    r = {"label": label, "material": kw.get("material", "koiter"), "stop": b.stop,
         "stage": b.p.tolist(), "w": b.w.tolist(), "energy": b.energy.tolist(),
         "folds": [(float(f.p), float(f.w), float(f.error_estimate)) for f in b.folds],
         "last_stage": float(b.p[-1]), "w_end": float(b.w[-1]),
         "thin_shell": max(b.equilibrium(i).thin_shell[1] for i in range(len(b.p))),
         "contact": next((float(b.p[i]) for i in range(len(b.p))
                          if self_contact(b.equilibrium(i).r, b.equilibrium(i).z)), None)}
    if b.stop:
        # where the branch stops, at a finer degree: the model's limit only if it stays
        finer = shellbvp.Chebyshev(nodes=default_nodes(sc) + 16)
        b2 = clock("branch (finer)", V.branch, sc, method=finer, energies=False)
        r["last_stage_finer"], r["stop_finer"] = float(b2.p[-1]), b2.stop
    if label == MAIN:
        finer = shellbvp.Chebyshev(nodes=default_nodes(sc) + 16)
        b2 = clock("branch (finer)", V.branch, sc, method=finer, energies=False)
        r["fold_finer"] = float(b2.folds[0].p) if b2.folds else math.nan
        r["shapes"] = {}
        for st in SHAPE_STAGES:
            i = int(np.argmin(abs(b.p - st)))
            eq = b.equilibrium(i)
            r["shapes"][f"stage {abs(b.p[i]):.2f}"] = (eq.r.tolist(), eq.z.tolist())
        if b.folds:
            eq = b.folds[0].equilibrium
            r["shapes"][f"the snap, stage {b.folds[0].p:.4f}"] = (eq.r.tolist(), eq.z.tolist())
    if instability and r["material"] == "koiter":
        r["instability"] = instability_record(clock, b, p_stop=(0.0, STAGE_MAX))
    r["seconds"] = clock.seconds
    return r


def closed_form_checks() -> list:
    """(check, value, tolerance) of the stage-0 state, the uniform sphere and the symmetry
    (module docstring)."""
    rows = []
    sc = V.scene()
    rows.append(("stage 0: |w| (R)", abs(shellbvp.solve(sc, 0.0).w), TOL_REST))
    g = 0.9
    uniform = V.scene(g_ant=g, g_bend=g, g_post=g, k_ant=-1 / g, k_bend=-1 / g, k_post=-1 / g)
    eq = shellbvp.solve(uniform, 0.5)
    eq = shellbvp.solve(uniform, 1.0, guess=eq)
    r_eq = float(eq(np.array([math.pi / 2]))[0][0])       # r at the equator, s = pi/2
    rows.append(("uniform contraction 0.9: |r(equator) - 0.9| (R)", abs(r_eq - g), TOL_SPHERE))
    rows.append(("uniform contraction 0.9: energy", abs(eq.energy), TOL_ENERGY))
    sym = V.scene(g_ant=g, g_post=g)
    eq = shellbvp.solve(sym, 0.5)
    s = np.linspace(0.05, math.pi / 2 - 0.2, 40)
    profile = lambda x: eq(x)[0]                     # noqa: E731  (r at arclength x)
    rows.append(("symmetric contraction: max |r(s) - r(pi - s)| (R)",
                 float(np.max(abs(profile(s) - profile(math.pi - s)))), TOL_SYMMETRY))
    return rows


def run(quick: bool = False) -> dict:
    labels = QUICK if quick else tuple(CASES)
    res = {"cases": {label: run_case(label, instability=not quick) for label in labels}}
    t = time.perf_counter()
    res["closed_form"] = [] if quick else closed_form_checks()
    res["closed_form_seconds"] = time.perf_counter() - t
    return res


def checks(res: dict) -> list:
    m = res["cases"][MAIN]
    rows = list(res["closed_form"])
    if m["folds"]:
        rows.append(("the snap: ladder error (stage)", m["folds"][0][2], TOL_FOLD))
        if "fold_finer" in m:
            rows.append(("the snap: change at degree + 16 (stage)",
                         abs(m["fold_finer"] - m["folds"][0][0]), TOL_FOLD))
    return [(n, v, t, v <= t) for n, v, t in rows]


def write(res: dict, out) -> None:
    rows = []
    for label, r in res["cases"].items():
        for st, w, e in zip(r["stage"], r["w"], r["energy"]):
            rows.append([label, st, w, e, "", ""])
        for st, w, err in r["folds"]:
            rows.append([label, st, w, "", "fold", err])
    write_csv(out / f"{STEM}.csv", ["case", "stage", "invagination_w_over_R", "energy_mu_h_R2",
                                    "event", "error_estimate"], rows)
    summary = []
    for label, r in res["cases"].items():
        ins = r.get("instability", {})
        first = r["folds"][0] if r["folds"] else (math.nan, math.nan, math.nan)
        summary.append([label, r["material"], first[0], first[2], first[1], r["last_stage"],
                        r["w_end"], r["thin_shell"], r["contact"] if r["contact"] else "",
                        ins.get("kind", ""), ins.get("n", ""), ins.get("p", ""),
                        ins.get("error_estimate", ""), ins.get("lobed", {}).get("kind", ""),
                        round(sum(r["seconds"].values()), 2), r["stop"][:160]])
    write_csv(out / f"{STEM}_summary.csv",
              ["case", "material", "snap_stage", "snap_error", "snap_w_over_R", "last_stage",
               "w_end_over_R", "max_h_kbar", "self_contact_stage", "instability", "n",
               "instability_stage", "instability_error", "lobed_branch", "seconds", "stop"],
              summary)
    write_checks(out, STEM, checks(res))


def figure(res: dict, out) -> None:
    plt = pyplot()
    fig = plt.figure(figsize=(11, 7.6))
    ax = fig.add_subplot(2, 2, 1)
    for r in res["cases"].values():
        plot_branch(ax, r, "w")
    ax.set_xlabel("stage (0: the sphere, 1: the full cell-shape changes)")
    ax.set_ylabel("invagination w / R")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6.5, loc="upper left")
    ax.set_title("Posterior pole toward the anterior (o the snap, D bifurcation, x stop)",
                 fontsize=9.5)
    m = res["cases"][MAIN]
    bx = fig.add_subplot(2, 2, 2)
    cmap = plt.get_cmap("viridis")
    shapes = list(m["shapes"].items())
    for k, (name, (rr, zz)) in enumerate(shapes):
        c = cmap(k / max(1, len(shapes) - 1))
        bx.plot(rr, zz, color=c, label=name)
        bx.plot(-np.asarray(rr), zz, color=c)
    bx.set_aspect("equal")
    bx.grid(alpha=0.3)
    bx.legend(fontsize=6.5, loc="lower center")
    bx.set_title(f"{MAIN}: meridians (R; anterior pole on top)", fontsize=9.5)
    for k, (name, (rr, zz)) in enumerate(shapes):
        cx = fig.add_subplot(2, len(shapes), len(shapes) + k + 1, projection="3d")
        surface(cx, np.asarray(rr), np.asarray(zz), color=cmap(k / max(1, len(shapes) - 1)))
        equal_3d(cx, 1.1, zmid=float(np.mean([min(zz), max(zz)])))
        cx.view_init(elev=12, azim=-60)
        cx.set_title(name, fontsize=9)
    finish(fig, out, STEM)


def report(res: dict) -> None:
    for label, r in res["cases"].items():
        folds = ", ".join(f"{st:.8f} +- {err:.1e} (w = {w:.4f} R)" for st, w, err in r["folds"])
        print(f"{label}: snap at stage {folds or 'none'}; last stage {r['last_stage']:.4f}, "
              f"w = {r['w_end']:.4f} R; max h|kbar| {r['thin_shell']:.2f}; self-contact "
              f"{r['contact']}; {sum(r['seconds'].values()):.1f} s")
        report_details(r)
        if "fold_finer" in r:
            print(f"   degree + 16: snap at stage {r['fold_finer']:.8f}")
    report_checks(checks(res))


def main(argv=None):
    return script_main(__doc__, argv, lambda a: run(a.quick), write, report, figure)


if __name__ == "__main__":
    main()
