"""What a design trades: the numbers an engineer weighs besides γ.

:func:`tradeoff_of` measures, on a problem and a gain,

* ``hinf`` — the H∞ norm from noise to estimation error (the worst-case
  noise gain, what the synthesis minimises);
* ``floor`` — ``γ∞*``, the optimal H∞ filter level with no constraint
  (:mod:`controlext.synthesis.floor`): no observer can be below it;
* ``luenberger`` — γ of the best one-copy design in the same region, where
  it is known (a coupled design's own start);
* ``gain_norm`` — ``‖G‖₂``;
* ``h2`` — the H2 norm from noise to error: the RMS error under unit white
  noise (``control.norm(obs, 2)``);
* ``peak`` and ``settling_time`` — the averaged error from the worst unit
  initial error with every copy starting equal: the envelope
  ``‖Cz̄ e^{Ae t} (1_N ⊗ I)‖₂`` at its largest, and the last time it
  exceeds 2 % of its start;
* ``decay`` — the rate of convergence;
* ``sensitivity`` — how much decay rate the design loses, at worst over
  random relative perturbations of its gain entries of size 1e-6 and 1e-3
  (a nearly defective pole cluster at the region's edge loses much more
  than a well-conditioned one);
* ``digits`` — how many significant digits the gain's entries need so
  that the rounded gain still has its error poles in the region (to the
  verification's tolerance): a user who types the printed gains into a
  controller gets the promised decay when they are printed to this many
  (``str(obs)`` does).

Examples
--------
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.tradeoff import tradeoff_of
>>> prob = ObserverProblem([[-0.5]], [[1.0]])
>>> t = tradeoff_of(prob, [[2.0]])
>>> round(t.hinf, 4), round(t.settling_time, 3)       # ln(50) / 2.5
(0.8, 1.565)
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any

import control as ct
import numpy as np
import scipy.linalg as la

from .._typing import Array, ArrayLike
from ..norms import hinfnorm_quiet
from .criteria import h2_norm
from .rates import REGION_TOL, SETTLING_BAND, decay_rate
from .._text import table_row

if TYPE_CHECKING:
    from .problem import ObserverProblem
    from .regions import Region

__all__ = ['Tradeoff', 'tradeoff_of', 'h2_norm', 'transient',
           'decay_sensitivity', 'digits_needed', 'rounded_keeps']

#: relative gain perturbations the sensitivity is reported for
PERTURBATIONS = (1e-6, 1e-3)
#: exact steps per sample interval where a continuous transient is refined
SUB = 256


@dataclass(repr=False)
class Tradeoff:
    """The trade-off numbers of one design (see the module's text).

    Attributes
    ----------
    name : str
        The design's name.
    hinf, floor, luenberger : float
        γ, the floor γ∞* and the one-copy γ (None where not known).
    gain_norm, h2, peak, settling_time, decay : float
        ‖G‖₂, the H2 norm, the transient's peak and 2 % settling time, the
        decay rate.
    sensitivity : dict
        ``{relative gain error: decay lost}``.
    digits : int
        Significant digits the printed gain needs to keep its region.
    """
    name: str
    hinf: float
    floor: float | None
    luenberger: float | None
    gain_norm: float
    h2: float
    peak: float
    settling_time: float
    decay: float
    sensitivity: dict[float, float] = field(default_factory=dict)
    digits: int = 17

    def as_dict(self) -> dict[str, Any]:
        """The numbers as a plain dictionary."""
        return asdict(self)

    @property
    def headroom(self) -> float | None:
        """``hinf / floor − 1``: how far the design is above what any
        observer could reach (None where the floor is not known or 0)."""
        if self.floor is None or not self.floor > 0:
            return None
        return self.hinf / self.floor - 1.0

    def __repr__(self) -> str:
        name = f"{self.name!r}, " if self.name else ''
        return (f"Tradeoff({name}hinf={self.hinf:.6g}, "
                f"h2={self.h2:.6g}, settling_time={self.settling_time:.4g}, "
                f"gain_norm={self.gain_norm:.4g})")

    def __str__(self) -> str:
        def num(value):
            return 'not known' if value is None else f"{value:.6g}"
        if self.floor is None:
            floor = 'not known'
        elif self.floor == 0:
            floor = ("0  (without a region the noise need not reach the "
                     "error at all)")
        else:
            floor = (f"{self.floor:.6g}  (the least any observer reaches "
                     "without a region)")
        lost = ', '.join(f"{loss:.3g} at {eps:g}"
                         for eps, loss in self.sensitivity.items())
        rows = [('floor γ∞*', floor),
                ('one copy (Luenberger) γ', num(self.luenberger)),
                ('H2 norm (white noise RMS)', f"{self.h2:.6g}"),
                ('transient from e(0)', f"peak {self.peak:.4g}, 2 % "
                 f"settling {self.settling_time:.4g} s"),
                ('decay lost to gain errors', f"{lost} (relative error)"
                 if lost else 'not measured'),
                ('printed gain needs', f"{self.digits} significant digits "
                 "to keep its region")]
        return '\n'.join(table_row(label, value) for label, value in rows)


def transient(problem: ObserverProblem, G: ArrayLike, points: int = 800
              ) -> tuple[float, float]:
    """``(peak, settling_time)`` of the averaged error from the worst unit
    initial error, every copy starting from the same error."""
    Acl, _, Ccl, _ = problem.error_system(G)
    m, N, dt = problem.n, problem.copies, problem.dt
    X0 = np.kron(np.ones((N, 1)), np.eye(m))
    rate = decay_rate(la.eigvals(Acl), dt)
    start = la.svdvals(Ccl @ X0)[0]
    if not rate > 0:
        return float('inf'), float('inf')
    step = 1.0 if dt is True else float(dt)
    horizon = 8.0 / rate
    for _ in range(8):
        if dt:
            # at most 4 × points samples: a slowly decaying error is
            # sampled every `stride` steps (one step at a time, a nearly
            # marginal plant would ask for gigabytes)
            k = max(int(np.ceil(horizon / step)), 1)
            stride = max(1, int(np.ceil(k / (4 * points))))
            times = step * stride * np.arange(int(np.ceil(k / stride)) + 1)
            with np.errstate(over='ignore', invalid='ignore'):
                Phi = np.linalg.matrix_power(Acl, stride)
        else:
            times = np.linspace(0.0, horizon, points + 1)
            Phi = la.expm(Acl * times[1])
        if not np.all(np.isfinite(Phi)):
            # e^{Ae h} overflows: a transient beyond floating point
            return float('inf'), float('inf')
        states = np.empty((times.size,) + X0.shape)
        X = X0.copy()
        with np.errstate(over='ignore', invalid='ignore'):
            for i in range(times.size):
                states[i] = X
                X = Phi @ X
            Y = Ccl @ states
        if not np.all(np.isfinite(Y)):
            return float('inf'), float('inf')
        env = np.linalg.svd(Y, compute_uv=False)[:, 0]
        band = SETTLING_BAND * (start if start > 0 else float(np.max(env)))
        if env[-1] <= band and \
                float(np.max(env[-max(2, times.size // 8):])) <= band:
            break
        horizon *= 2
    # between two samples: every step in discrete time, SUB exact steps
    # in continuous time
    count = stride if dt else SUB
    fine_step = Acl if dt else la.expm(Acl * (times[1] - times[0]) / SUB)

    def between(i, intervals=1):
        """The envelope at every fine step from sample ``i`` over the
        next ``intervals`` intervals (in chunks: a long stride is not
        held in memory at once)."""
        X, vals, left = states[i], [env[i:i + 1]], count * intervals
        with np.errstate(over='ignore', invalid='ignore'):
            while left:
                fine = np.empty((min(left, 4096),) + X0.shape)
                for j in range(fine.shape[0]):
                    X = fine[j] = fine_step @ X
                vals.append(np.linalg.svd(Ccl @ fine, compute_uv=False)
                            [:, 0])
                left -= fine.shape[0]
        return np.concatenate(vals)

    # the peak: the largest sample, refined over the intervals on either
    # side (sampled only, the double integrator's pair read 1.0439 for
    # 1.0487)
    i = int(np.argmax(env))
    lo, hi = max(i - 1, 0), min(i + 1, times.size - 1)
    peak = float(env[i])
    if count > 1 and hi > lo:
        peak = float(max(peak, np.max(between(lo, hi - lo))))
    above = np.nonzero(env > band)[0]
    if above.size == 0:
        return peak, 0.0
    last = above[-1]
    if last + 1 >= times.size:
        return peak, float('inf')
    vals = between(last)
    inside = np.nonzero(vals <= band)[0]
    if dt:
        # the first step across the crossing's stride
        settle = times[last] + inside[0] * step if inside.size else \
            times[last + 1]
    else:
        # the envelope is continuous: linear interpolation between the
        # two sub-steps around the crossing
        h = (times[1] - times[0]) / SUB
        j = int(inside[0]) if inside.size else SUB
        prev, val = vals[j - 1], vals[j]
        settle = times[last] + h * (j - (band - val) / (prev - val)
                                    if prev > val else j)
    return peak, float(settle)


def decay_sensitivity(problem: ObserverProblem, G: ArrayLike,
                      eps: float, draws: int = 64, seed: int = 0) -> float:
    """The largest loss of decay rate over ``draws`` random relative
    perturbations ``G ∘ (1 + eps Δ)``, ``Δ`` uniform in ``[−1, 1]``
    (entry-wise, seeded)."""
    G = np.asarray(G, dtype=float)
    base = decay_rate(la.eigvals(problem.error_system(G)[0]), problem.dt)
    rng = np.random.default_rng(seed)
    worst = 0.0
    for _ in range(draws):
        Gp = G * (1 + eps * rng.uniform(-1, 1, size=G.shape))
        rate = decay_rate(la.eigvals(problem.error_system(Gp)[0]),
                          problem.dt)
        worst = max(worst, base - rate)
    return float(worst)


def rounded_keeps(problem: ObserverProblem, G: ArrayLike,
                  region: Region | None, digits: int) -> bool:
    """Do the entries of ``G`` rounded to ``digits`` significant digits
    keep the error poles in ``region`` (or stable), to the verification's
    tolerance?"""
    G = np.asarray(G, dtype=float)
    Gr = np.array([[float(f"{x:.{digits - 1}e}") for x in row]
                   for row in G]) if G.size else G
    poles = la.eigvals(problem.error_system(Gr)[0])
    if decay_rate(poles, problem.dt) <= 0:
        return False
    if region is None:
        return True
    scale = max(1.0, float(np.max(np.abs(poles))) if poles.size else 1.0)
    return bool(region.worst_margin(poles) <= REGION_TOL * scale)


def digits_needed(problem: ObserverProblem, G: ArrayLike,
                  region: Region | None = None) -> int:
    """The fewest significant digits ``d`` (3-17) such that the entries
    of ``G`` rounded to ``d`` *or more* digits keep the error poles in
    ``region`` (or stable), to the verification's tolerance.

    Every count from 17 down is tried and the count is the last one
    before the first that fails, so the answer is monotone: a gain
    rounded to fewer digits may land inside by luck, which does not make
    those digits enough.
    """
    G = np.asarray(G, dtype=float)
    needed = 17
    for digits in range(17, 2, -1):
        if not rounded_keeps(problem, G, region, digits):
            break
        needed = digits
    return needed


def tradeoff_of(problem: ObserverProblem, G: ArrayLike, name: str = '',
                *, floor: float | None = None,
                luenberger: float | None = None,
                region: Region | None = None,
                hinf: float | None = None) -> Tradeoff:
    """The :class:`Tradeoff` of gain ``G`` on ``problem`` (``floor``,
    ``luenberger`` and ``hinf`` as known to the caller — a one-copy design
    is its own one-copy design; ``region`` the design's).  Without
    ``hinf`` the H∞ norm is :func:`~controlext.hinfnorm`'s, as the
    design's verification computes it: ``ab13dd`` alone may miss the peak
    of a far from normal error system."""
    G = np.asarray(G, dtype=float)
    Acl, Bcl, Ccl, Dcl = problem.error_system(G)
    poles = la.eigvals(Acl)
    if hinf is None:
        hinf, _ = hinfnorm_quiet(ct.ss(Acl, Bcl, Ccl, Dcl, problem.dt))
    peak, settle = transient(problem, G)
    if luenberger is None and problem.copies == 1:
        luenberger = float(hinf)
    return Tradeoff(
        name=name, hinf=float(hinf), floor=floor, luenberger=luenberger,
        gain_norm=float(np.linalg.norm(G, 2)) if G.size else 0.0,
        h2=h2_norm(Acl, Bcl, Ccl, problem.dt), peak=peak,
        settling_time=settle, decay=float(decay_rate(poles, problem.dt)),
        sensitivity={eps: decay_sensitivity(problem, G, eps)
                     for eps in PERTURBATIONS},
        digits=digits_needed(problem, G, region))
