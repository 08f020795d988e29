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

The runnable estimator comes from the same description.  Each copy has
``m`` states ``ξ_i`` (``m = n``, or ``n + r`` with the disturbance
estimate of the augmented GI observer), sees the measurement through a
map ``M`` and may feed it forward through ``F``::

    ξ_i' = A ξ_i + B u − Σ_j G_ij (C ξ_j − M (y − D u)) + F (y − D u)
    x̂   = Σ_i c_i [I_n 0] ξ_i

(``M = I``, ``F = 0`` for the Luenberger and coupled observers,
``M = I − Π`` and ``F = [Bw Π; 0]`` for GI).  With the plant's own noise
model ``(Bw_p, Dw_p)``, ``M C_p = C_p`` and ``F C_p = 0``, the error
``ξ_i − [x; 0]`` obeys the error system above with ``Dw = M Dw_p`` and
``Bw = [Bw_p; 0] − F Dw_p``: :meth:`ObserverProblem.estimator_matrices`
and :meth:`ObserverProblem.error_system` cannot disagree.

Examples
--------
>>> import numpy as np
>>> from controlext.synthesis import ObserverProblem
>>> prob = ObserverProblem(A=[[-0.5]], C=[[1.0]], copies=2)
>>> prob.gain_shape
(2, 2)
>>> Acl, Bcl, Ccl, Dcl = prob.error_system(np.diag([2.0, 2.0]))
>>> (Acl + 0.0).tolist(), Bcl.ravel().tolist(), Ccl.tolist()
([[-2.5, 0.0], [0.0, -2.5]], [2.0, 2.0], [[0.5, 0.5]])
"""

from __future__ import annotations

from functools import cached_property
from typing import Any

import numpy as np

from .._checks import (as_matrix, as_plant, check_copies, check_weights,
                       noise_model, signal_names, timebase)
from .._typing import Array, ArrayLike, Names
from ..exceptions import DimensionError, ParameterError

__all__ = ['ObserverProblem', 'plant_problem', 'signals_of']


class ObserverProblem:
    """Generalised observer plant for ``copies`` coupled observers.

    Parameters
    ----------
    A, C : array_like
        Design dynamics and measurement matrices (``m × m``, ``p × m``).
    Bw, Dw, Cz : array_like, optional
        Noise model of the error system (defaults ``0``, ``I_p``,
        ``I_m``).
    copies : int, optional
        Number of coupled observer copies ``N >= 1``.
    weights : array_like, optional
        Output weights ``c`` (length ``N``, summing to 1; default ``1/N``).
    dt : float or None, optional
        Sampling time (0 for continuous time, python-control's convention).
    B, D : array_like, optional
        The plant's input matrices (``m × nu`` in design coordinates,
        ``p × nu``); default no inputs.
    measure, feed : array_like, optional
        The estimator's measurement map ``M`` (``p × p``, default ``I``)
        and measurement feed-forward ``F`` (``m × p``, default 0).
    states : int, optional
        Number ``n <= m`` of plant states: the estimate is the first ``n``
        design states (default ``m``).
    plant_noise : (array_like, array_like), optional
        The plant's own ``(Bw_p, Dw_p)``, how a disturbance enters the
        plant (default: ``(Bw[:n], Dw)``, right when ``M = I``, ``F = 0``).
    extra_outputs : (str, array_like), optional
        A label and a map ``(k × (m − n))`` of further estimator outputs
        from the extra design states (the disturbance estimate).
    signals : dict, optional
        The plant's name and signal labels (``name``, ``inputs``,
        ``outputs``, ``states``).
    """

    def __init__(self, A: ArrayLike, C: ArrayLike, Bw: ArrayLike | None = None,
                 Dw: ArrayLike | None = None, Cz: ArrayLike | None = None,
                 copies: int = 1, weights: ArrayLike | None = None,
                 dt: float | bool = 0, *, B: ArrayLike | None = None,
                 D: ArrayLike | None = None, measure: ArrayLike | None = None,
                 feed: ArrayLike | None = None, states: int | None = None,
                 plant_noise: tuple[Array, Array] | None = None,
                 extra_outputs: tuple[str, Array] | None = None,
                 signals: dict[str, Any] | None = None) -> None:
        A = as_matrix(A, 'A', (None, None))
        m = A.shape[0]
        if A.shape != (m, m):
            raise DimensionError(f"A must be square; found shape {A.shape}")
        C = as_matrix(C, 'C', (None, m))
        p = C.shape[0]
        self.A, self.C = A, C
        self.Bw, self.Dw, self.Cz = noise_model(m, p, Bw, Dw, Cz)
        self.copies = check_copies(copies)
        self.weights = check_weights(weights, self.copies)
        self.dt = timebase(dt)
        self.B = np.zeros((m, 0)) if B is None else as_matrix(B, 'B', (m, None))
        self.D = np.zeros((p, self.B.shape[1])) if D is None else \
            as_matrix(D, 'D', (p, self.B.shape[1]))
        self.measure = np.eye(p) if measure is None else \
            as_matrix(measure, 'measure', (p, p))
        self.feed = np.zeros((m, p)) if feed is None else \
            as_matrix(feed, 'feed', (m, p))
        self.nx = m if states is None else int(states)
        if not 1 <= self.nx <= m:
            raise ParameterError(f"states must lie in [1, {m}]; found "
                                 f"{self.nx}")
        if plant_noise is None:
            plant_noise = (self.Bw[:self.nx], self.Dw)
        Bwp, Dwp = plant_noise
        self.plant_Bw = as_matrix(Bwp, 'plant Bw', (self.nx, None))
        self.plant_Dw = as_matrix(Dwp, 'plant Dw',
                                  (p, self.plant_Bw.shape[1]))
        if extra_outputs is not None:
            label, Mx = extra_outputs
            extra_outputs = (str(label),
                             as_matrix(Mx, 'extra outputs', (None,
                                                             m - self.nx)))
        self.extra_outputs = extra_outputs
        self.signals = dict(signals or {})

    # sizes
    @property
    def n(self) -> int:
        """Design states per copy."""
        return self.A.shape[0]

    @property
    def p(self) -> int:
        """Measurements."""
        return self.C.shape[0]

    @property
    def q(self) -> int:
        """Noise channels."""
        return self.Bw.shape[1]

    @property
    def nz(self) -> int:
        """Estimated outputs."""
        return self.Cz.shape[0]

    @property
    def nu(self) -> int:
        """Plant inputs."""
        return self.B.shape[1]


    @property
    def members(self) -> list[ObserverProblem]:
        """The plant models of the problem: ``[self]`` here, one per model
        for a :class:`~controlext.synthesis.models.ModelSet`."""
        return [self]

    @property
    def gain_shape(self) -> tuple[int, int]:
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
    def rate(self) -> float:
        """The plant's rate ``max(1, ‖A‖₂)``."""
        return max(1.0, float(np.linalg.norm(self.A, 2)))

    @property
    def noise_scale(self) -> float:
        """Size of the noise-to-error channel in the units of its norm,
        ``‖Cze‖ (‖Bwe‖ / r + ‖Dwe‖ / ‖C‖)`` with the plant's rate
        ``r = max(1, ‖A‖)``: the disturbance reaches the error through
        the dynamics (a factor of order ``1 / r``), the sensor noise
        through a gain of order ``r / ‖C‖``."""
        rate = self.rate
        sensor = float(np.linalg.norm(self.C, 2))
        noise = np.linalg.norm(self.Dwe, 2)
        return float(np.linalg.norm(self.Cze, 2) * (
            np.linalg.norm(self.Bwe, 2) / rate +
            (noise / sensor if sensor else noise)))

    def error_system(self, G: ArrayLike) -> tuple[Array, Array, Array, Array]:
        """Matrices ``(Acl, Bcl, Ccl, Dcl)`` of the error system for gain G."""
        G = np.asarray(G, dtype=float)
        return (self.Ae - G @ self.Ce, G @ self.Dwe - self.Bwe, self.Cze,
                np.zeros((self.nz, self.q)))

    def error_signals(self, inputs: Names = None, outputs: Names = None,
                      states: Names = None) -> dict[str, list[str]]:
        """Signal names of the error system: noise ``w[i]`` in, weighted
        error ``ebar[i]`` out, the copies' errors ``e[i]`` (one copy) or
        ``e<k>[i]`` as states, unless given (a base name or a list)."""
        N, n = self.copies, self.n
        default = [f'e[{i}]' for i in range(n)] if N == 1 else \
            [f'e{k + 1}[{i}]' for k in range(N) for i in range(n)]
        return dict(inputs=signal_names(inputs, 'w', self.q, 'inputs'),
                    outputs=signal_names(outputs, 'ebar', self.nz, 'outputs'),
                    states=signal_names(states, default, N * n, 'states'))

    def estimator_matrices(self, G: ArrayLike,
                           copy_outputs: bool = False) -> tuple[Array, Array,
                           Array, Array]:
        """``(A, Bu, By, C)`` of the runnable estimator for gain ``G``:
        ``ξ' = A ξ + Bu u + By y``, outputs ``C ξ``: the estimate ``x̂``
        (``n`` rows), then the extra outputs (averaged over the copies),
        then, with ``copy_outputs``, every copy's estimate."""
        G = np.asarray(G, dtype=float)
        N, m, n = self.copies, self.n, self.nx
        ones = np.ones((N, 1))
        By = G @ np.kron(ones, self.measure) + np.kron(ones, self.feed)
        Bu = np.kron(ones, self.B) - By @ self.D
        pick = np.eye(m)[:n]
        rows = [np.kron(self.weights.reshape(1, -1), pick)]
        if self.extra_outputs is not None:
            extra = np.hstack([np.zeros((self.extra_outputs[1].shape[0], n)),
                               self.extra_outputs[1]])
            rows.append(np.kron(self.weights.reshape(1, -1), extra))
        if copy_outputs:
            rows.append(np.kron(np.eye(N), pick))
        return self.Ae - G @ self.Ce, Bu, By, np.vstack(rows)

    def embed(self, L: ArrayLike) -> Array:
        """The coupled gain ``I_N ⊗ L`` of a one-copy gain: every copy runs
        the same Luenberger observer and the average equals it."""
        return np.kron(np.eye(self.copies), np.asarray(L, dtype=float))

    def grow(self, G: ArrayLike, L: ArrayLike) -> Array:
        """The gain of these ``N`` copies that has the H∞ and H2 norms of an
        ``(N − 1)``-copy gain ``G`` (equal weights): the first ``N − 1``
        copies run ``G``, and the last tracks their average, with the
        deviation ``δ`` from it obeying ``δ' = (A − L C) δ`` for the
        one-copy gain ``L``.  Its innovation gains are the average of the
        others' minus ``L/(N − 1)``, plus ``L`` on its own, so no noise
        reaches ``δ``; the average of all ``N`` errors is that of the
        ``N − 1`` plus ``δ/N``, and the error poles are those of ``G`` and
        of ``A − L C``."""
        G = np.asarray(G, dtype=float)
        L = np.asarray(L, dtype=float)
        N, n, p = self.copies, self.n, self.p
        M = N - 1
        out = np.zeros((N * n, N * p))
        out[:M * n, :M * p] = G
        for k in range(M):
            cols = slice(k * p, (k + 1) * p)
            out[M * n:, cols] = G[:, cols].reshape(M, n, p).mean(axis=0) \
                - L / M
        out[M * n:, M * p:] = L
        return out

    def replace(self, **changes: Any) -> ObserverProblem:
        """A copy with some fields changed."""
        fields = dict(A=self.A, C=self.C, Bw=self.Bw, Dw=self.Dw, Cz=self.Cz,
                      copies=self.copies, weights=None, dt=self.dt,
                      B=self.B, D=self.D, measure=self.measure,
                      feed=self.feed, states=self.nx,
                      plant_noise=(self.plant_Bw, self.plant_Dw),
                      extra_outputs=self.extra_outputs, signals=self.signals)
        if 'copies' not in changes:
            fields['weights'] = self.weights
        fields.update(changes)
        return ObserverProblem(**fields)

    def noise_scaled(self, factor: float) -> ObserverProblem:
        """The problem with its noise channels ``(Bw, Dw)`` times
        ``factor``."""
        return self.replace(Bw=self.Bw * factor, Dw=self.Dw * factor)

    def single(self) -> ObserverProblem:
        """The same problem with one copy."""
        return self if self.copies == 1 else self.replace(copies=1)

    def state_scaling(self, sweeps: int = 50) -> Array:
        """A diagonal state scaling ``d`` that does not depend on the
        units of the states: the realisation ``(D⁻¹ A D, C D, D⁻¹ Bw,
        Cz D)`` is the same for the problem in any units (``x' = T x``,
        ``T`` diagonal, with ``C``, ``Cz`` and ``Bw`` transformed alike).

        Each state is first measured in the units its columns of ``[C;
        Cz]`` give it (unit column norms); Osborne sweeps then balance the
        rows and columns of ``[[A, Bw], [C; Cz, 0]]`` over the states,
        keeping ``‖[C; Cz] D‖_F`` fixed, so that the result is unique.
        A state that no output sees keeps the scale of its neighbours.
        The sweeps move no state more than ``1e4`` from its output units:
        on a matrix that is not irreducible (the augmented GI observer's
        constant disturbance states drive the plant and nothing drives
        them) they do not converge, and drove such a state to 3e-30.

        Examples
        --------
        >>> import numpy as np
        >>> from controlext.synthesis import ObserverProblem
        >>> T = np.diag([1e-3, 1e3])
        >>> A, C = np.array([[-1.0, 1.0], [0.0, -2.0]]), np.array([[1.0, 0.0]])
        >>> p1 = ObserverProblem(A, C)
        >>> p2 = ObserverProblem(T @ A @ np.linalg.inv(T),
        ...                      C @ np.linalg.inv(T), Cz=np.linalg.inv(T))
        >>> d1, d2 = p1.state_scaling(), p2.state_scaling()
        >>> bool(np.allclose(p1.scaled(d1).A, p2.scaled(d2).A))
        True
        """
        A, n = self.A, self.n
        outputs = np.vstack([self.C, self.Cz])
        col = np.linalg.norm(outputs, axis=0)
        seen = col > 0
        d = np.ones(n)
        d[seen] = 1.0 / col[seen]
        if not seen.all():
            d[~seen] = np.exp(np.mean(np.log(d[seen]))) if seen.any() else 1
        units = d.copy()
        off = A * (1 - np.eye(n))
        out2 = np.sum(outputs**2, axis=0)
        bw2 = np.sum(self.Bw**2, axis=1)
        target = np.sum(out2 * d**2)
        for _ in range(sweeps):
            before = d.copy()
            for k in range(n):
                row = np.sum((off[k] * d)**2) + bw2[k]
                colk = np.sum((off[:, k] / d)**2) + out2[k]
                if row > 0 and colk > 0:
                    d[k] = (row / colk) ** 0.25
            if target > 0:
                d *= np.sqrt(target / np.sum(out2 * d**2))
            d = np.clip(d, units * 1e-4, units * 1e4)
            if np.max(np.abs(np.log(d / before))) < 1e-12:
                break
        return d

    def scaled(self, d: ArrayLike) -> ObserverProblem:
        """The problem in the scaled states ``D⁻¹ x`` (synthesis data
        only: a gain ``G_s`` of it is ``(I_N ⊗ D) G_s`` here)."""
        d = np.asarray(d, dtype=float)
        return ObserverProblem(self.A / d[:, None] * d[None, :],
                               self.C * d[None, :], self.Bw / d[:, None],
                               self.Dw, self.Cz * d[None, :],
                               copies=self.copies, weights=self.weights,
                               dt=self.dt)

    def unscale_gain(self, G: ArrayLike, d: ArrayLike) -> Array:
        """The gain of this problem for a gain ``G`` of ``scaled(d)``."""
        scale = np.kron(np.ones(self.copies), np.asarray(d, dtype=float))
        return scale[:, None] * np.asarray(G, dtype=float)


def plant_problem(plant, Bw=None, Dw=None, Cz=None, copies=1, weights=None):
    """The problem of a Luenberger or coupled observer of ``plant``
    (``x' = A x + B u + Bw w``, ``y = C x + D u + Dw w``).

    Examples
    --------
    >>> import control as ct
    >>> from controlext.synthesis.problem import plant_problem
    >>> prob = plant_problem(ct.ss([[-1.0]], [[1.0]], [[2.0]], 0), copies=2)
    >>> prob.gain_shape, prob.nu
    ((2, 2), 1)
    """
    A, B, C, D, dt = as_plant(plant)
    return ObserverProblem(A, C, Bw, Dw, Cz, copies=copies, weights=weights,
                           dt=dt, B=B, D=D, signals=signals_of(plant))


def signals_of(plant):
    """The name and signal labels of a python-control system."""
    return dict(name=plant.name, inputs=list(plant.input_labels),
                outputs=list(plant.output_labels),
                states=list(plant.state_labels))
