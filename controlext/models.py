"""Plant models over a parameter, and how a design holds between them.

A design for several plant models (pass a sequence of plants to any
factory) keeps its region and its norm on the models it was given; a
plant between them is another matter.  :func:`model_set` builds the
models from a function of a parameter, and :func:`check_models`
measures a design on a denser set, so that a user sees whether the
guarantee holds between the models.

Examples
--------
>>> import numpy as np
>>> import control as ct
>>> import controlext as cx
>>> def plant(a):
...     return ct.ss([[-a]], [[1.0]], [[1.0]], 0)
>>> obs = cx.hinf_observer(cx.model_set(plant, [0.5, 2.0]), decay=2.5)
>>> check = cx.check_models(obs, plant, np.linspace(0.5, 2.0, 7))
>>> bool(check.worst_decay >= 2.5 * (1 - 1e-6))
True
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import control as ct

from .exceptions import ArgumentError
from ._text import table_row

__all__ = ['model_set', 'ModelCheck', 'check_models']


def model_set(make_plant: Callable[[Any], ct.StateSpace],
              values: Sequence[Any]) -> list[ct.StateSpace]:
    """The plant models ``make_plant(v)`` for each parameter value ``v``
    (the first is the nominal model of a design).

    Parameters
    ----------
    make_plant : callable
        A function of one parameter value returning a python-control
        system (every one of equal sizes and timebase).
    values : sequence
        Parameter values (at least one).

    Returns
    -------
    list of control.StateSpace
        One model per value.

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> models = cx.model_set(lambda J: ct.tf([1.0], [J, 0.1, 0]),
    ...                       [1.0, 0.5, 2.0])
    >>> len(models), models[1].nstates
    (3, 2)
    """
    if not callable(make_plant):
        raise ArgumentError("make_plant must be a function of one parameter "
                            f"value; found {type(make_plant).__name__}")
    values = list(np.atleast_1d(np.asarray(values, dtype=object)))
    if not values:
        raise ArgumentError("values: expected at least one parameter value; "
                            "found none")
    plants = []
    for v in values:
        plant = make_plant(v)
        if isinstance(plant, ct.TransferFunction):
            plant = ct.ss(plant)
        if not isinstance(plant, ct.StateSpace):
            raise ArgumentError(
                f"make_plant({v!r}) must return a control.StateSpace; "
                f"found {type(plant).__name__}")
        plants.append(plant)
    return plants


@dataclass
class ModelCheck:
    """A design measured on plants over a parameter
    (:func:`check_models`).

    Attributes
    ----------
    values : ndarray
        The parameter values.
    hinf, decay : ndarray
        The H∞ norm and the decay rate of the design's error system on
        each plant.
    in_region : ndarray of bool
        Whether each plant's error poles are in the design's region (or
        stable, without one).
    claimed : float
        The worst-case norm the design claims over its own models.
    """
    values: np.ndarray
    hinf: np.ndarray
    decay: np.ndarray
    in_region: np.ndarray
    claimed: float

    @property
    def worst_hinf(self) -> float:
        """The largest norm over the plants."""
        return float(np.max(self.hinf))

    @property
    def worst_decay(self) -> float:
        """The slowest decay over the plants."""
        return float(np.min(self.decay))

    @property
    def holds(self) -> bool:
        """Does every plant keep the region and the claimed norm (to the
        verification's tolerance)?"""
        return bool(np.all(self.in_region)) and \
            self.worst_hinf <= self.claimed * (1 + 1e-6)

    def __str__(self):
        rows = [f"{'parameter':>12} {'H∞ norm γ':>12} {'decay':>12}  region"]
        for v, h, d, ok in zip(self.values, self.hinf, self.decay,
                               self.in_region):
            label = f"{v:.6g}" if isinstance(v, (float, np.floating)) \
                else str(v)
            rows.append(f"{label:>12} {h:>12.6g} {d:>12.6g}  "
                        f"{'kept' if ok else 'LOST'}")
        rows.append(table_row('worst over the plants',
                              f"γ {self.worst_hinf:.6g}, decay "
                              f"{self.worst_decay:.6g}"))
        rows.append(table_row('the design claims', f"γ ≤ {self.claimed:.6g}"
                              f" on its models: "
                              f"{'holds' if self.holds else 'does not hold'}"
                              " on these"))
        return '\n'.join(rows)


def check_models(observer: Any, make_plant: Any,
                 values: Sequence[Any] | None = None) -> ModelCheck:
    """Measure a design on other plants: the H∞ norm and decay of its
    gain on each, and whether its region holds there.

    Parameters
    ----------
    observer : Observer
        A design (for one model or several).
    make_plant : callable or sequence of control.StateSpace
        A function of a parameter value giving a plant, with ``values``;
        or the plants themselves.
    values : sequence, optional
        The parameter values (with a function; for plants given as a
        sequence, their labels, default ``0, 1, ...``).

    Returns
    -------
    ModelCheck

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> obs = cx.LuenbergerObserver(ct.ss([[-0.5]], [[1.0]], [[1.0]], 0),
    ...                             [[2.0]])
    >>> check = cx.check_models(obs, lambda a: ct.ss([[-a]], [[1.0]],
    ...                                              [[1.0]], 0), [0.5, 1.0])
    >>> check.decay.round(4).tolist()
    [2.5, 3.0]
    """
    if callable(make_plant):
        if values is None:
            raise ArgumentError("check_models needs values= with a function "
                                "of a parameter")
        plants = model_set(make_plant, values)
    else:
        plants = list(make_plant)
    labels = np.asarray(list(range(len(plants)) if values is None
                             else values), dtype=object)
    if len(labels) != len(plants):
        raise ArgumentError(f"expected one value per plant ({len(plants)});"
                            f" found {len(labels)}")
    region = observer.report.region
    hinf, decay, inside = [], [], []
    for plant in plants:
        other = observer.on(plant)
        hinf.append(other.report.hinf)
        decay.append(other.report.decay)
        poles = other.report.poles
        if region is not None:
            scale = max(1.0, float(np.max(np.abs(poles))))
            inside.append(region.worst_margin(poles) <= 1e-7 * scale)
        else:
            inside.append(bool(np.isfinite(other.report.hinf)))
    try:
        labels = labels.astype(float)
    except (TypeError, ValueError):
        pass
    return ModelCheck(values=labels, hinf=np.array(hinf),
                      decay=np.array(decay), in_region=np.array(inside),
                      claimed=float(observer.report.hinf))
