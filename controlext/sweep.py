"""Trade-off curves: one design parameter swept, every point's trade-off.

:func:`sweep` designs an observer for each value of ``decay``, ``copies``,
``max_gain``, ``max_hinf`` or ``max_h2`` (the others fixed; the last two
with the other norm as ``objective=``: a mixed H2/H∞ front) and returns every design's
:class:`~controlext.synthesis.tradeoff.Tradeoff`; :meth:`Sweep.front`
keeps the designs no other one beats in two of its numbers at once (the
Pareto front of, say, γ against settling time or against the H2 norm),
and :func:`~controlext.sweep_plot` draws either.  The points run on ``executor=``
when one is given (the results do not depend on it).

Examples
--------
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[1.0]], [[1.0]], [[1.0]], 0)     # unstable, scalar
>>> s = cx.sweep(plant, 'max_gain', [5.0, 20.0], decay=2.0)
>>> [round(r.hinf, 4) for r in s.rows]               # κ / (κ − 1)
[1.25, 1.0526]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import control as ct

from ._checks import as_plant, check_choice
from ._typing import ExecutorLike, Plant
from .exceptions import ArgumentError
from .synthesis.refine import single_threaded
from .synthesis.tradeoff import Tradeoff

__all__ = ['Sweep', 'sweep']

PARAMETERS = ('decay', 'copies', 'max_gain', 'max_hinf', 'max_h2')
METRICS = ('hinf', 'h2', 'gain_norm', 'peak', 'settling_time', 'decay')


@dataclass(repr=False)
class Sweep:
    """The designs of :func:`sweep`: ``values[k]`` gave ``rows[k]``.

    Attributes
    ----------
    parameter : str
        What was swept (``'decay'``, ``'copies'``, ``'max_gain'``).
    values : list
        The swept values.
    rows : list of Tradeoff
        The design of each value.
    """
    parameter: str
    values: list[Any]
    rows: list[Tradeoff]

    def __repr__(self) -> str:
        return (f"<Sweep of {self.parameter} over {len(self.values)} "
                "values>")

    def metric(self, name: str) -> np.ndarray:
        """One number of every design (``'hinf'``, ``'h2'``, ...)."""
        check_choice(name, 'metric', METRICS)
        return np.array([getattr(r, name) for r in self.rows], dtype=float)

    def front(self, x: str = 'settling_time', y: str = 'hinf') -> list[int]:
        """Indices of the designs on the Pareto front of metrics ``x`` and
        ``y`` (both smaller is better; a design is dropped when another is
        no worse in both and better in one), ordered by ``x``."""
        xs, ys = self.metric(x), self.metric(y)
        keep = [k for k in range(len(xs)) if not any(
            xs[j] <= xs[k] and ys[j] <= ys[k] and
            (xs[j] < xs[k] or ys[j] < ys[k]) for j in range(len(xs)))]
        return sorted(keep, key=lambda k: xs[k])


def observer(data, design):
    """The observer of ``design`` (the factories' keywords; ``copies = 1``,
    the default, is :func:`~controlext.hinf_observer`, more copies
    :func:`~controlext.coupled_observer`) for the plant ``data = (A, B, C,
    D, dt)``: plain arrays, which pickle to a worker."""
    from .coupled import coupled_observer
    from .luenberger import hinf_observer
    plant = ct.ss(*data)
    design = dict(design)
    copies = design.pop('copies', 1)
    return hinf_observer(plant, **design) if copies == 1 else \
        coupled_observer(plant, copies=copies, **design)


@single_threaded
def _point(job):
    """One design of a sweep (module level: picklable), BLAS on one
    thread: on a pool the other cores are busy."""
    return observer(*job).tradeoff


def sweep(plant: Plant, parameter: str, values: Sequence[Any], *,
          executor: ExecutorLike = None, **design: Any) -> Sweep:
    """Design an observer for every value of one parameter.

    Parameters
    ----------
    plant : control.StateSpace
        The plant.
    parameter : {'decay', 'copies', 'max_gain', 'max_hinf', 'max_h2'}
        What varies (``max_hinf`` needs ``objective='h2'``); ``copies = 1`` is the H∞ Luenberger observer
        (:func:`~controlext.hinf_observer`), more copies a coupled design.
    values : sequence
        The values it takes.
    executor : concurrent.futures.Executor, optional
        Runs the designs in parallel.
    **design
        The fixed keywords of every design (``decay=``, ``copies=``,
        ``Bw=``, ``Dw=``, ``region=``, ``max_gain=``, ...).

    Returns
    -------
    Sweep

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> s = cx.sweep(plant, 'copies', [1, 2], decay=2.5, gain_tolerance=0)
    >>> [round(r.hinf, 4) for r in s.rows]
    [0.8, 0.4953]
    """
    check_choice(parameter, 'parameter', PARAMETERS)
    if parameter in design:
        raise ArgumentError(f"{parameter} is the swept parameter; give its "
                            "values, not a fixed keyword")
    values = list(values)
    if not values:
        raise ArgumentError("sweep needs at least one value")
    A, B, C, D, dt = as_plant(plant)
    data = (A, B, C, D, dt)
    jobs = [(data, dict(design, **{parameter: value})) for value in values]
    rows = list(executor.map(_point, jobs) if executor is not None
                else map(_point, jobs))
    for value, row in zip(values, rows):
        row.name = f"{parameter} = {value}"
    return Sweep(parameter, values, rows)
