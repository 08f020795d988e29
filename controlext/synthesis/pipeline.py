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
the best one-copy design found for the same region.  A gain tolerance
(the factories' default) is designed from the nominal optimum
(:mod:`~controlext.synthesis.tolerance`).

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
from dataclasses import dataclass, field

import numpy as np

from .._warn import warn
from .._checks import (check_detectable, check_region_reachable,
                       check_system)
from .floor import filter_floor
from .tradeoff import tradeoff_of
from ..exceptions import (GainWarning, ParameterError,
                          RegionError, SolverError, VerificationError)
from .criteria import NAMES
from .convex import convex_stage
from .refine import refine_design
from .records import DesignStats, RefineSummary
from .regions import region_for
from .limits import limits_of
from .conditioning import (gain_bound,
                           warn_if_degenerate, warn_if_extreme,
                           warn_if_fragile, warn_if_held)
from .memo import memoised, one_design
from .lmi import check_lmi_memory, common_certificate
from .models import conflicts
from .verify import verify_design
from .judge import Judge, at_floor, equal, rank
from .tolerance import GAIN_TOLERANCE, NOMINAL, robust_default, tolerant
from .copies import fewer_copies, one_copy, split

__all__ = ['design', 'synthesise', 'needs_refinement', 'check_problem']


def design(cls, problem, options, *, decay=None, region=None, system=None,
           what='plant'):
    """The factories' road: check everything, synthesise on a scaled
    realisation (:meth:`ObserverProblem.state_scaling`), map the gain
    back, verify it on ``problem`` and build the observer of class
    ``cls`` from the problem it was designed on.

    ``decay``/``region`` give the pole region (:func:`region_for`);
    ``system`` holds python-control's system keywords (``name``,
    ``inputs``, ``outputs``, ``states``) for the observer; ``what`` names
    the plant in a detectability error.  Every check runs before any
    solver.
    """
    with one_design():
        return _design(cls, problem, options, decay, region, system, what)


def _design(cls, problem, options, decay, region, system, what):
    start = time.perf_counter()
    system = check_system(**(system or {}))
    problem.error_signals(system['inputs'], system['outputs'],
                          system['states'])
    region = region_for(decay, region, problem.dt)
    check_problem(problem, region, what)
    criteria = options.criteria
    limits_of(criteria, problem, region)    # refuses what a region can't hold
    floors = {}
    for name, bound in criteria.bounds:
        # a bound below the unconstrained optimum is met by no estimator
        floors[name] = filter_floor(problem, options.solver,
                                    max_states=options.lmi_max_states,
                                    criterion=name)
        if floors[name] is not None and bound < floors[name] * (1 - 1e-6):
            raise ParameterError(
                f"max_{name} = {bound:.6g} is below {floors[name]:.6g}, the "
                f"least {NAMES[name]} any linear estimator reaches on this "
                "plant (with no pole region at all): no observer meets it; "
                f"ask for max_{name} >= {floors[name]:.6g}")
    # synthesis on a realisation whose scaling does not depend on the
    # units of the states; the gain is mapped back and verified as given
    d = problem.state_scaling()
    if np.max(d) <= SPREAD * np.min(d):
        # states of comparable units keep them: refinement's search
        # depends on the realisation, and the paper's designs were tuned
        # on theirs
        d = np.ones_like(d)
    scaled = problem.scaled(d)

    options, default = robust_default(options, region)
    try:
        G, report, bound = _attempt(problem, scaled, d, region, options)
    except (VerificationError, SolverError):
        if not default:
            raise
        # the default tolerance is a preference, not a requirement: where
        # no design meets it (a plant whose poles are fragile in any
        # gain), the nominal optimum is returned, and says so
        options = options.replace(gain_tolerance=0)
        criteria = options.criteria
        G, report, bound = _attempt(problem, scaled, d, region, options)
        warn(f"no design was found whose error poles stay in "
             f"{region if region is not None else 'the stability region'} "
             f"under relative gain errors of {GAIN_TOLERANCE:g} and when "
             f"its gain is rounded to 6 significant digits; this is the "
             "nominal optimum: implement its gain to the digits "
             "the report's trade-off says it needs", GainWarning)
    warn_if_held(bound, G, report, options.max_gain)
    if not warn_if_extreme(scaled, G, report, region):
        warn_if_degenerate(scaled, G, report, region)
    G = problem.unscale_gain(G, d)
    if len(problem.members) > 1:
        report.polytope = _polytope(problem, G, region, options, report)
    # the trade-off reports the H∞ floor γ∞*, whatever was minimised
    floor = report.stats.get('floor_level', _no_floor) \
        if criteria.objective == 'hinf' else floors.get('hinf', _no_floor)
    if report.hinf <= equal(0.0, problem):
        floor = 0.0 if floor is _no_floor else floor     # 0 <= floor <= γ
    if floor is _no_floor:
        floor = filter_floor(problem, options.solver,
                             max_states=options.lmi_max_states)
    report.tradeoff = tradeoff_of(
        problem, G, system['name'] or '', floor=floor,
        luenberger=report.stats.luenberger_hinf, region=region,
        hinf=report.hinf)
    warn_if_fragile(report)
    report.time = time.perf_counter() - start
    return cls.from_problem(problem, G, report=report, **system)


def _attempt(problem, scaled, d, region, options):
    """``(G, report, bound)``: the design of ``scaled`` (``problem`` in
    the canonical units ``d``) verified on ``problem``, within the default
    gain bound where a design is, else without it; or the refusal."""
    criteria = options.criteria

    def check(G, **info):
        return verify_design(problem, problem.unscale_gain(G, d), region,
                             criteria=criteria, units=d, **info)

    bound = gain_bound(scaled, d, options.max_gain, region)
    try:
        convex = convex_stage(scaled, region, options)      # bound-free
        G, report = synthesise(scaled, region, options, convex=convex,
                               check=check, bound=bound)
    except (VerificationError, SolverError) as exc:
        if options.max_gain != 'auto' or not getattr(exc, 'bounded', False):
            _refuse(problem, region, options, exc)
        # the default bound is a guard, not a requirement: where no design
        # within it exists (a nearly unobservable plant), the unbounded
        # design is returned, with the GainWarning of warn_if_extreme
        bound = None
        try:
            G, report = synthesise(scaled, region, options, convex=convex,
                                   check=check)
        except (VerificationError, SolverError) as again:
            _refuse(problem, region, options, again)
    return G, report, bound


def _refuse(problem, region, options, exc):
    """Raise the refusal ``exc``; for several models, naming the pairs of
    models that share no Lyapunov matrix of the region (the likely
    conflict), if any."""
    pairs = [] if len(problem.members) == 1 else \
        conflicts(problem, region, options.solver)
    if not pairs:
        raise exc
    where = 'the stability region' if region is None else str(region)
    named = ', '.join(f"{i} and {j}" for i, j in pairs)
    raise VerificationError(
        f"no gain was found that puts the error poles of every model in "
        f"{where}: models {named} admit no gain with one Lyapunov "
        "matrix for both (a common gain for them is unlikely to exist); "
        "design for fewer or closer models, or a looser region.  The "
        f"steps that failed: {exc}") from None


def _polytope(problem, G, region, options, report):
    """The common-Lyapunov bound of ``G`` over the models' convex hull
    (:func:`~controlext.synthesis.lmi.common_certificate`), or None;
    never below a model's own norm."""
    try:
        check_lmi_memory(problem)
    except SolverError:
        return None
    level = common_certificate(problem, G, region, options.solver)
    if level is None or level < report.hinf * (1 - 1e-6):
        return None
    return level


def check_problem(problem, region, what='plant'):
    """Refuse a problem no gain can solve: an unstable mode unobservable
    from the measurements, or an unobservable mode outside the region (of
    any model, named when there are several)."""
    members = problem.members
    for k, member in enumerate(members, start=1):
        name = what if len(members) == 1 else \
            f"{what} (model {k} of {len(members)})"
        check_detectable(member.A, member.C, member.dt, name)
        if region is not None:
            try:
                check_region_reachable(member.A, member.C, region,
                                       member.dt)
            except RegionError as exc:
                if len(members) == 1:
                    raise
                raise RegionError(f"on {name}: {exc}") from None


def needs_refinement(problem, region):
    """Is the convex stage conservative for this problem?  With a pole
    region (one Lyapunov matrix for the bound and the region), more
    than one copy (a common Lyapunov matrix never beats one copy) or
    more than one plant model (one Lyapunov matrix for all)."""
    return region is not None or problem.copies > 1 or \
        len(problem.members) > 1


@memoised
def synthesise(problem, region, options, convex=None, check=None,
               bound=None, floor=None, single=None):
    """Convex stage, refinement where it is conservative, verification.

    Inside one :func:`design`, a call repeated with the same problem,
    region, options, bound and floor returns the first call's result
    (:mod:`~controlext.synthesis.memo`).

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
    check : callable, optional
        ``check(G, **facts) -> DesignReport`` verifies a candidate gain
        (default :func:`verify_design` on ``problem``); a candidate it
        refuses is dropped, so the design returned is one it verified.
    bound : GainBound, optional
        The gain bound of
        :func:`~controlext.synthesis.conditioning.gain_bound` (a pair
        ``(κ, weights)`` is read as one): refinement
        holds it, and a candidate above it is refused.
    floor : float, optional
        The problem's unconstrained filter level
        (:func:`~controlext.synthesis.floor.filter_floor`, computed here
        when not given): a design at it is not refined further.
    single : (ndarray, DesignReport), optional
        The one-copy design of ``problem``, when already made (a design of
        ``N`` copies makes it once and passes it to that of ``N − 1``).

    Returns
    -------
    G : ndarray
        The best verified gain.
    report : DesignReport
        Its verified report.
    """
    criteria = options.criteria
    if check is None:
        def check(G, **info):
            return verify_design(problem, G, region, criteria=criteria,
                                 **info)
    judge = Judge(check, bound)
    if convex is None:
        convex = convex_stage(problem, region, options)
    done, best, within = _convex_design(problem, region, options, convex,
                                        judge)
    if done is not None:
        return done
    stats = DesignStats.of(convex.stats)
    if floor is None:
        floor = filter_floor(problem, options.solver,
                             max_states=options.lmi_max_states,
                             criterion=criteria.objective)
    stats.update(floor_level=floor)
    if best is not None and within and \
            at_floor(criteria.value(best), floor, problem, options):
        # the convex design is within floor_tol of the level no observer
        # of any structure can beat: refinement has at most that to gain
        best.stats = stats.replace(headroom=(
            f"the convex design reaches the unconstrained filter level "
            f"{floor:.6g} of the {NAMES[criteria.objective]} "
            f"({criteria.value(best):.6g}): no observer of any structure "
            f"or order can do better{_by_more(options)}, so it was not "
            "refined"))
        return convex.G, best
    ladder = Ladder([(convex.stage, convex.G)])
    if best is None and criteria.bounds:
        ladder.starts += _bounded_starts(problem, region, options, bound)
    if problem.copies > 1:
        done = _copies_ladder(ladder, problem, region, options, convex,
                              judge, floor, single, stats)
        if done is not None:
            return done
    if criteria.gain_tolerance:
        done, extra, ladder.repair, ladder.kept = tolerant(
            synthesise, problem, region, options, convex, bound, floor,
            judge, ladder.fewer, stats)
        if done is not None:
            return done
        ladder.starts += extra
    if not ladder.repair and bound is not None and not within:
        ladder.starts += _looser_start(problem, region, options, convex,
                                       bound, floor)
    candidates = _refined(ladder, problem, region, options, bound, floor,
                          stats)
    method = f'{convex.method}+refine'
    verified = judge.verified(convex, candidates, method, stats)
    if not verified:
        raise judge.refusal(stats, convex)
    return rank(verified, criteria, problem, method, stats)


@dataclass
class Ladder:
    """The starts and candidates of one design's refinement.

    Attributes
    ----------
    starts : list of (str, ndarray)
        Labelled refinement starts; the first is the convex design.
    fewer : list of (ndarray, str)
        Designs of fewer copies grown to these: the one-copy design
        embedded (a start, or a candidate under a repair) and those of
        ``N − 1`` copies (candidates).
    kept : list of (ndarray, str)
        Verified designs the refinement must beat (the tolerance's
        repair).
    repair : bool
        Refinement starts from the given starts alone: not the convex
        design, no random starts (the tolerance's repair).
    """
    starts: list
    fewer: list = field(default_factory=list)
    kept: list = field(default_factory=list)
    repair: bool = False


def _convex_design(problem, region, options, convex, judge):
    """``(done, best, within)``: the convex design's report ``best`` (None
    where it misses the limits), whether it is ``within`` the gain bound,
    and ``done`` ``(G, report)`` where the convex design is the design:
    no refinement asked for or needed, or a norm of 0."""
    criteria, bound = options.criteria, judge.bound
    best = convex.report
    if best is not None and criteria.limits:
        # the convex stage does not hold the limits: its design is returned
        # only if it meets them, and is a start in any case
        try:
            best = judge(convex.G, convex=convex,
                         gamma_bound=convex.gamma_bound)
        except VerificationError as exc:
            if not options.refine:
                raise VerificationError(
                    f"{exc}; refine=False returns the convex design, and "
                    "only refinement holds settling_time= and "
                    "gain_tolerance=") from None
            best = None
    within = bound is None or bound.holds(convex.G)
    # a design without a certified level (the placement fallback) is
    # refined too: it may be the zero gain, at a huge γ
    if best is not None and not (options.refine and (
            needs_refinement(problem, region) or not within or
            convex.gamma_bound is None)):
        if not within:
            # the convex stage does not hold the bound; refinement does
            warn(f"the convex design's gain norm exceeds the bound "
                 f"{bound.level:.6g} (refine=False returns it as it is)",
                 GainWarning)
            return (convex.G, judge.verify(
                convex.G, convex=convex,
                gamma_bound=convex.gamma_bound)), best, within
        return (convex.G, judge(convex.G, convex=convex,
                                gamma_bound=convex.gamma_bound)), \
            best, within
    if best is not None and criteria.value(best) <= equal(0.0, problem):
        # 0 is the least any design can have, and no design counts as
        # better than one this close to it (see the ranking)
        best.stats = best.stats.replace(
            floor='the convex design has a norm of 0 to the ranking '
            'tolerance: nothing to refine')
        return (convex.G, best), best, within
    return None, best, within


def _copies_ladder(ladder, problem, region, options, convex, judge, floor,
                   single, stats):
    """The designs of fewer copies into ``ladder.fewer``; ``(G, report)``
    where the one-copy design is at the filter level (no copies can beat
    it), else None."""
    criteria, bound = options.criteria, judge.bound
    if single is None:
        single = one_copy(synthesise, problem, region, options, convex,
                          bound, floor)
    G1, rep1 = single
    stats.update(luenberger_hinf=rep1.hinf)
    one = criteria.value(rep1)
    if at_floor(one, floor, problem, options):
        # headroom: the one-copy design is within floor_tol of the level
        # no observer of any structure can beat; copies gain at most that
        stats['headroom'] = (
            f"the one-copy design reaches the unconstrained filter level "
            f"{floor:.6g} of the {NAMES[criteria.objective]} ({one:.6g}): "
            "no observer of any structure or order can do better"
            f"{_by_more(options)}, so the copies were not refined")
        try:
            report = judge(problem.embed(G1), method=f'{convex.method}'
                           '+headroom', stage='luenberger', convex=convex,
                           stats=stats)
        except VerificationError:
            del stats['headroom']
        else:
            return problem.embed(G1), report
    ladder.fewer.append((problem.embed(G1), 'luenberger'))
    if problem.copies > 2 and np.allclose(problem.weights,
                                          1 / problem.copies):
        ladder.fewer += fewer_copies(synthesise, problem, region, options,
                                     convex, bound, floor, single)
    return None


def _refined(ladder, problem, region, options, bound, floor, stats):
    """Refine from the ``ladder``'s starts: ``[(G, stage)]``, the refined
    design (where refinement succeeded; ``stats['refine']`` says how it
    went) and every other candidate of the ladder."""
    starts, grown = list(ladder.starts), list(ladder.kept)
    if ladder.fewer:
        if ladder.repair:
            # a candidate, not a start: copies are never worse than one
            grown.append(ladder.fewer[0])
        else:
            # identical copies, split: BFGS would keep them identical
            G1, label = ladder.fewer[0]
            starts.append((f'{label} split', split(G1, options.seed)))
            grown.append(ladder.fewer[0])
        grown += ladder.fewer[1:]
    # a repair starts from the nominal optimum and the design of the
    # loosest tolerance alone: the first is where the norm is least, the
    # second has split the nominal optimum's pole clusters
    # (benchmarks/robust_decay.py measures what it costs)
    try:
        res = refine_design(problem, region,
                            starts[1:] if ladder.repair else starts,
                            options, bound, floor,
                            random_starts=0 if ladder.repair else None)
    except VerificationError as exc:
        # the convex design is verified already: keep it, say why
        stats['refine'] = RefineSummary(failed=str(exc))
        candidates = []
    else:
        stats['refine'] = res.summary()
        candidates = [(res.G, 'refined')]
    # (the nominal optimum is a start only when it misses the tolerance)
    return candidates + [(G, label) for label, G in starts[1:]
                         if label != NOMINAL] + grown


def _bounded_starts(problem, region, options, bound):
    """Starts inside the norm bounds where the convex stage gave none
    (one Lyapunov matrix for both norms and the region is
    conservative): the design minimising a bounded norm alone meets its
    bound whenever any design does."""
    starts = []
    for name, _ in options.criteria.bounds:
        plain = options.replace(objective=name, max_hinf=None, max_h2=None)
        try:
            Gb, _ = synthesise(problem, region, plain, bound=bound)
        except (VerificationError, SolverError):
            continue
        starts.append((f'{name} design', Gb))
    return starts


def _looser_start(problem, region, options, convex, bound, floor):
    """Far above the gain bound, the convex design is a poor start for
    it: the design within :data:`GAIN_LADDER` times the bound is a nearer
    one (a geometric ladder: the square root of the ratio per step)."""
    ratio = bound.norm(convex.G) / bound.level
    if ratio <= GAIN_LADDER:
        return []
    looser = bound.loosened(max(GAIN_LADDER, np.sqrt(ratio)))
    try:
        Gl, _ = synthesise(problem, region, options, convex=convex,
                           bound=looser, floor=floor)
    except (VerificationError, SolverError):
        return []
    return [(f'max_gain={looser.level:.3g}', Gl)]


def _by_more(options):
    """' by more than 0.25 %': the refinement's floor tolerance, said."""
    return f" by more than {100 * options.refine_options.floor_tol:.3g} %"


_no_floor = object()
#: a gain bound far below the convex design's gain starts from the design
#: within this many times the bound
GAIN_LADDER = 1.5


#: a canonical state scaling spreading less than this is not applied
SPREAD = 10.0
