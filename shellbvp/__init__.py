"""shellbvp: reduced morphoelastic shell energies, axisymmetric equilibria, continuation.

Public API
----------
Energies (Taffetani & Pezzulla, Sections 2-4; derived symbolically, :mod:`shellbvp.reduction`)
    energy_density, energy_terms, EnergyTerms, thickness_map, stationary_series
Scenes and equilibria (DESIGN §4, §6)
    Scene, uniform_curvature, solve, Equilibrium, reference_state, BACKENDS, ConvergenceError
Continuation and folds (DESIGN §5)
    ContinuationOptions, continuation, refine_fold, follow, Branch, FoldPoint,
    at_monitor, MonitorPoint, default_nodes, BRANCH_BACKENDS
Back-ends (DESIGN §8)
    spectral (Chebyshev collocation, the default for continuation), shooting (diffrax),
    collocation (scipy's solve_bvp); :mod:`shellbvp.discrete` continues the first two
Files
    atomic_write_text

Importing shellbvp turns on JAX float64 (the solvers need double precision).
"""

from .cache import atomic_write_text
from .energy import EnergyTerms, energy_density, energy_terms, thickness_map
from .series import stationary_series
from .scene import Scene, uniform_curvature
from .equilibrium import BACKENDS, ConvergenceError, Equilibrium, reference_state, solve
from .continuation import ContinuationOptions, continuation, refine_fold
from .branch import (BRANCH_BACKENDS, Branch, FoldPoint, MonitorPoint, at_monitor,
                     default_nodes, follow)

__all__ = [
    "energy_density", "energy_terms", "EnergyTerms", "thickness_map", "stationary_series",
    "Scene", "uniform_curvature", "solve", "Equilibrium", "reference_state", "BACKENDS",
    "ConvergenceError", "ContinuationOptions", "continuation", "refine_fold", "follow",
    "Branch", "FoldPoint", "atomic_write_text", "at_monitor", "MonitorPoint", "default_nodes",
    "BRANCH_BACKENDS",
]
__version__ = "0.1.0"
