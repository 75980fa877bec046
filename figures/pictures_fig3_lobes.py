"""Pictures: the caps of Fig. 3 leave axisymmetry through n lobes, in 3D.

Fig. 3's relaxed Ciarlet-Geymonat caps (lam = 1, h0/R0 = 0.01) lose stability before their
axisymmetric fold from T = Theta sqrt(R0/h0) = 4.5 on, by a subcritical bifurcation into n
circumferential waves (``fig3_revisited.py``): they snap there, through n lobes. For the
caps T = 4.5, 5, 6.5, 8, 9.5 (n = 2, 3, 4, 5, 6) this script finds that bifurcation
(``cap_eversion.first_instability``), follows the branch of n-lobed equilibria from it
(``shellbvp.follow_bifurcation``, harmonics 0, n, 2n) for STEPS continuation steps, and
draws its last state (``LobedBranch.plot3d``): the whole cap seen from above, coloured by
the lobes' normal displacement (the harmonics n and 2n of the 2D state, along the
axisymmetric base's normal) in thicknesses h, the lobes drawn MAGNIFY times. One colour
scale for all caps.

Writes pictures_fig3_lobes.png and pictures_fig3_lobes.csv (per cap: T, Theta, n,
kappa_c of the bifurcation, kappa and the critical mode's amplitude of the state drawn, the
largest and smallest lobe displacement in h).

    python figures/pictures_fig3_lobes.py [--quick] [--out DIR]
"""

from __future__ import annotations

import math
import time

import numpy as np

from _common import parser, pyplot, save_png, write_csv
import shellbvp
from shellbvp.problems import cap_eversion as ce
from shellbvp.surface import OutputUnits, lobed_surface

STEM = "pictures_fig3_lobes"
H0, LAM = 0.01, 1.0
T_VALUES, QUICK_T = (4.5, 5.0, 6.5, 8.0, 9.5), (5.0, 8.0)
#: continuation steps along each lobed branch (the lobes grow to about a thickness)
STEPS, QUICK_STEPS = 40, 6
MAGNIFY = 12.0
#: seen from above: the n lobes all round
VIEW = (55.0, -60.0)
#: lengths in thicknesses: the lobes' displacement reads as xi
IN_H = OutputUnits(length=1 / H0, line_force=1.0, line_moment=1 / H0, length_label="h")
HEADER = ["T", "theta_rad", "n", "kappa_c", "kappa_drawn", "amplitude_drawn",
          "lobe_w_min_over_h", "lobe_w_max_over_h", "lobed_points", "seconds"]


def lobed(T: float, steps: int):
    """The cap of shallowness T: its bifurcation and the first ``steps`` points of its
    lobed branch."""
    theta = T * math.sqrt(H0)
    ins = ce.first_instability(theta, H0, LAM)
    if ins.kind != "bifurcation":
        raise RuntimeError(f"T = {T}: the first instability is {ins.kind}, not a "
                           f"bifurcation")
    options = shellbvp.postbuckling.LOBED_OPTIONS.with_(max_steps=steps)
    return shellbvp.follow_bifurcation(ins, K=2, n_folds=0, estimate_error=False,
                                       options=options)


def main():
    args = parser(__doc__).parse_args()
    caps = QUICK_T if args.quick else T_VALUES
    steps = QUICK_STEPS if args.quick else STEPS
    rows, branches = [], []
    for T in caps:
        t = time.perf_counter()
        br = lobed(T, steps)
        surface = lobed_surface(br.discretisation, br.states[-1], br.p[-1], units=IN_H)
        w = surface.fields["lobe_normal_displacement"]
        rows.append([T, T * math.sqrt(H0), br.n, br.p_c, float(br.p[-1]),
                     float(br.amplitude[-1]), float(w.min()), float(w.max()), len(br.p),
                     round(time.perf_counter() - t)])
        branches.append(br)
        print(dict(zip(HEADER, rows[-1])), flush=True)
    write_csv(args.out / f"{STEM}.csv", HEADER, rows)
    top = max(max(abs(r[6]), abs(r[7])) for r in rows)
    plt = pyplot()
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize

    fig = plt.figure(figsize=(2.6 * len(caps) + 1.0, 3.2))
    grid = fig.add_gridspec(1, len(caps), wspace=0.0, left=0.0, right=0.92)
    for k, (row, br) in enumerate(zip(rows, branches)):
        ax = fig.add_subplot(grid[k], projection="3d")
        br.plot3d(len(br.p) - 1, "lobe_normal_displacement", ax, magnify=MAGNIFY,
                  vmin=-top, vmax=top, cmap="coolwarm", colorbar=False, units=IN_H,
                  cut=0, view=VIEW,
                  title=f"T = {row[0]:g}: n = {row[2]}\nkappa R0 = {row[4]:.3f} "
                        f"(bifurcation {row[3]:.3f})")
    cax = fig.add_axes((0.93, 0.2, 0.012, 0.6))
    fig.colorbar(ScalarMappable(Normalize(-top, top), "coolwarm"), cax=cax).set_label(
        f"lobes' normal displacement / h (drawn x {MAGNIFY:g})", fontsize=8)
    save_png(fig, args.out / f"{STEM}.png")
    print(f"wrote {args.out / (STEM + '.png')} and .csv")


if __name__ == "__main__":
    main()
