"""shellbvp: reduced morphoelastic shell energies derived from 3D, axisymmetric equilibria of
stimulated spherical shells, continuation and folds (Taffetani & Pezzulla, "Nonlinear
morphoelastic energy based theory for stimuli responsive elastic shells").

Public API
----------
Energies (paper Sections 2-4; derived symbolically from the 3D densities)
    energy_density, energy_terms, EnergyTerms, thickness_map, stationary_series,
    MODELS, MATERIALS
Problem
    Scene, uniform_curvature (scenes as data); ShellBVP, reference_state (the multi-point
    axisymmetric BVP of a scene, written once)
Methods (discretisations behind one protocol)
    Chebyshev (spectral, default), Shooting (diffrax), Collocation (scipy's solve_bvp),
    default_nodes, bracketing_nodes
Solving and continuation
    solve, follow, at_monitor, fold_near, fold_curve_point, fold_gradient, MonitorPoint,
    FoldCurvePoint, ContinuationOptions
Stability
    second_variation, SecondVariation (the discrete second variation of the energy)
Results
    Equilibrium, Branch, Fold, ConvergenceError
Files
    atomic_write_text

Scenes of the paper live in :mod:`shellbvp.problems` (cap eversion, closed sphere), the
command line in :mod:`shellbvp.cli`. Names are imported on first use, so ``import shellbvp``
is cheap; the compiled parts turn on JAX float64 (``jax_enable_x64``), the one global JAX
setting the package changes, because continuation and fold refinement work at 1e-10.
"""

from importlib import import_module

__version__ = "0.2.0"

_WHERE = {
    "energy_density": "energy", "energy_terms": "energy", "EnergyTerms": "energy",
    "thickness_map": "energy", "stationary_series": "series",
    "MODELS": "models", "MATERIALS": "models",
    "Scene": "scene", "uniform_curvature": "scene",
    "ShellBVP": "bvp", "reference_state": "bvp",
    "Chebyshev": "methods", "Shooting": "methods", "Collocation": "methods",
    "default_nodes": "methods.chebyshev", "bracketing_nodes": "methods.chebyshev",
    "solve": "driver", "follow": "driver", "at_monitor": "driver", "MonitorPoint": "driver",
    "fold_near": "driver", "fold_gradient": "driver", "fold_curve_point": "driver",
    "FoldCurvePoint": "driver",
    "ContinuationOptions": "continuation",
    "Equilibrium": "results", "Branch": "results", "Fold": "results",
    "ConvergenceError": "errors",
    "second_variation": "stability", "SecondVariation": "stability",
    "atomic_write_text": "cache",
}

__all__ = sorted(_WHERE)


def __getattr__(name):
    if name in _WHERE:
        value = getattr(import_module(f".{_WHERE[name]}", __name__), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'shellbvp' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(__all__))
