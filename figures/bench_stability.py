"""Cost of the stability analysis beyond axisymmetry (medians over repeated runs, steady
state; the first call, which traces and compiles the Hessian kernel, reported apart).

* all harmonics n = 0..20 at one equilibrium (the default cap at kappa = 2, default degree);
* the first instability of the default cap's branch (Theta = pi/6, h = 0.01, lam = 1):
  branch from kappa = 0, harmonics at every point, the bifurcation located.

Writes bench_stability.csv.

    python figures/bench_stability.py [--quick]
"""

from __future__ import annotations

import math
import statistics

from _common import parser, wall_times, write_csv
import shellbvp
from shellbvp.problems import cap_eversion as ce


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    repeat = 3 if a.quick else 7
    eq = ce.equilibrium(2.0, math.pi / 6, 0.01)
    first = wall_times(lambda: shellbvp.modes(eq, range(0, 21)), 1)[0]
    modes = wall_times(lambda: shellbvp.modes(eq, range(0, 21)), repeat)
    first_b = wall_times(lambda: ce.first_instability(math.pi / 6, 0.01), 1)[0]
    inst = wall_times(lambda: ce.first_instability(math.pi / 6, 0.01), repeat)
    rows = [["modes n=0..20, one equilibrium", first, statistics.median(modes), min(modes),
             max(modes), repeat],
            ["first_instability, default cap", first_b, statistics.median(inst), min(inst),
             max(inst), repeat]]
    for r in rows:
        print(f"{r[0]}: first call {r[1]:.3f} s, median {r[2]:.3f} s (min {r[3]:.3f}, max "
              f"{r[4]:.3f}, {r[5]} runs)")
    write_csv(a.out / "bench_stability.csv",
              ["task", "first_call_s", "median_s", "min_s", "max_s", "runs"], rows)


if __name__ == "__main__":
    main()
