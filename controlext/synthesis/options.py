"""Synthesis options: every tunable of the engine, checked before any solve.

:class:`SynthesisOptions` holds what the factories' keyword arguments say
(``margin``, ``method``, ``solver``, ``seed``, ``refine``, ``executor``, …)
and :class:`RefineOptions` the refinement's budget policy.  Both are
frozen dataclasses validated completely in their constructors, so a typo
or a wrong type never costs a solve, and they travel with the call to any
executor's workers (nothing is read from module globals there).

Examples
--------
>>> from controlext.synthesis import SynthesisOptions, RefineOptions
>>> opts = SynthesisOptions(margin=1.05, refine_options={'polish': 3})
>>> opts.refine_options.polish, opts.margin
(3, 1.05)
>>> SynthesisOptions(refine_options={'seed': 3})
Traceback (most recent call last):
...
controlext.exceptions.ArgumentError: unrecognized refinement option(s): 'seed' (seed is a synthesis option: pass seed= to the factory)
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable
from dataclasses import MISSING, dataclass, field, fields, replace
from typing import Any, TypeVar

from .._checks import check_choice, check_number
from .placed import DRAWS
from .regions import check_decay
from ..exceptions import ArgumentError, ParameterError
from .criteria import Criteria

__all__ = ['SynthesisOptions', 'RefineOptions', 'METHODS']

#: convex stages a user may ask for
METHODS = ('auto', 'lmi', 'riccati', 'modal')


def _int(low):
    return dict(integer=True, low=low)


#: how each refinement field is checked: None = optional
_REFINE_CHECKS = {
    'random_starts': dict(integer=True, low=0, optional=True),
    'screen_iterations': _int(1),
    'polish': _int(1),
    'maxiter': dict(integer=True, low=1, optional=True),
    'restarts': dict(integer=True, low=0, optional=True),
    'delta': dict(low=0),
    'rho': dict(low=0, low_open=True, optional=True),
    'rho_scale': dict(low=0, low_open=True),
    'escalations': _int(0),
    'tikhonov': dict(low=0),
    'restart_every': _int(1),
    'race_keep': dict(low=1),
    'race_progress': dict(low=0),
    'race_reach': dict(low=0),
    'race_tie': dict(low=0),
    'floor_tol': dict(low=0),
    'push': _int(0),
    'costly_states': _int(0),
    'second_round': _int(0),
    'second_round_keep': dict(low=1),
    'peaks': _int(0),
    'placed_states': _int(0),
    'placed_starts': _int(0),
    'placed_draws': _int(0),
    'polish_tol': dict(low=0, low_open=True),
    'norm_tol': dict(low=0, low_open=True, high=1e-3),
}


@dataclass(frozen=True)
class RefineOptions:
    """The refinement's budget policy (:func:`~controlext.synthesis.refine.refine_gain`).

    Attributes
    ----------
    random_starts : int or None
        Seeded random perturbations of the given starts.  Default: 32 for
        up to 16 gain entries (at most 8 per entry), fewer for larger
        gains.
    screen_iterations : int
        BFGS steps every start gets before the best are polished.
    polish : int
        How many screened starts are polished (shrinks for large gains).
    maxiter, restarts : int or None
        Steps of a polishing segment and how many fresh-Hessian restarts
        follow while it improves (defaults depend on the gain's size).
    delta : float
        Margin kept inside the region during the search.
    rho : float or None
        Initial penalty weight; default ``rho_scale · γ₀`` over the
        slowest error rate of the first start.
    rho_scale : float
        That multiple: a few times the region constraint's multiplier
        ``dγ/dσ ~ γ/σ``, where the penalty's kink is mild.
    escalations : int
        How often a polishing run that ends outside the region may raise
        the weight tenfold (the penalty is exact only above the
        multiplier).
    tikhonov : float
        Relative weight of ``‖G‖²``, which keeps gains finite where the
        infimum of the norm needs unbounded ones.
    restart_every : int
        Polishing segments of gains with up to 64 entries are
        ``max(restart_every, 10 entries)`` steps (at most 600): progress
        near the norm's kinks comes in bursts after restarts.
    race_keep, race_progress, race_reach, race_tie : float
        After each segment a run more than ``race_keep`` behind the
        leader whose last segment gained less than ``race_progress``
        (relative) stops; so does a run whose remaining segments, at the
        pace of its last one (or, where its gains shrink, along their
        geometric series) times ``race_reach``, would not take it more
        than ``race_tie`` (relative) ahead of the leader.
    floor_tol : float
        Refinement stops once a point inside the region is within this
        (relative) of the unconstrained filter level, which no gain beats,
        and a convex or one-copy design that close to it is returned
        unrefined (copies cannot gain more).
    polish_tol : float
        A polishing run is converged when a segment gains less than this
        (relative); within a segment BFGS stops after 30 steps that
        together gained less than a hundredth of it.
    norm_tol : float
        Relative tolerance of the H∞ norms the search evaluates (slycot's
        ``ab13dd``); the result's norm is computed to 1e-10.
    push : int
        BFGS steps the feasibility push of a start outside the region
        may take before the start is dropped.
    costly_states, second_round, second_round_keep
        Gains of more than 64 entries on more than ``costly_states``
        error states get a second round of ``second_round`` screening
        steps; only starts within ``second_round_keep`` of the best after
        it (and the given starts) are polished.
    peaks : int
        Recent peak frequencies the line search's lower bound looks at.
    placed_states, placed_starts : int
        On error systems of at most ``placed_states`` states whose best
        design has three or more poles on the region's edge (or two,
        of more than two error poles), the best
        results whose pole map is regular (not the Luenberger-equivalent
        start, whose identical copies make it singular) are polished
        again with the poles as variables
        (:mod:`~controlext.synthesis.placed`), one per basin (each more
        than ``race_tie`` behind the last one polished), until
        ``placed_starts`` were polished or one reached the floor; the
        best of all is the result.
    placed_draws : int
        Where the best of that polish is a cluster of five or more poles
        held inside the region, this many more pole maps are drawn at its
        gain (how far a cluster splits depends on the map) and the best
        result kept: 0-8 % lower γ for 7-13 s on the nominal designs
        where they ran (quadruple tank pair, campaign seeds 5047, 5215,
        5216); 0 trades that for the time.
    """
    random_starts: int | None = None
    screen_iterations: int = 25
    polish: int = 3
    maxiter: int | None = None
    restarts: int | None = None
    delta: float = 1e-7
    rho: float | None = None
    rho_scale: float = 3.0
    escalations: int = 5
    tikhonov: float = 1e-5
    restart_every: int = 150
    race_keep: float = 1.05
    race_progress: float = 0.03
    race_reach: float = 1.0
    race_tie: float = 1e-3
    floor_tol: float = 2.5e-3
    polish_tol: float = 1e-7
    norm_tol: float = 1e-10
    push: int = 200
    costly_states: int = 32
    second_round: int = 60
    second_round_keep: float = 1.05
    peaks: int = 4
    placed_states: int = 12
    placed_starts: int = 3
    placed_draws: int = DRAWS

    def __post_init__(self):
        for name, rule in _REFINE_CHECKS.items():
            value = check_number(getattr(self, name),
                                 f"refine_options['{name}']", **rule)
            object.__setattr__(self, name, value)

    @classmethod
    def coerce(cls,
               value: RefineOptions | dict[str, Any] | None) -> RefineOptions:
        """``RefineOptions`` from None, a dict or a ``RefineOptions``."""
        if value is None:
            return cls()
        if isinstance(value, cls):
            return value
        if not isinstance(value, dict):
            raise ArgumentError("refine_options must be a dict or "
                                "RefineOptions; found "
                                f"{type(value).__name__}")
        known = {f.name for f in fields(cls)}
        unknown = [key for key in value if key not in known]
        if unknown:
            synth = {f.name for f in fields(SynthesisOptions)}
            hints = [f"{key} is a synthesis option: pass {key}= to the "
                     "factory" for key in unknown if key in synth]
            raise ArgumentError(
                "unrecognized refinement option(s): "
                + ', '.join(repr(k) for k in unknown)
                + (f" ({'; '.join(hints)})" if hints else
                   f"; expected any of {', '.join(sorted(known))}"))
        return cls(**value)


#: the largest margin: a certificate at ten times the convex optimum
#: certifies nothing a user would ask for
MAX_MARGIN = 10.0


@dataclass(frozen=True)
class SynthesisOptions:
    """How a design is synthesised; checked completely on construction.

    Attributes
    ----------
    margin : float
        The convex stage certifies its gain at ``margin · γ*`` (``>= 1``);
        a small margin keeps the gain moderate where ``γ*`` is not attained.
    method : {'auto', 'lmi', 'riccati', 'modal'}
        The convex stage (see :func:`~controlext.synthesis.convex_stage`).
    solver : str or None
        cvxpy solver (default clarabel); must be installed.
    solver_options : dict
        Options passed to the solver; for clarabel every key and value is
        checked against its settings.
    seed : int
        Seed of the refinement's random starts (results are reproducible).
    refine : bool
        Whether to refine where the convex stage is conservative (a pole
        region, or more than one copy).
    executor : concurrent.futures.Executor or None
        Runs the refinement's starts in parallel (anything with
        ``map(fn, iterable)`` returning results, or a Dask client, whose
        ``get_executor()`` is used); results do not depend on it.
    lmi_max_states : int
        The largest LMI ``method='auto'`` solves (full, or on the slow
        modes); above it the shifted Riccati design (the LMI costs about
        ``n^3.7``: 14–22 s at n = 40 on a 2-core machine).
    modal_guard : float
        Modes within this relative distance of the region count as slow
        for the modal stage.
    refine_options : RefineOptions
        The refinement's budget policy (a dict is converted and checked).
    max_gain : float, 'auto' or None
        A bound on the gain's spectral norm ``‖G‖₂`` (in the plant's
        units), held by refinement and verified on the result.  ``'auto'``
        bounds it at ``1e6`` times the plant's scale (the rate
        ``max(1, ‖A‖, the region's speed)`` over ``‖C‖``, on a unit-free
        realisation) and warns when that bound is reached; ``None`` sets
        no bound.
    objective : {'hinf', 'h2'}
        The norm from noise to estimation error that is minimised: the
        worst-case gain (H∞) or the RMS error under unit white noise (H2).
    max_hinf, max_h2 : float or None
        A bound on the norm that is not minimised (the mixed H2/H∞
        problem; :class:`~controlext.synthesis.criteria.Criteria`), held
        by every stage and verified on the result.
    settling_time, gain_tolerance : float or None
        Limits held by refinement and verified on the result: the latest
        2 % settling time of the averaged error, and the relative gain
        error under which the error poles must stay in the region
        (:mod:`~controlext.synthesis.limits`).
    """
    margin: float = 1.02
    method: str = 'auto'
    solver: str | None = None
    solver_options: dict = field(default_factory=dict)
    seed: int = 0
    refine: bool = True
    executor: object = None
    lmi_max_states: int = 40
    modal_guard: float = 0.05
    refine_options: RefineOptions = field(default_factory=RefineOptions)
    # the fields of Criteria, which checks them
    objective: str = 'hinf'
    max_hinf: float | None = None
    max_h2: float | None = None
    settling_time: float | None = None
    gain_tolerance: float | None = None
    max_gain: float | str | None = 'auto'

    def __post_init__(self):
        set_ = lambda name, value: object.__setattr__(self, name, value)
        set_('margin', check_number(self.margin, 'margin', low=1,
                                    high=MAX_MARGIN))
        set_('method', check_choice(self.method, 'method', METHODS))
        set_('seed', check_number(self.seed, 'seed', integer=True, low=0))
        if not isinstance(self.refine, (bool,)):
            raise ArgumentError(f"refine must be True or False; found "
                                f"{type(self.refine).__name__} "
                                f"{self.refine!r}")
        set_('lmi_max_states', check_number(
            self.lmi_max_states, 'lmi_max_states', integer=True, low=1))
        set_('modal_guard', check_number(self.modal_guard, 'modal_guard',
                                         low=0))
        set_('solver', _check_solver(self.solver))
        set_('solver_options', _check_solver_options(self.solver,
                                                     self.solver_options))
        set_('executor', _check_executor(self.executor))
        set_('refine_options', RefineOptions.coerce(self.refine_options))
        if self.max_gain is not None and self.max_gain != 'auto':
            if isinstance(self.max_gain, str):
                raise ParameterError(f"max_gain must be a positive number, "
                                     f"'auto' or None; found "
                                     f"{self.max_gain!r}")
            set_('max_gain', check_number(self.max_gain, 'max_gain',
                                          low=0, low_open=True))
        criteria = self.criteria
        for item in fields(Criteria):
            set_(item.name, getattr(criteria, item.name))

    @property
    def criteria(self) -> Criteria:
        """The norm minimised, the norm bounded and the limits."""
        return Criteria(**{item.name: getattr(self, item.name)
                           for item in fields(Criteria)})

    def replace(self, **changes: Any) -> SynthesisOptions:
        """A copy with some fields changed (checked again)."""
        return replace(self, **changes)

    @classmethod
    def from_keywords(cls, options: SynthesisOptions | None = None,
                      **keywords: Any) -> SynthesisOptions:
        """The options of a factory call: ``options`` (a
        ``SynthesisOptions``, default all defaults) with every keyword that
        differs from its default applied on top.

        Examples
        --------
        >>> from controlext.synthesis import SynthesisOptions
        >>> base = SynthesisOptions(lmi_max_states=10)
        >>> opts = SynthesisOptions.from_keywords(base, margin=1.1, seed=0)
        >>> opts.lmi_max_states, opts.margin
        (10, 1.1)
        """
        if options is None:
            options = cls()
        elif not isinstance(options, cls):
            raise ArgumentError("options must be a SynthesisOptions; found "
                                f"{type(options).__name__}")
        defaults = {f.name: f.default for f in fields(cls)}
        # None means "not given" only where the field allows it (its
        # default is None or built by a factory from None): method=None or
        # margin=None is a mistake, refused by the checks
        optional = {f.name for f in fields(cls)
                    if f.default is None or f.default is MISSING}
        changes = {key: value for key, value in keywords.items()
                   if not ((value is None and key in optional) or
                           value is defaults[key] or
                           (isinstance(value, (int, float, str)) and
                            not isinstance(value, bool) and
                            type(value) is type(defaults[key]) and
                            value == defaults[key]))}
        return options.replace(**changes) if changes else options

    @property
    def solver_name(self) -> str:
        """The cvxpy solver that will run."""
        return self.solver or 'CLARABEL'

    def __getstate__(self):
        # an executor does not travel to the workers it feeds
        state = dict(self.__dict__)
        state['executor'] = None
        return state

    def __setstate__(self, state):
        self.__dict__.update(state)


def _check_solver(solver):
    if solver is None:
        return None
    if not isinstance(solver, str):
        raise ArgumentError(f"solver must be a cvxpy solver name; found "
                            f"{type(solver).__name__}")
    import cvxpy as cp
    installed = cp.installed_solvers()
    name = solver.upper()
    if name not in installed:
        raise ParameterError(f"solver {solver!r} is not an installed cvxpy "
                             f"solver; installed: {', '.join(installed)}")
    return name


#: keywords cvxpy's ``Problem.solve`` takes beside the solver's own
_SOLVE_KEYWORDS = {'verbose', 'warm_start', 'ignore_dpp', 'canon_backend',
                   'enforce_dpp'}


def _check_solver_options(solver, options):
    if options is None:
        return {}
    if not isinstance(options, dict) or not all(isinstance(k, str)
                                                for k in options):
        raise ArgumentError("solver_options must be a dict with string "
                            f"keys; found {type(options).__name__}")
    options = dict(options)
    if (solver or 'CLARABEL') == 'CLARABEL':
        import clarabel
        settings = clarabel.DefaultSettings()
        for key, value in options.items():
            if key in _SOLVE_KEYWORDS:
                continue
            if not hasattr(settings, key):
                raise ArgumentError(
                    f"unrecognized solver_options key {key!r} for "
                    "clarabel (see clarabel.DefaultSettings())")
            try:
                setattr(settings, key, value)
            except (TypeError, ValueError) as exc:
                raise ArgumentError(
                    f"solver_options[{key!r}] has the wrong type for "
                    f"clarabel: found {type(value).__name__} "
                    f"{value!r}") from exc
    return options


def _check_executor(executor):
    if executor is None:
        return None
    if all(hasattr(executor, name) for name in
           ('get_executor', 'submit', 'gather')):
        executor = executor.get_executor()      # a Dask client
    if not callable(getattr(executor, 'map', None)):
        raise ArgumentError("executor must have a map(fn, iterable) method "
                            "(a concurrent.futures.Executor); found "
                            f"{type(executor).__name__}")
    return executor


F = TypeVar('F', bound=Callable[..., Any])


def synthesis_factory(factory: F) -> F:
    """Decorator of the factories: the synthesis keywords the factory's
    signature names (``method``, ``margin``, ``max_gain``, …) are checked
    and collected into its ``options`` argument, a
    :class:`SynthesisOptions` (the keywords override a given ``options``
    where they differ from their defaults), before the factory's body
    runs; ``decay`` is checked first, so that ``lqe``'s habit
    ``hinf_observer(plant, QN, RN)`` is told where the noise model goes.

    Examples
    --------
    >>> from controlext.synthesis.options import synthesis_factory
    >>> @synthesis_factory
    ... def factory(plant, decay=None, *, margin=1.02, options=None):
    ...     return options.margin
    >>> factory(None, margin=1.5)
    1.5
    """
    signature = inspect.signature(factory)
    names = [name for name in signature.parameters
             if name in {f.name for f in fields(SynthesisOptions)}]

    @functools.wraps(factory)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        bound = signature.bind(*args, **kwargs)
        bound.apply_defaults()
        given = bound.arguments
        if 'decay' in given:
            check_decay(given['decay'])
        given['options'] = SynthesisOptions.from_keywords(
            given.get('options'), **{name: given[name] for name in names})
        return factory(*bound.args, **bound.kwargs)
    return wrapper  # type: ignore[return-value]
