"""The first instability along an axisymmetric branch: the axisymmetric fold or a bifurcation
into n circumferential waves, whichever comes first (:mod:`shellbvp.harmonics`).

Along the branch from its first point, the lowest eigenvalue of the second variation is
computed per harmonic n at every point. Harmonics are scanned from 0 to a cutoff that is
checked, not assumed: at least ``N_SCAN``, and beyond it until the lowest eigenvalue has
increased with n over the last ``RISING`` harmonics (bending stiffness grows like n^4, so
the eigenvalue is eventually increasing in n); the cutoff and that reason are part of the
result. The first point where an eigenvalue is negative brackets the instability:

* n = 0 first: the axisymmetric fold (a fold in the load is a zero of the n = 0 second
  variation); its value is the branch's refined fold.
* n = 0 first with no fold of the branch there: a branch point within the axisymmetric
  class (a pitchfork of a symmetric state: a flat plate under edge compression), kind
  ``"bifurcation"`` with n = 0, located as the root of a minimally augmented test function
  of the branch's own discrete system, its error the change on the method's finer rungs
  (:mod:`shellbvp.continuation.branch_points`).
* n >= 1 first, or together with n = 0 in one bracket: a bifurcation. With n = 0 in the
  bracket too (a short cylinder between mirror planes in axial compression buckles
  axisymmetrically just before n = 1), n = 0's eigenvalue is one more candidate located as
  below; where it comes first, it is the branch point above. The parameter value is the
  root of the lowest eigenvalue mu_n(p), found by Brent's method on equilibria solved at
  intermediate p with the branch's own method (the bracket is narrowed to the fold's when
  the fold lies inside it). Its error estimate is the change of that root when the
  perturbation degree is raised by ``DEGREE_STEP`` and both degrees' eigenvalue round-off
  (``_degree_error``), plus the change when the state is solved on the method's next finer
  discretisation (``_base_error``) and when it is solved afresh from the bracket's end
  (``_state_error``), plus the root's own tolerance; where it exceeds ``UNRESOLVED`` of the
  bracket, ``note`` says so (it is the error estimate).

A bracketed instability is always answered. The states inside a bracket are solved on the
branch's own discretisation, from the nearest state known along its exact tangent; where
Newton stalls at round-off (next to an axisymmetric bifurcation at the same load the
Jacobian at prescribed p is nearly singular) the state is accepted at ``STATE_TOL`` of the
root's tolerance, and a state off the branch's Hermite interpolant (converged on a crossing
branch) ends the search. A search that ends so is narrowed from outside the neighbourhood
where the solves fail (:mod:`shellbvp.continuation.squeeze`) and answers with the narrowest
interval over which the eigenvalue changed sign, its linear root, and the interval's width
as the error estimate (``note`` says so).

Clusters: where several harmonics cross within ``NEARBY_FRACTION`` (1 %) of a bifurcation's
load, ``nearby`` lists them (at most ``NEARBY_COUNT``, the critical one first; see
:class:`Instability`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from .errors import ConvergenceError
from .harmonics import DEGREE, N_MAX, HarmonicSpectrum, modes
from .results import Branch, equilibrium_from

__all__ = ["Instability", "first_instability", "modes_along", "N_SCAN", "RISING"]

#: harmonics always scanned: 0..N_SCAN
N_SCAN = 20
#: the cutoff is where the lowest eigenvalue has risen with n over this many harmonics
RISING = 3
#: degree increase of the error estimate
DEGREE_STEP = 16
#: a located root whose degree error exceeds this fraction of its bracket is flagged (note)
UNRESOLVED = 0.25
#: an equilibrium inside the bracket that does not converge to the continuation's Newton
#: tolerance is accepted at this fraction of the root's relative tolerance (_parameter_solver)
STATE_TOL = 0.1
#: a state solved inside a bracket farther than this many times the bracket's interpolation
#: error scale from the branch's interpolant lies on another branch (_hermite)
OFF_BRANCH = 100.0
#: a root's error estimate takes the eigenvalue's slope between evaluations at least this
#: fraction of |p| from the root (_slope_at)
SLOPE_SPAN = 1e-4
#: "nearby": the harmonics whose eigenvalue crosses zero within this fraction of
#: |p| of a bifurcation's p (Instability.nearby) ...
NEARBY_FRACTION = 0.01
#: ... at most this many, the critical one included
NEARBY_COUNT = 5


@dataclass(frozen=True)
class Instability:
    """The first instability of an axisymmetric branch.

    Attributes:
        kind: ``"fold"`` (the axisymmetric fold comes first), ``"bifurcation"`` (a
            non-axisymmetric mode, n >= 1, loses stability first, or an axisymmetric one,
            n = 0, with no fold: a branch point) or ``"none"`` (neither
            up to ``p``, the last point checked: the branch's end, or the last point whose
            second variation could be evaluated; ``stop`` says which and why).
        n: the harmonic (0 for a fold or an axisymmetric bifurcation; -1 for none).
        p: the parameter value (the scene's parameter, in its units unless a scene converts
            it, see ``parameter``); w: the observable there (R0).
        error_estimate: of p (module docstring).
        parameter: the name of p.
        mode: the critical mode (:class:`shellbvp.harmonics.HarmonicSpectrum` at p) or None.
        cutoff: the highest harmonic scanned at the bracketing points; cutoff_reason: why
            it is enough.
        scan: per branch point up to the bracket, (p, w, lowest eigenvalue per n) rows.
        stop: the branch's own stop reason (kind ``"none"``).
        equilibrium: the axisymmetric equilibrium at p (a bifurcation: where the branch
            into n waves starts, :func:`shellbvp.follow_bifurcation`; located to its bracket
            only: the solved equilibrium nearest p), or None.
        note: "" for a root located to ``tol``; otherwise why the error estimate is larger
            (the root search stopped and p is the bracket's, or the perturbation degree
            moves the root by more than ``UNRESOLVED`` of the bracket).
        nearby: a bifurcation's cluster: ((n, p, error), ...) of the harmonics whose
            lowest eigenvalue crosses zero along the branch between p and p plus
            ``NEARBY_FRACTION`` (1 %) of |p| (or before p within the two roots' errors),
            the critical one first, then by increasing distance from p, at most
            ``NEARBY_COUNT`` (5) entries (the lowest crossings); each p located as the
            critical one (its error the same estimate; n = 0, an axisymmetric branch
            point, by its eigenvalue's root). Only the branch's points (up to its end or
            fold) are scanned for them. Several entries within the error of p: which is
            critical is not determined by the computation (a sphere under pressure: every
            n of one spherical wave number crosses at the same load). Empty for a fold and
            for none.
        branch_point: an axisymmetric bifurcation's (n = 0 without a fold)
            :class:`shellbvp.continuation.branch_points.BranchPoint`: the discrete state, its
            null vector and the bracket; None otherwise.
    """

    kind: str
    n: int
    p: float
    w: float
    error_estimate: float
    parameter: str
    mode: HarmonicSpectrum | None = field(repr=False, default=None)
    cutoff: int = N_SCAN
    cutoff_reason: str = field(repr=False, default="")
    scan: tuple = field(repr=False, default=())
    stop: str = field(repr=False, default="")
    equilibrium: object = field(repr=False, default=None, compare=False)
    branch_point: object = field(repr=False, default=None, compare=False)
    note: str = field(repr=False, default="")
    nearby: tuple = field(repr=False, default=())

    def __repr__(self) -> str:
        head = {"fold": "axisymmetric fold", "bifurcation": f"bifurcation into n = {self.n}",
                "none": "none before the branch's end"}[self.kind]
        return (f"Instability({head} at {self.parameter} = {self.p:.8g} +- "
                f"{self.error_estimate:.1e}, w = {self.w:.6g} R0, harmonics 0..{self.cutoff})")

    def scaled(self, factor: float, parameter: str) -> "Instability":
        """The same with p and its error divided by ``factor`` (a scene's unit)."""
        return replace(self, p=self.p / factor, error_estimate=self.error_estimate / factor,
                       parameter=parameter, nearby=tuple(
                           (n, p / factor, e / abs(factor)) for n, p, e in self.nearby))


def modes_along(branch: Branch, n=range(0, N_SCAN + 1), *, count: int = 1,
                degree: int | None = None) -> tuple:
    """The stability of every point of ``branch`` per circumferential harmonic: one
    :class:`shellbvp.harmonics.Modes` per point (:func:`shellbvp.modes`)."""
    if not isinstance(branch, Branch) or not branch.points:
        raise ValueError("branch must be a shellbvp.Branch with points")
    return tuple(modes(branch.equilibrium(i), n, count=count, degree=degree)
                 for i in range(len(branch.points)))


def _lowest(spectra) -> dict:
    return {sp.n: sp.lowest for sp in spectra}


def _scan_point(eq, degree, n_scan):
    """The lowest eigenvalue per harmonic at ``eq``, over 0..cutoff (module docstring)."""
    M = modes(eq, range(0, n_scan + 1), count=1, degree=degree)
    low = _lowest(M.spectra)
    n = n_scan
    while not _rising(low, n):
        if n >= N_MAX:
            raise ConvergenceError(f"the lowest eigenvalue does not rise with n up to n = "
                                   f"{N_MAX} at {eq.scene.quote(eq.p)}: no cutoff")
        extra = modes(eq, range(n + 1, min(n + 10, N_MAX) + 1), count=1, degree=degree)
        low.update(_lowest(extra.spectra))
        n = max(low)
    return low, n


def _rising(low: dict, n: int) -> bool:
    vals = [low[k] for k in range(n - RISING, n + 1)]
    return all(b > a for a, b in zip(vals, vals[1:])) and vals[-1] > min(low.values()) \
        and vals[-1] > 0


def first_instability(branch: Branch, *, degree: int | None = None, tol: float = 1e-6,
                      n_scan: int = N_SCAN, progress=None) -> Instability:
    """The first instability along ``branch`` (module docstring).

    Arguments:
        branch: an axisymmetric branch (:func:`shellbvp.follow` or a scene's ``branch``),
            followed from the state whose stability is in question.
        degree: Chebyshev degree of the perturbations (default ``DEGREE``).
        tol: relative tolerance of the located parameter value.
        n_scan: harmonics always scanned, 0..n_scan (>= RISING).
        progress: called as ``progress(checked, points)`` after each point's harmonics are
            checked (the scan stops at the first unstable point).

    Raises:
        ValueError: bad arguments (n_scan below RISING, tol outside (0, 1), an empty branch).
        ConvergenceError: no cutoff below N_MAX at the first point, or a bracket whose
            root search stopped before any sign change of the eigenvalue was known inside
            it (a bracket with one is answered: module docstring).
    """
    if not isinstance(branch, Branch) or not branch.points:
        raise ValueError("branch must be a shellbvp.Branch with points")
    if not (isinstance(n_scan, (int, np.integer)) and RISING <= n_scan <= N_MAX):
        raise ValueError(f"n_scan must be an integer in [{RISING}, {N_MAX}] (the cutoff "
                         f"cannot lie below the harmonics it is checked on), got {n_scan!r}")
    if not (isinstance(tol, (int, float)) and 0 < tol < 1):
        raise ValueError(f"tol must lie in (0, 1), got {tol!r}")
    degree = DEGREE if degree is None else degree
    name = branch.scene.parameter
    rows, prev, cutoff = [], None, n_scan
    last_scanned = None
    for i in range(len(branch.points)):
        eq = branch.equilibrium(i)
        try:
            low, cutoff = _scan_point(eq, degree, n_scan)
        except ConvergenceError as exc:
            if i == 0:
                raise
            # the branch's last points can lie at the edge of the admissible states (where
            # it stopped): nothing is claimed beyond the last point checked
            return Instability("none", -1, float(last_scanned.p), float(last_scanned.w),
                               math.nan, name, None, cutoff, _cutoff_reason(cutoff),
                               tuple(rows), f"{branch.stop}; the second variation could not "
                               f"be evaluated from {name} = {eq.p:.6g} on ({exc}): stable "
                               f"up to {name} = {last_scanned.p:.6g}, not checked beyond")
        last_scanned = eq
        if progress is not None:
            progress(i + 1, len(branch.points))
        rows.append((eq.p, eq.w, low))
        neg = {n: mu for n, mu in low.items() if mu < 0}
        if neg and i == 0:
            raise ValueError(f"the branch's first point ({name} = {eq.p:.6g}) is already "
                             f"unstable (n = {sorted(neg)}): follow it from a stable state")
        if neg:
            # harmonics past the previous point's cutoff: their eigenvalues there, so that
            # their crossings inside the bracket are seen (a long thin cylinder's cluster
            # lies around n = 28, past a cutoff of 20 before the bracket)
            missing = sorted(set(low) - set(prev))
            if missing:
                prev = {**prev, **_lowest(modes(branch.equilibrium(i - 1), missing,
                                                count=1, degree=degree).spectra)}
            found = _locate(branch, i, prev, low, degree, tol, cutoff, tuple(rows))
            if found.kind == "bifurcation":
                found = replace(found, nearby=_nearby(branch, i, found, prev, low, degree,
                                                      tol))
            return found
        prev = low
    last = branch.equilibrium(len(branch.points) - 1)
    return Instability("none", -1, float(last.p), float(last.w), math.nan, name, None, cutoff,
                       _cutoff_reason(cutoff), tuple(rows), branch.stop)


def _cutoff_reason(cutoff):
    return (f"harmonics 0..{cutoff} scanned at every point; the lowest eigenvalue is "
            f"positive and rises with n over n = {cutoff - RISING}..{cutoff}")


def _fold_in(branch, i):
    """The branch's fold between points i - 1 and i, if any."""
    for f in branch.folds:
        if f.index == i - 1:
            return f
    return None


def _locate(branch, i, low_prev, low, degree, tol, cutoff, rows) -> Instability:
    name = branch.scene.parameter
    fold = _fold_in(branch, i)
    eq_a = branch.equilibrium(i - 1)
    p_a, p_b = float(eq_a.p), float(branch.points[i].p)
    candidates = sorted((n for n, mu in low.items() if mu < 0 and n > 0),
                        key=lambda n: low[n])
    if fold is not None:
        # the bracket holds the fold: a bifurcation comes first only if already unstable there
        eq_f = fold.equilibrium
        low_f = _lowest(modes(eq_f, sorted(n for n in low if n > 0), count=1,
                              degree=degree).spectra)
        candidates = sorted((n for n, mu in low_f.items() if mu < 0), key=lambda n: low_f[n])
        p_b = float(fold.p)
        if not candidates:
            mode = modes(eq_f, [0], count=1, degree=degree)[0]
            return Instability("fold", 0, float(fold.p), float(fold.w),
                               float(fold.error_estimate), name, mode, cutoff,
                               _cutoff_reason(cutoff), rows, equilibrium=eq_f)
    elif 0 in low and low[0] < 0:
        if not candidates:
            return _branch_point(branch, i, degree, tol, cutoff, rows)
        # an axisymmetric branch point in the same bracket as n >= 1 crossings: its
        # eigenvalue's root is located like theirs, and where it comes first it is located
        # again on the branch's own system (_branch_point: the state and null vector the
        # branch switching needs)
        candidates.append(0)
    # the bifurcation whose eigenvalue crosses zero first: locate each candidate's root, in
    # p, or where the bracket ends at the fold in the monitor m (p is a coordinate of the
    # branch up to the fold, but a solve at prescribed p next to it is ill-conditioned: two
    # solutions a distance ~ sqrt(p_fold - p) apart; one at prescribed m is not)
    from scipy.optimize import brentq

    best = None
    eq_b = fold.equilibrium if fold is not None else branch.equilibrium(i)
    at = _monitor_solver(branch, i, fold, eq_a) if fold is not None else _parameter_solver(
        branch, i, tol)
    x_a, x_b = (branch.points[i - 1].monitor, fold.monitor) if fold is not None else (p_a, p_b)

    # refine first the harmonic whose crossing the end values put earliest; another one
    # is refined only where its eigenvalue is already negative at that root (it crosses
    # before it): one eigenvalue at a solved equilibrium instead of a root search
    ends = low_f if fold is not None else low
    def linear_crossing(n):
        a, b = low_prev.get(n, math.nan), ends[n]
        return a / (a - b) if math.isfinite(a) and a > 0 > b else 1.0

    candidates = sorted(candidates, key=linear_crossing)
    notes, bracket_only = {}, set()
    for n in candidates:
        if best is not None:
            # another harmonic comes first only where its eigenvalue is negative at the
            # root by more than the root's error allows: within it, it is a nearby one
            if modes(best[3], [n], count=1, degree=degree)[n].lowest \
                    >= -abs(best[5]) * best[2]:
                continue
            x_b, p_b = best[4], best[1]
        # every evaluation (x, p, mu, equilibrium), the bracket's ends from the scan
        evals = [(x_a, p_a, low_prev.get(n, math.nan), eq_a), (x_b, p_b, ends[n], eq_b)] \
            if best is None else [(x_a, p_a, low_prev.get(n, math.nan), eq_a)]

        def mu(x, deg=degree):
            eq = at(x)
            val = modes(eq, [n], count=1, degree=deg)[n].lowest
            evals.append((x, float(eq.p), val, eq))
            return val

        try:
            scale = max(abs(x_a), abs(x_b), 1e-12)
            if best is not None:
                mu(x_b)
            root = brentq(mu, x_a, x_b, xtol=tol * scale, rtol=1e-14, maxiter=100)
            # the perturbation degree's error: mu at the root on a finer degree, over the
            # slope of mu in p (_slope_at)
            eq_root = at(root)
            p_root = float(eq_root.p)
            slope = _slope_at(sorted((e[1], e[2]) for e in evals if math.isfinite(e[2])),
                              p_root)
            err, note = _root_error(branch, i, at, eq_root, n, degree, slope, tol)
            if note:
                notes[n] = note
            got = (n, p_root, err, eq_root, root, slope)
        except (ValueError, RuntimeError, ConvergenceError) as exc:
            _squeeze(mu, evals, tol * scale)
            got = _bracketed(n, evals, exc)
            if got is None:
                raise ConvergenceError(f"the bifurcation into n = {n} between {name} = "
                                       f"{p_a:.10g} and {p_b:.10g} was not located and no "
                                       f"sign change of its eigenvalue is known: {exc}") \
                    from exc
            bracket_only.add(n)
            notes[n] = (f"located to its bracket only (the root search stopped: "
                        f"{str(exc)[:200]}): the bracket's width is the error estimate")
        if best is None or _first(got, n in bracket_only, best, best[0] in bracket_only, p_a, p_b):
            best = got
    n, p, err, eq = best[:4]
    if n == 0:
        try:
            found = _branch_point(branch, i, degree, tol, cutoff, rows)
        except ConvergenceError as exc:
            # the branch's own system shows no branch point in the bracket (its test
            # function keeps its sign): the eigenvalue's root stands, with nothing to
            # switch branches from
            mode = modes(eq, [0], count=1, degree=degree)[0]
            return Instability(
                "bifurcation", 0, float(p), float(eq.w), float(err), name, mode, cutoff,
                _cutoff_reason(cutoff), rows, equilibrium=eq,
                note=(notes.get(0, "") + "; " if notes.get(0) else "") + "located by the "
                f"root of its eigenvalue (as n >= 1); not on the branch's own system "
                f"({str(exc)[:200]}): no branch point to follow the bifurcated branch from")
        if found.error_estimate <= err or 0 in bracket_only:
            return found
        # the branch's own system stopped on a bracket wider than the eigenvalue's root's
        # error (Newton at prescribed p stalls next to a branch point whose symmetry the
        # discretisation breaks): the root is the answer, the bracket's state the branch
        # point to switch from
        stall = found.branch_point.stats.get("stall", "")
        return replace(found, p=float(p), w=float(eq.w), error_estimate=float(err),
                       equilibrium=eq, mode=modes(eq, [0], count=1, degree=degree)[0],
                       note=f"located by the root of its eigenvalue (as n >= 1); on the "
                       f"branch's own system only to a bracket of width "
                       f"{found.error_estimate:.3g} ({stall[:160]}), whose state "
                       f"branch_point holds")
    note = notes.get(n, "")
    if not note and err > UNRESOLVED * max(abs(p_b - p_a), abs(p) * tol):
        note = (f"not resolved by the discretisation: raising the perturbation degree "
                f"from {degree} to {degree + DEGREE_STEP} and solving the state on the "
                f"method's next finer discretisation move the root by ~{err:.3g} (more than "
                f"{UNRESOLVED:g} of the bracket {p_a:.6g} .. {p_b:.6g}), which is its error "
                f"estimate")
    mode = modes(eq, [n], count=1, degree=degree)[n]
    return Instability("bifurcation", n, float(p), float(eq.w), float(err), name, mode,
                       cutoff, _cutoff_reason(cutoff), rows, equilibrium=eq, note=note)


def _branch_point(branch, i, degree, tol, cutoff, rows) -> Instability:
    """n = 0 negative with no fold between points i - 1 and i: a branch point of the
    axisymmetric branch (a pitchfork of a symmetric state), located on the branch's
    discretisation with its error estimate (:mod:`shellbvp.continuation.branch_points`)."""
    from .continuation.branch_points import branch_point_on

    bp = branch_point_on(branch, i, tol=tol)
    eq = bp.equilibrium
    mode = modes(eq, [0], count=1, degree=degree)[0]
    return Instability("bifurcation", 0, float(bp.p), float(bp.w), float(bp.error_estimate),
                       branch.scene.parameter, mode, cutoff, _cutoff_reason(cutoff), rows,
                       equilibrium=eq, branch_point=bp)


def _nearby(branch, i, found, low_prev, low, degree, tol) -> tuple:
    """Instability.nearby of the bifurcation ``found`` bracketed by points i - 1 and i
    (their lowest eigenvalues per n: low_prev, low): the branch's points after i are scanned
    (harmonics up to the bracket's cutoff) until p passes the window, and each harmonic
    whose eigenvalue has turned negative by then and is negative at the window's edge
    (a state solved there) is located between the two points where it changes sign: those
    crossed already at p first, then in the order of their linear crossings between p and
    the edge, at most ``NEARBY_COUNT`` + 2 root searches; the ``NEARBY_COUNT`` - 1 lowest
    inside the window are kept."""
    from scipy.optimize import brentq

    p_c, err_c = found.p, found.error_estimate
    sign = 1.0 if branch.points[i].p >= branch.points[i - 1].p else -1.0
    edge = p_c + sign * NEARBY_FRACTION * abs(p_c)
    # a harmonic located before p within the two roots' errors is one of the cluster: it
    # was not taken for the critical one (_locate) because it does not cross first by
    # more than they allow (a degenerate multiplet, e.g. a sphere's, lies within them)
    def inside(p, e):
        return -(err_c + e) <= sign * (p - p_c) <= NEARBY_FRACTION * abs(p_c)

    fold = _fold_in(branch, i)
    table = [(float(branch.points[i - 1].p), low_prev)]
    if fold is None:
        table.append((float(branch.points[i].p), low))
        j = i
        while sign * (table[-1][0] - edge) < 0 and j + 1 < len(branch.points) \
                and _fold_in(branch, j + 1) is None:
            j += 1
            try:
                table.append((float(branch.points[j].p), _lowest(modes(
                    branch.equilibrium(j), sorted(low), count=1, degree=degree).spectra)))
            except ConvergenceError:
                break
    # per harmonic: the first sign change in the table, and its linear crossing
    cross = {}
    for n in low:
        if n == found.n:
            continue
        for k in range(1, len(table)):
            a, b = table[k - 1][1].get(n, math.nan), table[k][1].get(n, math.nan)
            if a > 0 >= b:
                pa, pb = table[k - 1][0], table[k][0]
                cross[n] = (pa + a / (a - b) * (pb - pa), i - 1 + k)
                break
    # which of them cross inside the window, and in what order: their eigenvalues at p and
    # at the window's edge (a state solved there), each linear between the two (the
    # eigenvalues of different n differ in scale and curvature: on a long thin cylinder
    # n = 3 to 8 lay closest to zero at p and crossed 7 % past it, n = 29 crossed 7e-4 past
    # it, and a long step's linear crossings put it 5 % past)
    at_c = _lowest(modes(found.equilibrium, sorted(cross), count=1, degree=degree).spectra) \
        if cross else {}
    at_e = _at_edge(branch, i, table, edge, sorted(n for n in cross if at_c[n] > 0), degree,
                    tol)
    for n in list(cross):
        if at_c[n] > 0 and n in at_e:
            if at_e[n] > 0:
                del cross[n]                    # crosses past the window
            else:
                cross[n] = (p_c + at_c[n] / (at_c[n] - at_e[n]) * (edge - p_c), cross[n][1])
    out = [(int(found.n), float(p_c), float(err_c))]
    solvers, searches = {}, 0
    order = sorted(cross.items(), key=lambda kv: (0, at_c[kv[0]]) if at_c[kv[0]] <= 0
                   else (1, sign * kv[1][0]))
    for n, (guess, j) in order:
        if searches >= NEARBY_COUNT + 2:
            break
        if at_c[n] > 0 and sign * (guess - edge) > NEARBY_FRACTION * abs(p_c):
            continue                            # crosses well past the window
        if at_c[n] <= 0:
            # crossed already at p (within its error): between the bracket's points
            j = i
        searches += 1
        if j not in solvers:
            solvers[j] = _parameter_solver(branch, j, tol)
        at = solvers[j]
        evals = [(float(branch.points[j - 1].p), float(branch.points[j - 1].p),
                  table[j - i][1][n], None), (float(branch.points[j].p),
                  float(branch.points[j].p), table[j - i + 1][1][n], None)]

        def mu(x, n=n, evals=evals):
            eq = at(x)
            val = modes(eq, [n], count=1, degree=degree)[n].lowest
            evals.append((x, float(eq.p), val, eq))
            return val

        try:
            x_a, x_b = evals[0][0], evals[1][0]
            root = brentq(mu, x_a, x_b, xtol=tol * max(abs(x_a), abs(x_b)), rtol=1e-14,
                          maxiter=100)
            eq = at(root)
            slope = _slope_at(sorted((e[1], e[2]) for e in evals), root)
            p, err = float(eq.p), _root_error(branch, j, at, eq, n, degree, slope, tol)[0]
        except (ValueError, RuntimeError, ConvergenceError) as exc:
            _squeeze(mu, evals, tol * max(abs(x_a), abs(x_b)))
            got = _bracketed(n, evals, exc)
            if got is None:
                continue
            p, err = got[1], got[2]
        if inside(p, err):
            out.append((int(n), p, float(err)))
    # the lowest crossings: the order above is a linear guess, so every searched one that
    # lies inside is kept until here (a short cylinder's n = 1 came after n = 2 to 5)
    return (out[0],) + tuple(sorted(out[1:], key=lambda e: sign * (e[1] - p_c))
                             [:NEARBY_COUNT - 1])


def _at_edge(branch, i, table, edge, ns, degree, tol) -> dict:
    """{n: lowest eigenvalue} of harmonics ``ns`` at the state at p = ``edge`` (the end of
    a bifurcation's nearby window), solved between the branch points that bracket it; {}
    where no branch interval from i on holds it or the solve fails."""
    if not ns:
        return {}
    for j in range(i, i + len(table) - 1):
        a, b = float(branch.points[j - 1].p), float(branch.points[j].p)
        if min(a, b) <= edge <= max(a, b):
            try:
                eq = _parameter_solver(branch, j, tol)(float(edge))
                return _lowest(modes(eq, ns, count=1, degree=degree).spectra)
            except ConvergenceError:
                return {}
    return {}


def _slope_at(log, root) -> float:
    """The slope of an eigenvalue in p at ``root``, for the root's error estimate, from the
    evaluations ``log`` [(p, mu)] sorted by p: the secant between the nearest evaluation on
    either side that lies at least ``SLOPE_SPAN`` of |root| from it (the farthest on that
    side where none does). The last evaluations of a root search to a tight tolerance lie
    too close for their eigenvalues' round-off: at tol 1e-9 on a sphere under pressure
    their secant was 10 times the eigenvalue's slope, and the root's error as much too
    small (its perturbation-degree term, the change on a finer degree over the slope)."""
    span = SLOPE_SPAN * abs(root)
    below = [q for q in log if q[0] <= root]
    above = [q for q in log if q[0] > root]
    lo = max((q for q in below if root - q[0] >= span), default=below[0]) if below \
        else log[0]
    hi = min((q for q in above if q[0] - root >= span), default=above[-1]) if above \
        else log[-1]
    return (hi[1] - lo[1]) / (hi[0] - lo[0]) if hi[0] != lo[0] else math.inf


def _root_error(branch, i, at, eq, n, degree, slope, tol) -> tuple:
    """(error estimate, note) of the root of harmonic n's eigenvalue located at ``eq``
    between the branch's points i - 1 and i (``at`` the root search's solver, ``slope`` the
    eigenvalue's in p): the perturbation degree's error (_degree_error), the state's
    discretisation error (_base_error), its determination (_state_error) and the root's own
    tolerance. The note says which term could not be evaluated."""
    own = modes(eq, [n], count=1, degree=degree)[n]         # the spectrum at the root, once
    base = _base_error(branch, at, eq, n, degree, slope, tol, own.lowest)
    state = _state_error(branch, i, at, eq, n, degree, slope, tol, own.lowest)
    missing = [what for what, v in (("discretisation error (its solve on the next finer "
                                     "discretisation failed)", base),
                                    ("determination (a solve from the bracket's end "
                                     "failed)", state)) if not math.isfinite(v)]
    note = ("the axisymmetric state's " + " and ".join(missing) + " is not in the error "
            "estimate") if missing else ""
    err = _degree_error(eq, n, degree, slope, own) + sum(v for v in (base, state)
                                                    if math.isfinite(v))
    return err + tol * abs(float(eq.p)), note


def _state_error(branch, i, at, eq, n, degree, slope, tol, mu) -> float:
    """The root's error from how well the state at it is determined: the eigenvalue's
    change when that state is solved afresh from the bracket's nearer end (not from the root
    search's chain of solves), over its slope in p. Where the axisymmetric class bifurcates
    at (nearly) the same load (a sphere under pressure: the axisymmetric mode of the
    critical spherical wave number) the Jacobian at prescribed p is nearly singular, Newton
    stalls at round-off amplified along its null vector, and the states of a chain of
    solves drift along it: on the hemisphere at R/t = 100 with collocation, n = 12's root
    moved 3.6e-8 (its other terms 8e-9), where a fresh solve moved the eigenvalue by that
    much. ``mu``: the eigenvalue at ``eq``. 0 where ``at`` prescribes the monitor (next to
    a fold: the fold's own estimate), nan where the fresh solve fails."""
    if at.prescribes != "parameter" or id(eq) not in at.states:
        return 0.0
    try:
        fresh = _parameter_solver(branch, i, tol)(float(eq.p))
        mu_f = modes(fresh, [n], count=1, degree=degree)[n].lowest
    except (ConvergenceError, ValueError):
        return math.nan
    return abs(mu_f - mu) / abs(slope) if slope else math.nan


def _degree_error(eq, n, degree, slope, own) -> float:
    """The root's error from the perturbation degree: the eigenvalue at the root on the
    degree ``DEGREE_STEP`` finer, plus both degrees' round-off floors
    (:attr:`shellbvp.harmonics.HarmonicSpectrum.roundoff`), over its slope in p. The floors
    matter for high harmonics of thin shells, whose eigenvalues converge in the degree to
    their round-off and then wander by it: at a sphere's multiplet (tol 1e-9) the change
    alone left the roots of n = 10, 14 and 18 up to 1.5 times their summed estimates
    apart, where the sphere's symmetry puts them at one load. ``own``: the spectrum at
    ``eq`` on ``degree``."""
    fine = modes(eq, [n], count=1, degree=degree + DEGREE_STEP)[n]
    return (abs(fine.lowest) + fine.roundoff + own.roundoff) / abs(slope)


def _base_error(branch, at, eq, n, degree, slope, tol, mu) -> float:
    """The root's error from the axisymmetric state's discretisation: the change of the
    eigenvalue when the state at the root is solved again on the method's next finer
    discretisation (p held, or the monitor where ``at`` prescribes it: next to a fold),
    over its slope in p. Without it, two methods' roots of the hemisphere under pressure at
    R/t = 100 lay 8e-7 apart with error estimates of 5e-9 (the degree's and the root's
    alone). ``mu``: the eigenvalue at ``eq``. 0 for a state solved elsewhere (the fold: its
    own estimate), nan where the finer solve fails."""
    from .continuation import ContinuationOptions
    from .continuation.newton import newton

    if id(eq) not in at.states:
        return 0.0
    U, p = at.states[id(eq)]
    system = branch.system
    try:
        fine = system.refined()
        Uf = system.transfer(U, p, fine)
        alpha, beta, c = (1.0, 0.0, system.monitor(U)[0]) if at.prescribes == "monitor" \
            else (0.0, 1.0, p)
        for newton_tol in (ContinuationOptions().newton_tol, STATE_TOL * tol):
            res = newton(fine, Uf, p, alpha, beta, c, tol=newton_tol, maxiter=40,
                         fail_fast=False)
            if res.ok:
                break
        else:
            return math.nan
        eq_f = equilibrium_from(fine, res.U, res.p)
        mu_f = modes(eq_f, [n], count=1, degree=degree)[n].lowest
    except (ConvergenceError, ValueError, NotImplementedError):
        return math.nan
    # p moves with the monitor held: the eigenvalue's change includes that move's
    return abs(mu_f - mu + slope * (p - res.p)) / abs(slope) if slope else math.nan


def _squeeze(mu, evals, floor) -> None:
    """A stopped root search's bracket narrowed from outside the neighbourhood where the
    state's solves fail (:func:`shellbvp.continuation.squeeze.squeeze`): ``mu`` logs its
    evaluations into ``evals`` [(x, p, mu, eq)]."""
    from .continuation.squeeze import squeeze

    squeeze(mu, [(e[0], e[2]) for e in evals if math.isfinite(e[2])], floor=floor,
            errors=(ValueError, RuntimeError, ConvergenceError))


def _bracketed(n, evals, exc):
    """The answer from the evaluations of a root search that stopped (``exc``): the
    narrowest interval over which the eigenvalue changes sign, its root by linear
    interpolation, the interval's width as the error estimate, the equilibrium at the end
    nearer that root; None where no evaluation pair changes sign."""
    from .continuation.squeeze import narrowest_sign_change

    pair = narrowest_sign_change([(e[1], e[2], e) for e in evals if math.isfinite(e[2])])
    if pair is None:
        return None
    a, b = pair[0][2], pair[1][2]
    t = a[2] / (a[2] - b[2]) if a[2] != b[2] else 0.5
    p = a[1] + t * (b[1] - a[1])
    near = a if t <= 0.5 else b
    slope = (b[2] - a[2]) / (b[1] - a[1]) if b[1] != a[1] else math.inf
    return (n, p, abs(b[1] - a[1]), near[3], near[0], slope)


def _parameter_solver(branch, i, tol):
    """The branch's equilibrium at a prescribed parameter value between points i - 1 and i,
    on the branch's own discretisation, each solved by Newton from the nearest point already
    known, predicted along its exact tangent (a bracket can be a long continuation step: one
    natural-parameter jump across it may not converge).

    A solve that does not converge to the continuation's tolerance is tried again to
    ``STATE_TOL`` times the root's relative tolerance ``tol``: next to an axisymmetric
    bifurcation at (nearly) the same load (a sphere under pressure: n = 0 buckles with the
    n >= 1 harmonics of one spherical wave number) the Jacobian at prescribed p is nearly
    singular, Newton converges only linearly and its updates stall at round-off amplified by
    the condition number (~2e-8 relative at R/t = 100, 1e-5 from that load), above the
    continuation's tolerance. A state that good moves the eigenvalue's root by about that
    fraction of p, below the root's own tolerance."""
    from .continuation import ContinuationOptions
    from .continuation.arclength import point_at_parameter

    known = [branch.points[i - 1], branch.points[i]]
    solved = {float(q.p): branch.equilibrium(k) for q, k in zip(known, (i - 1, i))}
    tight = ContinuationOptions().newton_tol
    on_branch = _hermite(*known)

    def at(p):
        if p in solved:
            return solved[p]
        near = min(known, key=lambda q: abs(q.p - p))
        dpdt = near.tangent[1]
        U = near.U + (p - near.p) * near.dU / dpdt if dpdt != 0 else near.U
        try:
            q = point_at_parameter(branch.system, U, p, p, tol=tight)
        except ConvergenceError:
            q = point_at_parameter(branch.system, U, p, p, tol=STATE_TOL * tol, maxiter=40)
        on_branch(q.U, p, max(tight, STATE_TOL * tol))
        known.append(q)
        solved[p] = equilibrium_from(branch.system, q.U, q.p, stats=branch.stats)
        at.states[id(solved[p])] = (q.U, q.p)
        return solved[p]
    at.states = {id(solved[float(q.p)]): (q.U, q.p) for q in known}
    at.prescribes = "parameter"
    return at


def _hermite(a, b):
    """A check that a state solved at p between the branch points a and b lies on their
    branch: its distance from their cubic Hermite interpolant in p (values and exact
    tangents) is at most ``OFF_BRANCH`` times the interpolant's own scale of error (the
    trapezoidal defect of the bracket, O(dp^3)) or the Newton tolerance. Where the branch
    crosses another one inside the bracket (an axisymmetric bifurcation at the same load), a
    solve at prescribed p next to the crossing can converge on the other branch, whose
    eigenvalues are not this branch's: a ConvergenceError then, which ends the root search
    with the bracket found so far."""
    dp = b.p - a.p
    da, db = (q.dU / q.tangent[1] * dp for q in (a, b))
    size = 1.0 + max(float(np.abs(a.U).max()), float(np.abs(b.U).max()))
    defect = float(np.abs(b.U - a.U - (da + db) / 2).max()) / size

    def check(U, p, newton_tol):
        t = (p - a.p) / dp
        h00, h10, h01, h11 = (2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t,
                              -2 * t**3 + 3 * t**2, t**3 - t**2)
        UH = h00 * a.U + h10 * da + h01 * b.U + h11 * db
        off = float(np.abs(U - UH).max()) / size
        if off > OFF_BRANCH * max(defect, newton_tol):
            raise ConvergenceError(f"the state solved at p = {p:.10g} lies off the branch "
                                   f"({off:.1e} relative from its interpolant between "
                                   f"p = {a.p:.10g} and {b.p:.10g}, whose own error scale is "
                                   f"{defect:.1e}): another branch crosses it there")
    return check


def _monitor_solver(branch, i, fold, eq_a):
    """The branch's equilibrium at a prescribed monitor value between point i - 1 (its
    equilibrium eq_a) and the fold after it: bordered Newton with m fixed (well-posed
    through the fold) on the branch's discretisation, predicted along the exact tangent of
    the nearest point solved (the fold itself is its own equilibrium, located on a
    discretisation of its own)."""
    from .continuation import ContinuationOptions, point_at_monitor
    from .results import equilibrium_from

    known = [branch.points[i - 1]]                  # the points solved: the predictors
    solved = {known[0].monitor: eq_a, fold.monitor: fold.equilibrium}
    tol = ContinuationOptions().newton_tol

    def at(m):
        if m not in solved:
            near = min(known, key=lambda q: abs(q.monitor - m))
            q = point_at_monitor(branch.system, *near.predicted(m), m, tol=tol)
            known.append(q)
            solved[m] = equilibrium_from(branch.system, q.U, q.p, stats=branch.stats)
            at.states[id(solved[m])] = (q.U, q.p)
        return solved[m]
    at.states = {id(eq_a): (known[0].U, known[0].p)}
    at.prescribes = "monitor"
    return at


def _first(got, got_bracket, best, best_bracket, p_a, p_b) -> bool:
    """Whether the root ``got`` replaces ``best`` as the first crossing: it comes before
    it, except that a root known to its bracket only (``*_bracket``: p the bracket's
    interpolated root, its width the error) does not replace a located root inside that
    bracket, and is replaced by one."""
    if got_bracket and not best_bracket and abs(best[1] - got[1]) <= got[2]:
        return False
    if best_bracket and not got_bracket and abs(got[1] - best[1]) <= best[2]:
        return True
    return _before(got[1], best[1], p_a, p_b)


def _before(p, q, p_a, p_b) -> bool:
    """Whether p comes before q going from p_a to p_b."""
    return (p - q) * (p_b - p_a) < 0
