"""MATLAB-style names for controlext.

Import alongside ``control.matlab``; nothing here changes a global
setting::

    from control.matlab import *
    from controlext.matlab import *

The names follow MATLAB's return conventions where MATLAB has the name:
``[ninf, fpeak] = hinfnorm(sys)`` (``fpeak = Inf`` for an unstable
system), ``est = estim(sys, L, sensors, known)`` (inputs the measured
outputs and the known inputs, outputs ``[ŷ; x̂]``), ``[y, t, x] =
obsim(...)`` like ``lsim``.

Examples
--------
>>> from control.matlab import ss
>>> from controlext.matlab import hinfnorm, hinfobs, estim
>>> sys = ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]], 0)
>>> obs = hinfobs(sys, 1.0)
>>> ninf, fpeak = hinfnorm(obs)
>>> bool(ninf < 0.2852)
True
>>> est = estim(sys, obs.L, [0], [0])       # sensor y[0], known input u[0]
>>> est.input_labels, est.output_labels
(['y[0]', 'u[0]'], ['yhat[0]', 'xhat[0]', 'xhat[1]'])
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any
import numpy as np
import control as ct

from .coupled import coupled_observer
from .gi import gi_observer
from .luenberger import LuenbergerObserver, hinf_observer, \
    luenberger_observer
from .norms import hinfnorm
from .exceptions import ArgumentError, ParameterError
from .simulate import simulate
from ._typing import Array, ArrayLike, Plant

if TYPE_CHECKING:
    from .observers import Observer

__all__ = ['hinfnorm', 'luenobs', 'hinfobs', 'coupledobs', 'giobs',
           'obsim', 'estim']

#: ``obs = luenobs(sys, p)``: Luenberger observer with error poles ``p``
#: (its gain is ``obs.L``, what MATLAB's ``place(A', C', p)'`` gives)
luenobs = luenberger_observer
#: ``obs = hinfobs(sys, decay)``: H∞-optimal observer
hinfobs = hinf_observer
#: ``obs = coupledobs(sys, decay, copies)``: coupled observers
coupledobs = coupled_observer
#: ``obs = giobs(sys, Bw, decay)``: GI observer
giobs = gi_observer


def estim(sys: Plant, L: ArrayLike, sensors: ArrayLike | None = None,
          known: ArrayLike | None = None) -> ct.StateSpace:
    """``est = estim(sys, L, sensors, known)``: the estimator of gain ``L``.

    As MATLAB's ``estim``: the measured outputs ``sensors`` (default all)
    and the known inputs ``known`` (default none: ``estim(sys, L)`` takes
    every input of ``sys`` for unmeasured noise) are the estimator's
    inputs ``[y; u_known]``; its outputs are ``[ŷ; x̂]`` with
    ``ŷ = C x̂ + D u_known`` for the measured outputs.  ``L`` has one
    column per sensor.  For python-control's closed-loop tools use the
    observer's :meth:`~controlext.Observer.estimator` (inputs ``[y; u]``
    by name).

    Parameters
    ----------
    sys : control.StateSpace
        The plant.
    L : array_like
        Observer gain, ``nstates × len(sensors)``.
    sensors : sequence of int, optional
        Indices of the measured outputs (default: all).
    known : sequence of int, optional
        Indices of the known inputs (default: none).

    Returns
    -------
    control.StateSpace

    Examples
    --------
    >>> from control.matlab import ss
    >>> from controlext.matlab import estim
    >>> sys = ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> est = estim(sys, [[2.0]])
    >>> est.A.tolist(), est.B.tolist(), est.C.tolist()
    ([[-2.5]], [[2.0]], [[1.0], [1.0]])
    >>> estim(sys, [[2.0]], [0], [0]).B.tolist()      # inputs [y; u]
    [[2.0, 1.0]]
    """
    plant = ct.ss(sys)
    p, m = plant.noutputs, plant.ninputs
    outs = _indices(sensors, p, 'sensors', list(range(p)))
    ins = _indices(known, m, 'known', [])
    C, D = np.asarray(plant.C)[outs], np.asarray(plant.D)[outs]
    measured = ct.ss(plant.A, plant.B, C, D, plant.dt)
    est = LuenbergerObserver(measured, L).estimator()
    ps, n = len(outs), plant.nstates
    B = np.asarray(est.B)[:, list(range(ps)) + [ps + j for j in ins]]
    Cy = np.vstack([C @ est.C, est.C])
    Dy = np.vstack([np.hstack([np.zeros((ps, ps)), D[:, ins]]),
                    np.zeros((n, ps + len(ins)))])
    return ct.ss(est.A, B, Cy, Dy, plant.dt,
                 inputs=[plant.output_labels[i] for i in outs] +
                 [plant.input_labels[j] for j in ins],
                 outputs=[f'yhat[{i}]' for i in outs] +
                 list(est.output_labels), states=est.state_labels)


def _indices(value: Any, size: int, name: str,
             default: list[int]) -> list[int]:
    """Checked, distinct signal indices in ``range(size)``."""
    if value is None:
        return default
    try:
        idx = [int(i) for i in np.atleast_1d(np.asarray(value))]
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"{name} must be a sequence of indices; found "
                            f"{value!r}") from exc
    if any(not 0 <= i < size for i in idx) or len(set(idx)) != len(idx):
        raise ParameterError(f"{name} must be distinct indices in 0 ... "
                             f"{size - 1}; found {idx}")
    return idx


def obsim(sys: Plant, observers: Observer | Sequence[Observer], t: ArrayLike,
          *args: Any, **kwargs: Any) -> tuple[Array, Array, Array]:
    """``[y, t, x] = obsim(sys, observers, t, ...)``: simulate a plant and
    its observers (:func:`controlext.simulate`) and return as ``lsim``
    does: ``y`` (time × outputs: the state, each estimate, each error),
    ``t`` and ``x`` (time × states).

    Parameters
    ----------
    sys : control.StateSpace
        The plant.
    observers : Observer or sequence of Observer
        Observers of the plant.
    t : array_like
        Time points.
    *args, **kwargs
        Passed to :func:`controlext.simulate` (inputs, noise, initial
        state and estimates).

    Returns
    -------
    y, t, x : ndarray

    Examples
    --------
    >>> import numpy as np
    >>> from control.matlab import ss
    >>> from controlext.matlab import hinfobs, obsim
    >>> sys = ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> y, t, x = obsim(sys, hinfobs(sys, 2.5), np.linspace(0, 5, 51),
    ...                 x0=1.0)
    >>> y.shape, t.shape
    ((51, 3), (51,))
    """
    resp = simulate(sys, observers, t, *args, **kwargs)
    return (np.atleast_2d(resp.outputs).T, resp.time,
            np.atleast_2d(resp.states).T)
