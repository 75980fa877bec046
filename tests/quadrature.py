"""The first variation of an axisymmetric shell's total potential by an independent
quadrature: a referee of stationarity for the tests (test_budding, test_energy_method,
test_branch_points).

The total potential of a meridian that starts on the axis (a pole with no point force) and
ends on an edge that holds z (``clamped``, ``hinged``, ``roller``, ``sliding``) is

    Pi = 2 pi int W(lam1, lam2, k1, k2; kb1, kb2, h, rhob) g1 g2 r0 ds
         - 2 pi r0(L) [f_r r(L) - m theta(L)],

the reduced energy over the target area (:mod:`shellbvp.kinematics`; a uniform thickness)
less the work of the edge's dead line loads, read from the definitions of
:class:`shellbvp.scene.End`: the radial line force f_r per unit length of the reference
edge (along +r) and the line moment m (counterclockwise from +r toward +z, which turns
theta negatively), both on the edge's reference length 2 pi r0(L).

dPi along a direction is computed from the energy itself, not from the Euler-Lagrange
equations: Simpson's rule on n panels (2 n intervals) per piece (the fields may jump at an
interface), with a complex step in the amplitude (exact to round-off), through the
first-order system's own state (r, theta and the inner roots lam1, k1, with
theta' = -g1 lam1 k1). A direction is (phi, dphi, psi): delta theta with its derivative and
delta lam1; delta r and delta z follow from the kinematic constraint
(r', z') = g1 lam1 (cos theta, -sin theta), integrated from the pole (cumulative Simpson),
so that r = 0 stays on the axis.
"""

import math

import numpy as np
from scipy.integrate import cumulative_simpson, simpson

import shellbvp
from shellbvp import kinematics as K
from shellbvp.bvp import ShellBVP

#: what each kind of second end holds, of (r, z, theta)
HOLDS = {"clamped": ("r", "z", "theta"), "hinged": ("r", "z"), "roller": ("z",),
         "sliding": ("z", "theta")}


def _load(load, p):
    return 0.0 if load is None else float(load(p))


def first_variation(eq, directions, n=3000):
    """dPi/d delta at ``eq`` (an :class:`shellbvp.Equilibrium`, or one with another ``p``)
    along ``directions``, a list of (phi, dphi, psi), functions of s (module docstring).

    Admissible directions: phi = O(s^2) at the pole (theta = 0 there; a slower phi leaves
    the truncated integral's boundary term M(eps) phi(eps)), phi(L) = 0 where the edge holds
    theta (checked). Where it holds r or z, each direction is completed by the fixed ones
    (0, 0, sin^2(q s)) and (sin^2(q s), q sin(2 q s), 0), q = pi / L, so that the edge does
    not move that way (both together where it holds both; the least-norm combination where
    it holds one).

    Returns the list of dPi, one per direction.
    """
    sc = eq.scene
    first, second = sc.ends
    if first.kind != "pole" or first.loaded or second.kind not in HOLDS:
        raise ValueError(f"a meridian from an unloaded pole to an edge of kind "
                         f"{tuple(HOLDS)} is implemented, got {first.kind} to {second.kind}")
    bvp = ShellBVP(sc)
    pieces = np.stack([np.linspace(a, b, 2 * n + 1) for a, b in zip(bvp.a, bvp.b)])
    # an interface node belongs to both pieces, each with its own fields (row i = piece i)
    Ys = np.stack([eq.unknowns(s) for s in pieces])
    for i in range(bvp.P - 1):
        Ys[i, :, -1] = Ys[i + 1, :, 0]
    X, F, _, _ = bvp.state_and_hessian(pieces, Ys, eq.p, all_fields=True)
    state = [(pieces[i], Ys[i], X[i], F[i]) for i in range(bvp.P)]
    if not np.all(F[:, K.THICKNESS] == 1.0):
        raise ValueError("a uniform thickness is implemented (energy_density takes one h)")
    holds = HOLDS[second.kind]
    r0_edge = float(F[-1][K.R0][-1])
    f_r, moment = _load(second.radial, eq.p), _load(second.moment, eq.p)

    def parts(phi, dphi, psi):
        """(d lam1, d theta, d theta', d r, d z) on every piece, r and z integrated from the
        pole across the interfaces."""
        out, r0, z0 = [], 0.0, 0.0
        for s, y, X, F in state:
            g1 = F[K.G1]
            lam1, th = X[0], y[2]
            dr = r0 + cumulative_simpson(g1 * (psi(s) * np.cos(th) - lam1 * np.sin(th) * phi(s)),
                                         x=s, initial=0.0)
            dz = z0 + cumulative_simpson(g1 * (-psi(s) * np.sin(th) - lam1 * np.cos(th) * phi(s)),
                                         x=s, initial=0.0)
            r0, z0 = dr[-1], dz[-1]
            out.append((psi(s), phi(s), dphi(s), dr, dz))
        return out

    def dPi(var):
        d = 1e-20
        total = 0.0
        for (s, y, X, F), (dl, dth, ddth, dr, _) in zip(state, var):
            g1, g2 = F[K.G1], F[K.G2]
            lam1, k1 = X[0], X[2]
            l1c = lam1 + 1j * d * dl
            thp = -g1 * lam1 * k1 + 1j * d * ddth
            rc = y[0] + 1j * d * dr
            W = shellbvp.energy_density(
                l1c, rc / (g2 * F[K.R0]), -thp / (g1 * l1c), -np.sin(y[2] + 1j * d * dth) / rc,
                F[K.KB1], F[K.KB2], h=sc.h, lam=sc.lam, nu=sc.nu, model=sc.model,
                material=sc.material, rhob1=F[K.RHOB][0], rhob2=F[K.RHOB][1],
                rhob3=F[K.RHOB][2])
            total += simpson(np.imag(W) / d * g1 * g2 * F[K.R0], x=s)
        _, dth_edge, _, dr_edge, _ = (v[-1] for v in var[-1])
        work = r0_edge * (f_r * dr_edge - moment * dth_edge)
        return 2 * math.pi * (total - work)

    T = sc.length
    q = math.pi / T
    fixers = [(lambda s: 0 * s, lambda s: 0 * s, lambda s: np.sin(q * s) ** 2),
              (lambda s: np.sin(q * s) ** 2, lambda s: q * np.sin(2 * q * s), lambda s: 0 * s)]
    fix = [parts(*f) for f in fixers]
    rows = [j for j, name in ((3, "r"), (4, "z")) if name in holds]
    out = []
    for phi, dphi, psi in directions:
        if "theta" in holds and abs(float(phi(T))) > 1e-12:
            raise ValueError(f"the {second.kind} edge holds theta: a direction needs "
                             f"phi(L) = 0, got {float(phi(T)):.3g}")
        v = parts(phi, dphi, psi)
        if rows:
            # the edge displacement of each, then the coefficients that cancel it
            A = np.array([[f[-1][j][-1] for f in fix] for j in rows])
            c = np.linalg.lstsq(A, -np.array([v[-1][j][-1] for j in rows]), rcond=None)[0]
            v = [tuple(a + c[0] * b + c[1] * e for a, b, e in zip(vp, f0, f1))
                 for vp, f0, f1 in zip(v, fix[0], fix[1])]
        out.append(dPi(v))
    return out
