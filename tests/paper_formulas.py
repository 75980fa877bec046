"""The paper's printed formulas, transcribed for comparison only (never used by the library).

Taffetani & Pezzulla, "Nonlinear morphoelastic energy based theory for stimuli responsive
elastic shells". Transcribed literally, in the principal (diagonal) form with mu* = 1:
    a.abar^ = lam1^2 + lam2^2 (A),        b.abar^ = k1 lam1^2 + k2 lam2^2 (B),
    c.abar^ = k1^2 lam1^2 + k2^2 lam2^2 (C), a.bbar^ = kb1 lam1^2 + kb2 lam2^2 (Ab),
    b.bbar^ = k1 kb1 lam1^2 + k2 kb2 lam2^2 (Bb), a.cbar^ = kb1^2 lam1^2 + kb2^2 lam2^2 (Acb),
    H = (k1 + k2)/2, K = k1 k2, Hb = (kb1 + kb2)/2, Kb = kb1 kb2,
    Js = sqrt(det a / det abar) = lam1 lam2 (the paper's eq. (Js)).
Every formula takes ``Js`` explicitly so that the tests can try both readings of it.
"""

from __future__ import annotations

import numpy as np


def forms(lam1, lam2, k1, k2, kb1, kb2):
    l1, l2 = lam1**2, lam2**2
    return dict(
        A=l1 + l2, B=k1 * l1 + k2 * l2, C=k1**2 * l1 + k2**2 * l2,
        Ab=kb1 * l1 + kb2 * l2, Bb=k1 * kb1 * l1 + k2 * kb2 * l2, Acb=kb1**2 * l1 + kb2**2 * l2,
        H=(k1 + k2) / 2, K=k1 * k2, Hb=(kb1 + kb2) / 2, Kb=kb1 * kb2,
    )


# --- Ciarlet-Geymonat, Section 4.2, rhob2 = rhob3 = 0 --------------------------------------
def cg_w_s(f, Js, lam, rho1, rhob1):
    """eq. (CG_Stretching)."""
    x = (rho1 / rhob1) ** 2
    return rhob1 * (0.5 * (f["A"] + x - 3 - np.log(x * Js))
                    + lam / 4 * (x * Js - 1 - np.log(x * Js)))


def cg_rho1(Js, lam, rhob1):
    """eq. (a)."""
    return rhob1 * np.sqrt((lam + 2) / (lam * Js + 2))


def cg_g4(f, Js, lam, rho1, rho2, rhob1):
    H, K, Hb, Kb = f["H"], f["K"], f["Hb"], f["Kb"]
    l = lam
    return (
        rhob1 * (rho2**2 * (l + 2) / rho1**2
                 + 0.5 * rho1**2 * (2 * H**2 * (l + 2) + 2 * Hb**2 * Js * l - l * (Js * Kb + K) - 2 * K)
                 + rho2 * H * (l + 2))
        + rhob1**2 * 2 * Hb * (l + 2) * (rho2 - rho1**2 * H) / rho1
        + 0.5 * rhob1**3 * (2 * Hb**2 + Kb) * (l + 2)
        + 0.5 / rhob1 * (Js * l * (rho1**4 * (2 * H**2 + K) - 10 * rho1**2 * rho2 * H + 2 * rho2**2)
                         + 4 * rho2**2)
        - 2 * rho1 * Hb * (rho1**2 * H * Js * l - rho2 * Js * l + 2 * rho2)
    )


def cg_w_b_main(f, Js, lam, rho1, rho2, rhob1, w_s):
    """eq. (CG_Bending), main text."""
    return (rhob1**3 * f["Kb"] * w_s - rhob1 * rho2 * f["B"] - 2 * rhob1**2 * rho1 * f["Ab"]
            - 2 * rho1 * rhob1**2 * f["Bb"] + 0.5 * rho1**2 * rhob1 * f["C"]
            - 1.5 * rhob1**3 * f["Acb"] + cg_g4(f, Js, lam, rho1, rho2, rhob1))


def cg_w_b_appendix(f, Js, lam, rho1, rho2, rhob1, w_s):
    """eq. (CG_BendingTOT), appendix, at rhob2 = rhob3 = 0 (there g4 equals the main-text g4)."""
    g1 = rhob1**3 * f["Kb"]
    g2 = 2 * rho1 * rhob1**2 * f["Hb"] - rhob1 * rho2
    g3 = -2 * rhob1**3 * f["Hb"]
    return (g1 * w_s + g2 * f["B"] + g3 * f["Ab"] - 2 * rho1 * rhob1**2 * f["Bb"]
            + 0.5 * rho1**2 * rhob1 * f["C"] - 1.5 * rhob1**3 * f["Acb"]
            + cg_g4(f, Js, lam, rho1, rho2, rhob1))


def cg_rho2(f, Js, lam, rhob1):
    """eq. (b)."""
    H, Hb, l = f["H"], f["Hb"], lam
    return 0.5 * rhob1**2 * (H * (l + 2) * (2 * Js * l - 1) / (Js * l + 2) ** 2
                             - 2 * Hb * Js * l * np.sqrt(l + 2) / (Js * l + 2) ** 1.5
                             + f["B"] / (4 * Js * l + 8))


# --- incompressible neo-Hookean, J = 1 imposed kinematically, Section 4.1 --------------------
def nh_rhos(f, Js, rhob1, rhob2=0.0, rhob3=0.0):
    """eq. (TTT_coefficients_Incompressible)."""
    H, K, Hb, Kb = f["H"], f["K"], f["Hb"], f["Kb"]
    r1 = rhob1 / Js
    r2 = rhob1**2 / Js**2 * (Hb - H) + rhob2 / Js
    r3 = (rhob3 / Js + 2 * rhob1 * rhob2 / Js**2 * (Js * Hb - H)
          + rhob1**3 / (3 * Js**3) * (6 * H * (H - Js * Hb) - (K - Js**2 * Kb)))
    return r1, r2, r3


def nh_w_s(f, Js, rhob1):
    return rhob1 / 2 * (f["A"] - 3 + 1 / Js**2)


def nh_w_b(f, Js, rhob1, w_s):
    H, K, Hb, Kb = f["H"], f["K"], f["Hb"], f["Kb"]
    return rhob1**3 / (2 * Js**4) * (
        Js**4 * Kb * w_s + 2 * Js * (H - Hb * Js) * f["B"] - 4 * Js**4 * Hb * f["Ab"]
        + Js**2 * (-4 * Js * f["Bb"] + f["C"] + 3 * Js**2 * f["Acb"])
        + 2 * (8 * H**2 - 6 * H * Hb * Js - K + Js**2 * (-2 * Hb**2 + Kb))
    )


# --- closed sphere, Section 5.3 --------------------------------------------------------------
def sphere_plane_strain_c2(h, lam):
    """w/R0 = c2 kappa^2 with c2 = (1 - lam)/(24 (1 + lam)) h^2."""
    return (1 - lam) / (24 * (1 + lam)) * h**2


def sphere_relaxed_c1(h, lam):
    """w/R0 = c1 kappa with c1 = 3 h lam (lam + 2)/(h^2 (10 lam^2 + lam - 2) + 12 (lam + 2)^2) h."""
    return 3 * h * lam * (lam + 2) / (h**2 * (10 * lam**2 + lam - 2) + 12 * (lam + 2) ** 2) * h
