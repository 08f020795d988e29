"""The synthesis's one judge and its one ranking step.

Every gain the pipeline (:func:`~controlext.synthesis.pipeline.synthesise`)
may return passes one :class:`Judge`: the gain bound first (a candidate
above it is refused, and the judge remembers it), then the verification
(:func:`~controlext.synthesis.verify.verify_design` or the factory's own
check).  :meth:`Judge.verified` judges the candidates of a design,
:meth:`Judge.refusal` names every step that failed when none passed, and
:func:`rank` picks the verified design of least norm.

Examples
--------
A candidate above the gain bound is refused before its verification:

>>> import numpy as np
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.conditioning import GainBound
>>> from controlext.synthesis.verify import verify_design
>>> prob = ObserverProblem(A=[[-1.0]], C=[[1.0]])
>>> judge = Judge(lambda G, **facts: verify_design(prob, G),
...               GainBound(2.0, np.ones(1)))
>>> judge(np.array([[1.5]])).method
'given'
>>> try:
...     judge(np.array([[3.0]]), stage='refined')
... except Exception as exc:
...     print(exc)
the refined design's gain norm 3 exceeds max_gain = 2
>>> judge.over_bound
[3.0]
"""

import numpy as np

from ..exceptions import VerificationError

__all__ = ['Judge', 'rank', 'equal', 'at_floor']


class Judge:
    """Verify candidate gains of one design.

    Parameters
    ----------
    verify : callable
        ``verify(G, **facts) -> DesignReport``; raises
        :class:`~controlext.exceptions.VerificationError` on a gain it
        refuses.
    bound : GainBound or None
        The gain bound every candidate must meet (checked first).

    Attributes
    ----------
    over_bound : list of float
        The gain norms of the candidates the bound refused.
    """

    def __init__(self, verify, bound=None):
        self.verify, self.bound = verify, bound
        self.over_bound = []

    def __call__(self, G, **facts):
        """The report of ``G``, within the bound and verified."""
        bound = self.bound
        if bound is not None:
            norm = bound.norm(G)
            if not bound.meets(norm):
                self.over_bound.append(norm)
                raise VerificationError(
                    f"the {facts.get('stage', 'convex')} design's gain "
                    f"norm {norm:.6g} exceeds max_gain = {bound.level:.6g}")
        return self.verify(G, **facts)

    def verified(self, convex, candidates, method, stats):
        """``[(report, G)]``: the convex design and the ``candidates``
        ``[(G, stage)]`` that pass; the stages refused, and why, go to
        ``stats['refused']``."""
        verified, refused = [], []
        for Gc, stage, facts in [(convex.G, convex.stage, dict(
                convex=convex, gamma_bound=convex.gamma_bound))] + [
                (Gc, stage, dict(method=method, stage=stage, convex=convex,
                                 stats=stats)) for Gc, stage in candidates]:
            try:
                verified.append((self(Gc, **facts), Gc))
            except VerificationError as exc:
                refused.append((stage, str(exc)))
        if refused:
            stats['refused'] = refused
        return verified

    def refusal(self, stats, convex):
        """The error when no candidate passed, naming every step that
        failed; its ``bounded`` says whether the gain bound refused a
        candidate or held refinement back (a retry without it may find a
        design)."""
        failed = None if stats.refine is None else stats.refine.failed
        steps = [f"{stage}: {why}" for stage, why in stats.refused or []]
        if failed is not None:
            steps.append(f"refinement: {failed}")
        steps += [f"{name}: {why}" for name, why in
                  convex.stats.get('fallback', [])]
        refusal = VerificationError(
            "no candidate design verified (" + "; ".join(steps) + "); try "
            "a looser region or a larger margin=" +
            ("" if self.bound is None else " or max_gain="))
        refusal.bounded = self.bound is not None and (
            bool(self.over_bound) or failed is not None)
        return refusal


def rank(verified, criteria, problem, method, stats):
    """``(G, report)`` of the verified design of smallest true norm;
    designs equal to within :func:`equal` are ranked by gain norm (when
    γ* is not attained, or is 0, the last bits of γ cost unbounded
    gains).  Its report gets ``method`` and ``stats``."""
    lowest = min(criteria.value(rep) for rep, _ in verified)
    best, G = min(((rep, Gc) for rep, Gc in verified
                   if criteria.value(rep) <= lowest + equal(lowest,
                                                            problem)),
                  key=lambda item: np.linalg.norm(item[1], 2))
    limits = best.stats.limits
    best.method, best.stats = method, stats
    if limits is not None:
        best.stats = stats.replace(limits=limits)
    return G, best


def equal(gamma, problem):
    """How far above ``gamma`` a design still counts as equally good:
    0.1 % relative; a norm of at most ``1e-4 · problem.noise_scale`` (a
    norm near 0) is equal to any other that small.

    The absolute floor applies only to norms near 0: above them, a floor
    in the noise channel's units would make designs several tenths of a
    percent apart equal, and which of them is returned would move with
    the plant's last bits.

    >>> from controlext.synthesis import ObserverProblem
    >>> prob = ObserverProblem(A=[[-1.0]], C=[[1.0]], Bw=[[1.0, 0.0]],
    ...                        Dw=[[0.0, 1.0]])
    >>> prob.noise_scale
    2.0
    >>> equal(1.0, prob), equal(0.01, prob), equal(1e-5, prob)
    (0.001, 1e-05, 0.0002)
    """
    zero = 1e-4 * problem.noise_scale
    return zero if gamma <= zero else 1e-3 * gamma


def at_floor(value, floor, problem, options):
    """Is ``value`` at the unconstrained filter level ``floor`` (a level
    no observer of any structure beats), within the refinement's
    ``floor_tol`` (relative) or the absolute floor of :func:`equal`?
    Refinement stops there, and a design there is not refined further.

    >>> from controlext.synthesis import ObserverProblem, SynthesisOptions
    >>> prob = ObserverProblem(A=[[-1.0]], C=[[1.0]])
    >>> opts = SynthesisOptions()
    >>> at_floor(1.002, 1.0, prob, opts), at_floor(1.003, 1.0, prob, opts)
    (True, False)
    """
    if floor is None:
        return False
    tol = options.refine_options.floor_tol
    return value <= floor + max(tol * floor, equal(0.0, problem))
