"""Discretisations of the shell BVP behind one protocol (:mod:`shellbvp.methods.base`).

====================  ==========================================================
``Chebyshev(nodes)``  spectral collocation, geometric convergence (the default)
``Shooting(...)``     multiple shooting with diffrax (Tsit5, exact sensitivities)
``Collocation(tol)``  scipy's solve_bvp scheme (4th order; solve_bvp's own mesh)
``Ritz(degree)``      direct minimisation of the discrete energy (spectral elements,
                      graded toward a singular apex; no inner inversion, no pole
                      conditions)
====================  ==========================================================

The strings ``"spectral"``, ``"shooting"``, ``"collocation"`` and ``"energy"`` are shortcuts for the
defaults of each (used by the command line).
"""

from __future__ import annotations

from .base import (DirectSolver, DiscreteSystem, Discretisation, InnerRoots, Method,
                   MidSurface, NodalBVP, NodalSystem, SecondOrder, ShellProblem,
                   Transplantable, implements)
from .chebyshev import Chebyshev, bracketing_nodes, default_nodes
from .collocation import Collocation
from .ritz import Ritz
from .shooting import Shooting

__all__ = ["Chebyshev", "Shooting", "Collocation", "Ritz", "METHODS", "as_method",
           "default_nodes",
           "bracketing_nodes", "DiscreteSystem", "Discretisation", "Transplantable",
           "SecondOrder", "InnerRoots", "Method", "DirectSolver", "NodalBVP", "ShellProblem",
           "NodalSystem", "MidSurface"]

METHODS = {"spectral": Chebyshev, "shooting": Shooting, "collocation": Collocation,
           "energy": Ritz}


def as_method(method: "Method | str") -> Method:
    """A method object from a method object or one of the names in ``METHODS``
    (``"spectral"``, ``"shooting"``, ``"collocation"``, ``"energy"``: each with its
    defaults).

    Raises:
        ValueError: an unknown name, or an object that is not a :class:`Method` (a frozen
            dataclass with ``name`` and ``discretise``).
    """
    if isinstance(method, str):
        if method not in METHODS:
            raise ValueError(f"method must be one of {tuple(METHODS)} or a method object, "
                             f"got {method!r}")
        return METHODS[method]()
    if not implements(method, Method):
        raise ValueError(f"method must be one of {tuple(METHODS)} or a method object "
                         f"(Chebyshev, Shooting, Collocation, Ritz), got {type(method).__name__}")
    return method
