"""Gallery: a free disc whose isotropic natural curvature grows until its axisymmetric
(spherical-cap-like) shape bifurcates into the n = 2 (saddle / cylindrical) mode, against the
uniform-curvature Foppl-von Karman estimate kappa_c R^2 / h = 8 / (1 + nu)^(3/2).

The shell (``problems/gallery/disc-natural-curvature.toml``): a flat disc of radius R and
uniform thickness h = 0.01 R, Koiter material (E, nu = 0.3), its centre a pole and its edge
free, with the target curvatures kb1 = kb2 = kappa (a pure "incompatible" natural curvature:
no metric stimulus, no load; a bilayer, or a through-thickness thermal gradient, with no mean
in-plane expansion). Units: lengths in R, moduli in E; the quantity is the dimensionless
bifurcation curvature K_c = kappa_c R^2 / h. The perturbation harmonics
(:mod:`shellbvp.harmonics`) are cos(n w): at the pole, n = 0: U_r = U_w = 0, U_z' = 0;
n = 1: U_z = 0, U_r + U_w = 0; n >= 2: U_r = U_w = U_z = 0, U_z' = 0; at the free edge no
condition; the free body's rigid motions (n = 0: axial translation, rotation about the axis;
n = 1: lateral translation, tilt) are identified and removed, not held by supports.

Reference ("published" column; ``figures/gallery/disc-natural-curvature_published.csv``,
written by ``published_rows()``). The literature the case was meant to compare with -
Mansfield (1962, 1965) on heated lenticular and uniform plates, Freund, J. Mech. Phys.
Solids 48 (2000) 1159 (film on substrate: the axisymmetric to ellipsoidal bifurcation),
Pezzulla, Shillig, Nardinocchi & Holmes, Soft Matter 11 (2015) 5812, Pezzulla, Smith,
Nardinocchi & Holmes, Soft Matter 12 (2016) 4435, Seffen & McMahon, Int. J. Mech. Sci. 49
(2007) 230 - could not be read in the sources available to this case (abstracts only): no
published number is quoted here. The reference is instead the analytic estimate of those
papers' common approach (Mansfield's uniform-curvature Rayleigh-Ritz ansatz, used by Masters
& Salamon and Freund for the film-on-substrate disc), derived in ``ritz_critical()``:
w = (a x^2 + b y^2) / 2 in Foppl-von Karman theory; the Airy function of the Gaussian
curvature ab on the free disc is -E h ab (R^2 - r^2)^2 / 64, the stretching energy
pi E h (ab)^2 R^6 / 384, the bending energy (D/2) pi R^2 [(a-k)^2 + (b-k)^2 + 2 nu (a-k)(b-k)],
so the symmetric branch is k = a + (1 - nu) (R^2/h)^2 a^3 / 16 (in K = k R^2/h,
A = a R^2/h: K = A + (1 - nu) A^3 / 16) and the mode a - b loses stability at
A = 4 / sqrt(1 + nu),
K_c = 8 / (1 + nu)^(3/2) (5.3975 at nu = 0.3). It is NOT a published measurement, and not an
exact FvK solution: the ansatz holds the curvature uniform, while the real shape's curvature
varies over the disc (the edge bends less than the centre once the stretching matters).

Tolerance 10 % on K_c, and why: the one-term ansatz constrains the axisymmetric state; its
error is measured independently of the bifurcation on the axisymmetric branch itself (its
edge deflection against ours at K_c, reported as a check: ~+9 %), and a one-term Ritz
bifurcation load is expected within that order. (This tolerance was set after the first
run had given +4.1 %: it is the estimate's own measured error, not an a-priori bound, and
the case is a consistency check against a one-mode estimate, not a published benchmark.)
Our value is h-independent in K (the Koiter
shell tends to FvK as h/R -> 0; checked at h/R = 0.02, 0.01, 0.005) and converged in the
perturbation degree (16 to 40) to ~1e-6. The nu-dependence is compared at nu = 0, 0.15, 0.3,
0.45 (same tolerance).

Result (this script, full run, ~26 s): K_c = 5.6194 against 5.3975 (+4.1 %), n = 2; over nu
the difference is -1.3 % (nu = 0), +1.8 % (0.15), +4.1 % (0.3), +5.5 % (0.45): the ansatz
decreases faster with nu than the real plate. K_c = 5.62005, 5.61943, 5.61927 at h/R = 0.02,
0.01, 0.005; 5.619425 at degree 16, 24, 32 (5.619420 at 40). The ansatz's edge deflection at
K_c is 9.7 % above ours (its stiffening is too weak: it cannot flatten the edge).
Writes gallery_disc_curvature.csv (the axisymmetric branch, the bifurcation marked) and
gallery_disc_curvature.png, and prints the summary as one JSON line.

    python figures/gallery_disc_curvature.py [--quick]
"""

from __future__ import annotations

import csv
import math
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from _common import HERE, finish, parser, print_summary, pyplot, write_csv

ROOT = HERE.parent
SCENE = ROOT / "problems" / "gallery" / "disc-natural-curvature.toml"
PUBLISHED = HERE / "gallery" / "disc-natural-curvature_published.csv"
H, NU = 0.01, 0.3                 # h / R and Poisson's ratio of the scene file
NUS = (0.0, 0.15, 0.3, 0.45)      # the nu sweep of the full run
TOLERANCE = 0.10
SOURCE = ("uniform-curvature FvK Ritz estimate 8/(1+nu)^1.5 (Mansfield 1962 ansatz, as used by "
          "Freund 2000); derived here: no published number could be read")
PUBLISHED_HEADER = ["nu", "kappa_c_R2_over_h[-]", "A_c=a_c_R2_over_h[-]", "kind"]
KIND = "analytic estimate (uniform-curvature FvK Ritz ansatz), not a published measurement"


def ritz_critical(nu: float) -> float:
    """K_c = kappa_c R^2 / h of the uniform-curvature FvK ansatz: 8 / (1 + nu)^(3/2)."""
    return 8.0 / (1.0 + nu) ** 1.5


def ritz_branch(A, nu: float):
    """K(A) of the ansatz's axisymmetric branch, A = a R^2 / h its (uniform) curvature."""
    A = np.asarray(A, dtype=float)
    return A + (1.0 - nu) * A ** 3 / 16.0


def ritz_curvature(K: float, nu: float) -> float:
    """A(K): the ansatz's curvature at natural curvature K (the real root of the cubic)."""
    roots = np.roots([(1.0 - nu) / 16.0, 0.0, 1.0, -K])
    return float(min(roots, key=lambda r: abs(r.imag)).real)


def published_rows() -> list:
    return [[nu, ritz_critical(nu), 4.0 / math.sqrt(1.0 + nu), KIND] for nu in NUS]


def read_published() -> dict:
    """{nu: K_c} from the published CSV."""
    with open(PUBLISHED, newline="") as f:
        return {float(r["nu"]): float(r["kappa_c_R2_over_h[-]"]) for r in csv.DictReader(f)}


def _variant(text: str, h: float = H, nu: float = NU) -> str:
    """The scene file's text with thickness h (the range kept at K <= 10) and Poisson nu."""
    for old, new in (("thickness = 0.01", f"thickness = {h!r}"),
                     ("to = 0.1 ", f"to = {10 * h!r} "), ("nu = 0.3", f"nu = {nu!r}")):
        if old not in text:
            raise ValueError(f"{SCENE.name}: no {old!r} to replace")
        text = text.replace(old, new)
    return text


def bifurcation(h: float = H, nu: float = NU, degree=None, tol: float = 1e-9) -> dict:
    """The first instability of the scene (with h, nu), K_c in kappa R^2 / h."""
    import shellbvp
    from shellbvp.instability import first_instability

    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / SCENE.name
        path.write_text(_variant(SCENE.read_text(), h, nu))
        sf = shellbvp.load_scene(path)
        b = sf._follow(1)
        f = first_instability(b.branch, degree=degree, tol=tol)
    return {"kind": f.kind, "n": int(f.n), "K": float(sf.parameter_value(f.p)) / h,
            "error_estimate": float(f.error_estimate) * abs(sf.scale) / h,
            "cutoff": f.cutoff}


def branch(ds: float, to: float | None = None):
    """The scene file's axisymmetric branch in steps ds_max = ds (engine units), to ``to``
    (kappa, 1/R; default the file's): rows of (K, w_edge / h, rotation_edge / (kappa R),
    energy / E0), E0 = D (1 + nu) kappa^2 pi R^2 the stress-free flat plate's energy."""
    import shellbvp
    from shellbvp import ContinuationOptions
    from shellbvp.scenefile import SceneBranch

    sf = shellbvp.load_scene(SCENE)
    t_stop = sf.t_range[1] if to is None else to / sf.scale
    b = shellbvp.follow(sf.scene, p0=sf.t_range[0], p_stop=(sf.t_range[0], t_stop),
                        options=ContinuationOptions(ds=ds, ds_max=ds))
    tb = SceneBranch.of(sf, b, None)
    c = tb.columns
    ik, iw, irot, ie = (c.index("kappa[1/R]"), c.index("w_edge[R]"),
                        c.index("rotation_edge[rad]"), c.index("energy[E*R^3]"))
    D = H ** 3 / (12 * (1 - NU ** 2))
    out = []
    for r in tb.rows:
        k = r[ik]
        if r[c.index("is_fold")] or k <= 0:
            continue
        out.append([k / H, r[iw] / H, r[irot] / k, r[ie] / (D * (1 + NU) * k * k * math.pi)])
    return np.array(out)


def run(quick: bool = False) -> dict:
    """The bifurcation against the estimate (and its nu, h, degree checks); the summary."""
    t0 = time.perf_counter()
    pub = read_published()
    main_ = bifurcation()
    K_ref = pub[NU]
    checks = [{"quantity": "kappa_c R^2/h (n = 2 bifurcation), nu = 0.3",
               "published": K_ref, "shellbvp": main_["K"], "n": main_["n"],
               "difference": main_["K"] / K_ref - 1, "tolerance": TOLERANCE}]
    curve = branch(0.2 if quick else 0.02)
    # the ansatz's axisymmetric state at our K_c: edge deflection A h / 2 (w/h = A/2)
    w_ours = float(np.interp(main_["K"], curve[:, 0], curve[:, 1]))
    w_ritz = ritz_curvature(main_["K"], NU) / 2
    extra = {"ritz_edge_deflection_over_ours_at_Kc": w_ritz / w_ours}
    sweep = {}
    if not quick:
        for nu in NUS:
            r = main_ if nu == NU else bifurcation(nu=nu)
            sweep[nu] = r
            if nu != NU:
                checks.append({"quantity": f"kappa_c R^2/h, nu = {nu}", "published": pub[nu],
                               "shellbvp": r["K"], "n": r["n"],
                               "difference": r["K"] / pub[nu] - 1, "tolerance": TOLERANCE})
        extra["K_c_by_h"] = {h: bifurcation(h=h)["K"] for h in (0.02, 0.005)}
        extra["K_c_by_h"][H] = main_["K"]
        extra["K_c_by_degree"] = {deg: bifurcation(degree=deg)["K"] for deg in (16, 32, 40)}
        extra["K_c_by_degree"][24] = main_["K"]
    for c in checks:
        c["ok"] = bool(abs(c["difference"]) <= c["tolerance"] and c["n"] == 2)
    head = checks[0]
    return {"case": "disc-natural-curvature", "source": SOURCE, "quantity": head["quantity"],
            "published": head["published"], "shellbvp": head["shellbvp"],
            "difference": head["difference"], "tolerance": TOLERANCE,
            "ok": all(c["ok"] for c in checks), "seconds": time.perf_counter() - t0,
            "n": main_["n"], "error_estimate": main_["error_estimate"], "checks": checks,
            "extra": extra,
            "curves": {"branch": curve.tolist(),
                       "sweep": {str(nu): r["K"] for nu, r in sweep.items()}}}


def main(argv=None):
    p = parser(__doc__.splitlines()[0])
    p.add_argument("--write-published", action="store_true",
                   help="rewrite figures/gallery/disc-natural-curvature_published.csv and stop")
    a = p.parse_args(argv)
    if a.write_published:
        write_csv(PUBLISHED, PUBLISHED_HEADER, published_rows())
        print(f"wrote {PUBLISHED}")
        return
    r = run(a.quick)
    curve = np.array(r["curves"]["branch"])
    Kc = r["shellbvp"]
    rows = [[K, w, rot, e, ritz_curvature(K, NU) / 2, 0] for K, w, rot, e in curve]
    rows.append([Kc, float(np.interp(Kc, curve[:, 0], curve[:, 1])),
                 float(np.interp(Kc, curve[:, 0], curve[:, 2])),
                 float(np.interp(Kc, curve[:, 0], curve[:, 3])), ritz_curvature(Kc, NU) / 2,
                 r["n"]])
    rows.sort(key=lambda row: (row[0], row[5]))
    write_csv(a.out / "gallery_disc_curvature.csv",
              ["kappa_R2_over_h[-]", "w_edge_over_h[-]", "rotation_edge_over_kappa_R[-]",
               "energy_over_flat_plate_energy[-]", "w_edge_over_h_ritz[-]",
               "bifurcation_n"], rows)
    for c in r["checks"]:
        print(f"{'ok  ' if c['ok'] else 'MISS'} {c['quantity']}: estimate "
              f"{c['published']:.6g}, shellbvp {c['shellbvp']:.6g} (n = {c['n']}), difference "
              f"{100 * c['difference']:+.2f} % (tolerance {100 * c['tolerance']:g} %)")
    for k, v in r["extra"].items():
        print(f"     {k}: {v}")

    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.4))
    K = np.linspace(0, curve[-1, 0], 300)
    A = np.array([ritz_curvature(k, NU) for k in K])
    ax.plot(K, K / 2, ":", color="0.5", lw=1, label="stress-free sphere, w = kappa R^2 / 2")
    ax.plot(K, A / 2, "--", color="C1", lw=1.3, label="uniform-curvature FvK ansatz")
    ax.plot(curve[:, 0], curve[:, 1], "-", color="C0", lw=1.8,
            label="shellbvp, axisymmetric branch")
    wc = float(np.interp(Kc, curve[:, 0], curve[:, 1]))
    ax.plot([Kc], [wc], "o", color="C3", ms=7, zorder=5)
    ax.annotate(f"bifurcation, n = {r['n']}\nK = {Kc:.4f}", (Kc, wc), (Kc + 0.6, wc - 1.2),
                fontsize=8, arrowprops={"arrowstyle": "->", "lw": 0.8})
    ax.axvline(r["published"], color="C1", ls="-.", lw=1,
               label=f"estimate 8/(1+nu)^1.5 = {r['published']:.4f}")
    ax.set_xlabel("natural curvature  K = kappa R^2 / h")
    ax.set_ylabel("edge deflection  w(R) / h")
    ax.set_title(f"Free disc, h/R = {H}, nu = {NU}: axisymmetric branch\n"
                 "(the n = 2 mode takes over at the red point)", fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)
    sweep = {float(k): v for k, v in r["curves"]["sweep"].items()}
    nus = np.linspace(0, 0.49, 100)
    bx.plot(nus, [ritz_critical(n) for n in nus], "--", color="C1",
            label="8 / (1 + nu)^(3/2) (ansatz)")
    if sweep:
        bx.plot(list(sweep), list(sweep.values()), "o-", color="C0", label="shellbvp, n = 2")
    else:
        bx.plot([NU], [Kc], "o", color="C0", label="shellbvp, n = 2")
    bx.set_xlabel("Poisson ratio nu")
    bx.set_ylabel("K_c = kappa_c R^2 / h")
    bx.set_title("Bifurcation curvature against nu", fontsize=10)
    bx.legend(fontsize=8)
    bx.grid(alpha=0.3)
    finish(fig, a.out, "gallery_disc_curvature")
    print_summary(r, drop=("curves", "extra"))


if __name__ == "__main__":
    sys.exit(main())
