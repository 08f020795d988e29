"""Refinement: local nonsmooth optimisation of the gains on the true
objective.

The convex problem of :mod:`controlext.synthesis.lmi` uses one Lyapunov matrix for
the H∞ bound and the pole region, which is conservative (for the coupled
pair it never beats the Luenberger observer).  Refinement minimises the
*true* H∞ norm of the error system over the gain ``G``, subject to the
pole region, by the method of HIFOO (Burke, Henrion, Lewis & Overton):
BFGS with a weak-Wolfe line search, which copes with the nonsmoothness of
the H∞ norm, on the exact penalty

    f(G) = ‖T_G‖∞ + ρ · max(0, g(G) + δ),

where ``g(G)`` is the largest region margin over the eigenvalues of
``Ae − G Ce`` (``<= 0`` inside the region), evaluated with its gradient by
:class:`controlext.synthesis.objective.Objective`.  Many starts are screened with a
few iterations; the best are polished side by side
(:mod:`~controlext.synthesis.polish`), a run that falls far behind and
stalls stopping early; a final phase pushes the result
strictly inside the region.  The weight ρ starts a few times the
constraint's multiplier (``3 γ₀`` over the slowest error rate), where the
penalty's kink is mild; a polishing run that ends outside the region raises it
tenfold and goes on, since the penalty is exact only above the multiplier.

Examples
--------
>>> import numpy as np
>>> import controlext as cx
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.refine import refine_gain
>>> prob = ObserverProblem(A=[[-1.0, 1.0], [-1.0, 0.0]], C=[[1.0, 2.0]])
>>> res = refine_gain(prob, cx.HalfPlane(1.0), [('start', [[2.0], [5.0]])])
>>> bool(res.gamma < 0.2852)
True
"""

from dataclasses import dataclass, field, replace
import time

import numpy as np

from .bfgs import bfgs
from ..exceptions import VerificationError
from .objective import objective_of
from .options import RefineOptions
from .placed import near_edge, placed_polish
from .polish import make_feasible, polish_runs, run_all, single_threaded
from .rates import REGION_TOL
from .records import RefineSummary
from .stationary import Stationarity, stationarity

__all__ = ['RefineResult', 'refine_gain', 'refine_design']

@dataclass
class RefineResult:
    """Outcome of :func:`refine_gain`.

    Attributes
    ----------
    G : ndarray
        Best gain found (poles strictly inside the region).
    gamma : float
        Its true H∞ norm.
    start : str
        Label of the start that produced it.
    starts : list of (str, float)
        Each polished start with the norm it reached.
    evaluations : int
        Number of objective evaluations.
    time : float
        Wall-clock time in seconds.
    phases : dict
        Wall-clock seconds of each phase: ``screen`` (the feasibility
        pushes and short runs of every start), ``polish`` (the long runs
        of the best) and ``placed`` (the pole-cluster polish, where it
        ran).
    stationary : Stationarity or None
        The gradient-sampling test of the result
        (:func:`~controlext.synthesis.stationary.stationarity`).
    runners : list of (str, ndarray)
        The end points of up to :data:`RUNNERS` other basins within
        :data:`RUNNER_GAP` of ``gamma``, best first (each more than
        ``race_tie`` behind the one before it): starts for a refinement
        under a tighter limit.
    """
    G: np.ndarray
    gamma: float
    start: str
    starts: list = field(default_factory=list)
    evaluations: int = 0
    time: float = 0.0
    phases: dict = field(default_factory=dict)
    stationary: Stationarity | None = None
    runners: list = field(default_factory=list)

    def summary(self):
        """What a design report keeps of the refinement: everything but
        the gain and its norm (``report.stats['refine']``), the runners'
        gains included."""
        return RefineSummary(start=self.start, starts=self.starts,
                             evaluations=self.evaluations, time=self.time,
                             phases=self.phases, stationary=self.stationary,
                             runners=self.runners)


#: margin evaluations a start's feasibility push may take.  On the default
#: designs of the paper's two pairs and of six public plants (AC1, HE1,
#: batch reactor, cart-pendulum, quadruple tank, mass chain; one copy and
#: pair) a push that succeeded took at most 774 (the HE1 pair), one that
#: failed at most 825; pushes of the campaign's seed 113 (GI augmented,
#: unstable) averaged 3,900 and took 96 of its 104 s
PUSH_EVALUATIONS = 1600
#: the other basins' end points a refinement keeps
#: (:attr:`RefineResult.runners`), those within ``RUNNER_GAP`` of its
#: result (HE1 pair under 1e-4: the basins that ended lowest under 1e-6
#: were within 4 %; quadruple tank, one copy: runners 33 % behind made
#: the next refinement 2-5x as long for nothing)
RUNNERS = 2
RUNNER_GAP = 0.05


def _on_boundary(obj, G):
    """Is ``G`` inside the region up to the verification tolerance?"""
    lam = np.linalg.eigvals(obj.Ae - G @ obj.Ce)
    scale = max(1.0, float(np.max(np.abs(lam))))
    return obj.margin(G)[0] <= REGION_TOL * scale


@single_threaded
def _screen(args):
    """Make a start feasible and run a short BFGS (picklable worker)."""
    obj, G, delta, iterations, push = args
    before = obj.count
    obj.reset_best()
    # a random start the push cannot bring inside soon is dropped: pushes
    # that succeed do so within ~30 steps, those that stall creep on for
    # hundreds (HE1: 45 of 65 pushes failed after ~1,000 evaluations each,
    # 70 % of the screening), or spend their steps in 40-point line
    # searches (PUSH_EVALUATIONS)
    pushed = make_feasible(obj, G, -10 * delta, push, stall=(15, 1e-2),
                           evaluations=PUSH_EVALUATIONS)
    if pushed is None and _on_boundary(obj, G):
        pushed = G          # a verified design on the boundary: the
                            # penalty takes it from there
    if pushed is None:
        return np.inf, None, obj.count - before
    G = pushed
    x, fx = bfgs(obj, G.ravel(), iterations, stall=8, stall_tol=1e-6)
    if not np.isfinite(fx):
        return np.inf, None, obj.count - before
    return fx, (x, obj.best), obj.count - before


@single_threaded
def _advance(args):
    """More BFGS steps on a screened start (worker): the second round of
    screening of costly problems."""
    obj, (x, best), iterations = args
    before = obj.count
    obj.best = best
    x, fx = bfgs(obj, x, iterations, stall=8, stall_tol=1e-6)
    return fx, (x, obj.best), obj.count - before


def _clustered(obj, G, tol=1e-2):
    """Has ``G`` three or more error poles within ``tol`` (relative to
    the fastest) of the region's edge, where region margins stop being
    Lipschitz, or two there and others elsewhere that could join them?  (A
    pair can stall BFGS short of a larger cluster: the quadruple tank's
    one-copy design stopped at 2.464 with two of its four poles on the
    edge with numpy 2.0 and scipy 1.13 on one machine, 1.806 after this
    stage, 1.785 where BFGS itself reached three.  A pair that is every
    pole is the optimum of the paper's scalar pair, reached without
    this.  BFGS may stall a little short of the cluster: scalar N = 5,
    seed 3, with four poles 0 to 0.016 from the edge, 1.295x the best
    filter, 1.004x after this stage.)"""
    lam = np.linalg.eigvals(obj.Ae - G @ obj.Ce)
    scale = max(1.0, float(np.max(np.abs(lam))))
    near = near_edge(obj.region, lam, tol * scale)
    return near >= 3 or 2 <= near < lam.size


def _rate_scale(problem, G):
    """Rate of the slowest error mode of ``G`` (the one a region
    constraint binds) in the units of region margins: the smallest
    ``|λ|`` in continuous time; in discrete time the smallest ``|ln λ|``
    (the s-plane rate times ``dt``), since margins there are in ``|z|``
    units."""
    lam = np.linalg.eigvals(problem.Ae - G @ problem.Ce)
    if problem.dt:
        lam = np.log(lam.astype(complex) + 1e-300)
    return max(float(np.min(np.abs(lam))), 1e-6)


def refine_gain(problem, region, starts, *, options=None, seed=0,
                executor=None, gain_bound=None, gain_weights=None,
                floor=None, criteria=None):
    """Minimise the true H∞ norm (or the norm ``criteria`` say) over the
    gain, inside ``region``.

    Parameters
    ----------
    problem : ObserverProblem
        The generalised plant.
    region : Region or None
        Pole region (``None``: stability only).
    starts : list of (str, array_like)
        Labelled starting gains (for example the LMI solution and the
        Luenberger-equivalent design).
    options : RefineOptions or dict, optional
        The budget policy (:class:`~controlext.synthesis.RefineOptions`):
        every start runs ``screen_iterations`` BFGS steps and the
        ``polish`` best continue in segments of ``maxiter`` steps with up
        to ``restarts`` fresh-Hessian restarts while they improve.
        Defaults scale with the gain: up to 64 gain entries ``maxiter =
        max(restart_every, 10 entries)`` (at most 600) and as many
        restarts as fit in 2400 steps; more than 64 entries ``maxiter =
        600`` and one restart, shorter still on more than 64 error
        states, where only starts within 1.5x of the best screened one
        are polished.  The random starts are seeded perturbations of the
        given ones (32 for up to 16 entries, at most 8 per entry, fewer
        for larger gains).  A problem of ``k`` plant models, whose
        evaluations cost ``k`` times as much, has ``k`` times fewer random
        starts and polishing restarts.  The objective adds ``tikhonov ·
        γ₀ · ‖G‖² /
        max(1, ‖G₁‖²)`` (``G₁`` the first given start), which keeps the
        gain finite where the infimum of the norm needs unbounded gains.
    seed : int, optional
        Seed of the random starts (results are reproducible).
    executor : concurrent.futures.Executor, optional
        Runs the screening and polishing of the starts in parallel (any
        executor: a ``ProcessPoolExecutor``, or a Dask one).  The result
        does not depend on it: the options travel with every call.
    gain_bound, gain_weights : optional
        The constraint ``‖diag(gain_weights) G‖₂ <= gain_bound``, held
        like the region (an exact penalty; the result satisfies it).
    floor : float, optional
        A level no gain can beat (the unconstrained filter level
        :func:`~controlext.synthesis.floor.filter_floor`): refinement
        stops once a point inside the region is within
        ``options.floor_tol`` of it.
    criteria : Criteria, optional
        The norm minimised and the norm bounded (held like the region);
        default: minimise the H∞ norm.

    Returns
    -------
    RefineResult
    """
    t0 = time.perf_counter()
    opts = RefineOptions.coerce(options)
    shape = problem.gain_shape
    nvar = shape[0] * shape[1]
    shrink = min(1.0, 16.0 / nvar)      # 1 for the small problems
    # a worst case over several plant models costs one evaluation per
    # model: its search gets the budget of evaluations of one model
    # (three 4-state models: 4.6 s with the one-model budget, 2.2 s so,
    # γ 0.01 % higher)
    models = len(problem.members)
    random_starts = opts.random_starts
    if random_starts is None:
        # and a gain of one or two entries needs fewer than 32 starts
        random_starts = min(max(4, int(round(32 * shrink**1.5)) // models),
                            8 * nvar)
    polish = min(opts.polish, max(2, int(round(opts.polish * shrink))),
                 2 + nvar)
    # an evaluation costs ~(error states)³ and large gains need more BFGS
    # steps: gains of more than 64 entries on error systems of more than
    # 64 states get shorter polishing runs (a 60-state pair in about a
    # minute; its 60-state Luenberger start keeps the full budget, which
    # measured γ 19.9 against 30.9 with the short one)
    large = shrink < 0.25 and problem.Ae.shape[0] > 64
    costly = shrink < 0.25 and problem.Ae.shape[0] > opts.costly_states
    # BFGS's Hessian estimate goes stale near the kinks of the norm: on
    # small gains a fresh one every few hundred steps makes the runs
    # shorter for the same budget of steps
    every = min(600, max(opts.restart_every, 10 * nvar))
    maxiter, restarts = opts.maxiter, opts.restarts
    if maxiter is None:
        maxiter = every if shrink >= 0.25 else 600 if not large \
            else max(100, int(round(600 * np.sqrt(shrink))))
    if restarts is None:
        restarts = 1 if shrink < 0.25 else \
            max(1, 2400 // every // models - 1)
    starts = [(label, np.array(G, dtype=float).reshape(shape))
              for label, G in starts]
    rng = np.random.default_rng(seed)
    given = list(starts)
    for k in range(random_starts):
        label, base = given[k % len(given)]
        # per-entry size: ‖base‖ spread over the entries of large gains
        scale = max(1.0, np.linalg.norm(base)) * np.sqrt(shrink) * \
            (0.3 if k < random_starts // 2 else 1.0)
        starts.append((f'{label}+random{k}',
                       base + scale * rng.normal(size=shape)))
    probe = objective_of(problem, region, peaks=opts.peaks, criteria=criteria)
    g0 = min(probe.norm(G) for _, G in given)
    g0 = g0 if np.isfinite(g0) else 1.0
    rho = opts.rho
    if rho is None:
        rho = opts.rho_scale * g0 / _rate_scale(problem, given[0][1])
    G1 = given[0][1]
    reg = opts.tikhonov * max(g0, 1e-3) / max(1.0, float(np.sum(G1 * G1)))
    obj = objective_of(problem, region, rho, opts.delta, reg, opts.peaks,
                    gain_bound=gain_bound, gain_weights=gain_weights,
                    gain_units=_rate_scale(problem, G1), criteria=criteria,
                    norm_tol=opts.norm_tol)

    # random starts of large gains are often far outside the region: give
    # the feasibility push fewer steps there (each costs an eigen-
    # decomposition; at n = 60 four failed pushes took 13 s with 200)
    push = 20 if large else opts.push
    phases = {}
    clock = time.perf_counter()
    runs = list(run_all(executor, _screen, [
        (obj, G, opts.delta, opts.screen_iterations, push)
        for _, G in starts]))
    screened = sorted(((fx, label, x) for (label, _), (fx, x, count)
                       in zip(starts, runs) if x is not None),
                      key=lambda item: item[0])
    if large and screened:
        # a large problem polishes only the starts near the best one: a
        # start 1.5x behind after screening cost 28 s at n = 60 and did
        # not catch up
        screened = [item for item in screened
                    if item[0] <= 1.5 * screened[0][0]]
    evaluations = probe.count + sum(count for _, _, count in runs)
    batches = [screened[first:first + polish]
               for first in range(0, len(screened), polish)]
    if costly and batches and len(batches[0]) > 1:
        # a polishing run of a costly problem takes thousands of points:
        # a second round of screening decides which deserve one (at
        # n = 60 a start 1.4x behind after the first round was polished
        # for 26 s and ended 5 % behind)
        again = list(run_all(executor, _advance, [
            (obj, x, opts.second_round) for _, _, x in batches[0]]))
        evaluations += sum(count for _, _, count in again)
        ahead = sorted(((fx, label, x) for (_, label, _), (fx, x, _)
                        in zip(batches[0], again)), key=lambda item: item[0])
        # the given starts always go on: the convex design is often far
        # behind early and ahead in the end (n = 20 pair: 3.35 -> 2.74)
        labels = {label for label, _ in given}
        batches[0] = [item for item in ahead
                      if item[0] <= opts.second_round_keep * ahead[0][0]
                      or item[1] in labels]
    phases['screen'] = time.perf_counter() - clock
    clock = time.perf_counter()
    # polish the best screened starts; should every one of them fail the
    # final feasibility push (seen on ill-conditioned plants), go on down
    # the list rather than give up
    results = []
    for batch in batches:
        polished, points = polish_runs(executor, obj, [x for _, _, x in batch],
                                   maxiter, restarts, opts, floor)
        evaluations += points
        results += [(gamma, label, G) for (_, label, _), (gamma, G)
                    in zip(batch, polished) if G is not None]
        if results:
            break
    if not results:
        bound = '' if gain_bound is None else \
            f" and a gain norm of at most {gain_bound:.6g}"
        raise VerificationError(
            "refinement found no gain with the error poles in "
            f"{region if region is not None else 'the stability region'}"
            f"{bound}")
    results.sort(key=lambda item: item[0])
    phases['polish'] = time.perf_counter() - clock
    clock = time.perf_counter()
    if region is not None and problem.Ae.shape[0] <= opts.placed_states \
            and obj.placeable and _clustered(obj, results[0][2]):
        # the best results whose pole map is regular (that of the
        # Luenberger-equivalent start, identical copies, is singular),
        # one per basin (more than a tie behind the last one tried): the
        # basin whose polish ends lowest is not the one that led after
        # polishing (HE1 pair, nominal: 19.79 from the best, 17.18 from
        # the third), and stopping at the first that beats the best
        # result made which basin won move with the plant's last bits
        tried, last, low = 0, None, results[0][0]
        enough = None if floor is None else floor * (1 + opts.floor_tol)
        for gamma, label, G in list(results):
            if tried >= opts.placed_starts or (
                    tried and enough is not None and low <= enough):
                break
            if tried and gamma < last * (1 + opts.race_tie):
                continue
            last = gamma
            out = placed_polish(obj, region, G, seed, enough=enough,
                                draws=opts.placed_draws)
            if out is None:
                continue
            tried += 1
            low = min(low, out[0])
            if out[0] < gamma:
                results.append((out[0], f'{label}, poles as variables',
                                out[1]))
        results.sort(key=lambda item: item[0])
        phases['placed'] = time.perf_counter() - clock
    gamma, label, G = results[0]
    test = stationarity(obj, G, seed)
    return RefineResult(G=G, gamma=float(gamma), start=label,
                        starts=[(lb, float(g)) for g, lb, _ in results],
                        evaluations=evaluations + test.samples,
                        time=time.perf_counter() - t0, phases=phases,
                        stationary=test,
                        runners=_runners(results, opts.race_tie))


def _runners(results, tie):
    """``[(label, G)]``: the end points of ``results`` (sorted ``(γ,
    label, G)``) after the first, each more than ``tie`` (relative) behind
    the last one kept and within :data:`RUNNER_GAP` of the first, up to
    :data:`RUNNERS` of them."""
    out, last = [], results[0][0]
    for gamma, label, G in results[1:]:
        if len(out) >= RUNNERS or gamma > results[0][0] * (1 + RUNNER_GAP):
            break
        if np.isfinite(gamma) and gamma > last * (1 + tie):
            out.append((label, G))
            last = gamma
    return out


def refine_design(problem, region, starts, options, bound, floor, *,
                  random_starts=None):
    """:func:`refine_gain` as the synthesis calls it: the refinement
    options, seed, executor and criteria of the
    :class:`~controlext.synthesis.SynthesisOptions` ``options`` (with
    ``random_starts`` when given), the gain bound ``bound``
    (:class:`~controlext.synthesis.conditioning.GainBound` or None) and
    the ``floor``."""
    opts = options.refine_options
    if random_starts is not None:
        opts = replace(opts, random_starts=random_starts)
    return refine_gain(problem, region, starts, options=opts,
                       seed=options.seed, executor=options.executor,
                       gain_bound=None if bound is None else bound.level,
                       gain_weights=None if bound is None else
                       bound.weights,
                       floor=floor, criteria=options.criteria)
