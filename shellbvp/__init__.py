"""shellbvp: reduced morphoelastic shell energies and axisymmetric equilibria.

Public API
----------
energy_density, energy_terms, EnergyTerms, thickness_map
    The reduced energy W = w_s + h^2/12 w_b of Taffetani & Pezzulla (Sections 2-4), derived
    symbolically from the 3D energies (:mod:`shellbvp.reduction`), and its quadrature referee.
stationary_series
    Perturbation series of a stationary point of W along a one-parameter family of states.
"""

from .energy import EnergyTerms, energy_density, energy_terms, thickness_map


__all__ = ["energy_density", "energy_terms", "EnergyTerms", "thickness_map"]
__version__ = "0.1.0"
from .series import stationary_series  # noqa: E402

__all__ += ["stationary_series"]
from .scene import Scene, uniform_curvature  # noqa: E402
from .equilibrium import BACKENDS, ConvergenceError, Equilibrium, reference_state, solve  # noqa: E402

__all__ += ["Scene", "uniform_curvature", "solve", "Equilibrium", "ConvergenceError", "BACKENDS",
            "reference_state"]
from .continuation import ContinuationOptions, continuation, refine_fold  # noqa: E402
from .branch import Branch, FoldPoint, follow  # noqa: E402

__all__ += ["ContinuationOptions", "continuation", "refine_fold", "Branch", "FoldPoint", "follow"]
