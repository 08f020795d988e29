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
``range(C)`` (the seed's scalar form is ``U = C/|C|``).  With a constant
``α`` — ``α' = 0`` in continuous time, ``α(k+1) = α(k)`` in discrete
time — the augmented plant is ``Aa = [[A, Bw U], [0, Λ]]`` (``Λ = 0``,
respectively ``I``), ``Ca = [C, U]`` and gain ``[L; Lw]``; in the states
``(e, α̂)`` its error system from ``w`` has the same engine form with
``Bw_a = [Bw (I − Π); 0]``, ``Dw = I − Π`` and ``Cz = [I, 0]``, and its DC
gain is zero: constant disturbances are rejected exactly, the part in
``range(C)`` by estimation and the part outside it by measurement.

All of it — the measurement map ``I − Π``, the feed-forward ``Bw Π`` and
the disturbance model — is held by the observer's
:class:`~controlext.synthesis.ObserverProblem`, from which both the error
system and the runnable estimator are derived.

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
>>> obs.invariant_directions
1
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.linalg as la

from ._checks import as_matrix, as_plant, check_copies
from ._warn import warn
from .exceptions import ArgumentError, ParameterError
from .observers import Observer
from .synthesis import ObserverProblem, SynthesisOptions
from .synthesis.models import ModelSet, for_models
from .synthesis.options import synthesis_factory
from .synthesis.problem import signals_of
from .synthesis.pipeline import design
from ._typing import Array, ArrayLike, ExecutorLike, Names, Plant

if TYPE_CHECKING:
    from .synthesis import RefineOptions, Region
    from .synthesis.verify import DesignReport

__all__ = ['GIObserver', 'gi_observer', 'range_basis', 'projection',
           'gi_problem']


def range_basis(C: ArrayLike, tol: float = 1e-10) -> Array:
    """Orthonormal basis ``U`` of ``range(C)`` (``p × r``).

    Parameters
    ----------
    C : array_like
        Output matrix, ``p × n``.
    tol : float, optional
        Singular values below ``tol`` times the largest (or 1) count as 0.

    Returns
    -------
    ndarray

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


def projection(C: ArrayLike) -> Array:
    """``Π = I − C C⁺``: projection onto the complement of ``range(C)``.

    Parameters
    ----------
    C : array_like
        Output matrix, ``p × n``.

    Returns
    -------
    ndarray
        ``p × p``.

    Examples
    --------
    >>> import controlext as cx
    >>> cx.projection([[1.0], [1.0]]).round(3).tolist()
    [[0.5, -0.5], [-0.5, 0.5]]
    """
    U = range_basis(C)
    return np.eye(U.shape[0]) - U @ U.T


def gi_problem(plant: Plant, Bw: ArrayLike, augmented: bool = False,
               copies: int = 1,
               weights: ArrayLike | None = None) -> ObserverProblem:
    """The generalised plant of the (augmented, coupled) GI observer.

    Examples
    --------
    >>> import numpy as np
    >>> import control as ct
    >>> from controlext.gi import gi_problem
    >>> plant = ct.ss([[0.9]], [[1.0]], [[1.0], [1.0]], 0, 1.0)
    >>> prob = gi_problem(plant, [[0.5, 0.0]], augmented=True)
    >>> prob.A.round(4).tolist()         # alpha(k+1) = alpha(k)
    [[0.9, 0.3536], [0.0, 1.0]]
    """
    A, B, C, D, dt = as_plant(plant)
    n, p = A.shape[0], C.shape[0]
    Bw = as_matrix(Bw, 'Bw', (n, p))
    U = range_basis(C)
    r = U.shape[1]
    Pi = np.eye(p) - U @ U.T
    common = dict(copies=copies, weights=weights, dt=dt, D=D,
                  measure=np.eye(p) - Pi, plant_noise=(Bw, np.eye(p)),
                  states=n, signals=signals_of(plant))
    if not augmented:
        return ObserverProblem(A, C, Bw @ (np.eye(p) - Pi), np.eye(p) - Pi,
                               np.eye(n), B=B, feed=Bw @ Pi, **common)
    hold = np.eye(r) if dt else np.zeros((r, r))
    Aa = np.block([[A, Bw @ U], [np.zeros((r, n)), hold]])
    Ca = np.hstack([C, U])
    Bwa = np.vstack([Bw @ (np.eye(p) - Pi), np.zeros((r, p))])
    Cza = np.hstack([np.eye(n), np.zeros((n, r))])
    return ObserverProblem(
        Aa, Ca, Bwa, np.eye(p) - Pi, Cza,
        B=np.vstack([B, np.zeros((r, B.shape[1]))]),
        feed=np.vstack([Bw @ Pi, np.zeros((r, p))]),
        extra_outputs=('dhat', U), **common)


class GIObserver(Observer):
    """GI observer (plain or augmented, one or more copies), realised as
    its error system.

    The realisation is the error system from the **full** disturbance
    ``w`` (all ``p`` components) to the state error ``x̂ − x``: plain form
    ``(A − L C, (L − Bw)(I − Π), I, 0)``; augmented form with states
    ``(e, α̂)`` and ``ct.dcgain(obs) == 0``.  Its transfer function
    vanishes on ``range(Π)``: a disturbance there does not reach the
    estimate, whatever the gain.

    Parameters
    ----------
    plant : control.StateSpace
        Plant ``x' = A x + B u + Bw w``, ``y = C x + D u + w``.
    L : array_like
        Observer gain (``n × p``; ``N n × N p`` for ``N`` copies).
    Bw : array_like
        Disturbance input matrix (``n × p``).
    augmented : bool, optional
        Also estimate the constant disturbance in ``range(C)``.
    Lw : array_like, optional
        Gain of the disturbance estimate (``r × p``, ``r = rank C``;
        ``N r × N p`` for ``N`` copies); required when ``augmented``.
    weights : array_like, optional
        Output weights of the copies.
    report : DesignReport, optional
        The design report (computed, method ``'given'``, when omitted).
    name : str, optional
        System name.
    inputs, outputs, states : str or list of str, optional
        Signal names of the error system (python-control's system
        keywords; see :class:`~controlext.Observer`).
    copies : int, optional
        Number of coupled copies.

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

    def __init__(self, plant: Plant, L: ArrayLike, Bw: ArrayLike,
                 augmented: bool = False, Lw: ArrayLike | None = None,
                 weights: ArrayLike | None = None, name: str | None = None,
                 report: DesignReport | None = None, copies: int = 1, *,
                 inputs: Names = None, outputs: Names = None,
                 states: Names = None) -> None:
        copies = check_copies(copies)
        problem = gi_problem(plant, Bw, augmented, copies, weights)
        n, p, N = problem.nx, problem.p, copies
        r = problem.n - n
        L = as_matrix(L, 'L', (N * n, N * p))
        if augmented:
            if Lw is None:
                raise ArgumentError("the augmented GI observer needs Lw "
                                    f"(the {N * r} × {N * p} disturbance "
                                    "gain)")
            Lw = as_matrix(Lw, 'Lw', (N * r, N * p))
            G = np.empty(problem.gain_shape)
            rows = _rows(problem)
            G[rows[:, :n].ravel()] = L
            G[rows[:, n:].ravel()] = Lw
        else:
            if Lw is not None:
                raise ArgumentError("Lw is only used by the augmented GI "
                                    "observer (augmented=True)")
            G = L
        _warn_if_classic(problem)
        super().__init__(problem, G, report=report, name=name,
                         inputs=inputs, outputs=outputs, states=states)

    @property
    def Pi(self) -> Array:
        """The projection Π onto the complement of range(C)."""
        return np.eye(self.problem.p) - self.problem.measure

    @property
    def U(self) -> Array:
        """Orthonormal basis of range(C)."""
        return range_basis(self.problem.C[:, :self.problem.nx])

    @property
    def augmented(self) -> bool:
        """Does the observer estimate the disturbance?"""
        return self.problem.n > self.problem.nx

    @property
    def invariant_directions(self) -> int:
        """rank Π: disturbance directions the observer is blind to."""
        return int(round(np.trace(self.Pi)))

    @property
    def gi_Bw(self) -> Array:
        """The plant's disturbance input matrix Bw."""
        return self.problem.plant_Bw.copy()


    def _problem_of(self, plant):
        other = gi_problem(plant, self.gi_Bw, self.augmented, self.copies,
                           self.weights)
        _check_shared_output(ModelSet([self.problem, other]))
        return other

    @property
    def L(self) -> Array:
        """State gain ``L``."""
        return self.G[_rows(self.problem)[:, :self.problem.nx].ravel()]

    @property
    def Lw(self) -> Array | None:
        """Disturbance-estimate gain ``Lw`` (augmented form), else None."""
        if not self.augmented:
            return None
        return self.G[_rows(self.problem)[:, self.problem.nx:].ravel()]


def _rows(problem):
    """Row indices of the gain, one row of the array per copy."""
    return np.arange(problem.copies * problem.n).reshape(problem.copies,
                                                         problem.n)


def _check_shared_output(problem):
    """Refuse models that do not share ``C``: the GI observer's projection
    ``Π`` and its measurement map are built from it."""
    members = problem.members
    C = members[0].C
    for k, member in enumerate(members[1:], start=2):
        if not np.allclose(member.C, C, rtol=1e-12, atol=0):
            gap = float(np.max(np.abs(member.C - C)))
            raise ParameterError(
                "gi_observer: every plant model must have the first model's "
                f"C (the projection Π = I − C C⁺ is built from it); model {k}"
                f"'s differs by up to {gap:.3g}")


def _warn_if_classic(problem):
    if not np.any(problem.measure - np.eye(problem.p)):
        warn("range(C) is all of R^p (Π = 0): the GI observer equals the "
             "classic observer", UserWarning)


@synthesis_factory
def gi_observer(plant: Plant, Bw: ArrayLike, decay: float | None = None,
                augmented: bool = False, copies: int = 1, *,
                weights: ArrayLike | None = None, region: Region | None = None,
                method: str = 'auto', refine: bool = True,
                margin: float = 1.02, solver: str | None = None,
                solver_options: dict[str, Any] | None = None, seed: int = 0,
                refine_options: RefineOptions | dict[str, Any] | None = None,
                executor: ExecutorLike = None,
                options: SynthesisOptions | None = None,
                max_gain: float | str | None = 'auto',
                objective: str = 'hinf', max_hinf: float | None = None,
                max_h2: float | None = None,
                settling_time: float | None = None,
                gain_tolerance: float | None = None,
                name: str | None = None, inputs: Names = None,
                outputs: Names = None, states: Names = None) -> GIObserver:
    """H∞-optimal GI observer (optionally augmented, optionally coupled).

    Parameters
    ----------
    plant : control.StateSpace or sequence of control.StateSpace
        Plant ``x' = A x + B u + Bw w``, ``y = C x + D u + w``, or several
        models of it sharing ``C`` (the projection depends on it), equal
        sizes, one timebase: one gain for all, as for
        :func:`controlext.hinf_observer`.
    Bw : array_like
        Disturbance input matrix (``n × p``); with several models, one for
        all or a sequence of one per model.
    decay : float, optional
        Required rate of convergence (``region=cx.HalfPlane(decay)``).
    augmented : bool, optional
        Also estimate the constant disturbance in ``range(C)``.
    copies : int, optional
        ``>= 2`` gives a coupled GI observer.
    weights, region, method, refine, margin, solver, solver_options
        As for :func:`controlext.coupled_observer`.
    seed, refine_options, executor, options, max_gain, name
        As for :func:`controlext.coupled_observer`.
    objective, max_hinf, max_h2, settling_time, gain_tolerance
        As for :func:`controlext.coupled_observer`.
    inputs, outputs, states
        As for :func:`controlext.coupled_observer`.

    The same synthesis pipeline as every other observer: convex stage,
    refinement where it is conservative (a region or more than one copy,
    with the one-copy GI design among the starts), verification.

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
    copies = check_copies(copies)
    problem = for_models(
        plant, lambda P, Bw: gi_problem(P, Bw, augmented, copies, weights),
        Bw=Bw)
    _check_shared_output(problem)
    if not isinstance(augmented, (bool, np.bool_)):
        raise ArgumentError("augmented must be True or False; found "
                            f"{type(augmented).__name__} {augmented!r}")
    what = ("augmented plant (A, C) with the disturbance states "
            "[[A, Bw U], [0, Λ]], [C, U]") if augmented else "plant"
    obs = design(GIObserver, problem, options, decay=decay, region=region,
                 system=dict(name=name, inputs=inputs, outputs=outputs,
                             states=states), what=what)
    _warn_if_classic(problem)
    return obs
