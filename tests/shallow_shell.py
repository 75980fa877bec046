"""An independent model for the pressure tests: the Donnell-Mushtari-Vlasov shallow-shell
equations of a clamped spherical cap under uniform dead pressure, axisymmetric, solved with
scipy's solve_bvp alone (no shellbvp code).

Cap z0(r) = H - r^2 / (2 R) on 0 <= r <= a, a = sqrt(2 R H) (shallow geometry), deflection w
(positive toward the centre of curvature), radial displacement u; strains
eps_r = u' + (r / R) w' + w'^2 / 2, eps_t = u / r, curvature changes w'', w' / r; plane-stress
resultants N = C (eps + nu eps_other), M = D (kappa + nu kappa_other), C = E t / (1 - nu^2),
D = E t^3 / (12 (1 - nu^2)). Equilibrium: (r N_r)' = N_t, and the vertical force balance of
the disc of radius r, (r M_r)' - M_t = r N_r (r / R + w') + p r^2 / 2. Clamped edge
w = w' = u = 0; regular centre. The snap pressure is the maximum of p against the central
deflection w0 (prescribed, p unknown), valid while w0 is a coordinate of the branch
(lambda_B <= ~5.5). The shallow-shell results depend on lambda_B only, not on R/t.
"""

import math

import numpy as np
from scipy.integrate import solve_bvp
from scipy.optimize import minimize_scalar

#: centre offset of the regular series w' = M r / (D (1 + nu)), u = N r / (C (1 + nu))
EPS = 1e-4


def _problem(lambda_B, nu, R=1000.0):
    t = E = 1.0                                         # lengths in t, stresses in E
    H = lambda_B**2 / (4 * math.sqrt(3 * (1 - nu**2)))
    a = math.sqrt(2 * R * H)
    D, C = E * t**3 / (12 * (1 - nu**2)), E * t / (1 - nu**2)
    p0 = 2 * E * t**2 / (R**2 * math.sqrt(3 * (1 - nu**2)))
    scale = np.array([t, t / a, D * t / a**2, t**2 / a, D / a**2])[:, None]

    def rhs(x, Y, prm):                                  # x = r / a
        p, r = prm[0] * p0, a * x
        w, b, Mr, u, Nr = Y * scale
        db = Mr / D - nu * b / r
        Mt = D * (b / r + nu * db)
        dMr = (-Mr + Mt + r * Nr * (r / R + b) + p * r**2 / 2) / r
        er = Nr / C - nu * u / r
        Nt = C * (u / r + nu * er)
        return a * np.array([b, db, dMr, er - (r / R) * b - b**2 / 2, (Nt - Nr) / r]) / scale

    def bc(Ya, Yb, prm, w0):
        w, b, Mr, u, Nr = Ya * scale[:, 0]
        r = a * EPS
        return np.array([b - Mr * r / (D * (1 + nu)), u - Nr * r / (C * (1 + nu)), w - w0 * t,
                         Yb[0], Yb[1], Yb[3]])

    return rhs, bc


def _solve(problem, w0, guess):
    rhs, bc = problem
    x = np.linspace(EPS, 1.0, 401)
    Y, prm = (np.zeros((5, x.size)), [0.0]) if guess is None else (guess.sol(x), guess.p)
    sol = solve_bvp(rhs, lambda ya, yb, p: bc(ya, yb, p, w0), x, Y, p=prm, tol=1e-7,
                    max_nodes=200000)
    if not sol.success:
        raise RuntimeError(f"shallow-shell reference: {sol.message} at w0 = {w0}")
    return sol


def snap_pressure(lambda_B, nu=0.3):
    """(p_cr / p0, w0 / t at the maximum): march w0 in steps of 0.05 t until p falls, then
    maximise p(w0) on the last bracket (bounded Brent, w0 to 1e-7 t)."""
    problem = _problem(lambda_B, nu)
    sols, ps, w0s, prev = {}, [], np.arange(0.05, 4.0, 0.05), None
    for w0 in w0s:
        prev = sols[w0] = _solve(problem, w0, prev)
        ps.append(prev.p[0])
        if len(ps) > 2 and ps[-1] < ps[-2]:
            break
    k = int(np.argmax(ps))
    res = minimize_scalar(lambda w: -_solve(problem, w, sols[w0s[k]]).p[0],
                          bounds=(w0s[max(k - 1, 0)], w0s[k + 1]), method="bounded",
                          options=dict(xatol=1e-7))
    return -res.fun, res.x
