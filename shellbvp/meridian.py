"""The state along a solved meridian: the principal stretches and curvatures from the inner
constitutive root followed node to node, the Hessian of W there (ellipticity), the solution
as a function of s, and the energies by quadrature. A part of :class:`shellbvp.bvp.ShellBVP`
(a base class it inherits): post-processing of what a method has solved.
"""

from __future__ import annotations

import math

import numpy as np

from . import kinematics as K
from .nodal import flat_nodes

__all__ = ["MeridianStates", "STATE_CHUNK", "ENERGY_PANELS", "ENERGY_GAUSS"]

#: nodes per compiled call of the state along the meridian (:meth:`ShellBVP.state`), at
#: every node count: its scan is sequential, so chunking costs only a dispatch per chunk,
#: and one program (~5-8 s to compile for a relaxed energy) serves the solvers' nodes and
#: the energy quadrature's (which needed a second one at its own size)
STATE_CHUNK = 72
#: Gauss-Legendre panels and points per panel of the energy quadrature (per piece)
ENERGY_PANELS, ENERGY_GAUSS = 64, 4


class MeridianStates:
    """The state, profile and energies of a solution (uses the host's compiled kernels
    ``_k``, its node layout ``_layout`` and field check ``_check``, its pieces ``a``, ``b``,
    ``P``, ``lengths``, ``s_of`` and ``scene``: :class:`shellbvp.bvp.ShellBVP`)."""

    def state(self, s, Y, p, q_hint=None):
        """Principal state X = (lam1, lam2, k1, k2) (P, 4, m) and fields (P, 4, m) at nodes;
        ``q_hint`` (P, m, 2): starts for the inner roots (lam1, k1), e.g. a solver's."""
        X, F, _, _ = self.state_and_hessian(s, Y, p, q_hint)
        return X, F

    def state_and_hessian(self, s, Y, p, q_hint=None, all_fields=False):
        """:meth:`state` (fields (g1, g2, kb1, kb2), or with ``all_fields`` every field of
        :data:`shellbvp.kinematics.FIELDS`) and the gradient (P, 4, m) and Hessian
        (P, 4, 4, m) of W in X at every node: the ellipticity of the reduced energy is read
        from them (:func:`shellbvp.ellipticity.ellipticity`)."""
        s = np.asarray(s, dtype=float)
        P, m = s.shape
        X, F, ok, gw, Hw = self._scan(s, Y, p, q_hint)
        self._check(F, ok, s, p)
        F = F.reshape(P, m, -1)
        if not all_fields:
            F = F[:, :, :4]                        # the stimulus fields
        return (np.moveaxis(X.reshape(P, m, 4), -1, 1), np.moveaxis(F, -1, 1),
                np.moveaxis(gw.reshape(P, m, 4), -1, 1), np.moveaxis(Hw.reshape(P, m, 4, 4), 1, -1))

    def _scan(self, s, Y, p, q_hint=None):
        """The state along the meridian (flattened nodes, piece-major), each node's inner
        Newton started from ``q_hint`` there (P, m, 2) where given and finite, else from the
        previous node's root (see ``state_along`` in the kernels)."""
        P, m = s.shape
        piece, chunks = self._layout(P, m, STATE_CHUNK)
        sf, yf = s.reshape(-1), flat_nodes(Y)
        qh = np.full((P * m, 2), np.nan) if q_hint is None else \
            np.asarray(q_hint, dtype=float).reshape(P * m, 2)
        q = np.full(2, np.nan)         # the first node starts from the pole-like guess
        outs = []
        for start, stop, idx in chunks:
            X, F, ok, gw, Hw, q = self._k.state(piece[idx], sf[idx], yf[idx], float(p),
                                                   self.scene.material_parameter, self.scene.h,
                                                   self.field_parameters, q,
                                                   qh[idx])
            n = stop - start
            outs.append((X[:n], F[:n], ok[:n], gw[:n], Hw[:n]))
        return tuple(np.concatenate(parts) for parts in zip(*outs))

    def profile(self, dense_t):
        """A callable s -> (6, n) from a stacked interpolant t -> (6 P, n) in the piece
        coordinate (each s evaluated on its own piece; an interface belongs to the next)."""
        def ev(s):
            s = np.atleast_1d(np.asarray(s, dtype=float))
            out = np.empty((6, s.size))
            for i in range(self.P):
                lo = self.a[i] if i else -np.inf
                sel = (s >= lo) & ((s < self.b[i]) if i < self.P - 1 else (s <= np.inf))
                if np.any(sel):
                    t = (s[sel] - self.a[i]) / (self.b[i] - self.a[i])
                    out[:, sel] = np.asarray(dense_t(t))[6 * i:6 * i + 6]
            return out

        return ev

    def energies(self, dense_t, p, roots=None):
        """(E_s, E_b, E_p) = 2 pi int (w_s, (h t)^2/12 w_b) t g1 g2 r0 ds and the pressure's
        potential E_p = P V = pi P int r^2 g1 lam1 sin(theta) ds (0 without a load), per
        mu* h R^2, by Gauss-Legendre quadrature per piece plus the polar caps [0, eps] at
        poles (W is constant there to O(eps^2); r^2 makes its E_p O(eps^4)).
        ``dense_t(t)`` is the stacked (6 P, n) solution in the piece coordinate;
        ``roots`` = (t (m,), q (P, m, 2)): the inner roots at a solver's nodes, interpolated
        as starts at the quadrature points."""
        from .energy import energy_terms

        sc = self.scene
        xg, wg = np.polynomial.legendre.leggauss(ENERGY_GAUSS)
        edges = np.linspace(0.0, 1.0, ENERGY_PANELS + 1)
        mid, half = (edges[:-1] + edges[1:]) / 2, (edges[1:] - edges[:-1]) / 2
        t = (mid[:, None] + half[:, None] * xg[None, :]).ravel()
        wt = (half[:, None] * wg[None, :]).ravel()
        s = np.stack([self.s_of(i, t) for i in range(self.P)])
        Y = np.asarray(dense_t(t)).reshape(self.P, 6, t.size)
        hint = None
        if roots is not None:
            tn, qn = roots
            hint = np.stack([np.stack([np.interp(t, tn, qn[i, :, c]) for c in range(2)], -1)
                             for i in range(self.P)])
        X, F, _, _ = self.state_and_hessian(s, Y, p, hint, all_fields=True)
        F = np.moveaxis(F, 1, 0)                                   # (fields, P, m)
        rb = K.RHOB.start
        ws, wb, _, _ = energy_terms(*np.moveaxis(X, 1, 0), F[K.KB1], F[K.KB2], lam=sc.lam,
                                    nu=sc.nu, model=sc.model, material=sc.material,
                                    rhob1=F[rb], rhob2=F[rb + 1], rhob3=F[rb + 2])
        dA = K.area_factor(F) * self.lengths[:, None] * wt[None, :]
        ht2 = (sc.h * F[K.THICKNESS]) ** 2 / 12
        Es, Eb = float(np.sum(ws * dA)), float(np.sum(ht2 * wb * dA))
        # the polar caps: W and the fields at the node next to the pole, the area of the
        # reference's cap there (r0 ~ s) times g1 g2 t
        for end, (i, k) in enumerate(((0, 0), (self.P - 1, -1))):
            if self.poles[end]:
                cap = K.area_factor(F[:, i, k]) / F[K.R0, i, k] * self.eps ** 2 / 2
                Es += ws[i, k] * cap
                Eb += ht2[i, k] * wb[i, k] * cap
        Ep = 0.0
        if sc.pressure is not None:
            r, th = Y[:, 0], Y[:, 2]
            Ep = math.pi * float(sc.pressure(p)) * float(np.sum(
                r**2 * F[K.G1] * X[:, 0] * np.sin(th) * self.lengths[:, None] * wt[None, :]))
        return 2 * math.pi * Es, 2 * math.pi * Eb, Ep
