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

from ._checks import (as_plant, check_detectable,
                      check_region_reachable, unobservable_modes, _fmt_mode)
from .exceptions import (ArgumentError, DimensionError, ParameterError,
                         RegionError, VerificationError)
from .modal import modal_applies
from .observers import CoupledObserver, LuenbergerObserver
from .problem import ObserverProblem
from .synthesis import (LMI_MAX_STATES, synthesise, convex_info,
                        resolve_region, _check_margin, _modal_design,
                        _riccati_applies, _riccati_design)
from .verify import verify_design

__all__ = ['luenberger_observer', 'hinf_observer', 'coupled_observer']


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
    # redundant sensors (rank C < p): place through an orthonormal basis U
    # of range(C), C = U Cr, and use L = Lr Uᵀ so that L C = Lr Cr
    Usv, sv, _ = np.linalg.svd(C, full_matrices=False)
    U = Usv[:, :int(np.sum(sv > 1e-10 * max(1.0, sv[0])))]
    try:
        L = ct.place(A.T, (U.T @ C).T, poles).T @ U.T
    except ValueError as exc:
        raise ParameterError(f"pole placement failed: {exc}") from exc
    placed = np.linalg.eigvals(A - L @ C)
    err = _match_error(placed, poles)
    if err > 1e-6 * max(1.0, np.max(np.abs(poles))):
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
                  region=None, method='auto', refine=True, margin=1.02,
                  solver=None, solver_options=None, seed=0,
                  refine_options=None, name=None):
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
    method : {'auto', 'lmi', 'riccati', 'modal'}, optional
        ``'riccati'`` solves the filter Riccati equation (continuous time,
        all measurements noisy, no region or a decay half-plane — for
        ``Re s <= -σ`` the plant shifted by ``σ``, a certified but more
        conservative bound); ``'lmi'`` the two-stage LMI; ``'modal'`` that
        LMI on the modes outside or near the region only
        (:mod:`controlext.modal`; exact for the gains acting on them when
        the noise does not reach the others).  ``'auto'`` takes the
        Riccati route without a region; with one, the modal LMI where it
        applies (within 0.1 % of the full LMI's γ on the benchmark plants,
        10–40× faster), else the LMI up to ``LMI_MAX_STATES = 40``
        states (it costs about ``n^3.7``) and the shifted Riccati design
        above.  Refinement starts from any of them.
    refine : bool, optional
        With a region the LMI is conservative (one Lyapunov matrix for the
        bound and the region); refinement then minimises the true H∞ norm
        under the region constraint (:mod:`controlext.refine`).  The
        report's ``stage`` says which stage produced the gain.
    margin : float, optional
        The returned gain is certified to ``margin · γ*`` (``>= 1``); a
        small margin keeps the gain of moderate norm when ``γ*`` is not
        attained.
    solver, solver_options : optional
        cvxpy solver (default clarabel) and its options.
    seed : int, optional
        Seed of the refinement's random starts (results are reproducible).
    refine_options : dict, optional
        Options of :func:`controlext.refine.refine_gain` (number of random
        starts, iterations, ...).
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
    if method not in ('auto', 'lmi', 'riccati', 'modal'):
        raise ArgumentError(f"method must be 'auto', 'lmi', 'riccati' or "
                            f"'modal'; found {method!r}")
    check_detectable(A, C, dt)
    if region is not None:
        check_region_reachable(A, C, region, dt)
    riccati_ok = _riccati_applies(prob, region)
    if method == 'riccati' and not riccati_ok:
        raise ArgumentError("method='riccati' needs a continuous plant, no "
                            "pole region other than a decay half-plane, and "
                            "noise on every measurement (Dw Dwᵀ nonsingular)")
    large = prob.n > LMI_MAX_STATES
    split = modal_applies(prob, region, LMI_MAX_STATES) if \
        method in ('modal', 'auto') else None
    if method == 'modal' and split is None:
        raise ArgumentError(
            f"method='modal' needs a pole region with between 1 and "
            f"{min(LMI_MAX_STATES, prob.n - 1)} modes of A outside or near "
            "it, and noise that does not reach the other modes (Bw = 0 or "
            "in the span of the slow Schur vectors)")
    if split is not None:
        L, info = _modal_design(prob, region, margin, solver,
                                solver_options, split)
        L, report = synthesise(prob, region, refine=refine, margin=margin,
                               solver=solver, solver_options=solver_options,
                               seed=seed, refine_options=refine_options,
                               convex=(L, info))
    elif method == 'riccati' or (method == 'auto' and riccati_ok and (
            region is None or large)):
        L, report = _riccati_design(prob, region, margin)
        if refine and region is not None:
            L, report = synthesise(prob, region, refine=True, margin=margin,
                                   solver=solver,
                                   solver_options=solver_options, seed=seed,
                                   refine_options=refine_options,
                                   convex=(L, convex_info(report)))
    else:
        L, report = synthesise(prob, region, refine=refine and region
                               is not None, margin=margin, solver=solver,
                               solver_options=solver_options, seed=seed,
                               refine_options=refine_options)
    report.time = time.perf_counter() - start
    return LuenbergerObserver(plant, L, prob.Bw, prob.Dw, prob.Cz, name=name,
                              report=report)


def coupled_observer(plant, decay=None, copies=2, weights=None, Bw=None,
                     Dw=None, Cz=None, *, region=None, method='auto',
                     refine=True, margin=1.02, solver=None,
                     solver_options=None, seed=0, refine_options=None,
                     executor=None, name=None):
    """Coupled Luenberger observers minimising the H∞ norm (Li & Sanfelice).

    A convex stage gives a certified design; refinement then minimises the
    true H∞ norm of the error system under the pole-region constraint from
    several starts: the convex design, the Luenberger-equivalent design
    ``K_i = L0``, ``L_i = 0`` (with ``L0`` from :func:`hinf_observer`), and
    seeded perturbations of both.  The result is therefore never worse
    than the best Luenberger observer found for the same region.

    The convex stage is, by default (``method='auto'``), the n-state
    Luenberger LMI embedded as ``K_i = L0``, ``L_i = 0``: it has the same γ
    as the common-Lyapunov coupled LMI of Theorem 3.10 in every case
    measured, and its solve time grows as about ``n^3.7`` instead of
    ``n^4.5``.  ``method='lmi'`` solves Theorem 3.10 (``N n`` states).

    Parameters
    ----------
    plant : control.StateSpace
        Detectable plant.
    decay : float, optional
        Required rate of convergence (every error pole has
        ``Re s <= -decay``); shorthand for ``region=cx.HalfPlane(decay)``.
    copies : int, optional
        Number of coupled copies ``N >= 2``.
    weights : array_like, optional
        Output weights (length ``N``, summing to 1; default ``1/N``).
    Bw, Dw, Cz : array_like, optional
        Noise model (see :class:`LuenbergerObserver`).
    region : Region, optional
        Pole region.
    method : {'auto', 'lmi', 'riccati', 'modal'}, optional
        Convex stage: the embedded n-state design of :func:`hinf_observer`
        with the same ``method`` (``'auto'``, ``'riccati'``, ``'modal'``),
        or the coupled LMI of Theorem 3.10 (``'lmi'``).
    refine : bool, optional
        Run the refinement stage (default).  Without it the result is the
        convex (conservative) design.
    margin, solver, solver_options, seed, refine_options, name : optional
        As for :func:`hinf_observer`.
    executor : concurrent.futures.Executor, optional
        Runs the refinement's starts in parallel (results do not depend on
        it).

    Returns
    -------
    CoupledObserver

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> obs = cx.coupled_observer(plant, decay=2.5)
    >>> bool(obs.hinf <= 0.4953), bool(obs.decay >= 2.5 - 1e-6)
    (True, True)
    """
    start = time.perf_counter()
    A, B, C, D, dt = as_plant(plant)
    if isinstance(copies, bool) or not isinstance(copies, (int, np.integer)):
        raise ArgumentError(f"copies must be an integer >= 2; found "
                            f"{type(copies).__name__}")
    if copies < 2:
        raise ParameterError(f"a coupled observer needs copies >= 2; found "
                             f"{copies} (use hinf_observer for one copy)")
    prob = ObserverProblem(A, C, Bw, Dw, Cz, copies=copies, weights=weights,
                           dt=dt)
    region = resolve_region(decay, region, dt)
    margin = _check_margin(margin)
    check_detectable(A, C, dt)
    if region is not None:
        check_region_reachable(A, C, region, dt)
    if method not in ('auto', 'lmi', 'riccati', 'modal'):
        raise ArgumentError(f"method must be 'auto', 'lmi', 'riccati' or "
                            f"'modal'; found {method!r}")
    if method == 'riccati' and not _riccati_applies(prob, region):
        raise ArgumentError("method='riccati' needs a continuous plant, no "
                            "pole region other than a decay half-plane, and "
                            "noise on every measurement (Dw Dwᵀ nonsingular)")
    common = dict(Bw=prob.Bw, Dw=prob.Dw, Cz=prob.Cz, region=region,
                  margin=margin, solver=solver, solver_options=solver_options,
                  seed=seed)
    embed = lambda L: np.kron(np.eye(copies), L)
    convex, extra = None, []
    if method != 'lmi' or refine:
        # the n-state Luenberger design, solved once: the convex stage
        # (embedded) and the start of the single observer's refinement
        base = hinf_observer(plant, refine=False, method=(
            'auto' if method == 'lmi' else method), **common)
        info = convex_info(base.report, 'luenberger')
        if method != 'lmi':
            convex = (embed(base.L), info)
        if refine:
            L0 = base.L
            if region is not None:      # as hinf_observer(refine=True)
                single = ObserverProblem(A, C, prob.Bw, prob.Dw, prob.Cz,
                                         dt=dt)
                L0, _ = synthesise(single, region, refine=True,
                                   margin=margin, solver=solver,
                                   solver_options=solver_options, seed=seed,
                                   refine_options=refine_options,
                                   convex=(base.L, info), executor=executor)
            extra.append(('luenberger', embed(L0)))
    G, report = synthesise(prob, region, refine=refine, margin=margin,
                           solver=solver, solver_options=solver_options,
                           seed=seed, extra_starts=extra,
                           refine_options=refine_options, convex=convex,
                           executor=executor)
    report.time = time.perf_counter() - start
    return CoupledObserver(plant, G, prob.weights, prob.Bw, prob.Dw, prob.Cz,
                           name=name, report=report)
