"""The polishing race of refinement, and the helpers its workers share.

:func:`polish_runs` advances the best screened starts of
:func:`~controlext.synthesis.refine.refine_gain` side by side, one BFGS
segment (:func:`polish_step`) per run and round, each run a
:class:`PolishRun` carried from one segment to the next (and to a worker
and back); a run that falls behind and cannot catch up stops, and a
finished run is pushed strictly inside the region (:func:`finish`).
The workers run with BLAS on one thread (:func:`single_threaded`).

Examples
--------
>>> import numpy as np
>>> from controlext.synthesis.polish import PolishRun, reach
>>> # a run whose gains shrink by 0.8 a segment can still gain their
>>> # geometric series, 0.004 · 0.8 / 0.2
>>> run = PolishRun(x=np.zeros(1), best=(np.inf, None), gain=0.004,
...                 previous=0.005)
>>> round(reach(run, 100), 6)
0.016
"""

import contextlib
from dataclasses import dataclass, replace
import functools

import numpy as np

from .bfgs import bfgs
from .stationary import stationarity

try:
    from threadpoolctl import ThreadpoolController
except ImportError:         # pragma: no cover - a required dependency
    ThreadpoolController = None


__all__ = ['PolishRun', 'polish_runs', 'polish_step', 'finish',
           'make_feasible', 'single_threaded', 'run_all', 'reach']


@dataclass
class PolishRun:
    """One polishing run of :func:`polish_runs`, carried from one segment to
    the next (and to a worker and back).

    Attributes
    ----------
    x : ndarray
        The current point (the gain, flattened).
    best : (float, ndarray or None)
        The norm of the best point inside the constraints met so far,
        and the point.
    rho : float or None
        The penalty weight, once raised (None: the objective's own).
    escalation : int
        Times the weight was raised.
    restart : int
        Segments run since the last escalation.
    fx : float or None
        The objective at ``x`` (None: to be evaluated, the weight having
        changed).
    value : float
        The objective at the end of the last segment.
    gain, previous : float
        The relative decrease of the last segment, and of the one before.
    stop : bool
        Is the run over (it is then finished on its next call)?
    result : (float, ndarray or None) or None
        ``(γ, G)`` of the finished run.
    points : int
        Points evaluated by the last call.
    """
    x: np.ndarray
    best: tuple
    rho: float | None = None
    escalation: int = 0
    restart: int = 0
    fx: float | None = None
    value: float = np.inf
    gain: float = np.inf
    previous: float = np.inf
    stop: bool = False
    result: tuple | None = None
    points: int = 0


def make_feasible(obj, G, target, maxiter=200, stall=(10, 1e-7),
                  evaluations=None):
    """Push the worst constraint margin below ``target`` (phase 1); the
    push gives up when ``stall = (steps, rtol)`` steps gained less than
    ``rtol`` (relative), or after the step that reaches ``evaluations``
    margin evaluations (line searches included)."""
    if not obj.constrained or obj.margin(G)[0] <= target:
        return G
    count = [0]

    def f(x, grad=True, above=None):
        count[0] += 1
        m, g = obj.margin(x.reshape(G.shape))
        return m, g.ravel()

    def stop(x, fx):
        return fx <= target or (evaluations is not None and
                                count[0] >= evaluations)

    # beyond an edge a limit's margin is its constant ``outside`` plus
    # the region's margin, and the push's progress is the latter's
    offset = getattr(obj, 'offset', 0.0)

    def size(fx):
        return fx - offset if offset and fx >= offset else abs(fx)

    x, _ = bfgs(f, G.ravel(), maxiter, stop=stop, stall=stall[0],
                stall_tol=stall[1], size=size)
    G = x.reshape(G.shape)
    return G if obj.margin(G)[0] <= target else None


def single_threaded(fn):
    """Run ``fn`` with BLAS on one thread.

    The refinement evaluates thousands of small dense problems (eigen-
    decompositions, ``ab13dd``); OpenBLAS threads cost more than they save
    there — 2–11× per evaluation measured on a 2-core machine, most when
    another process holds the other core — and a process pool already
    uses the cores.
    """
    @functools.wraps(fn)
    def run(*args, **kwargs):
        with blas_limit():
            return fn(*args, **kwargs)
    return run


@functools.cache
def _controller():
    """This process's BLAS libraries, looked up once (a look-up per
    worker call, as ``threadpool_limits`` does, cost about 3 ms: 5 % of a
    small design)."""
    return ThreadpoolController()


def blas_limit():
    if ThreadpoolController is None:
        return contextlib.nullcontext()
    return _controller().limit(limits=1, user_api='blas')


def run_all(executor, fn, args):
    if executor is None:
        return map(fn, args)
    return executor.map(fn, args)


def finish(obj, x):
    """``(γ, G)`` of a polished point: pushed strictly inside the region
    (``(inf, None)`` if that fails)."""
    G = make_feasible(obj, x.reshape(obj.shape), 0.0)
    gamma = obj.norm(G) if G is not None else np.inf
    # the exact penalty may settle just outside the region when its weight
    # is below the multiplier; the best point inside seen on the way is
    # then the answer
    best_gamma, best_G = obj.best
    if best_G is not None and not gamma <= best_gamma:
        # (the search's norms of large systems are lower bounds: the
        # exact ones decide)
        other = obj.norm(best_G)
        if other < gamma:
            G, gamma = best_G, other
    if G is None or not np.isfinite(gamma):
        return np.inf, None
    return gamma, G


@single_threaded
def polish_step(args):
    """One BFGS segment of a polishing run (worker).

    A run is BFGS restarted with a fresh Hessian estimate while it
    improves, up to ``1 + restarts`` segments of ``maxiter`` steps; a run
    that then ends outside the region raises the penalty weight tenfold
    (the penalty is exact only above the constraint's multiplier) and
    goes on, up to ``escalations`` times.  ``run`` (a
    :class:`PolishRun`) carries the point, the weight and the best point
    inside met so far from one call to the next; a run that is over (or
    told to ``stop``) is pushed strictly inside the region and gets its
    ``result``.  A segment ends
    early at a point inside the constraints whose norm is ``enough`` or
    less (None: no such level).
    """
    obj, run, maxiter, restarts, escalations, tol, enough = args
    run = replace(run)
    before = obj.count
    base = obj.rho
    obj.best = run.best
    obj.rho = run.rho if run.rho is not None else base
    try:
        if not run.stop:
            x = run.x
            if run.fx is None:                  # an escalation starts
                run.fx = obj(x)[0]
            fx = run.fx
            # a point inside at the floor ends the segment: no gain of
            # any structure does better
            x, fnew = bfgs(obj, x, maxiter, stall=30, stall_tol=tol / 100,
                           stop=None if enough is None else
                           lambda x, fx: obj.best[0] <= enough)
            run.x, run.value, run.fx = x, fnew, fnew
            run.restart += 1
            inside = obj.margin(x.reshape(obj.shape))[0] <= 0
            if inside and run.restart <= restarts and \
                    stationarity(obj, x, run.restart).passed:
                # a stationary point inside the constraints: more steps
                # would not move it
                run.stop = True
            elif not fnew < fx - tol * abs(fx) or run.restart > restarts:
                if not obj.constrained or \
                        run.escalation >= escalations or inside:
                    run.stop = True
                else:
                    obj.rho *= 10
                    run.rho, run.escalation = obj.rho, run.escalation + 1
                    run.restart, run.fx = 0, None
        if run.stop:
            run.result = finish(obj, run.x)
    finally:
        obj.rho = base
        run.best = obj.best
        run.points = obj.count - before
    return run


def polish_runs(executor, obj, screened, maxiter, restarts, opts, floor=None):
    """Polish the screened starts ``(x, best)``; ``[(γ, G)]`` (``G`` None
    where the run failed) and the number of points evaluated.

    The runs advance in rounds of one segment each (in parallel on
    ``executor``); after a round, a run stops there when it is more than
    ``opts.race_keep`` behind the leader and its last segment gained less
    than ``opts.race_progress``, when at that segment's pace (or along
    the geometric series of its shrinking gains; times
    ``opts.race_reach``) its remaining segments would not take it more
    than ``opts.race_tie`` ahead of the leader, or when a point inside
    the region within ``opts.floor_tol`` of ``floor`` (a level no gain
    can beat) has been met; the segment that meets such a point ends
    there, and so does its round (the runs go in order of their values,
    the later ones' segments dropped).  The result does not depend on
    the executor.
    """
    enough = None if floor is None else floor * (1 + opts.floor_tol)
    at_floor = enough is not None and \
        min(best[0] for _, best in screened) <= enough
    runs = [PolishRun(x=x, best=best, stop=at_floor) for x, best in screened]
    points = 0
    while True:
        # the leader goes first: the run that meets the floor in a round
        # ends it, the later runs' segments being dropped (never computed
        # without an executor)
        going = sorted((k for k, run in enumerate(runs)
                        if run.result is None),
                       key=lambda k: runs[k].value)
        if not going:
            break
        for k, run in zip(going, run_all(executor, polish_step, [
                (obj, runs[k], maxiter, restarts, opts.escalations,
                 opts.polish_tol, enough)
                for k in going])):
            before, segment = runs[k].value, not runs[k].stop
            run.previous = run.gain
            run.gain = (before - run.value) / abs(run.value) \
                if np.isfinite(before) else np.inf
            runs[k] = run
            points += run.points
            if segment and enough is not None and run.best[0] <= enough:
                break
        lead = min(run.value for run in runs)
        inside = min(run.best[0] for run in runs)
        for run in runs:
            if run.result is not None or run.stop:
                continue
            behind = run.value / lead - 1 if lead > 0 else 0.0
            left = restarts + 1 - run.restart
            if run.gain < opts.race_progress and \
                    run.value > opts.race_keep * lead:
                run.stop = True
            elif behind > 0 and run.escalation == 0 and \
                    reach(run, left) * opts.race_reach < \
                    behind + opts.race_tie:
                # at the pace of its last segments it cannot get ahead of
                # the leader (by more than a tie) within its budget (a run
                # whose penalty weight was raised is not judged so: its
                # values jumped with the weight)
                run.stop = True
            elif enough is not None and inside <= enough:
                # a point inside the region at the floor: no gain of any
                # structure does better
                run.stop = True
    return [run.result for run in runs], points


def reach(run, left):
    """How much further a run may get in ``left`` segments: its last
    segment's gain each time, or, where its gains shrink, their geometric
    series."""
    gain, previous = run.gain, run.previous
    reach = gain * left
    if 0 < gain < previous < np.inf:
        ratio = gain / previous
        reach = min(reach, gain * ratio / (1 - ratio))
    return reach
