"""What a BVP hands a nodal discretisation: the right-hand side at nodes with its Jacobians
(:class:`Nodal`), the boundary rows and monitor with it (:class:`Collocated`), and the warm
start of the inner constitutive Newton carried from one evaluation to the next (:class:`Hint`).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

__all__ = ["Nodal", "Collocated", "Hint", "flat_nodes", "carried_roots"]


class Collocated(NamedTuple):
    """What a collocation method needs at one iterate: the :class:`Nodal` right-hand side,
    the boundary residual with its Jacobians (r, d/dya, d/dyb, d/dp) and the monitor with
    its gradients (m, dm/dya, dm/dyb)."""

    nodal: "Nodal"
    boundary: tuple
    monitor: tuple


class Nodal(NamedTuple):
    """The right-hand side at nodes of every piece: f (P, 6, m), df/dy (P, 6, 6, m),
    df/dp (P, 6, m) and ``hint``, an opaque warm start for the next evaluation."""

    f: np.ndarray
    J: np.ndarray
    fp: np.ndarray
    hint: object = None


class Hint(NamedTuple):
    """Warm start of the inner Newton: the nodal states y (nodes, 6) and parameter p of an
    evaluation, its roots q (nodes, 2) and their derivatives dq = [dq/dy, dq/dp] (nodes, 2, 7)."""

    y: np.ndarray
    p: float
    q: np.ndarray
    dq: np.ndarray


def flat_nodes(Y):
    """Y (P, 6, m) -> (P m, 6), nodes piece-major: a new array, never a view of Y. (For one
    piece the reshape alone is a view of the unknowns, and a :class:`Hint` holding it
    followed an outer Newton's in-place updates: its roots were then carried by the change
    in p alone, to 4x the outer update away from the new roots instead of O(update^2), and
    the inner Newton took ~2 more steps per evaluation.)"""
    return np.array(np.asarray(Y, dtype=float).transpose(0, 2, 1).reshape(-1, 6))


def carried_roots(hint, y, p):
    """The roots of ``hint`` carried to the nodal states y (nodes, 6) and parameter p along
    their implicit derivative dq = [dq/dy, dq/dp]: O(|change|^2) from the roots there."""
    dq = hint.dq
    return hint.q + (dq[:, :, :6] @ (y - hint.y)[:, :, None])[:, :, 0] \
        + dq[:, :, 6] * (p - hint.p)
