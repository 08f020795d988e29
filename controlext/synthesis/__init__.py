"""The synthesis engine: one road from a generalised plant to a verified
gain, whatever the observer kind.

::

    ObserverProblem ──► convex_stage ──► refine_gain ──► verify_design
    (problem.py)        (convex.py:       (refine.py,     (verify.py)
                         lmi, riccati,     objective.py,
                         modal)            bfgs.py)

:func:`synthesise` (pipeline.py) runs the road with a
:class:`SynthesisOptions` (options.py) checked before any solve; pole
regions live in regions.py.

Examples
--------
>>> import controlext as cx
>>> from controlext.synthesis import (ObserverProblem, SynthesisOptions,
...                                   synthesise)
>>> prob = ObserverProblem(A=[[-0.5]], C=[[1.0]], copies=2)
>>> G, report = synthesise(prob, cx.HalfPlane(2.5), SynthesisOptions())
>>> bool(report.hinf < 0.4954), report.stage
(True, 'refined')
"""

# the generalised plant  (problem.py)
from .problem import ObserverProblem, plant_problem
# what a design minimises and bounds  (criteria.py)
from .criteria import Criteria
# options, checked before any solve  (options.py)
from .options import SynthesisOptions, RefineOptions
# pole regions  (regions.py)
from .regions import Region, HalfPlane, Disk, Sector, region_for
# the convex stage  (convex.py, lmi.py, riccati.py, modal.py)
from .convex import ConvexResult, convex_stage
# refinement  (refine.py, objective.py, bfgs.py)
from .refine import RefineResult, refine_gain
# verification  (verify.py)
from .verify import DesignReport, verify_design
from .records import DesignStats, RefineSummary
# the pipeline  (pipeline.py)
from .pipeline import synthesise, needs_refinement

__all__ = ['ObserverProblem', 'plant_problem', 'Criteria', 'SynthesisOptions',
           'RefineOptions', 'Region', 'HalfPlane', 'Disk', 'Sector',
           'region_for', 'ConvexResult', 'convex_stage', 'RefineResult',
           'refine_gain', 'DesignReport', 'DesignStats', 'RefineSummary',
           'verify_design', 'synthesise', 'needs_refinement']
