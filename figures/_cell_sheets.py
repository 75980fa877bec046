"""Helpers of the cell-sheet figures (docs/cell-sheets.md): the 3D picture of a shell of
revolution, the check that a meridian does not cross itself (the engine has no contact),
the instability and timing records the three scripts share."""

from __future__ import annotations

import math
import time

import numpy as np

#: the part of the revolution drawn in 3D (the rest is cut away to show the inside)
SWEEP = 1.5 * math.pi


def surface(ax, r, z, *, color="tab:green", alpha=0.9, n_azimuth=48):
    """Draw the surface of revolution of the meridian (r, z) on a 3D axes, three quarters
    of it (``SWEEP``), shaded by the azimuth's light."""
    phi = np.linspace(0.25 * math.pi, 0.25 * math.pi + SWEEP, n_azimuth)
    R, P = np.meshgrid(np.asarray(r), phi)
    Z = np.broadcast_to(np.asarray(z), R.shape)
    ax.plot_surface(R * np.cos(P), R * np.sin(P), Z, color=color, alpha=alpha,
                    linewidth=0, antialiased=True, shade=True, rstride=1, cstride=1)
    ax.plot(np.asarray(r) * math.cos(phi[0]), np.asarray(r) * math.sin(phi[0]), z,
            color="k", lw=0.6)
    ax.plot(np.asarray(r) * math.cos(phi[-1]), np.asarray(r) * math.sin(phi[-1]), z,
            color="k", lw=0.6)


def equal_3d(ax, extent: float, zmid: float = 0.0):
    """Equal scales on a 3D axes over a cube of half-size ``extent`` about (0, 0, zmid)."""
    ax.set_xlim(-extent, extent)
    ax.set_ylim(-extent, extent)
    ax.set_zlim(zmid - extent, zmid + extent)
    ax.set_box_aspect((1, 1, 1))
    ax.set_axis_off()


def self_contact(r, z, *, axis_tol: float = 1e-9) -> bool:
    """Whether the surface of revolution of the meridian (r, z) passes through itself: the
    meridian meets the axis away from its poles (r <= axis_tol inside), or crosses itself
    (two of its segments, not neighbours, intersect properly). The engine has no contact,
    so a branch past such a state is not a physical shape."""
    r, z = np.asarray(r, float), np.asarray(z, float)
    if np.any(r[1:-1] <= axis_tol * max(1.0, float(np.max(r)))):
        return True
    p, q = np.stack([r[:-1], z[:-1]], 1), np.stack([r[1:], z[1:]], 1)
    d = q - p

    def orient(a, b, c):          # sign of (b - a) x (c - a), broadcast over pairs
        return (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - \
            (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])
    A, B = p[:, None, :], q[:, None, :]
    C, D = p[None, :, :], q[None, :, :]
    cross = (orient(C, D, A) * orient(C, D, B) < 0) & (orient(A, B, C) * orient(A, B, D) < 0)
    i, j = np.triu_indices(len(d), 2)
    return bool(np.any(cross[i, j]))


class Clock:
    """Wall times of named steps (s), in order."""

    def __init__(self):
        self.seconds = {}

    def __call__(self, name, f, *args, **kwargs):
        t = time.perf_counter()
        out = f(*args, **kwargs)
        self.seconds[name] = self.seconds.get(name, 0.0) + time.perf_counter() - t
        return out


def lowest_per_harmonic(instability, harmonics=range(0, 9)) -> dict:
    """{n: (smallest lowest eigenvalue over the scanned points, the parameter there)} of a
    :class:`shellbvp.Instability`'s scan: how close each harmonic came to instability."""
    out = {}
    for n in harmonics:
        vals = [(row[2][n], row[0]) for row in instability.scan if n in row[2]]
        if vals:
            out[n] = min(vals)
    return out


def instability_record(clock, branch, H: float = 1.0, p_stop=(0.0, 2.0)) -> dict:
    """The first instability along ``branch`` (:func:`shellbvp.first_instability`: kind, n,
    the parameter, its error, the observable over H, how close each harmonic came) and,
    from a bifurcation, the lobed branch (:func:`shellbvp.follow_bifurcation`, K = 2, in
    ``p_stop``): Koiter's coefficients, its folds, why it stopped. Timed on ``clock``."""
    import shellbvp

    ins = clock("first_instability", shellbvp.first_instability, branch)
    out = {"kind": ins.kind, "n": ins.n, "p": ins.p, "error_estimate": ins.error_estimate,
           "w_over_H": ins.w / H, "lowest": lowest_per_harmonic(ins)}
    if ins.kind == "bifurcation":
        try:
            lob = clock("follow_bifurcation", shellbvp.follow_bifurcation, ins, K=2,
                        p_stop=p_stop)
            out["lobed"] = {"kind": lob.koiter.kind, "b": lob.koiter.b, "p_c": lob.p_c,
                            "p_c_error": lob.p_c_error, "points": len(lob.p),
                            "folds": [(f.p, f.error_estimate) for f in lob.folds],
                            "stop": lob.stop}
        except shellbvp.ConvergenceError as exc:
            out["lobed"] = {"kind": "failed", "error": str(exc).splitlines()[0]}
    return out


def report_details(r: dict) -> None:
    """Print a case's stop reason, where a finer discretisation stopped, its instability."""
    if r["stop"]:
        print(f"   stop: {r['stop'][:300]}")
    if "last_stage_finer" in r:
        print(f"   finer: last stage {r['last_stage_finer']:.6f}: {r['stop_finer'][:200]}")
    if "instability" in r:
        report_instability(r["instability"])


def report_instability(i: dict) -> None:
    """Print an :func:`instability_record` (two or three indented lines)."""
    print(f"   first instability: {i['kind']} n = {i['n']} at stage {i['p']:.6f} +- "
          f"{i['error_estimate']:.1e}; lowest per n: "
          + ", ".join(f"{n}: {v:.3g}@{p:.2f}" for n, (v, p) in i["lowest"].items()))
    if "lobed" in i:
        print(f"   lobed branch: {i['lobed']}")


#: line styles of the materials on the branch panels
STYLES = {"koiter": "-", "nh": "--", "cg": "-."}


def mark_instability(ax, r: dict, color, key: str = "w_over_H") -> None:
    """A diamond and the harmonic at a case's first bifurcation (if it has one) on a branch
    panel (the parameter against ``r["instability"][key]``)."""
    i = r.get("instability", {})
    if i.get("kind") == "bifurcation":
        ax.plot(i["p"], i[key], "D", color=color, ms=6)
        ax.annotate(f"n = {i['n']}", (i["p"], i[key]), fontsize=7, xytext=(-22, 6),
                    textcoords="offset points")


def plot_branch(ax, r: dict, y: str, *, fold_size: float = 5) -> None:
    """A case's branch on a branch panel: the stage against ``r[y]`` in its material's
    style, its folds (o), where it stopped (x) and its first bifurcation (D)."""
    (line,) = ax.plot(r["stage"], r[y], STYLES[r["material"]], lw=1.3, label=r["label"])
    for st, w, _ in r["folds"]:
        ax.plot(st, w, "o", color=line.get_color(), ms=fold_size)
    if r["stop"]:
        ax.plot(r["stage"][-1], r[y][-1], "x", color=line.get_color(), ms=7)
    mark_instability(ax, r, line.get_color())


def write_checks(out, stem: str, rows) -> None:
    """``out/stem_checks.csv`` from (check, value, tolerance, pass) rows."""
    from _common import write_csv

    write_csv(out / f"{stem}_checks.csv", ["check", "value", "tolerance", "pass"],
              [[n, v, t, "pass" if ok else "miss"] for n, v, t, ok in rows])


def report_checks(rows) -> None:
    """Print (check, value, tolerance, pass) rows."""
    for name, v, tol, ok in rows:
        print(f"check {name}: {v:.3g} (tolerance {tol:g}): {'pass' if ok else 'MISS'}")


def script_main(doc: str, argv, run, write, report, figure, *, options=None):
    """A cell-sheet script's main: parse ``--quick``/``--out`` (and what ``options(parser)``
    adds), run, write the CSVs, print the report and the total wall time, draw."""
    from _common import parser

    p = parser(doc.splitlines()[0])
    if options is not None:
        options(p)
    a = p.parse_args(argv)
    t = time.perf_counter()
    res = run(a)
    write(res, a.out)
    report(res)
    figure(res, a.out)
    print(f"total {time.perf_counter() - t:.1f} s")
    return res
