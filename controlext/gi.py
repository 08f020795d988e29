"""GI observers: invariant to the part of a disturbance outside range(C).

Plant ``x' = A x + B u + Bw w``, ``y = C x + D u + w`` with ``w`` of
dimension ``p``.  The projection ``Π = I − C C⁺`` onto the complement of
``range(C)`` gives ``Π (y − D u) = Π w``: that part of ``w`` is measured
exactly.  The GI observer

    x̂' = A x̂ + B u + L ((I − Π)(y − D u) − C x̂) + Bw Π (y − D u)

has the error dynamics ``e' = (A − L C) e + (L − Bw)(I − Π) w``: a
Luenberger synthesis on the generalised plant with ``Bw (I − Π)`` and
``Dw = I − Π``, and ``T(s) Π = 0`` for *every* gain ``L``.

The augmented GI observer also estimates the constant component of ``w``
in ``range(C)``, written ``d = U α`` with ``U`` an orthonormal basis of
``range(C)`` (the seed's scalar form is ``U = C/|C|``).  With ``α' = 0`` the
augmented plant is ``Aa = [[A, Bw U], [0, 0]]``, ``Ca = [C, U]`` and gain
``[L; Lw]``; in the states ``(e, α̂)`` its error system from ``w`` has the
same engine form with ``Bw_a = [Bw (I − Π); 0]``, ``Dw = I − Π`` and
``Cz = [I, 0]``, and its DC gain is zero: constant disturbances are
rejected exactly, the part in ``range(C)`` by estimation and the part
outside it by measurement.

The design uses the bounded-real lemma with its output term
``[..., Czᵀ; ..., −γI]``; without that term, as in the final LMI of the GI
notes, the problem is unbounded below (scale ``P → tP``).

Examples
--------
>>> import numpy as np
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-1.0, 1.0], [0.0, -2.0]], [[0.0], [1.0]],
...               [[1.0, 0.0], [1.0, 0.0]], 0)
>>> Bw = np.array([[0.5, 0.2], [0.0, 1.0]])
>>> obs = cx.GIObserver(plant, [[1.0, 1.0], [0.5, 0.5]], Bw)
>>> bool(np.allclose(obs.B @ obs.Pi, 0))
True
"""

import time
import warnings

import numpy as np
import scipy.linalg as la
import control as ct

from ._checks import (as_matrix, as_plant, check_detectable,
                      check_region_reachable)
from .exceptions import ArgumentError, ParameterError
from .observers import Observer
from .problem import ObserverProblem

__all__ = ['GIObserver', 'gi_observer', 'range_basis', 'projection']


def range_basis(C, tol=1e-10):
    """Orthonormal basis ``U`` of ``range(C)`` (``p × r``).

    Examples
    --------
    >>> import controlext as cx
    >>> cx.range_basis([[1.0, 0.0], [1.0, 0.0]]).shape
    (2, 1)
    """
    C = np.atleast_2d(np.asarray(C, dtype=float))
    U, s, _ = la.svd(C, full_matrices=False)
    r = int(np.sum(s > tol * max(1.0, s[0] if s.size else 1.0)))
    return U[:, :r]


def projection(C):
    """``Π = I − C C⁺``: projection onto the complement of ``range(C)``.

    Examples
    --------
    >>> import controlext as cx
    >>> cx.projection([[1.0], [1.0]]).round(3).tolist()
    [[0.5, -0.5], [-0.5, 0.5]]
    """
    U = range_basis(C)
    return np.eye(U.shape[0]) - U @ U.T


def _gi_problem(A, C, Bw, augmented, copies=1, weights=None, dt=0):
    """Generalised plant of the (augmented) GI observer."""
    n, p = A.shape[0], C.shape[0]
    U = range_basis(C)
    r = U.shape[1]
    Pi = np.eye(p) - U @ U.T
    if not augmented:
        return ObserverProblem(A, C, Bw @ (np.eye(p) - Pi), np.eye(p) - Pi,
                               np.eye(n), copies=copies, weights=weights,
                               dt=dt), U, Pi
    Aa = np.block([[A, Bw @ U], [np.zeros((r, n + r))]])
    Ca = np.hstack([C, U])
    Bwa = np.vstack([Bw @ (np.eye(p) - Pi), np.zeros((r, p))])
    Cza = np.hstack([np.eye(n), np.zeros((n, r))])
    return ObserverProblem(Aa, Ca, Bwa, np.eye(p) - Pi, Cza, copies=copies,
                           weights=weights, dt=dt), U, Pi


def _check_gi_plant(plant, Bw):
    A, B, C, D, dt = as_plant(plant)
    Bw = as_matrix(Bw, 'Bw', (A.shape[0], C.shape[0]))
    return A, B, C, D, dt, Bw


class GIObserver(Observer):
    """GI observer (plain or augmented) realised as its error system.

    The realisation is the error system from the **full** disturbance
    ``w`` (all ``p`` components) to the state error ``x̂ − x``, so the
    invariance is visible: ``obs.B @ obs.Pi == 0``.  Plain form:
    ``(A − L C, (L − Bw)(I − Π), I, 0)``; augmented form: states
    ``(e, α̂)`` and ``ct.dcgain(obs) == 0``.

    Parameters
    ----------
    plant : control.StateSpace
        Plant ``x' = A x + B u + Bw w``, ``y = C x + D u + w``.
    L : array_like
        Observer gain (``n × p``).
    Bw : array_like
        Disturbance input matrix (``n × p``).
    augmented : bool, optional
        Also estimate the constant disturbance in ``range(C)``.
    Lw : array_like, optional
        Gain of the disturbance estimate (``r × p``, ``r = rank C``);
        required when ``augmented``.
    name : str, optional
        System name.

    Attributes
    ----------
    Pi : ndarray
        The projection ``Π``.
    U : ndarray
        Orthonormal basis of ``range(C)``.
    invariant_directions : int
        ``rank Π``: the number of disturbance directions the observer is
        blind to (0 means it equals the classic observer).

    Examples
    --------
    >>> import numpy as np
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-1.0, 1.0], [0.0, -2.0]], [[0.0], [1.0]],
    ...               [[1.0, 0.0], [1.0, 0.0]], 0)
    >>> obs = cx.GIObserver(plant, [[1.0, 1.0], [0.5, 0.5]],
    ...                     [[0.5, 0.2], [0.0, 1.0]], augmented=True,
    ...                     Lw=[[0.7, 0.7]])
    >>> bool(np.allclose(ct.dcgain(obs), 0, atol=1e-10))
    True
    """

    def __init__(self, plant, L, Bw, augmented=False, Lw=None, weights=None,
                 name=None, report=None, copies=1):
        A, B, C, D, dt, Bw = _check_gi_plant(plant, Bw)
        problem, U, Pi = _gi_problem(A, C, Bw, augmented, copies, weights,
                                     dt)
        n, p, r = A.shape[0], C.shape[0], U.shape[1]
        if augmented:
            if Lw is None:
                raise ArgumentError("the augmented GI observer needs Lw "
                                    f"(the {r} × {p} disturbance gain)")
            L = as_matrix(L, 'L', (copies * n, copies * p))
            Lw = as_matrix(Lw, 'Lw', (copies * r, copies * p))
            G = _interleave(L, Lw, n, r, copies)
        else:
            if Lw is not None:
                raise ArgumentError("Lw is only used by the augmented GI "
                                    "observer (augmented=True)")
            G = as_matrix(L, 'L', (copies * n, copies * p))
        self.Pi, self.U, self.augmented = Pi, U, bool(augmented)
        self.gi_Bw = Bw
        self.invariant_directions = p - r
        if self.invariant_directions == 0:
            warnings.warn("range(C) is all of R^p (Π = 0): the GI observer "
                          "equals the classic observer", UserWarning,
                          stacklevel=2)
        super().__init__(ct.ss(plant), problem, G, report=report, name=name)

    @property
    def L(self):
        """State gain ``L``."""
        return self._split()[0]

    @property
    def Lw(self):
        """Disturbance-estimate gain ``Lw`` (augmented form), else None."""
        return self._split()[1] if self.augmented else None

    def _split(self):
        n, r, N = self.plant.nstates, self.U.shape[1], self.copies
        if not self.augmented:
            return self.G.copy(), None
        m = n + r
        rows = np.arange(N * m).reshape(N, m)
        return (self.G[rows[:, :n].ravel()].copy(),
                self.G[rows[:, n:].ravel()].copy())

    def estimator(self, name=None):
        """The runnable GI observer: inputs ``[u; y]``, outputs ``x̂`` (and
        the disturbance estimate ``d̂ = U α̂`` in the augmented form)."""
        if self.copies != 1:
            return super().estimator(name)
        plant = self.plant
        A, B, C, D = plant.A, plant.B, plant.C, plant.D
        n, p = A.shape[0], C.shape[0]
        prob, G, Pi = self.problem, self.G, self.Pi
        Ay = prob.A - G @ prob.C                    # (Aa - Ga Ca)
        m = Ay.shape[0]
        Byy = G @ (np.eye(p) - Pi) + np.vstack(
            [self.gi_Bw @ Pi, np.zeros((m - n, p))])
        Bu = np.vstack([B, np.zeros((m - n, B.shape[1]))]) - Byy @ D
        outputs = [f'xhat[{i}]' for i in range(n)]
        Cout = np.hstack([np.eye(n), np.zeros((n, m - n))])
        if self.augmented:
            Cout = np.vstack([Cout, np.hstack([np.zeros((p, n)), self.U])])
            outputs += [f'dhat[{i}]' for i in range(p)]
        states = [f'xhat[{i}]' for i in range(n)] + \
            [f'alphahat[{i}]' for i in range(m - n)]
        return ct.ss(Ay, np.hstack([Bu, Byy]), Cout,
                     np.zeros((Cout.shape[0], B.shape[1] + p)), plant.dt,
                     name=name or f'{self.name}_estimator',
                     inputs=list(plant.input_labels) +
                     list(plant.output_labels), outputs=outputs,
                     states=states)


def _interleave(L, Lw, n, r, N):
    """Stack per-copy blocks ``[L_k; Lw_k]`` into the augmented gain."""
    rows = []
    for k in range(N):
        rows += [L[k * n:(k + 1) * n], Lw[k * r:(k + 1) * r]]
    return np.vstack(rows)


def gi_observer(plant, Bw, decay=None, augmented=False, copies=1, *,
                weights=None, region=None, refine=True, margin=1.02,
                solver=None, solver_options=None, seed=0,
                refine_options=None, name=None):
    """H∞-optimal GI observer (optionally augmented, optionally coupled).

    Parameters
    ----------
    plant : control.StateSpace
        Plant ``x' = A x + B u + Bw w``, ``y = C x + D u + w``.
    Bw : array_like
        Disturbance input matrix (``n × p``).
    decay : float, optional
        Required rate of convergence (``region=cx.HalfPlane(decay)``).
    augmented : bool, optional
        Also estimate the constant disturbance in ``range(C)``.
    copies : int, optional
        ``>= 2`` gives a coupled GI observer.
    weights, region, refine, margin, solver, solver_options, seed
        As for :func:`controlext.coupled_observer`.
    refine_options, name
        As for :func:`controlext.coupled_observer`.

    Returns
    -------
    GIObserver

    Examples
    --------
    >>> import numpy as np
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-1.0, 1.0], [0.0, -2.0]], [[0.0], [1.0]],
    ...               [[1.0, 0.0], [1.0, 0.0]], 0)
    >>> obs = cx.gi_observer(plant, [[0.5, 0.2], [0.0, 1.0]], decay=1.0,
    ...                      augmented=True)
    >>> bool(np.allclose(ct.dcgain(obs), 0, atol=1e-8))
    True
    """
    from .synthesis import _check_margin, resolve_region, synthesise
    start = time.perf_counter()
    A, B, C, D, dt, Bw = _check_gi_plant(plant, Bw)
    if isinstance(copies, bool) or not isinstance(copies, (int, np.integer)) \
            or copies < 1:
        raise ParameterError(f"copies must be an integer >= 1; found "
                             f"{copies!r}")
    problem, U, Pi = _gi_problem(A, C, Bw, augmented, copies, weights, dt)
    region = resolve_region(decay, region, dt)
    margin = _check_margin(margin)
    if augmented:
        check_detectable(problem.A, problem.C, dt, what=(
            "augmented plant (A, C) with the disturbance states "
            "[[A, Bw U], [0, 0]], [C, U]"))
    else:
        check_detectable(A, C, dt)
    if region is not None:
        check_region_reachable(problem.A, problem.C, region, dt)
    G, report = synthesise(problem, region,
                           refine=refine and (region is not None or
                                              copies > 1),
                           margin=margin, solver=solver,
                           solver_options=solver_options, seed=seed,
                           refine_options=refine_options)
    report.time = time.perf_counter() - start
    n, r = A.shape[0], U.shape[1]
    m = n + r if augmented else n
    rows = np.arange(copies * m).reshape(copies, m)
    L = G[rows[:, :n].ravel()]
    Lw = G[rows[:, n:].ravel()] if augmented else None
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', UserWarning)
        obs = GIObserver(plant, L, Bw, augmented=augmented, Lw=Lw,
                         weights=problem.weights, name=name, report=report,
                         copies=copies)
    if obs.invariant_directions == 0:
        warnings.warn("range(C) is all of R^p (Π = 0): the GI observer "
                      "equals the classic observer", UserWarning,
                      stacklevel=2)
    return obs
