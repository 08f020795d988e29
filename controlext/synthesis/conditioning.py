"""How well conditioned a design is: the default gain bound and the
warnings of a design the user should not trust to its last digits.

A design is verified on its error system, but its estimator runs in
floating point: a gain far beyond the plant's scale amplifies rounding
and unmodelled noise, an error that grows by many orders of magnitude
before it decays is reproduced only to that many digits fewer, and a
design whose decay rate is lost to gain errors of 1e-6 cannot be
printed, stored or implemented as designed.  :func:`gain_bound` builds
the constraint that keeps the gain within ``EXTREME`` times the plant's
scale by default (``max_gain='auto'``); the ``warn_if_*`` functions say,
with a :class:`~controlext.exceptions.GainWarning` at the user's call,
when a returned design is held at that bound or is ill-conditioned
anyway.  The scales are measured on the unit-free realisation of
:meth:`~controlext.synthesis.ObserverProblem.state_scaling`, so they do
not depend on the units of the states.

Examples
--------
>>> import numpy as np
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.conditioning import gain_bound, EXTREME
>>> prob = ObserverProblem(A=[[0.0, 1.0], [0.0, 0.0]], C=[[2.0, 0.0]])
>>> bound = gain_bound(prob, np.ones(2), 'auto')
>>> bool(bound.level == EXTREME * 1.0 / 2.0), bound.weights.tolist()
(True, [1.0, 1.0])
>>> bound.holds(np.array([[3e5], [4e5]]))      # ‖G‖₂ = 5e5 = κ
True
"""

from dataclasses import dataclass

import numpy as np

from .._checks import sample_step
from .._warn import warn
from ..exceptions import GainWarning

__all__ = ['EXTREME', 'FRAGILE', 'NEGLIGIBLE', 'SLOW', 'FAST', 'GainBound',
           'gain_bound', 'warn_if_held', 'warn_if_extreme',
           'warn_if_degenerate', 'warn_if_fragile']

#: how far beyond the plant's scale a gain or an error pole may go
#: before the user is told
EXTREME = 1e6

#: the share of its decay rate a design may lose to relative gain errors
#: of 1e-6 before the user is told
FRAGILE = 1 / 3

#: a gain below this share of the plant's scale is taken for none at all
NEGLIGIBLE = 1e-6

#: an error decaying at less than this share of the plant's rate lingers
#: a hundred and more of the plant's time constants: no decay to speak of
SLOW = 1e-2

#: error poles this many times faster than both the region's speed and
#: the plant's own modes are far beyond what the region asks (observers
#: are commonly made 2-10 times faster than the loop they serve, and a
#: hundredfold on purpose: this is well past both)
FAST = 500.0

_ADVICE = ("A looser region, or max_gain=, gives a better conditioned "
           "design")


@dataclass(frozen=True)
class GainBound:
    """The constraint ``‖diag(weights) G‖₂ <= level`` on a gain ``G``.

    Attributes
    ----------
    level : float
        The bound ``κ``.
    weights : ndarray
        One weight per gain row (they undo a state scaling).
    """
    level: float
    weights: np.ndarray

    @classmethod
    def of(cls, bound):
        """``bound`` as a :class:`GainBound`: None stays None, a pair
        ``(κ, weights)`` is read as one."""
        if bound is None or isinstance(bound, cls):
            return bound
        level, weights = bound
        return cls(float(level), np.asarray(weights, dtype=float))

    def norm(self, G):
        """``‖diag(weights) G‖₂``."""
        return float(np.linalg.norm(self.weights[:, None] * G, 2))

    def meets(self, norm):
        """Does a gain of bounded norm ``norm`` meet the bound (to the
        verification's rounding)?"""
        return bool(norm <= self.level * (1 + 1e-6))

    def holds(self, G):
        """Does ``G`` meet the bound?"""
        return self.meets(self.norm(G))

    def rows(self, count):
        """The bound on the gain of the first ``count`` rows (a problem
        of fewer copies)."""
        return GainBound(self.level, self.weights[:count])

    def loosened(self, factor):
        """The bound ``factor`` times looser."""
        return GainBound(factor * self.level, self.weights)

    def key(self):
        """A hashable key of the bound (the memo's)."""
        return float(self.level), np.asarray(self.weights).tobytes()


def gain_bound(scaled, d, max_gain, region=None):
    """The :class:`GainBound` on gains of the scaled problem (None
    without a bound): a number bounds the gain in the plant's units (the
    weights undo the scaling ``d``), ``'auto'`` at ``EXTREME`` times the
    plant's scale on the unit-free realisation (see
    :func:`warn_if_extreme`)."""
    if max_gain is None:
        return None
    if max_gain == 'auto':
        return GainBound(EXTREME * _scales(scaled, region)[1],
                         np.ones(scaled.gain_shape[0]))
    return GainBound(float(max_gain), np.kron(np.ones(scaled.copies), d))


def _scales(problem, region):
    """The plant's scale: the rate ``max(1, ‖A‖, the region's least
    speed)`` and the gain ``rate / ‖C‖``."""
    rate = problem.rate
    if region is not None and not problem.dt:
        rate = max(rate, -region.stable_interval()[1])
    return rate, rate / max(np.linalg.norm(problem.C, 2), 1e-300)


def warn_if_held(bound, G, report, max_gain):
    """Record the gain bound in ``report.stats['max_gain']`` and warn when
    the default bound (``max_gain='auto'``) holds the design: a design of
    smaller γ exists, with a larger gain."""
    if bound is None:
        return
    norm = bound.norm(G)
    report.stats['max_gain'] = dict(bound=bound.level, norm=norm)
    if max_gain == 'auto' and 0.999 * bound.level <= norm and \
            bound.meets(norm):
        # (above the bound only with refine=False, which said so)
        warn(f"the gain is held at the default bound max_gain='auto' "
             f"(1e6 times the plant's scale; γ = {report.hinf:.6g}): a "
             "design of smaller γ needs a larger gain, which amplifies "
             "rounding and unmodelled noise; pass max_gain=None (or a "
             "number) to lift the bound", GainWarning)


def warn_if_extreme(problem, G, report, region=None) -> bool:
    """Warn when the gain or the error poles of a design exceed
    ``EXTREME`` times the plant's scale, measured on the unit-free
    realisation: the rate ``max(1, ‖A‖, the region's least speed)`` for
    the poles, that rate over ``‖C‖`` for the gain.  Returns whether it
    warned."""
    rate, scale = _scales(problem, region)
    gain = np.linalg.norm(G, 2) / scale
    fastest = float(np.max(np.abs(report.poles))) / rate \
        if not problem.dt and report.poles.size else 0.0
    if not (gain > EXTREME or fastest > EXTREME):
        return False
    # (a discrete design's poles lie in the unit disk: no rate to say)
    poles = '' if problem.dt else \
        f" and its fastest error pole {fastest:.3g} times"
    warn(f"the design's gain is {gain:.3g} times the plant's scale"
         f"{poles} (γ = {report.hinf:.6g}); such a gain amplifies "
         "rounding and unmodelled noise.  refine=False returns the "
         "convex design, whose gain is conditioned (its γ within "
         "margin= of the convex optimum; margin=1.1 gives a smaller "
         "gain still)", GainWarning)
    return True


def warn_if_degenerate(problem, G, report, region=None):
    """Warn when a verified design is degenerate: its gain is all but
    zero (the observer ignores its sensors), its error all but does not
    decay, or its error poles are far faster than the region asks; each
    warning says what to change.  Measured on the unit-free realisation,
    like :func:`warn_if_extreme` (which, where it warns, says enough: the
    pipeline then does not call this)."""
    rate, scale = _scales(problem, region)
    gain = np.linalg.norm(G, 2) / scale
    if gain < NEGLIGIBLE:
        warn(f"the design's gain is {gain:.3g} times the plant's scale: the "
             "observer all but ignores its measurements (with measurement "
             "noise only, a plant that already meets the region is best "
             "left unobserved).  Give process noise Bw= (how disturbances "
             "enter the plant), or a decay= faster than the plant's own, "
             "for an observer that uses its sensors", GainWarning)
        return
    # the plant's own speed: its fastest mode (its scale where every mode
    # is at 0, as in a chain of integrators)
    modes = float(np.max(np.abs(np.linalg.eigvals(problem.A)))) \
        if problem.n else 0.0
    if problem.dt:
        speed = report.decay * sample_step(problem.dt)
    else:
        speed = report.decay / (modes if modes > 1e-9 * rate else rate)
    if region is None and speed < SLOW:
        warn(f"the design's error decays at the rate {report.decay:.3g}, "
             f"{speed:.3g} of the plant's scale: without a region the "
             "optimum leaves a mode all but where it was, and an initial "
             "error lingers for about 1/decay.  Ask for decay= (the rate "
             "you need)", GainWarning)
        return
    if region is None or problem.dt or not report.poles.size:
        return
    asked = max(-region.stable_interval()[1], modes)
    fastest = float(np.max(np.abs(report.poles)))
    if asked > 0 and fastest > FAST * asked:
        warn(f"the design's fastest error pole, {fastest:.3g}, is "
             f"{fastest / asked:.3g} times faster than the region and the "
             f"plant's modes ask (gain {np.linalg.norm(G, 2):.3g}): the "
             "last bits of γ are bought with a large gain, which amplifies "
             "unmodelled noise.  max_gain= bounds the gain (at some γ), and "
             "process noise Bw= weighs what the sensors cannot see",
             GainWarning)


def warn_if_fragile(report):
    """Warn when the design's averaged error from a unit initial error
    grows beyond ``EXTREME`` before it decays, or else when relative gain
    errors of 1e-6 cost it more than ``FRAGILE`` of its decay rate (from
    ``report.tradeoff``)."""
    trade = report.tradeoff
    if trade.peak > EXTREME:
        # an initial error (or a rounding error) grows this much before it
        # decays: the estimator reproduces its error system only to that
        # many digits fewer; inf: its simulation overflowed
        size = f"to {trade.peak:.3g}" if np.isfinite(trade.peak) else \
            "beyond the range of double precision"
        warn(f"the averaged error from a unit initial error grows {size} "
             f"before it decays (γ = {report.hinf:.6g}): the estimator "
             f"amplifies its own rounding as much.  {_ADVICE}", GainWarning)
        return
    lost = trade.sensitivity.get(1e-6, 0.0)
    if lost > FRAGILE * trade.decay:
        # relative gain errors of 1e-6 (a gain printed to 7 digits) cost
        # more than a third of the decay: the design is that fragile, and
        # its estimator parts from its error system by rounding
        warn(f"relative gain errors of 1e-6 cost this design {lost:.3g} of "
             f"its decay rate {trade.decay:.3g} (γ = {report.hinf:.6g}): it "
             "is fragile, and its estimator amplifies its own rounding.  "
             f"{_ADVICE}", GainWarning)
