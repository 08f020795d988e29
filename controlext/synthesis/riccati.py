"""The unconstrained H∞ filter through its Riccati equation (no LMI).

For ``e' = (A − L C) e + (L Dw − Bw) w``, ``z = Cz e`` with
``R = Dw Dwᵀ > 0``, a gain with ``‖T‖∞ < γ`` exists if and only if the
filter Riccati equation

    Ā Y + Y Āᵀ − Y (Cᵀ R⁻¹ C − γ⁻² Czᵀ Cz) Y + Q = 0,
    Ā = A − Bw Dwᵀ R⁻¹ C,   Q = Bw (I − Dwᵀ R⁻¹ Dw) Bwᵀ,

has a stabilising solution ``Y ≥ 0``; then ``L = (Y Cᵀ + Bw Dwᵀ) R⁻¹``
achieves it (Nagpal & Khargonekar).  The central H∞ filter has observer
form, so the infimum over ``L`` equals the optimal H∞ filtering level.
This module bisects on ``γ`` with an ordered Schur decomposition of the
Hamiltonian; it costs milliseconds.

Examples
--------
>>> from controlext.synthesis.riccati import hinf_filter_level
>>> round(hinf_filter_level([[1.0]], [[1.0]], [[0.0]], [[1.0]], [[1.0]]), 4)
1.0
"""

import numpy as np
import scipy.linalg as la

from ..exceptions import ParameterError

__all__ = ['hinf_filter_level', 'hinf_filter_gain', 'kalman_filter',
           'regularisations']


def _data(A, C, Bw, Dw, Cz, reg=0.0):
    A, C, Bw, Dw, Cz = (np.asarray(M, dtype=float) for M in (A, C, Bw, Dw, Cz))
    R = Dw @ Dw.T
    if np.linalg.matrix_rank(R) < R.shape[0]:
        raise ParameterError(
            "the Riccati route needs every measurement to be noisy "
            f"(Dw Dwᵀ nonsingular); found rank {np.linalg.matrix_rank(R)} "
            f"for {R.shape[0]} measurements: use method='lmi'")
    Ri = la.inv(R)
    Ab = A - Bw @ Dw.T @ Ri @ C
    Q = Bw @ (np.eye(Dw.shape[1]) - Dw.T @ Ri @ Dw) @ Bw.T + \
        reg * np.eye(A.shape[0])
    return A, C, Bw, Dw, Cz, Ri, Ab, 0.5 * (Q + Q.T)


def regularisations(A, Bw, Dw):
    """Process-noise levels ``ε`` to try, 0 first.

    With ``Q = 0`` on a mode of the imaginary axis (an integrator, an
    undamped pendulum) the Hamiltonian keeps that mode on the axis and no
    stabilising solution exists, although the filtering problem is well
    posed.  ``Q + ε I`` is the same problem with an extra noise channel
    ``√ε I`` that no measurement sees; its error system contains the
    original one, so a gain it certifies at ``γ`` is certified at ``γ``
    for the original problem too (more conservative by about ``√ε``).
    """
    size = max(1.0, np.linalg.norm(A, 2)) * max(
        1.0, np.linalg.norm(Bw, 2)**2, np.linalg.norm(Dw, 2)**2)
    return [0.0] + [float(k * size) for k in (1e-10, 1e-8, 1e-6)]


def _riccati(Ab, W, Q):
    """Stabilising solution of ``Ab Y + Y Abᵀ − Y W Y + Q = 0`` or None."""
    n = Ab.shape[0]
    H = np.block([[Ab.T, -W], [-Q, -Ab]])
    ev = la.eigvals(H)
    scale = max(1.0, np.max(np.abs(ev)))
    if np.min(np.abs(ev.real)) < 1e-9 * scale:
        return None
    try:
        T, Z, sdim = la.schur(H, sort='lhp')
    except np.linalg.LinAlgError:
        # the reordering moved eigenvalues near the axis across it
        # (LAPACK's trsen): no reliable solution here
        return None
    if sdim != n:
        return None
    U1, U2 = Z[:n, :n], Z[n:, :n]
    if np.linalg.cond(U1) > 1e12:
        return None
    Y = la.solve(U1.T, U2.T).T
    return 0.5 * (Y + Y.T)


def _feasible(data, gamma):
    A, C, Bw, Dw, Cz, Ri, Ab, Q = data
    W = C.T @ Ri @ C - Cz.T @ Cz / gamma**2
    Y = _riccati(Ab, W, Q)
    if Y is None:
        return None
    if np.min(np.linalg.eigvalsh(Y)) < -1e-9 * max(1.0, np.max(np.abs(Y))):
        return None
    return Y


def hinf_filter_level(A, C, Bw, Dw, Cz, rtol=1e-6, reg=0.0):
    """Optimal H∞ level ``γ*`` of the observer (bisection on the Riccati
    equation); 0 when the noise can be cancelled exactly (a level of
    ``1e-12`` relative to the data is still reached).  ``reg`` adds the
    process noise ``reg · I`` (:func:`regularisations`)."""
    data = _data(A, C, Bw, Dw, Cz, reg)
    hi = 1.0
    while _feasible(data, hi) is None:
        hi *= 4
        if hi > 1e12:
            raise ParameterError("no finite H∞ level found: is the plant "
                                 "detectable?")
    floor = 1e-12 * max(1.0, *(np.linalg.norm(M, 2) for M in (Bw, Dw, Cz)))
    lo = 0.0
    while True:
        trial = hi / 4
        if trial < floor:
            return 0.0              # γ* = 0 to the resolution of the data
        if _feasible(data, trial) is None:
            lo = trial
            break
        hi = trial
    while hi - lo > rtol * hi:
        mid = 0.5 * (lo + hi)
        if _feasible(data, mid) is None:
            lo = mid
        else:
            hi = mid
    return hi


def hinf_filter_gain(A, C, Bw, Dw, Cz, gamma, reg=0.0):
    """Central-filter gain ``L`` achieving ``‖T‖∞ < gamma``."""
    data = _data(A, C, Bw, Dw, Cz, reg)
    Y = _feasible(data, gamma)
    if Y is None:
        raise ParameterError(f"gamma = {gamma:g} is below the optimal H∞ "
                             "level; no gain reaches it")
    A, C, Bw, Dw, Cz, Ri = data[:6]
    return (Y @ C.T + Bw @ Dw.T) @ Ri


def kalman_filter(A, C, Bw, Dw, Cz, dt=0, reg=0.0):
    """The Kalman filter in observer form: ``(L, h)`` with ``h`` the H2
    norm of its error system ``sqrt(tr(Cz Y Czᵀ))`` (``Y`` the error
    covariance under unit white noise ``w``), the least any linear
    estimator reaches.

    Continuous time: the filter Riccati equation above with ``γ = ∞``;
    discrete time: the predictor's ``A Y Aᵀ − Y − (A Y Cᵀ + S)(R + C Y Cᵀ)⁻¹
    (C Y Aᵀ + Sᵀ) + Bw Bwᵀ = 0``, ``S = Bw Dwᵀ``, ``L = (A Y Cᵀ + S)
    (R + C Y Cᵀ)⁻¹`` (the error ``e_{k+1} = (A − L C) e_k + (L Dw − Bw) w_k``
    of this package's discrete observers).  ``reg`` adds the process noise
    ``reg · I`` (:func:`regularisations`): ``h`` is then a certified bound
    for the gain on the original problem.
    """
    A, C, Bw, Dw, Cz, Ri, Ab, Q = _data(A, C, Bw, Dw, Cz, reg)
    if not dt:
        Y = _riccati(Ab, C.T @ Ri @ C, Q)
        if Y is None:
            raise ParameterError("the Kalman filter Riccati equation has no "
                                 "stabilising solution")
        L = (Y @ C.T + Bw @ Dw.T) @ Ri
    else:
        R, S = Dw @ Dw.T, Bw @ Dw.T
        try:
            with np.errstate(all='ignore'):
                Y = la.solve_discrete_are(
                    A.T, C.T, Bw @ Bw.T + reg * np.eye(A.shape[0]), R, s=S)
        except (np.linalg.LinAlgError, ValueError) as exc:
            raise ParameterError("the Kalman predictor Riccati equation has "
                                 f"no stabilising solution ({exc})") from exc
        if not np.all(np.isfinite(Y)):
            raise ParameterError("the Kalman predictor Riccati equation has "
                                 "no stabilising solution")
        Y = 0.5 * (Y + Y.T)
        L = la.solve((R + C @ Y @ C.T).T, (A @ Y @ C.T + S).T).T
    return L, float(np.sqrt(max(np.trace(Cz @ Y @ Cz.T), 0.0)))
