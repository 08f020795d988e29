"""Analysis of observers: rates, ISS estimates and the conditions of
Section III of Li & Sanfelice.

Notation of the paper: ``α(A)`` spectral abscissa, ``µ(A)`` logarithmic
norm ``λmax((A + Aᵀ)/2)``, ``κ(A)`` eigenvector condition number.  For an
observer with error system ``e' = Ã e + K̃ m``, ``ē = C e`` the ISS
estimate (18) is

    |e(t)| ≤ κ(Ã) e^{α(Ã) t} |e(0)| + |K̃| / |µ(Ã)| · |m|∞,

and for the output ``ē`` the gain is multiplied by ``|C|`` (the factor
``√2/2`` of (33) for the averaged pair).

Examples
--------
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
>>> pair = cx.CoupledObserver.from_pair(plant, 1.7896, 2.2278, 0.0538,
...                                     -1.1633)
>>> round(cx.log_norm(pair.A), 4)
-1.9123
>>> round(cx.iss_estimate(pair).output_gain, 3)
0.787
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any
from dataclasses import dataclass, field

import numpy as np
import control as ct

from .synthesis.lmi import decay_certificate
from ._typing import Array, ArrayLike, ExecutorLike, Plant

if TYPE_CHECKING:
    from .observers import Observer

__all__ = ['spectral_abscissa', 'log_norm', 'eig_condition', 'ISSEstimate',
           'iss_estimate', 'ConditionCheck', 'check_lemma_3_2',
           'check_lemma_3_3', 'check_theorem_3_5', 'steady_state_error',
           'crossing_time', 'tradeoff_curve']


def spectral_abscissa(A: ArrayLike) -> float:
    """``α(A) = max Re λ(A)``.

    Parameters
    ----------
    A : array_like
        Square matrix.

    Returns
    -------
    float

    Examples
    --------
    >>> import controlext as cx
    >>> cx.spectral_abscissa([[-1.0, 5.0], [0.0, -2.0]])
    -1.0
    """
    return float(np.max(np.linalg.eigvals(np.atleast_2d(A)).real))


def log_norm(A: ArrayLike) -> float:
    """Logarithmic 2-norm ``µ(A) = λmax((A + Aᵀ)/2)``.

    Parameters
    ----------
    A : array_like
        Square matrix.

    Returns
    -------
    float

    Examples
    --------
    >>> import controlext as cx
    >>> round(cx.log_norm([[-1.0, 5.0], [0.0, -2.0]]), 4)
    1.0495
    """
    M: Array = np.atleast_2d(np.asarray(A, dtype=float))
    return float(np.linalg.eigvalsh(0.5 * (M + M.T))[-1])


def eig_condition(A: ArrayLike) -> float:
    """Upper bound on ``κ(A) = min |X| |X⁻¹|`` over eigenvector matrices.

    Returns the condition number of the eigenvector matrix with columns
    of unit norm, which is within a factor ``√n`` of the minimum (van der
    Sluis); ``inf`` for a defective matrix.

    Parameters
    ----------
    A : array_like
        Square matrix.

    Returns
    -------
    float

    Examples
    --------
    >>> import controlext as cx
    >>> cx.eig_condition([[-1.0, 0.0], [0.0, -2.0]])
    1.0
    """
    M: Array = np.atleast_2d(np.asarray(A, dtype=float))
    _, X = np.linalg.eig(M)
    X = X / np.linalg.norm(X, axis=0)
    return float(np.linalg.cond(X))


@dataclass
class ISSEstimate:
    """ISS estimate (18): ``β(s, t) = kappa e^{rate t} s``,
    ``γ(s) = gain s`` (state) and ``output_gain s`` (estimate).

    Attributes
    ----------
    kappa : float
        Eigenvector condition bound of the error matrix.
    rate : float
        Its spectral abscissa.
    mu : float
        Its logarithmic norm.
    gain, output_gain : float
        The ISS gains of the error and of the estimate's error.
    """
    kappa: float
    rate: float
    mu: float
    gain: float
    output_gain: float

    def beta(self, s: float, t: ArrayLike) -> Array:
        """The class-KL bound ``κ e^{α t} s``."""
        return self.kappa * np.exp(self.rate * np.asarray(t)) * s


def iss_estimate(obs: Observer) -> ISSEstimate:
    """ISS estimate (18) of an observer's error system.

    The gains are ``|K̃| / |µ(Ã)|`` and ``|C| |K̃| / |µ(Ã)|``; they are
    ``inf`` when ``Ã`` is not dissipative (``µ(Ã) >= 0``).

    Parameters
    ----------
    obs : Observer
        Any observer (its error system ``(Ã, K̃, C)``).

    Returns
    -------
    ISSEstimate

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> luen = cx.LuenbergerObserver(ct.ss([[-0.5]], [[1.0]], [[1.0]], 0),
    ...                              [[2.0]])
    >>> est = cx.iss_estimate(luen)
    >>> round(est.gain, 4), round(est.rate, 4)
    (0.8, -2.5)
    """
    mu = log_norm(obs.A)
    nB = np.linalg.norm(obs.B, 2)
    gain = float(nB / abs(mu)) if mu < 0 else np.inf
    return ISSEstimate(kappa=eig_condition(obs.A),
                       rate=spectral_abscissa(obs.A), mu=mu, gain=gain,
                       output_gain=float(np.linalg.norm(obs.C, 2) * gain))


@dataclass
class ConditionCheck:
    """Result of a lemma check: ``holds`` and each named condition.

    Attributes
    ----------
    holds : bool
        Every condition holds.
    conditions : dict
        ``{condition: bool}``, named by the paper's equation numbers.
    values : dict
        The quantities the conditions compare.
    """
    holds: bool
    conditions: dict
    values: dict = field(default_factory=dict)

    def __bool__(self):
        return bool(self.holds)


def _distinct(A, tol=1e-9):
    lam = np.linalg.eigvals(A)
    if len(lam) < 2:
        return True
    d = np.abs(lam[:, None] - lam[None, :])[~np.eye(len(lam), dtype=bool)]
    return bool(np.min(d) > tol * max(1.0, np.max(np.abs(lam))))


def check_lemma_3_2(luenberger: Observer, coupled: Observer,
                    output: bool = False) -> ConditionCheck:
    """Conditions (19)–(22) of Lemma 3.2 (``output=True``: with the output
    maps, as in Theorem 3.5 and (33)).

    Parameters
    ----------
    luenberger : Observer
        The classic (one-copy) observer, ``Ã0`` and ``K̃0``.
    coupled : Observer
        The coupled observer, ``Ã`` and ``K̃``.
    output : bool, optional
        Use the output maps (the averaged estimate's error).

    Returns
    -------
    ConditionCheck

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> luen = cx.LuenbergerObserver(plant, [[2.0]])
    >>> pair = cx.CoupledObserver.from_pair(plant, 1.7896, 2.2278, 0.0538,
    ...                                     -1.1633)
    >>> cx.check_lemma_3_2(luen, pair, output=True).holds
    True
    """
    A0, A = luenberger.A, coupled.A
    a0, a = -log_norm(A0), -log_norm(A)
    k0 = np.linalg.norm(luenberger.B, 2)
    k = np.linalg.norm(coupled.B, 2)
    if output:
        k0 *= np.linalg.norm(luenberger.C, 2)
        k *= np.linalg.norm(coupled.C, 2)
    g0 = k0 / a0 if a0 > 0 else np.inf
    g = k / a if a > 0 else np.inf
    cond = {
        '(19) Ã0 dissipative': a0 > 0,
        '(20) Ã dissipative': a > 0,
        '(21) distinct eigenvalues, α(Ã) < α(Ã0)':
            _distinct(A0) and _distinct(A) and
            spectral_abscissa(A) < spectral_abscissa(A0),
        '(22) |K̃|/α < |K̃0|/α0': bool(g < g0),
    }
    return ConditionCheck(all(cond.values()), cond,
                          dict(alpha0=a0, alpha=a, gain0=float(g0),
                               gain=float(g)))


def check_lemma_3_3(luenberger: Observer, coupled: Observer,
                    alpha0: float | None = None, alpha: float | None = None,
                    fraction: float = 0.99) -> ConditionCheck:
    """Conditions (23)–(26) of Lemma 3.3 with ``P0``, ``P`` found by LMI.

    For each observer the rate is taken as ``fraction`` of its decay rate
    unless given, and ``P`` is the best-conditioned matrix with
    ``Ãᵀ P + P Ã ≤ −2 α P`` (:func:`controlext.synthesis.lmi.decay_certificate`).

    Parameters
    ----------
    luenberger : Observer
        The classic (one-copy) observer, ``Ã0`` and ``K̃0``.
    coupled : Observer
        The coupled observer, ``Ã`` and ``K̃``.
    alpha0, alpha : float, optional
        The rates ``α0``, ``α`` of the certificates (default: ``fraction``
        of each observer's decay rate).
    fraction : float, optional
        Share of the decay rate used when a rate is not given.

    Returns
    -------
    ConditionCheck

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> luen = cx.LuenbergerObserver(plant, [[2.0]])
    >>> pair = cx.CoupledObserver.from_pair(plant, 1.7896, 2.2278, 0.0538,
    ...                                     -1.1633)
    >>> res = cx.check_lemma_3_3(luen, pair)
    >>> sorted(res.conditions)[:2]
    ['(23) P0 certificate', '(24) P certificate']
    """
    A0, A = luenberger.A, coupled.A
    alpha0 = fraction * -spectral_abscissa(A0) if alpha0 is None else alpha0
    alpha = fraction * -spectral_abscissa(A) if alpha is None else alpha
    if alpha0 <= 0 or alpha <= 0:
        cond = {'(23)/(24) exponential stability': False}
        return ConditionCheck(False, cond, dict(alpha0=alpha0, alpha=alpha))
    P0, kappa0 = decay_certificate(A0, alpha0)
    P, kappa = decay_certificate(A, alpha)
    k0 = np.linalg.norm(luenberger.B, 2)
    k = np.linalg.norm(coupled.B, 2)
    lhs25, rhs25 = alpha0 / kappa0, alpha / kappa
    lhs26, rhs26 = kappa**2 * k / alpha, kappa0**2 * k0 / alpha0
    cond = {'(23) P0 certificate': True, '(24) P certificate': True,
            '(25) α0 λmin/λmax(P0) < α λmin/λmax(P)': bool(lhs25 < rhs25),
            '(26) gain bound': bool(lhs26 < rhs26)}
    return ConditionCheck(all(cond.values()), cond,
                          dict(alpha0=alpha0, alpha=alpha, P0=P0, P=P,
                               kappa0=kappa0, kappa=kappa))


def check_theorem_3_5(luenberger: Observer,
                      coupled: Observer) -> ConditionCheck:
    """Theorem 3.5: the averaged estimate improves on the Luenberger one if
    (19)–(22) (with the output maps) or (23)–(26) hold.

    Parameters
    ----------
    luenberger : Observer
        The classic (one-copy) observer, ``Ã0`` and ``K̃0``.
    coupled : Observer
        The coupled observer, ``Ã`` and ``K̃``.

    Returns
    -------
    ConditionCheck
        That of Lemma 3.2 where it holds, else that of Lemma 3.3.

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> luen = cx.LuenbergerObserver(plant, [[2.0]])
    >>> pair = cx.CoupledObserver.from_pair(plant, 1.7896, 2.2278, 0.0538,
    ...                                     -1.1633)
    >>> cx.check_theorem_3_5(luen, pair).holds
    True
    """
    first = check_lemma_3_2(luenberger, coupled, output=True)
    if first:
        return first
    return check_lemma_3_3(luenberger, coupled)


def steady_state_error(obs: Observer, bias: ArrayLike) -> Array:
    """Steady-state estimation error under a constant noise ``bias``.

    Parameters
    ----------
    obs : Observer
        Any observer (its error system's DC gain is used).
    bias : array_like or float
        The constant noise, one value per noise input (a scalar for all).

    Returns
    -------
    ndarray
        The steady-state error, one value per error output.

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> luen = cx.LuenbergerObserver(plant, [[2.0]])
    >>> round(float(cx.steady_state_error(luen, 0.3)[0]), 4)
    0.24
    """
    bias = np.broadcast_to(np.asarray(bias, dtype=float), (obs.ninputs,))
    return np.atleast_2d(ct.dcgain(obs)).reshape(obs.noutputs, obs.ninputs) \
        @ bias


def crossing_time(luenberger: Observer, coupled: Observer, e0: ArrayLike,
                  bias: ArrayLike, T: ArrayLike | None = None) -> float:
    """``t⋆``: from then on the coupled error stays below the Luenberger one.

    Simulates both error systems from initial estimation error ``e0`` (in
    every copy) under a constant bias and returns the last time at which
    ``|ē(t)| > |e0(t)|`` (0 if never).

    Parameters
    ----------
    luenberger : Observer
        The classic (one-copy) observer, ``Ã0`` and ``K̃0``.
    coupled : Observer
        The coupled observer, ``Ã`` and ``K̃``.
    e0 : array_like
        Initial estimation error (the same in every copy).
    bias : array_like or float
        Constant noise, one value per noise input (a scalar for all).
    T : array_like, optional
        Time points (default: 20 time constants of the slower observer).

    Returns
    -------
    float

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> luen = cx.LuenbergerObserver(plant, [[2.0]])
    >>> pair = cx.CoupledObserver.from_pair(plant, 1.7896, 2.2278, 0.0538,
    ...                                     -1.1633)
    >>> round(cx.crossing_time(luen, pair, e0=[2.0], bias=0.3), 1)
    2.0
    """
    e0 = np.atleast_1d(np.asarray(e0, dtype=float))
    if T is None:
        slow = min(luenberger.decay, coupled.decay)
        T = np.linspace(0, 20 / max(slow, 1e-3), 20001)
    T = np.asarray(T, dtype=float)
    bias = np.asarray(bias, dtype=float)
    u0 = np.outer(np.ones(luenberger.ninputs) * bias, np.ones(len(T)))
    r0 = ct.forced_response(luenberger, T, u0, X0=e0)
    r = ct.forced_response(coupled, T, np.outer(
        np.ones(coupled.ninputs) * bias, np.ones(len(T))),
        X0=np.tile(e0, coupled.copies))
    n0 = np.linalg.norm(np.atleast_2d(r0.outputs), axis=0)
    n = np.linalg.norm(np.atleast_2d(r.outputs), axis=0)
    worse = np.nonzero(n > n0)[0]
    return float(T[worse[-1]]) if worse.size else 0.0


def tradeoff_curve(plant: Plant, decays: ArrayLike,
                   copies: Sequence[int] = (1, 2, 3),
                   executor: ExecutorLike = None, **kwargs: Any) -> dict[str,
                   Any]:
    """Best H∞ norm against required decay for several numbers of copies.

    Returns ``{'decay': array, N: array of γ, ...}`` (data; plot it with
    :func:`controlext.tradeoff_plot`).  Keyword arguments go to the
    factories; ``executor`` (any ``concurrent.futures.Executor``) runs the
    designs in parallel.

    Parameters
    ----------
    plant : control.StateSpace
        The plant.
    decays : array_like
        Required decay rates.
    copies : sequence of int, optional
        Numbers of copies, one curve each (1: the Luenberger observer).
    executor : concurrent.futures.Executor, optional
        Runs the designs in parallel.
    **kwargs
        Passed to :func:`~controlext.coupled_observer` (noise model,
        options).

    Returns
    -------
    dict

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> curve = cx.tradeoff_curve(plant, [2.5], copies=(1,))
    >>> [round(float(g), 4) for g in curve[1]]
    [0.8]
    """
    from .sweep import sweep
    decays = np.asarray(decays, dtype=float)
    out: dict[Any, Array] = {'decay': decays}
    for N in copies:
        out[N] = sweep(plant, 'decay', list(decays), copies=N,
                       executor=executor, **kwargs).metric('hinf')
    return out
