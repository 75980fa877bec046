"""Euler-Lagrange equations of the reduced axisymmetric energy, derived with sympy (paper
Section 4).

Kinematics (:mod:`shellbvp.kinematics`, the one home of the map): the reference meridian is
traced by its arclength s and enters only through its radius r0(s), a field like the target
stretches; with Lambda = g1 lam1 the current speed,

    r' = g1 lam1 cos(theta),   z' = -g1 lam1 sin(theta),   theta' = -g1 lam1 k1,
    lam2 = r / (g2 r0),        k2 = -sin(theta) / r,

so that the energy per 2 pi mu* h is the integral of
L = W(lam1, lam2, k1, k2) t g1 g2 r0 + (p/2) r^2 g1 lam1 sin th
    + F_r (r' - g1 lam1 cos th) + F_z (z' + g1 lam1 sin th),
with k1 = -theta' / (g1 lam1) and t = h(s)/h the thickness profile (W is evaluated at the
local thickness h t; its jet carries that). The shape of the reference shell is nowhere in
these equations but through the fields r0 and t: a new shape derives nothing new. The
pressure term is p V / (2 pi mu* h) for a uniform external pressure p (in mu* h / R,
positive toward the centre of curvature of a cap) on the deformed surface,
V = -pi int r^2 z' ds, the volume enclosed between the surface and the plane of its end
(closed through the axis and that plane, where dz = 0 or r = 0): a follower load with a
potential, written with z' = -g1 lam1 sin th so that it enters the same multipliers'
equations.
The Euler-Lagrange equations give the first-order system for
y = (r, z, theta, m, f_r, f_z), where m = 12 M / h^2, f = 12 F / h^2 (M = dL/dtheta' the
meridional moment; the scaling makes bending and membrane unknowns the same size), and two
algebraic equations G(q; y, F) = 0 for q = (lam1, k1):

    G1 = (12/h^2) (dL/dtheta' - M) / (g2 r0),     G2 = (dL/dlam1) / (g2 r0).

W enters only through its gradient W_a and Hessian W_ab in X = (lam1, lam2, k1, k2): the
chain rule through the kinematic map X(q, y, F) is done by sympy, so this module does not
depend on the constitutive model; the model's W-jet comes from :mod:`shellbvp.reduction`.
Jacobians: df/dy = f_y + f_q dq/dy with dq/dy = -G_q^-1 G_y (implicit differentiation).
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass
from functools import lru_cache

import sympy as sp

from . import cache
from . import kinematics as K

__all__ = ["ELSystem", "derive_el", "Y", "Q", "WGRAD", "WHESS", "FIELDS"]

h = sp.Symbol("h", positive=True)
r0, t = sp.symbols("r0 t", positive=True)
r, z, th, m, fr, fz = sp.symbols("r z theta m f_r f_z", real=True)
l1 = sp.Symbol("lam1", positive=True)
k1 = sp.Symbol("k1", real=True)
thp = sp.Symbol("thetap", real=True)
g1, g2 = sp.symbols("g1 g2", positive=True)
kb1, kb2 = sp.symbols("kb1 kb2", real=True)
pr = sp.Symbol("pressure", real=True)
rhob = sp.symbols("rhob1 rhob2 rhob3", real=True)

Y = (r, z, th, m, fr, fz)
Q = (l1, k1)
#: the fields in the order of :data:`shellbvp.kinematics.FIELDS`
FIELDS = (g1, g2, kb1, kb2, pr, r0, t) + rhob
WGRAD = sp.symbols("W_L1 W_L2 W_K1 W_K2", real=True)
_H = {}
for i in range(4):
    for j in range(i, 4):
        _H[(i, j)] = _H[(j, i)] = sp.Symbol(f"W_{i}{j}", real=True)
WHESS = tuple(_H[(i, j)] for i in range(4) for j in range(i, 4))


@dataclass(frozen=True)
class ELSystem:
    """First-order system and algebraic equations as sympy expressions.

    ``X``: kinematic map (lam1, lam2, k1, k2) in terms of (q, y, fields).
    ``G``, ``G_q``, ``G_y``: algebraic equations and their derivatives (2, 2x2, 2x6).
    ``f``, ``f_y``, ``f_q``: right-hand side dy/ds and its partial derivatives (6, 6x6, 6x2).
    All are expressions in y, q, h, the fields and the W-jet symbols WGRAD, WHESS (no s: the
    reference shell enters through the fields r0 and t only).
    """

    X: tuple
    G: tuple
    G_q: tuple
    G_y: tuple
    f: tuple
    f_y: tuple
    f_q: tuple
    metric: bool


def _total(expr, v, X):
    """d expr / d v where expr depends on v explicitly and through W_a(X(v))."""
    out = sp.diff(expr, v)
    for a in range(4):
        c = sp.diff(expr, WGRAD[a])
        if c != 0:
            out += c * sum(_H[(a, b)] * sp.diff(X[b], v) for b in range(4))
    return out


def _derive(metric: bool) -> ELSystem:
    G1_, G2_ = (g1, g2) if metric else (sp.Integer(1), sp.Integer(1))
    F = (G1_, G2_) + FIELDS[2:]
    # Kinematic map with theta' as the independent variable (before the Legendre step).
    Xp = K.principal_state(r, th, G1_ * l1, thp, r0, G1_, G2_, sp)
    jac = K.area_factor(F)
    Fr, Fz = h**2 / 12 * fr, h**2 / 12 * fz
    cons = -Fr * G1_ * l1 * sp.cos(th) + Fz * G1_ * l1 * sp.sin(th)  # the r', z' terms do not vary
    cons += pr / 2 * r**2 * G1_ * l1 * sp.sin(th)                    # the pressure potential p V

    def dL(v):  # partial derivative of the Lagrangian: W part by the chain rule, then constraints
        return sum(WGRAD[a] * sp.diff(Xp[a], v) for a in range(4)) * jac + sp.diff(cons, v)

    on_shell = {thp: -G1_ * l1 * k1}
    X = tuple(x.subs(on_shell) for x in Xp)
    M = dL(thp).subs(on_shell)
    G1 = sp.simplify(12 / h**2 * M / (G2_ * r0)) - m / (G2_ * r0)
    G2 = sp.simplify(dL(l1).subs(on_shell) / (G2_ * r0))
    f = (
        G1_ * l1 * sp.cos(th),
        -G1_ * l1 * sp.sin(th),
        -G1_ * l1 * k1,
        sp.simplify(12 / h**2 * dL(th).subs(on_shell)),
        sp.simplify(12 / h**2 * dL(r).subs(on_shell)),
        sp.Integer(0),
    )
    G = (G1, G2)
    G_q = tuple(tuple(_total(g, v, X) for v in Q) for g in G)
    G_y = tuple(tuple(_total(g, v, X) for v in Y) for g in G)
    f_y = tuple(tuple(_total(e, v, X) for v in Y) for e in f)
    f_q = tuple(tuple(_total(e, v, X) for v in Q) for e in f)
    return ELSystem(X, G, G_q, G_y, f, f_y, f_q, metric)


@lru_cache(maxsize=None)
def derive_el(metric: bool = False) -> ELSystem:
    """The Euler-Lagrange system, derived once and cached on disk.

    ``metric=False`` specialises to g1 = g2 = 1 (no in-plane metric stimulus): the generated
    equations then carry no g terms.
    """
    k = cache.key("euler_lagrange", bool(metric), inspect.getsource(inspect.getmodule(_derive)),
                  inspect.getsource(K))
    return cache.memo(k, lambda: _derive(bool(metric)))
