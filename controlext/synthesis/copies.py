"""Designs of copies made from designs of fewer.

A problem of ``N`` copies starts from its one-copy design embedded
(:func:`one_copy`) and, with equal weights, has the design of ``N − 1``
copies grown to ``N`` as a candidate (:func:`fewer_copies`), so that
copies are never worse than fewer.  The pipeline's ``synthesise`` is
passed in (it calls these).

The embedded design is a candidate as it is, but refinement starts from
it *split* (:func:`split`): with equal weights the norm does not change
when copies swap places, so its gradient at identical copies is that of
identical copies, and BFGS from them never leaves them but by rounding.
Which way rounding tipped it decided the design (quadruple tank pair,
nominal, the plant and three 1e-13 perturbations of it: 1.41–1.65; from
the split start 1.41–1.43).

Examples
--------
The grown gain has the norms of the ``N − 1``-copy gain it came from:

>>> import numpy as np
>>> import control as ct
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.norms import hinfnorm
>>> pair = ObserverProblem(A=[[-0.5]], C=[[1.0]], copies=2)
>>> three = pair.replace(copies=3)
>>> G2 = np.array([[2.0, 0.5], [0.3, 1.5]])
>>> G3 = three.grow(G2, np.array([[2.0]]))
>>> def norm(p, G):
...     return hinfnorm(ct.ss(p.Ae - G @ p.Ce, p.Bwe - G @ p.Dwe, p.Cze,
...                           0))[0]
>>> bool(abs(norm(three, G3) - norm(pair, G2)) < 1e-9)
True
"""

import numpy as np

from ..exceptions import SolverError, VerificationError
from .refine import refine_design

__all__ = ['one_copy', 'first_rows', 'fewer_copies', 'split']

#: relative size (to the gain's RMS entry) of the seeded perturbation
#: that splits the embedded one-copy start (1e-3 left a 2 % spread on
#: the quadruple tank pair, 1e-2 1.4 %)
SPLIT = 1e-2
#: under a smaller gain tolerance, the grown design of fewer copies is
#: also grown with the one-copy design of this tolerance
TRACKER_TOLERANCE = 1e-2


def one_copy(synthesise, problem, region, options, convex, bound, floor):
    """The one-copy design ``(G, report)`` of a problem of copies, a
    start for them (without the limits where no one-copy design meets
    them); ``synthesise`` is the pipeline's."""
    single = options if options.method != 'lmi' else \
        options.replace(method='auto')
    one_bound = first_rows(bound, problem.n)
    try:
        return synthesise(problem.single(), region, single,
                          convex=convex.luenberger, bound=one_bound,
                          floor=floor)
    except VerificationError:
        if not (options.criteria.limits or options.criteria.bounds):
            raise
        # no one-copy design meets the limits or the norm bounds (copies
        # may: on the second-order plant at decay 1 the best one copy has
        # H2 0.273, the best pair 0.0545): the one without them is still
        # a start for the copies
        return synthesise(problem.single(), region, single.replace(
            settling_time=None, gain_tolerance=None, max_hinf=None,
            max_h2=None), convex=convex.luenberger, bound=one_bound,
            floor=floor)


def first_rows(bound, rows):
    """The :class:`~controlext.synthesis.conditioning.GainBound` of the
    problem whose gain is the first ``rows`` rows (fewer copies; None
    stays None)."""
    return None if bound is None else bound.rows(rows)


def fewer_copies(synthesise, problem, region, options, convex, bound,
                 floor, single):
    """``[(G, label)]``: the best design of ``N − 1`` copies grown to
    ``N`` (the last tracking their average), a candidate so that more
    copies are never worse (quadruple tank, N = 3: 1.614 against 1.595
    for N = 2 without it).  Not a start: it leads the polishing race
    early and ends in a worse basin (scalar plant N = 6 up to 1.56x the
    best filter, second order N = 3 up to 4.6x).

    The last copy's deviation gets no noise, so its gain changes no norm,
    only the poles it adds.  Under a gain tolerance the ``N − 1`` design
    is at its tolerance's limit and the grown gain has more entries, so
    the grown design rarely meets it: it is grown with the one-copy
    design and with that of the loose tolerance :data:`TRACKER_TOLERANCE`
    (poles well away from the edge), and refined under the tolerance from
    both (quadruple tank, N = 3: the grown designs keep the region under
    gain errors of 3.7e-7 and 8.0e-7 only; refined, 1.4806 against 1.5208
    for N = 2, where the three-copy design had been 1.5537)."""
    fewer = problem.replace(copies=problem.copies - 1)
    try:
        Gf, _ = synthesise(fewer, region, options,
                           bound=first_rows(bound, fewer.copies * problem.n),
                           floor=floor, single=single)
    except (VerificationError, SolverError):
        return []
    label = f'{fewer.copies} copies'
    grown = [(problem.grow(Gf, single[0]), label)]
    tolerance = options.criteria.gain_tolerance
    if tolerance and tolerance < TRACKER_TOLERANCE:
        try:
            L, _ = one_copy(synthesise, problem, region, options.replace(
                gain_tolerance=TRACKER_TOLERANCE), convex, bound, floor)
        except (VerificationError, SolverError):
            pass
        else:
            grown.append((problem.grow(Gf, L), f'{label}, robust tracker'))
        try:
            res = refine_design(problem, region,
                                [(lab, G) for G, lab in grown], options,
                                bound, floor, random_starts=0)
        except VerificationError:
            pass
        else:
            grown.append((res.G, f'{label}, repaired'))
    return grown


def split(G, seed):
    """``G`` plus a seeded perturbation of :data:`SPLIT` times its RMS
    entry, in every entry (off the blocks of the copies too): a start
    that is not identical copies (module text)."""
    G = np.asarray(G, dtype=float)
    rms = np.linalg.norm(G) / np.sqrt(max(G.size, 1))
    rng = np.random.default_rng(seed)
    return G + SPLIT * max(rms, 1e-12) * rng.standard_normal(G.shape)
