"""Direct minimisation of the discrete reduced energy (a Ritz method): the paper's own route.

The other methods solve the first-order Euler-Lagrange system, which needs the inner
inversion of the moment M -> (lam1, k1) at every node and regular-series conditions at a
pole. This one never forms those equations. Its unknowns are the meridian itself, as the
tangent angle theta(s), the actual meridional stretch Lambda(s) = |x'| = g1 lam1 and the
radius r(s), on spectral elements (Chebyshev-Lobatto nodes of degree q per element), and
the discrete energy

    E = 2 pi int [ t W(lam1, lam2, k1, k2; kb, h t, rhob) g1 g2 r0
                   + (P / 2) r^2 Lambda sin(theta) ] ds - (work of the end loads)

with the principal state from the one kinematic map (:mod:`shellbvp.kinematics`:
lam1 = Lambda / g1, lam2 = r / (g2 r0), k1 = -theta' / Lambda, k2 = -sin(theta) / r),
Gauss-Legendre quadrature per element, P the pressure, if any, is made stationary under the
kinematic constraint r' = Lambda cos(theta), imposed at the q Gauss points of every element
with multipliers f = 12/h^2 F_r (the meridional force per radian, scaled as the first-order
system scales it). The discrete system is R = grad L = 0 for the Lagrangian
L = E + 2 pi int (h^2/12) f (r' - Lambda cos theta) ds, its Jacobian the Hessian of L,
both exact (JAX, per quadrature point, assembled through the elements' fixed linear maps
into a sparse symmetric matrix; the point kernel is compiled once per material, at a fixed
number of points, and serves every degree, mesh and scene). It plugs into the same
continuation, fold location and refinement ladder as every other method.

What it does not need:

* no inner constitutive inversion (lam1 and k1 are read from the unknowns), so it passes
  states where that inversion folds;
* no regular-series conditions at a pole: theta = 0 (pi at a second end) and r = 0 are the
  only conditions there (the finite-energy conditions: a nonzero pole angle costs a bending
  energy ~ log(1/s)); the quadrature points lie inside the elements, never on the axis.
  Where the target is a cone at a pole (g1 != g2) or its curvature is anisotropic there
  (kb1 != kb2), the solution is singular at the pole (curvatures ~ log s); the elements are
  then graded geometrically toward it (``layers`` layers, each ``grading`` times the next,
  down to a tenth of the thickness, below which the thin-shell energy is not valid), the
  hp-refinement that resolves such singularities (Babuska & Guo): w converges, the pole
  strains do not.

Ends (:class:`shellbvp.scene.End`): the fixed values of theta and r are removed from the
unknowns (a pole: theta at a right angle to the axis, r = 0; clamped: theta, r; hinged and
diaphragm: r; sliding and symmetry: theta); forces and moments are natural, their given line loads enter the energy
as the potential of dead loads on the end. The axial position z never enters the energy
(z' = -Lambda sin theta is integrated afterwards, I = int Lambda sin theta ds the drop from
the first end to the second): an end that fixes z holds the other's position through I, an
axial load on the other end has potential -Q z(end) (linear in I), and where both ends fix
z the constraint I = z0(0) - z0(L) enters with its own multiplier (the axial force). A
ring load (:class:`shellbvp.scene.Ring`) sits on an interface, a node of the mesh: its
radial force's potential is -Q_r r there, its axial one's -Q_z z there, z from the anchoring
end through the drops of the elements between (so each element's drop carries its own axial
force, which jumps at the ring). A
joint of the geometry with a kink turns theta by the reference's angle: the unknown is
theta less the kinks passed, continuous.

Stability comes with it: the Hessian of L restricted to the constraints' tangent space is
the discrete second variation at fixed stimulus (:meth:`RitzSystem.spectrum`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..mesh import loaded_pole_ratio, mesh_of, singular_poles
from ..scene import load_rate
from .chebyshev import chebyshev_points, differentiation_matrix

__all__ = ["Ritz", "RitzSystem", "MIN_DEGREE", "MAX_DEGREE", "REFINE_STEP"]

#: the smallest and largest polynomial degree per element
MIN_DEGREE, MAX_DEGREE = 6, 64
#: degree added per rung of the refinement ladder (the geometric layers grow with it)
REFINE_STEP = 4


#: the innermost element at a singular pole, in thicknesses h (:attr:`Ritz.core`). The
#: reduced energy is a thin-shell expansion, valid where the curvatures vary on lengths
#: >> h; at a singular pole its solution has curvatures ~ log s, which below s ~ h reach
#: h|k| >~ 1 and make W non-convex there: elements that resolve that core move where the
#: discrete Hessian turns indefinite with the resolution (budding eta = (0.5, 1): kbar =
#: 2.44, 1.40, 0.98 with innermost elements 4e-8, 1e-10, 4e-13 R0), an element of the
#: thickness's size does not
CORE = 1.0
#: the innermost element of the default apex layers (``Ritz.core`` None), in thicknesses
APEX_CORE = 0.1


@dataclass(frozen=True)
class Ritz:
    """Direct minimisation of the discrete reduced energy on spectral elements.

    Attributes:
        degree: polynomial degree per element (q; theta, Lambda and r at its q + 1
            Chebyshev-Lobatto nodes, the multiplier at its q Gauss points).
        elements: elements per piece of the scene, of equal length (outside the pole
            layers).
        core: where a pole is singular (a conical target, g1 != g2, or an anisotropic
            target curvature, kb1 != kb2, on the axis), the length of the innermost element
            there, in thicknesses h: the elements grow from it by 1/``grading`` per layer to
            the uniform ones; None (default): geometric layers from the uniform elements
            down to ``APEX_CORE`` h. The reduced energy is a thin-shell
            expansion that does not resolve the shell inside a disc of radius ~ h around
            such a pole (its log-singular curvatures make it non-elliptic there); one
            element of the core's size does not resolve it either, so the result does not
            depend on what the theory cannot say (the spread over core lengths is part of
            an error estimate; see the budding study).
        core_degree: the polynomial degree of the innermost element at a singular pole (its
            theta, Lambda and r of this degree, its multiplier one less), so that the
            element does not resolve the core it spans; None (default): ``degree``, as every
            other element.
        layers: instead of ``core``, this many geometric layers toward a singular pole (each
            ``grading`` times the next), the innermost then as short as they make it; None
            (default): from ``core``.
        grading: ratio of the lengths of consecutive layers (0 < grading < 1).
    """

    degree: int = 16
    elements: int = 2
    layers: int | None = None
    grading: float = 0.15
    core: float | None = None
    core_degree: int | None = None
    name = "energy"

    def __post_init__(self):
        if not (isinstance(self.degree, (int, np.integer))
                and MIN_DEGREE <= self.degree <= MAX_DEGREE):
            raise ValueError(f"degree must be an integer in [{MIN_DEGREE}, {MAX_DEGREE}] "
                             f"(polynomial degree per element), got {self.degree!r}")
        if not (isinstance(self.elements, (int, np.integer)) and 1 <= self.elements <= 64):
            raise ValueError(f"elements must be an integer in [1, 64] (per piece), got "
                             f"{self.elements!r}")
        if self.layers is not None and not (isinstance(self.layers, (int, np.integer))
                                            and 0 <= self.layers <= 60):
            raise ValueError(f"layers must be None or an integer in [0, 60], got "
                             f"{self.layers!r}")
        if not (isinstance(self.grading, (int, float)) and 0.01 <= self.grading <= 0.9):
            raise ValueError(f"grading must be a number in [0.01, 0.9], got {self.grading!r}")
        if self.core is not None and not (isinstance(self.core, (int, float))
                                          and 0.01 <= self.core <= 100):
            raise ValueError(f"core must be None or a number in [0.01, 100] (the innermost "
                             f"element at a singular pole, in thicknesses), got {self.core!r}")
        if self.core is not None and self.layers is not None:
            raise ValueError("give core (the innermost element's length) or layers, not both")
        if self.core_degree is not None and not (
                isinstance(self.core_degree, (int, np.integer))
                and 1 <= self.core_degree <= self.degree):
            raise ValueError(f"core_degree must be None or an integer in [1, degree = "
                             f"{self.degree}], got {self.core_degree!r}")

    def discretise(self, bvp) -> "RitzSystem":
        return RitzSystem(bvp, self)




def graded_piece(a: float, b: float, inner: float, grading: float, elements: int,
                 at_end: bool = False) -> list:
    """Cuts of the piece [a, b] graded toward a (toward b with ``at_end``): the innermost
    element ``inner`` long, each next one 1/``grading`` times longer while shorter than the
    piece's uniform elements ((b - a) / ``elements``), then the rest in uniform elements no
    longer than those; the uniform cuts where ``inner`` is not shorter than them."""
    span, uniform = b - a, (b - a) / elements
    if inner >= uniform:
        return list(np.linspace(a, b, elements + 1))
    lengths = [inner]
    while lengths[-1] / grading < uniform and sum(lengths) + lengths[-1] / grading < span:
        lengths.append(lengths[-1] / grading)
    rest = span - sum(lengths)
    n = max(1, math.ceil(rest / uniform - 1e-9))
    lengths += [rest / n] * n
    x = np.concatenate([[0.0], np.cumsum(lengths)])
    x[-1] = span
    return list(a + x) if not at_end else list(b - x[::-1])


def singular_apex(scene) -> bool:
    """Whether the first end is a pole where the target is singular (:func:`singular_poles`)."""
    return singular_poles(scene)[0]


# --- one element: nodes, quadrature, the fixed linear maps --------------------------------
def _gauss(n):
    x, w = np.polynomial.legendre.leggauss(n)
    return (x + 1) / 2, w / 2


def _barycentric(nodes, weights, x):
    """The matrix of Lagrange interpolation from ``nodes`` (barycentric ``weights``) to x."""
    x = np.asarray(x, dtype=float)
    d = x[:, None] - nodes[None, :]
    exact = d == 0
    d = np.where(exact, 1.0, d)
    C = weights[None, :] / d
    C /= C.sum(axis=1, keepdims=True)
    hit = exact.any(axis=1)
    C[hit] = exact[hit].astype(float)
    return C


def _lobatto_weights(q):
    w = (-1.0) ** np.arange(q + 1)
    w[0] *= 0.5
    w[-1] *= 0.5
    return w


def _general_weights(nodes):
    d = nodes[:, None] - nodes[None, :]
    np.fill_diagonal(d, 1.0)
    return 1.0 / d.prod(axis=1)


@lru_cache(maxsize=None)
def _element(q, nq):
    """(t nodes, tq, wq, tc, wc, B_E (nq, 4, nloc), B_C (q, 4, nloc)) of the reference
    element [0, 1]: the local unknowns are (theta, Lambda, r) at the q + 1 nodes and f at
    the q collocation (Gauss) points; B_E gives (theta, dtheta/dt, Lambda, r) at the energy
    quadrature points, B_C (theta, Lambda, dr/dt, f) at the collocation points."""
    t = chebyshev_points(q)
    D = differentiation_matrix(q)
    bw = _lobatto_weights(q)
    tq, wq = _gauss(nq)
    tc, wc = _gauss(q)
    Iq, Ic = _barycentric(t, bw, tq), _barycentric(t, bw, tc)
    n1 = q + 1
    nloc = 3 * n1 + q
    BE = np.zeros((nq, 4, nloc))
    BE[:, 0, :n1] = Iq
    BE[:, 1, :n1] = Iq @ D
    BE[:, 2, n1:2 * n1] = Iq
    BE[:, 3, 2 * n1:3 * n1] = Iq
    BC = np.zeros((q, 4, nloc))
    BC[:, 0, :n1] = Ic
    BC[:, 1, n1:2 * n1] = Ic
    BC[:, 2, 2 * n1:3 * n1] = Ic @ D
    BC[:, 3, 3 * n1:] = np.eye(q)
    return t, tq, wq, tc, wc, BE, BC


def quadrature_points(q: int) -> int:
    """Energy quadrature points per element of degree q (the integrand is a nonlinear
    function of degree-q interpolants: half as many again keeps its aliasing below the
    interpolation error)."""
    return (3 * q) // 2 + 2


# --- compiled programs ----------------------------------------------------------------------
#: points per call of the compiled point kernels (padded): one program serves every degree,
#: mesh and scene of a material (compiling the Hessian of a relaxed W takes ~4 s)
CHUNK = 256


def _padded(fn, n, arrays, scalars):
    """``fn`` on ``n`` points in chunks of CHUNK (the arrays' first axis padded with their
    last point), outputs concatenated and trimmed to n."""
    outs = []
    for start in range(0, n, CHUNK):
        idx = np.minimum(np.arange(start, start + CHUNK), n - 1)
        outs.append([np.asarray(o) for o in fn(*[a[idx] for a in arrays], *scalars)])
    return [np.concatenate(parts)[:n] for parts in zip(*outs)]


@lru_cache(maxsize=None)
def _point_kernels(model, material, through_thickness):
    """Per quadrature point, for the energy density of the Lagrangian

        phi(v; L, F, P) = t W(X; kb, h t, rhob) g1 g2 r0 + (P/2) r^2 Lambda sin(theta),

    X the principal state of v = (theta, theta_t, Lambda, r) (theta_t = dtheta/dt on an
    element of length L) by :func:`shellbvp.kinematics.principal_state`, F the fields
    (:data:`shellbvp.kinematics.FIELDS`): ``phi_kernel`` -> (gradient (n, 4), Hessian
    (n, 4, 4), d gradient / dp (n, 4) along the fields' and the pressure's derivatives
    dF, dP); ``w_kernel`` -> gradient and Hessian of W in X = (lam1, lam2, k1, k2).
    Compiled once per material, at CHUNK points."""
    from ..jaxsetup import jax, jit
    import jax.numpy as jnp

    from .. import kinematics as K
    from ..compiled import energy_at, energy_function

    W = energy_function(model, material, through_thickness)

    def phi(v, L, F, P, mat, h):
        th, tht, Lam, r = v
        X = K.principal_state(r, th, Lam, tht / L, F[K.R0], F[K.G1], F[K.G2], jnp)
        return (K.energy_per_length(W, X, F, mat, h)
                + 0.5 * P * r * r * Lam * jnp.sin(th))

    pts = (0, 0, 0, None, None, None)
    grad = jax.vmap(jax.grad(phi), pts)
    hess = jax.vmap(jax.hessian(phi), pts)

    def phi_kernel(V, L, F, dF, P, dP, mat, h):
        g, gp = jax.jvp(lambda F_, P_: grad(V, L, F_, P_, mat, h), (F, P), (dF, dP))
        return g, hess(V, L, F, P, mat, h), gp

    def w(X, F, mat, h):
        return energy_at(W, X, F, mat, h)

    one = (0, 0, None, None)
    w_grad, w_hess = jax.vmap(jax.grad(w), one), jax.vmap(jax.hessian(w), one)
    return (jit(phi_kernel),
            jit(lambda X, F, mat, h: (w_grad(X, F, mat, h), w_hess(X, F, mat, h))))


#: compiled field programs, per scene structure and element counts (each small)
_FIELD_PROGRAMS: dict = {}


def _fields_program(scene, pieces):
    """(s (E, k), p, c) -> fields (E, k, n_fields), their p-derivative, pressure P and
    dP/dp, the scene's fields (:func:`shellbvp.fields.point_fields`) piece by piece
    (``pieces``: elements per piece); small, compiled per scene structure and mesh."""
    from ..jaxsetup import jax, jit
    import jax.numpy as jnp

    from ..fields import point_fields
    from ..kernels import kernel_key

    key = (kernel_key(scene, (False, False)), pieces)
    found = _FIELD_PROGRAMS.get(key)
    if found is not None:
        return found
    bounds = np.cumsum((0,) + pieces)

    def values(s, p, c):
        out = [jnp.moveaxis(point_fields(scene, i, s[bounds[i]:bounds[i + 1]], p, c, jnp),
                            0, -1) for i in range(len(pieces))]
        P = 0.0 * p if scene.pressure is None else jnp.asarray(scene.pressure(p), dtype=float)
        return jnp.concatenate(out, axis=0), P

    def with_derivative(s, p, c):
        (F, P), (dF, dP) = jax.jvp(lambda p_: values(s, p_, c), (p,), (1.0,))
        return F, dF, P, dP

    found = _FIELD_PROGRAMS[key] = jit(with_derivative)
    return found


def _constraint_terms(U, L, h):
    """Gradient (E, q, 4) and Hessian (E, q, 4, 4) of psi = (h^2/12) f (r_t/L - Lambda
    cos(theta)) in u = (theta, Lambda, r_t, f) at the collocation points (by hand: it is
    that short)."""
    th, Lam, rt, f = np.moveaxis(U, -1, 0)
    c, s = np.cos(th), np.sin(th)
    k = h * h / 12.0
    Lb = np.broadcast_to(L[:, None], th.shape)
    g = k * np.stack([f * Lam * s, -f * c, f / Lb, rt / Lb - Lam * c], axis=-1)
    H = np.zeros(th.shape + (4, 4))
    H[..., 0, 0] = k * f * Lam * c
    H[..., 0, 1] = H[..., 1, 0] = k * f * s
    H[..., 0, 3] = H[..., 3, 0] = k * Lam * s
    H[..., 1, 3] = H[..., 3, 1] = -k * c
    H[..., 2, 3] = H[..., 3, 2] = k / Lb
    return g, H


# --- the discrete system --------------------------------------------------------------------
class RitzSystem:
    """R(U, p) = grad L on the free unknowns (see the module docstring); J its Hessian
    (scipy.sparse, symmetric), dR/dp exact. U: theta (less the kinks passed), Lambda, r at
    the element nodes, f at the collocation points and, where both ends fix z, the axial
    force's multiplier, less the fixed values of the ends."""

    #: relative error of the Jacobian: round-off (JAX's exact derivatives)
    jacobian_error = 0.0
    dense_jacobian = False

    def __init__(self, bvp, method: Ritz):
        sc = bvp.scene
        self.bvp, self.method = bvp, method
        self.scene = sc
        q = self.q = int(method.degree)
        self.nq = quadrature_points(q)
        self.singular = singular_poles(sc)
        ends = tuple(float(x) for x in sc.piece_ends)
        P = self.P = sc.pieces
        given = None if method.layers is None else int(method.layers)
        core = None if method.core is None else float(method.core)
        #: the apex core as given (thicknesses, degree), for :meth:`describe`
        self.core = (core, method.core_degree)
        if given is None and core is None:
            # the default layers: from the uniform elements, each grading times the next,
            # down to APEX_CORE h
            uniform = [(ends[1] - ends[0]) / method.elements,
                       (ends[-1] - ends[-2]) / method.elements]
            given = max([0] + [max(0, math.ceil(math.log(APEX_CORE * sc.h / u)
                                                / math.log(method.grading)))
                               for u, singular in zip(uniform, self.singular) if singular])
            graded_default = True
        else:
            graded_default = False
        # where the mesh is graded: toward each singular pole; with ``layers`` given, toward
        # the first end too (a regular one)
        graded_ends = (self.singular[0] or (given is not None and not graded_default),
                       self.singular[1])
        edges, counts, layers = [], [], [0, 0]
        # a thin shell's layers (:func:`shellbvp.mesh.mesh_of`): its elements graded into
        # every layer, the singular or loaded poles among them, where the scene's mesh is
        # graded and no pole grading is asked for here
        thin = mesh_of(sc)
        if thin.graded and method.layers is None and method.core is None:
            graded_ends, thin_cuts = (False, False), np.asarray(thin.ends)
            owner = np.asarray(thin.pieces)
        else:
            thin_cuts = None
        for i in range(P):
            a, b = ends[i], ends[i + 1]
            cuts = list(np.linspace(a, b, method.elements + 1)) if thin_cuts is None else \
                [a] + list(thin_cuts[1:][owner == i][:-1]) + [b]
            ends_here = [end for end in (1, 0) if graded_ends[end]
                         and i == (0 if end == 0 else P - 1)]
            if given is None and ends_here:
                if len(ends_here) == 2:          # a piece between two singular poles
                    mid = 0.5 * (a + b)
                    half = max(1, method.elements // 2)
                    cuts = graded_piece(a, mid, core * sc.h, method.grading, half)[:-1] + \
                        graded_piece(mid, b, core * sc.h, method.grading, half, True)
                else:
                    cuts = graded_piece(a, b, core * sc.h, method.grading, method.elements,
                                        ends_here[0] == 1)
                for end in ends_here:
                    d = np.diff(cuts)
                    k = 0 if end == 0 else len(d) - 1
                    layers[end] = int(d[k] < (b - a) / method.elements * (1 - 1e-9))
                ends_here = []
            for end in ends_here:
                lo, hi = (cuts[0], cuts[1]) if end == 0 else (cuts[-2], cuts[-1])
                if end == 0:
                    graded = [lo] + [lo + (hi - lo) * method.grading ** k
                                     for k in range(given, 0, -1)] + [hi]
                else:
                    graded = [lo] + [hi - (hi - lo) * method.grading ** k
                                     for k in range(1, given + 1)] + [hi]
                layers[end] = len(graded) - 2
                cuts = graded + cuts[2:] if end == 0 else cuts[:-2] + graded
            edges.append(np.array(cuts))
            counts.append(len(cuts) - 1)
        self.end_layers = tuple(layers)
        self.layers = sum(self.end_layers)
        #: the innermost element at each singular pole (nan where none is graded)
        self.core_lengths = (float(edges[0][1] - edges[0][0]) if layers[0] else math.nan,
                             float(edges[-1][-1] - edges[-1][-2]) if layers[1] else math.nan)
        self.pieces = tuple(counts)
        self.piece_ends = np.array(ends)
        self.ea = np.concatenate([e[:-1] for e in edges])            # element starts
        self.eb = np.concatenate([e[1:] for e in edges])
        self.L = self.eb - self.ea
        E = self.E = self.ea.size
        self.element_piece = np.repeat(np.arange(P), counts)
        #: theta's offset per piece: the kinks passed (the unknown is theta less them)
        self.kink_offset = np.concatenate([[0.0], np.cumsum(bvp.jumps[:, 2])])
        self.element_offset = self.kink_offset[self.element_piece]
        t, tq, _, tc, _, _, _ = _element(q, self.nq)
        self.t_nodes, self.tq, self.tc = t, tq, tc
        self.sq = self.ea[:, None] + self.L[:, None] * tq[None, :]     # (E, nq)
        self.sn = self.ea[:, None] + self.L[:, None] * t[None, :]      # (E, q + 1)
        # global numbering: theta and r continuous everywhere, Lambda within pieces
        n1 = q + 1
        nodes = E * q + 1
        node = np.arange(E)[:, None] * q + np.arange(n1)[None, :]      # (E, q + 1)
        lam_start = np.concatenate([[0], np.cumsum(np.array(counts) * q + 1)])[:-1]
        first_e = np.concatenate([[0], np.cumsum(counts)])[:-1]
        lam_node = np.stack([lam_start[self.element_piece[e]]
                             + (e - first_e[self.element_piece[e]]) * q + np.arange(n1)
                             for e in range(E)])
        n_lam = int(sum(c * q + 1 for c in counts))
        off_lam, off_r = nodes, nodes + n_lam
        off_f = off_r + nodes
        #: both ends fix z: the constraint I = z0(0) - z0(L) with its multiplier, the last
        #: unknown (the axial force per radian, scaled by 12/h^2)
        self.fixes_z = tuple(e.fixes_z for e in sc.ends)
        self.z_constraint = all(self.fixes_z)
        #: the end whose z stays at its reference's (:attr:`Scene.z_anchor`)
        self.anchor = sc.z_anchor
        #: the parameter of the last evaluation (a prescribed displacement's value there)
        self._p = 0.0
        self.n_full = off_f + E * q + (1 if self.z_constraint else 0)
        self.idx = np.concatenate([node, off_lam + lam_node, off_r + node,
                                   off_f + np.arange(E * q).reshape(E, q)], axis=1)
        self.offsets = (0, off_lam, off_r, off_f, nodes, n_lam)
        #: per ring: the first element after its interface, and its circle's r unknown
        self.ring_elements = tuple(int(first_e[i + 1]) for i in sc.ring_interfaces)
        self.ring_r_nodes = tuple(off_r + e * q for e in self.ring_elements)
        geo = sc.geometry
        self.reference_ends = [geo.at_end(which) for which in ("first", "second")]
        fixed = {}
        last_offset = self.kink_offset[-1]
        for k, (end, (th_node, r_node), offset) in enumerate(zip(
                sc.ends, ((0, off_r), (nodes - 1, off_r + nodes - 1)), (0.0, last_offset))):
            r0, _, th0 = self.reference_ends[k]
            if end.kind == "pole":
                fixed[th_node] = (0.0, math.pi)[k] - offset
                fixed[r_node] = 0.0
            if end.kind in ("clamped", "symmetry", "sliding"):
                fixed[th_node] = float(th0) - offset
            if end.kind in ("clamped", "hinged", "diaphragm"):
                fixed[r_node] = float(r0)
        self.fixed = np.zeros(self.n_full)
        free = np.ones(self.n_full, dtype=bool)
        for k, v in fixed.items():
            self.fixed[k], free[k] = v, False
        self.free = np.flatnonzero(free)
        self.size = self.free.size
        # the unknowns are scaled so that Newton sees every one at the size that matters:
        # the stiffness of Lambda in an element of length l at s ~ l falls like l^2 (the
        # area there), so Lambda enters U as Lambda l / l0 (l0 the first piece's elements):
        # its Jacobian block is then O(1) and its round-off does not stall the updates
        l0 = (self.piece_ends[1] - self.piece_ends[0]) / method.elements
        scale = np.ones(self.n_full)
        lam_cols = self.idx[:, n1:2 * n1]
        scale[off_lam:off_r] = 0.0               # Lambda's: the largest of its elements'
        np.maximum.at(scale, lam_cols, np.repeat(np.minimum(1.0, self.L / l0)[:, None], n1, 1))
        self.scale = scale[self.free]
        #: the kind of every unknown (0 theta, 1 Lambda, 2 r, 3 the multiplier f, 4 the axial
        #: force's)
        kind = np.full(self.n_full, 4)
        kind[:off_lam], kind[off_lam:off_r], kind[off_r:off_f] = 0, 1, 2
        kind[off_f:off_f + E * q] = 3
        self.kind = kind[self.free]
        #: the core elements' reduction (None: the unknowns are the free ones themselves)
        self.T = None
        cores = [e for end, e in ((0, 0), (1, E - 1)) if self.singular[end] and
                 layers[end] and method.core_degree is not None and method.core_degree < q
                 and method.core is not None]
        if cores:
            self._reduce_cores(sorted(set(cores)), int(method.core_degree), free, scale, kind)
        where = np.full(self.n_full, -1)
        where[self.free] = np.arange(self.free.size)
        self._where = where
        rows = np.broadcast_to(where[self.idx][:, :, None], (E, 4 * q + 3, 4 * q + 3))
        cols = np.broadcast_to(where[self.idx][:, None, :], (E, 4 * q + 3, 4 * q + 3))
        keep = (rows >= 0) & (cols >= 0)
        self._keep = keep.ravel()
        self._rows, self._cols = rows.ravel()[self._keep], cols.ravel()[self._keep]
        self._phi, self._w = _point_kernels(sc.model, sc.material,
                                            sc.through_thickness_stimulus)
        self._fields = _fields_program(sc, self.pieces)
        self._c = np.asarray(sc.field_parameters, dtype=float)
        self.evaluations = 0
        self._monitor = None

    @property
    def groups(self) -> np.ndarray:
        """The kind of every unknown: the continuation's norm scales each kind on its own
        (:func:`shellbvp.continuation.arclength.unknown_weights`)."""
        return self.kind

    def _reduce_cores(self, cores, qc, free, scale, kind):
        """Make the core elements (the innermost at singular poles) of degree qc: their
        theta, Lambda and r at the q + 1 nodes are the interpolants of their values at qc + 1
        Chebyshev-Lobatto nodes (the two ends, shared with the neighbours, and qc - 1 new
        unknowns), their multiplier at the q Gauss points that of qc values at qc Gauss
        points: x_full = fixed + T u, u the reduced unknowns (the free ones outside the
        cores and the cores' new ones), and ``Linv`` the left inverse that reads u from a
        full vector (the new ones by interpolating the full nodal values)."""
        import scipy.sparse as sps

        q, n1 = self.q, self.q + 1
        t = chebyshev_points(q)
        tl = chebyshev_points(qc)
        A = _barycentric(tl, _lobatto_weights(qc), t)                 # (q + 1, qc + 1)
        A_down = _barycentric(t, _lobatto_weights(q), tl)             # (qc + 1, q + 1)
        gh, _ = _gauss(q)
        gl, _ = _gauss(qc)
        B = _barycentric(gl, _general_weights(gl), gh)                # (q, qc)
        B_down = _barycentric(gh, _general_weights(gh), gl)           # (qc, q)
        interior = set()
        for e in cores:
            interior |= set(self.idx[e, 1:q].tolist() + self.idx[e, n1 + 1:n1 + q].tolist()
                            + self.idx[e, 2 * n1 + 1:2 * n1 + q].tolist()
                            + self.idx[e, 3 * n1:].tolist())
        kept = [k for k in np.flatnonzero(free) if k not in interior]
        col = {k: i for i, k in enumerate(kept)}
        rows, cols, vals = list(kept), list(range(len(kept))), [1.0] * len(kept)
        lrows, lcols, lvals = list(range(len(kept))), list(kept), [1.0] * len(kept)
        new_scale, new_kind = list(scale[kept]), list(kind[kept])
        fixed = self.fixed.copy()
        n = len(kept)
        for e in cores:
            for f in range(3):                       # theta, Lambda, r: nodal, shared ends
                loc = self.idx[e, f * n1:(f + 1) * n1]
                new = list(range(n, n + qc - 1))
                n += qc - 1
                for j in range(1, q):
                    for m in range(qc + 1):
                        a = A[j, m]
                        if a == 0.0:
                            continue
                        if 0 < m < qc:
                            rows.append(loc[j]), cols.append(new[m - 1]), vals.append(a)
                        else:
                            end = loc[0] if m == 0 else loc[q]
                            if end in col:
                                rows.append(loc[j]), cols.append(col[end]), vals.append(a)
                            else:
                                fixed[loc[j]] += a * self.fixed[end]
                for m in range(1, qc):
                    lrows += [new[m - 1]] * n1
                    lcols += list(loc)
                    lvals += list(A_down[m])
                new_scale += [float(np.max(scale[loc]))] * (qc - 1)
                new_kind += [f] * (qc - 1)
            loc = self.idx[e, 3 * n1:]               # the multiplier, element-local
            new = list(range(n, n + qc))
            n += qc
            for j in range(q):
                for m in range(qc):
                    rows.append(loc[j]), cols.append(new[m]), vals.append(B[j, m])
            for m in range(qc):
                lrows += [new[m]] * q
                lcols += list(loc)
                lvals += list(B_down[m])
            new_scale += [1.0] * qc
            new_kind += [3] * qc
        self.T = sps.csr_matrix((vals, (rows, cols)), shape=(self.n_full, n))
        self.Linv = sps.csr_matrix((lvals, (lrows, lcols)), shape=(n, self.n_full))
        self.fixed = fixed
        self.free = np.array(kept)              # the unknowns that are full ones themselves
        self.scale = np.array(new_scale)
        self.kind = np.array(new_kind)
        self.size = n

    # --- unknowns -------------------------------------------------------------------------
    def full(self, U) -> np.ndarray:
        """The full unknowns (theta, Lambda, r at every node, f, [the axial force]) of the
        reduced U (scaled)."""
        if self.T is not None:
            return self.fixed + self.T @ (U / self.scale)
        x = self.fixed.copy()
        x[self.free] = U / self.scale
        return x

    def reduced(self, x) -> np.ndarray:
        """U (scaled) from full unknowns x: the free ones, and a core element's by
        interpolation (:meth:`_reduce_cores`)."""
        if self.T is not None:
            return (self.Linv @ x) * self.scale
        return x[self.free] * self.scale

    def _reduce_vector(self, v):
        """A gradient in the full unknowns as one in the reduced ones (unscaled)."""
        return self.T.T @ v if self.T is not None else v[self.free]

    def local(self, U) -> np.ndarray:
        """The unknowns per element (E, 4 q + 3): theta (less the kinks passed), Lambda, r
        at the nodes, f."""
        return self.full(U)[self.idx]

    def _points(self, U, p):
        """The state at the energy points V (E, nq, 4), the collocation points (E, q, 4),
        the fields there (E, nq, n_fields), their p-derivative, and the pressure with its
        p-derivative; theta with the kinks passed added."""
        _, _, _, _, _, BE, BC = _element(self.q, self.nq)
        xl = self.local(U)
        F, dF, P, dP = (np.asarray(a) for a in self._fields(self.sq, float(p), self._c))
        if not self.scene.fields_admissible(F):
            # name what fails, and on which piece (elements are counted piece by piece)
            bad = next(e for e in range(F.shape[0]) if not self.scene.fields_admissible(F[e]))
            self.scene.check_fields(F[bad].T, int(self.element_piece[bad]), p, interior=True)
        V = np.einsum("gkn,en->egk", BE, xl)
        Uc = np.einsum("gkn,en->egk", BC, xl)
        V[..., 0] += self.element_offset[:, None]
        Uc[..., 0] += self.element_offset[:, None]
        return V, Uc, F, dF, float(P), float(dP)

    # --- end loads and the axial position -------------------------------------------------
    def _end_loads(self, p):
        """Per end, the conjugate loads per radian (Q_r, Q_z, Q_theta) at p and their
        p-derivatives (:meth:`End.conjugate`)."""
        return [(end.conjugate(p, float(ref[0])), end.conjugate(p, float(ref[0]), 1))
                for end, ref in zip(self.scene.ends, self.reference_ends)]

    def _ring_loads(self, p):
        """Per ring, its (Q_r, Q_z) per radian at p and their p-derivatives
        (:meth:`shellbvp.scene.Ring.conjugate`)."""
        return [(ring.conjugate(p), ring.conjugate(p, 1)) for ring in self.scene.rings]

    def _drop_coefficients(self, loads, rings):
        """Per element e, the coefficient c_e of its drop I_e = int_e Lambda sin(theta) ds in
        the dead loads' potential (-Q_z z on each end and ring, z eliminated through the
        drops from the anchoring end), and dc_e/dp (E,) each: with the first end anchoring,
        z(s) = z(0) - (the drops before s), so a load at s adds Q_z to the elements before
        it; with the second, z(s) = z(L) + (the drops after s), -Q_z to those after. c_e is
        the axial force F_z per radian in element e."""
        (Qa, dQa), (Qb, dQb) = loads
        c, dc = np.zeros(self.E), np.zeros(self.E)
        if self.anchor == 1:
            c -= Qa[1]                         # z(0) = z(L) + I: potential -Q_a I
            dc -= dQa[1]
        else:
            c += Qb[1]                         # z(L) = z(0) - I: potential +Q_b I
            dc += dQb[1]
        for (Qk, dQk), e in zip(rings, self.ring_elements):
            Q, dQ = Qk[1], dQk[1]
            side = slice(None, e) if self.anchor == 0 else slice(e, None)
            sign = 1.0 if self.anchor == 0 else -1.0
            c[side] += sign * Q
            dc[side] += sign * dQ
        return c, dc

    def _drop(self, V):
        """I = int Lambda sin(theta) ds by the energy quadrature, with its gradient (E, nq,
        4) and Hessian (E, nq, 4, 4) at the energy points in v = (theta, theta_t, Lambda,
        r), quadrature weights included."""
        _, _, wq, _, _, _, _ = _element(self.q, self.nq)
        w = self.L[:, None] * wq[None, :]
        th, Lam = V[..., 0], V[..., 2]
        sn, cs = np.sin(th), np.cos(th)
        g = np.zeros(V.shape)
        g[..., 0], g[..., 2] = Lam * cs * w, sn * w
        H = np.zeros(V.shape + (4,))
        H[..., 0, 0] = -Lam * sn * w
        H[..., 0, 2] = H[..., 2, 0] = cs * w
        return float(np.sum(Lam * sn * w)), g, H

    def _prescribed(self, end, p) -> tuple[float, float]:
        """(displacement, d/dp) prescribed at ``end`` (zeros where none is)."""
        d = self.scene.ends[end].displacement
        return (0.0, 0.0) if d is None else (float(d(p)), load_rate(d, p))

    def _z_first(self, I):
        """The height of the first end: its reference's where it anchors z (or where no end
        holds z: the first end is then the pinned one; plus its prescribed displacement where
        both ends are displaced), else the second's plus I."""
        z0a, z0b = float(self.reference_ends[0][1]), float(self.reference_ends[1][1])
        if self.anchor == 1:
            return z0b + I
        return z0a + self._prescribed(0, self._p)[0]

    def _z_residual(self, I, k) -> tuple[float, float]:
        """The axial constraint's row where both ends hold z, 2 pi k (z(0) - z(L) - I) with
        each end at its reference's height plus its prescribed displacement, and its
        p-derivative."""
        (da, dda), (db, ddb) = (self._prescribed(end, self._p) for end in (0, 1))
        z0a, z0b = float(self.reference_ends[0][1]), float(self.reference_ends[1][1])
        return (2 * math.pi * k * (z0a + da - z0b - db - I),
                2 * math.pi * k * (dda - ddb))

    # --- the system -----------------------------------------------------------------------
    def evaluate(self, U, p):
        import scipy.sparse as sps

        from ..errors import ConvergenceError

        sc, q, nq, E = self.scene, self.q, self.nq, self.E
        _, _, wq, _, wc, BE, BC = _element(q, nq)
        self._p = float(p)
        V, Uc, F, dF, P, dP = self._points(U, p)
        self.evaluations += 1
        self.bvp.evaluations += 1
        if not np.all(V[..., 2] > 0):
            raise ConvergenceError(f"energy method: the meridional stretch is not positive at "
                                   f"{sc.quote(p)} (a step too long)")
        n = E * nq
        Lq = np.repeat(self.L, nq)
        nf = F.shape[-1]
        gE, HE, gpE = _padded(self._phi, n, (V.reshape(n, 4), Lq, F.reshape(n, nf),
                                             dF.reshape(n, nf)),
                              (P, dP, sc.material_parameter, sc.h))
        gE, HE, gpE = gE.reshape(E, nq, 4), HE.reshape(E, nq, 4, 4), gpE.reshape(E, nq, 4)
        # the drop I's share: the axial end loads' potential, and the axial constraint
        loads, rings = self._end_loads(p), self._ring_loads(p)
        cI, dcI = self._drop_coefficients(loads, rings)
        xfull = self.full(U)
        fz = xfull[-1] if self.z_constraint else 0.0
        k = sc.h * sc.h / 12.0
        I, gI, HI = self._drop(V)
        coef = cI - k * fz                        # the constraint's term: fz (z0a - z0b - I)
        if np.any(coef != 0.0):
            gE = gE + coef[:, None, None] * gI / (self.L[:, None, None] * wq[None, :, None])
            HE = HE + coef[:, None, None, None] * HI / (self.L[:, None, None, None]
                                                        * wq[None, :, None, None])
        if np.any(dcI != 0.0):
            gpE = gpE + dcI[:, None, None] * gI / (self.L[:, None, None] * wq[None, :, None])
        we = (2 * math.pi * self.L[:, None] * wq[None, :]).reshape(n)
        gC, HC = _constraint_terms(Uc, self.L, sc.h)
        wk = 2 * math.pi * self.L[:, None] * wc[None, :]
        BEf, BCf = BE.reshape(nq * 4, -1), BC.reshape(q * 4, -1)
        g = ((gE.reshape(n, 4) * we[:, None]).reshape(E, nq * 4) @ BEf
             + (gC * wk[..., None]).reshape(E, q * 4) @ BCf)
        gp = (gpE.reshape(n, 4) * we[:, None]).reshape(E, nq * 4) @ BEf
        HEw = (HE.reshape(n, 4, 4) * we[:, None, None]).reshape(E, nq, 4, 4)
        HCw = HC * wk[..., None, None]
        # B^T blockdiag(H) B per element: the blocks applied to B, then B^T
        H = (BEf.T @ np.matmul(HEw, BE).reshape(E, nq * 4, -1)
             + BCf.T @ np.matmul(HCw, BC).reshape(E, q * 4, -1))
        Rf = np.bincount(self.idx.ravel(), g.ravel(), self.n_full)
        Rpf = np.bincount(self.idx.ravel(), gp.ravel(), self.n_full)
        # the radial loads and moments on the ends: potential -Q r(end) - Q_theta theta(end)
        nodes, off_r = self.offsets[4], self.offsets[2]
        for (Q, dQ), (th_node, r_node) in zip(loads, ((0, off_r),
                                                      (nodes - 1, off_r + nodes - 1))):
            Rf[r_node] -= 2 * math.pi * Q[0]
            Rf[th_node] -= 2 * math.pi * Q[2]
            Rpf[r_node] -= 2 * math.pi * dQ[0]
            Rpf[th_node] -= 2 * math.pi * dQ[2]
        for (Q, dQ), r_node in zip(rings, self.ring_r_nodes):    # the rings' radial loads
            Rf[r_node] -= 2 * math.pi * Q[0]
            Rpf[r_node] -= 2 * math.pi * dQ[0]
        if self.T is not None:
            return self._reduced_system(U, p, Rf, Rpf, H, I, gI, V, xfull, k, BE)
        rows, cols, vals = [self._rows], [self._cols], [H.ravel()[self._keep]]
        if self.z_constraint:
            # d L / d fz = 2 pi k (z(0) - z(L) - I); its cross terms -2 pi k dI/dU
            Rf[-1], Rpf[-1] = self._z_residual(I, k)
            dI = np.bincount(self.idx.ravel(), np.einsum("gkn,egk->en", BE, gI).ravel(),
                             self.n_full)
            col = self._where[-1]
            sel = np.flatnonzero((dI != 0) & (self._where >= 0))
            sel = sel[sel != self.n_full - 1]
            entries = -2 * math.pi * k * dI[sel]
            rows += [self._where[sel], np.full(sel.size, col)]
            cols += [np.full(sel.size, col), self._where[sel]]
            vals += [entries, entries]
        c = self.scale
        R = Rf[self.free] / c
        Rp = Rpf[self.free] / c
        r_all, c_all = np.concatenate(rows), np.concatenate(cols)
        v_all = np.concatenate(vals) / (c[r_all] * c[c_all])
        J = sps.csc_matrix((v_all, (r_all, c_all)), shape=(self.size, self.size))
        self._monitor = (np.array(U, dtype=float), self._observable(xfull, V, gI, I))
        if not (np.all(np.isfinite(R)) and np.all(np.isfinite(v_all))):
            raise ConvergenceError(f"energy method: non-finite energy gradient at "
                                   f"{sc.quote(p)}")
        return R, J, Rp

    def _reduced_system(self, U, p, Rf, Rpf, H, I, gI, V, xfull, k, BE):
        """:meth:`evaluate`'s (R, J, Rp) through the core reduction: the full gradient,
        Hessian and p-derivative (the axial constraint's terms included) mapped by T."""
        import scipy.sparse as sps

        from ..errors import ConvergenceError

        E, m = self.E, self.idx.shape[1]
        r = np.broadcast_to(self.idx[:, :, None], (E, m, m)).ravel()
        c_ = np.broadcast_to(self.idx[:, None, :], (E, m, m)).ravel()
        rows, cols, vals = [r], [c_], [H.ravel()]
        if self.z_constraint:
            Rf[-1], Rpf[-1] = self._z_residual(I, k)
            dI = np.bincount(self.idx.ravel(), np.einsum("gkn,egk->en", BE, gI).ravel(),
                             self.n_full)
            sel = np.flatnonzero(dI[:-1] != 0)
            entries = -2 * math.pi * k * dI[sel]
            last = np.full(sel.size, self.n_full - 1)
            rows += [sel, last]
            cols += [last, sel]
            vals += [entries, entries]
        Jf = sps.csr_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                    np.concatenate(cols))),
                            shape=(self.n_full, self.n_full))
        T, c = self.T, self.scale
        Dinv = sps.diags(1.0 / c)
        J = (Dinv @ (T.T @ Jf @ T) @ Dinv).tocsc()
        R = (T.T @ Rf) / c
        Rp = (T.T @ Rpf) / c
        self._monitor = (np.array(U, dtype=float), self._observable(xfull, V, gI, I))
        if not (np.all(np.isfinite(R)) and np.all(np.isfinite(J.data))):
            raise ConvergenceError(f"energy method: non-finite energy gradient at "
                                   f"{self.scene.quote(p)}")
        return R, J, Rp

    def _end_values(self, xfull, I):
        """Per end, the current (r, z, theta) there, and their gradients in the full unknowns
        through (r node, I, theta node): ((values, which) per end)."""
        nodes, off_r = self.offsets[4], self.offsets[2]
        za = self._z_first(I)
        out = []
        for k, (th_node, r_node, offset) in enumerate(((0, off_r, 0.0),
                                                       (nodes - 1, off_r + nodes - 1,
                                                        self.kink_offset[-1]))):
            z = za if k == 0 else za - I
            out.append({"r": xfull[r_node], "z": z, "theta": xfull[th_node] + offset,
                        "nodes": {"r": r_node, "theta": th_node}})
        return out

    def _observable(self, xfull, V, gI, I):
        """(m, dm/dU) from the state V at the energy points (:attr:`shellbvp.Scene.
        monitor_terms`): sum of coefficient x (end value - its reference) over the scale;
        z at the ends through I (dz/dI = 0, 1 or -1 by which end holds z)."""
        _, _, _, _, _, BE, _ = _element(self.q, self.nq)
        sc = self.scene
        refs = self.bvp._refs
        dI = np.bincount(self.idx.ravel(), np.einsum("gkn,egk->en", BE, gI).ravel(),
                         self.n_full)
        ends = self._end_values(xfull, I)
        held_second = self.anchor == 1
        dz = ((1.0 if held_second else 0.0), (0.0 if held_second else -1.0))
        value, grad = 0.0, np.zeros(self.n_full)
        for coef, comp, end in sc.monitor_terms:
            value += coef * (ends[end][comp] - refs[end][comp])
            if comp == "z":
                grad += coef * dz[end] * dI
            else:
                grad[ends[end]["nodes"][comp]] += coef
        scale = self.bvp.scale
        return value / scale, self._reduce_vector(grad) / self.scale / scale

    def monitor(self, U):
        """(m, dm/dU): the scene's monitor (the last evaluation's when it was at U)."""
        if self._monitor is not None and np.array_equal(self._monitor[0], U):
            return self._monitor[1]
        _, _, _, _, _, BE, _ = _element(self.q, self.nq)
        xfull = self.full(U)
        V = np.einsum("gkn,en->egk", BE, xfull[self.idx])
        V[..., 0] += self.element_offset[:, None]
        I, gI, _ = self._drop(V)
        return self._observable(xfull, V, gI, I)

    # --- profiles -------------------------------------------------------------------------
    def from_profile(self, profile) -> np.ndarray:
        """U from a callable s -> (6, n) of the BVP's unknowns (r, z, theta, m, f_r, f_z):
        theta and r at the nodes, Lambda = |(r', z')| by differences within each piece,
        f = f_r at the collocation points."""
        x = np.zeros(self.n_full)
        q, E = self.q, self.E
        _, off_lam, off_r, off_f, nodes, _ = self.offsets
        s_nodes = np.concatenate([self.sn[:, :-1].ravel(), [self.sn[-1, -1]]])
        Y = np.asarray(profile(s_nodes), dtype=float)
        x[:nodes], x[off_r:off_r + nodes] = Y[2] - self._node_offset(), Y[0]
        # Lambda per element node, by second-order differences kept inside the element's
        # piece (central, or one-sided at a piece's ends, where Lambda may jump)
        lo = self.piece_ends[self.element_piece][:, None]
        hi = self.piece_ends[self.element_piece + 1][:, None]
        d = 1e-5 * (hi - lo)
        side = np.where(self.sn - d < lo, 1.0, np.where(self.sn + d > hi, -1.0, 0.0))
        shift = np.stack([self.sn + (side + k) * d for k in (-1.0, 0.0, 1.0)])
        shift = np.clip(shift, lo, hi)
        Ys = np.asarray(profile(shift.ravel()), dtype=float).reshape(6, 3, E, q + 1)
        c = np.zeros((3, E, q + 1))
        c[:, side == 0] = np.array([-0.5, 0.0, 0.5])[:, None]
        c[:, side > 0] = np.array([-1.5, 2.0, -0.5])[:, None]
        c[:, side < 0] = np.array([0.5, -2.0, 1.5])[:, None]
        Lam = np.hypot(np.sum(c * Ys[0], axis=0), np.sum(c * Ys[1], axis=0)) / d
        x[self.idx[:, q + 1:2 * q + 2]] = Lam
        sc_ = self.ea[:, None] + self.L[:, None] * self.tc[None, :]
        x[off_f:off_f + E * q] = np.asarray(profile(sc_.ravel()), dtype=float)[4]
        if self.z_constraint:             # the axial force: F_z = -(h^2/12) fz
            x[-1] = -float(np.mean(Y[5]))
        return self.reduced(x)

    def _node_offset(self):
        """theta's kink offset at every global node (an interface's node belongs to the next
        piece, whose first element it starts)."""
        return np.concatenate([np.repeat(self.element_offset, self.q), self.element_offset[-1:]])

    def _values(self, U):
        """theta (less the kinks passed), Lambda, r at the nodes (E, q + 1) each, and f at
        the collocation points."""
        xl = self.local(U)
        n1 = self.q + 1
        return xl[:, :n1], xl[:, n1:2 * n1], xl[:, 2 * n1:3 * n1], xl[:, 3 * n1:]

    def _locate(self, s):
        """(element, local coordinate) of every s; an interface belongs to the next piece,
        as in :meth:`shellbvp.bvp.ShellBVP.profile`."""
        s = np.asarray(s, dtype=float)
        e = np.clip(np.searchsorted(self.ea, s, side="right") - 1, 0, self.E - 1)
        return e, (s - self.ea[e]) / self.L[e]

    def _at_nodes(self, x):
        """The Lagrange matrix from an element's nodes to local coordinates x."""
        return _barycentric(self.t_nodes, _lobatto_weights(self.q), x)

    def interpolate(self, values, s, *, at="nodes"):
        """Element-wise interpolation of ``values`` (E, k) (at the nodes, or at the
        collocation points with ``at="collocation"``) to the points s."""
        e, x = self._locate(s)
        C = self._at_nodes(x) if at == "nodes" else \
            _barycentric(self.tc, _general_weights(self.tc), x)
        return np.einsum("nk,nk->n", C, values[e])

    def _z(self, th, Lam, s):
        """z(s) = z(0) - int_0^s Lambda sin(theta) ds, by Gauss quadrature per element
        (theta with its kink offsets), z(0) as the ends hold it (:meth:`_z_first`); and
        z(0)."""
        _, _, wq, _, _, BE, _ = _element(self.q, self.nq)
        Iq = BE[:, 0, :self.q + 1]                       # nodes -> the energy points
        th = th + self.element_offset[:, None]
        f = np.sin(th @ Iq.T) * (Lam @ Iq.T)
        whole = np.concatenate([[0.0], np.cumsum(np.sum(f * wq * self.L[:, None], axis=1))])
        e, x = self._locate(s)
        tq, _ = _gauss(self.nq)
        C = self._at_nodes((x[:, None] * tq[None, :]).ravel()).reshape(x.size, self.nq, -1)
        part = np.sin(np.einsum("ngk,nk->ng", C, th[e])) * np.einsum("ngk,nk->ng", C, Lam[e])
        z0 = self._z_first(float(whole[-1]))
        return z0 - (whole[e] + np.sum(part * wq, axis=1) * x * self.L[e]), z0

    def _axial_force(self, U, p, s) -> np.ndarray:
        """F_z per radian at the points s: per element, the coefficient of its drop
        (:meth:`_drop_coefficients`: the axial line loads' reactions, F(second) = Q and
        F(first) = -Q, jumping by -Q at a ring) plus the axial constraint's multiplier
        where both ends hold z."""
        c, _ = self._drop_coefficients(self._end_loads(p), self._ring_loads(p))
        if self.z_constraint:
            c = c - self.scene.h ** 2 / 12 * float(self.full(U)[-1])
        return c[self._locate(np.atleast_1d(np.asarray(s, dtype=float)))[0]]

    def profile(self, U, p):
        """A callable s -> (6, n): the BVP's unknowns (r, z, theta, m, f_r, f_z) of this
        solution (m and f scaled by 12/h^2), a guess for any method."""
        scale = 12.0 / self.scene.h ** 2

        def ev(s):
            st = self.state_at(U, p, np.atleast_1d(np.asarray(s, dtype=float)))
            return np.stack([st["r"], st["z"], st["theta"], scale * st["M"],
                             scale * st["F_r"], scale * st["F_z"]])

        return ev

    def dense(self, U, p=None):
        ev = self.profile(U, 0.0 if p is None else p)
        a, b = self.piece_ends[:-1], self.piece_ends[1:]

        def at(t):
            t = np.atleast_1d(np.asarray(t, dtype=float))
            # each piece on its own side of an interface: nudge its ends inside
            out = []
            for i in range(self.P):
                s = a[i] + (b[i] - a[i]) * t
                s = np.clip(s, a[i], np.nextafter(b[i], a[i]) if i < self.P - 1 else b[i])
                out.append(ev(s))
            return np.concatenate(out)

        return at

    def _fields_at(self, s, p):
        """The fields (:data:`shellbvp.kinematics.FIELDS`, n_fields, len(s)) at points s,
        each on its element's piece."""
        from ..fields import point_fields

        e, _ = self._locate(s)
        F = None
        for i in range(self.P):
            sel = self.element_piece[e] == i
            if np.any(sel):
                vals = point_fields(self.scene, i, s[sel], p, self._c, np)
                if F is None:
                    F = np.zeros((vals.shape[0], s.size))
                F[:, sel] = vals
        return F

    def state_at(self, U, p, s) -> dict:
        """The state at the points s (inside the meridian): r, z, theta, stretches,
        curvatures, the stimulus fields (g1, g2, kb1, kb2), the moment M = -W_k1 t g1 g2 r0
        / Lambda and the forces F_r (the multipliers, h^2/12 f) and F_z, per mu* h R per
        radian, and the W gradient and Hessian in (lam1, lam2, k1, k2); ``z_pole`` the first
        end's height."""
        from .. import kinematics as K

        th, Lam, r, f = self._values(U)
        sc = self.scene
        s = np.atleast_1d(np.asarray(s, dtype=float))
        e, x = self._locate(s)
        C = self._at_nodes(x)
        Dm = differentiation_matrix(self.q)
        thv = np.einsum("nk,nk->n", C, th[e]) + self.element_offset[e]
        dth = np.einsum("nk,nk->n", C, (th @ Dm.T)[e]) / self.L[e]
        Lv = np.einsum("nk,nk->n", C, Lam[e])
        rv = np.einsum("nk,nk->n", C, r[e])
        F = self._fields_at(s, p)
        with np.errstate(divide="ignore", invalid="ignore"):
            X = np.stack(K.principal_state(rv, thv, Lv, dth, F[K.R0], F[K.G1], F[K.G2], np))
        gw, Hw = _padded(self._w, s.size, (np.ascontiguousarray(X.T),
                                           np.ascontiguousarray(F.T)),
                         (sc.material_parameter, sc.h))
        M = -gw[:, 2] * K.area_factor(F) / Lv
        F_r = sc.h ** 2 / 12 * self.interpolate(f, s, at="collocation")
        self._p = float(p)                 # (a prescribed displacement's value in z)
        z, z0 = self._z(th, Lam, s)
        return dict(s=s, r=rv, z=z, theta=thv, X=X, F=F[:4], t=F[K.THICKNESS], M=M, F_r=F_r,
                    F_z=self._axial_force(U, p, s), gw=gw, Hw=Hw, z_pole=z0)

    def output_points(self) -> np.ndarray:
        """The element nodes, each once, without the poles (where lam2 and k2 are limits),
        an interface's node belonging to the next piece."""
        s = np.concatenate([self.sn[:, :-1].ravel(), [self.sn[-1, -1]]])
        return s[int(self.bvp.poles[0]):len(s) - int(self.bvp.poles[1])]

    def nodes(self, U, p):
        t = np.linspace(0.0, 1.0, 2 * self.q + 1)
        return t, self.dense(U, p)(t)

    def transfer(self, U, p, other) -> np.ndarray:
        """U carried onto ``other`` (another :class:`RitzSystem` of the same scene) by
        element-wise interpolation."""
        if not isinstance(other, RitzSystem):
            return other.from_profile(self.profile(U, p))
        th, Lam, r, f = self._values(U)
        x = np.zeros(other.n_full)
        _, off_lam, off_r, off_f, nodes, _ = other.offsets
        s_nodes = np.concatenate([other.sn[:, :-1].ravel(), [other.sn[-1, -1]]])
        x[:nodes] = self.interpolate(th, s_nodes)
        x[off_r:off_r + nodes] = self.interpolate(r, s_nodes)
        # Lambda jumps at interfaces: each element's nodes from inside its own piece
        lo = other.piece_ends[other.element_piece][:, None]
        hi = other.piece_ends[other.element_piece + 1][:, None]
        inside = np.clip(other.sn, lo, np.nextafter(hi, lo))
        e, xx = self._locate(inside.ravel())
        C = self._at_nodes(xx)
        lam_vals = np.einsum("nk,nk->n", C, Lam[e]).reshape(other.sn.shape)
        x[other.idx[:, other.q + 1:2 * other.q + 2]] = lam_vals
        sc_ = other.ea[:, None] + other.L[:, None] * other.tc[None, :]
        x[off_f:off_f + other.E * other.q] = self.interpolate(f, sc_.ravel(), at="collocation")
        if other.z_constraint:
            x[-1] = -12.0 / self.scene.h ** 2 * float(
                self._axial_force(U, p, [self.scene.length])[0])
        return other.reduced(x)

    # --- resolution -----------------------------------------------------------------------
    def with_degree(self, q) -> "RitzSystem":
        from dataclasses import replace

        if not MIN_DEGREE <= q <= MAX_DEGREE:
            raise ValueError(f"cannot refine beyond degree {MAX_DEGREE} per element")
        return RitzSystem(self.bvp, replace(self.method, degree=int(q)))

    def refined(self) -> "RitzSystem":
        return self.with_degree(self.q + REFINE_STEP)

    @property
    def rung_ratio(self) -> float:
        """The error's factor per rung (:class:`~.base.Discretisation`): 0 where p-refinement
        converges exponentially (elements graded geometrically into every singularity);
        at a point-loaded pole without such layers, algebraic
        (:func:`shellbvp.mesh.loaded_pole_ratio`)."""
        return 0.0 if self.layers else loaded_pole_ratio(self.scene, self.q, REFINE_STEP)

    def for_tolerance(self, tol: float) -> "RitzSystem":
        return self

    def describe(self) -> dict:
        """The resolution: degree per element, elements in all (the pole layers included)
        and the pole layers."""
        out = {"method": "energy", "degree": self.q, "elements": self.E,
               "layers": self.layers}
        if self.core[0] is not None and any(self.singular):
            out["core"] = f"{self.core[0]:g} h"
            out["core_degree"] = self.q if self.core[1] is None else self.core[1]
        return out

    # --- what the energy gives beyond the equations ---------------------------------------
    def energies(self, U, p) -> tuple:
        """(E_s, E_b, E_p): stretching, bending energy and the pressure's potential, per
        mu* h R^2, by this system's own quadrature."""
        from .. import kinematics as K
        from ..energy import energy_terms

        sc = self.scene
        V, _, F, _, P, _ = self._points(U, p)
        F = np.moveaxis(F, -1, 0)
        th, Lam, r = V[..., 0], V[..., 2], V[..., 3]
        X = K.principal_state(r, th, Lam, V[..., 1] / self.L[:, None], F[K.R0], F[K.G1],
                              F[K.G2], np)
        pot = 0.5 * P * r * r * Lam * np.sin(th)
        rb = K.RHOB.start
        ws, wb, _, _ = energy_terms(*X, F[K.KB1], F[K.KB2], lam=sc.lam, nu=sc.nu,
                                    model=sc.model, material=sc.material, rhob1=F[rb],
                                    rhob2=F[rb + 1], rhob3=F[rb + 2])
        _, wq = _gauss(self.nq)
        dA = 2 * math.pi * K.area_factor(F) * self.L[:, None] * wq
        Ep = float(np.sum(2 * math.pi * pot * self.L[:, None] * wq))
        ht2 = (sc.h * F[K.THICKNESS]) ** 2 / 12
        return float(np.sum(ws * dA)), float(np.sum(ht2 * wb * dA)), Ep

    def spectrum(self, U, p, *, count: int = 4):
        """The ``count`` smallest eigenvalues and modes of the discrete second variation at
        fixed stimulus: the Hessian of the Lagrangian on the tangent space of the
        constraints (r' = Lambda cos theta at the collocation points and the fixed values),
        scaled by its own diagonal (eigenvalues relative to the stiffness of single nodal
        values, ~1 for a stiff mode, dimensionless; the elements graded toward a singular
        apex are so short that any mass weighted by the area is singular in double
        precision, while the signs, and so the stability, do not depend on the scaling).
        Modes scaled to a largest nodal value of 1. All positive: stable. A
        :class:`shellbvp.stability.SecondVariation` (theta and Lambda components at the
        element nodes ``s``; ``nodes`` is the degree per element; ``projected_gradient`` the
        gradient's norm on that space)."""
        from scipy.linalg import eigh, null_space

        from ..stability import SecondVariation

        R, J, _ = self.evaluate(U, p)
        J = J.toarray()
        q = self.q
        nodes = self.offsets[4]
        primal = self.kind < 3
        K, A = J[np.ix_(primal, primal)], J[np.ix_(~primal, primal)]
        # Jacobi scaling (a congruence: the inertia, so the stability, is unchanged): the
        # stiffness of the unknowns of elements graded toward the apex falls like their
        # length squared, below the round-off of an unscaled eigenvalue problem
        d = np.abs(np.diag(K))
        d = 1.0 / np.sqrt(np.maximum(d, 1e-300 + 1e-14 * d.max()))
        Z = null_space(A * d[None, :])
        Kr = Z.T @ (d[:, None] * K * d[None, :]) @ Z
        k = min(count, Kr.shape[0])
        vals, vecs = eigh((Kr + Kr.T) / 2, subset_by_index=[0, k - 1])
        modes = d[:, None] * (Z @ vecs) / self.scale[primal][:, None]
        modes /= np.max(np.abs(modes), axis=0)
        if self.T is not None:
            full = np.asarray(self.T[:, np.flatnonzero(primal)] @ modes)
        else:
            full = np.zeros((self.n_full, k))
            full[self.free[primal]] = modes
        th_modes = full[:nodes].T
        lam_nodes = full[self.idx[:, q + 1:2 * q + 2]]             # (E, q + 1, k)
        lam_modes = np.concatenate([lam_nodes[:, :-1].reshape(-1, k), lam_nodes[-1:, -1]]).T
        s = np.concatenate([self.sn[:, :-1].ravel(), [self.sn[-1, -1]]])
        return SecondVariation(eigenvalues=vals, s=s, theta_modes=th_modes,
                               lam1_modes=lam_modes, nodes=q,
                               projected_gradient=float(np.linalg.norm(Z.T @ (d * R[primal]))))
