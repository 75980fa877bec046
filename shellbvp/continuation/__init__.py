"""One continuation and fold machinery for every discretisation (:mod:`shellbvp.methods`).

* :mod:`.newton`: bordered Newton and the exact branch tangent;
* :mod:`.arclength`: pseudo-arclength continuation with step control, fold detection;
* :mod:`.folds`: fold location (dp/dm = 0), polishing, and the refinement ladder that gives
  every fold its error estimate;
* :mod:`.fold_curve`: a fold as the solution of one system (minimally augmented, exact
  second derivatives), Newton on it, and the fold curve in theta;
* :mod:`.options`: :class:`ContinuationOptions`, the one source of defaults.
"""

from .arclength import Point, point_at_monitor, pseudo_arclength
from .fold_curve import fold_at_monitor, fold_ladder, fold_system_terms, solve_fold
from .folds import fold_sensitivity, ladder, locate_fold, polish_fold, refine_fold
from .newton import NewtonResult, newton, tangent
from .options import ContinuationOptions

__all__ = ["ContinuationOptions", "Point", "point_at_monitor", "pseudo_arclength",
           "locate_fold", "polish_fold", "refine_fold", "ladder", "fold_sensitivity",
           "solve_fold", "fold_ladder", "fold_at_monitor", "fold_system_terms",
           "NewtonResult", "newton", "tangent"]
