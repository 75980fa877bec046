"""The isotropic bud past its first bifurcation: the lobed branch of the patch edge.

Budding's isotropic case (``problems/budding.py``: eta_a = eta_b = 1, the metric and the
curvature stimulated alike on the patch s < Theta / 4) loses axisymmetry at the patch edge
with n = 8 waves (``budding.first_instability``). Here the 2D reduced energy of the shell
(two pieces, the rigid joint at the patch edge imposed with multipliers per harmonic:
``shellbvp.fourier2d``) on the class of n = 8 with harmonics 0, 8, 16 is followed from that
bifurcation (``shellbvp.follow_bifurcation``) through its folds until kbar leaves
[0, KBAR_MAX]; the same with harmonics 0..24 (K = 3) and degree + 8 is the discretisation
check (the fold's change, and the lobe amplitude at kbar = KBAR_SHAPE on the stable part).

Per branch point the CSV has kbar, the mode amplitude (mass norm) and xi = a w_max / h (the
largest normal displacement of the unit mode over the thickness), the norm of each
harmonic, the lowest eigenvalue of the Hessian on the constrained class (negative:
unstable within the class), and at the patch edge the normal displacement's harmonic
amplitudes (in h). The PNG: kbar against xi (stable / unstable within the class, Koiter's
parabola, the fold), and the patch edge at kbar = KBAR_SHAPE: its normal displacement
around the circumference and the meridian at a crest and a trough.

    python figures/bud_lobed.py [--out DIR] [--plot-only]
"""

from __future__ import annotations

import csv
import math
import time

import numpy as np
from _common import finish, parser, pyplot, write_csv
import shellbvp
from shellbvp.problems import budding

KBAR_MAX = 70.0
#: the lobed branch runs over kbar ~ 36 to its fold and back while its amplitude moves by
#: ~0.006: steps up to 0.5 in the (y, kbar) arclength (the default's 0.05 is sized for
#: parameters of order one)
OPTIONS = shellbvp.postbuckling.LOBED_OPTIONS.with_(ds_max=0.5, max_steps=1500)
#: the kbar at which the lobed shape is drawn: the bifurcation's, on the stable part
KBAR_SHAPE = 56.6
STEM = "bud_lobed"
#: (K, degree) of the branches: far from the bifurcation the lobes are not sinusoidal (the
#: slope of a lobe at the patch edge is of order one at the fold) and the joint, imposed on
#: the class's harmonics only, converges with K; the degree's part is smaller (p_c moves by
#: 0.064 from degree 24 to 32 and by 0.0073 from 32 to 40)
DISCRETISATIONS = ((2, 32), (3, 32), (4, 32))
SUMMARY = ["K", "degree", "kbar_c", "kbar_c_error", "b", "p2", "kbar_fold", "kbar_fold_error",
           "xi_fold", "joint_angle_error_at_fold", "kbar_shape", "xi_shape", "edge_w_min_over_h",
           "edge_w_max_over_h", "points", "stop", "seconds"]
#: the most harmonics of any branch (the CSV's columns)
KMAX = max(K for K, _ in DISCRETISATIONS)
HARMONICS = ["0", "n"] + [f"{j}n" for j in range(2, KMAX + 1)]
HEADER = (["K", "degree", "kbar", "amplitude", "xi", "lowest_eigenvalue"]
          + [f"harmonic_{k}" for k in HARMONICS] + [f"edge_w{k}_over_h" for k in HARMONICS])
#: the columns of the patch edge's normal displacement per harmonic
EDGE = slice(6 + KMAX + 1, 6 + 2 * (KMAX + 1))


def edge(f, U) -> np.ndarray:
    """The patch edge's normal displacement per harmonic (cos(k omega) amplitudes): U at
    the joint along the base's normal there, (sin theta, 0, cos theta)."""
    theta = f.base.ends[(0, "b")][0]
    return f.joint_values(U)[:, :3] @ np.array([np.sin(theta), 0.0, np.cos(theta)])


def joint_error(f, U) -> float:
    """The largest angle (rad) between the tangents across the patch edge at the state U,
    on 8x the rule's points over the whole circle (only its projections on the class's
    harmonics are imposed)."""
    return float(np.max(np.abs(f.joint_angles(U))))


def row(f, K, U, p, a, w_max, h, harmonics) -> list:
    pad = [math.nan] * (KMAX + 1)
    hm = (list(harmonics) + pad)[:KMAX + 1]
    w = (list(edge(f, U) / h) + pad)[:KMAX + 1]
    return [K, f.degree, p, a, a * w_max / h, float(f.eigenvalues(U, p)[0]), *hm, *w]


def rows_of(br, h) -> list:
    f = br.discretisation
    return [row(f, f.K, U, p, a, br.koiter.w_max, h, hm)
            for U, p, a, hm in zip(br.states, br.p, br.amplitude, br.harmonics)]


def state_at(br, h, kbar) -> list:
    """The row of the stable lobed state at exactly ``kbar`` (Newton with kbar prescribed,
    from the nearest branch point past the fold)."""
    from shellbvp.continuation import newton

    f = br.discretisation
    i0 = br.folds[0].index + 1
    j = i0 + int(np.argmin(np.abs(br.p[i0:] - kbar)))
    system = shellbvp.postbuckling.LobedSystem(f, br.critical[2])
    res = newton(system, br.states[j], kbar, 0.0, 1.0, kbar, tol=1e-9, maxiter=25,
                 fail_fast=False)
    if not res.ok:
        raise shellbvp.ConvergenceError(f"no lobed state at kbar = {kbar}: {res.history}")
    U = res.U
    y_c = br.critical[1]
    hm = [np.linalg.norm((U - y_c)[f.block(k)]) for k in f.ks]
    return row(f, f.K, U, kbar, float(system.monitor(U)[0]), br.koiter.w_max, h, hm)


def compute(out):
    t0 = time.time()
    ins = budding.first_instability(1.0, 1.0)
    print(f"first instability: {ins}  ({time.time() - t0:.0f} s)", flush=True)
    rows, summary, shapes = [], [], []
    for K, degree in DISCRETISATIONS:
        t = time.time()
        br = shellbvp.follow_bifurcation(ins, K=K, degree=degree, n_folds=0,
                                         p_stop=(0.0, KBAR_MAX), options=OPTIONS,
                                         estimate_error=False)
        h = br.discretisation.eq.scene.h
        rows += rows_of(br, h)
        fo = br.folds[0] if br.folds else None
        shape = state_at(br, h, KBAR_SHAPE)
        shapes.append(shape)
        summary.append([K, br.degree, br.p_c, br.p_c_error, br.koiter.b, br.koiter.p2,
                        fo.p if fo else math.nan, fo.error_estimate if fo else math.nan,
                        fo.amplitude * br.koiter.w_max / h if fo else math.nan,
                        joint_error(br.discretisation, fo.y) if fo else math.nan, shape[2],
                        shape[4], *edge_range(shape), len(br.p), br.stop,
                        round(time.time() - t)])
        print(dict(zip(SUMMARY, summary[-1])), flush=True)
    write_csv(out / f"{STEM}.csv", HEADER, rows)
    write_csv(out / f"{STEM}_summary.csv", SUMMARY, summary)
    write_csv(out / f"{STEM}_shape.csv", HEADER, shapes)
    return rows, shapes


def read(path):
    with open(path, newline="") as fh:
        return [[float(v) for v in r] for r in csv.reader(fh)
                if r and not r[0].startswith(("#", "K"))]


def edge_profile(row, w):
    """The patch edge's normal displacement / h at the angles w, from a CSV row."""
    amp = [v for v in row[EDGE] if not math.isnan(v)]
    return sum(a * np.cos(8 * j * w) for j, a in enumerate(amp))


def edge_range(row):
    v = edge_profile(row, np.linspace(0, math.pi / 8, 401))
    return float(v.min()), float(v.max())


def plot(rows, shapes, out):
    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.4))
    for (K, _), style in zip(DISCRETISATIONS, ("-", "--", ":")):
        r = np.array([x for x in rows if x[0] == K])
        st = r[:, 5] > 0
        xi, kb = r[:, 4], r[:, 2]
        d = f"K = {K}, degree {r[0, 1]:.0f}"
        ax.plot(np.where(st, np.nan, xi), kb, "C3" + style, lw=1.5, label=f"unstable, {d}")
        ax.plot(np.where(st, xi, np.nan), kb, "C0" + style, lw=1.5, label=f"stable, {d}")
        i = int(np.argmin(kb))
        ax.plot(xi[i], kb[i], "ko", ms=4, label="fold" if K == DISCRETISATIONS[0][0] else None)
    ax.axhline(KBAR_SHAPE, color="0.6", lw=0.8,
               label=rf"$\bar k$ = {KBAR_SHAPE:g} (the state drawn right)")
    ax.set_xlabel(r"$\xi = a\,w_{max}/h$ (lobe amplitude / thickness)")
    ax.set_ylabel(r"$\bar k$")
    ax.set_title("isotropic bud, n = 8: the lobed branch")
    ax.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2)
    w = np.linspace(0, 2 * math.pi, 721)
    for x, style in zip(shapes, ("-", "--", ":")):
        K = int(x[0])
        bx.plot(np.degrees(w), edge_profile(x, w), style, color="C0",
                label=f"K = {K}, degree {x[1]:.0f}: kbar = {x[2]:.2f}")
    bx.set_xlabel(r"$\omega$ (degrees)")
    bx.set_ylabel("normal displacement at the patch edge / h")
    bx.set_title("the patch edge on the stable lobed branch")
    bx.legend(fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.2))
    finish(fig, out, STEM)


def main():
    p = parser(__doc__)
    p.add_argument("--plot-only", action="store_true", help="redraw from the CSV")
    args = p.parse_args()
    out = args.out
    rows, shapes = (read(out / f"{STEM}.csv"), read(out / f"{STEM}_shape.csv")) \
        if args.plot_only else compute(out)
    plot(rows, shapes, out)


if __name__ == "__main__":
    main()
