"""The energy method (shellbvp.Ritz) against the spectral method on the default cap
(Theta = pi/6, h = 0.01, lam = 1, relaxed CG): time per kappa_s at fold tolerance 1e-8 and
1e-10, first call (compilation included) and steady state (median of repeats), and the
difference of the two kappa_s. Writes bench_energy_method.csv.

    python figures/bench_energy_method.py [--quick]
"""

from __future__ import annotations

import math
import statistics
import time

import shellbvp
from shellbvp import ContinuationOptions, Ritz
from shellbvp.problems import cap_eversion as ce

from _common import parser, write_csv


def spectral(tol):
    return ce.snap_curvature(math.pi / 6, 0.01, 1.0, tol=tol)


def energy(tol, scene=ce.scene(theta=math.pi / 6, h=0.01, lam=1.0)):
    br = shellbvp.follow(scene, method=Ritz(degree=12), n_folds=1, energies=False,
                         options=ContinuationOptions.to_first_fold(tol))
    return br.folds[0]


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    repeats = 3 if a.quick else 7
    rows = []
    for tol in (1e-8, 1e-10):
        for name, fn in (("spectral", spectral), ("energy", energy)):
            t0 = time.perf_counter()
            fn(tol)
            cold = time.perf_counter() - t0
            times = []
            for _ in range(repeats):
                t0 = time.perf_counter()
                r = fn(tol)
                times.append(time.perf_counter() - t0)
            p = getattr(r, "kappa_s", getattr(r, "p", math.nan))
            err = r.error_estimate
            rows.append([name, tol, p, err, cold, statistics.median(times)])
            print(f"{name:8s} tol {tol:.0e}: kappa_s = {p:.12f} +- {err:.1e}, first call "
                  f"{cold:.2f} s, steady {1e3 * statistics.median(times):.1f} ms "
                  f"(median of {repeats})", flush=True)
    for tol in (1e-8, 1e-10):
        s, e = (r for r in rows if r[1] == tol)
        print(f"tol {tol:.0e}: |kappa_s difference| = {abs(s[2] - e[2]):.1e}, energy / spectral "
              f"time {e[5] / s[5]:.2f}")
    write_csv(a.out / "bench_energy_method.csv", ["method", "tol", "kappa_s_R0", "error_estimate",
                                                   "first_call_s", "steady_s"], rows)


if __name__ == "__main__":
    main()
