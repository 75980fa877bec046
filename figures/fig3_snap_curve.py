"""Fig. 3 of Taffetani & Pezzulla: snap curvature kappa_s R0 against the shallowness
T = Theta sqrt(R0/h0), relaxed model (rho1, rho2 minimising the energy), lam in
{0.01, 0.1, 1, 10}, h0/R0 = 0.01, with the morphoelastic Koiter shell (nu = 1/2) as the solid
line. T runs from below the onset of snapping (computed for every curve, vertical ticks) to
10 (each curve one ``snap_curve`` sweep: the caps after the first snapping one are found from
the folds before them). Writes fig3_snap_curve.png, fig3_snap_curve.csv (every kappa_s with its error estimate)
and fig3_onset.csv.

    python figures/fig3_snap_curve.py [--quick] [--h 0.01] [--jobs 2]

With ``--jobs N`` the onsets and the sweeps' chunks run on N local processes (the values are
the same: the chunks do not depend on who runs them).
"""

from __future__ import annotations

import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from tqdm import tqdm

from _common import finish, parser, pyplot, write_csv
from shellbvp.problems import cap_eversion as ce
from shellbvp.sweep import local_executor

LAMS = (0.01, 0.1, 1.0, 10.0)


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--h", type=float, default=0.01, help="h0/R0 (default 0.01)")
    p.add_argument("--jobs", type=int, default=1, help="local processes (default 1)")
    a = p.parse_args(argv)
    curves = [("koiter", 1.0)] + [("cg", lam) for lam in ((0.1, 10.0) if a.quick else LAMS)]
    T_values = np.array([3.0, 5.0, 7.0, 9.0]) if a.quick else np.arange(1.5, 10.001, 0.25)
    rows, onsets, times = [], [], []
    pool = local_executor(a.jobs) if a.jobs > 1 else None
    pending = {} if a.quick or pool is None else {
        (material, lam): pool.submit(ce.onset, a.h, lam, material=material)
        for material, lam in curves}

    def sweep(curve):
        material, lam = curve
        t0 = time.perf_counter()
        out = ce.snap_curve(T_values, a.h, lam, material=material, progress=False,
                            executor=pool)
        return out, time.perf_counter() - t0

    if pool is None:
        results = [sweep(c) for c in tqdm(curves, desc="fig3 curves")]
    else:
        with ThreadPoolExecutor(max_workers=len(curves)) as fan:
            results = list(fan.map(sweep, curves))
    for (material, lam), (out, t) in zip(curves, results):
        if not a.quick:
            o = pending[(material, lam)].result() if pending else \
                ce.onset(a.h, lam, material=material)
            onsets.append([material, lam, o.T, o.error_estimate])
        times.append((material, lam, t, int(out["along_fold_curve"].sum())))
        rows += [[material, lam, *r] for r in zip(
            out["T"], out["theta"], out["kappa_s"], out["w_s"], out["error_estimate"],
            out["snaps"].astype(int))]
    write_csv(a.out / "fig3_snap_curve.csv",
              ["material", "lam", "T", "theta_rad", "kappa_s_R0", "w_s_over_R0",
               "kappa_s_error", "snaps"], rows)
    if onsets:
        write_csv(a.out / "fig3_onset.csv", ["material", "lam", "T_onset", "T_onset_error"],
                  onsets)

    plt = pyplot()
    fig, ax = plt.subplots(figsize=(6, 4.2))
    for k, (material, lam) in enumerate(curves):
        sel = [r for r in rows if r[0] == material and r[1] == lam]
        T = np.array([r[2] for r in sel])
        ks = np.array([r[4] for r in sel])
        if material == "koiter":
            ax.plot(T, ks, "-", color="k", lw=1.5, label="Koiter, nu = 1/2")
        else:
            ax.plot(T, ks, "o-", color=f"C{k}", ms=3, lw=1, label=f"relaxed CG, lam = {lam:g}")
        for o in onsets:
            if o[0] == material and o[1] == lam:
                ax.axvline(o[2], color="k" if material == "koiter" else f"C{k}", lw=0.6,
                           ls=":")
    ax.set_xlabel(r"$\Theta \sqrt{R_0 / h_0}$")
    ax.set_ylabel(r"$\kappa_s R_0$")
    ax.set_title(f"snap curvature, h0/R0 = {a.h:g} (dotted: computed onset)", fontsize=9)
    ax.legend(fontsize=8)
    finish(fig, a.out, "fig3_snap_curve")
    for o in onsets:
        print(f"onset {o[0]:>6s} lam = {o[1]:<5g}: T = {o[2]:.6f} +- {o[3]:.1e}")
    for material, lam, t, n in times:
        print(f"sweep {material:>6s} lam = {lam:<5g}: {t:.2f} s for {len(T_values)} caps "
              f"({n} found along the fold curve; first sweep includes compilation; with "
              f"--jobs, wall time while the curves share the processes)")
    errs = [r[6] for r in rows if r[7]]
    print(f"{len(rows)} caps, {sum(r[7] for r in rows)} snap; largest kappa_s error estimate "
          f"{max(errs):.1e}")
    if pool is not None:
        pool.shutdown()


if __name__ == "__main__":
    main()
