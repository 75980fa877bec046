"""The full 2D energy in (s, omega) on a symmetry class of harmonics (shellbvp.fourier2d)
against what it must be.

References, each from another route than the module's: the axisymmetric equilibrium solved
by the spectral Euler-Lagrange method (its stationarity, and its reported energy, from the
principal-form energy of shellbvp.reduction by the BVP's own quadrature); the per-harmonic
second variation of shellbvp.harmonics (its own assembly, L_n maps, constraint handling);
the principal-form energy density (shellbvp.energy_density) integrated here over the
displaced meridian; a 2D energy computed here in Cartesian coordinates (the surface X(s,
omega) built from the equilibrium's interpolant and the displacement, omega derivatives by
FFT, the forms a, b from their definitions); the exact symmetries of the class; spectral
convergence in the degree.
"""

import math
from functools import lru_cache

import numpy as np
import pytest

import shellbvp
from shellbvp import harmonics as H
from shellbvp.fourier2d import Fourier2D
from shellbvp.problems import cap_eversion as ce

THETA, H0, N = math.pi / 6, 0.01, 3
C = np.polynomial.chebyshev


@lru_cache(maxsize=None)
def cap_at(kappa):
    if kappa == 4.0:
        return ce.equilibrium(kappa, THETA, H0)
    return ce.equilibrium(kappa, THETA, H0, guess=cap_at(4.0))


@lru_cache(maxsize=None)
def f2d(kappa, K=2, degree=None):
    return Fourier2D(cap_at(kappa), N, K, degree=degree)


def smooth_state(f, amplitudes, seed=1):
    """A state with the lowest 4 modes of each harmonic's block at the base (smooth), each
    harmonic with its amplitude (mass norm)."""
    Hm = f.hessian(np.zeros(f.size))
    rng = np.random.default_rng(seed)
    y = np.zeros(f.size)
    for k, a in zip(f.ks, amplitudes):
        b = f.block(k)
        V = np.linalg.eigh(Hm[b, b])[1][:, :4]
        c = rng.standard_normal(4)
        y[b] = a * V @ (c / np.linalg.norm(c))
    return y


def meridian_fit(eq, degree=120):
    """The equilibrium's meridian r(s), z(s) as Chebyshev series on [0, Theta] (from its
    own interpolant), for the references computed here."""
    x = np.cos(np.pi * np.arange(degree + 1) / degree)
    Y = eq(THETA * (x + 1) / 2)
    return C.chebfit(x, Y[0], degree), C.chebfit(x, Y[1], degree)


def values(c, s, order=0):
    """d^order/ds^order of the Chebyshev series c on [0, Theta] at s."""
    x = 2 * s / THETA - 1
    return C.chebval(x, C.chebder(c, order) if order else c) * (2 / THETA) ** order


# --- 1. the equilibrium is stationary; the other harmonics' gradient vanishes by symmetry --
@pytest.mark.parametrize("kappa", [4.0, 4.17])
def test_the_axisymmetric_equilibrium_is_stationary(kappa):
    f = f2d(kappa)
    y0 = np.zeros(f.size)
    g, Hm = f.hessian(y0, gradient=True)
    g_ad = f.gradient(y0)
    b0 = f.block(0)
    # against the gradient after a perturbation of 1e-6 (mass norm) along the softest
    # axisymmetric mode (mu 1e-6 to first order: 5e-7 at kappa = 4, 2e-7 at 4.17; the base's
    # 4e-11 and 2e-10: the gradient's norm is dominated by the stiffest modes)
    v = np.zeros(f.size)
    v[b0] = np.linalg.eigh(Hm[b0, b0])[1][:, 0]
    g_pert = np.linalg.norm(f.gradient(1e-6 * v)[b0])
    assert np.linalg.norm(g_ad[b0]) < 3e-3 * g_pert
    # the sharper measure: the step to this discretisation's own equilibrium (one Newton
    # step, exact here) is 6e-14 in the mass norm, its largest displacement 2e-13 R0, below
    # the equilibrium's own error estimate (7e-12 at kappa = 4, 2e-11 at 4.17)
    step = np.linalg.solve(Hm[b0, b0], g_ad[b0])
    assert np.linalg.norm(step) < 1e-12
    y = np.zeros(f.size)
    y[b0] = step
    c = f.coefficients(y)[0]
    x = np.linspace(-1, 1, 201)
    nb = f.degree + 1
    largest = max(np.max(np.abs(C.chebval(x, c[j * nb:(j + 1) * nb]))) for j in (0, 2))
    assert largest < cap_at(kappa).error_estimate
    # harmonics k >= 1: int cos(k omega) domega = 0, exactly on the rule
    for k in f.ks[1:]:
        assert np.max(np.abs(g_ad[f.block(k)])) < 1e-15 * np.max(np.abs(g_ad[b0])) + 1e-16
    assert np.allclose(g, g_ad, rtol=0, atol=1e-13)      # the two routes to the gradient


# --- 2. the Hessian's blocks are the per-harmonic second variation --------------------------
@pytest.mark.parametrize("kappa", [4.0, 4.17])
def test_hessian_blocks_are_the_harmonics_second_variation(kappa):
    f = f2d(kappa)
    Hm = f.hessian(np.zeros(f.size))
    M = H.modes(cap_at(kappa), [0, 3, 6], count=6)
    scale = np.max(np.abs(Hm))
    for k in (3, 6):
        b = f.block(k)
        mine = np.linalg.eigvalsh(Hm[b, b])[:3]
        theirs = M[k].eigenvalues[:3]
        # measured 0.5-1.7e-8 relative on the lowest (0.076) at kappa = 4, 1e-9 absolute:
        # the round-off floor of either assembly, a few eps |H| (|H| ~ 1.5e6 here)
        floor = 10 * np.finfo(float).eps * np.max(np.abs(Hm[b, b]))       # 3e-9
        assert np.all(np.abs(mine - theirs) < 3e-8 * np.abs(theirs) + floor), (k, mine)
    # harmonic 0 of the class has no twist: its eigenvalues are among n = 0's (which has it)
    b = f.block(0)
    for mu in np.linalg.eigvalsh(Hm[b, b])[:3]:
        assert np.min(np.abs(M[0].eigenvalues - mu)) < 3e-8 * abs(mu)
    # the harmonics decouple at an axisymmetric state
    for i, k in enumerate(f.ks):
        for l in f.ks[i + 1:]:
            assert np.max(np.abs(Hm[f.block(k), f.block(l)])) < 1e-14 * scale


def test_assembled_hessian_and_gradient_are_the_energys():
    """The chain-rule Hessian against the jvp of jax.grad of the energy, at a lobed state."""
    f = f2d(4.0)
    y = smooth_state(f, (3e-3, 3e-3, 1e-3))
    g, Hm = f.hessian(y, gradient=True)
    g_ad = f.gradient(y)
    assert np.max(np.abs(g - g_ad)) < 1e-12 * np.max(np.abs(g_ad))
    E, g2, H2 = f.energy_gradient_hessian(y)
    assert E == f.energy(y) and np.array_equal(g2, g) and np.array_equal(H2, Hm)
    rng = np.random.default_rng(7)
    for _ in range(2):
        v = rng.standard_normal(f.size)
        hv = f.hvp(y, v)
        assert np.max(np.abs(Hm @ v - hv)) < 1e-12 * np.max(np.abs(hv))
    # the lobed state's blocks couple (the Hessian is not block-diagonal there)
    assert np.max(np.abs(Hm[f.block(0), f.block(3)])) > 1e-6 * np.max(np.abs(Hm))


# --- 3. harmonic 0 is the axisymmetric energy -----------------------------------------------
def test_energy_of_the_base_and_of_another_equilibrium_is_the_reported_one():
    f = f2d(4.0)
    eq, other = cap_at(4.0), cap_at(4.17)
    assert abs(f.energy(np.zeros(f.size)) - eq.energy) < 1e-11 * eq.energy
    # the displacement from the base to the equilibrium at kappa = 4.17, sampled from the
    # two solutions: E at that parameter is its energy (the energy is stationary there, so
    # the fit's error enters squared)
    nb = f.degree + 1
    x = np.cos(np.pi * np.arange(nb) / f.degree)
    s = THETA * (x + 1) / 2
    d = other(s) - eq(s)
    c0 = np.concatenate([C.chebfit(x, d[0], f.degree), np.zeros(nb),
                         C.chebfit(x, d[1], f.degree)])
    y = f.reduce([c0] + [np.zeros(3 * nb)] * f.K)
    assert abs(f.energy(y, p=4.17) - other.energy) < 1e-10 * other.energy


def test_energy_of_an_axisymmetric_displacement_is_the_principal_forms():
    f = f2d(4.0)
    nb = f.degree + 1
    x = np.cos(np.pi * np.arange(nb) / f.degree)
    s = THETA * (x + 1) / 2
    ur = lambda s: 0.02 * s * (1 - s)                  # noqa: E731  U_r(0) = 0 (the pole)
    uz = lambda s: 0.03 * s**2 - 0.01 * s**3           # noqa: E731  U_z'(0) = 0
    c0 = np.concatenate([C.chebfit(x, ur(s), f.degree), np.zeros(nb),
                         C.chebfit(x, uz(s), f.degree)])
    y = f.reduce([c0] + [np.zeros(3 * nb)] * f.K)
    back = f.coefficients(y)[0]
    assert np.allclose(back[:nb], c0[:nb], atol=1e-14)                   # admissible:
    assert np.allclose(back[2 * nb + 1:], c0[2 * nb + 1:], atol=1e-14)   # kept (but a
    # translation, which costs nothing)
    mine = f.energy(y)
    # here: the displaced meridian's principal stretches and curvatures, W of the principal
    # reduction, 2 pi int W dA_target on the unit sphere's cap (dA = sin s ds domega)
    fr, fz = meridian_fit(cap_at(4.0))
    xg, wg = np.polynomial.legendre.leggauss(200)
    sg = THETA * (xg + 1) / 2
    r = values(fr, sg) + ur(sg)                        # (z itself does not enter W)
    rp = values(fr, sg, 1) + 0.02 * (1 - 2 * sg)
    zp = values(fz, sg, 1) + 0.06 * sg - 0.03 * sg**2
    rpp, zpp = values(fr, sg, 2) - 0.04, values(fz, sg, 2) + 0.06 - 0.06 * sg
    speed = np.hypot(rp, zp)
    k1 = (rp * zpp - zp * rpp) / speed**3
    k2 = zp / (speed * r)
    W = shellbvp.energy_density(speed, r / np.sin(sg), k1, k2, 3.0, 3.0, h=H0, lam=1.0)
    theirs = 2 * math.pi * np.sum(THETA / 2 * wg * W * np.sin(sg))
    assert abs(mine - theirs) < 1e-10 * theirs


# --- 4. the symmetries of the class and the rule in omega -----------------------------------
def test_energy_of_a_lobed_state_is_a_cartesian_2d_quadrature():
    """The 2D energy of a non-axisymmetric state from the surface in Cartesian coordinates:
    X(s, omega) from the equilibrium's interpolant and the harmonics' series, omega
    derivatives by FFT on 120 points, s derivatives of the series, a and b from their
    definitions, W(a, b; abar, bbar) of shellbvp.forms on 100 x 120 points."""
    import jax
    import jax.numpy as jnp

    from shellbvp.forms import reduced_energy

    f = f2d(4.0)
    y = smooth_state(f, (3e-3, 3e-3, 1e-3))
    nb = f.degree + 1
    fr, fz = meridian_fit(cap_at(4.0))
    xg, wg = np.polynomial.legendre.leggauss(100)
    s = THETA * (xg + 1) / 2
    M = 120
    w = 2 * math.pi * np.arange(M) / M
    # cylindrical components (R, Wc, Zc) and their s derivatives, (order, s, omega)
    R = np.stack([values(fr, s, o) for o in range(3)])[:, :, None] + 0 * w
    Wc = np.zeros_like(R)
    Zc = np.stack([values(fz, s, o) for o in range(3)])[:, :, None] + 0 * w
    for k, c in zip(f.ks, f.coefficients(y)):
        for o in range(3):
            R[o] += np.outer(values(c[:nb], s, o), np.cos(k * w))
            Wc[o] += np.outer(values(c[nb:2 * nb], s, o), np.sin(k * w))
            Zc[o] += np.outer(values(c[2 * nb:], s, o), np.cos(k * w))
    X = np.stack([R * np.cos(w) - Wc * np.sin(w), R * np.sin(w) + Wc * np.cos(w), Zc])
    freq = np.fft.fftfreq(M, 1.0 / M)

    def d_omega(F):
        return np.real(np.fft.ifft(1j * freq * np.fft.fft(F, axis=-1), axis=-1))

    Xs, Xss, Xo = X[:, 1], X[:, 2], d_omega(X[:, 0])
    Xso, Xoo = d_omega(X[:, 1]), d_omega(d_omega(X[:, 0]))
    nrm = np.cross(Xs, Xo, axis=0)
    Nv = nrm / np.linalg.norm(nrm, axis=0)
    a = np.stack([[np.sum(Xs * Xs, 0), np.sum(Xs * Xo, 0)],
                  [np.sum(Xs * Xo, 0), np.sum(Xo * Xo, 0)]])
    b = np.stack([[np.sum(Xss * Nv, 0), np.sum(Xso * Nv, 0)],
                  [np.sum(Xso * Nv, 0), np.sum(Xoo * Nv, 0)]])
    r0 = np.sin(s)[:, None] + 0 * w
    abar = np.stack([[np.ones_like(r0), 0 * r0], [0 * r0, r0**2]])
    flat = lambda m: jnp.asarray(m.reshape(2, 2, -1).transpose(2, 0, 1))  # noqa: E731
    W = jax.vmap(lambda a_, b_, ab_: reduced_energy(a_, b_, ab_, 3.0 * ab_, h=H0, lam=1.0))(
        flat(a), flat(b), flat(abar))
    W = np.asarray(W).reshape(r0.shape)
    theirs = np.sum(THETA / 2 * wg[:, None] * W * r0) * 2 * math.pi / M
    mine = f.energy(y)
    assert abs(mine - theirs) < 1e-10 * theirs


def test_symmetries_of_the_class_and_exactness_of_the_rule():
    f = f2d(4.0)
    y = smooth_state(f, (3e-3, 3e-3, 1e-3))
    E = f.energy(y)
    # omega -> omega + pi / n maps cos(k omega) to (-1)^(k/n) cos(k omega): harmonic n flips
    flipped = y.copy()
    flipped[f.block(3)] *= -1
    assert abs(f.energy(flipped) - E) < 1e-14 * E
    assert np.allclose(f.gradient(flipped)[f.block(3)], -f.gradient(y)[f.block(3)],
                       rtol=0, atol=1e-14 * np.max(np.abs(f.gradient(y))))
    # the half-period rule is the full one (evenness and 2 pi / n periodicity)
    assert abs(f.with_points(f.points, full_period=True).energy(y) - E) < 1e-14 * E
    # doubling the points: at a small state (1e-4) round-off, at this one (3e-3) the
    # aliasing of the terms of degree > 8 in dx (measured 1e-12 to 7e-12; 1e-6 with
    # N = 10, 5e-16 from 36 to 72: spectral)
    small = 1e-4 / 3e-3 * y
    Es = f.energy(small)
    assert abs(f.with_points(2 * f.points).energy(small) - Es) < 1e-14 * Es
    assert abs(f.with_points(2 * f.points).energy(y) - E) < 1e-10 * E
    # the Hessian at the axisymmetric state is quadratic in the harmonics: exact from
    # N = 2 K + 2 points per period
    Hm = f.hessian(np.zeros(f.size))
    H6 = f.with_points(6).hessian(np.zeros(f.size))
    assert np.max(np.abs(H6 - Hm)) < 1e-14 * np.max(np.abs(Hm))


# --- 5. convergence in the degree ------------------------------------------------------------
def test_lowest_eigenvalue_of_harmonic_n_converges_with_the_degree():
    lowest = {d: Fourier2D(cap_at(4.0), N, 1, degree=d).block_eigenvalues(N, count=1)[0]
              for d in (12, 16, 20, 32)}
    err = [abs(lowest[d] - lowest[32]) / lowest[32] for d in (12, 16, 20)]
    assert err[0] > err[1] > err[2]
    assert err[2] < 1e-7


# --- Newton: the building block of branch switching -----------------------------------------
def test_newton_returns_to_the_axisymmetric_state_below_the_bifurcation():
    f = f2d(4.0)
    y0 = 1e-3 * f.mode(3) + 3e-4 * f.mode(6)
    res = f.newton(y0)
    assert res.converged and len(res.history) <= 8
    g = [h[0] for h in res.history]
    assert g[-1] < 1e-10 * g[0]
    for k in f.ks[1:]:
        assert np.max(np.abs(res.y[f.block(k)])) < 1e-12
    # harmonic 0: this discretisation's own equilibrium, within 1e-9 of the base
    assert np.linalg.norm(res.y[f.block(0)]) < 1e-9


def test_refusals():
    eq = cap_at(4.0)
    for bad in (dict(n=0), dict(n=3, K=-1), dict(n=3, points=7), dict(n=3, degree=4)):
        n = bad.pop("n")
        K = bad.pop("K", 1)
        with pytest.raises(ValueError):
            Fourier2D(eq, n, K, **bad)



# --- its pictures and files: the lobed state's surface (shellbvp.surface) -------------------
def test_the_lobed_surface_is_the_2d_field(tmp_path):
    """The surface drawn and written for a lobed state against the discretisation's own
    synthesis of it (``state``: the JAX map from y to the local numbers at the Gauss
    points, through its derivative operators): its lobes (harmonics n..K n; the part
    of harmonic 0 left out) at the nodes of the base equilibrium, from Chebyshev series
    fitted here to that synthesis per angle of the rule (exact: polynomials of the
    degree), and their normal displacement along the base's normal; the file has the
    same; with no displacement the strains are the equilibrium's."""
    import meshio

    from shellbvp.paraview import write_surface
    from shellbvp.surface import lobed_surface

    f = f2d(4.0)
    eq = f.eq
    y = smooth_state(f, (2e-3, 2e-2, 1e-2))
    lobes = y.copy()
    lobes[f.block(0)] = 0.0
    lobes[f.ny:] = 0.0
    dx = f.state(lobes)[..., :3] - f.x0[0].T[:, None, :]            # (P m, J, 3) local
    (a, b), = f.base.pieces
    x = (2 * eq.s - a - b) / (b - a)
    xg = (2 * f.base.s[0] - a - b) / (b - a)
    fitted = np.stack([[C.chebval(x, C.chebfit(xg, dx[:, j, c], f.degree))
                        for c in range(3)] for j in range(f.w.size)])   # (J, 3, nodes)
    M = f.n * f.points                      # the rule's angles are the first J of the ring
    S = lobed_surface(f, y, eq.p, omega=M)
    assert np.allclose(S.omega[:f.w.size], f.w, rtol=0, atol=1e-15)
    v = S.fields["lobe_displacement"][:, :f.w.size]                    # (nodes, J, 3)
    c, s = np.cos(f.w), np.sin(f.w)
    local = np.stack([v[..., 0] * c + v[..., 1] * s, -v[..., 0] * s + v[..., 1] * c,
                      v[..., 2]]).transpose(2, 0, 1)                  # (J, 3, nodes)
    scale = np.abs(fitted).max()
    assert scale > 1e-3 and np.abs(local - fitted).max() < 1e-11 * scale
    normal = fitted[:, 0] * np.sin(eq.theta) + fitted[:, 2] * np.cos(eq.theta)
    assert np.abs(S.fields["lobe_normal_displacement"][:, :f.w.size] - normal.T).max() \
        < 1e-11 * scale
    write_surface(S, tmp_path / "lobed.vtu")
    back = meshio.read(tmp_path / "lobed.vtu").point_data["lobe_normal_displacement"]
    assert np.allclose(back.reshape(S.s.size, M), S.fields["lobe_normal_displacement"],
                       rtol=1e-6, atol=1e-7 * scale)
    rest = lobed_surface(f, f.origin, eq.p, omega=8)
    for name in ("eps11", "eps22"):
        assert np.abs(rest.fields[name] - getattr(eq, name)[:, None]).max() < 1e-13
    assert np.abs(rest.fields["eps12"]).max() < 1e-15


def test_a_lobed_branch_draws_writes_and_animates_its_states(tmp_path):
    """A LobedBranch of three states of this discretisation (made here: the delegations
    need no continuation): a picture of one, the collection of all, an animation."""
    import xml.etree.ElementTree as ET

    import matplotlib
    import matplotlib.pyplot as plt

    from shellbvp.postbuckling import LobedBranch

    matplotlib.use("Agg")
    f = f2d(4.0)
    rng = np.random.default_rng(5)        # smooth lobes: Chebyshev coefficients ~ 1/j^3
    decay = lambda Z: 1.0 / (1 + np.arange(Z.shape[0]) % (f.degree + 1)) ** 3  # noqa: E731
    shape = f.reduce([(k > 0) * decay(Z) * rng.standard_normal(Z.shape[0])
                      for k, Z in zip(f.ks, f.Z)])
    ys = tuple(f.origin + a * shape for a in (1e-3, 1e-2, 3e-2))
    br = LobedBranch(n=f.n, K=f.K, degree=f.degree, parameter="kappa", koiter=None,
                     p_c=f.eq.p, p_c_error=0.0, p=np.full(3, f.eq.p),
                     amplitude=np.array([1e-3, 1e-2, 3e-2]), harmonics=np.zeros((3, f.K + 1)),
                     folds=(), stop="", discretisation=f, states=ys)
    ax = br.plot3d(2, magnify=3)
    assert "lobes' normal displacement" in ax.figure.axes[-1].get_ylabel()
    plt.close("all")
    with pytest.raises(ValueError, match="i must index the branch's 3 states, got 3"):
        br.plot3d(3)
    with pytest.raises(ValueError, match=r"field must be one of .*lobe_normal_displacement"):
        br.plot3d(0, "N1")                  # a lobed state has no stress resultants here
    pvd = br.to_vtk(tmp_path / "lobed", omega=24)
    files = [d.get("file") for d in ET.parse(pvd).getroot().iter("DataSet")]
    assert len(files) == 3 and all((tmp_path / "lobed" / name).is_file() for name in files)
    br.animate(tmp_path / "lobed.gif", frames=2, dpi=20, progress=False)
    assert (tmp_path / "lobed.gif").stat().st_size > 0

@pytest.mark.slow
def test_pressurised_half_sphere_with_its_lid():
    """A follower pressure on the upper half of a sphere (Koiter, R = 1, h = 0.01) with a
    mirror end at the equator, the sphere's centre off the origin (z = 0.7) so that the lid
    that closes the rim matters: E at the base is the equilibrium's energy (elastic plus
    P V, V between the surface and the plane of its edge), the base is stationary, the
    blocks' eigenvalues are the harmonics' (which carry the lid's stiffness), and the lid's
    assembled gradient is jax.grad's at a lobed state."""
    from shellbvp.geometry import Meridian, Sphere

    geo = Meridian((Sphere(1.0, centre_z=0.7, angle=(0.0, math.pi / 2)),))
    sc = shellbvp.Scene(geo, 0.01, material="koiter", nu=0.3, ends=("pole", "symmetry"),
                        pressure=lambda p: p)
    eq = shellbvp.solve(sc, 0.02)
    f = Fourier2D(eq, 2, 2)
    y0 = np.zeros(f.size)
    assert abs(f.energy(y0) - eq.energy) < 1e-12 * eq.energy
    g, Hm = f.hessian(y0, gradient=True)
    b0 = f.block(0)
    assert np.linalg.norm(np.linalg.solve(Hm[b0, b0], g[b0])) < 1e-12     # measured 1.3e-13
    M = H.modes(eq, [0, 2, 4], count=3)
    for k in (0, 2, 4):      # harmonic 0: the lowest three of n = 0 are not twists here
        b = f.block(k)
        mine = np.linalg.eigvalsh(Hm[b, b])[:3]
        assert np.allclose(mine, M[k].eigenvalues, rtol=1e-8, atol=0), (k, mine)
    y = smooth_state(f, (1e-3, 1e-3, 1e-3))
    g, _ = f.hessian(y, gradient=True)
    g_ad = f.gradient(y)
    assert np.max(np.abs(g - g_ad)) < 1e-12 * np.max(np.abs(g_ad))
