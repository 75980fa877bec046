"""Benchmark: what pictures and ParaView files cost beside the branch they show.

The everting cap's scene file (``shellbvp follow everting-cap``) with ``[solver] points =
POINTS`` (a copy in a temporary folder) is followed to its snap, POINTS points; then, in
this one process:

* the branch's own computation, ``SceneFile.follow()``: the first call (which compiles the
  scene's programs, or loads them from the disk cache when it holds them) and the steady
  state (later calls);
* exporting it for ParaView, ``Branch.to_vtk(folder, units=OutputUnits.of(file))``: one
  file per point (a ring of 64 angles) and the ``.pvd``;
* drawing one 3D picture, ``Equilibrium.plot3d("N2")`` of the state at the snap and saving
  it as a PNG (Agg, 100 dpi): the first call (which imports matplotlib's 3D toolkit) and
  the steady state;
* an animation of the branch, ``Branch.animate`` (FRAMES frames, GIF, 72 dpi).

First calls are timed once; the steady states are medians of REPEATS runs (fewer for the
branch and the animation, ``--quick`` fewer still). Writes bench_pictures.csv (what, points,
first call s, median s, runs) and prints it.

    python figures/bench_pictures.py [--quick] [--out DIR]
"""

from __future__ import annotations

import statistics
import tempfile
import time
from pathlib import Path

from _common import parser, write_csv

POINTS = 400
REPEATS, BRANCH_REPEATS, FRAMES = 11, 5, 60
QUICK = dict(points=40, repeats=3, branch_repeats=2, frames=6)
STEM = "bench_pictures"


def timed(f):
    t = time.perf_counter()
    out = f()
    return time.perf_counter() - t, out


def scene_file(folder: Path, points: int):
    import shellbvp

    text = shellbvp.scenefile.example("everting-cap").read_text()
    path = folder / "everting-cap.toml"
    path.write_text(text.replace("[solver]\n", f"[solver]\npoints = {points}\n"))
    return shellbvp.load_scene(path)


def main():
    args = parser(__doc__).parse_args()
    q = QUICK if args.quick else dict(points=POINTS, repeats=REPEATS,
                                      branch_repeats=BRANCH_REPEATS, frames=FRAMES)
    import matplotlib

    matplotlib.use("Agg")
    from shellbvp.surface import OutputUnits

    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        sf = scene_file(tmp, q["points"])
        first, run = timed(sf.follow)
        steady = [timed(sf.follow)[0] for _ in range(q["branch_repeats"])]
        br = run.branch
        n = len(br.points)
        rows.append(["follow (the branch itself)", n, first, statistics.median(steady),
                     len(steady)])
        units = OutputUnits.of(sf)
        first, _ = timed(lambda: br.to_vtk(tmp / "vtk", units=units))
        steady = [timed(lambda: br.to_vtk(tmp / "vtk", units=units))[0]
                  for _ in range(q["branch_repeats"])]
        rows.append(["to_vtk (every point and the .pvd)", n, first, statistics.median(steady),
                     len(steady)])
        eq = br.folds[0].equilibrium
        import matplotlib.pyplot as plt

        def picture():
            ax = eq.plot3d("N2")
            ax.figure.savefig(tmp / "snap.png", dpi=100)
            plt.close(ax.figure)

        first, _ = timed(picture)
        steady = [timed(picture)[0] for _ in range(q["repeats"])]
        rows.append(["plot3d + savefig PNG (one picture)", 1, first,
                     statistics.median(steady), len(steady)])
        steady = [timed(lambda: br.animate(tmp / "snap.gif", frames=q["frames"], dpi=72,
                                           progress=False))[0]
                  for _ in range(q["branch_repeats"])]
        rows.append([f"animate GIF ({q['frames']} frames)", q["frames"], steady[0],
                     statistics.median(steady[1:] or steady), len(steady)])
    header = ["what", "points", "first_call_s", "median_s", "runs"]
    write_csv(args.out / f"{STEM}.csv", header,
              [[r[0], r[1], f"{r[2]:.3f}", f"{r[3]:.3f}", r[4]] for r in rows])
    for r in rows:
        print(f"{r[0]:40s} {r[1]:5d} points: first {r[2]:7.2f} s, median {r[3]:7.3f} s "
              f"of {r[4]}")


if __name__ == "__main__":
    main()
