"""The one synthesis pipeline behind every factory.

Whatever the observer kind, a design is: the convex stage
(:func:`~controlext.synthesis.convex.convex_stage`: a certified gain),
then — where that stage is conservative, that is with a pole region or
more than one copy — refinement on the true H∞ norm
(:func:`~controlext.synthesis.refine.refine_gain`), started from the
convex gain and, for coupled problems of every kind, from the
Luenberger-equivalent design ``I_N ⊗ L`` of the same problem with one
copy, itself designed by this pipeline.  Every candidate is verified
(:func:`~controlext.synthesis.verify.verify_design`) and the one with the
smallest true norm is returned, so a coupled design is never worse than
the best one-copy design found for the same region.

Examples
--------
>>> import controlext as cx
>>> from controlext.synthesis import (ObserverProblem, SynthesisOptions,
...                                   synthesise)
>>> prob = ObserverProblem(A=[[-1.0, 1.0], [-1.0, 0.0]], C=[[1.0, 2.0]])
>>> G, report = synthesise(prob, cx.HalfPlane(1.0),
...                        SynthesisOptions(refine=False))
>>> report.stage, bool(report.decay >= 1 - 1e-6)
('lmi', True)
"""

import time

import numpy as np

from .._checks import check_detectable, check_name, check_region_reachable
from ..exceptions import VerificationError
from .convex import convex_stage
from .refine import refine_gain
from .regions import region_for
from .verify import verify_design

__all__ = ['design', 'synthesise', 'needs_refinement', 'check_problem']


def design(cls, problem, options, *, decay=None, region=None, name=None,
           what='plant'):
    """The factories' road: check everything, synthesise, build the
    observer of class ``cls`` from the problem it was designed on.

    ``decay``/``region`` give the pole region (:func:`region_for`);
    ``what`` names the plant in a detectability error.  Every check runs
    before any solver.
    """
    start = time.perf_counter()
    check_name(name)
    region = region_for(decay, region, problem.dt)
    check_problem(problem, region, what)
    G, report = synthesise(problem, region, options)
    report.time = time.perf_counter() - start
    return cls.from_problem(problem, G, report=report, name=name)


def check_problem(problem, region, what='plant'):
    """Refuse a problem no gain can solve: an unstable mode unobservable
    from the measurements, or an unobservable mode outside the region."""
    check_detectable(problem.A, problem.C, problem.dt, what)
    if region is not None:
        check_region_reachable(problem.A, problem.C, region, problem.dt)


def needs_refinement(problem, region):
    """Is the convex stage conservative for this problem?  With a pole
    region (one Lyapunov matrix for the bound and the region) or more
    than one copy (a common Lyapunov matrix never beats one copy)."""
    return region is not None or problem.copies > 1


def synthesise(problem, region, options, convex=None):
    """Convex stage, refinement where it is conservative, verification.

    Parameters
    ----------
    problem : ObserverProblem
        The generalised plant (any kind, any number of copies).
    region : Region or None
        Pole region of the error dynamics.
    options : SynthesisOptions
        Checked options (``refine=False`` returns the convex design).
    convex : ConvexResult, optional
        An already computed convex stage of ``problem``.

    Returns
    -------
    G : ndarray
        The best verified gain.
    report : DesignReport
        Its verified report.
    """
    if convex is None:
        convex = convex_stage(problem, region, options)
    best = verify_design(problem, convex.G, region, convex=convex)
    if not (options.refine and needs_refinement(problem, region)):
        return convex.G, best
    if best.hinf <= _equal(0.0, problem):
        # γ = 0 is the least any design can have, and no design counts as
        # better than one this close to it (see the ranking below)
        best.stats = dict(best.stats, floor='the convex design has γ = 0 '
                          'to the ranking tolerance: nothing to refine')
        return convex.G, best
    starts = [(best.stage, convex.G)]
    if problem.copies > 1:
        single = options if options.method != 'lmi' else \
            options.replace(method='auto')
        G1, _ = synthesise(problem.single(), region, single,
                           convex=convex.luenberger)
        starts.append(('luenberger', problem.embed(G1)))
    stats = dict(convex.stats)
    try:
        res = refine_gain(problem, region, starts,
                          options=options.refine_options, seed=options.seed,
                          executor=options.executor)
    except VerificationError as exc:
        # the convex design is verified already: keep it, say why
        stats['refine'] = dict(failed=str(exc))
        candidates = []
    else:
        stats['refine'] = dict(start=res.start, starts=res.starts,
                               evaluations=res.evaluations, time=res.time)
        candidates = [(res.G, 'refined')]
    candidates += [(G, label) for label, G in starts[1:]]
    method = f'{convex.method}+refine'
    verified = [(best, convex.G)] + [
        (verify_design(problem, Gc, region, method=method, stage=stage,
                       convex=convex, stats=stats), Gc)
        for Gc, stage in candidates]
    # the smallest true norm wins; designs equal to within a tolerance are
    # ranked by gain norm (when γ* is not attained, or is 0, the last bits
    # of γ cost unbounded gains)
    lowest = min(rep.hinf for rep, _ in verified)
    best, G = min(((rep, Gc) for rep, Gc in verified
                   if rep.hinf <= lowest + _equal(lowest, problem)),
                  key=lambda item: np.linalg.norm(item[1], 2))
    best.method, best.stats = method, stats
    return G, best


def _equal(gamma, problem):
    """How far above ``gamma`` a design still counts as equally good:
    0.1 % relative, and an absolute floor for norms near 0."""
    return max(1e-3 * gamma, 1e-4 * problem.noise_scale)
