"""MATLAB-style names for controlext.

Import alongside ``control.matlab``; nothing here changes a global
setting::

    from control.matlab import *
    from controlext.matlab import *

The names follow MATLAB's return conventions where MATLAB has the name:
``[ninf, fpeak] = hinfnorm(sys)`` (``fpeak = Inf`` for an unstable
system), ``est = estim(sys, L)`` (outputs ``[ŷ; x̂]``), ``[y, t, x] =
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
>>> est = estim(sys, obs.L)
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


def estim(sys: Plant, L: ArrayLike) -> ct.StateSpace:
    """``est = estim(sys, L)``: the estimator of gain ``L`` for ``sys``.

    As MATLAB's ``estim`` with all inputs known: inputs ``[y; u]``,
    outputs ``[ŷ; x̂]`` with ``ŷ = C x̂ + D u``.

    Examples
    --------
    >>> from control.matlab import ss
    >>> from controlext.matlab import estim
    >>> est = estim(ss([[-0.5]], [[1.0]], [[1.0]], 0), [[2.0]])
    >>> est.A.tolist(), est.C.tolist()
    ([[-2.5]], [[1.0], [1.0]])
    """
    plant = ct.ss(sys)
    est = LuenbergerObserver(plant, L).estimator()
    p, n = plant.noutputs, plant.nstates
    Cy = np.vstack([plant.C @ est.C, est.C])
    Dy = np.vstack([np.hstack([np.zeros((p, p)), plant.D]),
                    np.zeros((n, p + plant.ninputs))])
    return ct.ss(est.A, est.B, Cy, Dy, plant.dt, inputs=est.input_labels,
                 outputs=[f'yhat[{i}]' for i in range(p)] +
                 list(est.output_labels), states=est.state_labels)


def obsim(sys: Plant, observers: Observer | Sequence[Observer], t: ArrayLike,
          *args: Any, **kwargs: Any) -> tuple[Array, Array, Array]:
    """``[y, t, x] = obsim(sys, observers, t, ...)``: simulate a plant and
    its observers (:func:`controlext.simulate`) and return as ``lsim``
    does: ``y`` (time × outputs: the state, each estimate, each error),
    ``t`` and ``x`` (time × states).

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
