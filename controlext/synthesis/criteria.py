"""What a design is judged by: the norm it minimises and the bounds it keeps.

By default a design minimises the H∞ norm from noise to estimation error
(the worst-case noise gain γ).  :class:`Criteria` lets the user choose

* ``objective='hinf'`` or ``'h2'`` — the H2 norm is the RMS estimation
  error under unit white noise (``control.norm(obs, 2)``), what a Kalman
  filter minimises;
* ``max_hinf=`` / ``max_h2=`` — a bound on the other norm: the mixed
  H2/H∞ problem of MATLAB's ``h2hinfsyn`` (the best white-noise error
  whose worst-case gain stays below a bound, or the reverse);
* ``settling_time=`` — the averaged error from the worst unit initial
  error settles within 2 % of its start by this time;
* ``gain_tolerance=`` — the error poles stay in the region under relative
  errors of this size in every gain entry (``5e-6`` for gains printed to
  6 significant digits), certified (:mod:`~controlext.synthesis.limits`).

The same criteria are held by every stage: the convex stage as LMIs with
one Lyapunov matrix (:mod:`~controlext.synthesis.lmi`, conservative and
certified; the two limits are not convex and only refinement holds
them), refinement as exact penalties on the true norms
(:mod:`~controlext.synthesis.objective`), and verification on the
returned design (:func:`~controlext.synthesis.verify.verify_design`).

The H2 norm of ``(A, B, C, 0)`` and its gradient come from the two
Gramians: with ``Aᵀ Q + Q A + Cᵀ C = 0`` and ``A P + P Aᵀ + B Bᵀ = 0``
(their Stein forms in discrete time), ``J = ‖T‖₂² = tr(Bᵀ Q B)``,
``∂J/∂B = 2 Q B`` and ``∂J/∂A = 2 Q P`` (``2 Q A P`` in discrete time).

Examples
--------
>>> from controlext.synthesis.criteria import Criteria, h2_norm
>>> Criteria(objective='h2', max_hinf=0.9).bounds
(('hinf', 0.9),)
>>> round(h2_norm([[-2.0]], [[1.0]], [[1.0]]), 6)        # 1 / sqrt(4)
0.5
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np
import scipy.linalg as la

from .._checks import check_choice, check_number
from .._warn import warn
from ..exceptions import ArgumentError

try:
    from slycot import sb03md57 as _sb03md, sb03od as _sb03od
except ImportError:         # pragma: no cover - a required dependency
    _sb03md = _sb03od = None

__all__ = ['Criteria', 'OBJECTIVES', 'h2_norm', 'h2_parts', 'NAMES']

#: the norms a design may minimise
OBJECTIVES = ('hinf', 'h2')
#: how a norm is named to a user
NAMES = {'hinf': 'H∞ norm', 'h2': 'H2 norm'}
#: how a limit is named to a user
LIMIT_NAMES = {'settling_time': 'settling within',
               'gain_tolerance': 'region kept under relative gain errors'}


@dataclass(frozen=True)
class Criteria:
    """The norm a design minimises and the bound it keeps on the other.

    Attributes
    ----------
    objective : {'hinf', 'h2'}
        The norm from noise to estimation error that is minimised.
    max_hinf, max_h2 : float or None
        A bound on the norm that is not minimised (``max_hinf`` with
        ``objective='h2'``, ``max_h2`` with ``objective='hinf'``).
    settling_time : float or None
        The latest 2 % settling time of the averaged error from the worst
        unit initial error (in the plant's time units).
    gain_tolerance : float or None
        The relative error of every gain entry under which the error poles
        must stay in the region (in ``[0, 0.1]``; 0 or None: none, the
        nominal optimum).
    """
    objective: str = 'hinf'
    max_hinf: float | None = None
    max_h2: float | None = None
    settling_time: float | None = None
    gain_tolerance: float | None = None

    def __post_init__(self):
        set_ = lambda name, value: object.__setattr__(self, name, value)
        set_('objective', check_choice(self.objective, 'objective',
                                       OBJECTIVES))
        for name in ('max_hinf', 'max_h2'):
            set_(name, check_number(getattr(self, name), name, low=0,
                                    low_open=True, optional=True))
        set_('settling_time', check_number(
            self.settling_time, 'settling_time', low=0, low_open=True,
            optional=True))
        set_('gain_tolerance', check_number(
            self.gain_tolerance, 'gain_tolerance', low=0, high=0.1,
            optional=True))
        own = getattr(self, f'max_{self.objective}')
        if own is not None:
            other = 'h2' if self.objective == 'hinf' else 'hinf'
            raise ArgumentError(
                f"max_{self.objective}= bounds the norm that "
                f"objective='{self.objective}' minimises already; bound the "
                f"other one (max_{other}=) or minimise the other "
                f"(objective='{other}')")

    @property
    def default(self) -> bool:
        """Is this the plain H∞ design (no H2 involved)?"""
        return self.objective == 'hinf' and self.max_h2 is None

    @property
    def bounds(self) -> tuple[tuple[str, float], ...]:
        """``((norm, bound), ...)`` of the bounded norms."""
        return tuple((name, value) for name, value in
                     (('hinf', self.max_hinf), ('h2', self.max_h2))
                     if value is not None)

    @property
    def limits(self) -> tuple[tuple[str, float], ...]:
        """``((name, value), ...)`` of the limits that are not norms
        (settling time, gain tolerance): refinement holds them, the
        convex stage does not."""
        return tuple((name, value) for name, value in
                     (('settling_time', self.settling_time),
                      ('gain_tolerance', self.gain_tolerance))
                     if value)

    @property
    def convex(self) -> Criteria:
        """The criteria without their limits: what the convex stage holds."""
        return Criteria(self.objective, self.max_hinf, self.max_h2) \
            if self.limits else self

    @property
    def norms(self) -> tuple[str, ...]:
        """Every norm the criteria involve, the objective first."""
        return (self.objective,) + tuple(name for name, _ in self.bounds)

    def value(self, report) -> float:
        """The objective's value on a design report."""
        return float(getattr(report, self.objective))

    def __str__(self) -> str:
        text = f"minimise the {NAMES[self.objective]}"
        for name, bound in self.bounds:
            text += f", {NAMES[name]} <= {bound:.6g}"
        for name, value in self.limits:
            text += f", {LIMIT_NAMES[name]} {value:.6g}"
        return text


def stable_poles(lam, dt=0) -> bool:
    """Are the poles ``lam`` inside the stability region?"""
    lam = np.asarray(lam)
    return bool(np.all(np.abs(lam) < 1)) if dt else \
        bool(np.all(lam.real < 0))


def _stein(A: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """``P`` with ``A P Aᵀ − P + Q = 0`` for a Schur-stable ``A``:
    SLICOT's ``SB03MD`` (Bartels–Stewart on the real Schur form), or the
    same in the complex Schur form where slycot raises."""
    if _sb03md is not None:
        n = A.shape[0]
        try:
            # op(A)ᵀ X op(A) − X = scale · C with op(A) = Aᵀ, C = −Q
            out = _sb03md(np.array(A, dtype=float), np.zeros((n, n)),
                          -np.array(Q, dtype=float), 'D', job='X',
                          fact='N', trana='T')
        except Exception:       # slycot raised: the fallback below
            pass
        else:
            X, scale = out[2], out[3]
            return (X + X.T) / (2 * scale)
    return _stein_schur(A, Q)


def _stein_schur(A: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """``P`` with ``A P Aᵀ − P + Q = 0`` for a Schur-stable ``A``, in the
    complex Schur form ``A = Z T Zᴴ``: column ``j`` of ``Y = Zᴴ P Z``
    solves the triangular system ``(I − conj(t_jj) T) y_j = q̃_j +
    T Σ_{l>j} conj(t_jl) y_l``, last column first."""
    T, Z = la.schur(np.asarray(A, dtype=complex), output='complex')
    Qt = Z.conj().T @ Q @ Z
    n = T.shape[0]
    Y = np.zeros((n, n), dtype=complex)
    eye = np.eye(n)
    for j in range(n - 1, -1, -1):
        rhs = Qt[:, j] + T @ (Y[:, j + 1:] @ T[j, j + 1:].conj())
        Y[:, j] = la.solve_triangular(eye - np.conj(T[j, j]) * T, rhs)
    P = (Z @ Y @ Z.conj().T).real
    return (P + P.T) / 2


def _lyap_schur(A: np.ndarray, Q: np.ndarray) -> np.ndarray | None:
    """``P`` with ``A P + P Aᵀ + Q = 0`` for a Hurwitz ``A``, in the
    complex Schur form ``A = Z T Zᴴ`` (``None`` where two poles sum to
    zero to working precision, both on the imaginary axis): column ``j``
    of ``Y = Zᴴ P Z`` solves the triangular system ``(T + conj(t_jj) I)
    y_j = −q̃_j − Σ_{l>j} conj(t_jl) y_l``, last column first.  Its
    triangular solves divide by the pole sums ``λ_i + conj(λ_j)`` only,
    where the real Schur form's 2×2 blocks of a far from normal ``A``
    may look singular to LAPACK's pivot test."""
    T, Z = la.schur(np.asarray(A, dtype=complex), output='complex')
    poles = np.diag(T)
    n = T.shape[0]
    if n and np.min(np.abs(2 * poles.real)) <= \
            n * np.finfo(float).eps * np.abs(T).max():
        return None
    Qt = Z.conj().T @ Q @ Z
    Y = np.zeros((n, n), dtype=complex)
    eye = np.eye(n)
    for j in range(n - 1, -1, -1):
        rhs = -Qt[:, j] - Y[:, j + 1:] @ T[j, j + 1:].conj()
        Y[:, j] = la.solve_triangular(T + np.conj(T[j, j]) * eye, rhs)
    P = (Z @ Y @ Z.conj().T).real
    return (P + P.T) / 2


def gramian(A: np.ndarray, Q: np.ndarray, dt: float = 0) -> np.ndarray:
    """``P`` with ``A P + P Aᵀ + Q = 0`` (``A P Aᵀ − P + Q = 0`` when
    ``dt``) for a stable ``A``, solved on the balanced ``D⁻¹ A D`` (``D``
    diagonal, powers of 2): the solvers judge the poles against ``‖A‖``,
    which states in mixed units inflate (a design for the second-order
    plant in states scaled by 1e-3 and 1e3, ‖A‖ 1.3e6, poles -1 ± 0.35j:
    scipy took its poles for a pair summing to zero, and its Gramian had
    a negative diagonal)."""
    A = np.asarray(A, dtype=float)
    if A.size:
        A, (d, _) = la.matrix_balance(A, permute=False, separate=True)
        P = _gramian(A, np.asarray(Q) / np.outer(d, d), dt)
        return P * np.outer(d, d)
    return _gramian(A, Q, dt)


def _gramian(A, Q, dt):
    if not dt:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter('always')
            P = la.solve_continuous_lyapunov(A, -Q)
        marginal = False
        for w in caught:
            if 'eigenvalue pair' in str(w.message):
                # scipy found two poles summing to zero: both on the
                # imaginary axis, where the Gramian is unbounded — or a
                # far from normal A whose 2×2 Schur blocks its pivot test
                # took for singular; the complex Schur form tells them
                # apart
                marginal = True
            else:
                warn(str(w.message), w.category)
        if not marginal:
            return P
        P = _lyap_schur(A, Q)
        return np.full((A.shape[0],) * 2, np.inf) if P is None else P
    # in the Schur form: on far from normal error matrices scipy's solvers
    # lose what it keeps (its Kronecker solve squares the conditioning,
    # its bilinear route inverts A + I)
    return _stein(A, Q)


def gramian_factor(A: np.ndarray, B: np.ndarray,
                   dt: float = 0) -> np.ndarray | None:
    """``U`` with ``P = U Uᵀ`` the controllability Gramian of a stable
    ``(A, B)`` (``A P + P Aᵀ + B Bᵀ = 0``, or ``A P Aᵀ − P + B Bᵀ = 0``
    when ``dt``), by Hammarling's method (SLICOT's ``SB03OD``) on the
    balanced ``D⁻¹ A D`` (see :func:`gramian`); None where slycot raises
    or warns (a pole on or near the stability boundary).

    The factor makes ``P`` positive semidefinite by construction: on far
    from normal matrices the solvers of :func:`gramian` may return an
    indefinite ``P`` whose traces cancel, and the H2 norm read 0 where the
    exact Gramian gives millions."""
    if _sb03od is None:     # pragma: no cover - a required dependency
        return None
    A = np.asarray(A, dtype=float)
    B = np.asarray(B, dtype=float)
    n, m = B.shape
    if n == 0:
        return np.zeros((0, 0))
    A, (d, _) = la.matrix_balance(A, permute=False, separate=True)
    work = np.zeros((n, max(m, n)))
    work[:, :m] = B / d[:, None]
    with warnings.catch_warnings():
        # slycot warns where the equation is nearly singular: the caller
        # decides there
        warnings.simplefilter('error')
        try:
            # op(A) = Aᵀ, op(B) = Bᵀ: A X Aᵀ − X = −scale² B Bᵀ, X = U Uᵀ
            U, scale, poles = _sb03od(n, m, A.copy(), np.zeros((n, n)),
                                      work, 'D' if dt else 'C', trans='T')
        except Exception:
            return None
    edge = 1.0 - np.abs(poles) if dt else -2.0 * poles.real
    scale_a = max(np.abs(A).max(), 1.0)
    if np.min(edge) <= n * np.finfo(float).eps * scale_a:
        # on the boundary to working precision: :func:`gramian` decides
        return None
    U = np.triu(U[:n, :n])
    if not scale > 0 or not np.all(np.isfinite(U)):
        return None
    return d[:, None] * U / scale


def h2_norm(A, B, C, dt: float = 0) -> float:
    """H2 norm of ``(A, B, C, 0)``: ``‖C U‖_F`` with ``U`` the Cholesky
    factor of its controllability Gramian (``inf`` if unstable)."""
    A, B, C = (np.asarray(M, dtype=float) for M in (A, B, C))
    if A.shape[0] == 0:
        return 0.0
    if not stable_poles(la.eigvals(A), dt):
        return float('inf')
    U = gramian_factor(A, B, dt)
    if U is not None:
        return float(np.linalg.norm(C @ U))
    P = gramian(A, B @ B.T, dt)
    if not np.all(np.isfinite(P)):
        return float('inf')
    return float(np.sqrt(max(np.trace(C @ P @ C.T), 0.0)))


def _search_gramian(A, Q, factor_of, dt):
    """The Gramian ``P`` solving the equation of ``Q = F Fᵀ`` for the
    search: from :func:`gramian`, or from the factor of
    :func:`gramian_factor` (``factor_of()`` gives ``F``) where that ``P``
    is visibly wrong, with a negative diagonal entry.  (The search's paths
    were measured with the former; with the factor throughout, H2 designs
    moved by rounding alone, the quadruple tank's three copies from
    0.5534 to 0.6042.)"""
    P = gramian(A, Q, dt)
    if np.all(np.isfinite(P)) and np.any(np.diag(P) < 0):
        U = gramian_factor(A, factor_of(), dt)
        if U is not None:
            return U @ U.T
    return P


def h2_parts(A: np.ndarray, B: np.ndarray, C: np.ndarray, dt: float = 0,
             gradient: bool = True):
    """``(h, dh/dA, dh/dB)`` of the H2 norm ``h`` of a stable
    ``(A, B, C, 0)`` (the derivatives None without ``gradient``; zero
    where ``h = 0``, a minimum)."""
    Q = _search_gramian(A.T, C.T @ C, lambda: C.T, dt)
    if not np.all(np.isfinite(Q)):
        return np.inf, (np.zeros_like(A) if gradient else None), \
            (np.zeros_like(B) if gradient else None)
    J = float(np.sum(B * (Q @ B)))
    if J < 0:
        # rounding made the Gramian indefinite; its factor cannot be
        W = gramian_factor(A.T, C.T, dt)
        if W is not None:
            Q = W @ W.T
            J = float(np.sum((W.T @ B) ** 2))
    h = float(np.sqrt(max(J, 0.0)))
    if not gradient:
        return h, None, None
    if h == 0.0 or not np.isfinite(h):
        return h, np.zeros_like(A), np.zeros_like(B)
    P = _search_gramian(A, B @ B.T, lambda: B, dt)
    if not np.all(np.isfinite(P)):
        return np.inf, np.zeros_like(A), np.zeros_like(B)
    dA = Q @ (A @ P if dt else P)
    return h, dA / h, (Q @ B) / h
