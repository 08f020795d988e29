"""Several plant models, one gain: the problem of a multi-model design.

A :class:`ModelSet` holds one :class:`~controlext.synthesis.problem.ObserverProblem`
per plant model (same sizes, copies, weights and timebase) and *is* the
first of them, the nominal model: everything that describes the observer
(its estimator, its signals, its error system) is the nominal model's.
The engine reads the models through :attr:`ObserverProblem.members`,
which is ``[problem]`` for an ordinary problem, so every stage has one
road for one model or many:

* the convex stage solves the LMI of every model with one Lyapunov matrix
  ``X`` and one ``Y = X G`` (the common-Lyapunov LMI: its level bounds the
  norm on every model and, the LMI being affine in the plant data, on
  every plant in the polytope the models span);
* refinement minimises the worst case over the models of the same
  objective, with every model's region and limits in the exact penalty
  (:class:`~controlext.synthesis.objective.WorstCase`);
* verification checks every model and reports each
  (:attr:`DesignReport.models`).

Examples
--------
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.models import ModelSet
>>> models = ModelSet([ObserverProblem([[-1.0]], [[1.0]]),
...                    ObserverProblem([[-2.0]], [[1.0]])])
>>> len(models.members), models.A.tolist(), models.gain_shape
(2, [[-1.0]], (1, 1))
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any
import warnings

import numpy as np

from ..exceptions import ArgumentError, DimensionError
from .problem import ObserverProblem

__all__ = ['ModelSet', 'for_models', 'per_model', 'is_model_sequence']


class ModelSet(ObserverProblem):
    """The problem of one gain for several models (module text).

    Parameters
    ----------
    members : sequence of ObserverProblem
        One problem per model, the nominal first; all of one state and
        output count, number of copies, weights and timebase.
    """

    def __init__(self, members: Sequence[ObserverProblem]) -> None:
        members = list(members)
        if not members:
            raise ArgumentError("a model set needs at least one model; "
                                "found none")
        first = members[0]
        for k, other in enumerate(members[1:], start=2):
            _same_shape(first, other, k)
        self.__dict__.update({key: value for key, value in
                              first.__dict__.items()
                              if key not in _CACHED})
        self._members = members

    @property
    def members(self) -> list[ObserverProblem]:
        """The model problems, the nominal one first."""
        return list(self._members)

    @property
    def rate(self) -> float:
        return max(member.rate for member in self._members)

    @property
    def noise_scale(self) -> float:
        return max(member.noise_scale for member in self._members)

    def replace(self, **changes: Any) -> ObserverProblem:
        return ModelSet([member.replace(**changes)
                         for member in self._members])

    def noise_scaled(self, factor: float) -> ObserverProblem:
        return ModelSet([member.noise_scaled(factor)
                         for member in self._members])

    def single(self) -> ObserverProblem:
        return self if self.copies == 1 else self.replace(copies=1)

    def scaled(self, d: Any) -> ObserverProblem:
        return ModelSet([member.scaled(d) for member in self._members])

    def state_scaling(self, sweeps: int = 50) -> np.ndarray:
        """The nominal model's scaling: the states are the same in every
        model, and the nominal one's units keep its realisation that of
        a one-model design."""
        return self._members[0].state_scaling(sweeps)


#: the cached matrices of a problem, which a model set does not copy
_CACHED = ('Ae', 'Ce', 'Bwe', 'Dwe', 'Cze')


def _same_shape(first, other, k):
    """Refuse model ``k`` unless it has the first model's sizes."""
    for what, a, b in (('states', first.n, other.n),
                       ('measurements', first.p, other.p),
                       ('noise inputs', first.q, other.q),
                       ('estimated outputs', first.nz, other.nz),
                       ('inputs', first.nu, other.nu),
                       ('copies', first.copies, other.copies)):
        if a != b:
            raise DimensionError(
                f"every model must have the first model's {what}: model 1 "
                f"has {a}, model {k} has {b}")
    if first.dt != other.dt:
        raise DimensionError(
            f"every model must have the first model's timebase: model 1 "
            f"has dt={first.dt}, model {k} has dt={other.dt}")


def is_model_sequence(plant: Any) -> bool:
    """Is ``plant`` a sequence of plant models rather than one plant?"""
    return isinstance(plant, (list, tuple))


def per_model(value: Any, count: int) -> list[Any]:
    """``value`` for each of ``count`` models: a sequence of ``count``
    matrices (each two-dimensional) gives one per model, anything else is
    shared."""
    if isinstance(value, (list, tuple)) and len(value) == count and \
            count > 1 and all(np.ndim(v) == 2 for v in value):
        return list(value)
    return [value] * count


def for_models(plant: Any, build: Callable[..., ObserverProblem],
               **noise: Any) -> ObserverProblem:
    """The problem of ``plant``, or the :class:`ModelSet` of a sequence
    of plants: ``build(plant, **noise)`` makes one model's problem, with
    each noise matrix shared or given per model (:func:`per_model`).

    Every model is checked before any solver runs: a model set of one
    plant is that plant's problem.
    """
    if not is_model_sequence(plant):
        return build(plant, **noise)
    plants = list(plant)
    if not plants:
        raise ArgumentError("plant: expected a plant or a sequence of plant "
                            "models; found an empty sequence")
    split = {name: per_model(value, len(plants))
             for name, value in noise.items()}
    members = [build(P, **{name: values[k] for name, values in split.items()})
               for k, P in enumerate(plants)]
    return members[0] if len(members) == 1 else ModelSet(members)


def conflicts(problem: ObserverProblem, region: Any,
              solver: str | None = None) -> list[tuple[int, int]]:
    """The pairs of models ``(i, j)`` (numbered from 1) for which no gain
    has one Lyapunov matrix keeping both models' poles in ``region`` (or
    stable): the LMI of the region alone, on the two models.  Where a
    common gain exists this LMI may still be infeasible (it is a
    sufficient condition), so it names the likely conflict of a refusal,
    not a proof."""
    import cvxpy as cp
    from .criteria import Criteria
    from .lmi import model_constraints
    from .regions import Disk, HalfPlane
    if region is None:
        region = Disk(1.0) if problem.dt else HalfPlane(1e-9)
    members = problem.members
    out = []
    for i in range(len(members)):
        for j in range(i + 1, len(members)):
            N = members[i].Ae.shape[0]
            X = cp.Variable((N, N), symmetric=True)
            Y = cp.Variable(members[i].gain_shape)
            cons = [X >> np.eye(N)]
            for member in (members[i], members[j]):
                cons += model_constraints(member, region, Criteria(), X, Y,
                                           0.0)[0]
            prob = cp.Problem(cp.Minimize(0), cons)
            try:
                # (a diagnosis: cvxpy's notes on its accuracy are not the
                # user's business)
                with warnings.catch_warnings():
                    warnings.simplefilter('ignore')
                    prob.solve(solver=solver or cp.CLARABEL)
            except cp.error.SolverError:
                continue
            if prob.status in (cp.INFEASIBLE, cp.INFEASIBLE_INACCURATE):
                out.append((i + 1, j + 1))
    return out
