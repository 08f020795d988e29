"""The gain tolerance's road: designs that keep their region under
relative gain errors.

A design of ``gain_tolerance=ε`` keeps its error poles in the region
under relative errors of ``ε`` in every gain entry, certified
(:class:`~controlext.synthesis.limits.GainTolerance`).  The factories ask
for :data:`GAIN_TOLERANCE` unless told otherwise (:func:`robust_default`).
:func:`tolerant` designs it from the nominal optimum, cheapest first:

1. the nominal optimum itself, when it meets the tolerance (most single
   observers on the public plants);
2. the nominal optimum *repaired*: refined under the tolerance from
   itself and two seeded splits of it (relative perturbations of
   :data:`SPLIT`, which part a pole cluster the certificate cannot
   hold), taken when it ends within :data:`REPAIR_COST` of the nominal
   norm (the paper's pairs and its scalar plant's three copies);
3. else refinement from the design of the looser tolerance
   :data:`TOLERANCE_TOP` (which meets every smaller one: its poles hold
   off the edge), the end points of the next basins of its refinement
   (:attr:`~controlext.synthesis.RefineResult.runners`) and the nominal
   optimum, the repaired design a candidate beside them.  Which basin
   of the looser design ends lowest under the tighter tolerance is not
   the one that led (HE1 pair: from the plant and three 1e-13
   perturbations of it, 18.41-19.26 from the leader alone, 18.41-18.99
   from the runners too).  The looser design is made the general way
   (convex design, random starts, the nominal optimum); so is a design
   of a tolerance at or above :data:`TOLERANCE_TOP`.

``python benchmarks/robust_decay.py`` measures what each costs.

Examples
--------
The paper's scalar pair: its nominal optimum stacks two poles on the
edge ``−2.5``, which 6-digit rounding moves past it; the default design
keeps the edge, at a γ 0.06 % higher.

>>> import numpy as np
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
>>> pair = cx.coupled_observer(plant, decay=2.5)
>>> G = np.vectorize(lambda x: float(f"{x:.5e}"))(pair.G)   # 6 digits
>>> p = pair.problem
>>> bool(np.linalg.eigvals(p.Ae - G @ p.Ce).real.max() <= -2.5)
True
>>> bool(pair.hinf <= 0.4953 * 1.002)
True
"""

import numpy as np

from ..exceptions import ArgumentError, SolverError, VerificationError
from .judge import equal
from .limits import edges_of
from .refine import refine_design

__all__ = ['GAIN_TOLERANCE', 'robust_default', 'tolerant']

#: the factories' default gain tolerance: a design keeps its region under
#: relative gain errors of this size, certified, and when its gain is
#: rounded to 6 significant digits (``gain_tolerance=0``: the nominal
#: optimum)
GAIN_TOLERANCE = 1e-6
#: a gain tolerance below this starts from the design of this tolerance,
#: the closest to the default's optimum of those tried (1e-2 to 1e-5)
TOLERANCE_TOP = 1e-4
#: the label of the nominal optimum among the starts of a gain tolerance
NOMINAL = 'nominal optimum'
#: a repair of the nominal optimum within this (relative) of its norm is
#: the design.  Repairs cost 0-0.21 % on single observers, 0.06-0.13 % on
#: the paper's pairs and 0.65 % on its scalar plant's three copies, where
#: refinement from the design of TOLERANCE_TOP gained 0.014 % in 2.6x the
#: time of the whole design; on the second-order plant's three copies
#: they cost 1.2-1.5 %, and that refinement keeps its γ within 0.04 %
#: under 1e-13 perturbations of the plant, the repair alone 0.24 %
REPAIR_COST = 1e-2
#: relative sizes of the seeded perturbations of the nominal optimum that
#: start its repair beside it
SPLIT = (1e-3, 1e-2)


def robust_default(options, region):
    """``(options, default)``: the options with :data:`GAIN_TOLERANCE`
    where no tolerance is given, refinement runs and the region's edges
    carry the certificate (half-planes and disks), and whether it was
    applied."""
    if options.gain_tolerance is not None or not options.refine:
        return options, False
    try:
        edges_of(region)
    except ArgumentError:
        return options, False
    return options.replace(gain_tolerance=GAIN_TOLERANCE), True


def tolerant(synthesise, problem, region, options, convex, bound, floor,
             check, rivals=(), stats=None):
    """The nominal-first road of a gain tolerance: ``(done, starts,
    repair, candidates)``.

    ``done`` is ``(G, report)`` when the nominal optimum, or its repair
    within :data:`REPAIR_COST`, is the design (see the module's text).
    Else ``starts`` are the starts of the refinement that follows:
    ``repair`` says that it should start from these alone (no random
    starts), and ``candidates`` ``[(G, label)]`` are verified designs it
    must beat.  ``synthesise`` is the pipeline's, ``check`` verifies a
    gain under the tolerance, and ``rivals`` ``[(G, label)]`` are designs
    of fewer copies grown to these (the one-copy design, ``N − 1``
    copies), which a design returned early (the nominal optimum or its
    repair) must beat.  Where the nominal optimum misses the tolerance,
    its norm goes to the statistics (``stats``, those of the design the
    road ends with, and those of a design returned early) as
    ``nominal``, unless it is a norm near 0 (:func:`equal` to 0), to
    which no cost is relative.
    """
    criteria = options.criteria
    try:
        Gn, nominal = synthesise(problem, region, options.replace(
            gain_tolerance=None), convex=convex, bound=bound, floor=floor)
    except (VerificationError, SolverError):
        return None, [], False, []
    try:
        report = check(Gn, method=nominal.method, stage=nominal.stage,
                       convex=convex, stats=nominal.stats,
                       gamma_bound=nominal.gamma_bound)
    except VerificationError:
        pass
    else:
        report.stats = nominal.stats.replace(
            limits=report.stats.limits,
            tolerance='the nominal optimum keeps its region under the gain '
            'tolerance')
        # the searches stop short of the optimum: a tolerant design of
        # fewer copies may still beat the nominal one of these (quadruple
        # tank pair: tolerant 1.5208, nominal 1.5753)
        return _best((Gn, report), rivals, check, criteria, convex), [], \
            False, []
    starts = [(NOMINAL, Gn)]
    level = criteria.value(nominal)
    cost = level > equal(0.0, problem)
    if stats is not None and cost:
        stats.update(nominal=level)
    if criteria.gain_tolerance >= TOLERANCE_TOP:
        return None, starts, False, []
    fast = _repaired(problem, region, options, convex, bound, floor, check,
                     Gn, nominal, level if cost else None)
    kept = []
    if fast is not None:
        if criteria.value(fast[1]) <= (1 + REPAIR_COST) * level:
            # copies are never worse than fewer (the repair may end up
            # to REPAIR_COST above the nominal optimum of copies)
            return _best(fast, rivals, check, criteria, convex), [], \
                False, []
        kept = [(fast[0], 'repaired')]
    try:
        Gt, looser = synthesise(problem, region, options.replace(
            gain_tolerance=TOLERANCE_TOP), convex=convex, bound=bound,
            floor=floor)
    except (VerificationError, SolverError):
        return None, starts, False, kept
    label = f'gain_tolerance={TOLERANCE_TOP:g}'
    refined = looser.stats.get('refine')
    runners = [] if refined is None else refined.get('runners', [])
    return None, [(label, Gt)] + [
        (f'{label} {where}', G) for where, G in runners] + starts, \
        True, kept


def _repaired(problem, region, options, convex, bound, floor, check, Gn,
              nominal, level):
    """The nominal optimum ``Gn`` refined under the gain tolerance from
    itself and its splits, ``(G, report)`` verified (its statistics
    keeping the nominal norm ``level`` where it is not None), or None."""
    criteria = options.criteria
    rng = np.random.default_rng(options.seed)
    starts = [(NOMINAL, Gn)] + [
        (f'{NOMINAL} split {size:g}',
         Gn * (1 + size * rng.standard_normal(Gn.shape))) for size in SPLIT]
    try:
        res = refine_design(problem, region, starts, options, bound, floor,
                            random_starts=0)
    except VerificationError:
        return None
    stats = nominal.stats.replace(
        refine=res.summary(),
        tolerance='the nominal optimum, refined under the gain tolerance',
        **({} if level is None else dict(nominal=level)))
    try:
        report = check(res.G, method=f'{convex.method}+refine',
                       stage='refined', convex=convex, stats=stats)
    except VerificationError:
        return None
    report.stats = stats.replace(limits=report.stats.limits)
    return res.G, report


def _best(design, rivals, check, criteria, convex):
    """``design`` or the rival ``(G, label)`` that verifies with the
    lowest value (``design`` when equal); ``design``'s method and
    statistics go to the winner's report, whose stage is its label."""
    like = design[1]
    for G, label in rivals:
        try:
            report = check(G, method=like.method, stage=label,
                           convex=convex, stats=like.stats)
        except VerificationError:
            continue
        if criteria.value(report) < criteria.value(design[1]):
            report.stats = like.stats.replace(limits=report.stats.limits)
            design = G, report
    return design
