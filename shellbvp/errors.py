"""Failure vocabulary: the exception every solver raises when it does not converge.

A solver never returns an unconverged answer as if it were good: it raises
:class:`ConvergenceError` (or, with ``throw=False``, returns a result whose ``success`` is
False and whose ``message`` says what failed and what to change).
"""

from __future__ import annotations

__all__ = ["ConvergenceError"]


class ConvergenceError(RuntimeError):
    """A solver did not converge. The message says where (parameter value, position on the
    meridian) and what to try (a smaller step, a finer discretisation, a closer guess).

    ``partial``: what was converged before the failure, when there is such a thing (a
    continuation that stalls carries its converged points and fold brackets), else None.
    ``round_off``: the cause is round-off in the discrete equations, not a bad start or
    step (a stiffer material or thinner shell than double precision resolves).
    """

    def __init__(self, message, partial=None, round_off=False):
        super().__init__(message)
        self.partial = partial
        self.round_off = round_off
