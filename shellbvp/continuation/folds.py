"""Folds: location between two branch points, polishing on another discretisation, and the
refinement ladder that gives every fold its error estimate.

Along the branch parametrised by the monitor m, p(m) is smooth and a fold of p is a
stationary point, dp/dm = 0, where dp/dm follows exactly from the bordered matrix with the
monitor prescribed (:func:`shellbvp.continuation.newton.tangent`). This is an exact fold
system, not a fit through coarse points: the fold is found to the discretisation's accuracy,
and since p is stationary there, an error delta in m costs only O(delta^2) in p.
"""

from __future__ import annotations

from dataclasses import replace

import math
import time

import numpy as np

from ..errors import ConvergenceError
from ..results import Fold
from ..methods.base import (Discretisation, SecondOrder, ShellProblem, Transplantable,
                            first_rung, implements)
from .newton import bordered_lu, newton, tangent
from .options import ContinuationOptions

__all__ = ["locate_fold", "polish_fold", "refine_fold", "ladder", "climb", "bracket_estimate",
           "fold_sensitivity", "refuse_below_round_off"]

#: Newton tolerance and monitor tolerance of a fold that is returned to the user
FOLD_NEWTON_TOL = 1e-10
FOLD_MONITOR_TOL = 1e-10
#: first secant step in m and the window the secant iteration may not leave (in w / H)
POLISH_STEP, POLISH_WINDOW = 1e-5, 0.05
POLISH_MAXITER = 12
#: dp/dm comes from the Jacobian before a solve's last update, so it is off by ~K update
#: (K / |d2p/dm2| = 0.14-0.48 measured on five caps, T = 3.3-16.6, lam = 0.01-10, both
#: models, for a smooth error; far less for a rough one): the polishing stops on it only
#: after an update of at most this many monitor tolerances (the monitor is then good to
#: ~1.5 of them; a larger last update takes one more solve)
SLOPE_TRUST = 1.0


def _scatter(system, p) -> float:
    """The round-off scatter of a fold parameter p of ``system``'s problem
    (``bvp.round_off``), 0 where the problem does not state it."""
    bvp = system.bvp if implements(system, Discretisation) else None
    return bvp.round_off(p) if implements(bvp, ShellProblem) else 0.0


class _Slope:
    """dp/dm along the branch at prescribed monitor values, remembering every solve (the
    nearest one, with its exact tangent, is the predictor for the next)."""

    def __init__(self, system, known, tol, early_stop=False):
        # early_stop: a solve may stop after one update or on its predicted next update
        # (newton's one_update, predict) where the error left is below tol
        self.system, self.tol, self.early_stop = system, tol, early_stop
        self.known = list(known)   # (m, U, p, dU/dm, dp/dm)
        self.update = {}           # m -> the last Newton update of its solve (relative)
        self.floor_step = 0.0      # largest last update of a solve ended at its round-off floor
        self.solves = self.iterations = 0
        self.round_off = 0.0       # largest uncertainty of p left by a Newton round-off floor

    def __call__(self, mv):
        for k in self.known:
            if k[0] == mv:
                return k[4]
        m0, U0, p0, dU0, g0 = min(self.known, key=lambda k: abs(k[0] - mv))
        res = newton(self.system, U0 + (mv - m0) * dU0, p0 + (mv - m0) * g0, 1.0, 0.0, mv,
                     tol=self.tol, one_update=self.early_stop, predict=self.early_stop)
        self.solves += 1
        self.iterations += res.iterations
        if not res.ok:
            raise ConvergenceError(f"fold location: Newton failed at monitor {mv:.10g}: "
                                   f"{res.history}")
        return self.record(mv, res)

    def record(self, mv, res):
        """Remember the converged solve ``res`` at monitor mv (its state, tangent, last
        update and round-off); returns its dp/dm."""
        v, _, dp = tangent(res)
        self.known.append((mv, res.U, res.p, v, dp))
        self.update[mv] = res.history[-1][1]
        self.round_off = max(self.round_off, res.p_noise)
        if res.p_noise > 0:
            self.floor_step = max(self.floor_step, res.history[-1][1])
        return dp

    def state(self, mv):
        self(mv)
        k = next(k for k in reversed(self.known) if k[0] == mv)
        return k[2], k[1]

    def stats(self, t0, extra=0):
        return dict(solves=self.solves, newton_iterations=self.iterations + extra,
                    round_off=self.round_off, wall_time=time.perf_counter() - t0)


def locate_fold(system, a, b, *, tol=FOLD_NEWTON_TOL, monitor_tol=FOLD_MONITOR_TOL) -> Fold:
    """The fold between branch points a and b (:class:`Point` with dp/ds of opposite signs):
    Brent's method on dp/dm over [m_a, m_b], each value from a Newton solve at prescribed m.

    Raises ConvergenceError if dp/dm does not change sign over the bracket (the monitor is
    not a coordinate of the branch there) or a Newton solve fails.
    """
    t0 = time.perf_counter()
    if a.tangent[0] == 0 or b.tangent[0] == 0 or not a.slope * b.slope < 0:
        raise ConvergenceError(f"fold location: dp/dm does not change sign between monitor "
                               f"{a.monitor:.6g} and {b.monitor:.6g} (tangents {a.tangent}, "
                               f"{b.tangent}): the monitor is not a coordinate of the branch")
    slope = _Slope(system, [(q.monitor, q.U, q.p, q.dU / q.tangent[0], q.slope)
                            for q in (a, b)], tol)
    lo, hi = sorted((a.monitor, b.monitor))
    from scipy.optimize import brentq

    m_star = brentq(slope, lo, hi, xtol=monitor_tol, rtol=4 * np.finfo(float).eps)
    p, U = slope.state(m_star)
    return Fold(p=p, monitor=m_star, U=U, system=system, stats=slope.stats(t0))


def polish_fold(system, U, p, monitor, *, curvature=None, step=POLISH_STEP,
                window=POLISH_WINDOW, tol=FOLD_NEWTON_TOL, monitor_tol=FOLD_MONITOR_TOL,
                maxiter=POLISH_MAXITER, refining: bool = False) -> Fold:
    """Re-locate a fold known approximately (e.g. on a coarser discretisation): Newton's
    method on dp/dm = 0 from ``monitor``, with d2p/dm2 from ``curvature`` (e.g. the fold's on
    a coarser rung, which is the same to a few digits) or a first difference over ``step``,
    updated by secants. Stops when the next Newton move |dp/dm / c| (predicted, so a solve
    that would only confirm it is saved) or the last one is at most ``monitor_tol``: near
    the fold p = p* + c (m - m*)^2 / 2, so p is then within c monitor_tol^2 / 2 of its fold
    value (the returned stats carry c as ``curvature`` and (dp/dm)^2 / 2|c| at the returned
    point, that distance in p, as ``location``). Each Newton solve stops as soon as the
    error it leaves is below ``tol``: on its predicted next update, or after one update from
    a start next to the solution (:func:`shellbvp.continuation.newton.newton`'s
    ``predict`` and ``one_update``); dp/dm then comes from the Jacobian before the last
    update, so the stop on it waits for a solve whose last update is at most
    ``SLOPE_TRUST * monitor_tol``. ``refining``: U, p, monitor are the fold of a coarser
    discretisation of the same problem carried over (a finer rung of the ladder), so its
    first solve may stop after one update too.

    Raises ConvergenceError if the iteration does not converge or leaves
    [monitor - window, monitor + window].
    """
    t0 = time.perf_counter()
    res = newton(system, U, p, 1.0, 0.0, monitor, tol=tol, min_iterations=2,
                 one_update=refining, predict=True)
    if not res.ok:
        raise ConvergenceError(f"fold polishing: Newton failed at monitor {monitor:.10g}: "
                               f"{res.history}")
    slope = _Slope(system, [], tol, early_stop=True)
    dp = slope.record(monitor, res)

    # updates at the round-off floor of the discrete equations (as large as those of a solve
    # that stalled there, or as the problem's round-off scatter) are as small as they get:
    # waiting for smaller ones never ends (a stiff material, lam = 1e5: updates of 2-4e-10
    # against a monitor tolerance of 1e-10); that round-off is counted in the estimate
    scatter = _scatter(system, p)

    def trusted(m):
        return slope.update.get(m, math.inf) <= max(SLOPE_TRUST * monitor_tol,
                                                    slope.floor_step, scatter)

    m0, g0 = monitor, dp
    if curvature is None or not math.isfinite(curvature) or curvature == 0:
        m1 = monitor + step
        g1 = slope(m1)
        curvature = (g1 - g0) / (m1 - m0)
        m0, g0 = m1, g1
    c = curvature
    for _ in range(maxiter):
        if abs(g0 / c) <= monitor_tol and trusted(m0):
            break
        m1 = m0 - g0 / c
        if not abs(m1 - monitor) <= window:
            raise ConvergenceError(f"fold polishing left its window: monitor {m1:.10g} from "
                                   f"{monitor:.10g} (window {window:g}); the estimate is too "
                                   f"far (use a finer starting discretisation)")
        g1 = slope(m1)
        # a secant only over a move larger than the two points' own uncertainty (dp/dm is
        # off by up to 0.5 |c| times its solve's last update): over a smaller one it is
        # noise (lam = 1e5: secants of -0.1 and +7 where c = -70, and no convergence)
        if g1 != g0 and abs(m1 - m0) > slope.update.get(m0, 0.0) + slope.update.get(m1, 0.0):
            c = (g1 - g0) / (m1 - m0)
        m0, g0, moved = m1, g1, abs(m1 - m0)
        if moved <= monitor_tol and trusted(m0):
            break
    else:
        raise ConvergenceError(f"fold polishing: no convergence in {maxiter} steps "
                               f"(last dp/dm {g0:.2e}, d2p/dm2 {c:.3g})")
    p, U = slope.state(m0)
    return Fold(p=p, monitor=m0, U=U, system=system,
                stats=dict(slope.stats(t0, res.iterations), curvature=c,
                           location=0.5 * g0 * g0 / abs(c)))


def bracket_estimate(a, b) -> tuple[float, float]:
    """The fold between branch points a and b from their values alone: the stationary
    point m of the cubic Hermite interpolant of p(m) through (m, p, dp/dm) at both (no
    solve; exact for a cubic, and a seed within the polishing window in practice), and the
    interpolant's d2p/dm2 there. The first stationary point in [m_a, m_b] (the midpoint
    where there is none).

    In the variable t = (m - m_a) / d (d = m_b - m_a) the interpolant's derivative is the
    quadratic dp/dt = A t^2 + B t + C with A = 6 (p_a - p_b) + 3 d (g_a + g_b),
    B = 6 (p_b - p_a) - d (4 g_a + 2 g_b), C = d g_a (g = dp/dm; the Hermite basis
    differentiated), so d2p/dm2 = (2 A t + B) / d^2. Closed form rather than
    scipy.interpolate (identical values, checked in the tests), whose import alone took
    ~0.2-0.3 s of every process's start."""
    (ma, pa, ga), (mb, pb, gb) = sorted(
        (q.monitor, q.p, q.slope) for q in (a, b))
    d = mb - ma
    A = 6.0 * (pa - pb) + 3.0 * d * (ga + gb)
    B = 6.0 * (pb - pa) - d * (4.0 * ga + 2.0 * gb)
    C = d * ga
    roots = np.polynomial.polynomial.polyroots([C, B, A]) if (A, B) != (0.0, 0.0) \
        else np.array([])
    t = np.sort(roots.real[(np.abs(roots.imag) <= 1e-12 * (1.0 + np.abs(roots.real)))
                           & (roots.real >= 0.0) & (roots.real <= 1.0)])
    t0 = float(t[0]) if t.size else 0.5
    return ma + t0 * d, float((2.0 * A * t0 + B) / d**2)


def refine_fold(system, a, b, *, options: ContinuationOptions = ContinuationOptions(),
                index: int = -1) -> Fold:
    """The fold between branch points a and b, to ``options.fold_tol``.

    Seeded by :func:`bracket_estimate`, then refined on the ladder (:func:`ladder`); where
    that fails, seeded by :func:`locate_fold` on the branch's system instead; where the
    monitor is not a coordinate of the branch at the fold (it turns there as well, e.g. the
    apex deflection of a pressurised cap), located and refined in a coordinate of the end
    states instead (:func:`_in_end_state_coordinate`). The branch itself may be followed on a
    coarser system than the ladder's: it only brackets the fold.
    """
    t0 = time.perf_counter()

    def seeded():
        m0, c0 = bracket_estimate(a, b)
        q = min((a, b), key=lambda q: abs(q.monitor - m0))
        U0, p0 = q.predicted(m0)
        return ladder(system, U0, p0, m0, c0 if c0 * a.slope < 0 else None,
                      options=options, index=index, t0=t0)

    def bracketed():
        # the cubic seed was too far for Newton on dp/dm (a coarse branch of a deep cap):
        # locate the fold on the branch's own system by bracketing (Brent), then the ladder
        f = locate_fold(system, a, b, monitor_tol=max(FOLD_MONITOR_TOL, options.fold_tol))
        return ladder(system, f.U, f.p, f.monitor, options=options, index=index, t0=t0)

    def other_coordinate():
        return _in_end_state_coordinate(system, a, b, options=options, index=index, t0=t0)

    errors = []
    for attempt in (seeded, bracketed, other_coordinate):
        try:
            return attempt()
        except ConvergenceError as exc:
            errors.append(exc)
    raise errors[0]


class _EndStateCoordinate:
    """A view of a BVP whose monitor is the linear coordinate m = c_a . y(a) + c_b . y(b) of
    its end states (everything else is the BVP's own)."""

    def __init__(self, bvp, ca, cb):
        self._bvp, self.ca, self.cb = bvp, np.asarray(ca, float), np.asarray(cb, float)

    def __getattr__(self, name):
        return getattr(self._bvp, name)

    def monitor(self, ya, yb):
        return float(self.ca @ np.asarray(ya) + self.cb @ np.asarray(yb)), self.ca, self.cb

    def collocate(self, s, Y, p, hint=None):
        out = self._bvp.collocate(s, Y, p, hint)
        return type(out)(out.nodal, out.boundary, self.monitor(Y[0, :, 0], Y[-1, :, -1]))


def _in_end_state_coordinate(system, a, b, *, options, index, t0) -> Fold:
    """The fold between a and b located and refined with the monitor replaced by the
    direction in which the end states (y(eps), y(theta)) change from a to b, scaled so that
    it grows by 1 from a to b: a coordinate of the branch across a short bracket wherever
    the end states move, even where the BVP's monitor turns at the fold. The fold is
    returned on the original BVP (its monitor that BVP's), so that everything downstream
    (shape, w, continuation from it) reads it as any other. Needs a nodal system that can
    be carried to another BVP (``on``, ``split``: the Chebyshev method)."""
    from dataclasses import replace

    if not implements(system, Transplantable):
        raise ConvergenceError("fold location in an end-state coordinate needs the spectral "
                               "method")

    def ends(U):
        Y = system.states(U)
        return Y[0, :, 0], Y[-1, :, -1]

    (ya, yb), (za, zb) = ends(a.U), ends(b.U)
    da, db = za - ya, zb - yb
    norm = float(da @ da + db @ db)
    if not norm > 0:
        raise ConvergenceError("fold location: the end states do not move across the bracket")
    view = _EndStateCoordinate(system.bvp, da / norm, db / norm)
    other = system.on(view)

    def carried(q):
        m, _, _ = view.monitor(*ends(q.U))
        dm, _, _ = view.monitor(*ends(q.dU))     # linear: the derivative along the tangent
        return replace(q, monitor=m, tangent=(dm, q.tangent[1]))

    f = locate_fold(other, carried(a), carried(b),
                    monitor_tol=max(FOLD_MONITOR_TOL, options.fold_tol))
    fold = ladder(other, f.U, f.p, f.monitor, options=options, index=index, t0=t0)
    home = fold.system.on(system.bvp)
    m, _ = home.monitor(fold.U)
    stats = dict(fold.stats, curvature=None, coordinate="end states")
    return replace(fold, monitor=m, system=home, stats=stats)


def ladder(system, U, p, monitor, curvature=None, *,
           options: ContinuationOptions = ContinuationOptions(), index: int = -1,
           t0: float | None = None) -> Fold:
    """A fold known approximately on ``system`` (state U, parameter p, monitor, and d2p/dm2
    if known), to ``options.fold_tol``: polished on the first rung the tolerance needs
    (``system.for_tolerance(fold_tol)`` where the method offers it, else ``system``), then on
    its refinement, and so on, until the fold parameter changes by at most ``fold_tol`` on
    two consecutive rungs; the larger of those two changes is the error estimate and the
    finest fold is returned (so the estimate bounds the error of the values before and
    overestimates that of the returned one; two changes, not one, because a single change
    can understate the error where it oscillates in sign with the degree, see
    :func:`climb`). The estimate is at least the round-off in p, which a change between
    rungs does not see: that of a Newton solve stalled at its floor and the problem's own
    round-off scatter (``bvp.round_off(p)`` where offered), plus the error in p of the
    monitor the fold was located at, which both rungs share; ConvergenceError if the
    round-off exceeds ``fold_tol``, or after ``options.max_refinements`` rungs.
    """
    t0 = time.perf_counter() if t0 is None else t0
    refuse_below_round_off(system, p, options.fold_tol)
    first = first_rung(system, options.fold_tol)
    # the monitor of the fold to fold_tol / 10 (at least FOLD_MONITOR_TOL): p is then good
    # to ~c (fold_tol / 10)^2, and w to the accuracy asked of p
    m_tol = max(FOLD_MONITOR_TOL, options.fold_tol / 10)
    current = polish_fold(first, system.transfer(U, p, first), p, monitor,
                          curvature=curvature, monitor_tol=m_tol)

    def advance(finer, current):
        return polish_fold(finer, current.system.transfer(current.U, current.p, finer),
                           current.p, current.monitor, monitor_tol=m_tol,
                           curvature=current.stats["curvature"], refining=True)

    # the rungs share the monitor the fold was located at (the finer one starts there and
    # stops when its predicted move is below the monitor tolerance), so the change between
    # them does not see that location error either: add it, twice its quadratic-model value
    # (c is a secant estimate and p(m) not exactly a parabola: on a thin cap at tol 1e-4 the
    # model gave 5.96e-9 for an error of 6.06e-9)
    return climb(system, first, current, advance, options=options, index=index, t0=t0,
                 location_weight=2.0)


def refuse_below_round_off(system, p, fold_tol) -> None:
    """ConvergenceError where the problem's own round-off scatter at p (a seed of the fold,
    within ~1e-5 of it) exceeds fold_tol: a floor no rung of a ladder goes below, so the
    tolerance is refused before the ladder climbs (a thin shell at tol 1e-12 compiled and
    solved degree after degree for minutes, then was refused at the end)."""
    floor = _scatter(system, p)
    if floor > fold_tol:
        raise _below_round_off(p, floor, fold_tol)


def _below_round_off(p, noise, fold_tol) -> ConvergenceError:
    """The error of a fold near p that round-off leaves uncertain by ``noise`` > fold_tol,
    with the tolerance to ask for: noise rounded up to one digit (rounded to the nearest,
    5.007e-12 became 5e-12, itself refused)."""
    e = 10.0 ** math.floor(math.log10(noise))
    allowed = math.ceil(noise / e * (1 - 1e-12)) * e
    return ConvergenceError(
        f"fold near {p:.10g}: round-off in the discrete equations leaves it uncertain by "
        f"{noise:.1e} > fold_tol = {fold_tol:g} (a thin or stiff shell); ask for a "
        f"tolerance >= {allowed:.0e}", round_off=True)


def climb(coarse, first, current, advance, *, options: ContinuationOptions, index: int,
          t0: float, location_weight: float, **stats) -> Fold:
    """The refinement ladder from the fold ``current`` on the rung ``first``: the fold on
    each next rung (``advance(finer, current)``) until p changes by at most
    ``options.fold_tol`` on two consecutive rungs. The estimate of the finest fold is the
    larger of those two changes, at least the
    round-off (of a Newton solve stalled at its floor, ``stats["round_off"]`` of either
    rung, and the problem's own, ``bvp.round_off``), plus ``location_weight`` times the
    error in p its location left (``stats["location"]``); ConvergenceError where the
    round-off exceeds fold_tol, the degree cannot grow, or after ``max_refinements``."""
    solves, iterations = current.stats["solves"], current.stats["newton_iterations"]
    change = previous = math.nan
    moves = []          # the monitor's change per rung
    for k in range(1, options.max_refinements + 1):
        try:
            finer = current.system.refined()
        except ValueError as exc:
            raise ConvergenceError(
                f"fold near {current.p:.10g}: not converged to fold_tol = "
                f"{options.fold_tol:g} ({exc}; last change {change:.2e})") from None
        fine = advance(finer, current)
        solves += fine.stats["solves"]
        iterations += fine.stats["newton_iterations"]
        previous, change = change, abs(fine.p - current.p)
        moves.append(abs(fine.monitor - current.monitor))
        # two consecutive changes within the tolerance, the estimate the larger: where the
        # error oscillates in sign with the degree, one rung can sit near a zero crossing
        # and a single change understate the error 20x (a thick deep plane-strain cap,
        # h = 0.12, Theta = 1.96: fold errors 6.7e-12, 1.8e-11, -3.6e-12 at N = 40, 44,
        # 48; the change 40 -> 44 was 1.1e-11)
        if k >= 2 and max(change, previous) <= options.fold_tol:
            change = max(change, previous)
            # round-off leaves p uncertain by the last update of a Newton solve stalled at
            # its floor, and by the problem's own round-off scatter where it states one (a
            # change between rungs sees neither): the estimate includes both, and more than
            # fold_tol is an error, not a result that misses its tolerance
            noise = max(current.stats["round_off"], fine.stats["round_off"],
                        _scatter(fine.system, fine.p))
            if noise > options.fold_tol:
                raise _below_round_off(fine.p, noise, options.fold_tol)
            estimate = max(change, noise) + location_weight * fine.stats["location"]
            return replace(fine, monitor_error=max(moves[-2:]), previous=current) \
                .with_estimate(
                estimate, index=index,
                stats=dict(coarse=coarse.describe(), first=first.describe(), refinements=k,
                           resolution=finer.describe(), solves=solves,
                           newton_iterations=iterations, error_estimate=estimate,
                           round_off=noise, curvature=fine.stats["curvature"],
                           wall_time=time.perf_counter() - t0, **stats))
        current = fine
    raise ConvergenceError(f"fold near {current.p:.10g}: not converged to fold_tol = "
                           f"{options.fold_tol:g} after {options.max_refinements} refinements "
                           f"(last change {change:.2e})")


def fold_sensitivity(fold) -> dict:
    """d p_fold / dx for every scene quantity x of the fold's discrete system
    (``system.parameter_derivatives``: dR/dx and dm/dx), exact to round-off.

    Along the branch parametrised by the monitor m, p = P(m, x), and the fold value is
    p* (x) = P(m*(x), x) with dP/dm = 0 at m* (an envelope): dp*/dx = dP/dx at fixed m, which
    solves the bordered system of the monitor-prescribed Newton,

        [[dR/dU, dR/dp], [dm/dU, 0]] [dU/dx; dP/dx] = -[dR/dx; dm/dx],

    nonsingular at a simple fold (there dR/dU is singular, the bordered matrix is not).
    Equivalently dp*/dx = -psi . dR/dx / psi . dR/dp with psi the left null vector of dR/dU.
    """
    system = fold.system
    if not implements(system, SecondOrder):
        raise ValueError(f"fold derivatives need a discretisation that offers them (the "
                         f"spectral method), got {system.describe()}")
    R, J, Rp = system.evaluate(fold.U, fold.p)
    _, gm = system.monitor(fold.U)
    factor = bordered_lu(J, Rp, gm, 0.0)
    return {x: float(-factor.solve(np.append(dR, dm))[-1])
            for x, (dR, dm) in system.parameter_derivatives(fold.U, fold.p).items()}
