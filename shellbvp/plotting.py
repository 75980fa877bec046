"""Pictures of results: an equilibrium's meridian and strains, a branch's diagram.

Both draw on matplotlib axes (new ones where none are given) and return them, so that a
notebook user can restyle, annotate or save them. matplotlib is imported here only, when a
picture is asked for: ``import shellbvp`` stays free of it.

Units as in :mod:`shellbvp.results`: lengths in R0, the parameter in its scene's unit
(``kappa R0`` for a cap under a curvature stimulus, ``kbar`` for budding).
"""

from __future__ import annotations

import numpy as np

__all__ = ["plot_equilibrium", "plot_branch", "stimulated"]

#: a stimulus field differs from the reference's (g = 1, kb = the reference's principal
#: curvatures) by more than this where it acts
STIMULUS_TOL = 1e-12


def stimulated(eq) -> np.ndarray:
    """Per node of ``eq``, whether the stimulus acts there: a target metric g != 1 or a
    target curvature kb different from the reference's, at the equilibrium's parameter."""
    from .fields import reference_point

    sc = eq.scene
    edges = sc.piece_ends
    piece = np.clip(np.searchsorted(edges, eq.s, side="right") - 1, 0, sc.pieces - 1)
    out = np.zeros(eq.s.shape, dtype=bool)
    for i in range(sc.pieces):
        on = piece == i
        if on.any():
            g1, g2, kb1, kb2 = (np.broadcast_to(np.asarray(v, float), eq.s[on].shape)
                                for v in sc.field_values(i, eq.s[on], eq.p))
            x = reference_point(sc, i, eq.s[on])
            out[on] = (np.abs(g1 - 1) + np.abs(g2 - 1) + np.abs(kb1 - x.k1)
                       + np.abs(kb2 - x.k2) > STIMULUS_TOL)
    return out


def _pyplot():
    import matplotlib.pyplot as plt

    return plt


def plot_equilibrium(eq, ax=None, *, strains: bool = True, mirror: bool = True,
                     origin: str = "apex", label: str | None = None, color=None):
    """The meridian (r, z) of ``eq``, the stimulated part drawn thick, and with ``strains``
    the mid-surface strains eps11, eps22 against the arclength of the reference meridian
    (s, R0) on a second axes, the stimulated part shaded.

    ``ax``: the axes of the shape, or a pair (shape, strains); new ones where None (several
    equilibria may share axes: the stimulated part is named in the legend once).
    ``mirror``: draw the meridian's reflection r -> -r too (the axisymmetric section).
    ``origin``: z as it is in the reference's frame (``"frame"``), or measured from the
    first end (``"first"``, or ``"apex"``: a cap's apex) or from the second (``"second"``,
    or ``"edge"``: natural for a clamped cap, whose edge does not move).
    ``label``, ``color``: of the meridian (default: the parameter's value; the next color).
    Returns the shape's axes, or the pair (shape, strains) with ``strains``.
    """
    origins = ("frame", "first", "second", "apex", "edge")
    if origin not in origins:
        raise ValueError(f"origin must be one of {origins}, got {origin!r}")
    if ax is None:
        plt = _pyplot()
        if strains:
            _, ax = plt.subplots(1, 2, figsize=(9, 3.6), layout="constrained")
        else:
            _, ax = plt.subplots(figsize=(4.5, 3.6), layout="constrained")
    shape_ax, strain_ax = (ax[0], ax[1]) if strains else (ax, None)
    on = stimulated(eq)
    sc = eq.scene
    label = f"{sc.parameter} = {eq.p:.6g}" if label is None else label
    z = {"frame": eq.z, "first": eq.z - eq.z[0], "apex": eq.z - eq.z[0],
         "second": eq.z - eq.z[-1], "edge": eq.z - eq.z[-1]}[origin]
    named = "stimulated" in [ln.get_label() for ln in shape_ax.lines]
    for sign in ((1.0, -1.0) if mirror else (1.0,)):
        line, = shape_ax.plot(sign * eq.r, z, "-", lw=1.2, color=color,
                              label=label if sign > 0 else None)
        color = line.get_color()          # the mirror image and the marks in the same color
        if on.any():
            shape_ax.plot(np.where(on, sign * eq.r, np.nan), np.where(on, z, np.nan),
                          "-", lw=3.5, alpha=0.45, color=color,
                          label="stimulated" if sign > 0 and not named else None)
    shape_ax.set_aspect("equal", adjustable="datalim")
    shape_ax.set_xlabel("r / R0")
    shape_ax.set_ylabel(f"z / R0 (from the {origin})")
    shape_ax.legend(fontsize=7)
    if strain_ax is None:
        return shape_ax
    strain_ax.plot(eq.s, eq.eps11, "-", color=color, label="eps11 (meridional)")
    strain_ax.plot(eq.s, eq.eps22, "--", color=color, label="eps22 (hoop)")
    if on.any():
        lo, hi = strain_ax.get_ylim()
        strain_ax.fill_between(eq.s, lo, hi, where=on, color="0.9", zorder=0,
                               label="stimulated")
        strain_ax.set_ylim(lo, hi)
    strain_ax.set_xlabel("s (reference arclength / R0)")
    strain_ax.set_ylabel("elastic strain")
    strain_ax.legend(fontsize=7)
    return shape_ax, strain_ax


def plot_branch(branch, ax=None, *, instability=None, label: str | None = None):
    """The branch's parameter against w (R0), its folds marked (circles, with their value),
    and an :class:`shellbvp.Instability` of it (``instability``: a bifurcation or fold found
    beyond axisymmetry, a star with its n) where given. Returns the axes."""
    if ax is None:
        _, ax = _pyplot().subplots(figsize=(5, 3.6), layout="constrained")
    sc = branch.scene
    line, = ax.plot(branch.w, branch.p, "-", lw=1.2, label=label)
    for f in branch.folds:
        ax.plot(f.w, f.p, "o", ms=5, color=line.get_color())
        ax.annotate(f"fold {f.p:.6g}", (f.w, f.p), fontsize=7, xytext=(-4, 6),
                    textcoords="offset points", ha="right")
    if instability is not None and instability.kind != "none":
        ax.plot(instability.w, instability.p, "*", ms=10, color="C3",
                label=f"{instability.kind}, n = {instability.n}")
    ax.set_xlabel("w / R0")
    ax.set_ylabel(sc.parameter_column)
    if label is not None or (instability is not None and instability.kind != "none"):
        ax.legend(fontsize=7)
    return ax
