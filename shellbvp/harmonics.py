"""Stability beyond axisymmetry: the second variation of the full 2D energy, one circumferential
harmonic at a time.

About an axisymmetric equilibrium x0(s, omega) = (r cos omega, r sin omega, z) (s the
arclength of the reference meridian) perturb the mid-surface by

    dx = U_r(s) cos(n omega) e_r + U_w(s) sin(n omega) e_omega + U_z(s) cos(n omega) e_z

(cylindrical components; the meridional, azimuthal and normal components of the issue's
u cos, v sin, w cos are u = U_r cos(theta) - U_z sin(theta), v = U_w,
w = U_r sin(theta) + U_z cos(theta), a pointwise rotation in the meridional plane). The energy
is E = int int W(a, b; abar, bbar) dA_target + P V, W the reduced energy of general forms
(:mod:`shellbvp.forms`), a_ij = x_i . x_j, b_ij = x_ij . N, and for a pressure P
(follower load) V = (1/3) int int x . (x_s x x_omega) ds domega plus, at an end that moves in
its own plane (roller, sliding, symmetry) or keeps its radius (diaphragm), the lid that closes
the rim (:data:`LID_ENDS`, :func:`_lid_stiffness`): the volume of the axisymmetric solve,
whose variation is the follower load. An end free to leave its plane and change its radius
(free) has no such lid, and a pressure there is refused (no potential).

Decoupling. The density depends on (x, x_s, x_omega, x_ss, x_somega, x_omegaomega) at a point,
and is invariant under rotations about the axis, so its Hessian H in these 18 numbers, written
in the local frame (e_r, e_omega, e_z), is the same at every omega. In that frame every
component of dx and of its derivatives is either (coefficient)(s) cos(n omega) (the r and z
components of dx, dx_s, dx_ss, dx_oo and the omega components of dx_o, dx_so) or
(coefficient)(s) sin(n omega) (the others), with the coefficients (L_n below)

    dx_o  = (-n U_r - U_w, n U_w + U_r, -n U_z),
    dx_oo = (-(n^2 + 1) U_r - 2 n U_w, -2 n U_r - (n^2 + 1) U_w, -n^2 U_z),

and the base state's reflection symmetry omega -> -omega makes H couple cos-components with
cos-components only. The integral over omega is then exact: pi int (L_n d)^T H (L_n d) ds for
n >= 1. For n = 0 the cos family is the axisymmetric (U_r, U_z) and the sin family vanishes;
its partner (U_w e_omega: twist) is taken together with it, with weight 2 pi: the n = 0
matrix holds the axisymmetric second variation and the torsional one.

Pole regularity (a smooth vector field near the axis: a scalar ~ r^n, u_r +- i u_omega ~
r^(n -+ 1)), imposed at each end on the axis:

* n = 0: U_r = U_w = 0 and U_z' = 0 (no cone at the apex), and U_z = 0 where the pole's
  displacement is prescribed (an indenter holds it);
* n = 1: U_z = 0 and U_r + U_w = 0 (a lateral translation is U_r = 1, U_w = -1; a tilt
  has U_z ~ r, so U_z' is free);
* n >= 2: U_r = U_w = U_z = 0 and U_z' = 0 (curvature changes ~ n^2 U_z / r^2 must be
  square-integrable).

The other ends (:class:`shellbvp.scene.End`): a clamped end has U = 0 and no rotation of
the tangent out of the surface, U_r' sin(theta) + U_z' cos(theta) = 0; a hinged end U = 0; a
roller U_z = 0; a sliding end U_z = 0 and no rotation; a diaphragm U_r = U_w = 0 (the end
ring keeps its radius and its points their azimuth; U_z, the warping, is free); a symmetry
end (a mirror plane normal to the axis) U_z = 0 and no rotation:
only the modes symmetric about that plane are seen, as in the axisymmetric problem (the
antisymmetric ones of the whole shell need the whole meridian); a free end none. Across an
interface (a joint of the geometry or a break of the stimulus) U and the rotation
(dx_s . N) / |x_s| are continuous: the joint is rigid, at a kink too. Where the stretch
|x_s| jumps there or the tangent turns, "the angle between the two tangents does not
change" is not linear in dx: the second variation on the admissible set is then the
Hessian of the Lagrangian, whose extra term (the interface moment times the condition's
second variation) is included; without it the eigenvalues fall without bound as the degree
grows. Where the ends leave rigid motions (n = 0: the axial translation U_z = 1 unless an
end holds z, the rotation about the axis U_w = r unless an end holds its position; n = 1:
the lateral translation (1, -1, 0) and the tilt (z, -z, -r) unless an end holds them) they
are zero-energy modes: they are identified (their Rayleigh quotients reported) and the
spectrum is computed on their complement in the mass norm, never suppressed by supports the
real shell does not have.

Discretisation: per piece, each U a Chebyshev series of degree ``degree``; the quadratic
form and the mass int int |dx|^2 dA_target by Gauss-Legendre quadrature; the energy from the
reference and target forms of :mod:`shellbvp.kinematics` and the fields of
:mod:`shellbvp.fields`; the base state from
the equilibrium's own interpolant and inner roots at Chebyshev points (its stretch
derivative by Chebyshev differentiation). The eigenvalues, in energy per mu* h0 R0^2 per unit
squared amplitude in that mass norm, converge spectrally with the degree.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from .errors import ConvergenceError
from .results import Equilibrium

__all__ = ["HarmonicSpectrum", "Modes", "modes", "DEGREE", "N_MAX"]

#: default Chebyshev degree of each perturbation component per piece: eigenvalues converge to
#: ~1e-9 relative by 20-24 on the caps of the tests; beyond ~32 round-off near the pole (terms
#: ~ 1/r^4 at the innermost Gauss points) grows past the truncation error
DEGREE = 24
#: Chebyshev degree of the base state's interpolants per piece
BASE_DEGREE = 64
#: the largest harmonic accepted
N_MAX = 200


@dataclass(frozen=True)
class HarmonicSpectrum:
    """The smallest eigenvalues of the second variation in harmonic n.

    Attributes:
        n: the harmonic (number of circumferential waves).
        eigenvalues: increasing, rigid-body modes excluded (energy per mu* h0 R0^2 per unit
            squared amplitude in the mass norm int int |dx|^2 dA_target).
        s: points (meridional angle) at which the modes are given.
        u, v, w: the modes' meridional, azimuthal and normal displacement components at
            ``s`` (one row per eigenvalue, unit mass norm, sign fixed by max |w| > 0).
        rigid: the free cap's rigid-body modes of this n, as (name, Rayleigh quotient): the
            quotient is zero in the continuum, and its size is the discretisation's
            (compare with ``eigenvalues``).
        roundoff: the eigenvalues' round-off floor, eps ||A||_F for the symmetric matrix A
            whose eigenvalues they are: LAPACK's error bound eps ||A||_2 for a symmetric
            eigenproblem (LAPACK Users' Guide, section 4.7.1), with the Frobenius norm, an
            upper bound of ||A||_2, in place of it. ||A|| grows like the degree^8 (bending),
            so a finer degree's eigenvalue is the noisier: at a sphere's harmonic n = 18 at
            degree 40 the floor is ~1e-7, and the eigenvalue changes erratically by as much
            from one degree to the next (the root's error, :mod:`shellbvp.instability`).
    """

    n: int
    eigenvalues: np.ndarray
    s: np.ndarray = field(repr=False)
    u: np.ndarray = field(repr=False)
    v: np.ndarray = field(repr=False)
    w: np.ndarray = field(repr=False)
    rigid: tuple = ()
    roundoff: float = 0.0

    @property
    def lowest(self) -> float:
        return float(self.eigenvalues[0])


@dataclass(frozen=True)
class Modes:
    """The second variation of an equilibrium, per harmonic (:func:`modes`).

    Attributes:
        p: the equilibrium's parameter value; parameter: its name.
        spectra: one :class:`HarmonicSpectrum` per harmonic scanned, in the order given.
        degree: Chebyshev degree per piece and component.
    """

    p: float
    parameter: str
    spectra: tuple
    degree: int

    @property
    def harmonics(self) -> tuple:
        return tuple(sp.n for sp in self.spectra)

    def __getitem__(self, n: int) -> HarmonicSpectrum:
        for sp in self.spectra:
            if sp.n == n:
                return sp
        raise KeyError(f"harmonic n = {n} was not scanned (scanned: {self.harmonics})")

    @property
    def lowest(self) -> tuple:
        """(n, eigenvalue) of the smallest eigenvalue over the harmonics scanned."""
        sp = min(self.spectra, key=lambda sp: sp.lowest)
        return sp.n, sp.lowest

    def __repr__(self) -> str:
        n, mu = self.lowest
        return (f"Modes({self.parameter}={self.p:.6g}, n = {min(self.harmonics)}.."
                f"{max(self.harmonics)}, lowest {mu:.4g} at n = {n}, degree {self.degree})")


# --- the local density and its Hessian ------------------------------------------------------
def _triple(u, v, w):
    return _dot(u, _cross(v, w))


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    import jax.numpy as jnp

    return jnp.stack([a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                      a[0] * b[1] - a[1] * b[0]])


def _forms(q):
    """(a11, a12, a22, b11, b12, b22) of a surface from its local numbers q = (x, x_s, x_o,
    x_ss, x_so, x_oo) (JAX): a = x_i . x_j, b = x_ij . N, N the unit normal x_s x x_o."""
    import jax.numpy as jnp

    xs, xo, xss, xso, xoo = (q[3 * i:3 * i + 3] for i in range(1, 6))
    nrm = _cross(xs, xo)
    N = nrm / jnp.sqrt(_dot(nrm, nrm))
    return jnp.stack([_dot(xs, xs), _dot(xs, xo), _dot(xo, xo),
                      _dot(xss, N), _dot(xso, N), _dot(xoo, N)])


@lru_cache(maxsize=None)
def _hessian_kernel(model: str, material: str, imperfect: bool = False):
    """jit(vmap) of the Hessian of the density per ds domega in the 18 local numbers q =
    (x, x_s, x_o, x_ss, x_so, x_oo), with per-point fields F (:data:`shellbvp.kinematics.
    FIELDS`) and the scalars (material parameter, h, pressure); ``imperfect``: a per-point
    change of the target forms too (:func:`shellbvp.kinematics.target_matrices`), the
    argument after F. The reduced energy enters
    through the six entries of (a, b), so its Hessian is taken in those six (36 second-order
    directions, not 324) and chained through the geometry: H_q = J^T H_ab J + sum_k
    dW/d(ab)_k Hess_q (ab)_k, the last a Hessian of the cheap geometric map only."""
    from .jaxsetup import jax, jit
    import jax.numpy as jnp

    from . import kinematics as K
    from .forms import reduced_energy

    def energy(ab, F, change, mat, h):
        a = jnp.array([[ab[0], ab[1]], [ab[1], ab[2]]])
        b = jnp.array([[ab[3], ab[4]], [ab[4], ab[5]]])
        abar, bbar, area = K.target_matrices(F, change)
        kw = dict(nu=mat) if material == "koiter" else dict(lam=mat)
        rb = K.RHOB.start
        return reduced_energy(a, b, abar, bbar, h=h * F[K.THICKNESS], model=model,
                              material=material, rhob=(F[rb], F[rb + 1], F[rb + 2]),
                              **kw) * area

    def load(q):
        return _triple(q[0:3], q[3:6], q[6:9]) / 3.0

    def hessian(q, F, change, mat, h, P):
        ab = _forms(q)
        gW = jax.grad(energy)(ab, F, change, mat, h)
        HW = jax.jacfwd(jax.grad(energy))(ab, F, change, mat, h)
        J = jax.jacfwd(_forms)(q)
        Hg = jax.hessian(lambda x: jnp.dot(gW, _forms(x)))(q)
        grad = J.T @ gW + P * jax.grad(load)(q)
        return grad, J.T @ HW @ J + Hg + P * jax.hessian(load)(q)

    if imperfect:
        return jit(jax.vmap(hessian, in_axes=(0, 0, 0, None, None, None)))
    return jit(jax.vmap(lambda q, F, mat, h, P: hessian(q, F, None, mat, h, P),
                        in_axes=(0, 0, None, None, None)))


def _local_map(n: int) -> np.ndarray:
    """L_n (18, 9): the local components of (dx, dx_s, dx_o, dx_ss, dx_so, dx_oo) from
    d = (U, U', U'') (each (U_r, U_w, U_z)), the cos/sin factors dropped (module docstring)."""
    L = np.zeros((18, 9))
    for k, off in ((0, 0), (3, 3), (9, 6)):          # dx, dx_s, dx_ss: U, U', U''
        L[k:k + 3, off:off + 3] = np.eye(3)
    for k, off in ((6, 0), (12, 3)):                 # dx_o (from U), dx_so (from U')
        L[k, off], L[k, off + 1] = -n, -1.0
        L[k + 1, off], L[k + 1, off + 1] = 1.0, n
        L[k + 2, off + 2] = -n
    L[15, 0], L[15, 1] = -(n * n + 1.0), -2.0 * n
    L[16, 0], L[16, 1] = -2.0 * n, -(n * n + 1.0)
    L[17, 2] = -float(n * n)
    return L


# --- the base state -------------------------------------------------------------------------
@dataclass(frozen=True)
class _Base:
    """The equilibrium and its discretisation: quadrature points, basis values, Hessians."""

    pieces: tuple                 # (a, b) per piece, from 0 to the meridian's length
    s: np.ndarray                 # (P, m) Gauss points
    wq: np.ndarray                # (P, m) weights (ds)
    area: np.ndarray              # (P, m) the target area per ds domega, g1 g2 r0
    theta: np.ndarray             # (P, m)
    r: np.ndarray
    z: np.ndarray
    stretch: np.ndarray           # (P, m) |x_s| = g1 lam1
    H: np.ndarray                 # (P, m, 18, 18)
    ends: dict                    # theta, |x_s|, r, z at piece ends: {(i, side): tuple}
    degree: int
    E: tuple                      # (E0, E1, E2) per piece: (m, degree + 1) basis derivatives
    kinds: tuple                  # the kinds of the two ends (shellbvp.scene.End)
    G: np.ndarray                 # (P, m, 18): the density's gradient (first variation)
    pressure: float               # the follower pressure P at this equilibrium
    displaced: tuple              # per end: a pole whose axial displacement is prescribed


@lru_cache(maxsize=32)
def _cheb_basis_x(N: int, m: int):
    """T_0..T_N and their first two x-derivatives at the m Gauss-Legendre points."""
    C = np.polynomial.chebyshev
    x = np.polynomial.legendre.leggauss(m)[0]
    I = np.eye(N + 1)
    E0 = C.chebvander(x, N)
    E1 = np.stack([C.chebval(x, C.chebder(I[k])) for k in range(N + 1)], axis=-1)
    E2 = np.stack([C.chebval(x, C.chebder(I[k], 2)) for k in range(N + 1)], axis=-1)
    for E in (E0, E1, E2):
        E.setflags(write=False)
    return E0, E1, E2


def _cheb_basis(m, N, scale):
    """Values of T_0..T_N and of their first two derivatives in s at the m Gauss points."""
    E0, E1, E2 = _cheb_basis_x(N, m)
    return E0, E1 * scale, E2 * scale**2


def _base(eq: Equilibrium, degree: int) -> _Base:
    from .bvp import ShellBVP
    from .fields import point_fields
    from .methods.chebyshev import chebyshev_points
    from . import kinematics as K

    sc = eq.scene
    bvp = ShellBVP(sc)
    P = bvp.P
    ends_s = sc.piece_ends
    bounds = [(float(ends_s[i]), float(ends_s[i + 1])) for i in range(P)]
    c = np.asarray(sc.field_parameters, dtype=float)
    Nb = BASE_DEGREE
    tb = chebyshev_points(Nb)
    sb = np.stack([bvp.s_of(i, tb) for i in range(P)])          # from eps on the first piece
    Y = np.stack([eq.unknowns(sb[i]) for i in range(P)])         # (P, 6, Nb + 1)
    # the inner roots' starts from the equilibrium's own nodes on the same piece: lam1 and k1
    # jump at an interface of the stimulus, and a start from the other side can converge to
    # another root of the constitutive inversion
    hint = []
    for i in range(P):
        on = (eq.s > bvp.a[i] if i else eq.s > -np.inf) & (eq.s <= bvp.b[i])
        hint.append(np.stack([np.interp(sb[i], eq.s[on], eq.lam1[on]),
                              np.interp(sb[i], eq.s[on], eq.k1[on])], axis=-1))
    hint = np.stack(hint)
    X, F = bvp.state(sb, Y, eq.p, hint)                         # (P, 4, Nb + 1)
    m = max(2 * degree, Nb) + 8
    xg, wg = np.polynomial.legendre.leggauss(m)
    C = np.polynomial.chebyshev
    S, WQ, AREA, TH, R, Zs, LAM, Es, ends = [], [], [], [], [], [], [], [], {}
    data, Q = [], []
    for i, (a, b) in enumerate(bounds):
        # interpolants on the base nodes' own interval, evaluated on [a, b] (at a pole the
        # piece's [0, eps] is an extrapolation over ~1e-4 of the piece)
        lo, hi = float(sb[i, 0]), float(sb[i, -1])
        xb = 2 * (sb[i] - lo) / (hi - lo) - 1
        g1 = F[i, 0]
        fit = {k: C.chebfit(xb, v, Nb) for k, v in
               (("lam", g1 * X[i, 0]), ("k1", X[i, 2]), ("theta", Y[i, 2]), ("r", Y[i, 0]),
                ("z", Y[i, 1]))}
        s = (a + b) / 2 + (b - a) / 2 * xg
        xs = 2 * (s - lo) / (hi - lo) - 1
        ev = {k: C.chebval(xs, c_) for k, c_ in fit.items()}
        dlam = C.chebval(xs, C.chebder(fit["lam"])) * 2 / (hi - lo)
        fv = point_fields(sc, i, s, eq.p, c, np)                  # (fields, m)
        lam, th, r, z = ev["lam"], ev["theta"], ev["r"], ev["z"]
        dth = -lam * ev["k1"]                   # theta' = -g1 lam1 k1 = -|x_s| k1
        t = np.stack([np.cos(th), np.zeros_like(th), -np.sin(th)])
        N = np.stack([np.sin(th), np.zeros_like(th), np.cos(th)])
        q = np.concatenate([
            np.stack([r, 0 * r, z]), lam * t, np.stack([0 * r, r, 0 * r]),
            dlam * t - lam * dth * N, np.stack([0 * r, lam * np.cos(th), 0 * r]),
            np.stack([-r, 0 * r, 0 * r])]).T                     # (m, 18)
        Q.append(q)
        data.append(fv.T)
        S.append(s)
        WQ.append((b - a) / 2 * wg)
        AREA.append(fv[K.G1] * fv[K.G2] * fv[K.R0])
        TH.append(th), R.append(r), Zs.append(z), LAM.append(lam)
        Es.append(_cheb_basis(m, degree, 2.0 / (b - a)))
        for side, x_end in (("a", -1.0), ("b", 1.0)):
            xe = 2 * ((a if side == "a" else b) - lo) / (hi - lo) - 1
            ends[(i, side)] = tuple(float(C.chebval(xe, fit[k])) for k in
                                    ("theta", "lam", "r", "z"))
    kernel = _hessian_kernel(sc.model, sc.material)
    pressure = 0.0 if sc.pressure is None else float(sc.pressure(eq.p))
    qa, da = np.concatenate(Q), np.concatenate(data)
    G, H = (np.asarray(x) for x in kernel(qa, da, float(sc.material_parameter), float(sc.h),
                                           pressure))
    if not (np.all(np.isfinite(H)) and np.all(np.isfinite(G))):
        raise ConvergenceError("the second variation is not finite at this equilibrium "
                               "(a quadrature point without a valid state)")
    return _Base(tuple(bounds), np.stack(S), np.stack(WQ), np.stack(AREA), np.stack(TH),
                 np.stack(R), np.stack(Zs), np.stack(LAM), H.reshape(P, m, 18, 18), ends,
                 degree, tuple(Es), tuple(e.kind for e in sc.ends), G.reshape(P, m, 18),
                 pressure, tuple(e.displacement is not None for e in sc.ends))


# --- assembly -------------------------------------------------------------------------------
def _derivative_operators(base: _Base):
    """D (9, P m, ndof): (U, U', U'') at every quadrature point from the Chebyshev
    coefficients, unknowns ordered piece, component (r, w, z), coefficient."""
    P, m = base.s.shape
    nb = base.degree + 1
    ndof = 3 * nb * P
    D = np.zeros((9, P * m, ndof))
    for i in range(P):
        E = base.E[i]
        for order in range(3):
            for c in range(3):
                col = (i * 3 + c) * nb
                D[3 * order + c, i * m:(i + 1) * m, col:col + nb] = E[order]
    return D


@lru_cache(maxsize=None)
def _end_values(nb: int) -> np.ndarray:
    """(2, 3, nb): T_k and its first two derivatives at x = -1 and x = 1 (in x)."""
    k = np.arange(nb, dtype=float)
    out = np.empty((2, 3, nb))
    for side, x in enumerate((-1.0, 1.0)):
        sgn = x ** np.arange(nb)
        out[side] = [sgn, x * sgn * k**2, sgn * (k**4 - k**2) / 3]
    return out


def _end_rows(base: _Base, i: int, side: str, order: int, comp: int) -> np.ndarray:
    """The row giving derivative ``order`` of component ``comp`` of piece i at its end."""
    P = base.s.shape[0]
    nb = base.degree + 1
    a, b = base.pieces[i]
    row = np.zeros(3 * nb * P)
    row[(i * 3 + comp) * nb:(i * 3 + comp + 1) * nb] = \
        _end_values(nb)[0 if side == "a" else 1, order] * (2.0 / (b - a)) ** order
    return row


def _pole_class(n: int) -> int:
    return min(n, 2)


#: the displacement components (U_r, U_w, U_z) each kind of end holds, and whether it holds
#: the rotation of the tangent out of the surface
HOLDS = {"clamped": ((0, 1, 2), True), "hinged": ((0, 1, 2), False), "roller": ((2,), False),
         "sliding": ((2,), True), "diaphragm": ((0, 1), False),
         "symmetry": ((2,), True), "free": ((), False)}
#: the ends whose rim a pressure's lid closes (:func:`_lid_stiffness`): those that move in
#: their own plane, and the diaphragm, whose rim keeps its radius while it warps axially
LID_ENDS = ("roller", "symmetry", "sliding", "diaphragm")


def _constraints(base: _Base, n: int) -> np.ndarray:
    P = base.s.shape[0]
    rows = []
    R = lambda i, side, order, comp: _end_rows(base, i, side, order, comp)  # noqa: E731

    def rot(j, side, th, lam):
        return (np.sin(th) * R(j, side, 1, 0) + np.cos(th) * R(j, side, 1, 2)) / lam

    for end, (i, side) in enumerate(((0, "a"), (P - 1, "b"))):
        kind = base.kinds[end]
        if kind == "pole":
            if n == 0:
                rows += [R(i, side, 0, 0), R(i, side, 0, 1), R(i, side, 1, 2)]
                if base.displaced[end]:          # the indenter holds the pole's z
                    rows.append(R(i, side, 0, 2))
            elif n == 1:
                rows += [R(i, side, 0, 2), R(i, side, 0, 0) + R(i, side, 0, 1)]
            else:
                rows += [R(i, side, 0, c) for c in range(3)] + [R(i, side, 1, 2)]
            continue
        comps, rotation = HOLDS[kind]
        rows += [R(i, side, 0, c) for c in comps]
        if rotation:
            th, lam = base.ends[(i, side)][:2]
            rows.append(rot(i, side, th, lam))
    for i in range(P - 1):
        rows += [R(i, "b", 0, c) - R(i + 1, "a", 0, c) for c in range(3)]
        th_l, lam_l = base.ends[(i, "b")][:2]
        th_r, lam_r = base.ends[(i + 1, "a")][:2]
        rows.append(rot(i, "b", th_l, lam_l) - rot(i + 1, "a", th_r, lam_r))
    return np.array(rows).reshape(len(rows), -1) if rows else np.zeros((0, 0))


def _interface_row(base: _Base, n: int, i: int) -> int:
    """The index of interface i's rotation row in :func:`_constraints` (the ends' rows come
    first, then 3 + 1 rows per interface)."""
    count = 0
    for kind, displaced in zip(base.kinds, base.displaced):
        if kind == "pole":
            count += (3, 2, 4)[_pole_class(n)] + int(displaced and n == 0)
        else:
            comps, rotation = HOLDS[kind]
            count += len(comps) + int(rotation)
    return count + 4 * i + 3


def _rigid(base: _Base, n: int) -> list:
    """(name, (3, P m) values of (U_r, U_w, U_z) at the quadrature points) of the rigid
    motions the ends leave (module docstring)."""
    if n > 1:
        return []
    held = set()
    for kind, displaced in zip(base.kinds, base.displaced):
        if kind != "pole":
            held |= set(HOLDS[kind][0])
        elif displaced:
            held.add(2)
    r, z = base.r.ravel(), base.z.ravel()
    one, zero = np.ones_like(r), np.zeros_like(r)
    if n == 0:
        out = [] if 2 in held else [("axial translation", np.stack([zero, zero, one]))]
        return out + ([] if 1 in held else [("rotation about the axis",
                                              np.stack([zero, r, zero]))])
    out = [] if {0, 1} & held else [("lateral translation", np.stack([one, -one, zero]))]
    return out + ([] if held else [("tilt", np.stack([z, -z, -r]))])


@dataclass(frozen=True)
class _Space:
    """The admissible perturbations of one pole class: a mass-orthonormal basis Z of the
    constrained space (rigid modes removed), and the rigid modes' coefficients."""

    Z: np.ndarray
    rigid: tuple          # (name, coefficient vector) per rigid mode


def _space(base: _Base, D, M, n: int) -> _Space:
    """``M``: the mass matrix of harmonic n (:func:`_mass`)."""
    from scipy.linalg import cholesky, qr, solve_triangular

    A = _constraints(base, n)
    if A.size:
        Q, _ = qr(A.T, mode="full")
        Z = Q[:, A.shape[0]:]                                # null space of the constraints
    else:                                                    # free ends: nothing holds it
        Z = np.eye(M.shape[0])
    rigid = []
    modes = _rigid(base, n)
    if modes:
        Mz = Z.T @ M @ Z
        B = []
        for name, vals in modes:
            rhs = sum(D[c].T @ (_mass_weights(base, n) * vals[c]) for c in range(3))
            y = np.linalg.solve(Mz, Z.T @ rhs)              # best approximation, mass norm
            rigid.append((name, Z @ y))
            B.append(y)
        Qb, _ = qr(Mz @ np.array(B).T, mode="full")
        Z = Z @ Qb[:, len(B):]                              # the mass-complement
    Lc = cholesky(Z.T @ M @ Z, lower=True)
    Z = solve_triangular(Lc, Z.T, lower=True).T             # mass-orthonormal
    return _Space(Z, tuple(rigid))


def _local_components(L: np.ndarray, D) -> np.ndarray:
    """(points, 18, ndof): the local components L (U, U', U'') at every quadrature point."""
    return (L @ D.reshape(9, -1)).reshape(18, D.shape[1], D.shape[2]).transpose(1, 0, 2)


def _stiffness_parts(base: _Base, D) -> dict:
    """P_ij = (L_i D)^T H (L_j D) (quadrature weights included) for L_n = L_0 + n L_1 +
    n^2 L_2: the stiffness of every harmonic is then sum n^(i + j) P_ij, assembled once per
    equilibrium rather than once per n."""
    P, m = base.s.shape
    ndof = D.shape[-1]
    Lm, L0, Lp = _local_map(-1), _local_map(0), _local_map(1)
    Ls = (L0, (Lp - Lm) / 2, (Lp + Lm) / 2 - L0)
    B = [_local_components(L, D) for L in Ls]
    Hw = base.H.reshape(P * m, 18, 18) * base.wq.reshape(-1)[:, None, None]
    out = {}
    for j in range(3):
        T = (Hw @ B[j]).reshape(-1, ndof)
        for i in range(j + 1):
            out[(i, j)] = B[i].reshape(-1, ndof).T @ T
    return out


def _joint_angle(xl, xr, xo):
    """The signed angle between the tangents x_s^l, x_s^r on either side of a joint about
    the hoop direction x_o, atan2(x_s^r . (x_s^l x x_o) / |x_o|, x_s^l . x_s^r) (components
    on the first axis; JAX): a rigid joint keeps it at its reference value."""
    import jax.numpy as jnp

    return jnp.arctan2(_triple(xr, xl, xo) / jnp.sqrt(_dot(xo, xo)), _dot(xl, xr))


def _joint_base(base: _Base, i: int):
    """(x, x_s on the left, x_s on the right) of the base state at the joint between pieces
    i and i + 1, in the frame (e_r, e_omega, e_z)."""
    th_l, lam_l, r, z = base.ends[(i, "b")]
    th_r, lam_r = base.ends[(i + 1, "a")][:2]
    return (np.array([r, 0.0, z]), lam_l * np.array([np.cos(th_l), 0.0, -np.sin(th_l)]),
            lam_r * np.array([np.cos(th_r), 0.0, -np.sin(th_r)]))


@lru_cache(maxsize=None)
def _kink_hessian():
    """Hessian of the interface condition c (:func:`_joint_angle`) in (x_s^l, x_s^r, x_o):
    the joint is rigid (c keeps its reference value, zero where the tangent does not turn);
    its linear part is the rotation condition of :func:`_constraints`."""
    from .jaxsetup import jax, jit

    return jit(jax.hessian(lambda v: _joint_angle(v[0:3], v[3:6], v[6:9])))


def _interface_terms(base: _Base, D) -> list:
    """Per interface (piece i | i + 1): (mu', H_c) with mu' the multiplier of its rotation
    condition per unit angle, from the first variation of the n = 0 family (least squares on
    all the conditions), and H_c the Hessian of the condition. Where the stretch jumps or the
    tangent turns the condition is not linear in the displacement: the second variation on
    the admissible set (the Hessian of the Lagrangian) then has the term -mu' int c_2 domega,
    which the quadratic form of the density alone misses (without it the eigenvalues fall
    without bound as the degree grows)."""
    P, m = base.s.shape
    if P == 1:
        return []
    B = _local_components(_local_map(0), D)
    g = 2 * math.pi * np.einsum("qc,qcj->j", base.G.reshape(P * m, 18) *
                                base.wq.reshape(-1)[:, None], B)
    A = _constraints(base, 0)
    mu = np.linalg.lstsq(A.T, g, rcond=None)[0]
    out = []
    for i in range(P - 1):
        x, tl, tr = _joint_base(base, i)
        v = np.concatenate([tl, tr, [0.0, x[0], 0.0]])          # x_o = (0, r, 0)
        Hc = np.asarray(_kink_hessian()(v))
        out.append((i, mu[_interface_row(base, 0, i)] / (2 * math.pi), Hc))
    return out


def _interface_stiffness(base: _Base, terms, n: int) -> np.ndarray:
    L = _local_map(n)
    K = 0.0
    for i, mu, Hc in terms:
        V = np.array([_end_rows(base, i, "b", 1, c) for c in range(3)]
                     + [_end_rows(base, i + 1, "a", 1, c) for c in range(3)]
                     + list(L[6:9, 0:3] @ np.array([_end_rows(base, i, "b", 0, c)
                                                     for c in range(3)])))
        # + mu: the rotation row of _constraints is rho_l - rho_r, the negative of c's linear
        # part, so its multiplier is -mu' of the Lagrangian E - mu' c
        K = K + mu * V.T @ Hc @ V
    return K * (2 * math.pi if n == 0 else math.pi)


def _stiffness_direct(base: _Base, D, n: int) -> np.ndarray:
    P, m = base.s.shape
    ndof = D.shape[-1]
    B = _local_components(_local_map(n), D)
    Hw = base.H.reshape(P * m, 18, 18) * base.wq.reshape(-1)[:, None, None]
    K = B.reshape(-1, ndof).T @ (Hw @ B).reshape(-1, ndof)
    return (K + K.T) / 2 * (2 * math.pi if n == 0 else math.pi)


def _stiffness(parts: dict, n: int) -> np.ndarray:
    K = sum(float(n) ** (i + j) * (P if i == j else P + P.T) for (i, j), P in parts.items())
    return (K + K.T) / 2 * (2 * math.pi if n == 0 else math.pi)


def _lid_stiffness(base: _Base, n: int) -> np.ndarray | float:
    """The pressure's stiffness from the lids that close an open shell at its moving ends.

    The density's load term (1/3) x . (x_s x x_o) integrates to the volume of the cone from
    the origin to the surface; the closed volume adds, at each end of :data:`LID_ENDS`, the
    lid ruled by the segments from the axis to the rim at its height Z(omega),
    (1/3) sigma_e (1/2) int Z (x x x_o) . e_z domega, sigma = +1 at the first end, -1 at the
    second (a clamped or hinged end does not move). Where the end keeps its plane (roller,
    sliding, symmetry: Z = z_e) it is the flat lid (1/3) sigma_e z_e A_e, A_e the area the
    rim encloses; with the rim at r_e + U_r cos(n omega), U_w sin(n omega),
    A_e = pi r_e^2 + (pi / 2)(U_r^2 + U_w^2 + 2 n U_r U_w) exactly (n >= 1; at n = 0 the
    twist U_w adds pi U_w^2), so the term's Hessian is P sigma_e z_e / 3 [[1, n], [n, 1]] in
    (U_r, U_w), times the omega weight. Every rigid motion then leaves the closed volume,
    so it costs no energy, and the variation of the closed volume is the follower load on
    the shell alone (the lid moves in its own plane). At a diaphragm U_r = U_w = 0 on the
    rim, so the lid is (1/3) sigma_e pi r_e^2 (z_e + U_z^0), linear in the rim's axial
    displacement: the lid's pressure is a dead axial force there (in the axisymmetric solve
    too), with no stiffness (the rows below vanish on the admissible set)."""
    if base.pressure == 0.0:
        return 0.0
    P = base.s.shape[0]
    K = 0.0
    for sigma, (i, side), kind in zip((1.0, -1.0), ((0, "a"), (P - 1, "b")), base.kinds):
        if kind not in LID_ENDS:
            continue
        z = base.ends[(i, side)][3]
        rows = np.array([_end_rows(base, i, side, 0, c) for c in (0, 1)])
        K = K + rows.T @ (sigma * z / 3.0 * np.array([[1.0, n], [n, 1.0]])) @ rows
    return base.pressure * K * (2 * math.pi if n == 0 else math.pi)


def _spectrum(base: _Base, D, parts, space: _Space, n: int, count: int,
              M=None, terms=()) -> HarmonicSpectrum:
    from scipy.linalg import eigh

    K = _stiffness(parts, n) if parts is not None else _stiffness_direct(base, D, n)
    if terms:
        K = K + _interface_stiffness(base, terms, n)
    K = K + _lid_stiffness(base, n)
    rigid = tuple((name, float(y @ K @ y / (y @ M @ y))) for name, y in space.rigid)
    Z = space.Z
    count = min(count, Z.shape[1])
    A = Z.T @ K @ Z
    vals, vecs = eigh(A, subset_by_index=[0, count - 1], driver="evr")
    coef = Z @ vecs                                          # (ndof, count)
    Ur, Uw, Uz = (D[c] @ coef for c in range(3))             # (P m, count)
    th = base.theta.reshape(-1)[:, None]
    u = Ur * np.cos(th) - Uz * np.sin(th)
    w = Ur * np.sin(th) + Uz * np.cos(th)
    sign = np.sign(w[np.argmax(np.abs(w), axis=0), np.arange(count)])
    sign[sign == 0] = 1.0
    return HarmonicSpectrum(int(n), vals, base.s.reshape(-1), (u * sign).T, (Uw * sign).T,
                            (w * sign).T, rigid, float(np.finfo(float).eps * np.linalg.norm(A)))


def _mass_weights(base: _Base, n: int) -> np.ndarray:
    return (base.wq * base.area).reshape(-1) * (2 * math.pi if n == 0 else math.pi)


def _mass(base: _Base, D, n: int = 1) -> np.ndarray:
    """int int |dx|^2 dA_target as a matrix on the coefficients (weight of harmonic n)."""
    w = _mass_weights(base, n)
    return sum(D[c].T @ (w[:, None] * D[c]) for c in range(3))


def _check_harmonics(n) -> tuple:
    try:
        ns = (n,) if isinstance(n, (int, np.integer, float)) else tuple(n)
    except TypeError:
        raise ValueError(f"n must be a harmonic or an iterable of harmonics, got {n!r}") \
            from None
    if not ns:
        raise ValueError("n must name at least one harmonic")
    for k in ns:
        if not isinstance(k, (int, np.integer)) or isinstance(k, bool) or not 0 <= k <= N_MAX:
            raise ValueError(f"n must be integers in [0, {N_MAX}] (circumferential wave "
                             f"numbers), got {k!r}")
    return tuple(int(k) for k in ns)


def modes(eq: Equilibrium, n=range(0, 21), *, count: int = 3, degree: int | None = None) -> Modes:
    """The second variation of the full 2D energy at the axisymmetric equilibrium ``eq``, per
    circumferential harmonic n (module docstring): for each n the ``count`` smallest
    eigenvalues and their modes, rigid-body modes of a free cap excluded.

    Arguments:
        eq: a converged :class:`shellbvp.Equilibrium` (any method).
        n: a harmonic or an iterable of harmonics (integers in [0, N_MAX]).
        count: eigenvalues per harmonic.
        degree: Chebyshev degree of each component per piece (default ``DEGREE``).

    Raises:
        ValueError: an unconverged equilibrium, or n, count, degree out of range.
        ConvergenceError: the state cannot be evaluated along the meridian.
    """
    if not isinstance(eq, Equilibrium) or not eq.success:
        raise ValueError("eq must be a converged Equilibrium (this one did not converge: "
                         f"{getattr(eq, 'message', type(eq).__name__)})")
    ns = _check_harmonics(n)
    if not (isinstance(count, (int, np.integer)) and count >= 1):
        raise ValueError(f"count must be a positive integer, got {count!r}")
    degree = DEGREE if degree is None else degree
    if not (isinstance(degree, (int, np.integer)) and 8 <= degree <= 160):
        raise ValueError(f"degree must be an integer in [8, 160], got {degree!r}")
    sc = eq.scene
    free = [name for name, end in zip(("first", "second"), sc.ends) if end.kind == "free"]
    if sc.pressure is not None and free:
        raise ValueError(f"a follower pressure on a shell whose {free[0]} end is free has no "
                         "potential beyond axisymmetry (no lid closes a rim that leaves its "
                         "plane), so its second variation is not an energy's; modes need "
                         "every end a pole, in a fixed plane or of a fixed radius (clamped, "
                         "hinged, roller, sliding, diaphragm, symmetry)")
    from threadpoolctl import threadpool_limits

    base = _base(eq, int(degree))
    # small dense matrices (~100-400): one BLAS thread, where several threads contend with
    # JAX's own pool (10 ms an eigenproblem instead of 1 ms, measured on 2 cores)
    with threadpool_limits(1, user_api="blas"):
        return _modes(eq, base, ns, count, int(degree))


def _modes(eq, base, ns, count, degree) -> Modes:
    D = _derivative_operators(base)
    # a few harmonics: each stiffness directly; many: once in powers of n (_stiffness_parts)
    parts = _stiffness_parts(base, D) if len(ns) > 3 else None
    terms = _interface_terms(base, D)
    mass = _mass(base, D, 1)
    spaces = {}
    spectra = []
    for k in ns:
        cls = _pole_class(k)
        M = mass if k else 2 * mass                  # the omega integral: 2 pi at n = 0
        if cls not in spaces or cls < 2:
            spaces[cls] = _space(base, D, M, k)
        spectra.append(_spectrum(base, D, parts, spaces[cls], k, count, M, terms))
    return Modes(float(eq.p), eq.scene.parameter, tuple(spectra), degree)
