"""Pictures: the isotropic bud with its lobes, in 3D.

Budding's isotropic case (``problems/budding.py``, paper Section 5.4: a clamped cap, R0 =
0.25, h0 = 0.005, Theta = pi/8, lam = 7.5, the metric and the curvature stimulated alike on
the patch s < Theta/4) loses axisymmetry at its patch edge into n = 8 waves at kbar_c =
56.56, subcritically; its branch of lobed equilibria turns at a fold (kbar ~ 34.5 with
harmonics 0, 8, 16) and comes back stable (``bud_lobed.py``, whose settings this script
takes). Here that branch (K = 2, degree 32) is followed from the bifurcation until kbar
leaves [0, KBAR_MAX], and the stable lobed state at kbar = KBAR_SHAPE is drawn
(``LobedBranch.plot3d``), a quarter cut away: left, as it is, coloured by its normal
displacement from the reference cap in thicknesses h; right, coloured by the lobes' normal
displacement (the harmonics 8 and 16 along the axisymmetric base's normal) in h, the lobes
drawn MAGNIFY times. Seen from above, the bud's head would hide the lobes at its neck.
``--quick`` draws instead the branch's sixth point, near the bifurcation (unstable, small
lobes).

Writes pictures_bud.png and pictures_bud.csv (the state drawn: kbar, the critical mode's
amplitude, xi = a w_max / h, the lobes' extreme normal displacements in h).

    python figures/pictures_bud.py [--quick] [--out DIR]
"""

from __future__ import annotations

import time

import numpy as np

from _common import parser, pyplot, save_png, write_csv
import shellbvp
from shellbvp.continuation import newton
from shellbvp.pictures import plot_lobed3d
from shellbvp.problems import budding
from shellbvp.surface import OutputUnits, lobed_surface

import bud_lobed

STEM = "pictures_bud"
K, DEGREE = 2, 32
KBAR_MAX, KBAR_SHAPE = bud_lobed.KBAR_MAX, bud_lobed.KBAR_SHAPE
MAGNIFY = 2.0
QUICK_STEPS = 6
HEADER = ["kbar", "amplitude", "xi", "lobe_w_min_over_h", "lobe_w_max_over_h", "stable_part",
          "points", "seconds"]


def stable_state(br, kbar):
    """(U, kbar) of the stable lobed state at exactly ``kbar``: Newton with kbar prescribed
    from the nearest branch point past the fold."""
    system = shellbvp.postbuckling.LobedSystem(br.discretisation, br.critical[2])
    i0 = br.folds[0].index + 1
    j = i0 + int(np.argmin(np.abs(br.p[i0:] - kbar)))
    res = newton(system, br.states[j], kbar, 0.0, 1.0, kbar, tol=1e-9, maxiter=25,
                 fail_fast=False)
    if not res.ok:
        raise shellbvp.ConvergenceError(f"no lobed state at kbar = {kbar}: {res.history}")
    return res.U, kbar, float(system.monitor(res.U)[0])


def main():
    args = parser(__doc__).parse_args()
    t = time.perf_counter()
    ins = budding.first_instability(1.0, 1.0)
    options = bud_lobed.OPTIONS.with_(max_steps=QUICK_STEPS) if args.quick else \
        bud_lobed.OPTIONS
    br = shellbvp.follow_bifurcation(ins, K=K, degree=DEGREE, n_folds=0,
                                     p_stop=(0.0, KBAR_MAX), options=options,
                                     estimate_error=False)
    print(f"{br}  ({time.perf_counter() - t:.0f} s)", flush=True)
    f = br.discretisation
    h = f.eq.scene.h
    if args.quick:
        U, kbar, a = br.states[-1], float(br.p[-1]), float(br.amplitude[-1])
    else:
        U, kbar, a = stable_state(br, KBAR_SHAPE)
    in_h = OutputUnits(length=1 / h, line_moment=1 / h, length_label="h")
    w = lobed_surface(f, U, kbar, units=in_h).fields["lobe_normal_displacement"]
    row = [kbar, a, a * br.koiter.w_max / h, float(w.min()), float(w.max()),
           int(not args.quick), len(br.p), round(time.perf_counter() - t)]
    print(dict(zip(HEADER, row)), flush=True)
    write_csv(args.out / f"{STEM}.csv", HEADER, [row])
    plt = pyplot()
    fig = plt.figure(figsize=(10.0, 4.2), layout="constrained")
    left = fig.add_subplot(1, 2, 1, projection="3d")
    right = fig.add_subplot(1, 2, 2, projection="3d")
    plot_lobed3d(f, U, kbar, "normal_displacement", left, units=in_h, view=(20, -60),
                 title=f"kbar = {kbar:.4g}: the bud as it is")
    plot_lobed3d(f, U, kbar, "lobe_normal_displacement", right, magnify=MAGNIFY,
                 units=in_h, view=(15, -60),
                 title=f"kbar = {kbar:.4g}: its lobes, drawn x {MAGNIFY:g}")
    save_png(fig, args.out / f"{STEM}.png")
    print(f"wrote {args.out / (STEM + '.png')} and .csv")


if __name__ == "__main__":
    main()
