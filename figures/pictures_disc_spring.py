"""Pictures: the steel disc spring of the gallery that snaps (``problems/gallery/
disc-spring-almen-snap.toml``: D_e = 100 mm, D_i = 50 mm, t = 2.5 mm, cone height 5 mm,
pushed down at its inner edge by a force F, its outer edge on a flat plate), in 3D along
its load-deflection curve, in the file's own units (mm, N, MPa).

The spring is followed from F = 0 through its load maximum (where, under a given load, it
snaps) and its minimum to past flat (``SceneFile.follow``; ``gallery_disc_spring.py``
compares the curve with the Almen-Laszlo formula). Drawn: the unloaded spring, the load
maximum and the load minimum (the branch's two folds) and the last point, each in 3D with
a quarter cut away, coloured by the meridional bending moment per unit length (N mm / mm:
the file's modulus x length^2), one colour scale; beside them F against the deflection s
with the four marked. Writes pictures_disc_spring.png and pictures_disc_spring.csv (the
branch: F, s and its folds).

    python figures/pictures_disc_spring.py [--quick] [--out DIR]
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from _common import HERE, parser, save_png, states_and_branch, write_csv
import shellbvp
from shellbvp.surface import OutputUnits

STEM = "pictures_disc_spring"
SCENE = HERE.parent / "problems" / "gallery" / "disc-spring-almen-snap.toml"
#: points of the branch (the file's [solver] points, which it leaves unset)
POINTS, QUICK_POINTS = 80, 20


def main():
    args = parser(__doc__).parse_args()
    sf = replace(shellbvp.load_scene(SCENE), points=QUICK_POINTS if args.quick else POINTS)
    t = time.perf_counter()
    run = sf.follow()
    br = run.branch
    print(f"{br}  ({time.perf_counter() - t:.0f} s)", flush=True)
    F = sf.parameter_value(br.p)
    s = np.array([sf.observe(br.system, pt.U, pt.p)["deflection"] for pt in br.points])
    folds = [(float(sf.observe(f.system, f.U, f.p)["deflection"]),
              float(sf.parameter_value(f.p)), f) for f in br.folds]
    states = [(br.equilibrium(0, energies=False), s[0], F[0])]
    states += [(f.equilibrium, x, y) for x, y, f in folds[:2]]
    states += [(br.equilibrium(len(br.p) - 1, energies=False), s[-1], F[-1])]
    write_csv(args.out / f"{STEM}.csv", ["F_N", "deflection_mm", "is_fold"],
              sorted([[repr(float(F[i])), repr(float(s[i])), 0] for i in range(len(br.p))]
                     + [[repr(y), repr(x), 1] for x, y, _ in folds],
                     key=lambda r: float(r[1])))
    fig = states_and_branch(
        [(eq, x, y, f"F = {y:.0f} N") for eq, x, y in states], "moment", (s, F),
        xlabel="deflection s [mm]", ylabel="F [N]",
        label="meridional bending moment [N mm/mm]", units=OutputUnits.of(sf),
        folds=[(x, y) for x, y, _ in folds])
    save_png(fig, args.out / f"{STEM}.png")
    print(f"wrote {args.out / (STEM + '.png')} and .csv")


if __name__ == "__main__":
    main()
