"""Factories: design an observer and return it verified.

Each factory builds the generalised plant (:mod:`controlext.problem`),
synthesises the gain (pole placement, the Riccati route or the LMI engine
of :mod:`controlext.lmi`), verifies the result (:mod:`controlext.verify`)
and wraps it in an observer object.  Bad input raises before any solver
runs.

Examples
--------
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-1, 1], [-1, 0]], [[0], [1]], [[1, 2]], 0)
>>> obs = cx.hinf_observer(plant)
>>> round(obs.report.gamma_opt, 4)
0.0
"""

import time

import numpy as np
import control as ct

from ._checks import (as_plant, check_decay, check_detectable,
                      check_region_reachable, unobservable_modes, _fmt_mode)
from .exceptions import ArgumentError, DimensionError, ParameterError, \
    RegionError
from .lmi import solve_observer_lmi
from .observers import LuenbergerObserver
from .problem import ObserverProblem
from .regions import Disk, HalfPlane, Region
from .riccati import hinf_filter_gain, hinf_filter_level
from .verify import verify_design

__all__ = ['luenberger_observer', 'hinf_observer']


def luenberger_observer(plant, poles, Bw=None, Dw=None, Cz=None, name=None):
    """Luenberger observer with error poles placed at ``poles``.

    Parameters
    ----------
    plant : control.StateSpace
        Observable plant.
    poles : array_like
        ``n`` desired error poles (complex ones in conjugate pairs).
    Bw, Dw, Cz : array_like, optional
        Noise model (see :class:`LuenbergerObserver`).
    name : str, optional
        System name.

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
    A, B, C, D, dt = as_plant(plant)
    prob = ObserverProblem(A, C, Bw, Dw, Cz, dt=dt)
    try:
        poles = np.array(poles, dtype=complex).ravel()
    except (TypeError, ValueError) as exc:
        raise ArgumentError("poles must be a sequence of numbers; found "
                            f"{type(poles).__name__}") from exc
    if poles.size != prob.n:
        raise DimensionError(f"poles has the wrong length; expected "
                             f"{prob.n} (one per state) instead of "
                             f"{poles.size}")
    if not np.all(np.isfinite(poles)):
        raise ParameterError(f"poles must be finite; found {poles.tolist()}")
    for lam in unobservable_modes(A, C):
        raise RegionError(
            f"poles cannot be placed freely: the mode at "
            f"{_fmt_mode(lam, dt)} is unobservable from C")
    if np.any(np.abs(np.sort_complex(poles) -
                     np.sort_complex(poles.conj())) > 1e-12):
        raise ParameterError("complex poles must come in conjugate pairs; "
                             f"found {poles.tolist()}")
    try:
        L = ct.place(A.T, C.T, poles).T
    except ValueError as exc:
        raise ParameterError(f"pole placement failed: {exc}") from exc
    placed = np.linalg.eigvals(A - L @ C)
    err = _match_error(placed, poles)
    if err > 1e-6 * max(1.0, np.max(np.abs(poles))):
        from .exceptions import VerificationError
        raise VerificationError(
            f"placed poles {np.round(placed, 6).tolist()} miss the requested "
            f"{np.round(poles, 6).tolist()} by {err:.3g}")
    report = verify_design(prob, L, method='placement', check=False,
                           time=time.perf_counter() - start)
    return LuenbergerObserver(plant, L, prob.Bw, prob.Dw, prob.Cz, name=name,
                              report=report)


def _match_error(a, b):
    b = list(b)
    worst = 0.0
    for x in a:
        k = int(np.argmin([abs(x - y) for y in b]))
        worst = max(worst, abs(x - b.pop(k)))
    return worst


def hinf_observer(plant, decay=None, Bw=None, Dw=None, Cz=None, *,
                  region=None, method='auto', margin=1.02, solver=None,
                  solver_options=None, name=None):
    """H∞-optimal Luenberger observer, optionally with a decay constraint.

    Minimises the H∞ norm from noise ``w`` to estimation error
    ``Cz (x̂ − x)`` over gains ``L`` (LMIs in Control's H∞-optimal
    observer; Theorem 3.12 of Li & Sanfelice, linearised).

    Parameters
    ----------
    plant : control.StateSpace
        Detectable plant.
    decay : float, optional
        Required rate of convergence ``σ >= 0``: every error pole has
        ``Re s <= -σ``.  Shorthand for ``region=cx.HalfPlane(σ)``.
    Bw, Dw, Cz : array_like, optional
        Noise model (see :class:`LuenbergerObserver`).
    region : Region, optional
        Pole region for the error dynamics.
    method : {'auto', 'lmi', 'riccati'}, optional
        ``'riccati'`` solves the filter Riccati equation (no region, all
        measurements noisy); ``'lmi'`` the two-stage LMI; ``'auto'`` picks
        the Riccati route when it applies.
    margin : float, optional
        The returned gain is certified to ``margin · γ*`` (``>= 1``); a
        small margin keeps the gain of moderate norm when ``γ*`` is not
        attained.
    solver, solver_options : optional
        cvxpy solver (default clarabel) and its options.
    name : str, optional
        System name.

    Returns
    -------
    LuenbergerObserver
        With ``report.gamma_opt = γ*`` and ``report.hinf`` the true norm.

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-1, 1], [-1, 0]], [[0], [1]], [[1, 2]], 0)
    >>> obs = cx.hinf_observer(plant, decay=1.0)
    >>> obs.decay >= 1 - 1e-6
    True
    """
    start = time.perf_counter()
    A, B, C, D, dt = as_plant(plant)
    prob = ObserverProblem(A, C, Bw, Dw, Cz, dt=dt)
    region = resolve_region(decay, region, dt)
    margin = _check_margin(margin)
    if method not in ('auto', 'lmi', 'riccati'):
        raise ArgumentError(f"method must be 'auto', 'lmi' or 'riccati'; "
                            f"found {method!r}")
    check_detectable(A, C, dt)
    if region is not None:
        check_region_reachable(A, C, region, dt)
    riccati_ok = region is None and not dt and np.linalg.matrix_rank(
        prob.Dw @ prob.Dw.T) == prob.p
    if method == 'riccati' and not riccati_ok:
        raise ArgumentError("method='riccati' needs a continuous plant, no "
                            "pole region and noise on every measurement "
                            "(Dw Dwᵀ nonsingular)")
    if method == 'riccati' or (method == 'auto' and riccati_ok):
        gopt = hinf_filter_level(A, C, prob.Bw, prob.Dw, prob.Cz)
        gbound = margin * gopt if gopt > 0 else 1e-9
        L = hinf_filter_gain(A, C, prob.Bw, prob.Dw, prob.Cz,
                             gbound if margin > 1 else gopt * (1 + 1e-6))
        info = dict(gamma_opt=gopt, solver='riccati', status='optimal')
        used = 'riccati'
    else:
        sol = solve_observer_lmi(prob, region, margin, solver,
                                 solver_options)
        L, gbound = sol.G, sol.gamma_bound
        info = dict(gamma_opt=sol.gamma_opt, solver=sol.stats['solver'],
                    status=sol.status, stats=sol.stats)
        used = 'lmi'
    report = verify_design(prob, L, region, gamma_bound=gbound, method=used,
                           **info)
    report.time = time.perf_counter() - start
    return LuenbergerObserver(plant, L, prob.Bw, prob.Dw, prob.Cz, name=name,
                              report=report)


def resolve_region(decay, region, dt):
    """The pole region requested by ``decay=`` or ``region=``."""
    decay = check_decay(decay)
    if decay is not None and region is not None:
        raise ArgumentError("give either decay= or region=, not both")
    if region is not None and not isinstance(region, Region):
        raise ArgumentError(f"region must be a controlext Region; found "
                            f"{type(region).__name__}")
    if decay is not None:
        if dt:
            step = 1.0 if dt is True else float(dt)
            region = Disk(float(np.exp(-decay * step)))
            region.domain = 'discrete'
        else:
            region = HalfPlane(decay)
    if region is not None:
        want = 'discrete' if dt else 'continuous'
        if region.domain not in ('any', want):
            raise RegionError(f"{region} is a {region.domain}-time region "
                              f"but the plant is {want}-time")
    return region


def _check_margin(margin):
    try:
        margin = float(margin)
    except (TypeError, ValueError) as exc:
        raise ArgumentError("margin must be a number >= 1; found "
                            f"{type(margin).__name__}") from exc
    if not np.isfinite(margin) or margin < 1:
        raise ParameterError(f"margin must be a finite number >= 1; found "
                             f"{margin}")
    return margin
