"""Tutorial: two gallery cases with a morphoelastic stimulus (docs/tutorial.md, "Beyond the
anchors"): a disc spring whose inner band has swollen, and an axially compressed cylinder
with a ring that grows circumferentially.

Scenes (their headers state the cases and the units):

* ``problems/scenes/disc-spring-swelling.toml``: the gallery's disc spring (h0/t = 0.75,
  mm, MPa, N) with the inner third of its meridian swollen in-plane by 1 %
  (g1 = g2 = 1.01), loaded by the force F on its inner edge. Set beside the dry spring
  (``problems/gallery/disc-spring-almen.toml``): the dry one has no load maximum, the swollen
  one snaps (a fold in F), axisymmetrically (``first_instability``: the fold comes first).
* ``problems/scenes/cylinder-growing-ring.toml``: a clamped cylinder (R/t = 100) held at a
  fixed axial load 0.8 N_cl, whose band of 20 mm around mid-length grows circumferentially
  (g2 = 1 + g); the parameter is g. Its axisymmetric response and its first bifurcation
  (n, g).

Sanity checks (independent closed forms, each printed with its relative difference):

* the band's free growth in a flat annulus: the same file with the cone made flat (a plate
  from r = 25 to 50 mm, the same band and ramp) and the swelling 1e-6, no load. Plane-stress
  elasticity with an isotropic eigenstrain e(r) (Lame): both free edges move as under a
  uniform growth by the area average of e, u(a) / a = u(c) / c = 2 / (c^2 - a^2)
  int_a^c e r dr, whatever nu (the closed form in ``annulus_average``). Tolerance 1e-5: the
  nonlinear terms are of the order of the strain, 1e-6.
* the ring's bulge without the load: the same file with F0 = 0 and g = 1e-6: a long
  cylinder's axisymmetric linear bending (a beam on an elastic foundation, D w'''' +
  (E t / R^2) w = (E t / R) e(z), e the band's growth profile) gives at the band's centre
  w / (g R) = 1 + (B(a + d) - B(a)) / d, B(x) = exp(-beta x) (cos beta x - sin beta x) /
  (2 beta), beta^4 = 3 (1 - nu^2) / (R t)^2, a = 10 mm the band's half-width, d = 2 mm its
  ramp (``ring_bulge``); it tends to 1 (the free growth, w = g R: the membrane hoop strain
  equal to the growth) as the band widens. Tolerance 1e-3: the closed form is the shallow
  (Donnell) linear theory, whose neglected terms are O(t/R) at most; the clamp lies
  68 mm = 8.7 / beta from the band (exp(-8.7) = 2e-4); nonlinear terms ~ g = 1e-6.

    python figures/tutorial_morphoelastic.py [--out DIR]
"""

from __future__ import annotations

import math
import tempfile
import time
from pathlib import Path

import numpy as np

from _common import HERE, finish, parser, pyplot, write_csv

ROOT = HERE.parent
SPRING = ROOT / "problems" / "scenes" / "disc-spring-swelling.toml"
DRY = ROOT / "problems" / "gallery" / "disc-spring-almen.toml"
CYLINDER = ROOT / "problems" / "scenes" / "cylinder-growing-ring.toml"

# the disc spring (the file's numbers): inner and outer radius, the band fully swollen for
# s <= S_FULL, the swelling falling linearly to none at s = S_ZERO (mm), its amount
R_I, R_E, S_FULL, S_ZERO, SWELLING = 25.0, 50.0, 8.0, 9.0, 0.01
# the cylinder: modulus (MPa), Poisson ratio, radius, thickness, half-length (mm); the band's
# half-width and ramp (mm); the fixed axial load (N/mm)
E, NU, R, T, HALF = 2.0e5, 0.3, 100.0, 1.0, 80.0
BAND, RAMP, F0 = 10.0, 2.0, 968.4
N_CL = E * T * T / (R * math.sqrt(3 * (1 - NU * NU)))
#: the sanity checks' stimulus and tolerances (module docstring)
SMALL = 1e-6
TOL_ANNULUS, TOL_RING = 1e-5, 1e-3
#: growths at which the cylinder's meridian is drawn
PROFILE_G = (0.0005, 0.001, 0.0015, 0.003)


def variant(path: Path, replacements: dict):
    """The scene file ``path`` loaded with each key of ``replacements`` (a piece of its text,
    found at least once) replaced by its value everywhere, from a temporary copy."""
    import shellbvp

    text = path.read_text()
    for old, new in replacements.items():
        if old not in text:
            raise RuntimeError(f"{path.name}: no '{old}' to replace")
        text = text.replace(old, new)
    with tempfile.TemporaryDirectory() as d:
        copy = Path(d) / path.name
        copy.write_text(text)
        return shellbvp.load_scene(copy)


def annulus_average(a=R_I, c=R_E, s_full=S_FULL, s_zero=S_ZERO) -> float:
    """2 / (c^2 - a^2) int_a^c e(r) r dr for the band e = 1 on a <= r <= a + s_full, falling
    linearly to 0 at r = a + s_zero: the uniform growth that moves a free annulus' edges as
    the band does (Lame, plane stress, small strain; module docstring)."""
    r1, r2 = a + s_full, a + s_zero
    full = (r1 * r1 - a * a) / 2
    ramp = (r2 * (r2 * r2 - r1 * r1) / 2 - (r2 ** 3 - r1 ** 3) / 3) / (r2 - r1)
    return 2 * (full + ramp) / (c * c - a * a)


def ring_bulge(a=BAND, d=RAMP) -> float:
    """w / (g R) at the centre of a band of half-width a, growth ramping to none over d
    beyond it, in a long unloaded cylinder (linear, shallow theory; module docstring)."""
    beta = (3 * (1 - NU * NU)) ** 0.25 / math.sqrt(R * T)

    def B(x):
        return math.exp(-beta * x) * (math.cos(beta * x) - math.sin(beta * x)) / (2 * beta)

    return 1 + (B(a + d) - B(a)) / d


def _ends_radial(eq, L):
    """(u_r at the first end, u_r at the second) of an equilibrium, in the file's length."""
    r0, r1 = eq(np.array([eq.s[0], eq.s[-1]]))[0] * L
    return float(r0), float(r1)


def spring_check(g: float = SMALL) -> dict:
    """The band of the disc spring's file on a flat annulus, swollen by g, no load: the
    edges' u / r against ``annulus_average`` (module docstring)."""
    import shellbvp

    sf = variant(SPRING, {
        '{ type = "cone", from = [25.0, 1.875], to = [50.0, 0.0] }':
            '{ type = "plate", r = [25.0, 50.0], z = 0.0 }',
        "1 + 0.01*minimum": f"1 + {g!r}*minimum"})
    eq = shellbvp.solve(sf.scene, 0.0)
    r_a, r_c = _ends_radial(eq, sf.units.length)
    expected = g * annulus_average()
    out = {"expected": expected, "inner": (r_a - R_I) / R_I, "outer": (r_c - R_E) / R_E,
           "error_estimate": eq.error_estimate * sf.units.length}
    out["difference"] = max(abs(out["inner"] / expected - 1), abs(out["outer"] / expected - 1))
    return out


def cylinder_check(g: float = SMALL) -> dict:
    """The cylinder's file without its load, grown by g: the bulge at the band's centre
    against ``ring_bulge`` (module docstring)."""
    import shellbvp

    sf = variant(CYLINDER, {'second_axial_force = "-968.4"': 'second_axial_force = "0.0"'})
    eq = shellbvp.solve(sf.scene, g / sf.scale)
    _, r_mid = _ends_radial(eq, sf.units.length)
    ratio = (r_mid - R) / (g * R)
    expected = ring_bulge()
    return {"expected": expected, "shellbvp": ratio, "difference": ratio / expected - 1,
            "error_estimate": eq.error_estimate * sf.units.length}


def _column(branch, name):
    return [row[branch.columns.index(name)] for row in branch.rows]


def run_spring() -> dict:
    """The swollen spring's branch (with its folds) and first instability, the dry spring's
    branch, the check."""
    import shellbvp

    t0 = time.perf_counter()
    sf = shellbvp.load_scene(SPRING)
    b = sf.follow()
    ins = sf.first_instability()
    seconds = time.perf_counter() - t0
    # the gallery's file drawn with more points (a continuation setting: no new compilation)
    dry = variant(DRY, {"[ends]": "[solver]\npoints = 40\n\n[ends]"}).follow()
    t1 = time.perf_counter()
    check = spring_check()
    curves = {}
    for name, br in (("swollen", b), ("dry", dry)):
        curves[name] = {"F": _column(br, "F[N]"), "s": _column(br, "deflection[mm]"),
                        "is_fold": _column(br, "is_fold"),
                        "error_estimate": _column(br, "error_estimate[N]")}
    first = b.rows[0]
    L = sf.units.length
    shapes = {"dry, unloaded": ([R_I, R_E], [1.875, 0.0])}
    for label, eq in (("swollen, F = 0", b.branch.equilibrium(0)),
                      ("the snap (fold 1)", b.branch.folds[0].equilibrium),
                      ("the load minimum (fold 2)", b.branch.folds[1].equilibrium),
                      (f"F = {b.last['p']:.0f} N", b.branch.equilibrium(len(b.branch.points) - 1))):
        shapes[label] = ((eq.r * L).tolist(), (eq.z * L).tolist())
    return {"folds": [dict(f) for f in b.folds], "dry_folds": len(dry.folds),
            "shapes": shapes,
            "rise": -first[b.columns.index("deflection[mm]")],
            "instability": {"kind": ins.kind, "n": ins.n, "p": ins.p,
                            "error_estimate": ins.error_estimate},
            "check": check, "seconds": seconds, "check_seconds": time.perf_counter() - t1,
            "curves": curves}


def run_cylinder() -> dict:
    """The cylinder's branch in g, its first instability, meridians along it, the check."""
    import shellbvp

    t0 = time.perf_counter()
    sf = shellbvp.load_scene(CYLINDER)
    b = sf.follow()
    ins = sf.first_instability()
    seconds = time.perf_counter() - t0
    L = sf.units.length
    branch = b.branch
    g_points = np.array([float(sf.parameter_value(pt.p)) for pt in branch.points])
    s = np.linspace(0.0, HALF / L, 401)

    def profile(eq):
        return (eq(s)[0] * L - R).tolist()

    profiles = {}
    for g in PROFILE_G:
        i = int(np.argmin(abs(g_points - g)))
        eq = shellbvp.solve(sf.scene, g / sf.scale, guess=branch.equilibrium(i))
        profiles[g] = profile(eq)
    i = int(np.argmin(abs(g_points - ins.p)))
    eq_cr = shellbvp.solve(sf.scene, ins.instability.p, guess=branch.equilibrium(i))
    t1 = time.perf_counter()
    check = cylinder_check()
    return {"instability": {"kind": ins.kind, "n": ins.n, "p": ins.p,
                            "error_estimate": ins.error_estimate,
                            "bulge": _ends_radial(eq_cr, L)[1] - R},
            "g": _column(b, "g"), "bulge": _column(b, "bulge[mm]"),
            "band_edge": _column(b, "band_edge[mm]"), "z": (s * L).tolist(),
            "profiles": profiles, "profile_cr": profile(eq_cr), "check": check,
            "seconds": seconds, "check_seconds": time.perf_counter() - t1}


def run() -> dict:
    return {"spring": run_spring(), "cylinder": run_cylinder()}


def report(r: dict) -> None:
    sp, cy = r["spring"], r["cylinder"]
    snap, low = sp["folds"][0], sp["folds"][1]
    print(f"disc spring, inner band swollen by {100 * SWELLING:g} %: unloaded, the cone rises "
          f"by {sp['rise']:.3f} mm (h0 {1.875:g} -> {1.875 + sp['rise']:.3f} mm)")
    print(f"  snap (fold 1): F = {snap['p']:.4f} +- {snap['error_estimate']:.1e} N at "
          f"s = {snap['deflection']:.4f} mm; load minimum (fold 2): F = {low['p']:.4f} N at "
          f"s = {low['deflection']:.4f} mm; the dry spring: {sp['dry_folds']} fold(s)")
    i = sp["instability"]
    print(f"  first instability: {i['kind']} (n = {i['n']}) at F = {i['p']:.4f} N")
    c = sp["check"]
    print(f"  check, the band on a flat annulus (g = {SMALL:g}): u/r inner {c['inner']:.6e}, "
          f"outer {c['outer']:.6e}, Lame {c['expected']:.6e}: relative difference "
          f"{c['difference']:.1e} (tolerance {TOL_ANNULUS:g})")
    print(f"  {sp['seconds']:.1f} s (branch and instability), check {sp['check_seconds']:.1f} s")
    i = cy["instability"]
    print(f"cylinder R/t = {R / T:g} at F0 = {F0:g} N/mm = {F0 / N_CL:.4f} N_cl, growing ring: "
          f"first instability {i['kind']} into n = {i['n']} at g = {i['p']:.7f} +- "
          f"{i['error_estimate']:.1e} (bulge {i['bulge']:.4f} mm)")
    c = cy["check"]
    print(f"  check, the ring without the load (g = {SMALL:g}): bulge / (g R) = "
          f"{c['shellbvp']:.6f}, beam on an elastic foundation {c['expected']:.6f}: relative "
          f"difference {c['difference']:.1e} (tolerance {TOL_RING:g})")
    print(f"  {cy['seconds']:.1f} s (branch and instability), check {cy['check_seconds']:.1f} s")


def figure(r: dict, out: Path) -> None:
    sp, cy = r["spring"], r["cylinder"]
    plt = pyplot()
    fig, ((ax, dx), (bx, cx)) = plt.subplots(2, 2, figsize=(11.5, 8.8))
    for name, color, label in (("dry", "0.45", "dry (the gallery's spring)"),
                               ("swollen", "C3", "inner band swollen by 1 %")):
        c = sp["curves"][name]
        pts = [(s, F) for s, F, f in zip(c["s"], c["F"], c["is_fold"]) if not f]
        ax.plot([p[0] for p in pts], [p[1] / 1e3 for p in pts], "-", color=color, lw=1.6,
                label=label)
    for k, f in enumerate(sp["folds"]):
        ax.plot([f["deflection"]], [f["p"] / 1e3], "^" if k == 0 else "v", color="C3", ms=8)
    snap, low = sp["folds"][0], sp["folds"][1]
    ax.annotate(f"snap (fold)\nF = {snap['p'] / 1e3:.3f} kN", (snap["deflection"], snap["p"] / 1e3),
                (snap["deflection"] + 1.0, snap["p"] / 1e3 + 0.5), fontsize=8,
                arrowprops={"arrowstyle": "->", "lw": 0.8})
    ax.annotate(f"load minimum\nF = {low['p'] / 1e3:.3f} kN", (low["deflection"], low["p"] / 1e3),
                (low["deflection"] - 0.6, low["p"] / 1e3 + 2.2), fontsize=8,
                arrowprops={"arrowstyle": "->", "lw": 0.8})
    ax.axvline(0.0, color="k", lw=0.6)
    ax.set_xlabel("deflection s of the inner edge from the dry cone (mm)")
    ax.set_ylabel("force F (kN)")
    ax.set_title("Disc spring ($h_0/t$ = 0.75): swelling its inner third\n"
                 "raises the cone and makes it snap", fontsize=10)
    ax.set_ylim(-0.3, 10.3)
    ax.legend(fontsize=8, loc="upper center")
    ax.grid(alpha=0.3)

    styles = {"dry, unloaded": ("0.45", "--"), "swollen, F = 0": ("C3", "-"),
              "the snap (fold 1)": ("C1", "-"), "the load minimum (fold 2)": ("C2", "-")}
    for label, (r_m, z_m) in sp["shapes"].items():
        color, ls = styles.get(label, ("C0", "-"))
        dx.plot(r_m, z_m, ls, color=color, lw=1.6, label=label)
    dx.axvspan(R_I, R_I + S_FULL, color="C1", alpha=0.15, lw=0, label="swollen band, s <= 8 mm (at rest)")
    dx.set_xlabel("r (mm)")
    dx.set_ylabel("z (mm)")
    dx.set_title("The spring's meridian (its mid-surface; z stretched)", fontsize=10)
    dx.legend(fontsize=8, loc="upper right")
    dx.grid(alpha=0.3)

    i = cy["instability"]
    bx.plot(1e2 * np.array(cy["g"]), cy["bulge"], "-", color="C0", lw=1.6,
            label="bulge at the band's centre")
    bx.plot(1e2 * np.array(cy["g"]), cy["band_edge"], "--", color="C0", lw=1.2,
            label="at the band's edge")
    g = np.array(cy["g"])
    bx.plot(1e2 * g, cy["bulge"][0] + cy["check"]["expected"] * g * R, ":", color="0.4", lw=1.2,
            label=f"without the load: slope {cy['check']['expected']:.3f} g R (closed form)")
    bx.plot([1e2 * i["p"]], [i["bulge"]], "o", color="C3", ms=7,
            label=f"first bifurcation: n = {i['n']}, g = {1e2 * i['p']:.4f} %")
    bx.set_xlabel("circumferential growth g of the ring (%)")
    bx.set_ylabel("radial displacement (mm)")
    bx.set_title(f"Cylinder, R/t = {R / T:g}, at $F_0$ = 0.8 $N_{{cl}}$: a growing ring",
                 fontsize=10)
    bx.legend(fontsize=8, loc="upper left")
    bx.grid(alpha=0.3)

    z = np.array(cy["z"])
    zz = np.concatenate([z, 2 * HALF - z[::-1]])
    for k, (g, w) in enumerate(sorted(cy["profiles"].items())):
        w = np.array(w)
        cx.plot(zz, np.concatenate([w, w[::-1]]), "-", color=plt.cm.viridis(0.15 + 0.22 * k),
                lw=1.1, label=f"g = {1e2 * g:.3f} %")
    w = np.array(cy["profile_cr"])
    cx.plot(zz, np.concatenate([w, w[::-1]]), "-", color="C3", lw=2.0,
            label=f"g = {1e2 * i['p']:.4f} %: bifurcation, n = {i['n']}")
    cx.axvspan(HALF - BAND, HALF + BAND, color="C1", alpha=0.15, lw=0, label="growing band")
    for side in (-1, 1):
        cx.axvspan(HALF + side * BAND, HALF + side * (BAND + RAMP), color="C1", alpha=0.07, lw=0)
    cx.set_xlabel("z (mm)")
    cx.set_ylabel("radial displacement $u_r$ (mm)")
    cx.set_title("The cylinder's meridian (both halves): the ring bulges out", fontsize=10)
    cx.legend(fontsize=7.5, loc="upper left")
    cx.grid(alpha=0.3)
    finish(fig, out, "tutorial_morphoelastic")


def write(r: dict, out: Path) -> None:
    rows = []
    for name, example in (("swollen", "disc-spring-swelling"), ("dry", "disc-spring-almen")):
        c = r["spring"]["curves"][name]
        for F, s, f, err in zip(c["F"], c["s"], c["is_fold"], c["error_estimate"]):
            rows.append([example, "F[N]", F, "deflection[mm]", s, "fold" if f else "",
                         err if f else ""])
    cy = r["cylinder"]
    for g, w in zip(cy["g"], cy["bulge"]):
        rows.append(["cylinder-growing-ring", "g", g, "bulge[mm]", w, "", ""])
    i = cy["instability"]
    rows.append(["cylinder-growing-ring", "g", i["p"], "bulge[mm]", i["bulge"],
                 f"{i['kind']} n={i['n']}", i["error_estimate"]])
    write_csv(out / "tutorial_morphoelastic.csv",
              ["example", "parameter", "value", "observable", "observed", "event",
               "error_estimate"], rows)


def main(argv=None):
    a = parser(__doc__.splitlines()[0]).parse_args(argv)
    r = run()
    write(r, a.out)
    report(r)
    figure(r, a.out)
    return r


if __name__ == "__main__":
    main()
