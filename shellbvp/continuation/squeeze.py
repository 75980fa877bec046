"""Narrowing a root's bracket where the solves stop short of the root.

Next to a branch point of the axisymmetric branch, a solve at prescribed p fails in a
neighbourhood of the branch point whenever the discretisation breaks the symmetry that makes
the branch point a pitchfork (the residual then has a component along the Jacobian's
near-null vector; a cylinder between mirror planes whose two ends are discretised
differently). A root search (Brent's method) whose iterate lands in that neighbourhood
stops with the bracket it had, which can be as wide as the continuation step it started
from. The solves still succeed outside the neighbourhood: :func:`squeeze` takes false
position steps until one fails, then evaluates the function toward the failed point from
either side at distances shrinking geometrically, each side until its first failure, so
that the narrowest sign change logged is about as wide as the neighbourhood (the answer's
error estimate, honestly).
"""

from __future__ import annotations

__all__ = ["squeeze", "narrowest_sign_change", "RATIO", "ROUNDS"]

#: probing toward a failed point from either end of the bracket: the distance to it
#: shrinks by this factor per probe
RATIO = 0.125
#: evaluations at most, the probes included
ROUNDS = 60


def narrowest_sign_change(samples):
    """(a, b), two samples adjacent in x with f changing sign (one zero counts, two do
    not), the narrowest such pair of ``samples`` [(x, f, ...)] (items may carry more after
    x and f); None where f keeps its sign."""
    pts = sorted(samples, key=lambda q: q[0])
    best = None
    for a, b in zip(pts, pts[1:]):
        if a[1] * b[1] <= 0 and (a[1] != 0 or b[1] != 0) \
                and (best is None or b[0] - a[0] < best[1][0] - best[0][0]):
            best = (a, b)
    return best


def squeeze(f, samples, *, floor: float, errors: tuple) -> None:
    """Narrow the narrowest sign change of ``samples`` [(x, f(x))] down to ``floor`` or to
    the neighbourhood where ``f`` raises one of ``errors``: false position steps (the
    bracket's midpoint where that step would lie within a sixteenth of its width from an
    end) until one fails; then, from either end of the bracket toward the failed point, at
    distances from it shrinking by ``RATIO``, until a probe fails on that side. ``f`` logs
    its own values (the caller reads the narrower bracket from its log); nothing is
    returned. At most ``ROUNDS`` evaluations."""
    log = list(samples)
    calls = 0
    while calls < ROUNDS:
        pair = narrowest_sign_change(log)
        if pair is None:
            return
        (a, fa), (b, fb) = pair
        if b - a <= floor or fa == 0 or fb == 0:
            return
        x = a + fa / (fa - fb) * (b - a)
        if not a + (b - a) / 16 < x < b - (b - a) / 16:
            x = 0.5 * (a + b)
        calls += 1
        try:
            log.append((x, f(x)))
            continue
        except errors:
            pass
        for end in (a, b):
            k = 1
            while calls < ROUNDS:
                y = x + (end - x) * RATIO ** k
                if abs(y - x) < floor:
                    break
                calls += 1
                try:
                    log.append((y, f(y)))
                except errors:
                    break
                k += 1
        return
