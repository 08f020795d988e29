"""The Luenberger observer: its object and its two factories.

:class:`LuenbergerObserver` is ``x̂' = A x̂ + B u + L (y − C x̂ − D u)``,
realised as its error system ``(A − L C, L Dw − Bw, Cz, 0)``.
:func:`luenberger_observer` places its poles; :func:`hinf_observer`
minimises its H∞ norm from noise to estimation error through the
synthesis engine (:mod:`controlext.synthesis`).

Examples
--------
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-1, 1], [-1, 0]], [[0], [1]], [[1, 2]], 0)
>>> obs = cx.hinf_observer(plant, decay=1.0)
>>> bool(obs.decay >= 1 - 1e-6), bool(obs.hinf < 0.2852)
(True, True)
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any
import time

import numpy as np

from ._checks import (as_matrix, check_system, format_mode,
                      unobservable_modes)
from ._warn import warn
from .exceptions import (ArgumentError, DimensionError, GainWarning,
                         ParameterError,
                         RegionError, VerificationError)
from .observers import Observer
from .synthesis import SynthesisOptions, plant_problem
from .synthesis.models import for_models
from .synthesis.options import synthesis_factory
from .synthesis.pipeline import design
from .synthesis.placement import place_gain, placement_error
from .synthesis.verify import verify_design
from ._typing import Array, ArrayLike, ExecutorLike, Names, Plant

if TYPE_CHECKING:
    from .synthesis import RefineOptions, Region
    from .synthesis.verify import DesignReport

__all__ = ['LuenbergerObserver', 'luenberger_observer', 'hinf_observer']


class LuenbergerObserver(Observer):
    """Luenberger observer ``x̂' = A x̂ + B u + L (y − C x̂ − D u)``.

    Its realisation is the error system ``(A − L C, L Dw − Bw, Cz, 0)``
    from noise ``w`` to ``Cz (x̂ − x)``.

    Parameters
    ----------
    plant : control.StateSpace
        The plant.
    L : array_like
        Observer gain, ``n × p``.
    Bw, Dw, Cz : array_like, optional
        Noise model: ``x' = A x + B u + Bw w``, ``y = C x + D u + Dw w``,
        estimated output ``Cz x``.  Defaults: ``0``, ``I_p``, ``I_n``
        (measurement noise, full-state estimate).
    report : DesignReport, optional
        The design report (computed, method ``'given'``, when omitted).
    name : str, optional
        System name.
    inputs, outputs, states : str or list of str, optional
        Signal names of the error system (python-control's system
        keywords; see :class:`~controlext.Observer`).

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-1, 1], [-1, 0]], [[0], [1]], [[1, 2]], 0)
    >>> obs = cx.LuenbergerObserver(plant, [[2], [5]])
    >>> float(round(ct.norm(obs, "inf"), 4)), round(obs.decay, 4)
    (0.4859, 1.0)
    """

    def __init__(self, plant: Plant, L: ArrayLike, Bw: ArrayLike | None = None,
                 Dw: ArrayLike | None = None, Cz: ArrayLike | None = None,
                 name: str | None = None, report: DesignReport | None = None,
                 *, inputs: Names = None, outputs: Names = None,
                 states: Names = None) -> None:
        problem = plant_problem(plant, Bw, Dw, Cz)
        L = as_matrix(L, 'L', (problem.n, problem.p))
        super().__init__(problem, L, report=report, name=name,
                         inputs=inputs, outputs=outputs, states=states)

    @property
    def L(self) -> Array:
        """The observer gain ``L`` (``n × p``)."""
        return self.G


def luenberger_observer(plant: Plant, poles: ArrayLike,
                        Bw: ArrayLike | None = None,
                        Dw: ArrayLike | None = None,
                        Cz: ArrayLike | None = None, name: str | None = None,
                        *, inputs: Names = None, outputs: Names = None,
                        states: Names = None) -> LuenbergerObserver:
    """Luenberger observer with error poles placed at ``poles``.

    Repeated poles are placed too (up to the multiplicity the number of
    independent sensors allows, as :func:`control.place_varga` does).

    Parameters
    ----------
    plant : control.StateSpace or sequence of control.StateSpace
        Observable plant, or several models of it (equal sizes, one
        timebase): the poles are placed on the first (nominal) one, and
        the report says where they land on each
        (:attr:`DesignReport.models`).
    poles : array_like
        ``n`` desired error poles (complex ones in conjugate pairs).
    Bw, Dw, Cz : array_like, optional
        Noise model (see :class:`LuenbergerObserver`).
    name : str, optional
        System name.
    inputs, outputs, states : str or list of str, optional
        Signal names of the error system (python-control's system
        keywords; see :class:`~controlext.Observer`).

    Returns
    -------
    LuenbergerObserver

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> obs = cx.luenberger_observer(plant, [-2.5])
    >>> float(round(obs.L[0, 0], 4)), round(obs.hinf, 4)
    (2.0, 0.8)
    """
    start = time.perf_counter()
    system = check_system(name, inputs, outputs, states)
    problem = for_models(plant, plant_problem, Bw=Bw, Dw=Dw, Cz=Cz)
    problem.error_signals(inputs, outputs, states)
    A, C, dt = problem.A, problem.C, problem.dt
    try:
        poles = np.array(poles, dtype=complex).ravel()
    except (TypeError, ValueError) as exc:
        raise ArgumentError("poles must be a sequence of numbers; found "
                            f"{type(poles).__name__}") from exc
    if poles.size != problem.n:
        raise DimensionError(f"poles has the wrong length; expected "
                             f"{problem.n} (one per state) instead of "
                             f"{poles.size}")
    if not np.all(np.isfinite(poles)):
        raise ParameterError(f"poles must be finite; found {poles.tolist()}")
    for lam in unobservable_modes(A, C):
        raise RegionError(
            f"poles cannot be placed freely: the mode at "
            f"{format_mode(lam, dt)} is unobservable from C")
    unstable = poles[np.abs(poles) >= 1] if dt else poles[poles.real >= 0]
    if unstable.size:
        where = 'inside the unit circle' if dt else \
            'in the open left half-plane'
        raise ParameterError(
            f"poles must lie {where} (error dynamics that do not decay "
            f"make no observer); found {np.round(unstable, 6).tolist()}")
    if np.any(np.abs(np.sort_complex(poles) -
                     np.sort_complex(poles.conj())) > 1e-12):
        raise ParameterError("complex poles must come in conjugate pairs; "
                             f"found {poles.tolist()}")
    L = place_gain(A, C, poles)
    placed, V = np.linalg.eig(A - L @ C)
    err = placement_error(placed, poles)
    scale = max(1.0, float(np.max(np.abs(poles))))
    # Bauer-Fike: rounding of size eps (‖A‖ + ‖L‖‖C‖) moves the poles by
    # up to κ(V) times that, whatever the placement algorithm
    kappa = float(np.linalg.cond(V)) if problem.n else 1.0
    reach = 10 * max(problem.n, 1) * np.finfo(float).eps * kappa * (
        np.linalg.norm(A, 2) + np.linalg.norm(L, 2) * np.linalg.norm(C, 2))
    tol = max(1e-6 * scale, reach)
    stable = bool(np.all(np.abs(placed) < 1)) if dt else \
        bool(np.all(placed.real < 0))
    if err > tol or not stable:
        raise VerificationError(
            f"placed poles {np.round(placed, 6).tolist()} miss the requested "
            f"{np.round(poles, 6).tolist()} by {err:.3g}, more than the "
            f"{tol:.3g} that rounding explains (eigenvector condition "
            f"number {kappa:.3g} of the placed error matrix)"
            + ("" if stable else " and are not stable") +
            "; poles spread farther apart, or more sensors, give a better "
            "conditioned placement")
    if err > 1e-6 * scale:
        warn(f"the placed poles miss the requested ones by {err:.3g}: the "
             f"placement is ill-conditioned (eigenvector condition number "
             f"{kappa:.3g}), so rounding alone moves its poles that far; "
             "poles spread farther apart, or more sensors, give a better "
             "conditioned design", GainWarning)
    report = verify_design(problem, L, method='placement', check=False,
                           time=time.perf_counter() - start)
    return LuenbergerObserver.from_problem(problem, L, report=report,
                                           **system)


@synthesis_factory
def hinf_observer(plant: Plant, decay: float | None = None,
                  Bw: ArrayLike | None = None, Dw: ArrayLike | None = None,
                  Cz: ArrayLike | None = None, *, region: Region | None = None,
                  method: str = 'auto', refine: bool = True,
                  margin: float = 1.02, solver: str | None = None,
                  solver_options: dict[str, Any] | None = None, seed: int = 0,
                  refine_options: RefineOptions | dict[str, Any] | None = None,
                  executor: ExecutorLike = None,
                  options: SynthesisOptions | None = None,
                  max_gain: float | str | None = 'auto',
                  objective: str = 'hinf', max_hinf: float | None = None,
                  max_h2: float | None = None,
                  settling_time: float | None = None,
                  gain_tolerance: float | None = None,
                  name: str | None = None, inputs: Names = None,
                  outputs: Names = None,
                  states: Names = None) -> LuenbergerObserver:
    """H∞-optimal Luenberger observer, optionally with a decay constraint.

    Minimises the H∞ norm from noise ``w`` to estimation error
    ``Cz (x̂ − x)`` over gains ``L`` (LMIs in Control's H∞-optimal
    observer; Theorem 3.12 of Li & Sanfelice, linearised).  Every option
    is checked before any solver runs.

    Parameters
    ----------
    plant : control.StateSpace or sequence of control.StateSpace
        Detectable plant, or several models of it (equal sizes, one
        timebase; the first is the nominal one): one gain is designed for
        all, the worst case over the models minimised, the region and
        every limit held on each (:attr:`Observer.models`).
    decay : float, optional
        Required rate of convergence ``σ > 0``: every error pole has
        ``Re s <= -σ``.  Shorthand for ``region=cx.HalfPlane(σ)``.
    Bw, Dw, Cz : array_like, optional
        Noise model (see :class:`LuenbergerObserver`); with several plant
        models, one for all or a sequence of one matrix per model.
    region : Region, optional
        Pole region for the error dynamics.
    method : {'auto', 'lmi', 'riccati', 'modal'}, optional
        ``'riccati'`` solves the filter Riccati equation (continuous time,
        all measurements noisy, no region or a decay half-plane — for
        ``Re s <= -σ`` the plant shifted by ``σ``, a certified but more
        conservative bound); ``'lmi'`` the two-stage LMI; ``'modal'`` that
        LMI on the modes outside or near the region only
        (:mod:`controlext.synthesis.modal`; exact for the gains acting on
        them when the noise does not reach the others).  ``'auto'`` takes
        the Riccati route without a region; with one, the modal LMI where
        it applies (within 0.1 % of the full LMI's γ on the benchmark
        plants, 10–40× faster), else the LMI up to 40 states (it costs
        about ``n^3.7``; ``lmi_max_states`` of
        :class:`~controlext.synthesis.SynthesisOptions`) and the shifted
        Riccati design above.  Refinement starts from any of them.
    refine : bool, optional
        With a region the LMI is conservative (one Lyapunov matrix for the
        bound and the region); refinement then minimises the true H∞ norm
        under the region constraint (:mod:`controlext.synthesis.refine`).
        The report's ``stage`` says which stage produced the gain.
    margin : float, optional
        The returned gain is certified to ``margin · γ*`` (``>= 1``); a
        small margin keeps the gain of moderate norm when ``γ*`` is not
        attained.
    solver, solver_options : optional
        cvxpy solver (default clarabel) and its options.
    seed : int, optional
        Seed of the refinement's random starts (results are reproducible).
    refine_options : dict or RefineOptions, optional
        The refinement's budget (:class:`~controlext.synthesis.RefineOptions`:
        random starts, iterations, ...).
    executor : concurrent.futures.Executor, optional
        Runs the refinement's starts in parallel (results do not depend
        on it).
    max_gain : float, 'auto' or None, optional
        Bound on the gain's spectral norm ``‖G‖₂`` in the plant's units,
        held by refinement and verified; ``'auto'`` (default) bounds it at
        1e6 times the plant's scale and warns when it binds, ``None``
        lifts it (:class:`~controlext.synthesis.SynthesisOptions`).
    objective : {'hinf', 'h2'}, optional
        The norm from noise to estimation error that is minimised: the
        worst-case gain (H∞, default) or the RMS error under unit white
        noise (H2, what a Kalman filter minimises).
    max_hinf, max_h2 : float, optional
        A bound on the norm that is not minimised: ``objective='h2',
        max_hinf=b`` is the mixed H2/H∞ design (the best white-noise error
        whose worst-case gain is at most ``b``), ``max_h2=`` the reverse.
        Held by the convex stage (one Lyapunov matrix for both norms) and
        by refinement, verified on the result; a bound below what any
        linear estimator reaches is refused at once.
    settling_time : float, optional
        The averaged error from the worst unit initial error must be
        within 2 % of its start from this time on (the report's
        ``tradeoff.settling_time``): a faster transient for a larger γ.
    gain_tolerance : float, optional
        Relative error of every gain entry under which the error poles
        must stay in the region, certified
        (:mod:`~controlext.synthesis.limits`; half-plane and disk regions),
        and the gain rounded to ``⌈−log10 ε⌉`` significant digits keeps
        them there.  Default ``1e-6`` (6 digits) wherever refinement runs
        and the region is made of half-planes and disks; ``0`` gives the
        nominal optimum.  Where no design meets the default, the nominal
        optimum is returned with a ``GainWarning``; a tolerance given
        explicitly is a requirement.  Both limits are held by refinement
        and verified on the result.
    options : SynthesisOptions, optional
        Every tunable of the engine (``lmi_max_states``, ``modal_guard``,
        …); the keywords above override it where they differ from their
        defaults.
    name : str, optional
        System name.
    inputs, outputs, states : str or list of str, optional
        Signal names of the error system (python-control's system
        keywords; see :class:`~controlext.Observer`).

    Returns
    -------
    LuenbergerObserver
        With ``report.gamma_convex = γ*`` and ``report.hinf`` the true norm.

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-1, 1], [-1, 0]], [[0], [1]], [[1, 2]], 0)
    >>> obs = cx.hinf_observer(plant, decay=1.0)
    >>> obs.decay >= 1 - 1e-6
    True
    """
    problem = for_models(plant, plant_problem, Bw=Bw, Dw=Dw, Cz=Cz)
    return design(LuenbergerObserver, problem, options, decay=decay,
                  region=region, system=dict(name=name, inputs=inputs,
                                             outputs=outputs, states=states))
