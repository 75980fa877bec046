"""The full 2D reduced energy of a shell of revolution in (s, omega), for displacements of one
circumferential symmetry class: the foundation for following a branch past a bifurcation.

About an axisymmetric equilibrium x0(s, omega) = (r cos omega, r sin omega, z) the mid-surface
is displaced by

    dx = sum over k in {0, n, 2n, ..., K n} of
         U_r^k(s) cos(k omega) e_r + U_w^k(s) sin(k omega) e_omega + U_z^k(s) cos(k omega) e_z

(the family symmetric under omega -> -omega that holds the bifurcating mode of
:mod:`shellbvp.harmonics`; U_w^0 is absent, sin 0 = 0: no twist), each U^k a Chebyshev series
of degree ``degree`` per piece, coefficients laid out as in :mod:`shellbvp.harmonics`
(piece, component (r, omega, z), coefficient). The energy is that of :mod:`shellbvp.harmonics`
without its expansion to second order:

    E = int int [ W(a, b; abar, bbar) t g1 g2 r0 + (P / 3) x . (x_s x x_omega) ] ds domega
        + the lids of a pressure at the ends that move in their plane (roller, sliding,
          symmetry) or keep their radius (diaphragm) (:data:`shellbvp.harmonics.LID_ENDS`)
        - the dead end loads' work (a pole's force, a free end's axial and radial line loads)

per mu* h0 R0^2, W the reduced energy of general forms (:func:`shellbvp.forms.reduced_energy`)
evaluated on the local components of (x, x_s, x_o, x_ss, x_so, x_oo) in the frame
(e_r, e_omega, e_z) (the density is invariant under rotations about the axis):

    x_o  = (X_r,o - X_w, X_w,o + X_r, X_z,o),
    x_oo = (X_r,oo - 2 X_w,o - X_r, X_w,oo + 2 X_r,o - X_w, X_z,oo),

X = x0 + dx in that frame, and x_so the s-derivative of x_o. At the base state (dx = 0) E is
the axisymmetric equilibrium's energy (``eq.energy``: elastic plus pressure potential, up to
a pressure term constant where the ends do not move) and its Hessian per harmonic is
:func:`shellbvp.harmonics.modes`' second variation.

Quadrature. In s: the Gauss-Legendre points of :mod:`shellbvp.harmonics` (``max(2 degree,
64) + 8`` per piece). In omega: the trapezoidal rule on M = n N points over [0, 2 pi)
(N even, points per period 2 pi / n), exact for every Fourier component of the integrand
below frequency n N. The integrand is a function of the state, whose content is in
harmonics up to K n, so its degree-d terms in dx reach d K n: the default N = 8 K + 2
integrates exactly all terms up to degree 8 in dx (the second variation at an axisymmetric
state, degree 2, needs only N > 2 K), the higher ones alias at O(|dx|^9). The integrand is
even in omega and 2 pi / n periodic (the class is invariant under omega -> -omega and under
the rotation by 2 pi / n, and so is the density), so the rule is evaluated on the N / 2 + 1
points omega_j = 2 pi j / (n N), j = 0..N/2, of [0, pi / n] with weights (2 pi / N)
(1, 2, ..., 2, 1): the same sum as the full rule, on N / 2 + 1 points instead of n N
(``full_period=True`` evaluates the full rule: a check).

Admissible set (:func:`_admissible`): per harmonic the linear end, pole and interface rows of
:func:`shellbvp.harmonics._constraints` (pole regularity per harmonic, clamped / hinged /
roller / symmetry ends; exact for the nonlinear problem too: a clamped end holding dx = 0
keeps its normal iff dx_s . N0 = 0, linear; at a symmetry end U_w'^k = 0, which the mirror
image of a smooth state has, is left natural as in the harmonics), plus U_w^0 = 0,
eliminated by a null-space basis; the rigid motions the ends leave in the class (k = 0:
the axial translation; n = 1: the lateral translation and the tilt) are removed by taking
the mass-orthogonal complement, as :func:`shellbvp.harmonics.modes` does (a gauge: a slice
transversal to the rigid orbit).
The basis Z_k is mass-orthonormal in int int |dx|^2 dA_target, so the unknowns y (the Z_k
coordinates of every harmonic, stacked) have the identity mass matrix, and the eigenvalues of
the Hessian's block k are those of :func:`shellbvp.harmonics.modes` (same normalisation).

Derivatives: ``energy`` is a JAX function of y; ``gradient`` is its ``jax.grad`` and
``hvp`` a jvp of that gradient (exact). ``hessian`` assembles the same Hessian by the chain
rule: the density's exact Hessian in the 18 local numbers at every point
(:func:`shellbvp.harmonics._hessian_kernel`), contracted with the linear map from the
Chebyshev coefficients to those numbers, per harmonic pair (k, l): dense (K + 1)^2 blocks,
block-diagonal at an axisymmetric state.

Joints. Across an interface between pieces (a joint of the geometry or a break of the
stimulus) U is continuous (linear rows, in the basis) and the joint is rigid: the signed
angle between the tangents on either side about the hoop direction keeps the reference
shell's (:func:`_joint_condition`). That condition is not linear in dx where the stretch
jumps or the tangent turns, so it is imposed with multipliers: its projections on cos(k
omega) of the class's harmonics, one per harmonic and joint, appended to the unknowns
(``U = (y, lambda)``, :attr:`Fourier2D.size` counts both; ``ny`` the displacement's). E is
replaced by the Lagrangian E - lambda . c(y): its stationary points are the constrained
equilibria; its gradient, Hessian (symmetric, indefinite: [[H_L, -J^T], [-J, 0]]) and
higher derivatives are those of the same JAX function, and the stability of a state is
that of H_L on the null space of J (:meth:`Fourier2D.block_modes` at axisymmetric states,
equal to :func:`shellbvp.harmonics.modes`, which imposes the linearised condition with the
Lagrangian's interface term). The base state is ``origin``: zero displacement and the
multipliers that make it stationary.

Not yet: end moments (a nonlinear potential), a pole's prescribed displacement at another
parameter value than the base's (a nonhomogeneous constraint).
"""

from __future__ import annotations

import math
from functools import cached_property, lru_cache

import numpy as np

from . import harmonics as _H
from .results import Equilibrium

__all__ = ["Fourier2D", "discretise", "NewtonResult"]

#: indices of the 18 local numbers (x, x_s, x_o, x_ss, x_so, x_oo) that go with cos(k omega)
#: (the r and z components of x, x_s, x_ss, x_oo, the omega components of x_o and x_so); the
#: others go with sin(k omega)
_COS = (0, 2, 3, 5, 7, 9, 11, 13, 15, 17)


def _default_points(K: int) -> int:
    return 8 * K + 2


def _legendre_derivative(values: np.ndarray, m: int, scale: float) -> np.ndarray:
    """d/ds of the degree m - 1 Legendre interpolant of ``values`` at the m Gauss-Legendre
    points (exact for the base state's Chebyshev interpolants of degree < m: Gauss quadrature
    gives their Legendre coefficients exactly)."""
    L = np.polynomial.legendre
    x, w = L.leggauss(m)
    V = L.legvander(x, m - 1)                                   # (m, m)
    coef = (np.arange(m) + 0.5) * (V.T @ (w * values))
    return L.legval(x, L.legder(coef)) * scale


class NewtonResult:
    """The outcome of :meth:`Fourier2D.newton`: the state y, whether it converged, and per
    iteration (|gradient|, |step|)."""

    def __init__(self, y, converged, history, p):
        self.y, self.converged, self.history, self.p = y, converged, history, p

    def __repr__(self) -> str:
        return (f"NewtonResult(converged={self.converged}, iterations={len(self.history)}, "
                f"|g|={self.history[-1][0] if self.history else math.nan:.2e})")


class Fourier2D:
    """The 2D energy about the axisymmetric equilibrium ``eq`` on the symmetry class of
    harmonic ``n`` with harmonics 0, n, ..., K n (module docstring).

    Attributes:
        eq: the base equilibrium; n, K; ks: the harmonics (0, n, ..., K n).
        degree: Chebyshev degree per component and piece.
        points: N, trapezoidal points per period 2 pi / n (even).
        sizes: the number of unknowns of each harmonic; ny: their total.
        joints: the interfaces between pieces; size: ny plus one multiplier per harmonic
            and joint (the unknowns U = (y, lambda), module docstring).
    """

    def __init__(self, eq: Equilibrium, n: int, K: int, *, degree: int | None = None,
                 points: int | None = None, full_period: bool = False):
        if not isinstance(eq, Equilibrium) or not eq.success:
            raise ValueError("eq must be a converged Equilibrium")
        if not (isinstance(n, (int, np.integer)) and 1 <= n <= _H.N_MAX):
            raise ValueError(f"n must be an integer in [1, {_H.N_MAX}], got {n!r}")
        if not (isinstance(K, (int, np.integer)) and K >= 0):
            raise ValueError(f"K must be a non-negative integer, got {K!r}")
        sc = eq.scene
        if sc.pressure is not None and any(e.kind == "free" for e in sc.ends):
            raise ValueError("a follower pressure on a shell with a free end has no potential "
                             "beyond axisymmetry (as in shellbvp.harmonics)")
        for e in sc.ends:
            if e.moment is not None:
                raise NotImplementedError("end moments (a nonlinear potential) are not "
                                          "handled yet")
        self.eq, self.n, self.K = eq, int(n), int(K)
        self.ks = tuple(self.n * j for j in range(self.K + 1))
        degree = _H.DEGREE if degree is None else degree
        if not (isinstance(degree, (int, np.integer)) and 8 <= degree <= 160):
            raise ValueError(f"degree must be an integer in [8, 160], got {degree!r}")
        self.degree = int(degree)
        N = _default_points(self.K) if points is None else points
        if not isinstance(N, (int, np.integer)):
            raise ValueError(f"points must be an even integer >= 2, got {points!r}")
        self._grid(N, full_period)
        base = _H._base(eq, self.degree)
        self.base = base
        D = _H._derivative_operators(base)
        self._D = D
        self.Z, self.rigid = zip(*(_admissible(base, D, k) for k in self.ks))
        self.sizes = tuple(Z.shape[1] for Z in self.Z)
        self.offsets = tuple(int(x) for x in np.concatenate([[0], np.cumsum(self.sizes)]))
        self.ny = self.offsets[-1]
        self.joints = base.s.shape[0] - 1
        self.size = self.ny + self.joints * (self.K + 1)
        # (9, P m, size_k): (U, U', U'') at the Gauss points from each harmonic's unknowns
        self.G = tuple(np.einsum("apj,jr->apr", D, Z) for Z in self.Z)
        self.imperfection = None
        self._base_state()
        self._ends()

    # --- set-up ---------------------------------------------------------------------------
    def _grid(self, N: int, full_period: bool):
        """The trapezoidal rule in omega: N points per period 2 pi / n, evaluated on
        [0, pi / n] (weights (2 pi / N)(1, 2, ..., 2, 1)) or on all of [0, 2 pi)."""
        if N < 2 or N % 2:
            raise ValueError(f"points must be an even integer >= 2, got {N!r}")
        self.points, self.full_period = int(N), bool(full_period)
        if full_period:
            M = self.n * N
            self.w = 2 * math.pi * np.arange(M) / M
            self.w_weights = np.full(M, 2 * math.pi / M)
        else:
            self.w = 2 * math.pi * np.arange(N // 2 + 1) / (self.n * N)
            self.w_weights = np.full(N // 2 + 1, 4 * math.pi / N)
            self.w_weights[[0, -1]] /= 2

    def with_points(self, points: int, *, full_period: bool = False) -> "Fourier2D":
        """The same discretisation (base state, unknowns) with another rule in omega."""
        import copy

        out = copy.copy(self)
        for name in ("_trig", "_data", "_change", "origin"):
            out.__dict__.pop(name, None)
        out._grid(int(points), full_period)
        return out

    def _base_state(self):
        """x0, x0_s, x0_ss (local components (r, omega, z)) at the Gauss points: (r, 0, z),
        |x_s| t and d(|x_s| t)/ds, |x_s| and theta the base's interpolants (those of
        :func:`shellbvp.harmonics._base`), differentiated as Legendre interpolants."""
        b = self.base
        P, m = b.s.shape
        lam, th = b.stretch, b.theta
        dlam = np.stack([_legendre_derivative(lam[i], m, 2.0 / (hi - lo))
                         for i, (lo, hi) in enumerate(b.pieces)])
        dth = np.stack([_legendre_derivative(th[i], m, 2.0 / (hi - lo))
                        for i, (lo, hi) in enumerate(b.pieces)])
        c, s = np.cos(th), np.sin(th)
        zero = np.zeros_like(th)
        x = np.stack([b.r, zero, b.z])
        xs = np.stack([lam * c, zero, -lam * s])
        xss = np.stack([dlam * c - lam * dth * s, zero, -dlam * s - lam * dth * c])
        # (3 orders, 3 components, P m)
        self.x0 = np.stack([x, xs, xss]).reshape(3, 3, P * m)

    def _ends(self):
        """The rows giving U^k at each end, the pressure's lids and the dead end loads."""
        b, sc = self.base, self.eq.scene
        P = b.s.shape[0]
        self._end_rows = []          # per end: (3, size) rows per harmonic -> list
        for i, side in ((0, "a"), (P - 1, "b")):
            rows = np.array([_H._end_rows(b, i, side, 0, c) for c in range(3)])  # (3, ndof)
            self._end_rows.append([rows @ Z for Z in self.Z])
        self._lids = []              # (end, sigma, z_e) of each lid
        if sc.pressure is not None:
            for e, (sigma, (i, side), end) in enumerate(zip((1.0, -1.0),
                                                            ((0, "a"), (P - 1, "b")),
                                                            sc.ends)):
                if end.kind in _H.LID_ENDS:
                    self._lids.append((e, sigma, b.ends[(i, side)][3]))
        self._loaded = [e.loaded and e.displacement is None for e in sc.ends]
        self._joints = tuple(self._joint(i) for i in range(P - 1))

    def _joint(self, i: int) -> dict:
        """The data of the joint between pieces i and i + 1 (:func:`_joint_condition`): the
        rows R (9 (K + 1), ny) giving per harmonic (U, U' on the left, U' on the right) there,
        the base's position and tangents on either side, and the reference shell's angle
        between its tangents (zero where it does not turn: a break of the stimulus)."""
        from scipy.linalg import block_diag

        from .fields import reference_point

        b, sc = self.base, self.eq.scene
        R = lambda j, side, order, c: _H._end_rows(b, j, side, order, c)  # noqa: E731
        rows = np.array([R(i, "b", 0, c) for c in range(3)] + [R(i, "b", 1, c) for c in range(3)]
                        + [R(i + 1, "a", 1, c) for c in range(3)])
        x0, tl, tr = _H._joint_base(b, i)
        s = np.array([b.pieces[i][1]])
        ref = [float(np.ravel(reference_point(sc, j, s, np).theta)[0]) for j in (i, i + 1)]
        return dict(R=block_diag(*(rows @ Z for Z in self.Z)), x0=x0, tl=tl, tr=tr,
                    angle=ref[0] - ref[1])

    def fields(self, p=None, xp=np):
        """(P m, fields) at the Gauss points and parameter p (default the base's); ``xp``
        the array module (``jax.numpy`` to trace p)."""
        from .fields import point_fields

        sc = self.eq.scene
        p = self.eq.p if p is None else p
        c = np.asarray(sc.field_parameters, dtype=float)
        return xp.concatenate([point_fields(sc, i, self.base.s[i], p, c, xp).T
                               for i in range(self.base.s.shape[0])])

    def _end_r0(self, e: int) -> float:
        """The reference radius at end e (0: the first, 1: the last)."""
        i, s = (0, self.base.pieces[0][0]) if e == 0 else \
            (self.base.s.shape[0] - 1, self.base.pieces[-1][1])
        return float(self._r0_at(i, s))

    def _check_p(self, p):
        p = self.eq.p if p is None else float(p)
        if p != self.eq.p and any(e.displacement is not None for e in self.eq.scene.ends):
            raise NotImplementedError("a prescribed pole displacement at another parameter "
                                      "value than the base's is not handled yet")
        return p

    def _scalars(self, p):
        sc = self.eq.scene
        P = 0.0 if sc.pressure is None else float(sc.pressure(p))
        loads = np.zeros((2, 2))                   # per end: (Q_r, Q_z) per radian
        for e, end in enumerate(sc.ends):
            if self._loaded[e]:
                loads[e] = end.conjugate(p, self._end_r0(e))[:2]
        return P, loads

    def _rates(self, p):
        """The p-derivatives of what the energy takes from the parameter: the fields at the
        Gauss points (a JAX jvp of the scene's fields, as the compiled programs trace them),
        the pressure and the dead end loads."""
        from .scene import load_rate

        sc = self.eq.scene
        dF = np.asarray(self._field_rate(float(p)))
        dP = 0.0 if sc.pressure is None else load_rate(sc.pressure, p, 1)
        dloads = np.zeros((2, 2))
        for e, end in enumerate(sc.ends):
            if self._loaded[e]:
                dloads[e] = end.conjugate(p, self._end_r0(e), 1)[:2]
        return dF, dP, dloads

    @cached_property
    def _field_rate(self):
        """p -> dF/dp at the Gauss points: the jvp of :meth:`fields`, compiled once per
        discretisation (called at every continuation step)."""
        from .jaxsetup import jax
        import jax.numpy as jnp

        return jax.jit(lambda p: jax.jvp(lambda q: self.fields(q, jnp), (p,), (1.0,))[1])

    def _r0_at(self, i, s):
        from .fields import point_fields
        from . import kinematics as Kin

        sc = self.eq.scene
        c = np.asarray(sc.field_parameters, dtype=float)
        return point_fields(sc, i, np.array([s]), self.eq.p, c, np)[Kin.R0, 0]

    # --- an imperfect reference -----------------------------------------------------------
    def imperfect(self, shape, amplitude: float) -> "Fourier2D":
        """This discretisation for the shell whose reference surface is the surface of
        revolution displaced by ``amplitude`` times ``shape`` (a displacement field of this
        class, as unknowns y: e.g. the critical mode). The target forms change by the
        reference forms' change, exact in the amplitude (:meth:`reference_change`), and the
        area element with them (:func:`shellbvp.kinematics.target_matrices`). Where the
        target is the reference (no stimulus) this is the imperfect stress-free surface;
        with a stimulus, the stimulus changes the imperfect shell's forms as it changes the
        perfect shell's."""
        import copy

        shape = np.asarray(shape, dtype=float)
        if shape.shape != (self.size,):
            raise ValueError(f"shape must be a vector of this discretisation's {self.size} "
                             f"unknowns, got shape {shape.shape}")
        if not (isinstance(amplitude, (int, float)) and math.isfinite(amplitude)):
            raise ValueError(f"amplitude must be a finite number, got {amplitude!r}")
        out = copy.copy(self)
        for name in ("_data", "_change", "origin"):
            out.__dict__.pop(name, None)
        out.imperfection = (shape, float(amplitude))
        return out

    @cached_property
    def _reference_x0(self) -> np.ndarray:
        """(3 orders, 3 components, P m): x, x_s, x_ss of the reference surface of
        revolution at the Gauss points in the frame (e_r, e_omega, e_z), parametrised by
        its arclength: (r0, 0, z0), (cos th0, 0, -sin th0), th0' (-sin th0, 0, -cos th0),
        th0' that of th0's Legendre interpolant (as in ``_base_state``)."""
        from .fields import reference_point

        b, sc = self.base, self.eq.scene
        P, m = b.s.shape
        pts = [reference_point(sc, i, b.s[i], np) for i in range(P)]
        r, z, th = (np.stack([np.broadcast_to(getattr(q, a), (m,)) for q in pts])
                    for a in ("r", "z", "theta"))
        dth = np.stack([_legendre_derivative(th[i], m, 2.0 / (hi - lo))
                        for i, (lo, hi) in enumerate(b.pieces)])
        c, sn, zero = np.cos(th), np.sin(th), np.zeros_like(th)
        return np.stack([np.stack([r, zero, z]), np.stack([c, zero, -sn]),
                         np.stack([-dth * sn, zero, -dth * c])]).reshape(3, 3, P * m)

    def reference_change(self, shape, amplitude):
        """(P m, J, 6): the change of the reference surface's forms (a11, a12, a22, b11,
        b12, b22) at every point when it is displaced by amplitude times shape (exact; a
        JAX array, traceable in the amplitude)."""
        from .jaxsetup import jax

        C, S, ks = self._trig
        data = dict(G=tuple(self.G), x0=self._reference_x0, C=C, S=S, ks=ks)
        forms = jax.vmap(jax.vmap(_H._forms))
        q0 = _synthesis(0.0 * np.asarray(shape), data)
        return forms(_synthesis(amplitude * np.asarray(shape), data)) - forms(q0)

    @cached_property
    def _change(self):
        if self.imperfection is None:
            return None
        return np.asarray(self.reference_change(*self.imperfection))

    def imperfection_gradient(self, y, shape, p=None) -> np.ndarray:
        """d(dE/dy)/de at y: the gradient's rate in the amplitude e of an imperfection of
        the given shape (:meth:`imperfect`), at e = 0 (a jvp, exact)."""
        from .jaxsetup import jax

        if self.imperfection is not None:
            raise ValueError("imperfection_gradient is taken about the perfect shell")
        dchange = jax.jvp(lambda e: self.reference_change(shape, e), (0.0,), (1.0,))[1]
        return np.asarray(self._programs["grad_e"](np.asarray(y, dtype=float), *self._args(p),
                                                   dchange))

    # --- the state on the grid ------------------------------------------------------------
    def split(self, y):
        """The unknowns of each harmonic."""
        return [y[self.offsets[j]:self.offsets[j + 1]] for j in range(self.K + 1)]

    def block(self, k: int) -> slice:
        """The slice of y holding harmonic k (a multiple of n)."""
        j = self.ks.index(k)
        return slice(self.offsets[j], self.offsets[j + 1])

    def multipliers(self, k: int) -> np.ndarray:
        """The indices of the multipliers of harmonic k's joint conditions (one per joint;
        none on a one-piece shell)."""
        j = self.ks.index(k)
        return self.ny + j + (self.K + 1) * np.arange(self.joints)

    def indices(self, k: int) -> np.ndarray:
        """The indices of harmonic k's unknowns and of its joint conditions' multipliers: the
        system an axisymmetric state's harmonic k decouples into."""
        b = self.block(k)
        return np.concatenate([np.arange(b.start, b.stop), self.multipliers(k)])

    def displacement(self, U) -> np.ndarray:
        """U with its multipliers set to zero: the displacement part, as a vector of the
        same size (the monitor of a mode's amplitude, phi . U, reads only that part)."""
        out = np.array(U, dtype=float)
        out[self.ny:] = 0.0
        return out

    @cached_property
    def origin(self) -> np.ndarray:
        """The base equilibrium as unknowns: zero displacement and, with joints, the
        multipliers that make it stationary, J^T lambda = dE/dy (least squares: the base is
        stationary to its own solver's tolerance)."""
        U = np.zeros(self.size)
        if self.joints:
            g, Hm = self.hessian(U, gradient=True)
            U[self.ny:] = np.linalg.lstsq(-Hm[:self.ny, self.ny:], g[:self.ny], rcond=None)[0]
        return U

    def coefficients(self, y) -> list:
        """The Chebyshev coefficients of each harmonic (layout of
        :func:`shellbvp.harmonics._derivative_operators`: piece, component, coefficient)."""
        return [Z @ yk for Z, yk in zip(self.Z, self.split(np.asarray(y)))]

    def reduce(self, coefficients, multipliers=None) -> np.ndarray:
        """The unknowns closest in the mass norm to the given Chebyshev coefficients (one
        vector per harmonic; rigid motions and inadmissible parts dropped), with the given
        joint multipliers (default zero)."""
        out = []
        for k, Z, c in zip(self.ks, self.Z, coefficients):
            M = _H._mass(self.base, self._D, k)
            out.append(Z.T @ (M @ np.asarray(c, dtype=float)))
        lam = np.zeros(self.size - self.ny) if multipliers is None else multipliers
        return np.concatenate(out + [np.asarray(lam, dtype=float)])

    def mass(self, k: int) -> np.ndarray:
        """The mass matrix int int |dx|^2 dA_target of harmonic k on its Chebyshev
        coefficients (the identity on its unknowns y)."""
        return _H._mass(self.base, self._D, k)

    @cached_property
    def _trig(self):
        ks = np.array(self.ks, dtype=float)[:, None]
        return np.cos(ks * self.w), np.sin(ks * self.w), ks

    @cached_property
    def _data(self) -> dict:
        """The arrays the compiled programs take (all but y and the parameter's fields)."""
        C, S, ks = self._trig
        return dict(G=tuple(self.G), x0=self.x0, C=C, S=S, ks=ks, change=self._change,
                    wq=self.base.wq.reshape(-1), ww=self.w_weights,
                    ends=tuple(tuple(rows) for rows in self._end_rows),
                    lids=np.array([sigma * z for _, sigma, z in self._lids]),
                    lid_signs=np.array([sigma for _, sigma, _ in self._lids]),
                    joints=self._joints,
                    rims=np.array([self.base.ends[(0, "a")][2],
                                   self.base.ends[(self.base.s.shape[0] - 1, "b")][2]]))

    @cached_property
    def _programs(self) -> dict:
        sc = self.eq.scene
        return _programs(sc.model, sc.material, tuple(e for e, _, _ in self._lids),
                         self.joints)

    def _args(self, p):
        p = self._check_p(p)
        P, loads = self._scalars(p)
        sc = self.eq.scene
        return (self._data, self.fields(p), P, loads, float(sc.material_parameter),
                float(sc.h))

    def energy(self, y, p=None) -> float:
        """E(y; p) per mu* h0 R0^2 (module docstring)."""
        return float(self._programs["energy"](np.asarray(y, dtype=float), *self._args(p)))

    def gradient(self, y, p=None) -> np.ndarray:
        """dE/dy (jax.grad)."""
        return np.asarray(self._programs["grad"](np.asarray(y, dtype=float), *self._args(p)))

    def hvp(self, y, v, p=None) -> np.ndarray:
        """The Hessian of E at y applied to v (a jvp of the gradient)."""
        return np.asarray(self._programs["hvp"](np.asarray(y, dtype=float),
                                                np.asarray(v, dtype=float), *self._args(p)))

    def parameter_gradient(self, y, p=None) -> np.ndarray:
        """d(dE/dy)/dp at y: the gradient's rate in the parameter through the fields, the
        pressure and the dead loads (a jvp of ``gradient``, exact)."""
        p = self._check_p(p)
        return np.asarray(self._programs["grad_p"](np.asarray(y, dtype=float),
                                                   *self._args(p), *self._rates(p)))

    def hessian_rate(self, y, v, p=None) -> np.ndarray:
        """d(H v)/dp at fixed y: the Hessian's rate in the parameter through the fields, the
        pressure and the dead loads, applied to v (a jvp of ``hvp``, exact)."""
        p = self._check_p(p)
        return np.asarray(self._programs["hvp_p"](np.asarray(y, dtype=float),
                                                  np.asarray(v, dtype=float),
                                                  *self._args(p), *self._rates(p)))

    def third(self, y, u, v, p=None) -> np.ndarray:
        """D^3 E(y)[u, v, .]: the Hessian's derivative along v applied to u (exact)."""
        return np.asarray(self._programs["d3"](*(np.asarray(a, dtype=float) for a in (y, u, v)),
                                               *self._args(p)))

    def fourth(self, y, u, p=None) -> float:
        """D^4 E(y)[u, u, u, u] (exact)."""
        return float(self._programs["d4"](np.asarray(y, dtype=float),
                                          np.asarray(u, dtype=float), *self._args(p)))

    def state(self, y) -> np.ndarray:
        """(P m, J, 18): the local numbers (x, x_s, x_o, x_ss, x_so, x_oo) at every point."""
        return np.asarray(self._programs["q"](np.asarray(y, dtype=float), self._data))

    def hessian(self, y, p=None, *, gradient: bool = False):
        """The Hessian of E at y as a dense (size, size) matrix, by the chain rule from the
        density's exact Hessian in the 18 local numbers at every point (module docstring);
        with ``gradient=True`` also the gradient assembled the same way: (g, H)."""
        from threadpoolctl import threadpool_limits

        _, F, P, loads, mat, h = self._args(p)
        y = np.asarray(y, dtype=float)
        q = self.state(y)                                           # (P m, J, 18)
        Pm, J = q.shape[:2]
        change = self._change
        kernel = _H._hessian_kernel(self.eq.scene.model, self.eq.scene.material,
                                    change is not None)
        extra = () if change is None else (change.reshape(Pm * J, 6),)
        g18, H18 = kernel(q.reshape(Pm * J, 18), np.repeat(F, J, axis=0), *extra, mat, h, P)
        g18 = np.asarray(g18).reshape(Pm, J, 18)
        H18 = np.asarray(H18).reshape(Pm, J, 18, 18)
        with threadpool_limits(1, user_api="blas"):
            nK = self.K + 1
            T = self._maps().reshape(J, 18, nK * 9)                 # (J, 18, 9 (K + 1))
            wgt = self.base.wq.reshape(-1)[:, None] * self.w_weights[None, :]
            HT = np.matmul(H18 * wgt[:, :, None, None], T)          # (P m, J, 18, 9 (K + 1))
            A = np.matmul(np.swapaxes(T, 1, 2), HT).sum(axis=1)    # (P m, 9 (K + 1), ...)
            A = A.reshape(Pm, nK, 9, nK, 9)
            gd = np.einsum("jqa,sjq->sa", T, g18 * wgt[:, :, None]).reshape(Pm, nK, 9)
            Hm = np.zeros((self.size, self.size))
            g = np.zeros(self.size)
            # (P m 9, size_k): the rows (U, U', U'') of each harmonic, point-major
            Gs = [np.ascontiguousarray(Gk.transpose(1, 0, 2)).reshape(Pm * 9, -1)
                  for Gk in self.G]
            for k in range(nK):
                bk = slice(self.offsets[k], self.offsets[k + 1])
                g[bk] = Gs[k].T @ gd[:, k].reshape(-1)
                for l in range(k, nK):
                    bl = slice(self.offsets[l], self.offsets[l + 1])
                    AG = np.matmul(A[:, k, :, l, :], Gs[l].reshape(Pm, 9, -1))
                    B = Gs[k].T @ AG.reshape(Pm * 9, -1)
                    Hm[bk, bl] = B
                    if l != k:
                        Hm[bl, bk] = B.T
            Hm += self._lid_hessian(P)
            g -= self._load_gradient(loads)
            g += self._lid_gradient(y, P)
            self._add_joints(y, g, Hm)
        Hm = (Hm + Hm.T) / 2
        return (g, Hm) if gradient else Hm

    def joint_values(self, U, i: int = 0) -> np.ndarray:
        """(K + 1, 9): per harmonic the displacement at joint i and its s-derivative on the
        left and on the right, (U, U'_left, U'_right) (components r, omega, z)."""
        return (self._joints[i]["R"] @ np.asarray(U)[:self.ny]).reshape(-1, 9)

    def joint_angles(self, U, i: int = 0, *, points: int | None = None) -> np.ndarray:
        """The angle between the tangents across joint i less its reference value, at every
        omega of the full-circle rule with ``points`` per period (default 8 times this
        rule's): only its projections on the class's harmonics are imposed, so this is the
        pointwise error of a state's joint (a check)."""
        fine = self.with_points(8 * self.points if points is None else points,
                                full_period=True)
        C, S, ks = fine._trig
        return np.asarray(_joint_condition(self.joint_values(U, i).reshape(-1),
                                           self._joints[i], C, S, ks, None))

    def _add_joints(self, U, g, Hm):
        """Adds the joint conditions' part of the Lagrangian E - lambda . c(y) to its gradient
        and Hessian: -J^T lambda and -c; -sum lambda_i R^T c_i'' R and the borders -J."""
        C, S, ks = self._trig
        nK, ny = self.K + 1, self.ny
        for i, jt in enumerate(self._joints):
            rows = slice(ny + i * nK, ny + (i + 1) * nK)
            V = self.joint_values(U, i).reshape(-1)
            c, dc, Hc = (np.asarray(a) for a in _joint_derivatives()(
                V, U[rows], jt, C, S, ks, self.w_weights))
            Jc = dc @ jt["R"]                                        # (K + 1, ny)
            g[:ny] -= Jc.T @ U[rows]
            g[rows] -= c
            Hm[:ny, :ny] -= jt["R"].T @ Hc @ jt["R"]
            Hm[:ny, rows] -= Jc.T
            Hm[rows, :ny] -= Jc

    def _maps(self) -> np.ndarray:
        """T (J, 18, K + 1, 9): the local numbers' increments at omega_j from (U, U', U'') of
        each harmonic: diag(cos or sin) L_k (:func:`shellbvp.harmonics._local_map`)."""
        C, S, _ = self._trig
        out = np.zeros((self.w.size, 18, self.K + 1, 9))
        cos = np.zeros(18, bool)
        cos[list(_COS)] = True
        for j, k in enumerate(self.ks):
            L = _H._local_map(k)
            phi = np.where(cos[None, :], C[j][:, None], S[j][:, None])   # (J, 18)
            out[:, :, j, :] = phi[:, :, None] * L[None]
        return out

    def _load_gradient(self, loads) -> np.ndarray:
        g = np.zeros(self.size)
        for e in range(2):
            rows = self._end_rows[e][0]
            g[self.block(0)] += 2 * math.pi * (loads[e, 0] * rows[0] + loads[e, 1] * rows[2])
        return g

    def _lid_parts(self, e):
        """(R, Hq, lin) of the lid at end e: R the rows giving (U_r^k, U_w^k) there from y;
        the area the rim encloses, 1/2 sum_j ww_j [X_r (X_w,o + X_r) - X_w (X_r,o - X_w)]
        with X_r = r_e + U_r . cos, X_w = U_w . sin, is quadratic in them: pi r_e^2 +
        lin . u + u . Hq u / 2 (the rule is exact: a trig polynomial of degree 2 K n)."""
        C, S, ks = self._trig
        ww, kc, nK = self.w_weights, ks[:, 0], self.K + 1
        r_e = self._data["rims"][e]
        CC, SS = (C * ww) @ C.T, (S * ww) @ S.T
        Hrw = 0.5 * (CC * kc[None, :] + SS * kc[:, None])
        Hq = np.block([[CC, Hrw], [Hrw.T, SS]])
        lin = np.concatenate([r_e * (C @ ww), 0.5 * r_e * kc * (C @ ww)])
        R = np.zeros((2 * nK, self.size))
        for j in range(nK):
            rows = self._end_rows[e][j]
            R[j, self.offsets[j]:self.offsets[j + 1]] = rows[0]
            R[nK + j, self.offsets[j]:self.offsets[j + 1]] = rows[1]
        return R, Hq, lin

    def _lid_hessian(self, P) -> np.ndarray:
        Hm = np.zeros((self.size, self.size))
        for e, sigma, z in self._lids:
            R, Hq, _ = self._lid_parts(e)
            Hm += P * sigma * z / 3.0 * R.T @ Hq @ R
        return Hm

    def _lid_gradient(self, y, P) -> np.ndarray:
        """The lids' gradient: the flat lid's, and the rim's axial lift (the energy's
        ``lift``), which on the admissible set is linear, (1/3) sigma pi r_e^2 U_z^0: every
        end in :data:`shellbvp.harmonics.LID_ENDS` holds either U_z (in its plane) or
        U_r and U_w (a diaphragm) on its rim, so the lift's products of the two vanish there,
        and with them its Hessian."""
        g = np.zeros(self.size)
        C, _, _ = self._trig
        mean = C @ self.w_weights                      # int cos(k omega) domega per harmonic
        for e, sigma, z in self._lids:
            R, Hq, lin = self._lid_parts(e)
            g += P * sigma * z / 3.0 * R.T @ (Hq @ (R @ y) + lin)
            r_e = self._data["rims"][e]
            for j in range(self.K + 1):
                rows = self._end_rows[e][j][2]
                g[self.offsets[j]:self.offsets[j + 1]] += (P * sigma / 3.0 * 0.5 * r_e**2
                                                           * mean[j] * rows)
        return g

    def energy_gradient_hessian(self, y, p=None):
        """(E, gradient, Hessian) at y and parameter p: the Newton building block."""
        g, H = self.hessian(y, p, gradient=True)
        return self.energy(y, p), g, H

    # --- checks and uses ------------------------------------------------------------------
    def block_modes(self, k: int, y=None, p=None, *, hessian=None):
        """(eigenvalues, modes) of the Hessian's block k at y (default the base state,
        :attr:`origin`) in the mass norm, ascending: :func:`shellbvp.harmonics.modes`' at an
        axisymmetric state. With joints, those of the Lagrangian's Hessian on the null space
        of harmonic k's linearised joint conditions (its second variation on the admissible
        set), each mode's multipliers from H_yy phi + H_y,lambda phi_lambda = mu phi. The
        modes are columns of full vectors (unit mass norm in y)."""
        y = self.origin if y is None else y
        H = self.hessian(y, p) if hessian is None else hessian
        b, m = self.block(k), self.multipliers(k)
        Hb = H[b, b]
        vals, Y = _constrained_eigh(Hb, H[m, b])
        out = np.zeros((self.size, Y.shape[1]))
        out[b] = Y
        if m.size:
            out[m] = np.linalg.lstsq(H[b, m], Y * vals - Hb @ Y, rcond=None)[0]
        return vals, out

    def eigenvalues(self, y, p=None, count: int = 1) -> np.ndarray:
        """The ``count`` smallest eigenvalues of the Hessian at y on the whole class (with
        joints, the Lagrangian's on the null space of the linearised joints: a negative one
        is an unstable direction within the class)."""
        Hm = self.hessian(y, p)
        return _constrained_eigh(Hm[:self.ny, :self.ny], Hm[self.ny:, :self.ny])[0][:count]

    def block_eigenvalues(self, k: int, y=None, p=None, count: int = 3) -> np.ndarray:
        """The ``count`` smallest eigenvalues of block k (:meth:`block_modes`)."""
        return self.block_modes(k, y, p)[0][:count]

    def mode(self, k: int, y=None, p=None) -> np.ndarray:
        """The lowest mode of block k (:meth:`block_modes`), as a full vector."""
        return self.block_modes(k, y, p)[1][:, 0]

    def newton(self, y0, p=None, *, tol: float = 1e-10, max_iter: int = 25) -> NewtonResult:
        """Newton's method for a stationary point of E(.; p) from y0 (no line search): stops
        when the step's size is below tol (1 + |y|)."""
        y = np.array(y0, dtype=float)
        history = []
        for _ in range(max_iter):
            g, H = self.hessian(y, p, gradient=True)
            dy = np.linalg.solve(H, -g)
            y = y + dy
            history.append((float(np.linalg.norm(g)), float(np.linalg.norm(dy))))
            if history[-1][1] < tol * (1 + np.linalg.norm(y)):
                return NewtonResult(y, True, history, p)
        return NewtonResult(y, False, history, p)


def _constrained_eigh(H, J):
    """(eigenvalues, eigenvectors) of the symmetric H on the null space of the rows J (-J
    the Lagrangian Hessian's border; none: H itself), the vectors in H's coordinates."""
    from scipy.linalg import null_space

    N = null_space(J) if J.size else np.eye(H.shape[0])
    vals, W = np.linalg.eigh(N.T @ H @ N)
    return vals, N @ W


def _synthesis(y, data):
    """q (P m, J, 18): the local numbers (x, x_s, x_o, x_ss, x_so, x_oo) in the frame
    (e_r, e_omega, e_z) at every Gauss point and omega_j, from the unknowns y (JAX)."""
    import jax.numpy as jnp

    C, S, ks, x0 = data["C"], data["S"], data["ks"], data["x0"]
    parts, o = [], 0
    for G in data["G"]:
        parts.append(G @ y[o:o + G.shape[-1]])
        o += G.shape[-1]
    d = jnp.stack(parts).reshape(len(parts), 3, 3, -1)   # (harmonic, order, component, point)
    ur, uw, uz = d[:, :, 0], d[:, :, 1], d[:, :, 2]      # (harmonic, order, point)

    def syn(u, T):
        return jnp.einsum("kop,kj->opj", u, T)

    Xr = x0[:, 0, :, None] + syn(ur, C)
    Xw = syn(uw, S)
    Xz = x0[:, 2, :, None] + syn(uz, C)
    Xr_o, Xr_oo = syn(ur, -ks * S), syn(ur, -ks**2 * C)
    Xw_o, Xw_oo = syn(uw, ks * C), syn(uw, -ks**2 * S)
    Xz_o, Xz_oo = syn(uz, -ks * S), syn(uz, -ks**2 * C)
    x = jnp.stack([Xr[0], Xw[0], Xz[0]])
    xs = jnp.stack([Xr[1], Xw[1], Xz[1]])
    xss = jnp.stack([Xr[2], Xw[2], Xz[2]])
    xo = jnp.stack([Xr_o[0] - Xw[0], Xw_o[0] + Xr[0], Xz_o[0]])
    xso = jnp.stack([Xr_o[1] - Xw[1], Xw_o[1] + Xr[1], Xz_o[1]])
    xoo = jnp.stack([Xr_oo[0] - 2 * Xw_o[0] - Xr[0], Xw_oo[0] + 2 * Xr_o[0] - Xw[0],
                     Xz_oo[0]])
    return jnp.concatenate([x, xs, xo, xss, xso, xoo]).transpose(1, 2, 0)


def _joint_condition(V, joint, C, S, ks, ww):
    """c (K + 1,): the joint's condition per harmonic, int cos(k omega) (angle(omega) -
    reference angle) domega, angle the signed angle between the tangents on either side about
    the hoop direction (:func:`shellbvp.harmonics._joint_angle`): the joint is rigid. ``V``
    (9 (K + 1),): per harmonic U there, U' on the left and U' on the right (the joint's
    rows times y). The projections on the class's harmonics are the conditions a Galerkin
    method imposes: the multiplier field (the joint's moment) is discretised as the
    displacement is (JAX).
    ``ww`` None: the angle's error at every omega instead (a check)."""
    import jax.numpy as jnp

    V = V.reshape(-1, 9)
    k = ks[:, 0]

    def vec(a, base):       # (r, omega, z) of the harmonics' parts a (K + 1, 3) + base
        return jnp.stack([base[0] + a[:, 0] @ C, base[1] + a[:, 1] @ S, base[2] + a[:, 2] @ C])

    x = vec(V[:, 0:3], joint["x0"])
    xo = jnp.stack([(-k * V[:, 0]) @ S - x[1], (k * V[:, 1]) @ C + x[0], (-k * V[:, 2]) @ S])
    xl, xr = vec(V[:, 3:6], joint["tl"]), vec(V[:, 6:9], joint["tr"])
    angle = _H._joint_angle(xl, xr, xo) - joint["angle"]
    return angle if ww is None else C @ (ww * angle)


@lru_cache(maxsize=None)
def _joint_derivatives():
    """(c, dc/dV, the Hessian of lambda . c in V) of :func:`_joint_condition` (compiled)."""
    from .jaxsetup import jax

    def parts(V, lam, joint, C, S, ks, ww):
        c = _joint_condition(V, joint, C, S, ks, ww)
        dc = jax.jacfwd(_joint_condition)(V, joint, C, S, ks, ww)
        Hc = jax.hessian(lambda v: lam @ _joint_condition(v, joint, C, S, ks, ww))(V)
        return c, dc, Hc

    return jax.jit(parts)


@lru_cache(maxsize=None)
def _programs(model: str, material: str, lid_ends: tuple, joints: int = 0) -> dict:
    """The compiled energy, its gradient and Hessian-vector product, and the synthesis, for
    one energy (model, material) and the ends that carry a pressure lid; the arrays are
    arguments, so every discretisation of the same shapes shares the programs."""
    from .jaxsetup import jax
    import jax.numpy as jnp

    from . import kinematics as Kin
    from .forms import reduced_energy

    def density(q, F, P, mat, h, change=None):
        """The energy per ds domega at a point: W t sqrt(det abar) + (P / 3) x . (x_s x x_o)
        (``change``: the target forms' change there, an imperfect reference)."""
        ab = _H._forms(q)
        a = jnp.array([[ab[0], ab[1]], [ab[1], ab[2]]])
        b = jnp.array([[ab[3], ab[4]], [ab[4], ab[5]]])
        abar, bbar, area = Kin.target_matrices(F, change)
        kw = dict(nu=mat) if material == "koiter" else dict(lam=mat)
        rb = Kin.RHOB.start
        W = reduced_energy(a, b, abar, bbar, h=h * F[Kin.THICKNESS], model=model,
                           material=material, rhob=(F[rb], F[rb + 1], F[rb + 2]), **kw)
        return W * area + P * _H._triple(q[0:3], q[3:6], q[6:9]) / 3.0

    dens = jax.vmap(jax.vmap(density, in_axes=(0, None, None, None, None)),
                    in_axes=(0, 0, None, None, None))
    dens_imperfect = jax.vmap(jax.vmap(density, in_axes=(0, None, None, None, None, 0)),
                              in_axes=(0, 0, None, None, None, 0))

    def end_values(y, data, e):
        """(3 components, harmonic): U^k at end e."""
        out, o = [], 0
        for rows in data["ends"][e]:
            out.append(rows @ y[o:o + rows.shape[-1]])
            o += rows.shape[-1]
        return jnp.stack(out, axis=1)

    def energy(y, data, F, P, loads, mat, h):
        q = _synthesis(y, data)
        ww = data["ww"]
        d = dens(q, F, P, mat, h) if data["change"] is None else \
            dens_imperfect(q, F, P, mat, h, data["change"])
        E = jnp.sum(data["wq"][:, None] * ww[None, :] * d)
        for e in range(2):          # the dead end loads (per radian), harmonic 0 only
            U = end_values(y, data, e)
            E = E - 2 * math.pi * (loads[e, 0] * U[0, 0] + loads[e, 1] * U[2, 0])
        C, S, ks = data["C"], data["S"], data["ks"][:, 0]
        for j, e in enumerate(lid_ends):
            # the lid ruled from the axis to the rim (r_e + dx) at its height z_e + U_z:
            # (1/3) sigma 1/2 int (z_e + U_z) (x x x_o) . e_z domega (exact: a trig
            # polynomial); U_z = 0 on the rim of an end that keeps its plane (the flat lid,
            # z_e times the area the rim encloses), U_r = U_w = 0 on a diaphragm's
            U = end_values(y, data, e)
            Xr, Xw = data["rims"][e] + U[0] @ C, U[1] @ S
            Xr_o, Xw_o = (-ks * U[0]) @ S, (ks * U[1]) @ C
            swept = ww * (Xr * (Xw_o + Xr) - Xw * (Xr_o - Xw))
            area = 0.5 * jnp.sum(swept)
            lift = 0.5 * jnp.sum(swept * (U[2] @ C))
            E = E + P * (data["lids"][j] * area + data["lid_signs"][j] * lift) / 3.0
        ny, nK = y.shape[0] - joints * C.shape[0], C.shape[0]
        for i, jt in enumerate(data["joints"]):     # the Lagrangian E - lambda . c
            lam = y[ny + i * nK:ny + (i + 1) * nK]
            E = E - lam @ _joint_condition(jt["R"] @ y[:ny], jt, C, S, data["ks"], ww)
        return E

    grad = jax.grad(energy)

    def hvp(y, v, *args):
        return jax.jvp(lambda u: grad(u, *args), (y,), (v,))[1]

    def grad_p(y, data, F, P, loads, mat, h, dF, dP, dloads):
        return jax.jvp(lambda F_, P_, L_: grad(y, data, F_, P_, L_, mat, h),
                       (F, P, loads), (dF, dP, dloads))[1]

    def hvp_p(y, v, data, F, P, loads, mat, h, dF, dP, dloads):
        return jax.jvp(lambda F_, P_, L_: hvp(y, v, data, F_, P_, L_, mat, h),
                       (F, P, loads), (dF, dP, dloads))[1]

    def grad_e(y, data, F, P, loads, mat, h, dchange):
        """The gradient's rate along a change of the target forms (from none)."""
        return jax.jvp(lambda c: grad(y, dict(data, change=c), F, P, loads, mat, h),
                       (jnp.zeros_like(dchange),), (dchange,))[1]

    def d3(y, u, v, *args):
        return jax.jvp(lambda z: hvp(z, u, *args), (y,), (v,))[1]

    def d4(y, u, *args):
        return u @ jax.jvp(lambda z: d3(z, u, u, *args), (y,), (u,))[1]

    return dict(energy=jax.jit(energy), grad=jax.jit(grad), hvp=jax.jit(hvp),
                grad_p=jax.jit(grad_p), hvp_p=jax.jit(hvp_p), grad_e=jax.jit(grad_e),
                d3=jax.jit(d3), d4=jax.jit(d4),
                q=jax.jit(_synthesis))


def _admissible(base, D, k: int):
    """(Z, rigid): a mass-orthonormal basis of harmonic k's admissible coefficients (the
    rows of :func:`shellbvp.harmonics._constraints` but the joints' rotation conditions,
    U_w^0 = 0 at k = 0, the complement of
    the rigid motions in the class) and the rigid motions removed (name, coefficients)."""
    from scipy.linalg import cholesky, null_space, qr, solve_triangular

    P = base.s.shape[0]
    nb = base.degree + 1
    ndof = 3 * nb * P
    A = _H._constraints(base, k)
    if P > 1:       # the joints' rotation conditions are imposed nonlinearly, with multipliers
        A = np.delete(A, [_H._interface_row(base, k, i) for i in range(P - 1)], axis=0)
    rows = [A] if A.size else []
    if k == 0:
        W = np.zeros((nb * P, ndof))
        for i in range(P):
            W[i * nb:(i + 1) * nb, (3 * i + 1) * nb:(3 * i + 2) * nb] = np.eye(nb)
        rows.append(W)
    Z = null_space(np.vstack(rows)) if rows else np.eye(ndof)
    M = _H._mass(base, D, k)
    rigid = [(name, vals) for name, vals in _H._rigid(base, k)
             if not (k == 0 and name == "rotation about the axis")]
    removed = []
    if rigid:
        Mz = Z.T @ M @ Z
        B = []
        w = _H._mass_weights(base, k)
        for name, vals in rigid:
            rhs = sum(D[c].T @ (w * vals[c]) for c in range(3))
            y = np.linalg.solve(Mz, Z.T @ rhs)
            removed.append((name, Z @ y))
            B.append(y)
        Qb, _ = qr(Mz @ np.array(B).T, mode="full")
        Z = Z @ Qb[:, len(B):]
    L = cholesky(Z.T @ M @ Z, lower=True)
    return solve_triangular(L, Z.T, lower=True).T, tuple(removed)


def discretise(eq: Equilibrium, n: int, K: int = 2, **kwargs) -> Fourier2D:
    """:class:`Fourier2D` of ``eq`` on the class of harmonic n with harmonics 0..K n."""
    return Fourier2D(eq, n, K, **kwargs)
