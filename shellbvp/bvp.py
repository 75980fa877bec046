"""The axisymmetric boundary-value problem of a scene, written once for every method.

A :class:`ShellBVP` turns a :class:`shellbvp.Scene` into a multi-point first-order BVP
for y = (r, z, theta, m, f_r, f_z) (m, f = 12/h^2 times the moment and forces, so that
bending and membrane unknowns have the same size):

* **pieces**: the meridian s in [eps, theta] is cut at the scene's interfaces into pieces
  [a_i, b_i], each mapped to the piece coordinate t in [0, 1] (dy/dt = (b_i - a_i) f). The
  methods keep one state per piece and impose continuity of all six components at every
  interface, so a jump of the stimulus is exact (the meridional stretch may jump there);
* **pole**, at s = eps = ``POLE_OFFSET`` theta: the pole is a regular singular point whose
  regular solution has g1 lam1 = g2 lam2 + O(s^2) (equal actual stretches: r ~ g1 lam1 s and
  lam2 = r / (g2 sin s); lam1 = lam2 only without a metric stimulus), k1 = k2 + O(s^2) and
  z(0) = z(eps) + r theta / 2 + O(eps^4); the conditions are g1 lam1 = g2 lam2, k1 = k2 and
  z(0) = 0 (apex ``held``) or f_z = 0 (apex ``free``). Their O(eps^2) relative error gives
  an O(eps^4) error in the solution. Where the target curvature is anisotropic at the apex
  (kb1 != kb2) the solution is not regular: k1 - k2 tends to a nonzero constant and both
  curvatures grow like log s (as for a plate with anisotropic natural curvature: the moment
  balance (s M1)' = M2 near s = 0 with M linear in k forces k1 - k2 = (1 - nu)(k*1 - k*2)/2,
  nu = W_k1k2 / W_k1k1, k* where the moments vanish). There the condition is k1 - k2 = A,
  which excludes the 1/s mode as k1 = k2 does at a regular apex: the shape and w converge,
  the apex curvatures do not (they diverge like log s). A target metric anisotropic at the
  apex (g1 != g2, a cone) would need the same treatment of the stretches; it keeps
  g1 lam1 = g2 lam2 at eps, which is exact only for a regular membrane state;
* **edge**, at s = theta: m = f_r = f_z = 0 (``free``) or r, z, theta at the reference
  sphere's values (``clamped``);
* **load**: a scene's uniform pressure (``Scene.pressure``) enters the compiled equations as a
  fifth field beside (g1, g2, kb1, kb2), through its potential P V
  (:mod:`shellbvp.euler_lagrange`);
* **observable** (the branch monitor), in units of the rise H = 1 - cos theta: for a free
  edge the vertical displacement of the edge relative to the apex, for a clamped edge that
  of the apex relative to the edge (positive along +z, the cap's axis at the apex).

The reference mid-surface is r = sin s, z = cos s - 1, theta = s (apex at the origin). All
of the above is JAX code compiled once per (model, material, fields, pieces, conditions); the
methods in :mod:`shellbvp.methods` only discretise it. The nodal right-hand side is
evaluated in chunks padded to one of a few sizes (``CHUNKS``), so that a change of
resolution reuses a compiled program instead of compiling a new one.
"""

from __future__ import annotations

import math

import numpy as np

from .bvp_derivatives import Derivatives
from .errors import ConvergenceError
from .kernels import kernels, observable_and_gradient, untraceable
from .meridian import MeridianStates
from .nodal import Collocated, Hint, Nodal, carried_roots, flat_nodes
from .scene import Scene

__all__ = ["ShellBVP", "Nodal", "Collocated", "reference_state", "POLE_OFFSET", "CHUNKS"]

#: eps / theta. The pole conditions are exact to O(eps^2), so the solution is good to
#: O(eps^4) = 1e-16 relative: below every tolerance the solvers reach, while eps stays far
#: enough from s = 0 that lam2 = r / (g2 sin s) is evaluated without cancellation.
POLE_OFFSET = 1e-4
#: nodes are evaluated in chunks padded to one of these sizes (larger sets in chunks of the
#: last), so that a change of resolution mostly reuses a compiled program (each costs
#: seconds of compilation for a relaxed model): every Chebyshev degree of a kappa_s at
#: tol 1e-6 ... 1e-8 on the default cap (the branch at N = 16, the ladder at 20 ... 36,
#: 17 ... 37 nodes) shares the program of 40 (padding 17 nodes to 40 costs ~45 us per
#: evaluation relaxed; a program of 24 took ~3 s more of a first run's compilation);
#: geometric above, so that solve_bvp's ever-changing meshes reuse ~a dozen programs.
#: (Fixed chunks of 16 or 24 nodes, dispatched together so that every degree runs on the
#: same programs, cost 30-50 % more per kappa_s: each compiled call has a fixed cost.)
CHUNKS = (8, 16, 40, 56, 72, 96, 128, 192, 256, 384, 512)
#: largest relative distance between a state and the states of a warm start that is carried
#: to another discretisation with it (:meth:`ShellBVP.carried_hint`)
HINT_CARRY = 1e-3
#: round-off scatter of a fold parameter, in eps (1 + |p|) / h (:meth:`ShellBVP.round_off`)
ROUND_OFF_PER_H = 5.0
#: Ciarlet-Geymonat lam above which that scatter grows like lam (the forces of the lam term
#: carry round-off ~ lam eps): scatter / (ROUND_OFF_PER_H eps (1 + |p|) / h) of folds located
#: at degrees 40-68 (relaxed, Theta = pi/6, h = 0.01) was 0.6-0.7 at lam = 1-100, 5.5 at
#: 1e3 and 52 at 1e4 (plane strain, which snaps up to lam = 100: 0.4-1.0)
ROUND_OFF_LAM = 100.0


def reference_state(s):
    """The undeformed cap: (r, z, theta, m, f_r, f_z) = (sin s, cos s - 1, s, 0, 0, 0)."""
    s = np.asarray(s, dtype=float)
    z0 = np.zeros_like(s)
    return np.stack([np.sin(s), np.cos(s) - 1.0, s, z0, z0, z0])


def _chunk(n: int) -> int:
    return next((c for c in CHUNKS if c >= n), CHUNKS[-1])

#: parameter values at which the fields are probed for anisotropy at the apex
APEX_PROBES = (0.0, 1.0, 10.0, 100.0)


def _anisotropic_apex(scene, eps) -> bool:
    """Whether the target curvature is anisotropic at the apex (kb1 != kb2 at s = eps for
    some probed parameter value): then the pole condition k1 = k2 becomes k1 - k2 = A
    (module docstring), which costs third derivatives of W in the compiled boundary rows."""
    for p in APEX_PROBES:
        F = [float(v) for v in scene.field_values(0, eps, p)]
        if F[2] != F[3] and all(math.isfinite(v) for v in F):
            return True
    return False


class ShellBVP(Derivatives, MeridianStates):
    """The multi-point BVP of ``scene`` (see the module docstring).

    Arguments:
        scene: the problem.
        eps: pole offset (default ``POLE_OFFSET * theta``); must be below a tenth of the
            first piece.

    Attributes:
        scene, eps, P (number of pieces), a, b (piece ends in s), rise (H = 1 - cos theta).
    """

    n = 6
    #: relative error of the derivatives :meth:`rhs` returns: round-off, for they are
    #: analytic and the inner roots' derivatives (implicit differentiation) are taken at
    #: the roots themselves, converged to round-off, never at an earlier iterate
    jacobian_error = 0.0

    def __init__(self, scene: Scene, eps: float | None = None):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a shellbvp.Scene, got {type(scene).__name__}")
        eps_given = eps
        eps = POLE_OFFSET * scene.theta if eps is None else float(eps)
        first = scene.breaks[0] if scene.breaks else scene.theta
        if not (0 < eps < first / 10):
            raise ValueError(f"eps must lie in (0, {first / 10:g}) (a tenth of the first "
                             f"piece), got {eps!r}")
        self.scene, self.eps = scene, eps
        #: d eps / d theta: the default pole offset scales with theta, a given one is fixed
        self.eps_per_theta = POLE_OFFSET if eps_given is None else 0.0
        self.a = np.array((eps,) + scene.breaks)
        self.b = np.array(scene.breaks + (scene.theta,))
        self.P = scene.pieces
        self.rise = 1.0 - math.cos(scene.theta)
        n_c = len(scene.field_parameters)
        problem = untraceable(scene.fields, self.P, scene.pressure, n_c)
        if problem:
            raise ValueError(problem)
        self._layouts = {}
        #: kb1 != kb2 at the apex: curvatures diverge like log s there (module docstring)
        self.anisotropic_apex = _anisotropic_apex(scene, eps)
        self._k = kernels(scene.model, scene.material, float(scene.rhob1),
                           bool(scene.metric), scene.fields, self.P, scene.apex, scene.edge,
                           self.anisotropic_apex, scene.pressure, n_c)
        #: the field parameters, an argument of every compiled function of the fields
        self.field_parameters = np.array(scene.field_parameters, dtype=float)
        self.evaluations = 0

    def round_off(self, p: float) -> float:
        """Round-off scatter of a fold's parameter value p: ``ROUND_OFF_PER_H`` eps (1 + |p|)
        / h, times lam / ``ROUND_OFF_LAM`` for a Ciarlet-Geymonat material stiffer than
        that. Measured on caps (values at converged degrees, different degrees and Newton
        paths): ~1e-13 relative at h = 0.01, 2e-13 at h = 1e-3, 1.3e-12 at h = 1e-4 (the
        moment and forces enter the equations scaled by 12 / h^2), and growing like lam
        above lam ~ 100 (7e-13 relative at lam = 1e3, 7e-12 at 1e4). A change between rungs
        of the ladder does not see it, so fold error estimates are at least this."""
        sc = self.scene
        stiff = max(1.0, sc.lam / ROUND_OFF_LAM) if sc.material == "cg" else 1.0
        return ROUND_OFF_PER_H * np.finfo(float).eps * (1.0 + abs(p)) / sc.h * stiff

    @property
    def lengths(self) -> np.ndarray:
        return self.b - self.a

    def s_of(self, i: int, t):
        """s on piece i at the piece coordinate t in [0, 1]."""
        return self.a[i] + (self.b[i] - self.a[i]) * np.asarray(t, dtype=float)

    def reference(self, s):
        """The undeformed state at s (the default guess)."""
        return reference_state(s)

    # --- nodal functions ----------------------------------------------------------------------
    def _layout(self, P, m, size=None):
        """Per node count: the piece of every flattened node and the padded chunks (of the
        size :func:`_chunk` picks, or of ``size``)."""
        key = (P, m, size)
        if key not in self._layouts:
            n = P * m
            size = _chunk(n) if size is None else size
            chunks = [(start, min(start + size, n),
                       np.minimum(np.arange(start, start + size), min(start + size, n) - 1))
                      for start in range(0, n, size)]          # padded with the last node
            self._layouts[key] = (np.repeat(np.arange(P), m), chunks)
        return self._layouts[key]

    def _flat(self, kernel, s, Y, p, extra=(), *, scalars=(), chunk=None):
        """Call the nodal ``kernel`` on every node of s (P, m), Y (P, 6, m), in padded chunks
        (of size ``chunk`` if given), with per-node ``extra`` arrays and trailing
        ``scalars``."""
        P, m = s.shape
        piece, chunks = self._layout(P, m, chunk)
        sf = s.reshape(-1)
        yf = flat_nodes(Y)
        handles = [kernel.dispatch(piece[idx], sf[idx], yf[idx], float(p),
                                   self.scene.material_parameter, self.scene.h,
                                   self.field_parameters,
                                   *[e[idx] for e in extra], *scalars)
                   for _, _, idx in chunks]
        outs = [[np.asarray(o)[: stop - start] for o in kernel.collect(hd)]
                for (start, stop, _), hd in zip(chunks, handles)]
        return [np.concatenate(parts) for parts in zip(*outs)]

    def _check(self, F, ok, s, p):
        P, m = s.shape
        F = F.reshape(P, m, 5)
        if not self.scene.fields_admissible(F):     # all pieces at once; name the culprit
            for i in range(P):
                self.scene.check_fields(F[i].T, i, p)
        if not ok.all():
            k = int(np.argmin(ok))
            raise ConvergenceError(
                f"inner Newton for (lam1, k1) did not converge at s = {s.ravel()[k]:.6g} "
                f"({self.scene.parameter} = {p:g}): the state is far from admissible "
                f"(lam1 <= 0, or the constitutive inversion folds); take a smaller step")

    def rhs(self, s, Y, p, hint=None) -> Nodal:
        """f, df/dy and df/dp at nodes s (P, m) with states Y (P, 6, m) (piece-major).

        ``hint``: the ``hint`` of a previous evaluation at the same nodes (warm start of the
        inner Newton; changes cost only). Raises ConvergenceError where the inner Newton fails
        and ValueError for inadmissible stimulus fields.
        """
        s, Y, yf, q0 = self._nodal_args(s, Y, hint, p)
        out = self._flat(self._k.nodal, s, Y, p, (q0,))
        if not np.all(out[4]):         # a stale warm start: restart along the meridian
            q0 = self._start(s, Y, p)
            out = self._flat(self._k.nodal, s, Y, p, (q0,))
        return self._nodal_result(s, Y, p, out, yf)

    def _nodal_args(self, s, Y, hint, p):
        """(s, Y, the nodal states flattened (P m, 6), the start of the inner Newton)."""
        s, Y = np.asarray(s, dtype=float), np.asarray(Y, dtype=float)
        P, m = s.shape
        yf = flat_nodes(Y)
        if isinstance(hint, Hint) and hint.q.shape == (P * m, 2):
            # the previous root carried to the new iterate: the inner Newton then starts
            # O(|change|^2) from its root
            return s, Y, yf, carried_roots(hint, yf, p)
        return s, Y, yf, self._start(s, Y, p)

    def _start(self, s, Y, p):
        """A start for the inner Newton at every node when no previous iterate is known:
        (lam1, k1) followed along the meridian from the pole (:meth:`state_and_hessian`;
        an independent start per node from (lam2, k2) misses the root where the fields jump
        at an interface); nan (the pole-like guess) where that fails. A one-piece scene has
        no interface: there the pole-like guess is the start at every node (it needs no
        sequential scan, which is one more program to compile)."""
        if self.P == 1:
            return np.full((s.size, 2), np.nan)
        X, _, ok, _, _ = self._scan(s, Y, p)
        return np.where(ok[:, None], X[:, [0, 2]], np.nan)

    def carried_hint(self, hint, Y, Y_new, p, resample):
        """A warm start for an evaluation at states Y_new (P, 6, m') on other nodes of the
        same pieces, from ``hint``, that of an evaluation at nodes (P, m) near the states Y
        (P, 6, m) there: its roots carried to Y along their derivatives and resampled
        (``resample`` maps arrays (P, k, m) to the new nodes; the roots are smooth along
        each piece). None unless Y is within HINT_CARRY of the hint's states (relative):
        from farther, e.g. a fold bracketed away from the last continuation step, the
        carried roots can be a worse start than the pole-like guess."""
        y = flat_nodes(Y)
        if not isinstance(hint, Hint) or hint.y.shape != y.shape or \
                np.max(np.abs(y - hint.y)) > HINT_CARRY * (1.0 + np.max(np.abs(y))):
            return None
        q = carried_roots(hint, y, p)
        P = Y.shape[0]
        q_new = np.moveaxis(resample(np.moveaxis(q.reshape(P, -1, 2), 1, 2)), 2, 1)
        n = P * q_new.shape[1]
        return Hint(flat_nodes(Y_new), float(p), q_new.reshape(n, 2), np.zeros((n, 2, 7)))

    def _nodal_result(self, s, Y, p, out, yf) -> Nodal:
        F, f, J, fp, ok, q, dq = out
        P, m = s.shape
        self.evaluations += 1
        self._check(F, ok, s, p)
        f = f.reshape(P, m, 6).transpose(0, 2, 1)
        J = J.reshape(P, m, 6, 6).transpose(0, 2, 3, 1)
        fp = fp.reshape(P, m, 6).transpose(0, 2, 1)
        return Nodal(f, J, fp, Hint(yf, float(p), q, dq))

    def collocate(self, s, Y, p, hint=None) -> Collocated:
        """:meth:`rhs` at the nodes, :meth:`boundary` at y(eps) = Y[0, :, 0] and
        y(theta) = Y[-1, :, -1], and :meth:`monitor` there: the same values, in one compiled
        call when all nodes fit in one chunk."""
        s, Y, yf, q0 = self._nodal_args(s, Y, hint, p)
        P, m = s.shape
        piece, chunks = self._layout(P, m)
        if len(chunks) > 1:
            return Collocated(self.rhs(s, Y, p, hint), self.boundary(Y[0, :, 0], Y[-1, :, -1], p),
                              self.monitor(Y[0, :, 0], Y[-1, :, -1]))
        sc = self.scene
        ((_, _, idx),) = chunks

        def call(q):
            nod, bc, mon = self._k.collocate(
                piece[idx], s.reshape(-1)[idx], yf[idx], float(p), self.scene.material_parameter,
                sc.h, self.field_parameters, q[idx], Y[0, :, 0], Y[-1, :, -1], self.eps,
                sc.theta)
            return [o[:P * m] for o in nod], bc, mon

        out, bc, mon = call(q0)
        if not out[4].all():           # a stale warm start: restart along the meridian
            q0 = self._start(s, Y, p)
            out, bc, mon = call(q0)
        nodal = self._nodal_result(s, Y, p, out, yf)
        m_, (ga, gb) = mon
        return Collocated(nodal, self._boundary_result(bc, p),
                          (float(m_), np.asarray(ga), np.asarray(gb)))

    # --- boundary conditions and observable ---------------------------------------------------
    def boundary(self, ya, yb, p):
        """Residual (6,) of the pole (3 rows) and edge (3 rows) conditions, with its
        derivatives in ya = y(eps), yb = y(theta) and p. Interface continuity is imposed by
        the methods (all six components)."""
        sc = self.scene
        return self._boundary_result(self._k.boundary(
            np.asarray(ya, dtype=float), np.asarray(yb, dtype=float), float(p), self.eps,
            sc.theta, self.scene.material_parameter, sc.h, self.field_parameters), p)

    def _boundary_result(self, out, p):
        r, Ja, Jb, Jp, ok, F0 = out
        if not self.scene.fields_admissible(F0):
            self.scene.check_fields(F0[:, None], 0, p)
        if not ok:
            raise ConvergenceError(f"inner Newton for (lam1, k1) did not converge at the pole "
                                   f"({self.scene.parameter} = {p:g})")
        return r, Ja, Jb, Jp

    def monitor(self, ya, yb):
        """The observable w / H (module docstring) and its gradients in ya and yb."""
        m, (ga, gb) = observable_and_gradient(np.asarray(ya, dtype=float),
                                              np.asarray(yb, dtype=float), self.scene.theta,
                                              self.scene.edge == "free", np)
        return float(m), ga, gb

    def vector_field(self):
        """The traceable point function (piece, s, y, p, material_parameter, h) -> f (6,),
        for methods that integrate the ODE themselves (shooting)."""
        return self._k.vector_field
