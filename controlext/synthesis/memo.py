"""Within one design, each sub-design is made once.

The gain-bound and tolerance ladders of
:func:`~controlext.synthesis.pipeline.synthesise` and its designs of fewer
copies ask for the same sub-design many times (a weakly observable
three-copy design asked for one one-copy design 14 times).  A call
repeated inside one :func:`one_design` scope with the same problem,
region, options, bound and floor returns the first call's result,
failures included: the result depends on nothing else (the search is
seeded).  Outside a scope every call runs.
"""

import contextlib
import contextvars
import copy
import functools

import numpy as np

from ..exceptions import SolverError, VerificationError
from .conditioning import GainBound

__all__ = ['one_design', 'memoised']

#: the results of the current design: key -> [(options, outcome), ...]
_RESULTS: contextvars.ContextVar = contextvars.ContextVar(
    'synthesis_memo', default=None)


@contextlib.contextmanager
def one_design():
    """The scope of one design: its sub-designs are made once."""
    token = _RESULTS.set({})
    try:
        yield
    finally:
        _RESULTS.reset(token)


def key_of(problem, region, bound, floor):
    """What, besides the options, a call of ``synthesise`` depends on."""
    arrays = [M for member in problem.members
              for M in (member.Ae, member.Ce, member.Bwe, member.Dwe,
                        member.Cze)] + [np.asarray(problem.weights,
                                                   dtype=float)]
    return (problem.copies, problem.dt, repr(region), floor,
            None if bound is None else bound.key(),
            tuple(np.ascontiguousarray(M).tobytes() for M in arrays))


def memoised(synthesise):
    """``synthesise`` made once per key inside :func:`one_design` (a call
    with its own ``check`` always runs: it verifies against another
    problem).  The undecorated function is ``.inner``."""
    @functools.wraps(synthesise)
    def run(problem, region, options, convex=None, check=None, bound=None,
            floor=None, single=None):
        bound = GainBound.of(bound)
        args = (problem, region, options, convex, check, bound, floor,
                single)
        results = _RESULTS.get()
        if results is None or check is not None:
            return run.inner(*args)
        key = key_of(problem, region, bound, floor)
        for known, outcome in results.get(key, ()):
            if known == options:
                if isinstance(outcome, Exception):
                    raise outcome
                return outcome[0].copy(), copy.deepcopy(outcome[1])
        try:
            G, report = run.inner(*args)
        except (VerificationError, SolverError) as exc:
            results.setdefault(key, []).append((options, exc))
            raise
        results.setdefault(key, []).append(
            (options, (G.copy(), copy.deepcopy(report))))
        return G, report

    run.inner = synthesise
    return run
