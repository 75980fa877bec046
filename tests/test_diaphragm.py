"""The ``diaphragm`` end (the shear diaphragm of the shell-buckling literature, Sobel's SS3):
r held, z free, the axial force and the moment given (default zero); per harmonic U_r = U_w
= 0, U_z and the rotation free.

References, each independent of the method under test: the other methods (spectral,
collocation, shooting, energy) on the same scene, each with its own error estimate; the
closed form of a simply supported cylinder under pressure (Timoshenko & Woinowsky-Krieger,
Theory of Plates and Shells, 2nd ed. (1959), Sec. 114); von Mises' (1914) buckling pressure
of a finite simply supported cylinder under lateral pressure (Timoshenko & Gere, Theory of
Elastic Stability, 2nd ed. (1961), Sec. 11.5); the full 2D energy's own derivatives
(jax.grad) and the harmonics' second variation for shellbvp.fourier2d.

Units (shellbvp.scene): lengths in R, a pressure in mu* h / R, a line force per unit edge
length in mu* h. The Koiter shell's Young modulus is E = 2 mu* (1 + nu), so with R = 1 the
membrane stiffness E t / (mu* h) is YOUNG = 2 (1 + nu) and a pressure p gives the hoop strain
p / YOUNG of a free ring.

Lateral pressure. A follower pressure's potential P V (V between the surface and the planes
of its ends) loads a ring that moves axially (a diaphragm or a symmetry end) with the lid's
axial force, P R / 2 per unit length (the closed vessel). The scenes below cancel it with an
axial line load of the same size on each end (``half_lid``, ``lower_lid``), so that the
wall carries no axial force: the lateral pressure of von Mises. Where r is held the lid's
area is fixed, so the lid's load is a dead load and so is its cancellation (conservative).
The axisymmetric solve holds the first end's z where no end fixes it and takes the axial
force there as a reaction (zero when the loads balance), but the harmonics hold U_z at a
mirror end instead, and the full 2D energy then needs the loads of a free body: each end's
own.
"""

import math

import numpy as np
import pytest

import shellbvp
from shellbvp import Collocation, End, Scene, Shooting
from shellbvp import geometry as g
from shellbvp import harmonics as H
from shellbvp.geometry import Cylinder, Meridian, Sphere

NU = 0.3
#: E / mu* of the Koiter shell
YOUNG = 2 * (1 + NU)


def external(p):
    """An external pressure p on a cylinder traced upward (its reference normal points to the
    axis, and a positive scene pressure inflates it). One function for every scene of this
    file, so that scenes of one structure share their compiled programs."""
    return -p


def half_lid(p):
    """The axial line load on the upper end (the mid-length mirror) that cancels the lid of an
    external pressure p (N_x = 0 in the wall): +p R / 2 along +z, R = 1."""
    return p / 2


def lower_lid(p):
    """The same on the lower end: -p R / 2 along +z."""
    return -p / 2


def half_cylinder(L_over_R, R_over_t):
    """The lower half of a cylinder (R = 1) of length L with diaphragm ends, under lateral
    external pressure: a diaphragm at z = 0, a mirror end at mid-length (the modes even
    about it, which hold the critical one of a uniform cylinder)."""
    ends = (End("diaphragm", axial=lower_lid), End("symmetry", axial=half_lid))
    return Scene(geometry=g.cylinder(1.0, L_over_R / 2), h=1.0 / R_over_t, material="koiter",
                 nu=NU, ends=ends, pressure=external, parameter="p")


# ---- the kind: what it holds, what it takes -------------------------------------------------
def test_a_diaphragm_holds_r_and_takes_an_axial_force_and_a_moment():
    end = End("diaphragm", axial=0.5, moment=lambda p: 2 * p)
    assert not end.fixes_z
    assert np.allclose(end.conjugate(1.0, 2.0), [0.0, 1.0, -4.0])   # Q = (0, q r0, -m r0)
    assert H.HOLDS["diaphragm"] == ((0, 1), False)                    # U_r, U_w; no rotation
    sc = Scene(geometry=g.cylinder(1.0, 1.0), h=0.01, material="koiter", nu=NU,
               ends=("diaphragm", "diaphragm"))
    assert sc.pinned == 0              # no end holds z: the first end's is held
    # the default monitor: the axial displacement of the second end relative to the first
    assert sc.monitor_terms == ((1.0, "z", 1), (-1.0, "z", 0))


def test_a_diaphragm_refuses_a_radial_load_naming_it():
    with pytest.raises(ValueError, match="a diaphragm end takes no radial load .*"
                                         "loads it takes: axial, moment"):
        End("diaphragm", radial=1.0)


def test_a_scene_file_refuses_a_radial_force_on_a_diaphragm_naming_the_key(tmp_path):
    text = """title = "cylinder"
[geometry]
segments = [ { type = "cylinder", radius = 1.0, z = [0.0, 1.0] } ]
thickness = 0.01
[material]
name = "koiter"
E = 1.0
nu = 0.3
[parameter]
name = "p"
from = 0.0
to = 1.0e-6
[loads]
pressure = "p"
[ends]
first = "diaphragm"
second = "diaphragm"
second_radial_force = "p"
"""
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError) as e:
        shellbvp.load_scene(path)
    message = str(e.value)
    assert message.startswith("ends.second_radial_force: a diaphragm end takes no radial "
                              "force"), message
    assert "loads it takes: second_axial_force, second_moment" in message
    path.write_text(text.replace('second_radial_force = "p"',
                                 'second_axial_force = "p"\nsecond_moment = "p"'))
    ends = shellbvp.load_scene(path).scene.ends
    assert [e.kind for e in ends] == ["diaphragm", "diaphragm"]
    assert ends[1].axial is not None and ends[1].moment is not None


# ---- (a) every method on one diaphragm-ended shell -----------------------------------------
def zone_pressure(p):
    return p


def zone_axial(p):
    return 0.3 * p


def zone_moment(p):
    return 8e-3 * p


ZONE = Scene(geometry=Meridian((Sphere(1.0, -1.0, angle=(0.4, 1.2)),)), h=0.02,
             material="koiter", nu=NU, pressure=zone_pressure, parameter="p",
             ends=(End("diaphragm"), End("diaphragm", axial=zone_axial, moment=zone_moment)))
P_ZONE = 0.004


@pytest.fixture(scope="module")
def zone_spectral():
    eq = shellbvp.solve(ZONE, P_ZONE)
    assert eq.success
    return eq


@pytest.mark.parametrize("method", ["energy"] + [pytest.param(m, marks=pytest.mark.slow)
                                                for m in ("collocation", "shooting")])
def test_methods_agree_on_a_diaphragm_ended_zone(method, zone_spectral):
    """A spherical zone (R = 1, s from 0.4 to 1.2 rad, h = 0.02) with diaphragm ends, under a
    pressure, the second end also carrying an axial line load and a moment: every BVP row of
    the kind and the loads it takes. The tangent turns by 0.03 rad and the second end moves
    by 3.4e-3 R along z: a nonlinear state.

    Each method against the default spectral one. The observable w within the sum of their
    error estimates (each the change to the next finer discretisation). The profile
    (r, z, theta) at the method's own nodes within twice that sum: an estimate by the change
    to a discretisation refined by 2 is the error times (1 - 2^-q) for an algebraic order q
    (collocation's q = 4; the energy method's elements and shooting's tolerance), which a
    factor 2 covers for every q >= 1."""
    methods = {"collocation": Collocation(tol=1e-8), "shooting": Shooting(rtol=1e-10),
               "energy": "energy"}
    ref = zone_spectral
    eq = shellbvp.solve(ZONE, P_ZONE, method=methods[method])
    assert eq.success
    assert abs(eq.w) > 3e-3                                      # a state, not the reference
    budget = eq.error_estimate + ref.error_estimate
    assert abs(eq.w - ref.w) <= budget, (eq.w - ref.w, budget)
    mine = np.array([eq.r, eq.z, eq.theta])
    assert np.max(np.abs(mine - ref(eq.s)[:3])) <= 2 * budget
    # the diaphragm holds r at both ends, and only r: z and theta move
    r0 = (math.sin(0.4), math.sin(1.2))
    assert abs(eq.r[0] - r0[0]) < 1e-12 and abs(eq.r[-1] - r0[1]) < 1e-12
    assert abs(eq.theta[-1] - ref.scene.geometry.at_end("second")[2]) > 1e-2


# ---- (b) the closed form: a simply supported cylinder under pressure -----------------------
def simply_supported_cylinder(x, L, p, t):
    """Radial displacement w(x) (outward) of a cylinder (R = 1, thickness t) of length L,
    simply supported at x = +-L/2 (w = 0, M_x = 0, N_x = 0), under an internal pressure p
    (external: p < 0), in the linear theory of the Koiter shell of this package (DESIGN
    Sec. 3: stretching (t/8) A(a - abar)(a - abar), bending (t^3/24) A(b - bbar)(b - bbar)).
    With N inward (x_xx = w'' e_r, x_oo = -(R + w) e_r) the bending measures are
    b_11 - bbar_11 = -w'' and (b_22 - bbar_22) / R^2 = w / R^2, so the energy per unit area
    is E t w^2 / (2 R^2) + (D / 2) (w''^2 - 2 nu w'' w / R^2 + w^2 / R^4) - p w, and

        D w'''' - 2 nu D w'' / R^2 + (E t / R^2 + D / R^4) w = p,

    with w = 0 and M_x = D (w'' - nu w / R^2) = 0, i.e. w'' = 0, at the ends. Its solution
    symmetric about x = 0 is w = p / K + Re[c cosh(m x)], K = E t / R^2 + D / R^4,
    m^2 = nu / R^2 + i sqrt(K / D - nu^2 / R^4), the complex c from the two end conditions.
    Donnell's equation (D w'''' + E t w / R^2 = p: Timoshenko & Woinowsky-Krieger, Theory of
    Plates and Shells, Sec. 114) drops the two D / R^2 terms, of relative order t/R in the
    end layers. In the units of this file E t -> YOUNG (per mu* h)."""
    D = YOUNG * t * t / (12 * (1 - NU**2))
    K = YOUNG + D
    m = np.sqrt(NU + 1j * math.sqrt(K / D - NU**2))
    e = np.cosh(m * L / 2)
    # Re[c e] = -p / K and Re[c m^2 e] = 0, for (Re c, Im c)
    A = np.array([[e.real, -e.imag], [(m * m * e).real, -(m * m * e).imag]])
    cr, ci = np.linalg.solve(A, [-p / K, 0.0])
    return p / K + ((cr + 1j * ci) * np.cosh(m * x)).real


@pytest.mark.parametrize("L_over_R", [5.0, pytest.param(0.3, marks=pytest.mark.slow)])
def test_simply_supported_cylinder_under_pressure_closed_form(L_over_R):
    """A cylinder, R/t = 100, with diaphragm ends under lateral external pressure p = 1e-6
    (the lid cancelled: N_x = 0). The ends hold r, so the state is the free ring,
    w = -p R^2 / (E t), only away from them: ``simply_supported_cylinder``, a beam on an
    elastic foundation with simply supported ends. L = 0.3 R (b L / 2 = 1.9,
    b = (3 (1 - nu^2))^(1/4) / sqrt(R t): the two end layers overlap, and the mid-length
    displacement is 1.1 times the ring's) and L = 5 R (b L / 2 = 32: the mid-section is
    the free ring; the scene of von Mises' test below).

    Tolerances, from what each reference leaves out. The profile against the closed form,
    1e-5 of the ring's displacement: the geometric nonlinearity, O(strain) = 4e-7 relative.
    The mid-section of L = 5 R against the ring's p R^2 / (E t), 2e-5: Koiter's hoop bending,
    D / (E t R^2) = (t/R)^2 / (12 (1 - nu^2)) = 9.2e-6 (the end layers' remainder,
    2 exp(-b L / 2), is 1e-14). The axial force: the lid's load on the deformed section,
    p (r^2 - R^2) / 2 r, is cancelled at the reference radius, so N_x ~ p w = O(strain)
    N_theta: below 1e-5 N_theta."""
    p, t = 1e-6, 0.01
    sc = half_cylinder(L_over_R, 100)
    eq = shellbvp.solve(sc, p)
    assert eq.success
    L = L_over_R
    x = eq.s - L / 2                                   # from mid-length
    expected = simply_supported_cylinder(x, L, -p, t)
    ring = p / YOUNG
    assert np.max(np.abs((eq.r - 1.0) - expected)) < 1e-5 * ring
    mid = np.argmin(np.abs(x))
    assert np.max(np.abs(eq.N1)) < 1e-5 * abs(eq.N2[mid])
    if L_over_R == 5.0:                                # the free ring at mid-length
        assert eq.r[mid] - 1.0 == pytest.approx(-ring, rel=2e-5)
    else:                                              # the layers overlap: not the ring
        assert abs((eq.r[mid] - 1.0) / -ring - 1.0) > 0.05


# ---- (c) von Mises' finite-length buckling pressure ----------------------------------------
def von_mises(L_over_R, R_over_t):
    """(n, p) of von Mises' (1914) buckling pressure of a cylinder with simply supported ends
    (w = v = 0, N_x = M_x = 0) under lateral pressure (Timoshenko & Gere, Sec. 11.5), with
    a = (n L / (pi R))^2,

        p(n) = E t / (R (n^2 - 1) (1 + a)^2) + D / R^3 (n^2 - 1 + (2 n^2 - 1 - nu) / (1 + a)),

    minimised over n; p per mu* h / R with R = 1, as the scenes take it."""
    t = 1.0 / R_over_t

    def p(n):
        a = (n * L_over_R / math.pi) ** 2
        return (YOUNG / ((n * n - 1) * (1 + a) ** 2)
                + YOUNG * t * t / (12 * (1 - NU**2)) * (n * n - 1 + (2 * n * n - 1 - NU) / (1 + a)))

    n = min(range(2, 200), key=p)
    return n, p(n)


def check_von_mises(L_over_R, R_over_t, n_expected):
    """The first instability of the half cylinder against von Mises. The bound is the
    theories' own error: von Mises' equations and Koiter's are both first-approximation
    shell theories, whose relative error is O(t/R) (Koiter 1960; the (t n / R)^2 of the
    mode's wavelength is smaller here), taken with coefficient 1, plus the prebuckling hoop
    strain p R / (E t) that von Mises' undeformed state leaves out; the prebuckling state's
    end layers (the ends hold r) touch the mode where it vanishes, an effect of relative
    order (b L)^-3 < 1e-5. Returns p_cr / p_vM - 1."""
    n, p_vm = von_mises(L_over_R, R_over_t)
    assert n == n_expected                      # the formula's own n (a check of the helper)
    sc = half_cylinder(L_over_R, R_over_t)
    b = shellbvp.follow(sc, p_stop=(-1.0, 1.3 * p_vm), energies=False)
    ins = shellbvp.first_instability(b)
    assert ins.kind == "bifurcation" and ins.n == n
    bound = 1.0 / R_over_t + p_vm / YOUNG
    diff = ins.p / p_vm - 1.0
    assert abs(diff) + ins.error_estimate / p_vm <= bound, (diff, bound)
    return diff


def test_von_mises_finite_cylinder_R_over_t_100():
    """L/R = 5, R/t = 100: von Mises' n = 4 at p = 4.7525e-4 mu* h / R (n = 3 and 5 at 1.64
    and 1.30 times it); the bound 1.018e-2 (t/R = 1e-2, the prebuckling strain 1.8e-4)."""
    check_von_mises(5.0, 100, 4)


@pytest.mark.slow
@pytest.mark.parametrize("L_over_R, R_over_t, n", [(5.0, 1000, 7), (2.0, 100, 6)])
def test_von_mises_finite_cylinder_slow(L_over_R, R_over_t, n):
    """L/R = 5 at R/t = 1000 (n = 7; bound 1e-3 + 5.8e-6) and L/R = 2 at R/t = 100 (n = 6;
    bound 1e-2 + 4.8e-4): the thinner shell's difference falls with t/R."""
    check_von_mises(L_over_R, R_over_t, n)


# ---- the full 2D energy: the lid of a rim that keeps its radius and lifts ------------------
@pytest.mark.slow
def test_fourier2d_with_a_diaphragm_under_lateral_pressure():
    """A cylinder off the origin (z from 0.7 to 2.2, R = 1, h = 0.01), a diaphragm below and
    a mirror end above, under lateral external pressure: the rim of the diaphragm moves
    axially, and the lid that closes it lifts with it ((1/3) sigma pi r_e^2 U_z^0, linear:
    without it the base is not stationary, the Newton step to it 5e-5; so is the diaphragm's
    own load, the cancellation of that lid, which the axisymmetric solve would take as the
    reaction of its held z). E at the base is the
    equilibrium's energy, the base is stationary (the step to this discretisation's own
    equilibrium below 1e-12), the blocks' eigenvalues are the harmonics', and the assembled
    gradient is jax.grad's at a lobed state."""
    from shellbvp.fourier2d import Fourier2D

    from test_fourier2d import smooth_state

    geo = Meridian((Cylinder(1.0, (0.7, 2.2)),))
    sc = Scene(geo, 0.01, material="koiter", nu=NU, pressure=external, parameter="p",
               ends=(End("diaphragm", axial=lower_lid), End("symmetry", axial=half_lid)))
    eq = shellbvp.solve(sc, 3e-4)
    f = Fourier2D(eq, 4, 2)
    y0 = np.zeros(f.size)
    assert abs(f.energy(y0) - eq.energy) < 1e-12 * abs(eq.energy)
    g0, Hm = f.hessian(y0, gradient=True)
    b0 = f.block(0)
    assert np.linalg.norm(np.linalg.solve(Hm[b0, b0], g0[b0])) < 1e-12
    M = H.modes(eq, [0, 4, 8], count=4)
    for k in (4, 8):
        mine = np.linalg.eigvalsh(Hm[f.block(k), f.block(k)])[:3]
        assert np.allclose(mine, M[k].eigenvalues[:3], rtol=1e-8, atol=0), (k, mine)
    for mu in np.linalg.eigvalsh(Hm[b0, b0])[:3]:      # n = 0 without the twist
        assert np.min(np.abs(M[0].eigenvalues - mu)) < 1e-8 * abs(mu)
    y = smooth_state(f, (1e-3, 1e-3, 1e-3))
    g, _ = f.hessian(y, gradient=True)
    assert np.max(np.abs(g - f.gradient(y))) < 1e-12 * np.max(np.abs(g))
