"""Pole placement for observers, also with redundant sensors.

The gain is found through an orthonormal basis ``U`` of ``range(C)``
(``C = U Cr``, ``L = Lr Uᵀ``, so ``L C = Lr Cr``): redundant sensors do
not make the placement ill-posed, and the gain acts only through
``range(C)``.  Distinct poles use python-control's robust placement;
a pole repeated more often than ``rank C`` allows there uses
``place_varga``.

Examples
--------
>>> import numpy as np
>>> from controlext.synthesis.placement import place_gain
>>> L = place_gain(np.array([[0.0, 1.0], [0.0, 0.0]]),
...                np.array([[1.0, 0.0]]), [-2.0, -2.0])
>>> np.round(L, 6).ravel().tolist()
[4.0, 4.0]
"""

import warnings

import numpy as np
import scipy.linalg as la
import control as ct

from ..exceptions import ParameterError

__all__ = ['place_gain', 'placement_error', 'interior_poles',
           'partial_gain']


def place_gain(A, C, poles):
    """Observer gain ``L`` with the eigenvalues of ``A − L C`` at
    ``poles``; raises :class:`ParameterError` when placement fails."""
    Usv, sv, _ = np.linalg.svd(C, full_matrices=False)
    U = Usv[:, :int(np.sum(sv > 1e-10 * max(1.0, sv[0])))]
    Cr = U.T @ C
    poles = np.asarray(poles)
    _, counts = np.unique(np.round(poles, 9), return_counts=True)
    tries = [ct.place_varga] if counts.max() > Cr.shape[0] else \
        [ct.place, ct.place_varga]
    best, failure = None, None
    for method in tries:
        try:
            with warnings.catch_warnings():
                # place's "convergence was not reached" is about its
                # robustness iteration; the poles placed are measured
                # below, and place_varga is tried when they miss
                warnings.simplefilter('ignore', UserWarning)
                L = method(A.T, Cr.T, poles).T @ U.T
        except (ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
            failure = exc
            continue
        miss = placement_error(np.linalg.eigvals(A - L @ C), poles)
        if best is None or miss < best[0]:
            best = (miss, L)
        if miss <= 1e-8 * max(1.0, np.max(np.abs(poles))):
            break
    if best is None:
        raise ParameterError(
            f"pole placement failed: {failure} (a pole may be repeated more "
            f"often than the {U.shape[1]} independent measurements, "
            "rank(C), allow)") from failure
    return best[1]


def placement_error(placed, poles):
    """The largest distance from a placed pole to its requested one."""
    left = list(poles)
    worst = 0.0
    for x in placed:
        k = int(np.argmin([abs(x - y) for y in left]))
        worst = max(worst, abs(x - left.pop(k)))
    return worst


def interior_poles(A, region, dt=0):
    """``n`` distinct real points inside ``region`` (and the stability
    region), at the scale of ``A``'s spectrum: starts for a design when
    the convex routes fail.

    Examples
    --------
    >>> import numpy as np
    >>> import controlext as cx
    >>> from controlext.synthesis.placement import interior_poles
    >>> poles = interior_poles(np.diag([1.0, -3.0]), cx.HalfPlane(1.0))
    >>> bool(np.all(poles < -1.0)), len(set(poles.tolist()))
    (True, 2)
    """
    n = A.shape[0]
    a, b = region.stable_interval(dt)
    if not dt:
        scale = max(1.0, float(np.max(np.abs(np.linalg.eigvals(A)))),
                    abs(b))
        a = max(a, b - 2 * scale)
    width = b - a
    return np.linspace(b - 0.1 * width, a + 0.1 * width, n) if n > 1 else \
        np.array([0.5 * (a + b)])


#: a pole of ``A`` within this (relative to ``max(1, |λ|)``) of the
#: region's edge is moved by :func:`partial_gain`
EDGE = 1e-3


def partial_gain(A, C, region, stable, dt=0):
    """Observer gain that moves only the eigenvalues of ``A`` outside
    ``region`` or ``stable`` (or within :data:`EDGE` of an edge) and keeps
    the others: placement on the leading block of the real Schur form
    ordered with the moved ones first (``A Z₁ = Z₁ T₁₁``, ``L = Z₁ L₁``,
    so the error matrix is block triangular with ``T₁₁ − L₁ C Z₁`` and
    the kept block); the zero gain when none has to move.

    Moving all ``n`` poles of a plant whose poles cluster is
    ill-conditioned where keeping most of them is not: the full
    placement of a plant already inside its region can come out
    unstable.

    Examples
    --------
    >>> import numpy as np
    >>> import controlext as cx
    >>> from controlext.synthesis.placement import partial_gain
    >>> A = np.diag([-3.0, 1.0])
    >>> L = partial_gain(A, np.ones((1, 2)), cx.HalfPlane(1.0),
    ...                  cx.HalfPlane(0.0))
    >>> poles = np.sort(np.linalg.eigvals(A - L @ np.ones((1, 2))).real)
    >>> bool(poles[0] == -3.0 or abs(poles[0] + 3.0) < 1e-9), bool(
    ...     poles[1] < -1.0)
    (True, True)
    """
    A = np.asarray(A, dtype=float)
    C = np.asarray(C, dtype=float)

    def moved(re, im):
        lam = complex(re, im)
        worst = max(region.worst_margin(lam), stable.worst_margin(lam))
        return bool(worst > -EDGE * max(1.0, abs(lam)))

    T, Z, k = la.schur(A, output='real', sort=moved)
    if k == 0:
        return np.zeros((A.shape[0], C.shape[0]))
    Z1 = Z[:, :k]
    poles = interior_poles(T[:k, :k], region, dt)
    return Z1 @ place_gain(T[:k, :k], C @ Z1, poles)
