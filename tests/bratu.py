"""Bratu's problem u'' + p e^u = 0, u(0) = u(1) = 0 as a first-order BVP y = (u, u') in the
protocol the nodal methods need of a BVP (:class:`shellbvp.methods.base.NodalBVP`): a test
problem with an exactly known fold, independent of the shell equations. The fold is
p* = 3.513830719125161 (Bratu 1914; 8 x^2 / cosh(x)^2 at the root of x tanh x = 1), with
u'(0) = 4 there.
"""

import numpy as np

from shellbvp.nodal import Nodal

LAM_STAR = 3.513830719125161


class BratuBVP:
    """Bratu as a first-order BVP y = (u, u') on one piece [0, 1], in the protocol that the
    methods use for the shell (:class:`shellbvp.ShellBVP`): nodal rhs with exact Jacobians,
    boundary conditions u(0) = u(1) = 0 with theirs, monitor u'(0)."""

    n, P = 2, 1
    a, b, lengths = np.array([0.0]), np.array([1.0]), np.array([1.0])
    rise = 1.0
    evaluations = 0

    def s_of(self, i, t):
        return np.asarray(t, dtype=float)

    def rhs(self, s, Y, p, hint=None):
        u, v = Y[:, 0], Y[:, 1]
        f = np.stack([v, -p * np.exp(u)], axis=1)
        J = np.zeros((1, 2, 2, s.shape[1]))
        J[:, 0, 1] = 1.0
        J[:, 1, 0] = -p * np.exp(u)
        fp = np.stack([0 * u, -np.exp(u)], axis=1)
        return Nodal(f, J, fp)

    def boundary(self, ya, yb, p):
        Ja, Jb = np.zeros((2, 2)), np.zeros((2, 2))
        Ja[0, 0] = Jb[1, 0] = 1.0
        return np.array([ya[0], yb[0]]), Ja, Jb, np.zeros(2)

    def monitor(self, ya, yb):
        return float(ya[1]), np.array([0.0, 1.0]), np.zeros(2)
