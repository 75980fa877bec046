"""Where a shell's solution varies fast, and the elements that resolve it.

A thin shell's axisymmetric state is a smooth membrane state plus bending layers of width

    l = sqrt(h t R) / (3 (1 - nu^2))^(1/4)  ~  sqrt(h t R) / LAYER_FACTOR

(R the local radius of curvature, h t the thickness) at every place that disturbs it: an
end held or loaded, a joint of the geometry (a kink), a break of the stimulus, a ring load;
around a pole that carries a point force (or a prescribed displacement: an indenter) the
shell has a point-load zone of width ~ l and, inside it, curvatures that diverge like
log s, as they do at a pole where the target is singular (a cone, g1 != g2, or an
anisotropic target curvature, kb1 != kb2). Everywhere else the solution varies on the
lengths of the geometry and the stimulus, whatever the thickness (Timoshenko &
Woinowsky-Krieger, *Theory of Plates and Shells*, ch. 15-16; Calladine, *Theory of Shell
Structures*, ch. 14).

A :class:`Mesh` cuts every piece of the scene (the stretches between its interfaces) into
elements graded geometrically into each such layer: the innermost element one layer width
long (``CORE_ELEMENTS``; a tenth of the thickness at a loaded or singular pole, below which
the thin-shell energy says nothing), each next one ``GRADING`` times longer, until they meet
in the middle of the piece or reach its far end. On an element [x, 3 x] from a layer the
pole's s log s is analytic in a Bernstein ellipse of parameter 2 + sqrt(3) whatever x (the
layer's exponential, decayed by exp(-x / l) there, likewise needs no more), so a fixed
degree per element resolves it to the same accuracy at every distance (hp-refinement,
Babuska & Guo, SIAM J. Numer. Anal. 25, 1988), while the number of elements grows only like
the logarithm of the piece's length in layer widths: the cost does not grow with R/t or
with a shell's length.

A scene whose bending layers are wide against its meridian (shallowness
T = L / sqrt(h R_c) at most ``SINGLE_T``) gets one element per piece, the single-domain
case, whose degree then grows with T (:func:`shellbvp.methods.chebyshev.default_nodes`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Mesh", "mesh_of", "single_mesh", "layer_width", "singular_poles", "loaded_poles",
           "loaded_pole_ratio", "LOADED_POLE_ORDER",
           "GRADING", "CORE_ELEMENTS", "POLE_CORE", "SINGLE_T", "LAYER_FACTOR"]

#: (3 (1 - nu^2))^(1/4) at nu ~ 0.3 (1.24 at nu = 1/2, 1.32 at nu = 0): the layer's decay
#: length is sqrt(h R) over it
LAYER_FACTOR = 1.3
#: ratio of the lengths of consecutive elements graded into a layer (a smaller one needs
#: more elements for the same accuracy, a larger one a higher degree; tests/test_thin_shells
#: shows the solution independent of it)
GRADING = 3.0
#: the innermost element at an end, joint, break or ring, in layer widths
CORE_ELEMENTS = 1.0
#: the innermost element at a pole with a point load or a singular target, in thicknesses
POLE_CORE = 0.1
#: shallowness up to which a piece is one element (the single-domain method)
SINGLE_T = 12.0
#: parameter values at which the fields are probed for a singular pole
APEX_PROBES = (0.0, 1.0, 10.0, 100.0)


@dataclass(frozen=True)
class Mesh:
    """The elements of a meridian: their ends in s (from 0 to L, every interface of the scene
    among them) and the piece of the scene each lies on.

    Attributes:
        ends: element ends (E + 1,), increasing, from 0 to the meridian's length.
        pieces: the scene's piece of each element (E,), non-decreasing.
    """

    ends: tuple
    pieces: tuple

    @property
    def elements(self) -> int:
        return len(self.pieces)

    @property
    def lengths(self) -> np.ndarray:
        return np.diff(np.asarray(self.ends, dtype=float))

    @property
    def graded(self) -> bool:
        """Whether some piece is cut into several elements."""
        return len(set(self.pieces)) < len(self.pieces)

    def interfaces(self) -> np.ndarray:
        """(E - 1,) bool: whether each element boundary is an interface of the scene (a
        joint, break or ring: the unknowns may jump there) rather than a cut inside a
        piece."""
        p = np.asarray(self.pieces)
        return p[1:] != p[:-1]


def singular_poles(scene) -> tuple:
    """Per end, whether it is a pole where the target is singular for some probed parameter
    value: a cone (g1 != g2) or an anisotropic curvature (kb1 != kb2) on the axis, where
    the curvatures of the solution diverge like log s."""
    out = []
    for end, (piece, s) in enumerate(((0, 0.0), (scene.pieces - 1, scene.length))):
        found = False
        if scene.ends[end].kind == "pole":
            for p in APEX_PROBES:
                g1, g2, kb1, kb2 = (float(np.asarray(v).ravel()[0])
                                    for v in scene.field_values(piece, np.array([s]), p))
                if all(math.isfinite(v) for v in (g1, g2, kb1, kb2)) and \
                        (g1 != g2 or kb1 != kb2):
                    found = True
                    break
        out.append(found)
    return tuple(out)


def loaded_poles(scene) -> tuple:
    """Per end, whether it is a pole carrying a point force or a prescribed displacement
    (an indenter): a point load, whose curvatures diverge like log s at the pole."""
    return tuple(e.kind == "pole" and (e.force is not None or e.displacement is not None)
                 for e in scene.ends)


#: the rate in the degree assumed at a point-loaded pole (below the 3-4 observed on the
#: hemisphere, so that the estimate errs on the safe side)
LOADED_POLE_ORDER = 2


def loaded_pole_ratio(scene, degree: int, step: int) -> float:
    """The error's factor per rung of a discretisation that raises its degree from
    ``degree`` by ``step`` on a fixed mesh: 0 (exponential convergence) unless a pole
    carries a point load, whose state ~ r^2 log r converges algebraically in the degree
    on its fixed pole element: (degree / (degree + step))^LOADED_POLE_ORDER there. One
    rung's change then understates the error by 1 / (1 - that factor)."""
    if not any(loaded_poles(scene)):
        return 0.0
    return (degree / (degree + step)) ** LOADED_POLE_ORDER


def layer_width(scene, piece: int, s: float) -> float:
    """The bending layer's width at arclength s of piece ``piece``:
    sqrt(h t R) / ``LAYER_FACTOR`` with t the thickness profile and R = 1 / max(|k1|, |k2|)
    of the reference there, or the meridian's length where it is flat (a plate's layers,
    membrane ones, are as wide as sqrt(h L) at the loads that make them)."""
    from . import kinematics as K
    from .fields import point_fields

    x = np.array([float(s)])
    F = point_fields(scene, piece, x, 0.0, np.asarray(scene.field_parameters), np)
    k1, k2 = scene.geometry.curvatures(x)
    kmax = max(abs(float(k1[0])), abs(float(k2[0])))
    R = min(1.0 / kmax if kmax > 0 else math.inf, scene.length)
    return math.sqrt(scene.h * float(F[K.THICKNESS][0]) * R) / LAYER_FACTOR


def _piece_cuts(a: float, b: float, left, right, ratio: float) -> list:
    """Element ends of the piece [a, b]: graded from ``left`` (the innermost element's
    length at a, or None) and ``right`` (at b), each side's next element ``ratio`` times its
    last, the side with the shorter next element growing first, until no further pair fits;
    the middle then in equal elements no longer than ``ratio`` times the shorter side's last
    (consecutive elements differ by at most ``ratio`` everywhere)."""
    span = b - a
    sides = {k: [] for k, core in (("lo", left), ("hi", right)) if core is not None}
    nxt = {"lo": left, "hi": right}
    gap = span
    while sides:
        k = min(sides, key=lambda k: nxt[k])
        if gap < nxt[k] * (1.0 + ratio):
            break
        sides[k].append(nxt[k])
        gap -= nxt[k]
        nxt[k] *= ratio
    lo, hi = sides.get("lo", []), sides.get("hi", [])
    last = min(lo[-1:] + hi[-1:], default=None)
    middle = 1 if last is None else max(1, math.ceil(gap / (ratio * last) - 1e-9))
    sizes = lo + [gap / middle] * middle + hi[::-1]
    x = a + np.concatenate([[0.0], np.cumsum(sizes)])
    x[-1] = b
    return list(x)


def single_mesh(scene) -> Mesh:
    """One element per piece of the scene: the single-domain discretisation."""
    ends = tuple(float(x) for x in scene.piece_ends)
    return Mesh(ends, tuple(range(scene.pieces)))


def mesh_of(scene, *, grading: float = GRADING, core: float = CORE_ELEMENTS,
            pole_core: float = POLE_CORE, single_t: float = SINGLE_T) -> Mesh:
    """The elements of ``scene`` (module docstring): one per piece where its shallowness is
    at most ``single_t``, else graded into every layer by ``grading``, the innermost element
    ``core`` layer widths long (``pole_core`` thicknesses at a loaded or singular pole).

    Raises:
        ValueError: for a grading outside [1.2, 8] or a core outside (0, 10].
    """
    if not (isinstance(grading, (int, float)) and 1.2 <= grading <= 8.0):
        raise ValueError(f"grading must be a number in [1.2, 8] (the ratio of consecutive "
                         f"elements), got {grading!r}")
    for name, v in (("core", core), ("pole_core", pole_core)):
        if not (isinstance(v, (int, float)) and 0 < v <= 10):
            raise ValueError(f"{name} must be a number in (0, 10], got {v!r}")
    if scene.shallowness <= single_t:
        return single_mesh(scene)
    ends = scene.piece_ends
    P = scene.pieces
    fine_pole = tuple(a or b for a, b in zip(loaded_poles(scene), singular_poles(scene)))
    cuts, pieces = [0.0], []
    for i in range(P):
        a, b = float(ends[i]), float(ends[i + 1])
        inside = np.nextafter(a, b), np.nextafter(b, a)
        layers = []
        for side, (end, x) in enumerate(((0, inside[0]), (1, inside[1]))):
            outer = (i == 0) if end == 0 else (i == P - 1)
            if outer and scene.ends[end].kind == "pole":
                # a regular pole is smooth; a loaded or singular one is graded to pole_core h
                layers.append(pole_core * scene.h if fine_pole[end] else None)
            else:
                layers.append(core * layer_width(scene, i, x))
        here = _piece_cuts(a, b, *layers, float(grading))
        cuts.extend(here[1:])
        pieces.extend([i] * (len(here) - 1))
    return Mesh(tuple(cuts), tuple(pieces))
