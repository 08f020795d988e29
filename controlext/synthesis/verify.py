"""Design reports and the verification every returned design passes.

A design is never trusted: after synthesis the true H∞ norm of the
returned error system is computed (slycot ``ab13dd`` with a fallback), its
poles are checked against the requested region, and the certified bound
must not be below the true norm beyond the solver's tolerance.  A design
that fails is a :class:`~controlext.exceptions.VerificationError`.

Examples
--------
>>> import controlext as cx
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.verify import verify_design
>>> prob = ObserverProblem(A=[[-0.5]], C=[[1.0]])
>>> rep = verify_design(prob, [[2.0]], region=cx.HalfPlane(2.5))
>>> round(rep.hinf, 4), round(rep.decay, 4)
(0.8, 2.5)
"""

from __future__ import annotations

from dataclasses import dataclass, field, asdict, replace
from typing import TYPE_CHECKING, Any

import numpy as np
import control as ct

from .._warn import warn
from ..exceptions import VerificationError
from ..norms import hinfnorm_quiet, hinfnorm_upper
from .._text import table_row
from .criteria import NAMES, Criteria, h2_norm
from .limits import limits_of
from .rates import REGION_TOL, STABILITY_TOL, decay_rate
from .records import DesignStats

if TYPE_CHECKING:
    from .regions import Region
    from .tradeoff import Tradeoff

__all__ = ['DesignReport', 'ModelReport', 'verify_design', 'error_poles']

#: relative tolerance between a certified bound and the true norm
BOUND_RTOL = 1e-5
#: absolute tolerance, for bounds near zero
BOUND_ATOL = 1e-5
#: relative tolerance of a norm bound (max_hinf=, max_h2=)
NORM_RTOL = 1e-6


@dataclass
class ModelReport:
    """The design on one plant model of a multi-model design.

    Attributes
    ----------
    hinf : float
        True H∞ norm of the error system on this model.
    h2 : float or None
        Its H2 norm, where the criteria involve it.
    decay : float
        Its rate of convergence.
    poles : ndarray
        Its error poles.
    peak_frequency : float
        Frequency of its peak gain.
    hinf_rounding : float
        The rounding bound included in ``hinf`` (see
        :attr:`DesignReport.hinf_rounding`).
    """
    hinf: float
    h2: float | None
    decay: float
    poles: np.ndarray
    peak_frequency: float
    hinf_rounding: float = 0.0


@dataclass(repr=False)
class DesignReport:
    """What a design is and how it was obtained.

    Attributes
    ----------
    method : str
        ``'given'``, ``'placement'``, ``'riccati'``, ``'lmi'`` or
        ``'lmi+refine'``.
    hinf : float
        True H∞ norm of the error system (``inf`` if unstable).
    h2 : float or None
        Its H2 norm (the RMS error under unit white noise), computed where
        the criteria involve it.
    criteria : Criteria or None
        What the design minimised and bounded (None: the H∞ norm).
    hinf_rounding : float
        The rounding bound added to ``hinf`` where double precision cannot
        evaluate the error system's gain to its eighth digit (so that
        ``hinf`` is never below the true norm); 0 elsewhere.
    peak_frequency : float
        Frequency (rad/s) of the peak gain.
    decay : float
        Rate of convergence ``-max Re λ`` (continuous) or ``-ln max|λ|/dt``
        (discrete) of the error dynamics.
    poles : ndarray
        Poles of the error system.
    region : Region or None
        The requested pole region.
    stage : str or None
        Which stage produced the gain: ``'lmi'``, ``'riccati'``,
        ``'refined'`` or ``'luenberger'`` (the Luenberger-equivalent start
        of a coupled design).
    gamma_convex : float or None
        The level the convex problem (stage 1) reached, when one was solved:
        a bound for the convex stage's own gain, not the H∞ norm of the
        returned (possibly refined) design — that is ``hinf``.
        (``gamma_opt`` is a deprecated alias.)
    gamma_bound : float or None
        Certified bound on the H∞ norm of the convex stage's gain.
    solver, status : str or None
        Solver used and its final status.
    time : float
        Wall-clock time of the design, in seconds.
    stats : DesignStats
        How the design was made: solver statistics, the refinement, the
        limits' ratios (:class:`~controlext.synthesis.records.DesignStats`,
        a typed record that reads as a mapping of what was recorded; a
        mapping given here becomes one).
    tradeoff : Tradeoff or None
        What the design trades besides γ (floor, H2 norm, transient, gain
        norm, decay sensitivity; :mod:`controlext.synthesis.tradeoff`):
        measured on every design a factory returns.
    models : list of ModelReport or None
        A design for several plant models: each model's numbers, the
        nominal first.  ``hinf``, ``h2`` and ``decay`` are then the worst
        case over the models and ``poles`` those of every model.
    polytope : float or None
        A design for several models whose gain has a common Lyapunov
        certificate: the certified bound of its norm on every plant in the
        convex hull of the models (their matrices' convex combinations),
        each with its poles in the region; None where no such
        certificate was found.
    """
    method: str
    hinf: float
    peak_frequency: float
    decay: float
    poles: np.ndarray
    region: Region | None = None
    stage: str | None = None
    gamma_convex: float | None = None
    gamma_bound: float | None = None
    solver: str | None = None
    status: str | None = None
    time: float = 0.0
    stats: DesignStats = field(default_factory=DesignStats)
    tradeoff: Tradeoff | None = None
    h2: float | None = None
    criteria: Criteria | None = None
    hinf_rounding: float = 0.0
    models: list[ModelReport] | None = None
    polytope: float | None = None

    def __setattr__(self, name, value):
        if name == 'stats' and not isinstance(value, DesignStats):
            value = DesignStats.of(value)
        super().__setattr__(name, value)

    @property
    def gamma_opt(self) -> float | None:
        """Deprecated alias of :attr:`gamma_convex`."""
        warn("DesignReport.gamma_opt is deprecated: it is the convex stage's "
             "level, now named gamma_convex (the design's H∞ norm is hinf)",
             DeprecationWarning)
        return self.gamma_convex

    @property
    def stationary(self) -> bool | None:
        """Did refinement's end point pass the gradient-sampling
        stationarity test (:mod:`~controlext.synthesis.stationary`)?
        None where the design was not refined."""
        test = self._stationarity()
        return None if test is None else bool(test.passed)

    def _stationarity(self):
        """The stationarity test of refinement's end point, or None."""
        refine = self.stats.refine
        return None if refine is None else refine.stationary

    def as_dict(self) -> dict[str, Any]:
        """The report as a plain dictionary."""
        return asdict(self)

    def __repr__(self):
        bound = 'none' if self.gamma_bound is None else \
            f'{self.gamma_bound:.6g}'
        return (f"DesignReport(hinf={self.hinf:.6g}, decay={self.decay:.6g}, "
                f"stage={self.stage!r}, method={self.method!r}, "
                f"convex bound={bound}, time={self.time:.3g} s)")

    def __str__(self):
        peak = (f"  (peak at ω = {self.peak_frequency:.4g} rad/s)"
                if np.isfinite(self.peak_frequency) else "")
        lines = [table_row('H∞ norm γ, noise → error',
                           f"{self.hinf:.6g}{peak}")]
        rounding = self.hinf_rounding
        if rounding:
            lines.append(table_row(
                '', f"(an upper bound: double precision evaluates the gain "
                f"only to ±{rounding:.3g})"))
        if self.h2 is not None:
            lines.append(table_row('H2 norm (white noise RMS)',
                                   f"{self.h2:.6g}"))
        lines.append(table_row('decay rate', f"{self.decay:.6g}" + (
            f"  (asked: {self.region})" if self.region is not None else "")))
        if self.gamma_bound is not None:
            lines.append(table_row(
                'convex stage certifies', f"γ ≤ {self.gamma_bound:.6g}"
                + (f"  (its optimum {self.gamma_convex:.6g})"
                   if self.gamma_convex is not None and
                   np.isfinite(self.gamma_convex) else "")))
        if self.criteria is not None and (not self.criteria.default or
                                          self.criteria.limits):
            lines.append(table_row('criteria', f"{self.criteria}"))
        lines.append(table_row('how the gain was found',
                               f"{origin(self.stage, self.method)} "
                               f"({self.time:.3g} s)"))
        lines += self._tolerance_text()
        test = self._stationarity()
        if test is not None:
            lines.append(table_row(
                'refinement ended', "at a stationary point" if test.passed
                else "short of a stationary point" +
                f"  (gradient sampling: {test.measure:.2g} relative "
                "decrease left)"))
        if self.models:
            lines += self._models_text()
        return '\n'.join(lines)

    def _tolerance_text(self):
        """What the gain tolerance cost, where the nominal optimum missed
        it (``stats['nominal']``)."""
        nominal = self.stats.get('nominal')
        criteria = self.criteria or Criteria()
        if nominal is None or not nominal > 0:
            return []
        value = criteria.value(self)
        name = 'γ' if criteria.objective == 'hinf' else \
            NAMES[criteria.objective]
        if value < nominal:
            # the road found a design the nominal search missed (a grown
            # design of fewer copies, refined under the tolerance)
            text = (f"nothing: this design's {name} is "
                    f"{100 * (1 - value / nominal):.3g} % below the nominal "
                    f"search's {nominal:.6g}, which misses the tolerance")
        else:
            text = (f"{100 * (value / nominal - 1):+.3g} % in {name} over "
                    f"the nominal optimum's {nominal:.6g}, which misses it")
        return [table_row('gain tolerance costs', text +
                          " (gain_tolerance=0 returns that design)")]

    def _models_text(self):
        """The table of a multi-model design: one row per model."""
        h2 = any(model.h2 is not None for model in self.models)
        head = f"{'model':>13} {'H∞ norm γ':>12} " + \
            (f"{'H2 norm':>12} " if h2 else "") + f"{'decay':>12}"
        rows = [f"{len(self.models)} plant models, one gain "
                "(worst case above):", head]
        for k, model in enumerate(self.models, start=1):
            label = f"{k}" + (" (nominal)" if k == 1 else "")
            rows.append(f"{label:>13} {model.hinf:>12.6g} " + (
                f"{model.h2:>12.6g} " if h2 and model.h2 is not None else
                ("" if not h2 else f"{'—':>12} ")) + f"{model.decay:>12.6g}")
        if self.polytope is not None:
            rows.append(table_row(
                'between the models', f"γ ≤ {self.polytope:.6g} and the "
                "region on every plant of their convex hull (one Lyapunov "
                "matrix certifies the gain on all)"))
        else:
            rows.append(table_row(
                'between the models', "not certified: check a denser set "
                "of models (controlext.check_models)"))
        return rows


#: the convex routes in words
ROUTES = {'lmi': 'the LMI design',
          'modal lmi': 'the LMI design on the slow modes',
          'riccati': 'the Riccati filter',
          'shifted riccati': 'the Riccati filter of the shifted plant',
          'kalman': 'the Kalman filter', 'placement': 'pole placement',
          'given': 'given'}


def origin(stage, method) -> str:
    """How a gain was found, in words, from the report's ``stage`` and
    ``method`` (for example ``'refined'`` and ``'embedded lmi+refine'``).

    Examples
    --------
    >>> from controlext.synthesis.verify import origin
    >>> origin('refined', 'embedded lmi+refine')
    'refined on the true norm, from the one-copy LMI design in every copy'
    >>> origin('riccati', 'riccati')
    'the Riccati filter'
    """
    method = str(method or 'given')
    base = method.split('+')[0]
    embedded = base.startswith('embedded ')
    base = base.replace('embedded ', '')
    route = ROUTES.get(base, base)
    if embedded:
        route = f"the one-copy {route.replace('the ', '', 1)} in every copy"
    if stage == 'refined':
        return f"refined on the true norm, from {route}"
    if method.endswith('+headroom'):
        return f"{route} (at the floor: nothing to refine)"
    if '+refine' in method and stage not in (None, base):
        return f"{route}, with the {stage} design as a start"
    return route


def error_poles(problem, A, units=None):
    """Eigenvalues of an error matrix ``A`` of ``problem``, computed in
    whichever of two similar realisations has the smaller norm: the given
    units or, when given, ``units`` (a diagonal state scaling per plant
    state, the units a gain was designed in).  Rounding in the
    eigenvalue solver is of the order of ``eps ‖A‖``: in badly scaled
    units it can split a pole cluster on the region's edge past the edge,
    where the same matrix in balanced units shows it inside.

    Examples
    --------
    >>> import numpy as np
    >>> from controlext.synthesis import ObserverProblem
    >>> prob = ObserverProblem([[-1.0, 1e6], [0.0, -2.0]], [[1.0, 0.0]])
    >>> lam = error_poles(prob, prob.Ae, units=[1.0, 1e-6])
    >>> np.sort(lam.real).tolist()
    [-2.0, -1.0]
    """
    A = np.asarray(A, dtype=float)
    if not A.size:
        return np.zeros(0)
    if units is not None:
        d = np.kron(np.ones(problem.copies), np.asarray(units, float))
        balanced = A / d[:, None] * d[None, :]
        if np.linalg.norm(balanced) < np.linalg.norm(A):
            A = balanced
    return np.linalg.eigvals(A)


def verify_design(problem, G, region=None, gamma_bound=None, method='given',
                  check=True, convex=None, criteria=None, units=None,
                  **info):
    """Compute the report of gain ``G`` on ``problem`` and check it.

    On a problem of several plant models (``problem.members``) every
    model is verified; the report holds the worst case and each model's
    numbers (:attr:`DesignReport.models`), and a refusal names the model.

    Raises :class:`VerificationError` (when ``check``) if the error system
    is unstable, a pole is outside ``region``, the true value of the
    minimised norm (``criteria``, default H∞) exceeds ``gamma_bound``
    beyond :data:`BOUND_RTOL`, or a bounded norm exceeds its bound beyond
    :data:`NORM_RTOL`, or a limit (settling time, gain tolerance;
    :mod:`~controlext.synthesis.limits`) is missed beyond it; the limits'
    ratios go to ``stats['limits']``.  ``convex`` (a
    :class:`~controlext.synthesis.convex.ConvexResult`) fills in the
    method, bound, γ*, solver, status and statistics of the convex stage.
    ``units`` (a diagonal state scaling, per plant state) are the units a
    gain was designed in: a gain tolerance is then also certified in
    them (:meth:`~controlext.synthesis.limits.GainTolerance.verify`), and
    the poles are read in them where that realisation is the better
    scaled (:func:`error_poles`).
    """
    if convex is not None:
        if G is convex.G and gamma_bound is None:
            gamma_bound = convex.gamma_bound
        method = convex.method if method == 'given' else method
        info = dict(dict(stage=convex.stage, gamma_convex=convex.gamma_convex,
                         solver=convex.solver, status=convex.status,
                         stats=convex.stats), **info)
    members = problem.members
    if len(members) > 1:
        reports = []
        for k, member in enumerate(members, start=1):
            try:
                reports.append(verify_design(
                    member, G, region, gamma_bound, method, check, convex,
                    criteria, units, **info))
            except VerificationError as exc:
                raise VerificationError(
                    f"on model {k} of {len(members)}: {exc}") from None
        return worst_case(reports)
    sys = ct.ss(*problem.error_system(G), problem.dt)
    poles = error_poles(problem, sys.A, units)
    gamma, wpeak = hinfnorm_quiet(sys)
    # where double precision cannot evaluate the gain to its eighth digit
    # (a far from normal error system) the norm is stated as the upper
    # bound of the computed peak, never below the true one
    gamma, rounding = hinfnorm_upper(sys, gamma, wpeak, 0.0)
    h2 = None
    if criteria is not None and not criteria.default:
        h2 = h2_norm(sys.A, sys.B, sys.C, problem.dt)
    report = DesignReport(method=method, hinf=gamma, peak_frequency=wpeak,
                          decay=decay_rate(poles, problem.dt), poles=poles,
                          region=region, gamma_bound=gamma_bound, h2=h2,
                          criteria=criteria, hinf_rounding=rounding, **info)
    criteria = Criteria() if criteria is None else criteria
    if not check:
        return report
    scale = max(1.0, float(np.max(np.abs(poles))) if poles.size else 1.0)
    # distance of the slowest pole from the stability boundary (relative
    # to the poles' size in continuous time)
    if not poles.size:
        slowest = 1.0
    elif problem.dt:
        slowest = 1 - float(np.max(np.abs(poles)))
    else:
        slowest = -float(np.max(poles.real)) / scale
    if not np.isfinite(gamma) or slowest <= STABILITY_TOL:
        raise VerificationError(
            f"the {method} design is not stable"
            + (" beyond rounding" if np.isfinite(gamma) else "")
            + f": error poles {np.round(poles, 6).tolist()}")
    if region is not None:
        scale = max(1.0, float(np.max(np.abs(poles))) if poles.size else 1.0)
        worst = region.worst_margin(poles)
        if worst > REGION_TOL * scale:
            raise VerificationError(
                f"the {method} design has poles outside {region} (worst "
                f"margin {worst:.3g}); poles {np.round(poles, 6).tolist()}")
    value = criteria.value(report)
    if gamma_bound is not None and value > gamma_bound * (1 + BOUND_RTOL) \
            + BOUND_ATOL:
        raise VerificationError(
            f"the {method} design's true {NAMES[criteria.objective]} "
            f"{value:.6g} exceeds its certified bound {gamma_bound:.6g}")
    for name, bound in criteria.bounds:
        value = getattr(report, name)
        if value > bound * (1 + NORM_RTOL):
            raise VerificationError(
                f"the {method} design's {NAMES[name]} {value:.6g} exceeds "
                f"max_{name} = {bound:.6g}")
    ratios = {}
    for limit in limits_of(criteria, problem, region):
        ratios[limit.name] = ratio = limit.verify(problem, G, region,
                                                  units=units)
        if not ratio <= 1 + NORM_RTOL:
            raise VerificationError(f"the {method} design "
                                    f"{limit.explain(ratio)}")
    if ratios:
        report.stats = report.stats.replace(limits=ratios)
    return report



def worst_case(reports):
    """One report of a design on several models: the worst case of each
    number, every model's poles, and the models' own numbers."""
    worst = max(range(len(reports)), key=lambda k: reports[k].hinf)
    top = reports[worst]
    h2 = [rep.h2 for rep in reports]
    limits = {}
    for rep in reports:
        for name, ratio in (rep.stats.limits or {}).items():
            limits[name] = max(ratio, limits.get(name, ratio))
    out = replace(reports[0], hinf=top.hinf, peak_frequency=top.peak_frequency,
                  hinf_rounding=top.hinf_rounding,
                  h2=None if any(v is None for v in h2) else max(h2),
                  decay=min(rep.decay for rep in reports),
                  poles=np.concatenate([rep.poles for rep in reports]),
                  models=[ModelReport(hinf=rep.hinf, h2=rep.h2,
                                      decay=rep.decay, poles=rep.poles,
                                      peak_frequency=rep.peak_frequency,
                                      hinf_rounding=rep.hinf_rounding)
                          for rep in reports])
    if limits:
        out.stats = out.stats.replace(limits=limits)
    return out
