"""Derivatives of the shell BVP beyond its Jacobian: in the scene's data (the meridian's
length, the material parameter, h) and the second derivatives of the fold system, all exact
(JAX, the inner root differentiated implicitly). A part of :class:`shellbvp.bvp.ShellBVP`
(a base class it inherits), kept apart because only the fold machinery of the spectral
method needs it (:class:`shellbvp.methods.base.SecondOrder`).
"""

from __future__ import annotations

import numpy as np

from .errors import ConvergenceError
from .nodal import Hint, flat_nodes

__all__ = ["Derivatives", "FOLD_CHUNK"]

#: nodes per compiled call of the fold system's second derivatives (:meth:`ShellBVP.fold_terms`)
FOLD_CHUNK = 24


class Derivatives:
    """Derivatives of a BVP in its data and its fold system's second derivatives (uses the
    host's compiled kernels ``_k`` and its nodal evaluation: ``_nodal_args``, ``_flat``,
    ``rhs``; :class:`shellbvp.bvp.ShellBVP`)."""

    def sensitivities(self, s, Y, p, hint=None, geometry_only=False):
        """f and its derivatives in (s, material parameter, h) at nodes s (P, m), states
        Y (P, 6, m) and fixed p: (f (P, 6, m), df/d(s, mat, h) (P, 6, m, 3)), the inner root
        differentiated implicitly (no finite differences). With :meth:`boundary_sensitivities`
        this gives the derivative of a discrete system in the meridian's length, h and the
        material.
        ``geometry_only``: the derivative in s alone (zeros in the others; compiles ~5x
        faster)."""
        s, Y, _, q0 = self._nodal_args(s, Y, hint, p)
        P, m = s.shape
        kernel = self._k.geometry_sensitivity if geometry_only else self._k.sensitivity
        f, df = self._flat(kernel, s, Y, p,
                           (q0,))
        if not np.all(np.isfinite(df)):
            raise ConvergenceError("parameter derivatives of the right-hand side are not "
                                   "finite (the inner root was not found)")
        return (np.moveaxis(f.reshape(P, m, 6), -1, 1),
                np.moveaxis(df.reshape(P, m, 6, 3), 1, 2))

    def boundary_sensitivities(self, ya, yb, p, geometry_only=False):
        """The derivatives of the boundary residual (6,) in (the meridian's length L,
        material parameter, h) as (6, 3), and of the monitor in L, at fixed ya, yb and p,
        the domain's ends moving with L as :attr:`ends_per_length` says (``geometry_only``:
        zeros for the material parameter and h)."""
        sc = self.scene
        kernel = (self._k.boundary_geometry_sensitivity if geometry_only
                  else self._k.boundary_sensitivity)
        dr, dm = kernel(
            np.asarray(ya, dtype=float), np.asarray(yb, dtype=float), float(p), *self._ends(),
            self.scene.material_parameter, sc.h, self.field_parameters)
        dr, dm = np.asarray(dr), np.asarray(dm)
        da, db = self.ends_per_length
        dL = dr[:, 0] * da + dr[:, 1] * db + dr[:, 2]
        return np.column_stack([dL, dr[:, 3], dr[:, 4]]), float(dm[0] * da + dm[1] * db
                                                               + dm[2])

    def fold_terms(self, s, Y, p, Wn, wb, V, dp, hint=None):
        """Second-derivative terms of a fold system at nodes s (P, m), states Y (P, 6, m):
        for phi = Wn . f at every node (weights Wn (P, 6, m)) plus wb[k] . (pole rows) at the
        end node of end k where it is a pole (wb (2, 3): the weights of the first and second
        end's rows), the derivative of phi along (V (P, 6, m), dp) and that of its gradient
        in (y, p, s), exact (no finite differences): (dphi (P, m, 2), the parts wn . f and
        wb . (pole rows); dgrad_y (P, 6, m); dgrad_p (P, m); dgrad_s (P, m)). ``hint``: the
        BVP's nodal result at exactly these states (its roots and their derivatives), else
        computed."""
        s, Y = np.asarray(s, dtype=float), np.asarray(Y, dtype=float)
        P, m = s.shape
        if not (isinstance(hint, Hint) and hint.q.shape == (P * m, 2) and hint.p == p
                and np.array_equal(hint.y, flat_nodes(Y))):
            hint = self.rhs(s, Y, p, hint).hint
        WB = np.zeros((P * m, 6))
        wb = np.asarray(wb, dtype=float).reshape(2, 3)
        WB[0, :3] = wb[0]
        WB[-1, 3:] = wb[1]
        # chunks of one size, FOLD_CHUNK: every resolution runs on one compiled program
        # (~13 s to compile for a relaxed energy, against ~0.1 ms per extra chunk)
        out = self._flat(self._k.fold_nodal, s, Y, p,
                         (hint.q, hint.dq, flat_nodes(Wn), WB, flat_nodes(V)),
                         scalars=(float(dp), self.length), chunk=FOLD_CHUNK)
        dphi, dgy, dgp, dgs = out
        if not all(np.all(np.isfinite(o)) for o in out):
            raise ConvergenceError("fold system: second derivatives are not finite")
        return (dphi.reshape(P, m, 2), np.moveaxis(dgy.reshape(P, m, 6), -1, 1),
                dgp.reshape(P, m), dgs.reshape(P, m))

    def monitor_curvature(self, ya, yb, va, vb):
        """The gradient in (ya, yb, L) of the monitor's derivative along (va, vb) (L the
        meridian's length, the domain's ends moving with it)."""
        ga, gb, da, db, dL = (np.asarray(o) for o in self._k.observable_curvature(
            np.asarray(ya, float), np.asarray(yb, float), *self._ends(), self.scene.h,
            np.asarray(va, float), np.asarray(vb, float)))
        pa, pb = self.ends_per_length
        return ga, gb, float(da * pa + db * pb + dL)
