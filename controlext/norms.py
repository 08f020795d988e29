"""The H∞ norm with MATLAB's meaning.

:func:`hinfnorm` returns ``(γ, ω_peak)`` like MATLAB's ``hinfnorm``: the
H∞ norm of a stable system and ``inf`` for an unstable one (python-control's
``linfnorm`` returns the L∞ norm in that case).  It uses slycot's
``ab13dd`` through :func:`control.linfnorm` and falls back on a level-set
(Hamiltonian) algorithm of Bruinsma and Steinbuch when slycot raises;
discrete-time systems reach the fallback through the norm-preserving
bilinear map ``z = (1 + s) / (1 - s)``.
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg as la
import control as ct

from ._checks import check_finite
from ._warn import warn
from .exceptions import ArgumentError, ParameterError
from ._typing import ArrayLike, Plant

try:
    from slycot import ab13dd as _ab13dd
except ImportError:         # pragma: no cover - a required dependency
    _ab13dd = None

__all__ = ['hinfnorm', 'hinfnorm_quiet', 'hinfnorm_upper', 'is_stable',
           'rounding_bound']


def is_stable(sys_or_poles: Plant | ArrayLike, dt: float | bool = 0) -> bool:
    """True if every pole lies strictly inside the stability region.

    Parameters
    ----------
    sys_or_poles : control.StateSpace or control.TransferFunction or array_like
        A linear system (its poles and timebase are used) or its poles.
    dt : float or bool, optional
        Timebase of the poles (0: continuous time); ignored for a system.

    Returns
    -------
    bool

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> cx.is_stable(ct.ss([[-1.0]], [[1.0]], [[1.0]], 0))
    True
    """
    if isinstance(sys_or_poles, ct.LTI):
        poles, dt = ct.poles(sys_or_poles), sys_or_poles.dt
    else:
        try:
            poles = np.asarray(sys_or_poles, dtype=complex)
        except (TypeError, ValueError) as exc:
            raise ArgumentError("is_stable expects a linear system or a "
                                "sequence of poles; found "
                                f"{type(sys_or_poles).__name__} "
                                f"{sys_or_poles!r}") from exc
        if isinstance(sys_or_poles, (str, bytes)):
            raise ArgumentError("is_stable expects a linear system or a "
                                f"sequence of poles; found str "
                                f"{sys_or_poles!r}")
    if poles.size == 0:
        return True
    return bool(np.abs(poles).max() < 1 if dt else poles.real.max() < 0)


def hinfnorm(sys: Plant, tol: float = 1e-10) -> tuple[float, float]:
    """H∞ norm and peak frequency of a linear system.

    Parameters
    ----------
    sys : control.StateSpace or control.TransferFunction
        Continuous- or discrete-time system.
    tol : float, optional
        Relative accuracy of the norm.

    Returns
    -------
    gamma : float
        The H∞ norm; ``inf`` if the system is not stable.
    fpeak : float
        Frequency (rad/s) where the gain peaks (``inf`` for a peak at
        infinite frequency); ``inf`` if unstable, as MATLAB returns.

    Raises
    ------
    ParameterError
        At once if the system has a NaN or inf entry.

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> gamma, w = cx.hinfnorm(ct.tf([1], [1, 0.2, 1]))
    >>> round(gamma, 4), round(w, 3)
    (5.0252, 0.99)
    >>> cx.hinfnorm(ct.tf([1], [1, -1]))
    (inf, inf)
    """
    gamma, fpeak, failure = _norm(sys, tol)
    if failure is not None:
        warn(f"slycot ab13dd failed ({failure}); using the level-set "
             "fallback", RuntimeWarning)
    return gamma, fpeak


def hinfnorm_quiet(sys: Plant, tol: float = 1e-10) -> tuple[float, float]:
    """:func:`hinfnorm` without its warning when slycot fails: the norm a
    design's verification and trade-off report use.  The level-set
    algorithm's value is the one kept whenever it is larger anyway, so a
    design verified on it needs no note (ab13dd's QR iteration can fail on
    a far from normal error system).

    Examples
    --------
    >>> import control as ct
    >>> from controlext.norms import hinfnorm_quiet
    >>> round(hinfnorm_quiet(ct.tf([1], [1, 0.2, 1]))[0], 4)
    5.0252
    """
    return _norm(sys, tol)[:2]


def _norm(sys, tol):
    """``(γ, peak frequency, why slycot failed or None)``."""
    if isinstance(sys, ct.TransferFunction):
        if not all(np.all(np.isfinite(c)) for row in sys.num + sys.den
                   for c in row):
            raise ParameterError("hinfnorm: the transfer function has a "
                                 "NaN or inf coefficient")
        sys = ct.ss(sys)
    if not isinstance(sys, ct.StateSpace):
        raise ArgumentError(f"hinfnorm expects a linear system; found "
                            f"{type(sys).__name__}")
    for name in ('A', 'B', 'C', 'D'):
        check_finite(np.asarray(getattr(sys, name), dtype=float),
                     f"hinfnorm: {name}")
    if not is_stable(sys):
        return float('inf'), float('inf'), None
    wother, failure = np.nan, None
    try:
        gamma, fpeak = ct.linfnorm(sys, tol=tol)
    except Exception as exc:          # slycot raised (or is missing)
        failure = repr(exc)
        gamma, fpeak = _hinfnorm_fallback(sys, tol)
    else:
        # both values are gains at a frequency, so lower bounds: keep the
        # larger (ab13dd was seen to miss a discrete system's peak by
        # 0.05 %, 974.899 at 64.1 rad/s against 975.346 at 48.65)
        try:
            other, wother = _hinfnorm_fallback(sys, tol, near=fpeak)
        except (np.linalg.LinAlgError, ValueError):
            # a pole at z = -1 to rounding: no bilinear map; slycot stands
            other = -np.inf
        if other > gamma:
            gamma, fpeak = other, wother
    if sys.isdtime():
        gamma, fpeak = _attained(sys, gamma, fpeak, wother)
    return float(gamma), float(fpeak), failure


def rounding_bound(sys: Plant, *freqs: float) -> float:
    """A first-order bound on the error of the gain ``σmax(G(s))`` that
    double precision computes at the frequencies ``freqs`` (rad/s),
    largest over them.

    Solving ``(sI − A) X = B`` by LU is backward stable: it solves a
    system ``sI − A + E`` with ``‖E‖ ≤ c n eps ‖sI − A‖``, which moves the
    gain by at most ``‖C R‖ ‖E‖ ‖R B‖`` (``R`` the resolvent).  On far
    from normal error systems (gains of 1e5 and more) this is no longer
    negligible: a design's H∞ norm, the largest computed gain, may then
    lie below the true one, and :func:`hinfnorm_upper` adds the bound.

    Examples
    --------
    >>> import control as ct
    >>> from controlext.norms import rounding_bound
    >>> rounding_bound(ct.tf([1], [1, 0.2, 1]), 0.99) < 1e-12
    True
    """
    A, B, C, D = (np.asarray(M, dtype=float) for M in ct.ssdata(ct.ss(sys)))
    n = A.shape[0]
    if n == 0 or B.size == 0 or C.size == 0:
        return 0.0
    # on the balanced realisation, as the norm's own algorithms evaluate
    # it: a diagonal similarity leaves G(s) as it is, and states in mixed
    # units would otherwise inflate the bound without any loss of accuracy
    A, (d, _) = la.matrix_balance(A, permute=False, separate=True)
    B, C = B / d[:, None], C * d[None, :]
    A, B, C, D = (M.astype(complex) for M in (A, B, C, D))
    dt = 0 if not sys.dt else (1.0 if sys.dt is True else float(sys.dt))
    eps = np.finfo(float).eps
    worst = 0.0
    for w in freqs:
        if not np.isfinite(w):
            continue
        s = np.exp(1j * w * dt) if dt else 1j * w
        M = s * np.eye(n) - A
        with warnings.catch_warnings():
            # an ill-conditioned resolvent is what the bound measures
            warnings.simplefilter('ignore', la.LinAlgWarning)
            try:
                R = la.inv(M)
            except (np.linalg.LinAlgError, ValueError):
                return float('inf')
        CR, RB = C @ R, R @ B
        spread = 4 * n * eps * np.linalg.norm(M, 2)
        worst = max(worst, float(
            np.linalg.norm(CR, 2) * spread * np.linalg.norm(RB, 2) +
            n * eps * (np.linalg.norm(C, 2) * np.linalg.norm(RB, 2) +
                       np.linalg.norm(D, 2))))
    return worst if np.isfinite(worst) else float('inf')


def hinfnorm_upper(sys: Plant, gamma: float, *freqs: float
                   ) -> tuple[float, float]:
    """``(γ_up, δ)``: the norm ``gamma`` computed at the peak ``freqs``
    raised by the rounding bound ``δ`` of :func:`rounding_bound` where
    that bound shows in the eighth digit, so that the value never lies
    below the true norm of the system's binary data at its peak; ``δ`` is
    0 where the bound is below that.

    Examples
    --------
    >>> import control as ct
    >>> from controlext.norms import hinfnorm_upper
    >>> hinfnorm_upper(ct.tf([1], [1, 0.2, 1]), 5.0252, 0.99)
    (5.0252, 0.0)
    """
    if not np.isfinite(gamma) or gamma <= 0:
        return gamma, 0.0
    delta = rounding_bound(sys, *freqs)
    if delta <= 1e-8 * gamma:
        return gamma, 0.0
    return gamma + delta, delta


def hinfnorm_matrices(A, B, C, D, dt=0, tol=1e-10, poles=None):
    """:func:`hinfnorm` of ``(A, B, C, D)`` without building a system.

    Calls slycot's ``ab13dd`` directly (the inner loop of refinement) and
    falls back on the level-set algorithm when it raises.  ``poles`` (the
    eigenvalues of ``A``) may be passed when already known.
    """
    n = A.shape[0]
    if poles is None:
        poles = la.eigvals(A) if n else np.zeros(0)
    if not is_stable(poles, dt):
        return float('inf'), float('inf')
    if n == 0:
        return (float(la.svdvals(D)[0]) if D.size else 0.0), 0.0
    if _ab13dd is not None:
        try:
            jobd = 'D' if D.any() else 'Z'
            gamma, fpeak = _ab13dd('D' if dt else 'C', 'I', 'S', jobd, n,
                                   B.shape[1], C.shape[0], A, np.eye(n), B,
                                   C, D, tol)
        except Exception:       # slycot raised: the level-set fallback
            pass
        else:
            if dt:
                fpeak /= (1.0 if dt is True else dt)
            return float(gamma), float(fpeak)
    gamma, fpeak = _hinfnorm_fallback(ct.ss(A, B, C, D, dt), tol)
    return float(gamma), float(fpeak)


def _hinfnorm_fallback(sys, tol=1e-10, near=None):
    """The level-set norm ``(γ, peak frequency)``; ``near`` is the peak
    frequency another algorithm found (see :func:`_levelset`)."""
    A, B, C, D = (np.asarray(M, dtype=float) for M in ct.ssdata(sys))
    with warnings.catch_warnings():
        # scipy's note on an ill-conditioned resolvent or bilinear map (a
        # discrete design of gain 9e8: 200 of them reached the user, A + I
        # at rcond 4e-19); the values are gains at frequencies, checked by
        # the caller, and a design that far from normal has its GainWarning
        warnings.simplefilter('ignore', la.LinAlgWarning)
        if sys.isdtime():
            dt = 1.0 if sys.dt is True else float(sys.dt)
            A, B, C, D = _bilinear(A, B, C, D)
            if near is not None:
                # the bilinear image of the frequency: ν = tan(ω dt / 2)
                near = np.tan(min(abs(near) * dt, np.pi) / 2)
            gamma, nu = _levelset(A, B, C, D, tol, near=near)
            return gamma, 2 * np.arctan(nu) / dt
        return _levelset(A, B, C, D, tol, near=near)


def _attained(sys, gamma, *freqs):
    """A discrete system's norm as a gain attained on the unit circle.

    The level set runs on the bilinear image, whose realisation can be far
    worse conditioned than the system's (a 12-state design: 585,151 on the
    image against 523,329 at the true peak, which ab13dd missed with
    500,246).  The candidates' frequencies and a grid over ``[0, π/dt]``
    are evaluated on the system itself and the largest local maxima
    polished there; the image's value is kept only where no evaluation
    contradicts it by more than 1e-6.
    """
    A, B, C, D = (np.asarray(M, dtype=float) for M in ct.ssdata(sys))
    dt = 1.0 if sys.dt is True else float(sys.dt)
    n = A.shape[0]
    if n == 0:
        return gamma, freqs[0]

    def gain(theta):
        return _resolvent_gain(A, B, C, D, np.exp(1j * theta))

    grid = np.linspace(0, np.pi, 257)
    known = [min(abs(w) * dt, np.pi) for w in freqs if np.isfinite(w)]
    thetas = np.unique(np.concatenate([grid, known]))
    vals = np.array([gain(t) for t in thetas])
    best = (vals.max(), thetas[int(np.argmax(vals))])
    tops = [k for k in range(len(thetas))
            if vals[k] >= vals[max(k - 1, 0)] and
            vals[k] >= vals[min(k + 1, len(thetas) - 1)]]
    from scipy.optimize import minimize_scalar
    for k in sorted(tops, key=lambda k: vals[k])[-5:]:
        lo, hi = thetas[max(k - 1, 0)], thetas[min(k + 1, len(thetas) - 1)]
        if hi > lo:
            res = minimize_scalar(lambda t: -gain(t), bounds=(lo, hi),
                                  method='bounded',
                                  options={'xatol': 1e-13})
            best = max(best, (-res.fun, float(res.x)))
    # the claimed value at its own frequency
    if np.isfinite(freqs[0]):
        claimed = gain(min(abs(freqs[0]) * dt, np.pi))
        if claimed >= gamma * (1 - 1e-6):
            best = max(best, (gamma, min(abs(freqs[0]) * dt, np.pi)))
    return best[0], best[1] / dt


def _bilinear(A, B, C, D):
    """Continuous system with the same H∞ norm as a discrete one."""
    n = A.shape[0]
    F = la.inv(A + np.eye(n))
    return (F @ (A - np.eye(n)), np.sqrt(2) * F @ B,
            np.sqrt(2) * C @ F, D - C @ F @ B)


def _sigma_max(A, B, C, D, w):
    return _resolvent_gain(A, B, C, D, 1j * w)


def _resolvent_gain(A, B, C, D, s):
    """``σmax(C (sI − A)⁻¹ B + D)``; ``inf`` where ``sI − A`` is singular
    in floating point (a pole on the boundary to rounding: the gain there
    is unbounded, and a lower bound of the norm must not be lost)."""
    n = A.shape[0]
    with warnings.catch_warnings():
        # an ill-conditioned resolvent is what the callers look for
        warnings.simplefilter('ignore', la.LinAlgWarning)
        try:
            G = C @ la.solve(s * np.eye(n) - A, B) + D
        except (np.linalg.LinAlgError, ValueError):
            return float('inf')
    if not np.all(np.isfinite(G)):
        return float('inf')
    return la.svdvals(G)[0] if G.size else 0.0


def _levelset(A, B, C, D, tol=1e-10, maxiter=100, near=None):
    """Bruinsma-Steinbuch level-set algorithm for a stable system.

    ``near`` is the peak frequency another algorithm found (ab13dd, whose
    value this one checks): where no gain is above the gain there (one
    Hamiltonian test, at a level well above ``σmax(D)`` where the test is
    well conditioned), that is the answer, without the grid and local
    searches (the AC1 pair's 12 verifications: 0.25 s, where they took
    1.17 s); else the full search runs.
    """
    n = A.shape[0]
    if n == 0:
        return (la.svdvals(D)[0] if D.size else 0.0), 0.0
    dinf = la.svdvals(D)[0] if D.size else 0.0
    if near is not None and np.isfinite(near):
        top = _sigma_max(A, B, C, D, abs(near))
        if top > 1.01 * dinf and \
                _crossings(A, B, C, D, (1 + 2 * tol) * top).size == 0:
            return top, abs(near)
    poles = la.eigvals(A)
    size = np.abs(poles[np.abs(poles) > 0])
    # the modes' frequencies and a coarse grid over their band: a start
    # well above σmax(D) keeps the Hamiltonian well conditioned
    band = np.logspace(np.log10(size.min() / 100), np.log10(size.max() * 100),
                       60) if size.size else np.zeros(0)
    cands = np.unique([0.0] + [abs(p) for p in poles if abs(p.imag) > 0] +
                      [abs(p.real) for p in poles] + list(band))
    vals = np.array([_sigma_max(A, B, C, D, w) for w in cands])
    k = int(np.argmax(vals))
    glb, wpeak = vals[k], cands[k]
    # local searches at the highest local maxima of the candidates: a
    # level that starts at a peak's top leaves no near-double crossings
    # for the Hamiltonian test to miss (a response flat at σmax(D) with a
    # ripple of 1e-5 was missed otherwise)
    peaks = [k for k in range(1, len(cands) - 1)
             if vals[k] >= vals[k - 1] and vals[k] >= vals[k + 1]]
    for k in sorted(peaks, key=lambda k: vals[k])[-5:]:
        glb, wpeak = max((glb, wpeak), _bracket(A, B, C, D, cands[k - 1],
                                                cands[k + 1]))
    # the gain at infinite frequency is σmax(D) (the Nyquist frequency of
    # a discrete system under the bilinear map)
    if dinf > glb:
        glb, wpeak = dinf, np.inf
    for _ in range(maxiter):
        if glb == 0:
            return 0.0, 0.0
        ws = _crossings(A, B, C, D, (1 + 2 * tol) * glb)
        if ws.size == 0:
            return _polish(A, B, C, D, glb, wpeak)
        # the gain exceeds the level between crossings, and possibly
        # below the first and above the last one
        mids = list(0.5 * (ws[:-1] + ws[1:])) + [0.5 * ws[0], 2 * ws[-1]]
        vals = [_sigma_max(A, B, C, D, w) for w in mids]
        k = int(np.argmax(vals))
        if vals[k] <= glb:
            return _polish(A, B, C, D, glb, wpeak)
        glb, wpeak = vals[k], mids[k]
    return _polish(A, B, C, D, glb, wpeak)


def _crossings(A, B, C, D, g):
    """The frequencies ``ω >= 0`` where a singular value of the
    frequency response crosses the level ``g > σmax(D)`` (the Hamiltonian's
    imaginary-axis eigenvalues), sorted."""
    R = D.T @ D - g**2 * np.eye(D.shape[1])
    S = D @ D.T - g**2 * np.eye(D.shape[0])
    Ri = la.inv(R)
    H = np.block([[A - B @ Ri @ D.T @ C, -g * B @ Ri @ B.T],
                  [g * C.T @ la.inv(S) @ C, -A.T + C.T @ D @ Ri @ B.T]])
    ev = la.eigvals(H)
    # imaginary-axis eigenvalues, judged relative to their own size (a
    # crossing at high frequency has a larger rounding error)
    return np.sort(ev.imag[(np.abs(ev.real) <= 1e-5 * np.maximum(
        1.0, np.abs(ev))) & (ev.imag >= 0)])


def _bracket(A, B, C, D, lo, hi):
    """The largest gain between ``lo`` and ``hi`` (a bounded search)."""
    from scipy.optimize import minimize_scalar
    res = minimize_scalar(lambda w: -_sigma_max(A, B, C, D, w),
                          bounds=(lo, hi), method='bounded',
                          options={'xatol': 1e-12 * max(hi, 1e-300)})
    return -res.fun, float(res.x)


def _polish(A, B, C, D, glb, wpeak, spread=2.0):
    """A last local search around a finite peak (every value found is a
    lower bound of the norm, so the largest is kept)."""
    if not np.isfinite(wpeak) or wpeak == 0:
        return glb, wpeak
    from scipy.optimize import minimize_scalar
    res = minimize_scalar(lambda w: -_sigma_max(A, B, C, D, w),
                          bounds=(wpeak / spread, spread * wpeak),
                          method='bounded',
                          options={'xatol': 1e-12 * wpeak})
    if -res.fun > glb:
        return -res.fun, float(res.x)
    return glb, wpeak
