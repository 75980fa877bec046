"""Cost of a load-deflection curve through a limit point (medians over repeated runs, steady
state, one pinned core; the first call, which traces and compiles, reported apart).

The cases are gallery scene files whose curve has a load maximum, followed by
``SceneFile.follow`` at the file's default tolerance, its steps limited so that the curve has
at least ``POINTS`` points (``[solver] points``): the whole curve (every point of the
pseudo-arclength continuation) and the limit point located to that tolerance, with its
error estimate.

* ``disc-spring-almen-snap``: a conical disc spring (h0/t = 2) pushed at its inner edge, past
  its load maximum and its minimum;
* ``cap-ring-load``: the clamped shallow cap of Teng & Rotter (1989) under a ring load, past
  its limit point (where that scene file is present).

The goal the gallery's issue sets: under 5 s per curve of 100-300 points. There is no
AUTO-07p model of these shells beside us (the peer's model is the everting cap:
``bench_snap.py``), so these are absolute times on this machine, not ratios.

Writes bench_limit_point.csv.

    python figures/bench_limit_point.py [--quick]
"""

from __future__ import annotations

from _pinned import PINNED  # first: before numpy reads its threads

import dataclasses  # noqa: E402
import statistics  # noqa: E402

from _common import HERE, parser, wall_times, write_csv  # noqa: E402
import shellbvp  # noqa: E402

CASES = ("disc-spring-almen-snap", "cap-ring-load")
GOAL_S = 5.0
#: points asked of each curve (the issue's 100-300)
POINTS = 150


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    repeat = 3 if a.quick else 7
    rows = []
    for name in CASES:
        path = HERE.parent / "problems" / "gallery" / f"{name}.toml"
        if not path.exists():
            print(f"{name}: no scene file, skipped")
            continue
        # the curve drawn with 150 points or more ([solver] points), as a figure needs it
        sf = dataclasses.replace(shellbvp.load_scene(path), points=POINTS)
        first = wall_times(sf.follow, 1)[0]
        times = wall_times(sf.follow, repeat)
        result = sf.follow()
        fold = result.folds[0] if result.folds else None
        points = len(result.branch.points)
        med = statistics.median(times)
        rows.append([name, points, len(result.folds),
                     "" if fold is None else fold["p"],
                     "" if fold is None else fold["p_error"], sf.tol, first, med,
                     min(times), max(times), repeat, med < GOAL_S])
        limit = "no limit point" if fold is None else \
            f"limit point {fold['p']:.6g} +- {fold['p_error']:.2g}"
        print(f"{name}: {points} points, {limit}; first call {first:.2f} s, median "
              f"{med:.3f} s (min {min(times):.3f}, max {max(times):.3f}, {repeat} runs)"
              f"{'' if PINNED else ' (not pinned)'}; goal {GOAL_S:g} s: "
              f"{'met' if med < GOAL_S else 'missed'}")
    write_csv(a.out / "bench_limit_point.csv",
              ["case", "points", "folds", "limit_load", "limit_error", "tol_t",
               "first_call_s", "median_s", "min_s", "max_s", "runs", "goal_met"], rows)


if __name__ == "__main__":
    main()
