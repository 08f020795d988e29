"""The generalised plant: one description that every observer reduces to.

::

              w (noise, disturbance)
              │
        ┌─────▼──────────────────────────┐
        │ x' = A x + B u + Bw w          │
        │ y  = C x + D u + Dw w          ├──► z = Cz x   (what is estimated)
        └─────┬──────────────────────────┘
              │ y
        ┌─────▼──────────────────────────────────────────────────┐
        │ N coupled copies  x̂_i' = A x̂_i + B u                   │
        │                       − Σ_j G_ij (C x̂_j + D u − y)     │
        │ x̄ = Σ_i c_i x̂_i                                        │
        └────────────────────────────────────────────────────────┘

With ``Ae = I_N ⊗ A``, ``Ce = I_N ⊗ C``, ``Bwe = 1_N ⊗ Bw``,
``Dwe = 1_N ⊗ Dw``, ``Cze = cᵀ ⊗ Cz`` and ``e_i = x̂_i − x``, the error obeys

    e' = (Ae − G Ce) e + (G Dwe − Bwe) w,      z̄ = Cze e.

``N = 1`` is the Luenberger observer (3) of Li & Sanfelice, ``N = 2`` their
coupled pair (17)/(28) with ``G = Mu = [[K1, L1], [L2, K2]]``. The GI
observer is the same problem with ``Bw (I − Π)`` and ``Dw = I − Π``.

Examples
--------
>>> import numpy as np
>>> from controlext.problem import ObserverProblem
>>> prob = ObserverProblem(A=[[-0.5]], C=[[1.0]], copies=2)
>>> prob.gain_shape
(2, 2)
>>> Acl, Bcl, Ccl, Dcl = prob.error_system(np.diag([2.0, 2.0]))
>>> (Acl + 0.0).tolist(), Bcl.ravel().tolist(), Ccl.tolist()
([[-2.5, 0.0], [0.0, -2.5]], [2.0, 2.0], [[0.5, 0.5]])
"""

from functools import cached_property

import numpy as np

from ._checks import as_matrix, noise_model
from .exceptions import ArgumentError, DimensionError, ParameterError

__all__ = ['ObserverProblem']


class ObserverProblem:
    """Generalised observer plant for ``copies`` coupled observers.

    Parameters
    ----------
    A, C : array_like
        Plant dynamics and measurement matrices (``n × n``, ``p × n``).
    Bw, Dw, Cz : array_like, optional
        Noise model (defaults ``0``, ``I_p``, ``I_n``).
    copies : int, optional
        Number of coupled observer copies ``N >= 1``.
    weights : array_like, optional
        Output weights ``c`` (length ``N``, summing to 1; default ``1/N``).
    dt : float or None, optional
        Sampling time (0 for continuous time, python-control's convention).
    """

    def __init__(self, A, C, Bw=None, Dw=None, Cz=None, copies=1,
                 weights=None, dt=0):
        A = as_matrix(A, 'A', (None, None))
        n = A.shape[0]
        if A.shape != (n, n):
            raise DimensionError(f"A must be square; found shape {A.shape}")
        C = as_matrix(C, 'C', (None, n))
        self.A, self.C = A, C
        self.Bw, self.Dw, self.Cz = noise_model(n, C.shape[0], Bw, Dw, Cz)
        if isinstance(copies, bool) or not isinstance(copies, (int, np.integer)):
            raise ArgumentError(f"copies must be an integer; found "
                                f"{type(copies).__name__}")
        if copies < 1:
            raise ParameterError(f"copies must be >= 1; found {copies}")
        self.copies = int(copies)
        self.weights = check_weights(weights, self.copies)
        self.dt = dt

    # sizes
    n = property(lambda self: self.A.shape[0], doc="plant states")
    p = property(lambda self: self.C.shape[0], doc="measurements")
    q = property(lambda self: self.Bw.shape[1], doc="noise channels")
    nz = property(lambda self: self.Cz.shape[0], doc="estimated outputs")

    @property
    def gain_shape(self):
        """Shape ``(N n, N p)`` of the coupled gain ``G``."""
        return (self.copies * self.n, self.copies * self.p)

    @cached_property
    def Ae(self):
        return np.kron(np.eye(self.copies), self.A)

    @cached_property
    def Ce(self):
        return np.kron(np.eye(self.copies), self.C)

    @cached_property
    def Bwe(self):
        return np.kron(np.ones((self.copies, 1)), self.Bw)

    @cached_property
    def Dwe(self):
        return np.kron(np.ones((self.copies, 1)), self.Dw)

    @cached_property
    def Cze(self):
        return np.kron(self.weights.reshape(1, -1), self.Cz)

    @property
    def noise_scale(self):
        """Size of the noise-to-error channel ``‖Cze‖ (‖Bwe‖ + ‖Dwe‖)``."""
        return float(np.linalg.norm(self.Cze, 2) *
                     (np.linalg.norm(self.Bwe, 2) +
                      np.linalg.norm(self.Dwe, 2)))

    def error_system(self, G):
        """Matrices ``(Acl, Bcl, Ccl, Dcl)`` of the error system for gain G."""
        G = np.asarray(G, dtype=float)
        return (self.Ae - G @ self.Ce, G @ self.Dwe - self.Bwe, self.Cze,
                np.zeros((self.nz, self.q)))

    def replace(self, **changes):
        """A copy with some fields changed."""
        fields = dict(A=self.A, C=self.C, Bw=self.Bw, Dw=self.Dw, Cz=self.Cz,
                      copies=self.copies, weights=None, dt=self.dt)
        if 'copies' not in changes:
            fields['weights'] = self.weights
        fields.update(changes)
        return ObserverProblem(**fields)


def check_weights(weights, copies):
    """Output weights as an array of length ``copies`` summing to one."""
    if weights is None:
        return np.full(copies, 1.0 / copies)
    try:
        w = np.array(weights, dtype=float).ravel()
    except (TypeError, ValueError) as exc:
        raise ArgumentError("weights must be a sequence of numbers; found "
                            f"{type(weights).__name__}") from exc
    if w.size != copies:
        raise DimensionError(f"weights has the wrong length; expected "
                             f"{copies} (one per copy) instead of {w.size}")
    if not np.all(np.isfinite(w)):
        raise ParameterError(f"weights must be finite; found {w.tolist()}")
    if abs(w.sum() - 1) > 1e-9:
        raise ParameterError(f"weights must sum to 1; found sum "
                             f"{w.sum():.6g} for weights {w.tolist()}")
    return w
