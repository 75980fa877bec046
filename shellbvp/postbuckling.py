"""Past the first bifurcation: the branch of n-lobed equilibria, Koiter's initial
post-buckling coefficients and the imperfection sensitivity they imply.

At a bifurcation into n waves (:func:`shellbvp.first_instability`) the full 2D energy is
discretised on the symmetry class of the critical mode (:mod:`shellbvp.fourier2d`:
harmonics 0, n, ..., K n about the axisymmetric equilibrium there, unknowns y with the
identity mass matrix). Its stationarity, G(y, p) = dE/dy = 0, is a discrete system of the
one continuation (:class:`LobedSystem`: Jacobian the exact Hessian, dG/dp exact, monitor
the amplitude a = phi . y of the critical mode phi).

The bifurcation in this discretisation (:func:`critical_point`): along the axisymmetric
branch y_0(p) (harmonic 0 alone; the others' gradient vanishes there by symmetry) the root
p_c of the lowest eigenvalue mu_n(p) of the Hessian's block n, phi its eigenvector.

Koiter's expansion (:func:`koiter`). The rotation by pi / n maps the class onto itself and
phi onto -phi, so E is even in a and the bifurcation is a pitchfork: Koiter's a = 0. With
w = y - y_0(p) = a phi + a^2 psi + ..., phi . psi = 0, and p = p_c + p2 a^2 + ...:

    order a^2:  H psi = -1/2 E'''[phi, phi, .]                      (one linear solve)
    order a^3:  p2 = -(E'''[phi, phi, psi] + E''''[phi, phi, phi, phi] / 6) / mu_n'(p_c)

(H, E''', E'''' at the bifurcation, mu_n' the rate of mu_n along the axisymmetric branch).
In the classical normalisation p / p_c = 1 + b xi^2, xi = a w_max / h the largest normal
displacement of the mode over the thickness: b = p2 h^2 / (w_max^2 p_c). The branch is
subcritical where p2 points back along the loading (the axisymmetric branch reached p_c
with p moving the other way): the shell snaps at the bifurcation; supercritical where it
points on: it wrinkles into n lobes, and snaps (if at all) at the lobed branch's fold.

Imperfection sensitivity (:meth:`Koiter.limit`). An imperfection of amplitude e enters the
reduced equation along phi as the force e gamma, gamma = phi . d G / d e; then
mu_n' [(p - p_c) a - p2 a^3] + gamma e = 0, whose limit point (d/da = 0) is

    p_s - p_c = 3 p2 a_s^2,   a_s^3 = -gamma e / (2 mu_n' p2)

(Koiter 1945; Hutchinson & Koiter 1970, eq. 2.10: the two-thirds power law).

Branch switching (:func:`follow_bifurcation`): from (y_0 + a0 phi + a0^2 psi, p_c + p2 a0^2)
Newton with the amplitude prescribed (a0 = ``start``), then pseudo-arclength continuation
(:func:`shellbvp.continuation.pseudo_arclength`) to the lobed branch's first fold or to a
stated end. The fold is located by Brent's method on dp/da and located again on a finer
discretisation (degree + ``DEGREE_STEP``, K + 1): the change is its error estimate.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .continuation import (ContinuationOptions, locate_fold, newton, point_at_monitor,
                           pseudo_arclength)
from .errors import ConvergenceError
from .fourier2d import Fourier2D
from .results import Equilibrium

__all__ = ["LobedSystem", "Koiter", "LobedBranch", "LobedFold", "Critical", "critical_point",
           "koiter", "imperfect_limit", "follow_bifurcation", "DEGREE_STEP", "LOBED_OPTIONS"]

#: degree increase of the finer discretisation that gives every lobed fold its error
DEGREE_STEP = 8
#: the continuation's settings on a lobed branch (unknowns of unit mass norm: ds = 0.02 is a
#: change of shape of a fiftieth of the amplitude scale, or of p). Fold probes (the monitor
#: prescribed past a fold the slope predicts) take the branch through folds where it turns
#: sharply in (y, p): the bud's, where p runs over 22 while the amplitude moves by 0.006,
#: and the default cap's nearly axisymmetric one at kappa R0 = -2.034
LOBED_OPTIONS = ContinuationOptions(ds=0.005, ds_min=1e-7, ds_max=0.05, max_steps=400,
                                    newton_tol=1e-9, fold_probe=True)
#: relative tolerance of the bifurcation's p in the 2D discretisation
CRITICAL_TOL = 1e-13
#: ... and the step at which the secant is at the eigenvalue's round-off floor
FLOOR_TOL = 1e-9
#: a secant stopped by the eigenvalue's round-off has settled where its last SETTLED iterates
#: lie within SETTLED_TOL (relative): the cylinder with a growing ring (R/t = 100, eigenvalues
#: up to 1e12, mu_n' = -0.37) scatters its mu_n by 2e-6
SETTLED, SETTLED_TOL = 8, 1e-6


class LobedSystem:
    """G(y, p) = dE/dy = 0 of a :class:`shellbvp.fourier2d.Fourier2D` discretisation as a
    discrete system of the continuation: ``evaluate`` gives (G, the exact Hessian, dG/dp);
    ``monitor`` the amplitude phi . y of the critical mode (and its gradient phi)."""

    def __init__(self, f: Fourier2D, phi: np.ndarray):
        self.f, self.phi = f, f.displacement(phi)
        self.size = f.size

    def evaluate(self, y, p):
        g, Hm = self.f.hessian(y, p, gradient=True)
        return g, Hm, self.f.parameter_gradient(y, p)

    def monitor(self, y):
        return float(self.phi @ y), self.phi


@dataclass(frozen=True)
class Koiter:
    """Koiter's initial post-buckling coefficients at a bifurcation into n waves (module
    docstring).

    Attributes:
        n: the harmonic; p_c: the bifurcation (the 2D discretisation's); parameter: its name.
        a: the asymmetric coefficient (0: the class is symmetric under phi -> -phi).
        p2: p = p_c + p2 a^2 + ... along the lobed branch, a the mass-norm amplitude.
        b: the same in the classical normalisation, p / p_c = 1 + b xi^2, xi = a w_max / h.
        mu_p: d mu_n / dp at p_c along the axisymmetric branch.
        w_max: the largest normal displacement of the unit (mass norm) mode.
        h: the thickness the normalisation uses.
        direction: +1 or -1, the way p moved along the axisymmetric branch to p_c.
        E3, E4: E'''[phi, phi, psi] and E''''[phi, phi, phi, phi].
        gamma: phi . dG/de, the force along phi per unit amplitude e of an imperfection of
            the critical mode's shape in the reference surface (:meth:`Fourier2D.imperfect`,
            e on the mode of unit mass norm).
    """

    n: int
    p_c: float
    parameter: str
    p2: float
    b: float
    mu_p: float
    w_max: float
    h: float
    direction: float
    E3: float
    E4: float
    gamma: float = math.nan
    a: float = 0.0

    @property
    def kind(self) -> str:
        """``"subcritical"`` (the lobed branch turns back along the loading: the shell snaps
        at the bifurcation and is imperfection sensitive) or ``"supercritical"``."""
        return "subcritical" if self.p2 * self.direction < 0 else "supercritical"

    def p_of(self, amplitude) -> np.ndarray:
        """p on the lobed branch at mass-norm amplitude a, to second order."""
        return self.p_c + self.p2 * np.asarray(amplitude, dtype=float) ** 2

    def limit(self, imperfection) -> np.ndarray:
        """The limit load of the imperfect shell to leading order: p_s = p_c + 3 p2 a_s^2,
        a_s^3 = -gamma e / (2 mu_n' p2), for imperfection amplitudes e of the critical
        mode's shape (unit mass norm; NaN where the bifurcation is supercritical: no limit
        point near it)."""
        e = np.asarray(imperfection, dtype=float)
        if self.kind == "supercritical":
            return np.full(e.shape, math.nan)
        a_s = np.cbrt(-self.gamma * e / (2 * self.mu_p * self.p2))
        return self.p_c + 3 * self.p2 * a_s**2

    def knockdown(self, xi) -> np.ndarray:
        """p_s / p_c (:meth:`limit`) for imperfections of the critical mode's shape whose
        largest normal displacement is xi times the thickness (e = xi h / w_max)."""
        return self.limit(np.asarray(xi, dtype=float) * self.h / self.w_max) / self.p_c

    def __repr__(self) -> str:
        return (f"Koiter(n = {self.n}, {self.kind}, {self.parameter}_c = {self.p_c:.10g}, "
                f"b = {self.b:.5g}, p2 = {self.p2:.5g})")


@dataclass(frozen=True)
class LobedFold:
    """A fold of a lobed branch: the parameter there, the mass-norm amplitude of the
    critical mode, the error estimate of p (the change on the finer discretisation) and
    the branch point after which it lies; ``error_note`` says why an error estimate is
    NaN (the fold not found again on the finer discretisation)."""

    p: float
    amplitude: float
    error_estimate: float
    index: int
    y: np.ndarray = field(repr=False, default=None)
    error_note: str = ""


@dataclass(frozen=True)
class LobedBranch:
    """The branch of n-lobed equilibria from a bifurcation (:func:`follow_bifurcation`).

    Attributes:
        n, K, degree: the discretisation (harmonics 0..K n, Chebyshev degree).
        parameter: the name of p.
        koiter: the coefficients at the bifurcation (:class:`Koiter`).
        p_c, p_c_error: the bifurcation in this discretisation and its change on the finer
            one.
        p: the parameter at every point; amplitude: phi . y there.
        harmonics: (points, K + 1) the mass norm of each harmonic's displacement, harmonic 0
            measured from the axisymmetric branch at p_c.
        folds: the lobed branch's folds (:class:`LobedFold`).
        stop: why the continuation stopped.
        discretisation: the :class:`shellbvp.fourier2d.Fourier2D`; states: y per point.
        critical: (p_c, y_c, phi, mu) in that discretisation (:func:`critical_point`).
    """

    n: int
    K: int
    degree: int
    parameter: str
    koiter: Koiter
    p_c: float
    p_c_error: float
    p: np.ndarray
    amplitude: np.ndarray
    harmonics: np.ndarray
    folds: tuple
    stop: str
    discretisation: Fourier2D = field(repr=False, default=None)
    states: tuple = field(repr=False, default=())
    critical: tuple = field(repr=False, default=())

    def imperfect_limit(self, xi: float, *,
                        options: ContinuationOptions = LOBED_OPTIONS) -> LobedFold:
        """The limit load of this shell with an imperfection of the critical mode's shape
        whose largest normal deviation is ``xi`` thicknesses, computed directly
        (:func:`imperfect_limit`; its leading-order estimate is ``koiter.knockdown(xi) *
        p_c``)."""
        if not (isinstance(xi, (int, float)) and xi > 0 and math.isfinite(xi)):
            raise ValueError(f"xi must be a positive number of thicknesses, got {xi!r}")
        k = self.koiter
        return imperfect_limit(self.discretisation, self.critical, k,
                               float(xi) * k.h / k.w_max, options=options)

    @property
    def snap(self) -> float:
        """Where the shell leaves this equilibrium path: the bifurcation itself if
        subcritical, else the lobed branch's first fold (NaN: none before the stop)."""
        if self.koiter.kind == "subcritical":
            return self.p_c
        return self.folds[0].p if self.folds else math.nan

    def plot3d(self, i: int, field: str = "lobe_normal_displacement", ax=None, **options):
        """The lobed state at point i in 3D, a sector cut away, coloured by ``field``
        (:func:`shellbvp.pictures.plot_lobed3d`: the fields, ``cut``, ``magnify`` of the
        lobes, ``units``); returns the 3D axes."""
        from .pictures import plot_lobed3d

        return plot_lobed3d(self.discretisation, self.states[self._index(i)], self.p[i],
                            field, ax, **options)

    def animate(self, path, **options) -> None:
        """Write the lobed states in 3D beside the branch's diagram as a GIF or MP4
        (:func:`shellbvp.pictures.animate_lobed`)."""
        from .pictures import animate_lobed

        animate_lobed(self, path, **options)

    def to_vtk(self, folder, **options):
        """Write every lobed state as a ParaView file in ``folder`` and their collection
        ``lobed.pvd`` (:func:`shellbvp.paraview.write_lobed_branch`); returns its path."""
        from .paraview import write_lobed_branch

        return write_lobed_branch(self, folder, **options)

    def _index(self, i) -> int:
        if not (isinstance(i, (int, np.integer)) and -len(self.states) <= i < len(self.states)):
            raise ValueError(f"i must index the branch's {len(self.states)} states, got {i!r}")
        return int(i)

    def columns(self) -> dict:
        """The branch as named columns (p, the amplitude, |y_k| per harmonic k)."""
        out = {self.parameter: self.p, "amplitude": self.amplitude}
        for j in range(self.K + 1):
            out[f"harmonic_{j * self.n}"] = self.harmonics[:, j]
        return out

    def __repr__(self) -> str:
        end = (f"fold at {self.parameter} = {self.folds[0].p:.10g} +- "
               f"{self.folds[0].error_estimate:.1e}" if self.folds else f"stop: {self.stop}")
        return (f"LobedBranch(n = {self.n}, {self.koiter.kind}, {self.parameter}_c = "
                f"{self.p_c:.10g}, {len(self.p)} points, {end})")


# --- the bifurcation in the 2D discretisation ------------------------------------------------
def _axisymmetric(f: Fourier2D, p: float, y0=None, tol: float = 1e-13, maxiter: int = 20):
    """y_0(p): the axisymmetric equilibrium in f's unknowns (Newton on harmonic 0 and its
    joint multipliers)."""
    b = f.indices(0)
    y = f.origin.copy() if y0 is None else np.array(y0, dtype=float)
    for _ in range(maxiter):
        g, Hm = f.hessian(y, p, gradient=True)
        d = np.linalg.solve(Hm[np.ix_(b, b)], g[b])
        y[b] -= d
        if np.linalg.norm(d) <= tol * (1 + np.linalg.norm(y)):
            return y, Hm
    raise ConvergenceError(f"the axisymmetric state at {f.eq.scene.quote(p, 10)} "
                           f"did not converge in the 2D discretisation")


def _lowest(f: Fourier2D, y, p):
    """(mu, phi, H): the lowest eigenpair of the Hessian's block n at (y, p)
    (:meth:`Fourier2D.block_modes`: phi with its joint multipliers)."""
    Hm = f.hessian(y, p)
    mu, V = f.block_modes(f.n, y, p, hessian=Hm)
    return float(mu[0]), V[:, 0], Hm


class Critical(tuple):
    """(p_c, y_0(p_c), phi, mu_n'(p_c)) of :func:`critical_point`, with ``floor``: p_c's
    uncertainty where the eigenvalue's round-off, not the tolerance, ended the secant (0
    otherwise)."""

    floor = 0.0


def critical_point(f: Fourier2D, p_guess: float | None = None, *,
                   tol: float = CRITICAL_TOL) -> Critical:
    """(p_c, y_0(p_c), phi, mu_n'(p_c)): the bifurcation into f's harmonic n in the 2D
    discretisation (module docstring), by the secant method on mu_n(p) from ``p_guess``
    (default the base equilibrium's p). The mode's sign: its largest normal displacement is
    positive. Where mu_n's round-off (eps times the largest eigenvalue, the stiffest short
    waves, against a small rate mu_n') stops the secant before ``tol``, its iterates still
    settle: the last SETTLED of them within SETTLED_TOL; p_c is then the last, and
    ``floor`` the larger of their spread and the scatter of their mu over mu_n'."""
    p0 = f.eq.p if p_guess is None else float(p_guess)
    scale = max(abs(p0), 1.0)
    y = None
    ys = {}

    def mu(p):
        nonlocal y
        y, _ = _axisymmetric(f, p, y)
        ys[p] = y.copy()
        return _lowest(f, y, p)[0]

    pa, pb = p0, p0 + 1e-6 * scale
    ma, mb = mu(pa), mu(pb)
    step = math.inf
    last = [(pa, ma), (pb, mb)]
    for _ in range(30):
        if mb == ma:
            break
        pc = pb - mb * (pb - pa) / (mb - ma)
        pa, ma = pb, mb
        pb, mb = pc, mu(pc)
        last.append((pb, mb))
        step = abs(pb - pa)
        if step <= tol * scale:
            break
    ps, ms = np.array(last[-SETTLED:]).T
    spread = float(np.ptp(ps)) if len(last) >= SETTLED else math.inf
    # the secant's last steps wander at mu's round-off floor: accepted below FLOOR_TOL, or
    # where its iterates have settled (the floor then measured)
    if not (step <= FLOOR_TOL * scale or spread <= SETTLED_TOL * scale):
        raise ConvergenceError(f"the bifurcation into n = {f.n} was not located in the 2D "
                               f"discretisation near {p0:.8g} (last secant step {step:.1e})")
    p_c = pb
    y_c = ys[p_c]
    _, phi, Hm = _lowest(f, y_c, p_c)
    w = _normal_displacement(f, phi)
    if w[np.argmax(np.abs(w))] < 0:
        phi = -phi
    # mu_n' = phi . dA/dp phi along the branch (the pencil (A, diag(I, 0)), phi unit in y):
    # the Hessian's own rate plus its change along y_0'(p), exact
    dy0 = _branch_rate(f, y_c, p_c, Hm)
    mu_p = phi @ f.hessian_rate(y_c, phi, p_c) + phi @ f.third(y_c, phi, dy0, p_c)
    out = Critical((p_c, y_c, phi, float(mu_p)))
    if not step <= FLOOR_TOL * scale:
        out.floor = max(spread, float(np.std(ms)) / abs(mu_p))
    return out


def _branch_rate(f: Fourier2D, y, p, Hm) -> np.ndarray:
    """y_0'(p): the axisymmetric branch's rate (harmonic 0 and its multipliers), from the
    Hessian Hm there."""
    b0 = f.indices(0)
    dy0 = np.zeros(f.size)
    dy0[b0] = -np.linalg.solve(Hm[np.ix_(b0, b0)], f.parameter_gradient(y, p)[b0])
    return dy0


def _normal_displacement(f: Fourier2D, y) -> np.ndarray:
    """The normal displacement of harmonic n's part of y at the Gauss points (at omega = 0,
    where cos(n omega) = 1): U . (sin theta, 0, cos theta) of the base state."""
    Gk = f.G[f.ks.index(f.n)]
    U = Gk[:3] @ y[f.block(f.n)]                    # (3 components, points): U (not U', U'')
    th = f.base.theta.reshape(-1)
    return U[0] * np.sin(th) + U[2] * np.cos(th)


def koiter(f: Fourier2D, critical=None, *, direction: float = 1.0) -> tuple:
    """(:class:`Koiter`, psi, y_0'(p_c)) at the bifurcation ``critical`` (the tuple of
    :func:`critical_point`; computed when None). ``direction``: the way p moved along the
    axisymmetric branch to the bifurcation."""
    p_c, y_c, phi, mu_p = critical_point(f) if critical is None else critical
    Hm = f.hessian(y_c, p_c)
    B = f.third(y_c, phi, phi, p_c)
    n = f.size
    e = f.displacement(phi)             # the amplitude a = e . (y - y_0), e . psi = 0
    A = np.zeros((n + 1, n + 1))
    A[:n, :n], A[:n, n], A[n, :n] = Hm, e, e
    psi = np.linalg.solve(A, np.append(-0.5 * B, 0.0))[:n]
    E3 = float(psi @ B)
    E4 = f.fourth(y_c, phi, p_c)
    p2 = -(E3 + E4 / 6.0) / mu_p
    w_max = float(np.max(np.abs(_normal_displacement(f, phi))))
    h = float(f.eq.scene.h)
    dy0 = _branch_rate(f, y_c, p_c, Hm)
    gamma = float(phi @ f.imperfection_gradient(y_c, phi, p_c))
    K = Koiter(n=f.n, p_c=float(p_c), parameter=f.eq.scene.parameter, p2=float(p2),
               b=float(p2 * h**2 / (w_max**2 * p_c)) if p_c != 0 else math.nan,
               mu_p=mu_p, w_max=w_max, h=h, direction=math.copysign(1.0, direction),
               E3=E3, E4=float(E4), gamma=gamma)
    return K, psi, dy0


# --- following the lobed branch --------------------------------------------------------------
def _transfer(y, f: Fourier2D, g: Fourier2D) -> np.ndarray:
    """f's state y as g's unknowns (g finer: Chebyshev coefficients padded, harmonics
    added as zero; the joints' multipliers of the harmonics f has kept, the others zero:
    the conditions are the same integrals in both)."""
    out = []
    lam = np.zeros(g.size)
    P = f.base.s.shape[0]
    for j, k in enumerate(g.ks):
        nb = g.degree + 1
        if k in f.ks:
            c = f.coefficients(y)[f.ks.index(k)].reshape(P, 3, f.degree + 1)
            pad = np.zeros((P, 3, nb))
            pad[:, :, :f.degree + 1] = c
            out.append(pad.reshape(-1))
            lam[g.multipliers(k)] = np.asarray(y)[f.multipliers(k)]
        else:
            out.append(np.zeros(P * 3 * nb))
    return g.reduce(out, lam[g.ny:])


def _fold_on(f: Fourier2D, critical, y, p, amplitude, tol) -> LobedFold:
    """The fold of f's lobed branch near (y, p) at about ``amplitude``: branch points with
    the amplitude prescribed, marched outward from it on both sides (each Newton solve
    predicted along its neighbour's exact tangent; the step grows by 1.5 after a success
    and halves after a failure) until dp/da changes sign between neighbours, never closer
    to zero amplitude than half of it (where the branch meets the axisymmetric one), at most
    a doubling of it. Raises ConvergenceError where that fails."""
    system = LobedSystem(f, critical[2])
    sign = math.copysign(1.0, amplitude)
    mid = point_at_monitor(system, y, p, amplitude, tol=tol)
    ends, pts = [mid, mid], [mid]                             # ends: the lowest, the highest
    step = [0.02 * abs(amplitude)] * 2
    for _ in range(40):
        for side, direction in ((0, -1.0), (1, 1.0)):
            last = ends[side]
            a = last.monitor + direction * sign * step[side]
            if not 0.5 <= a / amplitude <= 2.0 or step[side] < 1e-6 * abs(amplitude):
                continue
            try:
                q = point_at_monitor(system, *last.predicted(a), a, tol=tol)
            except ConvergenceError:
                step[side] *= 0.5
                continue
            ends[side] = q
            pts.insert(0 if side == 0 else len(pts), q)
            step[side] *= 1.5
        for u, v in zip(pts, pts[1:]):
            if u.slope * v.slope < 0:
                fold = locate_fold(system, u, v)
                return LobedFold(float(fold.p), float(fold.monitor), math.nan, -1, fold.U)
    raise ConvergenceError(f"the lobed fold near amplitude {amplitude:.6g} was not found on "
                           f"the finer discretisation (dp/da of one sign from amplitude "
                           f"{pts[0].monitor:.6g} to {pts[-1].monitor:.6g})")


def imperfect_limit(f: Fourier2D, critical, kc: Koiter, amplitude: float, *,
                    options: ContinuationOptions = LOBED_OPTIONS) -> LobedFold:
    """The limit load of the shell with an imperfection of the critical mode's shape
    (:meth:`Fourier2D.imperfect`, ``amplitude`` e on the mode of unit mass norm), computed
    directly: its equilibria from before the bifurcation (where Koiter's law, ``kc``, puts
    the limit twice as far from p_c, but not closer to p = 0 than 0.1 p_c; the imperfect
    shell's state there from the perfect one's) continued along the loading to their first
    fold,
    located by Brent's method on dp/da. The check of :meth:`Koiter.limit` that does not go
    through the expansion. The fold is one within f's symmetry class (harmonics 0, n, ...,
    K n): a bifurcation of the imperfect shell into another class is not looked for, which
    is the shell's limit only while the imperfect path stays below the perfect shell's
    other bifurcations (small amplitudes, near p_c). A path that passes p_c without a fold
    is refused: the single-mode picture no longer holds at that amplitude.

    Raises:
        ValueError: a supercritical bifurcation (no limit point near it), bad amplitude.
        ConvergenceError: no fold before the continuation stopped, or the imperfect path
            passed p_c before its fold.
    """
    if kc.kind != "subcritical":
        raise ValueError("imperfect_limit needs a subcritical bifurcation: a supercritical "
                         "one has no limit point near it")
    if not (isinstance(amplitude, (int, float)) and amplitude != 0
            and math.isfinite(amplitude)):
        raise ValueError(f"amplitude must be a finite nonzero number, got {amplitude!r}")
    p_c, y_c, phi, _ = critical
    drop = 2.0 * (p_c - float(kc.limit(amplitude)))
    if p_c != 0 and abs(drop) > 0.9 * abs(p_c):  # a large knockdown: start from 0.1 p_c
        drop = math.copysign(0.9 * abs(p_c), drop)
    p0 = p_c - drop
    y0, _ = _axisymmetric(f, p0, y_c)
    system = LobedSystem(f.imperfect(phi, float(amplitude)), phi)
    pts, brackets = pseudo_arclength(system, y0, p0, options=options, n_folds=1,
                                     direction=kc.direction)
    if not brackets:
        raise ConvergenceError(f"imperfect shell (amplitude {amplitude:.3g}): no limit point "
                               f"before the continuation stopped at {pts[-1].p:.8g}")
    i, j = brackets[0]
    fold = locate_fold(system, pts[i], pts[j])
    if (fold.p - p_c) * kc.direction > 0:
        raise ConvergenceError(f"imperfect shell (amplitude {amplitude:.3g}): its path passes "
                               f"the bifurcation {p_c:.8g} and folds only at {fold.p:.8g}, "
                               f"within harmonics 0, {f.n}, ..., {f.K * f.n}: at this amplitude "
                               f"the single-mode picture does not hold (other classes are "
                               f"not checked)")
    return LobedFold(float(fold.p), float(fold.monitor), math.nan, i, fold.U)


def follow_bifurcation(instability, *, K: int = 2, degree: int | None = None,
                       start: float | None = None, p_stop=None,
                       amplitude_max: float = math.inf, n_folds: int = 1,
                       options: ContinuationOptions = LOBED_OPTIONS,
                       estimate_error: bool = True, progress=None) -> LobedBranch:
    """The branch of n-lobed equilibria from a bifurcation found by
    :func:`shellbvp.first_instability`, followed to its ``n_folds``-th fold or a stated end.
    At an axisymmetric bifurcation (n = 0) the bifurcated axisymmetric branch instead, with
    Koiter's a and b (:func:`shellbvp.pitchfork.follow_branch_point`, a
    :class:`shellbvp.pitchfork.BifurcatedBranch`; ``start`` and ``amplitude_max`` are then
    offsets of the monitor, w / H, and K, degree and estimate_error do not apply).

    Arguments:
        instability: a :class:`shellbvp.Instability` of kind ``"bifurcation"`` (it carries
            the axisymmetric equilibrium there).
        K: harmonics 0, n, ..., K n; degree: Chebyshev degree (default that of
            :mod:`shellbvp.harmonics`).
        start: the mass-norm amplitude of the first point (default: where Koiter's
            parabola has moved p by 1e-4 of p_c, at least 1e-3).
        p_stop: (low, high) the parameter range to stay in (default: unbounded).
        amplitude_max: stop once the amplitude exceeds this.
        n_folds: folds to pass before stopping (0: none, follow to the other ends).
        options: the continuation's settings.
        estimate_error: locate p_c and the folds again on the finer discretisation (degree
            + ``DEGREE_STEP``, K + 1): their change is the error estimate.
        progress: called with every accepted continuation point.

    Raises:
        ValueError: an instability that is not a bifurcation, bad arguments.
        ConvergenceError: the start or the continuation fails (with what converged).
    """
    from .instability import Instability

    if not isinstance(instability, Instability) or instability.kind != "bifurcation":
        raise ValueError("instability must be a shellbvp.Instability of kind 'bifurcation' "
                         f"(from first_instability), got {instability!r}")
    if instability.n == 0:
        # an axisymmetric bifurcation: the bifurcated branch is axisymmetric too, followed
        # on the branch's own discretisation (start and amplitude_max in its monitor, w / H)
        from .pitchfork import follow_branch_point

        H = instability.branch_point.system.bvp.scale
        return follow_branch_point(
            instability, start=start, p_stop=p_stop,
            w_stop=(-amplitude_max * H, amplitude_max * H), n_folds=n_folds or None,
            options=None if options is LOBED_OPTIONS else options, progress=progress)
    eq = instability.equilibrium
    if not isinstance(eq, Equilibrium):
        raise ValueError("instability carries no equilibrium: compute it with "
                         "shellbvp.first_instability")
    if not (isinstance(K, (int, np.integer)) and 1 <= K <= 8):
        raise ValueError(f"K must be an integer in [1, 8] (harmonic 0 and n at least), got {K!r}")
    if not (isinstance(n_folds, (int, np.integer)) and n_folds >= 0):
        raise ValueError(f"n_folds must be a non-negative integer, got {n_folds!r}")
    if not (isinstance(amplitude_max, (int, float)) and amplitude_max > 0):
        raise ValueError(f"amplitude_max must be positive, got {amplitude_max!r}")
    if start is not None and not (isinstance(start, (int, float)) and start > 0
                                  and math.isfinite(start)):
        raise ValueError(f"start must be a positive amplitude, got {start!r}")
    # in the scene's units (instability.p may be scaled, the equilibrium and scan are not)
    direction = math.copysign(1.0, eq.p - instability.scan[0][0]) \
        if instability.scan else 1.0
    f = Fourier2D(eq, instability.n, int(K), degree=degree)
    crit = critical_point(f, eq.p)
    kc, psi, dy0 = koiter(f, crit, direction=direction)
    p_c, y_c, phi, _ = crit
    if start is None:
        start = max(math.sqrt(1e-4 * max(abs(p_c), 1.0) / max(abs(kc.p2), 1e-300)), 1e-3)
    a0 = float(start)
    dp0 = kc.p2 * a0**2
    system = LobedSystem(f, phi)
    y0 = y_c + dp0 * dy0 + a0 * phi + a0**2 * psi
    first = newton(system, y0, p_c + dp0, 1.0, 0.0, a0, tol=options.newton_tol, maxiter=25,
                   fail_fast=False)
    if not first.ok:
        raise ConvergenceError(f"branch switching: no lobed state at amplitude {a0:.3g} "
                               f"from Koiter's prediction ({first.history})")
    lo, hi = (-math.inf, math.inf) if p_stop is None else map(float, p_stop)
    stop = "max_steps"
    try:
        pts, brackets = pseudo_arclength(
            system, first.U, first.p, options=options, p_stop=(lo, hi),
            monitor_stop=(-amplitude_max, amplitude_max),
            n_folds=n_folds if n_folds > 0 else None,
            direction=math.copysign(1.0, first.p - p_c) if first.p != p_c else 1.0,
            progress=progress)
    except ConvergenceError as exc:
        if exc.partial is None:
            raise
        pts, brackets = exc.partial
        stop = f"continuation stalled: {exc}"
    else:
        last = pts[-1]
        if n_folds and len(brackets) >= n_folds:
            stop = f"after {n_folds} fold(s)"
        elif not lo < last.p < hi:
            # the continuation lands its last point on the bound it crosses
            stop = f"{f.eq.scene.parameter} left [{lo:g}, {hi:g}]"
        elif abs(last.monitor) >= amplitude_max:
            stop = f"amplitude beyond {amplitude_max:g}"
    folds = []
    for i, j in brackets:
        fold = locate_fold(system, pts[i], pts[j])
        folds.append(LobedFold(float(fold.p), float(fold.monitor), math.nan, i, fold.U))
    p_c_error = math.nan
    if estimate_error:
        g = Fourier2D(eq, instability.n, int(K) + 1, degree=f.degree + DEGREE_STEP)
        crit_g = critical_point(g, p_c)
        p_c_error = max(abs(crit_g[0] - p_c), crit.floor, crit_g.floor)
        phi_g = crit_g[2]
        fine = []
        for fo in folds:
            yg = _transfer(fo.y, f, g)
            # the finer mode may have the other sign: continue the amplitude's
            a_g = float(g.displacement(phi_g) @ yg)
            try:
                ff = _fold_on(g, crit_g, yg, fo.p, a_g, options.newton_tol)
            except ConvergenceError as exc:     # the fold stands; its error is unknown
                fine.append(LobedFold(fo.p, fo.amplitude, math.nan, fo.index, fo.y,
                                      error_note=str(exc)))
                continue
            fine.append(LobedFold(fo.p, fo.amplitude, abs(ff.p - fo.p), fo.index, fo.y))
        folds = fine
    ys = tuple(q.U for q in pts)
    harm = np.array([[np.linalg.norm((q.U - y_c)[f.block(k)]) for k in f.ks] for q in pts])
    return LobedBranch(n=f.n, K=f.K, degree=f.degree, parameter=f.eq.scene.parameter,
                       koiter=kc, p_c=float(p_c), p_c_error=p_c_error,
                       p=np.array([q.p for q in pts]),
                       amplitude=np.array([q.monitor for q in pts]), harmonics=harm,
                       folds=tuple(folds), stop=stop, discretisation=f, states=ys,
                       critical=crit)
