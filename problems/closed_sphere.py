"""Eversion of a closed sphere (paper Section 5.3).

Geometry: a closed sphere of radius R0 (lengths in R0, so R0 = 1), thickness h = h0/R0.
Stimulus: the cap-eversion stimulus of eq. (stimulus), abar = a°, bbar = b° + kappa a°, so the
target curvatures are kb1 = kb2 = kappa - 1 (outward normal, reference k = -1), with no
through-thickness stimulus (rhob1 = 1).
Ansatz: homogeneous radius 1 + w, so that lam1 = lam2 = 1 + w and k1 = k2 = -1/(1 + w); the
target area is fixed, so the energy is proportional to W and the equilibrium is the root of
dW/dw (computed by complex-step differentiation, exact to round-off) continuously connected
to w = 0 at kappa = 0 (:func:`equilibrium`).
The same sphere is also a scene like any other shell (:func:`scene`: the closed meridian
from pole to pole, the cap-eversion stimulus, two poles): its boundary-value problem, solved
without the ansatz (:func:`shell_equilibrium`), returns the homogeneous state, which the
tests check against the root.

The paper's expansions, which the tests and the docs' validation page compare with the
symbolic series (:func:`series`):
    plane strain: w/R0 = (1 - lam)/(24 (1 + lam)) (kappa h0)^2 + O((kappa h0)^3),
    relaxed:      w/R0 = 3 h lam (lam + 2)/(h^2 (10 lam^2 + lam - 2) + 12 (lam + 2)^2) (kappa h0)
                         + O((kappa h0)^2).

Run ``python -m problems.closed_sphere --help``.
"""

from __future__ import annotations

import argparse
import sys
from dataclasses import dataclass

import numpy as np
from scipy.optimize import root_scalar

import shellbvp

__all__ = ["SphereEquilibrium", "equilibrium", "series", "series_value", "state", "scene",
           "shell_equilibrium"]

_STEP = 1e-30  # complex step: no subtractive cancellation, so any tiny step is exact


def state(w, kappa):
    """Principal state (lam1, lam2, k1, k2, kb1, kb2) of the homogeneous sphere of radius 1 + w."""
    return (1 + w, 1 + w, -1 / (1 + w), -1 / (1 + w), kappa - 1, kappa - 1)


@dataclass(frozen=True)
class SphereEquilibrium:
    """Homogeneous equilibrium of the closed sphere.

    Attributes:
        kappa_R0: curvature stimulus kappa R0.
        w_over_R0: radial displacement w_R / R0.
        energy: W at the equilibrium (per mu*, unit target area, unit thickness).
        residual: |dW/dw| at the returned w.
        error_estimate: |residual / (d2W/dw2)|, the Newton estimate of the error in w.
        stiffness: d2W/dw2 (> 0: a stable equilibrium).
        iterations: root-finder iterations.
    """

    kappa_R0: float
    w_over_R0: float
    energy: float
    residual: float
    error_estimate: float
    stiffness: float
    iterations: int
    h: float
    lam: float
    model: str
    material: str
    exact: bool


def _dW_dw(w, kappa, opts):
    """dW/dw by the complex step: Im W(w + i eps) / eps."""
    return float(np.imag(shellbvp.energy_density(*state(w + 1j * _STEP, kappa), **opts)) / _STEP)


def equilibrium(kappa, *, h, lam=1.0, model="relaxed", material="cg", exact=False,
                guess=0.0, xtol=1e-15) -> SphereEquilibrium:
    """Homogeneous radius change of the closed sphere under the curvature stimulus kappa.

    Arguments:
        kappa: curvature stimulus in 1/R0.
        h: h0/R0 in (0, 1).
        lam, model, material, exact: as in :func:`shellbvp.energy_density`.
        guess: starting value of w/R0 (the root continuously connected to w = 0 is found from
            w = 0 for moderate kappa; continue in kappa for large stimuli).

    Raises:
        ValueError: bad parameters (named).
        RuntimeError: the root finder did not converge, or the root is not a minimum.
    """
    if not np.isfinite(kappa) or np.ndim(kappa) != 0:
        raise ValueError(f"kappa must be a finite scalar, got {kappa!r}")
    kappa = float(kappa)
    opts = dict(h=h, lam=lam, model=model, material=material, exact=exact)
    # Validate everything once, at the boundary, with the undeformed state.
    shellbvp.energy_density(*state(0.0, kappa), **opts)
    f = lambda w: _dW_dw(w, kappa, opts)  # noqa: E731
    x0 = float(guess)
    sol = root_scalar(f, x0=x0, x1=x0 + 1e-7, method="secant", xtol=xtol, rtol=1e-14,
                      maxiter=100)
    w = float(sol.root)
    d = 1e-6
    stiff = (f(w + d) - f(w - d)) / (2 * d)
    res = abs(f(w))
    if not sol.converged or not np.isfinite(w) or res > 1e-10 * max(1.0, abs(stiff)):
        raise RuntimeError(
            f"closed sphere: root of dW/dw not found at kappa = {kappa:g} "
            f"(flag {sol.flag!r}, |dW/dw| = {res:.3g}); start from a better guess"
        )
    if stiff <= 0:
        raise RuntimeError(f"closed sphere: equilibrium at kappa = {kappa:g} is not a minimum "
                           f"(d2W/dw2 = {stiff:.3g})")
    W = float(np.real(shellbvp.energy_density(*state(w, kappa), **opts)))
    return SphereEquilibrium(kappa, w, W, res, res / abs(stiff), stiff, sol.iterations,
                             float(h), float(lam), model, material, bool(exact))


def scene(h, lam=1.0, *, model="relaxed", material="cg") -> shellbvp.Scene:
    """The closed sphere of radius R0 = 1 as a shell of revolution: the meridian from its top
    pole to its bottom pole, both ends poles (the top one pinned), the cap-eversion stimulus
    in kappa (:func:`shellbvp.uniform_curvature`)."""
    return shellbvp.Scene(geometry=shellbvp.closed_sphere(1.0), h=h, lam=lam, model=model,
                          material=material, ends=("pole", "pole"),
                          fields=shellbvp.uniform_curvature, parameter="kappa",
                          parameter_unit="R0")


def shell_equilibrium(kappa, *, h, lam=1.0, model="relaxed", material="cg",
                      method="spectral") -> shellbvp.Equilibrium:
    """The closed sphere's equilibrium at kappa from its boundary-value problem (:func:`scene`,
    no ansatz), reached by natural continuation from kappa = 0 in steps of at most 0.5 in
    kappa R0. Its radius change is ``eq.r`` at the equator minus 1."""
    sc = scene(h, lam, model=model, material=material)
    guess = None
    for k in np.linspace(0.0, kappa, max(2, int(np.ceil(abs(kappa) / 0.5)) + 1))[1:-1]:
        guess = shellbvp.solve(sc, k, method=method, guess=guess, estimate_error=False)
    return shellbvp.solve(sc, kappa, method=method, guess=guess)


def series(order=2, *, model="relaxed", material="cg"):
    """Symbolic coefficients c_n(h, lam) of w/R0 = sum_n c_n kappa^n (exact in h)."""
    from shellbvp.series import stationary_series

    return stationary_series(state, order=order, model=model, material=material)


def series_value(kappa, *, h, lam=1.0, order=2, model="relaxed", material="cg"):
    """w/R0 from the symbolic series truncated at ``order``."""
    cs = series(order, model=model, material=material)
    names = {s.name: s for c in cs for s in c.free_symbols}
    vals = {names[n]: v for n, v in (("h", h), ("lam", lam)) if n in names}
    return sum(float(c.subs(vals)) * kappa ** (n + 1) for n, c in enumerate(cs))


def main(argv=None) -> int:
    p = argparse.ArgumentParser(
        prog="python -m problems.closed_sphere",
        description="Homogeneous radius change w/R0 of a closed sphere under the curvature "
                    "stimulus kappa (Taffetani & Pezzulla, Section 5.3).")
    p.add_argument("--kappa", type=float, default=1.0,
                   help="curvature stimulus kappa R0 (default 1)")
    p.add_argument("--h", type=float, default=0.01, help="h0/R0 in (0, 1) (default 0.01)")
    p.add_argument("--lam", type=float, default=10.0, help="lambda*/mu* > 0 (default 10)")
    p.add_argument("--model", default="relaxed", choices=["plane_strain", "relaxed"])
    p.add_argument("--material", default="cg", choices=["cg", "nh"])
    a = p.parse_args(argv)
    try:
        rows = []
        for exact in (False, True):
            r = equilibrium(a.kappa, h=a.h, lam=a.lam, model=a.model, material=a.material,
                            exact=exact)
            rows.append(("exact quadrature" if exact else "reduced", r.w_over_R0, r.error_estimate))
        s = series_value(a.kappa, h=a.h, lam=a.lam, model=a.model, material=a.material)
    except (ValueError, RuntimeError) as exc:
        p.exit(2, f"{p.prog}: error: {exc}\n")
    print(f"closed sphere, kappa R0 = {a.kappa:g}, h0/R0 = {a.h:g}, lam = {a.lam:g}, "
          f"model = {a.model}, material = {a.material}")
    for name, w, err in rows:
        print(f"  w/R0 ({name:16s}) = {w: .12e}  (root error {err:.1e})")
    print(f"  w/R0 (series, order 2)  = {s: .12e}  (difference from reduced {s - rows[0][1]:.2e})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
