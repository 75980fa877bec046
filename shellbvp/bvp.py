"""The axisymmetric boundary-value problem of a scene, written once for every method.

A :class:`ShellBVP` turns a :class:`shellbvp.Scene` into a multi-point first-order BVP
for y = (r, z, theta, m, f_r, f_z) in the meridian's arclength s (m, f = 12/h^2 times the
moment and forces, so that bending and membrane unknowns have the same size):

* **pieces**: the domain [s_a, s_b] (the meridian [0, L], less the pole offset eps at an end
  on the axis) is cut at the scene's interfaces (the joints of the geometry and the breaks
  of the fields) into pieces [a_i, b_i], each mapped to the piece coordinate t in [0, 1]
  (dy/dt = (b_i - a_i) f). The methods keep one state per piece and impose
  y(a_{i+1}) = y(b_i) + jump_i at every interface: continuity of all six components, but
  for theta at a kink of the geometry, which jumps by the reference's angle (a rigid
  joint), so a jump of the stimulus or of the tangent is exact (the meridional stretch may
  jump there);
* **poles**, an end on the axis (r0 = 0), at eps = ``POLE_OFFSET`` L from it: the pole is
  a regular singular point whose regular solution has g1 lam1 = g2 lam2 + O(s^2) (equal
  actual stretches: r ~ g1 lam1 r0 and lam2 = r / (g2 r0); lam1 = lam2 only without a
  metric stimulus), k1 = k2 + O(s^2) and z(pole) = z(eps) + r (theta - theta_pole) / 2
  + O(eps^4) (theta_pole = 0 at a first end, pi at a second); the conditions are
  g1 lam1 = g2 lam2, k1 = k2 and, at the pinned end (:attr:`shellbvp.Scene.pinned`),
  z(pole) = its reference height, else f_z = 0 (no point force). Their O(eps^2) relative
  error gives an O(eps^4) error in the solution. Where the target curvature is anisotropic
  at a pole (kb1 != kb2) the solution is not regular: k1 - k2 tends to a nonzero constant
  and both curvatures grow like log s (as for a plate with anisotropic natural curvature:
  the moment balance (s M1)' = M2 near s = 0 with M linear in k forces
  k1 - k2 = (1 - nu)(k*1 - k*2)/2, nu = W_k1k2 / W_k1k1, k* where the moments vanish).
  There the condition is k1 - k2 = A, which excludes the 1/s mode as k1 = k2 does at a
  regular pole: the shape and w converge, the pole curvatures do not (they diverge like
  log s). A target metric anisotropic at a pole (g1 != g2, a cone) would need the same
  treatment of the stretches; it keeps g1 lam1 = g2 lam2 at eps, which is exact only for a
  regular membrane state;
* **other ends** (:class:`shellbvp.scene.End`): ``free`` (m, f_r, f_z given by the line
  loads: F(second end) = Q and F(first end) = -Q per radian, Q the load per unit reference
  length times r0), ``clamped`` (r, z, theta at the reference's values), ``hinged`` (r, z;
  m given), ``roller`` (z; f_r, m given), ``sliding`` (z, theta; f_r given), ``diaphragm``
  (r; f_z, m given), ``symmetry`` (theta at the reference's, f_r = 0, f_z given), and at
  the pinned end z at its reference height in place of f_z;
* **rings** (:class:`shellbvp.scene.Ring`), dead forces on circles of the meridian: each
  is an interface across which (f_r, f_z) jump by -(12/h^2) Q, Q its total force per
  radian (:meth:`ShellBVP.jumps_at`);
* **load**: a scene's uniform pressure (``Scene.pressure``) enters the compiled equations as
  a field beside the stimulus, through its potential P V (:mod:`shellbvp.euler_lagrange`);
* **monitor**, the branch observable (:attr:`shellbvp.Scene.monitor_terms`): by default the
  axial displacement of the end that does not fix z relative to the one that does, in
  units of the reference's rise (:attr:`shellbvp.Scene.monitor_scale`).

The reference state is (r0, z0, theta0, 0, 0, 0) from the geometry. All of the above is JAX
code compiled once per scene structure (:func:`shellbvp.kernels.kernel_key`); the methods in
:mod:`shellbvp.methods` only discretise it. The nodal right-hand side is evaluated in chunks
padded to one of a few sizes (``CHUNKS``), so that a change of resolution reuses a compiled
program instead of compiling a new one.
"""

from __future__ import annotations

import math

import numpy as np

from .bvp_derivatives import Derivatives
from .errors import ConvergenceError
from .fields import interface_jumps
from .kernels import kernels, monitor_and_gradient, untraceable
from .meridian import MeridianStates
from .mesh import APEX_PROBES, Mesh, single_mesh
from .nodal import Collocated, Hint, Nodal, carried_roots, flat_nodes
from .scene import Scene, per_scene

__all__ = ["ShellBVP", "Nodal", "Collocated", "POLE_OFFSET", "CHUNKS"]

#: eps / L (L the meridian's length). The pole conditions are exact to O(eps^2), so the
#: solution is good to O(eps^4) = 1e-16 relative: below every tolerance the solvers reach,
#: while eps stays far enough from the axis that lam2 = r / (g2 r0) is evaluated without
#: cancellation.
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


def _chunk(n: int) -> int:
    return next((c for c in CHUNKS if c >= n), CHUNKS[-1])

#: relative difference of the target curvatures at a pole's offset point beyond which the
#: pole is anisotropic (the reference's own is O(eps^2) ~ 1e-8 there)
ANISOTROPY_TOL = 1e-6


@per_scene
def _anisotropic_pole(scene, piece, s) -> bool:
    """Whether the target curvature is anisotropic at a pole (kb1 != kb2 at its offset point
    s for some probed parameter value): then the pole condition k1 = k2 becomes k1 - k2 = A
    (module docstring), which costs third derivatives of W in the compiled end rows."""
    probes = np.asarray(APEX_PROBES)
    F = np.stack(scene.field_values(piece, np.full(probes.shape, float(s)), probes))
    # at the offset point the reference's own k1 - k2 is O(eps^2) on any pole but a
    # sphere's: anisotropic means beyond that, relative to the curvatures
    tol = ANISOTROPY_TOL * (np.abs(F[2]) + np.abs(F[3]) + 1.0 / scene.length)
    return bool(np.any((np.abs(F[2] - F[3]) > tol) & np.isfinite(F).all(axis=0)))


class ShellBVP(Derivatives, MeridianStates):
    """The multi-point BVP of ``scene`` (see the module docstring).

    Arguments:
        scene: the problem.
        eps: pole offset (default ``POLE_OFFSET * L``); must be below a tenth of the piece
            at a pole.

    Attributes:
        scene, eps, P (number of pieces), a, b (piece ends in s), jumps ((P - 1, 6), the
        unknowns' jumps across the interfaces), poles (per end), s_a, s_b (the domain's
        ends), length (the meridian's L), scale (the monitor's unit length).
    """

    n = 6
    #: relative error of the derivatives :meth:`rhs` returns: round-off, for they are
    #: analytic and the inner roots' derivatives (implicit differentiation) are taken at
    #: the roots themselves, converged to round-off, never at an earlier iterate
    jacobian_error = 0.0

    def __init__(self, scene: Scene, eps: float | None = None, mesh: Mesh | None = None):
        if not isinstance(scene, Scene):
            raise ValueError(f"scene must be a shellbvp.Scene, got {type(scene).__name__}")
        mesh = single_mesh(scene) if mesh is None else mesh
        ends = np.asarray(mesh.ends, dtype=float)
        L = scene.length
        if not (isinstance(mesh, Mesh) and ends[0] == 0.0 and abs(ends[-1] - L) <= 1e-12 * L
                and len(mesh.pieces) == ends.size - 1
                and np.all(np.diff(ends) > 0) and set(mesh.pieces) == set(range(scene.pieces))):
            raise ValueError("mesh must be a shellbvp.mesh.Mesh of this scene's meridian "
                             "(shellbvp.mesh.mesh_of(scene))")
        ends[-1] = L
        eps_given = eps
        self.poles = tuple(e.kind == "pole" for e in scene.ends)
        # the default pole offset: a fixed fraction of the element at the pole (of the
        # meridian, where that element is at least a tenth of it: the single-domain case)
        per_L = POLE_OFFSET if eps is None else 0.0
        if eps is None:
            pole_element = min(ends[1] - ends[0], ends[-1] - ends[-2])
            if 10.0 * pole_element < L:
                eps, per_L = 10.0 * POLE_OFFSET * pole_element, 0.0
            else:
                eps = POLE_OFFSET * L
        eps = float(eps)
        for k, (pole, piece) in enumerate(zip(self.poles, (ends[1] - ends[0],
                                                            ends[-1] - ends[-2]))):
            if pole and not (0 < eps < piece / 10):
                raise ValueError(f"eps must lie in (0, {piece / 10:g}) (a tenth of the element "
                                 f"at the pole), got {eps!r}")
        self.scene, self.eps, self.length, self.mesh = scene, eps, L, mesh
        self.s_a = eps if self.poles[0] else 0.0
        self.s_b = L - eps if self.poles[1] else L
        #: whether eps was given (else it is the default, a fixed fraction of L or of the
        #: element at the pole)
        self.eps_given = eps_given is not None
        #: d s_a / d L and d s_b / d L: the default pole offset of the single-domain case
        #: scales with the meridian's length, a given one or one of a graded mesh's pole
        #: element is fixed (derivatives in the length move the second end)
        self.ends_per_length = (per_L if self.poles[0] else 0.0,
                                1.0 - per_L if self.poles[1] else 1.0)
        self.a = np.concatenate([[self.s_a], ends[1:-1]])
        self.b = np.concatenate([ends[1:-1], [self.s_b]])
        self.P = mesh.elements
        #: the scene's piece of every element (the fields and geometry of that piece)
        self.pieces = np.asarray(mesh.pieces, dtype=int)
        #: for every element boundary, the scene interface it is, or -1 (a cut in a piece)
        at = mesh.interfaces()
        self.interface_of = np.where(at, np.cumsum(at) - 1, -1)
        self.jumps = self._on_elements(interface_jumps(scene))
        self._fixed_jumps = (self.jumps, np.zeros_like(self.jumps))
        self.scale = scene.monitor_scale
        problem = untraceable(scene)
        if problem:
            raise ValueError(problem)
        self._layouts = {}
        #: kb1 != kb2 at a pole: curvatures diverge like log s there (module docstring)
        self.anisotropic_poles = (
            self.poles[0] and _anisotropic_pole(scene, 0, self.s_a),
            self.poles[1] and _anisotropic_pole(scene, scene.pieces - 1, self.s_b))
        self._k = kernels(scene, self.anisotropic_poles)
        #: the field parameters, an argument of every compiled function of the fields
        self.field_parameters = np.array(scene.field_parameters, dtype=float)
        self._refs = self._monitor_references()
        self.evaluations = 0

    def on_mesh(self, mesh: Mesh) -> "ShellBVP":
        """The same scene's BVP on the elements of ``mesh`` (the same pole offset where it
        was given; the compiled programs are shared)."""
        return ShellBVP(self.scene, self.eps if self.eps_given else None, mesh)

    def _on_elements(self, per_interface) -> np.ndarray:
        """Values per scene interface (P_scene - 1, k) -> per element boundary (P - 1, k),
        zero at the cuts inside a piece."""
        per_interface = np.asarray(per_interface, dtype=float)
        out = np.zeros((self.P - 1,) + per_interface.shape[1:])
        at = self.interface_of >= 0
        out[at] = per_interface[self.interface_of[at]]
        return out

    @property
    def anisotropic_apex(self) -> bool:
        """Whether the first end is a pole with an anisotropic target curvature."""
        return self.anisotropic_poles[0]

    def _monitor_references(self):
        """The reference values of r, z, theta at the two ends the monitor reads (at a pole
        the pole itself: r = 0, theta at a right angle to the axis)."""
        geo = self.scene.geometry
        out = []
        for k, (which, pole, s) in enumerate(zip(("first", "second"), self.poles,
                                                 (self.s_a, self.s_b))):
            if pole:
                out.append({"r": 0.0, "z": float(geo.at_end(which)[1]),
                            "theta": (0.0, math.pi)[k]})
            else:
                r0, z0, th0 = (float(v) for v in geo.at_end(which))
                out.append({"r": r0, "z": z0, "theta": th0})
        return out

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
        return ROUND_OFF_PER_H * np.finfo(float).eps * (1.0 + abs(p)) \
            / (sc.h / sc.curvature_radius) * stiff

    @property
    def round_off_step(self) -> float:
        """The relative Newton update at which the discrete equations reach their round-off
        floor: ``ROUND_OFF_STEP`` (1e-8) down to h = 1e-3 R_c, growing like 1/h below (the
        forces enter scaled by 12/h^2: updates stalled at 1e-9 at h = 1e-3 R_c, 1-3e-8 at
        h = 1e-4 and 4e-8 at h = 1e-5)."""
        from .continuation.newton import ROUND_OFF_STEP

        return ROUND_OFF_STEP * max(1.0, 1e-3 * self.scene.curvature_radius / self.scene.h)

    @property
    def lengths(self) -> np.ndarray:
        return self.b - self.a

    def s_of(self, i: int, t):
        """s on piece i at the piece coordinate t in [0, 1]."""
        return self.a[i] + (self.b[i] - self.a[i]) * np.asarray(t, dtype=float)

    def reference(self, s):
        """The undeformed state (r0, z0, theta0, 0, 0, 0) at s (the default guess; a joint
        of the geometry belongs to the next segment)."""
        s = np.asarray(s, dtype=float)
        r0, z0, th0, _ = self.scene.geometry.evaluate(s)
        zero = np.zeros_like(s)
        return np.stack([r0 + zero, z0 + zero, th0 + zero, zero, zero, zero])

    def reference_rate(self, s, order: int = 1):
        """The ``order``-th s-derivative (1 or 2) of :meth:`reference` at s, exact:
        (cos theta0, -sin theta0, -k1, 0, 0, 0) and (k1 sin theta0, k1 cos theta0, -k1',
        0, 0, 0), k1 = -dtheta0/ds the reference's meridional curvature (k1' by JAX's
        derivative of the geometry)."""
        s = np.asarray(s, dtype=float)
        _, _, th0, k1 = self.scene.geometry.evaluate(s)
        zero = np.zeros_like(s)
        if order == 1:
            return np.stack([np.cos(th0) + zero, -np.sin(th0) + zero, -k1 + zero, zero,
                             zero, zero])
        from .jaxsetup import jax
        import jax.numpy as jnp

        geo = self.scene.geometry
        dk1 = np.asarray(jax.jvp(lambda x: geo.evaluate(x, jnp)[3], (jnp.asarray(s),),
                                 (jnp.ones_like(jnp.asarray(s)),))[1])
        return np.stack([k1 * np.sin(th0) + zero, k1 * np.cos(th0) + zero, -dk1 + zero,
                         zero, zero, zero])

    # --- nodal functions ----------------------------------------------------------------------
    def _layout(self, P, m, size=None):
        """Per node count: the piece of every flattened node and the padded chunks (of the
        size :func:`_chunk` picks, or of ``size``)."""
        key = (P, m, size)
        if P != self.P:
            raise ValueError(f"nodes on {P} elements given to a BVP of {self.P}")
        if key not in self._layouts:
            n = P * m
            size = _chunk(n) if size is None else size
            chunks = [(start, min(start + size, n),
                       np.minimum(np.arange(start, start + size), min(start + size, n) - 1))
                      for start in range(0, n, size)]          # padded with the last node
            self._layouts[key] = (np.repeat(self.pieces[:P], m), chunks)
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
        F = F.reshape(P, m, -1)
        if not self.scene.fields_admissible(F):     # all pieces at once; name the culprit
            for i in range(P):
                self.scene.check_fields(F[i].T, i, p)
        if not ok.all():
            k = int(np.argmin(ok))
            raise ConvergenceError(
                f"inner Newton for (lam1, k1) did not converge at "
                f"{self.scene.quote_s(s.ravel()[k], 6)} ({self.scene.quote(p)}): the state "
                f"is far from admissible "
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
        if self.scene.pieces == 1:
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

    def _ends(self):
        """The domain's ends and the meridian's length: the trailing scalars of the compiled
        boundary functions."""
        return self.s_a, self.s_b, self.length

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
        """:meth:`rhs` at the nodes, :meth:`boundary` at y(s_a) = Y[0, :, 0] and
        y(s_b) = Y[-1, :, -1], and :meth:`monitor` there: the same values, in one compiled
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
                sc.h, self.field_parameters, q[idx], Y[0, :, 0], Y[-1, :, -1], *self._ends())
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
        """Residual (6,) of the first end's (3 rows) and second end's (3 rows) conditions,
        with its derivatives in ya = y(s_a), yb = y(s_b) and p. Interface conditions are
        imposed by the methods (all six components, with :attr:`jumps`)."""
        sc = self.scene
        return self._boundary_result(self._k.boundary(
            np.asarray(ya, dtype=float), np.asarray(yb, dtype=float), float(p), *self._ends(),
            self.scene.material_parameter, sc.h, self.field_parameters), p)

    def _boundary_result(self, out, p):
        r, Ja, Jb, Jp, ok, F0 = out
        if not self.scene.fields_admissible(F0):
            self.scene.check_fields(F0[:, None], 0, p)
        if not ok:
            raise ConvergenceError(f"inner Newton for (lam1, k1) did not converge at a pole "
                                   f"({self.scene.quote(p)})")
        return r, Ja, Jb, Jp

    def monitor(self, ya, yb):
        """The monitor (module docstring) and its gradients in ya and yb."""
        sc = self.scene
        m, (ga, gb) = monitor_and_gradient(np.asarray(ya, dtype=float),
                                           np.asarray(yb, dtype=float), sc.monitor_terms,
                                           self.poles, self._refs, self.scale, np)
        return float(m), ga, gb

    def ring_jumps(self, p, order: int = 0) -> np.ndarray:
        """(P - 1, 6): the rings' part of the jumps across the interfaces at p (its
        ``order``-th derivative in p): f_r and f_z jump by -(12/h^2) Q at a ring carrying
        Q per radian (:class:`shellbvp.scene.Ring`), the corner condition of its potential."""
        sc = self.scene
        out = np.zeros((sc.pieces - 1, 6))
        for ring, i in zip(sc.rings, sc.ring_interfaces):
            out[i, 4:6] -= 12.0 / sc.h ** 2 * ring.conjugate(p, order)
        return self._on_elements(out)

    def jumps_at(self, p) -> tuple[np.ndarray, np.ndarray]:
        """The jumps across the interfaces at p, (P - 1, 6) (:attr:`jumps`, the rigid
        joints' angles, plus the rings' forces) and their p-derivative."""
        if not self.scene.rings:
            return self._fixed_jumps
        return self.jumps + self.ring_jumps(p), self.ring_jumps(p, 1)

    def vector_field(self):
        """The traceable point function (piece, s, y, p, material_parameter, h) -> f (6,),
        for methods that integrate the ODE themselves (shooting)."""
        return self._k.vector_field
