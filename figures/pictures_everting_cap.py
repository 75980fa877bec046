"""Pictures: the everting cap of the paper (Section 5.2: Theta = pi/6, h0/R0 = 0.01,
relaxed Ciarlet-Geymonat, lam = 1) along its whole equilibrium branch, from the undeformed
cap (kappa = 0) through its snap (the first fold, kappa_s R0 = 4.2214) and the branch's
further folds to the everted cap (kappa R0 = 6), in 3D.

* ``pictures_everting_cap.gif``: the animation (``Branch.animate``): the cap in 3D with a
  quarter cut away, coloured by its normal displacement from the reference sphere, beside
  kappa against the edge's displacement w, the current point marked;
* ``pictures_everting_cap.png``: four states of that branch (undeformed, at the snap, half
  way along the branch, the last), each in 3D coloured by the hoop stress resultant N2
  (per mu* h; one colour scale), and the branch with the four marked;
* ``pictures_everting_cap.csv``: the branch (kappa, w, its arclength, the points that are
  frames of the animation).

A cap held at its apex and free at its edge, under a stimulus only: its equilibrium branch
snakes through ten folds (kappa_s, then -2.04, 3.53, ...) before it everts; the cap snaps
at the first (and where a bifurcation comes first, earlier: n = 3 at 4.1758, see
``fig3_revisited.py``), jumping to the far stable part of the branch at the same kappa.

    python figures/pictures_everting_cap.py [--quick] [--out DIR]
"""

from __future__ import annotations

import math
import time

import numpy as np

from _common import parser, save_png, states_and_branch, write_csv
import shellbvp
from shellbvp.problems import cap_eversion as ce

STEM = "pictures_everting_cap"
THETA, H0, LAM = math.pi / 6, 0.01, 1.0
KAPPA_MAX = 6.0
FRAMES, QUICK_FRAMES = 72, 6


def branch(quick: bool):
    """The cap's branch from kappa = 0 to kappa = KAPPA_MAX (through every fold), or to
    past its first fold (``quick``)."""
    sc = ce.scene(THETA, H0, LAM)
    if quick:
        return shellbvp.follow(sc, n_folds=1, energies=False)
    return shellbvp.follow(sc, p_stop=(-3 * KAPPA_MAX, KAPPA_MAX), energies=False,
                           options=shellbvp.ContinuationOptions(max_steps=600))


def drawn(br) -> list:
    """The states drawn in the still picture, (equilibrium, w, kappa) each: the undeformed
    cap, the snap (the first fold), half way along the branch's arclength, the last
    point."""
    half = int(np.searchsorted(br.arclength, br.arclength[-1] / 2))
    out = [(br.equilibrium(i, energies=False), br.w[i], br.p[i]) for i in (0, half, -1)]
    snap = br.folds[0]
    return [out[0], (snap.equilibrium, snap.w, snap.p), *out[1:]]


def still(br, states, out):
    fig = states_and_branch([(eq, w, p, f"kappa R0 = {p:.3f}") for eq, w, p in states], "N2",
                            (br.w, br.p), xlabel="w / R0 (edge relative to apex)",
                            ylabel="kappa R0", label="hoop stress resultant N2 [mu* h]",
                            folds=[(f.w, f.p) for f in br.folds])
    save_png(fig, out / f"{STEM}.png")
    print(f"wrote {out / (STEM + '.png')} and .csv")


def main():
    args = parser(__doc__).parse_args()
    t0 = time.perf_counter()
    br = branch(args.quick)
    print(f"{br}  ({time.perf_counter() - t0:.0f} s)", flush=True)
    states = drawn(br)
    frames = QUICK_FRAMES if args.quick else FRAMES
    from shellbvp.pictures import frame_indices

    in_gif = set(frame_indices(br.arclength, frames).tolist())
    write_csv(args.out / f"{STEM}.csv", ["kappa_R0", "w_over_R0", "arclength",
                                         "in_animation"],
              [[repr(float(br.p[i])), repr(float(br.w[i])), repr(float(br.arclength[i])),
                int(i in in_gif)] for i in range(len(br.p))])
    still(br, states, args.out)
    t = time.perf_counter()
    br.animate(args.out / f"{STEM}.gif", frames=frames, fps=12, dpi=72)
    print(f"wrote {args.out / (STEM + '.gif')} ({frames} frames, "
          f"{time.perf_counter() - t:.0f} s)")


if __name__ == "__main__":
    main()
