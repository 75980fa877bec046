"""The 2D discretisation past axisymmetry (shellbvp.fourier2d) and its lobed states
(shellbvp.postbuckling) against routes of their own.

References: the default cap's axisymmetric snap kappa_s (the spectral Euler-Lagrange method
of the meridian ODEs, refined on its ladder of degrees to 1e-9; an independent AUTO-07p model
of the same equations agrees to ~1e-11), which the 2D energy restricted to harmonic 0 must
reproduce; the rotation by pi / n of the continuum problem, carried out here on the surface
itself (the local numbers synthesised on the full circle and shifted by pi / n) and met by a
Newton solve from an unrelated start.

The per-harmonic spectrum of the Hessian at an axisymmetric state is not repeated here:
tests/test_fourier2d.py (test_hessian_blocks_are_the_harmonics_second_variation) checks it
against shellbvp.harmonics.modes. At kappa = 4.17 the lowest n = 3 eigenvalue (4.1e-3)
differs by 1.1e-9 absolute, 2.6e-7 relative: the round-off floor of either assembly, a few
eps |H| (|H| = 2.3e6), so no relative 1e-8 can hold for the small eigenvalues; the O(1) ones
agree to 1e-9 relative.

The equilibria and the 2D discretisations are those of tests/test_fourier2d.py (one
computation per test process). dG/dp in the Newton systems here is a central difference of
the assembled gradient, not fourier2d's parameter_gradient: no new JAX program to compile
(its first call costs ~20 s per shape), and a converged state does not depend on it (the
residual is exact); only the convergence rate and dp/dm (whose error moves a fold's p by its
square) do.
"""

import itertools
import math
from functools import lru_cache

import numpy as np
import pytest

from shellbvp.continuation import locate_fold, newton, point_at_monitor
from shellbvp.fourier2d import Fourier2D
from shellbvp.problems import cap_eversion as ce
from test_fourier2d import cap_at, f2d, smooth_state      # the same states, computed once


@lru_cache(maxsize=None)
def kappa_s() -> float:
    """The default cap's axisymmetric snap (Theta = pi/6, h = 0.01, lam = 1) by the
    spectral Euler-Lagrange method on its refinement ladder (cap_eversion.snap_curvature),
    refined to 1e-12: the comparisons below go down to ~1e-12, below the default tolerance's
    ~1e-10 (its error estimate, 5.8e-13, is checked)."""
    r = ce.snap_curvature(math.pi / 6, 0.01, 1.0, tol=1e-12)
    assert r.error_estimate < 1e-12, r.error_estimate
    return r.kappa_s


#: the degrees of the fast test (all share the Gauss points, max(2 d, 64) + 8 = 72, hence
#: the compiled Hessian kernel of tests/test_fourier2d.py)
FAST_DEGREES = (20, 24, 28)


class _System:
    """G(y, p) = dE/dy = 0 of a discretisation as a continuation system: the assembled
    gradient and Hessian (the chain-rule route), dG/dp by central differences of that
    gradient (module docstring), the monitor the projection on ``phi``."""

    def __init__(self, f: Fourier2D, phi, dp: float = 1e-4):
        self.f, self.phi, self.size, self.dp = f, np.asarray(phi, dtype=float), f.size, dp

    def evaluate(self, y, p):
        g, H = self.f.hessian(y, p, gradient=True)
        up = self.f.hessian(y, p + self.dp, gradient=True)[0]
        down = self.f.hessian(y, p - self.dp, gradient=True)[0]
        return g, H, (up - down) / (2 * self.dp)

    def monitor(self, y):
        return float(self.phi @ y), self.phi


def _harmonic_zero_fold(degree, step=5e-4):
    """The fold of the axisymmetric branch of Fourier2D(cap at 4.17, n = 3, K = 0, degree):
    the monitor (the amplitude of the softest axisymmetric mode at the base) stepped by
    ``step`` the way p rises until dp/dm changes sign, then Brent's method on dp/dm
    (:func:`shellbvp.continuation.locate_fold`: Newton with the monitor prescribed, dp/dm
    exact from the bordered matrix). 18 points per period instead of K = 0's 2 (harmonic 0
    is constant in omega: the same sum) so that the kernel's shapes are those already
    compiled for K = 2. (Pseudo-arclength is not used: with unknowns in the mass norm the
    branch turns at the fold within ~1e-5 of arclength, below the default ds_min.)"""
    f = Fourier2D(cap_at(4.17), 3, 0, degree=degree).with_points(18)
    system = _System(f, f.mode(0))
    a = point_at_monitor(system, np.zeros(f.size), f.eq.p, 0.0, tol=1e-11, maxiter=30)
    sign = math.copysign(1.0, a.slope)
    for j in range(1, 40):
        b = point_at_monitor(system, a.U, a.p, sign * j * step, tol=1e-11, maxiter=30)
        if b.slope * sign < 0:
            return locate_fold(system, a, b)
        a = b
    raise AssertionError(f"no fold within {39 * step} of the base at degree {degree}")


def test_harmonic_zero_reproduces_the_axisymmetric_snap():
    """Restricted to harmonic 0 the 2D energy is the axisymmetric one: its fold is kappa_s of
    the spectral Euler-Lagrange method (another discretisation - of the meridian ODEs, not
    of the energy - and another solver; AUTO-07p agrees to ~1e-11). Measured (kappa - kappa_s
    at degree 16, 20, 24, 28, 32, 40): 1.3e-5, 5.5e-8, 1.9e-10, 1.1e-12, -5e-15, -6e-15:
    spectral convergence (~200x per 4 degrees) down to the reference's round-off (on a base
    at kappa = 4.2 instead the floor is -1.2e-13: the base state's own error); the default
    degree 24 is 1.9e-10 off, 1e-10 is met from 28 on."""
    err = {d: _harmonic_zero_fold(d).p - kappa_s() for d in FAST_DEGREES}
    e20, e24, e28 = (abs(err[d]) for d in FAST_DEGREES)
    assert e20 > 50 * e24 and e24 > 50 * e28, err          # measured 290 and 175
    assert e28 < 1e-10, err                                  # measured 1.1e-12


@pytest.mark.slow
def test_harmonic_zero_fold_converges_to_the_floor():
    """The same at degree 16 .. 40 (40: more Gauss points, 88, a new kernel to compile): the
    change falls spectrally to the floor and stays there (measured 1.1e-12, -5e-15, -6e-15
    at 28, 32, 40; ~1e-13 on other bases: the base state's own error)."""
    err = {d: _harmonic_zero_fold(d).p - kappa_s() for d in (16, 20, 24, 28, 32, 40)}
    e = [abs(err[d]) for d in (16, 20, 24, 28)]
    assert all(a > 50 * b for a, b in itertools.pairwise(e)), err
    assert all(abs(err[d]) < 1e-11 for d in (28, 32, 40)), err      # measured <= 1.1e-12


# --- the rotation by pi / n maps a lobed equilibrium to one ---------------------------------
def _rotated(f: Fourier2D, y, turns: int = 1):
    """y rotated by turns pi / n: harmonic k = j n takes the sign (-1)^(j turns)."""
    out = np.array(y, dtype=float)
    for j, k in enumerate(f.ks):
        out[f.block(k)] *= (-1) ** (j * turns)
    return out


def _lobed(f: Fourier2D, phi, a, p0, y0=None):
    """The lobed equilibrium with phi . y = a (Newton with the amplitude prescribed)."""
    system = _System(f, phi)
    y0 = a * phi if y0 is None else y0
    res = newton(system, y0, p0, 1.0, 0.0, a, tol=1e-12, maxiter=30, fail_fast=False)
    assert res.ok, res.history
    return res.U, res.p


def test_rotation_by_pi_over_n_maps_a_lobed_equilibrium_to_one():
    """A lobed equilibrium (n = 3, amplitude 2e-3 along the softest n = 3 mode at kappa =
    4.17, kappa = 4.15) rotated by pi / n: (1) on the surface, synthesised on the full circle
    (another grid than the half period the energy uses), the local numbers of the rotated
    state at omega are those of the state at omega + pi / n, and the state's at omega + 2 pi /
    n its own (the class is 2 pi / n periodic); (2) it is an equilibrium with the same energy
    and the same spectrum; (3) Newton with the amplitude -a prescribed, from an unrelated
    start (harmonics 0 and 6 perturbed, p off by 1e-3), converges to it, at the same p."""
    f = f2d(4.17)
    phi = f.mode(3)
    a = 2e-3
    y, p = _lobed(f, phi, a, 4.17)
    assert 4.14 < p < 4.16 and np.linalg.norm(y[f.block(3)]) > 0.9 * a
    yr = _rotated(f, y)
    # (1) the surface: 6 points per period on the full circle, a period is 6 of them
    g = f.with_points(6, full_period=True)
    q, qr = g.state(y), g.state(yr)
    N = g.points
    scale = np.max(np.abs(q))
    assert np.max(np.abs(np.roll(q, -N, axis=1) - q)) < 1e-14 * scale
    assert np.max(np.abs(np.roll(q, -N // 2, axis=1) - qr)) < 1e-14 * scale
    assert np.max(np.abs(qr - q)) > 0.1 * a          # ... and it is another state
    # (2) an equilibrium, the same energy, the same Hessian spectrum
    gy, H = f.hessian(y, p, gradient=True)
    gr, Hr = f.hessian(yr, p, gradient=True)
    # the gradient's scale: that of the same state off equilibrium by 1e-6 along phi
    off = np.linalg.norm(f.hessian(y + 1e-6 * phi, p, gradient=True)[0])
    assert np.linalg.norm(gy) < 1e-8 * off and np.linalg.norm(gr) < 1e-8 * off   # 8e-10
    E = f.energy(y, p)
    assert abs(f.energy(yr, p) - E) < 1e-14 * abs(E)
    ev, evr = np.linalg.eigvalsh(H), np.linalg.eigvalsh(Hr)
    assert np.max(np.abs(ev - evr)) < 1e-12 * np.max(np.abs(ev))
    # (3) the solver finds it at -a from elsewhere
    start = -a * phi + smooth_state(f, (1e-4, 0.0, 1e-4), seed=3)
    ym, pm = _lobed(f, phi, -a, p + 1e-3, start)
    assert abs(pm - p) < 1e-12
    assert np.max(np.abs(ym - yr)) < 1e-11 * np.max(np.abs(y))
