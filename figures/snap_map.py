"""A map of the snap curvature over shallowness and material: kappa_s R0 against
T = Theta sqrt(R0/h0) in [1.5, 10] (from below the onset, so that the caps that do not snap
show) and lam = lambda*/mu* in [1e-2, 1e2] (log-spaced), relaxed
Ciarlet-Geymonat, h0/R0 = 0.01, every cap at tol 1e-9, coloured by kappa_s / kappa_s of the
morphoelastic Koiter shell (nu = 1/2) at the same T; the caps that do not snap (grey) and the
onset line (the first snapping T of each lam, to the map's resolution in T) drawn over it.

Each lam is one ``snap_curve`` sweep (chunks of consecutive caps, each following its fold
curve); the sweeps run on ``--jobs`` local processes. Also times the Fig. 3 set (lam in
{0.01, 0.1, 1, 10}, T = 2:0.25:10, tol 1e-10, 132 caps) serially and on the processes, and
the map itself both ways (``--serial`` adds the serial map): wall time of the sweeps, after a
warm-up of every process (JAX's compilation cache on, as for the command line), on a pool
whose start-up (spawn, import, programs loaded from disk, the warm-up) is timed apart. Writes snap_map.png, snap_map.csv (every cap: lam, T, status, kappa_s, its
estimate, the Koiter kappa_s) and snap_map_timing.csv.

    python figures/snap_map.py [--quick] [--jobs 2] [--serial]
"""

from __future__ import annotations

import time

import numpy as np

from _common import finish, parser, pyplot, write_csv
from shellbvp.problems import cap_eversion as ce
from shellbvp.jaxsetup import use_persistent_cache
from shellbvp.sweep import local_executor

H = 0.01
FIG3_LAMS = (0.01, 0.1, 1.0, 10.0)


def sweeps(lams, T, *, tol, executor=None, material="cg"):
    """One snap_curve per lam, in order; with an ``executor``, the sweeps are handed to it
    together (one thread each submits its chunks), so that its workers share all of them."""
    def one(lam):
        return ce.snap_curve(T, H, lam, material=material, tol=tol, progress=False,
                             executor=executor)

    if executor is None:
        return [one(lam) for lam in lams]
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(max_workers=len(lams)) as fan:
        return list(fan.map(one, lams))


WARM_T = (2.0, 4.0, 6.0, 8.0, 10.0)


def _warm(_=None):
    """A process's first caps, at both tolerances: imports, and compiles (or loads from
    JAX's cache) the programs of the degrees the sweeps use."""
    for tol in (1e-10, 1e-9):
        ce.snap_curve(WARM_T, H, 1.0, tol=tol, progress=False)
        ce.snap_curve(WARM_T, H, 1.0, tol=tol, progress=False, material="koiter")
    return True


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--jobs", type=int, default=2, help="local processes (default 2)")
    p.add_argument("--serial", action="store_true", help="also time the map serially")
    p.add_argument("--plot-only", action="store_true", help="redraw from snap_map.csv")
    a = p.parse_args(argv)
    if a.plot_only:
        plot(a.out)
        return
    T = np.round(np.arange(1.5, 10.0001, 0.5 if a.quick else 0.1), 10)
    lams = np.logspace(-2, 2, 5 if a.quick else 25)
    T3 = np.round(np.arange(2.0, 10.0001, 1.0 if a.quick else 0.25), 10)

    use_persistent_cache(default=True)    # as the command line: workers load, not compile
    _warm()                                                   # compile this process
    pool, t_pool = timed(lambda: local_executor(a.jobs))
    _, t_warm = timed(lambda: list(pool.map(_warm, range(a.jobs))))
    timing = [("pool start-up (spawn, import, programs from disk)", a.jobs, t_pool + t_warm)]
    fig3_serial, t3s = timed(lambda: sweeps(FIG3_LAMS, T3, tol=1e-10))
    fig3_par, t3p = timed(lambda: sweeps(FIG3_LAMS, T3, tol=1e-10, executor=pool))
    same3 = all(repr(x.records) == repr(y.records) for x, y in zip(fig3_serial, fig3_par))
    n3 = len(FIG3_LAMS) * T3.size
    timing += [(f"Fig. 3 set ({n3} caps), serial", 1, t3s),
               (f"Fig. 3 set ({n3} caps), {a.jobs} processes", a.jobs, t3p)]

    koiter, _ = timed(lambda: sweeps([1.0], T, tol=1e-9, material="koiter", executor=pool))
    k_koiter = koiter[0]["kappa_s"]
    curves, t_map = timed(lambda: sweeps(lams, T, tol=1e-9, executor=pool))
    n = lams.size * T.size
    timing.append((f"map ({n} caps), {a.jobs} processes", a.jobs, t_map))
    if a.serial:
        serial, t_ser = timed(lambda: sweeps(lams, T, tol=1e-9))
        timing.append((f"map ({n} caps), serial", 1, t_ser))
        assert all(repr(x.records) == repr(y.records) for x, y in zip(serial, curves)), \
            "the serial map differs from the parallel one"
    pool.shutdown()

    rows = []
    for lam, c in zip(lams, curves):
        for j, r in enumerate(c.records):
            v = r.values
            rows.append([lam, r.key, r.status, v["kappa_s"], v["error_estimate"], k_koiter[j],
                         r.reason])
    write_csv(a.out / "snap_map.csv", ["lam", "T", "status", "kappa_s_R0", "kappa_s_error",
                                       "kappa_s_koiter_R0", "reason"], rows)
    write_csv(a.out / "snap_map_timing.csv", ["what", "processes", "wall_time_s"], timing)
    status = plot(a.out)
    for what, procs, t in timing:
        print(f"{what}: {t:.2f} s")
    print(f"Fig. 3 set: {a.jobs} processes / serial = {t3p / t3s:.2f}; values "
          f"{'identical' if same3 else 'DIFFER'}")
    counts = {s: int(np.sum(status == k)) for k, s in enumerate(("ok", "no snap", "failed"))}
    print(f"map: {counts}")


def plot(out):
    """Draw snap_map.png from snap_map.csv (``--plot-only`` redraws without computing)."""
    import csv

    from matplotlib.colors import ListedColormap

    with open(out / "snap_map.csv") as f:
        rows = list(csv.DictReader(f))
    lams = np.array(sorted({float(r["lam"]) for r in rows}))
    T = np.array(sorted({float(r["T"]) for r in rows}))
    K = np.full((lams.size, T.size), np.nan)
    status = np.zeros((lams.size, T.size))
    for r in rows:
        i, j = np.searchsorted(lams, float(r["lam"])), np.searchsorted(T, float(r["T"]))
        K[i, j] = float(r["kappa_s_R0"]) / float(r["kappa_s_koiter_R0"])
        status[i, j] = {"ok": 0, "no snap": 1, "failed": 2}[r["status"]]
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.4))
    dT = T[1] - T[0]
    edges_T = np.append(T - dT / 2, T[-1] + dT / 2)
    lg = np.log10(lams)
    dl = lg[1] - lg[0]
    edges_l = 10 ** np.append(lg - dl / 2, lg[-1] + dl / 2)
    mesh = ax.pcolormesh(edges_T, edges_l, np.ma.masked_invalid(K), cmap="viridis",
                         shading="flat")
    fig.colorbar(mesh, ax=ax, label=r"$\kappa_s / \kappa_s^{\rm Koiter}$")
    # grey: no snap; light red: snaps where the Koiter shell does not (no ratio)
    kind = np.where(status == 1, 0.0, np.where((status == 0) & np.isnan(K), 1.0, np.nan))
    ax.pcolormesh(edges_T, edges_l, np.ma.masked_invalid(kind),
                  cmap=ListedColormap(["0.6", "#f4a6a6"]), vmin=0, vmax=1, shading="flat")
    onset = []
    for i in range(lams.size):
        snaps = np.flatnonzero(status[i] == 0)
        onset.append(T[snaps[0]] - dT / 2 if snaps.size else np.nan)
    ax.plot(onset, lams, "r-", lw=1.5, label="onset of snapping (to the grid in T)")
    bad = np.argwhere(status == 2)
    if bad.size:
        ax.plot(T[bad[:, 1]], lams[bad[:, 0]], "kx", ms=5, label="failed cap")
    ax.set_yscale("log")
    ax.set_xlabel(r"$T = \Theta \sqrt{R_0 / h_0}$")
    ax.set_ylabel(r"$\lambda^* / \mu^*$")
    ax.set_title(f"snap curvature, relaxed CG, h0/R0 = {H:g}, {len(rows)} caps (grey: no snap; "
                 f"light red: snaps, the Koiter shell does not)", fontsize=8)
    ax.legend(fontsize=8, loc="center right")
    finish(fig, out, "snap_map")
    return status


if __name__ == "__main__":
    main()
