"""shellbvp: reduced morphoelastic shell energies derived from 3D, axisymmetric equilibria of
stimulated shells of revolution, continuation and folds (Taffetani & Pezzulla, "Nonlinear
morphoelastic energy based theory for stimuli responsive elastic shells").

Public API (this module; everything else is reached through its submodules)
------------------------------------------------------------------------------
Energies (paper Sections 2-4; derived symbolically from the 3D densities)
    energy_density, energy_terms, EnergyTerms, MODELS, MATERIALS
Problem (scenes as data)
    Scene, End, Ring, ReferencePoint, cap, uniform_curvature; the reference geometry: Meridian and
    its segments Plate, Cylinder, Cone, Sphere, Torus, Ellipse, Points, with spherical_cap,
    closed_sphere, disc, annulus, cylinder
Methods (discretisations behind one protocol, :mod:`shellbvp.methods`)
    Chebyshev (spectral, default), Shooting (diffrax), Collocation (scipy's solve_bvp),
    Ritz (direct minimisation of the discrete energy), as_method
Solving and continuation
    solve, follow, at_monitor, fold_near, fold_curve_point, fold_gradient,
    ContinuationOptions
Stability
    second_variation; beyond axisymmetry: modes (per harmonic n), modes_along (per point of
    a branch), first_instability, Instability, Modes; past the first bifurcation:
    follow_bifurcation (the n-lobed branch), Koiter, LobedBranch
Scene files (a shell as a TOML file, :mod:`shellbvp.scenefile`)
    load_scene, SceneFile
Results
    Equilibrium, Branch, Fold, MonitorPoint, FoldCurvePoint, SecondVariation, SnapResult,
    Onset, PressureResult, SnapCurve, ConvergenceError
Pictures and files (the methods ``plot3d``, ``animate``, ``to_vtk`` of the results)
    OutputUnits (the units they are written in: the engine's or a scene file's)

Lower tiers: :mod:`shellbvp.bvp` (``ShellBVP``, the multi-point BVP of a scene),
:mod:`shellbvp.methods` (``default_nodes``, ``bracketing_nodes``, the protocols),
:mod:`shellbvp.continuation` (Newton, pseudo-arclength, folds), :mod:`shellbvp.energy`
(``thickness_map``), :mod:`shellbvp.series`, :mod:`shellbvp.cache` (``atomic_write_text``),
:mod:`shellbvp.sweep` (sweeps with per-item outcomes, a journal, resumption and executors),
:mod:`shellbvp.surface` (the 3D surface of a state and its fields), :mod:`shellbvp.pictures`
(3D pictures, animations), :mod:`shellbvp.paraview` (VTK files and ParaView collections).
Scenes of the paper live in :mod:`shellbvp.problems`, the command line in
:mod:`shellbvp.cli`.

``import shellbvp`` loads numpy and scipy only: JAX (~1 s to import), sympy and diffrax are
imported by the functions that need them. The compiled parts turn on JAX float64
(``jax_enable_x64``), the one global JAX setting the package changes, because
continuation and fold refinement work at 1e-10.
"""

from importlib.metadata import PackageNotFoundError, version as _version

from .continuation.options import ContinuationOptions
from .driver import (FoldCurvePoint, MonitorPoint, at_monitor, fold_curve_point, fold_gradient,
                     fold_near, follow, solve)
from .energy import EnergyTerms, energy_density, energy_terms
from .errors import ConvergenceError
from .methods import Chebyshev, Collocation, Ritz, Shooting, as_method
from .models import MATERIALS, MODELS
from .results import Branch, Equilibrium, Fold
from .geometry import (Cone, Cylinder, Ellipse, Meridian, Plate, Points, Sphere, Torus,
                       annulus, closed_sphere, cylinder, disc, spherical_cap)
from .scene import End, ReferencePoint, Ring, Scene, cap, uniform_curvature
from .scenefile import SceneFile, load_scene
from .scene_results import Onset, PressureResult, SnapCurve, SnapResult
from .stability import SecondVariation, second_variation
from .harmonics import Modes, modes
from .instability import Instability, first_instability, modes_along
from .postbuckling import Koiter, LobedBranch, follow_bifurcation
from .surface import OutputUnits

try:
    __version__ = _version("shellbvp")
except PackageNotFoundError:        # a source tree that is not installed
    __version__ = "0+unknown"

__all__ = [
    "energy_density", "energy_terms", "EnergyTerms", "MODELS", "MATERIALS",
    "Scene", "End", "Ring", "ReferencePoint", "cap", "uniform_curvature", "load_scene", "SceneFile",
    "Meridian", "Plate", "Cylinder", "Cone", "Sphere", "Torus", "Ellipse", "Points",
    "spherical_cap", "closed_sphere", "disc", "annulus", "cylinder",
    "Chebyshev", "Shooting", "Collocation", "Ritz", "as_method",
    "solve", "follow", "at_monitor", "fold_near", "fold_curve_point", "fold_gradient",
    "ContinuationOptions",
    "second_variation", "modes", "modes_along", "first_instability", "Instability", "Modes",
    "follow_bifurcation", "Koiter", "LobedBranch",
    "Equilibrium", "Branch", "Fold", "MonitorPoint", "FoldCurvePoint", "SecondVariation",
    "SnapResult", "Onset", "PressureResult", "SnapCurve", "ConvergenceError",
    "OutputUnits", "__version__",
]
