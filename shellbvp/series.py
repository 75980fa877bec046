"""Perturbation series of stationary points of the reduced energy (a derivation module).

Given a one-parameter family of principal states ``state(x, p)`` (x the unknown, p the
stimulus parameter) with x = 0 stationary at p = 0, the implicit-function theorem applied to
dW/dx (x(p), p) = 0 gives x(p) = c1 p + c2 p^2 + ...; the c_n are solved order by order
from the Taylor coefficients of dW/dx, exactly, with sympy. Used by the closed-sphere scene
(paper Section 5.3) to derive the expansions that the paper prints.
"""

from __future__ import annotations

import inspect
from typing import Callable, Sequence

import sympy as sp

from . import cache
from . import reduction as R

__all__ = ["stationary_series"]


def stationary_series(
    state: Callable[[sp.Symbol, sp.Symbol], Sequence],
    *,
    order: int = 2,
    model: str = "relaxed",
    material: str = "cg",
) -> tuple[sp.Expr, ...]:
    """Coefficients (c_1, ..., c_order) of the stationary point x(p) = sum c_n p^n of W.

    Arguments:
        state: ``state(x, p) -> (lam1, lam2, k1, k2, kb1, kb2)`` built with ordinary
            arithmetic (it is called with sympy symbols). x = 0 must be stationary at p = 0.
        order: highest power of p (>= 1).
        model, material: as in :func:`shellbvp.energy_density`; no through-thickness stimulus.

    Returns:
        sympy expressions in the symbols ``h`` (h0/R0) and ``lam`` (lambda*/mu*), exact in h.

    Raises:
        ValueError: ``order`` < 1, or x = 0 not stationary at p = 0, or dW/dx degenerate.
    """
    if int(order) != order or order < 1:
        raise ValueError(f"order must be an integer >= 1, got {order!r}")
    x, p = sp.symbols("x p", real=True)
    family = tuple(sp.sympify(e) for e in state(x, p))
    if len(family) != 6:
        raise ValueError(f"state must return 6 expressions (lam1, lam2, k1, k2, kb1, kb2), "
                         f"got {len(family)}")
    k = cache.key("stationary_series", sp.srepr(family), order, model, material,
                  inspect.getsource(stationary_series), inspect.getsource(R))
    return cache.memo(k, lambda: _series(family, x, p, order, model, material))


def _series(family, x, p, order, model, material):
    W = R.full_energy(model, material, stimulus={R.rhob1: 1, R.rhob2: 0, R.rhob3: 0})
    W = W.subs(dict(zip(R.STATE, family)), simultaneous=True)
    G = sp.diff(W, x)
    g00 = sp.simplify(G.subs({x: 0, p: 0}))
    if g00 != 0:
        raise ValueError(f"x = 0 is not stationary at p = 0: dW/dx = {g00}")
    Gx = sp.simplify(sp.diff(G, x).subs({x: 0, p: 0}))
    if Gx == 0:
        raise ValueError("d2W/dx2 vanishes at the origin: the stationary point is degenerate")
    cs = sp.symbols(f"c1:{order + 1}")
    Gp = G.subs(x, sum(c * p ** (n + 1) for n, c in enumerate(cs)))
    sol: dict = {}
    deriv = Gp
    for n, c in enumerate(cs, start=1):
        deriv = sp.diff(deriv, p)
        eq = (deriv.subs(p, 0) / sp.factorial(n)).subs(sol)
        sol[c] = sp.factor(sp.simplify(sp.solve(eq, c)[0]))
    return tuple(sol[c] for c in cs)
