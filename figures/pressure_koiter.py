"""Koiter's initial post-buckling coefficient b at the first bifurcation of clamped spherical
caps under external pressure, and the imperfection sensitivity it implies.

Caps: ``shellbvp.problems.pressure_cap``, Koiter shell (the module's default material),
nu = 0.3, R/t = 100, lambda_B = 2 [3 (1 - nu^2)]^(1/4) sqrt(H/t) = 6, 7, ..., 16; pressure
in units of the complete sphere's classical buckling pressure p0 = 2 E t^2 / (R^2 sqrt(3 (1 -
nu^2))). For each cap:

* the first instability along the branch from p = 0 (``pressure_cap.first_instability``): its
  kind, harmonic n, p_c / p0 and error estimate; and the axisymmetric snap (the branch's
  first pressure maximum, ``pressure_cap.critical_pressure``) for comparison;
* at a bifurcation, Koiter's coefficients (:mod:`shellbvp.postbuckling`: the full 2D energy
  on the symmetry class of the mode, harmonics 0, n, ..., K n, K = 2, Chebyshev degree 24):
  p = p_c + p2 a^2 (a the mass-norm amplitude of the mode) and, in the classical
  normalisation, p / p_c = 1 + b xi^2, xi the largest normal displacement of the mode over
  the thickness; the branch is subcritical (imperfection sensitive) where b < 0;
* the bifurcations into n - 1 and n + 1 in the same discretisation (how isolated the
  critical mode is: Koiter's single-mode expansion holds for |p - p_c| below their gaps);
* the knockdown p_s / p_c of Koiter's two-thirds power law in the classical form
  (Hutchinson & Koiter 1970, Appl. Mech. Rev. 23, 1353-1366; the form Hutchinson 1967 uses),

      (1 - p_s / p_c)^(3/2) = (3 sqrt(3) / 2) sqrt(-b) xi_bar p_s / p_c,

  for an imperfection in the shape of the critical mode of amplitude xi_bar = 0.1 and 0.5
  thicknesses (largest normal deviation over t). That form assumes the imperfection enters
  the reduced equation as in the classical theory with a linear prebuckling state,
  (1 - p/p_c) xi + b xi^2 ... = (p / p_c) xi_bar; the caps' prebuckling state is nonlinear,
  so it is the classical estimate, not this discretisation's own imperfect-shell limit
  load. Valid for b < 0 and small xi_bar (leading order).

* the knockdown of the cap whose reference surface carries the imperfection (the critical
  mode's shape, largest normal deviation xi_bar t: ``Fourier2D.imperfect``), which enters
  the nonlinear prebuckling state as it is, not through the classical reduced equation:
  from Koiter's expansion with its own imperfection coefficient (``Koiter.knockdown``) and
  computed directly as the fold of the imperfect cap's equilibria (``imperfect_limit``; at
  xi_bar = 0.1 only, see ``XI_DIRECT``).

Convergence: at a few caps b is computed again with K + 1 harmonics, with the Chebyshev
degree + 8, and with both; the changes are the discretisation error estimates in the CSV. At
the same caps p2 is checked against the lobed equilibria themselves (Newton with the mode's
amplitude prescribed, a = 1e-4 ... 4e-4, xi ~ 0.03 ... 0.15): p - p_c = p2 a^2 + c4 a^4
fitted, its b in the CSV (``b_lobed_fit``).

Reference (derived here, not a published number; see below): the complete sphere in the
shallow-shell (Donnell-Mushtari-Vlasov) equations with the linear membrane prebuckling state
N0 = -p R / 2 and a dead pressure, classical p_c = p0. Its critical modes are all the
waves of wavenumber q, q^4 = 12 (1 - nu^2) / (R t)^2. Koiter's expansion about one of them:

* the square (checkerboard) mode w = t xi cos(q x / sqrt 2) cos(q y / sqrt 2): a = 0 and
  b = -(9/2) (1 - nu^2) = -(3/2) c^2, c = sqrt(3 (1 - nu^2)) (b = -4.095 at nu = 0.3);
* the hexagonal mode w = t xi [cos q x + 2 cos(q x / 2) cos(sqrt 3 q y / 2)] / 3:
  p / p_c = 1 + a xi, a = 3 c / 8 (0.620 at nu = 0.3), subcritical for inward dimples; its
  imperfection law is the half-power one, (1 - p_s / p_c)^2 = 4 a |xi_bar| p_s / p_c =
  (3/2) c |xi_bar| p_s / p_c (inward imperfection in the mode's shape).

Both follow from the second- and third-order solvability conditions with the second-order
field solved in closed form (for the square mode it has the wavevectors (+-sqrt 2 q, 0),
(0, +-sqrt 2 q)); both were checked against the periodic nonlinear equations solved by
Newton at prescribed amplitude (b = -4.094 and a = 0.6196 fitted). The caps' b is in the
same normalisation (xi = largest normal displacement / t) but of a different mode (waves at
the clamped edge, not a sphere's interior pattern), so the sphere is a scale, not a limit.

Writes pressure_koiter.csv and pressure_koiter.png.

    python figures/pressure_koiter.py [--quick]
"""

from __future__ import annotations

import math
import time

import numpy as np
from scipy.optimize import brentq
from tqdm import tqdm

from _common import finish, parser, pyplot, write_csv
import shellbvp
from shellbvp import postbuckling as pb
from shellbvp.continuation import point_at_monitor
from shellbvp.problems import pressure_cap as pc

NU, R_OVER_T = 0.3, 100.0
LAMBDAS = tuple(float(x) for x in range(6, 17))
#: harmonics 0, n, ..., K n of the 2D discretisation; the refinements of the convergence check
K, DEGREE_STEP = 2, 8
CONVERGENCE_AT = (6.0, 10.0, 16.0)
#: imperfection amplitudes, in thicknesses (largest normal deviation in the mode's shape)
XI_BARS = (0.1, 0.5)
#: the amplitudes whose imperfect caps are also computed directly. At 0.5 thicknesses the
#: imperfect caps' paths within the class 0, n, 2n run past p_c (to 1.07 p_c at lambda_B =
#: 7, a fold ``imperfect_limit`` now refuses): past the neighbouring harmonics' bifurcations
#: of the perfect cap (0.02-7 % above p_c, outside the class), so no in-class fold is the
#: cap's limit there
XI_DIRECT = (0.1,)


def knockdown(b: float, xi_bar: float) -> float:
    """p_s / p_c from (1 - L)^(3/2) = (3 sqrt(3) / 2) sqrt(-b) xi_bar L (NaN for b >= 0:
    no limit point near the bifurcation)."""
    if not b < 0:
        return math.nan
    k = 1.5 * math.sqrt(3.0) * math.sqrt(-b) * xi_bar
    return brentq(lambda L: (1.0 - L) ** 1.5 - k * L, 0.0, 1.0, xtol=1e-14)


def sphere_reference(nu: float = NU) -> dict:
    """The complete sphere's coefficients in the shallow-shell equations (module docstring):
    the square mode's b and the hexagonal mode's a."""
    c = math.sqrt(3.0 * (1.0 - nu**2))
    return {"b_square": -1.5 * c**2, "a_hexagonal": 3.0 * c / 8.0}


def knockdown_half_power(a: float, xi_bar: float) -> float:
    """p_s / p_c from (1 - L)^2 = 4 |a| xi_bar L (an asymmetric bifurcation, imperfection of
    the unstable sign)."""
    k = 4.0 * abs(a) * xi_bar
    return ((2.0 + k) - math.sqrt((2.0 + k) ** 2 - 4.0)) / 2.0


def lobed_fit(eq, n: int, p_guess: float, direction: float) -> float:
    """b from lobed equilibria (not the expansion): Newton with the mass-norm amplitude a of
    the mode prescribed (a = 1e-4 ... 4e-4) from Koiter's prediction, p - p_c = p2 a^2 +
    c4 a^4 fitted, p2 in the classical normalisation."""
    f = pb.Fourier2D(eq, n, K)
    crit = pb.critical_point(f, p_guess)
    kc, psi, dy0 = pb.koiter(f, crit, direction=direction)
    p_c, y_c, phi, _ = crit
    system = pb.LobedSystem(f, phi)
    amps = np.array([1e-4, 2e-4, 3e-4, 4e-4])
    dp = []
    for a in amps:
        d = kc.p2 * a**2
        pt = point_at_monitor(system, y_c + d * dy0 + a * phi + a**2 * psi, p_c + d, a,
                              tol=1e-11)
        dp.append(pt.p - p_c)
    p2 = np.polyfit(amps**2, np.array(dp), 2)[1]
    return float(p2 * kc.h**2 / (kc.w_max**2 * p_c))


def coefficients(eq, n: int, K: int, degree: int | None, p_guess: float, direction: float):
    """(Koiter, p_c in scene units) in the discretisation (n, K, degree) about eq."""
    f = pb.Fourier2D(eq, n, K, degree=degree)
    crit = pb.critical_point(f, p_guess)
    kc, _, _ = pb.koiter(f, crit, direction=direction)
    return kc, f, crit


def direct_knockdown(f, crit, kc, xi_bar: float) -> float:
    """p_s / p_c of the imperfect cap computed directly (``imperfect_limit``: its own
    equilibria continued to their fold), the imperfection of the mode's shape with largest
    normal deviation xi_bar t; NaN where that continuation fails."""
    try:
        return pb.imperfect_limit(f, crit, kc, xi_bar * kc.h / kc.w_max).p / kc.p_c
    except (shellbvp.ConvergenceError, ValueError):
        return math.nan


def neighbour(eq, n: int, p_guess: float) -> float:
    """The bifurcation into harmonic n in the 2D discretisation (scene units). NaN where the
    secant from p_guess does not locate it: it then steps past the axisymmetric snap, where
    the axisymmetric state is not continued (the bifurcation lies near or above the snap)."""
    if n < 1:
        return math.nan
    try:
        return pb.critical_point(pb.Fourier2D(eq, n, 1), p_guess)[0]
    except Exception:                       # noqa: BLE001  (reported as missing)
        return math.nan


def cap(lb: float, convergence: bool) -> dict:
    t0 = time.perf_counter()
    ins = pc.first_instability(lb, R_OVER_T, NU)
    snap = pc.critical_pressure(lb, R_over_t=R_OVER_T, nu=NU)
    out = {"lambda_B": lb, "kind": ins.kind, "n": ins.n, "p_c": ins.p,
           "p_c_error": ins.error_estimate, "snap": snap.p_cr_over_p0,
           "snap_error": snap.error_estimate}
    if ins.kind != "bifurcation":
        out["seconds"] = time.perf_counter() - t0
        return out
    eq = ins.equilibrium
    c = pc.pressure_scale(eq.scene.h, NU)
    # the way p moved along the axisymmetric branch to the bifurcation (as follow_bifurcation)
    direction = math.copysign(1.0, eq.p - ins.scan[0][0]) if ins.scan else 1.0
    kc, f, crit = coefficients(eq, ins.n, K, None, eq.p, direction)
    degree = f.degree
    out.update(p_c_2d=kc.p_c / c, p2=kc.p2, b=kc.b, koiter_kind=kc.kind, w_max=kc.w_max,
               mu_p=kc.mu_p, K=K, degree=degree,
               p_c_n_minus_1=neighbour(eq, ins.n - 1, eq.p) / c,
               p_c_n_plus_1=neighbour(eq, ins.n + 1, eq.p) / c)
    for x in XI_BARS:
        out[f"knockdown_{x:g}"] = knockdown(kc.b, x)
        out[f"knockdown_mode_{x:g}"] = float(kc.knockdown(x))
        if x in XI_DIRECT:
            out[f"knockdown_direct_{x:g}"] = direct_knockdown(f, crit, kc, x)
    if convergence:
        refined = {"K_plus_1": (K + 1, degree), "degree_plus": (K, degree + DEGREE_STEP),
                   "both": (K + 1, degree + DEGREE_STEP)}
        for key, (k, d) in refined.items():
            kf, *_ = coefficients(eq, ins.n, k, d, kc.p_c, direction)
            out[f"b_{key}"] = kf.b
        out["b_lobed_fit"] = lobed_fit(eq, ins.n, eq.p, direction)
    out["seconds"] = time.perf_counter() - t0
    return out


COLUMNS = ["lambda_B", "kind", "n", "p_c", "p_c_error", "snap", "snap_error", "p_c_2d",
           "p_c_n_minus_1", "p_c_n_plus_1", "K", "degree", "p2", "b", "koiter_kind",
           "w_max", "mu_p"] + [f"knockdown_{x:g}" for x in XI_BARS] + \
          [f"knockdown_mode_{x:g}" for x in XI_BARS] + \
          [f"knockdown_direct_{x:g}" for x in XI_DIRECT] + \
          ["b_K_plus_1", "b_degree_plus", "b_both", "b_lobed_fit", "seconds"]
HEADER = ["lambda_B", "kind", "n", "p_c_over_p0", "p_c_error", "snap_p_over_p0", "snap_error",
          "p_c_2d_over_p0", "p_c_n_minus_1_over_p0", "p_c_n_plus_1_over_p0", "K", "degree",
          "p2", "b", "koiter_kind", "w_max_unit_mode", "dmu_dp"] + \
         [f"knockdown_xi_{x:g}" for x in XI_BARS] + \
         [f"knockdown_koiter_mode_xi_{x:g}" for x in XI_BARS] + \
         [f"knockdown_direct_mode_xi_{x:g}" for x in XI_DIRECT] + \
         ["b_K_plus_1", f"b_degree_plus_{DEGREE_STEP}", f"b_K_plus_1_degree_plus_{DEGREE_STEP}",
          "b_lobed_fit", "seconds"]


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    lams = (6.0, 12.0) if a.quick else LAMBDAS
    conv = (6.0,) if a.quick else CONVERGENCE_AT
    rows, t0 = [], time.perf_counter()
    for lb in tqdm(lams, desc="Koiter b", unit="cap"):
        r = cap(lb, lb in conv)
        rows.append(r)
        msg = (f"lambda_B = {lb:4.1f}: {r['kind']} n = {r['n']:2d}, p_c/p0 = {r['p_c']:.5f} "
               f"+- {r['p_c_error']:.1e} (snap {r['snap']:.4f})")
        if "b" in r:
            msg += (f"; b = {r['b']:.4f} ({r['koiter_kind']}), knockdown "
                    + ", ".join(f"{r[f'knockdown_{x:g}']:.3f} (xi = {x:g})" for x in XI_BARS))
        if "b_both" in r:
            msg += (f"; b with K+1: {r['b_K_plus_1']:.5f}, degree+{DEGREE_STEP}: "
                    f"{r['b_degree_plus']:.5f}, both: {r['b_both']:.5f}; from lobed states "
                    f"{r['b_lobed_fit']:.5f}")
        tqdm.write(msg + f"  [{r['seconds']:.0f} s]")
    elapsed = time.perf_counter() - t0
    print(f"{elapsed:.0f} s in all")
    sph = sphere_reference(NU)
    write_csv(a.out / "pressure_koiter.csv", HEADER,
              [[r.get(k, math.nan) for k in COLUMNS] for r in rows]
              + [["# total_seconds", elapsed]]
              + [["# sphere_shallow_shell_b_square_mode", sph["b_square"]],
                 ["# sphere_shallow_shell_a_hexagonal_mode", sph["a_hexagonal"]]]
              + [[f"# sphere_knockdown_square_xi_{x:g}", knockdown(sph["b_square"], x)]
                 for x in XI_BARS]
              + [[f"# sphere_knockdown_hexagonal_xi_{x:g}",
                  knockdown_half_power(sph["a_hexagonal"], x)] for x in XI_BARS])

    plt = pyplot()
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(12, 4.8))
    bif = [r for r in rows if "b" in r]
    L = np.array([r["lambda_B"] for r in bif])
    b = np.array([r["b"] for r in bif])
    ax1.plot(L, b, "o-", color="C0", label=r"ours: $b$ ($K = 2$, degree 24)")
    cv = [r for r in bif if "b_both" in r]
    if cv:
        ax1.plot([r["lambda_B"] for r in cv], [r["b_both"] for r in cv], "x", color="C3",
                 ms=9, mew=1.5, label=rf"ours: $K = 3$, degree {24 + DEGREE_STEP}")
        ax1.plot([r["lambda_B"] for r in cv], [r["b_lobed_fit"] for r in cv], "+", color="k",
                 ms=12, mew=1.2, label="ours: fitted to the lobed equilibria")
    for r in bif:
        ax1.annotate(f"n={r['n']}", (r["lambda_B"], r["b"]), textcoords="offset points",
                     xytext=(0, -13), ha="center", fontsize=7)
    ax1.set_ylim(min(b.min() * 1.12, -0.1), 0.0)
    ax1.text(0.03, 0.97, "complete sphere, shallow-shell equations, linear prebuckling\n"
             rf"(derived here; off scale): square mode $b = -\frac{{3}}{{2}}c^2 = "
             rf"{sph['b_square']:.3f}$;" "\n"
             rf"hexagonal mode $a = \frac{{3}}{{8}}c = {sph['a_hexagonal']:.3f}$ "
             r"($p/p_c = 1 + a\xi$), $c = \sqrt{3(1-\nu^2)}$", transform=ax1.transAxes,
             fontsize=7.5, va="top",
             bbox={"boxstyle": "round", "fc": "white", "ec": "0.7"})
    ax1.set_xlabel(r"$\lambda_B$")
    ax1.set_ylabel(r"$b$  in  $p/p_c = 1 + b\,\xi^2$,  $\xi = w_{max}/t$")
    ax1.set_title(r"clamped cap, Koiter shell, $\nu = 0.3$, $R/t = 100$: first bifurcation "
                  r"(all subcritical)", fontsize=10)
    ax1.legend(fontsize=8, loc="center right")
    ax1.grid(alpha=0.3)
    for k, (x, m) in enumerate(zip(XI_BARS, ("o-", "s-"))):
        ax2.plot(L, [r[f"knockdown_{x:g}"] for r in bif], m, color=f"C{k}",
                 label=rf"caps, $\bar\xi = {x:g}$")
        ax2.plot(L, [r[f"knockdown_mode_{x:g}"] for r in bif], m[0] + ":", mfc="none",
                 color=f"C{k}", label=rf"caps, mode in the geometry: Koiter, $\bar\xi = {x:g}$")
        if x in XI_DIRECT:
            ax2.plot(L, [r[f"knockdown_direct_{x:g}"] for r in bif], "x", ms=8, color=f"C{k}",
                     label=rf"caps, mode in the geometry: direct, $\bar\xi = {x:g}$")
        ax2.axhline(knockdown(sph["b_square"], x), color=f"C{k}", ls="--", lw=1,
                    label=rf"sphere, square mode, $\bar\xi = {x:g}$")
        ax2.axhline(knockdown_half_power(sph["a_hexagonal"], x), color=f"C{k}", ls=":", lw=1.2,
                    label=rf"sphere, hexagonal (half power), $\bar\xi = {x:g}$")
    ax2.set_xlabel(r"$\lambda_B$")
    ax2.set_ylabel(r"$p_s/p_c$")
    ax2.set_title("knockdown by an imperfection of the mode's shape, amplitude "
                  r"$\bar\xi$ thicknesses:" "\n"
                  r"classical form $(1 - p_s/p_c)^{3/2} = \frac{3\sqrt{3}}{2}\sqrt{-b}\,"
                  r"\bar\xi\,p_s/p_c$; the imperfect reference geometry", fontsize=10)
    ax2.set_ylim(0.0, 1.15)
    ax2.legend(fontsize=6.5, ncol=2, loc="upper center")
    ax2.grid(alpha=0.3)
    finish(fig, a.out, "pressure_koiter")


if __name__ == "__main__":
    main()
