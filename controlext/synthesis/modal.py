"""The modal convex stage: the LMI on the modes that must move.

On a large plant most modes often lie well inside the pole region already
(flexible structures, aircraft: a few slow or unstable modes, many fast
ones).  With an ordered real Schur form ``A = U T Uᵀ``,

::

    T = [[T11, T12],      T11: the k modes outside or near the region
         [0,   T22]],     T22: the others, inside it with a margin

and a gain acting on the first ``k`` Schur coordinates only,
``L = U₁ L₁``, the error in Schur coordinates ``ξ = Uᵀ e`` obeys

    ξ₁' = (T11 − L₁ C U₁) ξ₁ + (T12 − L₁ C U₂) ξ₂ + (L₁ Dw − U₁ᵀ Bw) w,
    ξ₂' = T22 ξ₂ − U₂ᵀ Bw w.

Its poles are those of ``T11 − L₁ C U₁`` and of ``T22``; and when the noise
does not reach the fast coordinates (``U₂ᵀ Bw = 0``: measurement noise
only, the default noise model) ``ξ₂`` stays zero, so the noise-to-error
system is exactly the k-state one ``(T11 − L₁ C₁, L₁ Dw − Bw₁, Cz U₁)``.
Its LMI certifies the full design and costs ``k^3.7`` instead of ``n^3.7``
(60 states with 14 slow: 0.7 s against 155 s).  The restriction to
``L = U₁ L₁`` is the price: refinement then works on the full gain.

Examples
--------
>>> import numpy as np
>>> import controlext as cx
>>> from controlext.synthesis.problem import ObserverProblem
>>> from controlext.synthesis.modal import modal_split
>>> A = np.diag([0.5, -0.3, -5.0, -6.0])
>>> U, k = modal_split(A, cx.HalfPlane(1.0))
>>> slow = np.linalg.eigvals((U.T @ A @ U)[:k, :k]).real
>>> k, np.sort(slow).round(6).tolist()
(2, [-0.3, 0.5])
"""

import numpy as np
import scipy.linalg as la

from .problem import ObserverProblem

__all__ = ['modal_split', 'modal_applies', 'modal_problem']

def modal_split(A, region, guard=0.05):
    """Ordered real Schur basis ``U`` and the number ``k`` of slow modes
    (outside ``region`` or within ``guard · max(1, |Re λ|)`` of its
    boundary; the real part, so that lightly damped high-frequency modes
    of a flexible structure count as fast)."""
    A = np.asarray(A, dtype=float)

    def slow(re, im):
        lam = np.atleast_1d(re + 1j * im)
        return bool(region.worst_margin(lam) >
                    -guard * max(1.0, abs(lam[0].real)))

    T, U, k = la.schur(A, output='real', sort=slow)
    return U, int(k)


def modal_applies(prob, region, max_states, guard=0.05):
    """``(U, k)`` when the modal stage applies to ``prob``: a region, fewer
    than ``n`` but at least one slow mode, at most ``max_states`` of them,
    and noise that does not reach the fast Schur coordinates; else None.

    Examples
    --------
    >>> import controlext as cx
    >>> from controlext.synthesis.problem import ObserverProblem
    >>> from controlext.synthesis.modal import modal_applies
    >>> prob = ObserverProblem(A=[[0.5, 0.0], [0.0, -5.0]], C=[[1.0, 1.0]])
    >>> modal_applies(prob, cx.HalfPlane(1.0), 40)[1]
    1
    >>> modal_applies(prob, None, 40) is None
    True
    """
    if region is None or prob.copies != 1:
        return None
    U, k = modal_split(prob.A, region, guard)
    if not 0 < k <= max_states or k == prob.n:
        return None
    leak = np.linalg.norm(U[:, k:].T @ prob.Bw)
    if leak > 1e-9 * (1.0 + np.linalg.norm(prob.Bw)):
        return None
    return U, k


def modal_problem(prob, U, k):
    """The k-state problem ``(T11, C U₁, U₁ᵀ Bw, Dw, Cz U₁)``; a gain
    ``L₁`` of it is ``U₁ L₁`` for ``prob``.

    Examples
    --------
    >>> import controlext as cx
    >>> from controlext.synthesis.problem import ObserverProblem
    >>> from controlext.synthesis.modal import modal_applies, modal_problem
    >>> prob = ObserverProblem(A=[[0.5, 0.0], [0.0, -5.0]], C=[[1.0, 1.0]])
    >>> U, k = modal_applies(prob, cx.HalfPlane(1.0), 40)
    >>> sub = modal_problem(prob, U, k)
    >>> sub.A.round(6).tolist(), abs(sub.C).round(6).tolist()
    ([[0.5]], [[1.0]])
    >>> sub.Cz.shape            # Cz = I compressed to the slow coordinates
    (1, 1)
    """
    U1 = U[:, :k]
    Cz = prob.Cz @ U1
    if Cz.shape[0] > k:
        # ‖Cz U₁ ξ‖ = ‖R ξ‖ with Cz U₁ = Q R: k outputs instead of nz keep
        # the bounded-real block small (n = 60, Cz = I: 76 -> 30 rows)
        Cz = np.linalg.qr(Cz, mode='r')
    return ObserverProblem(U1.T @ prob.A @ U1, prob.C @ U1, U1.T @ prob.Bw,
                           prob.Dw, Cz, dt=prob.dt)
