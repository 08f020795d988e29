"""Simulation of a plant with one or more observers.

:func:`simulate` wires each observer's :meth:`~controlext.Observer.estimator`
to the plant ``x' = A x + B u + Bw w``, ``y = C x + D u + Dw w`` and returns
python-control's :class:`control.TimeResponseData` with the true state
``x[i]``, each estimate ``xhat<k>[i]`` and each error ``e<k>[i] = xhat − x``
as named outputs.

Examples
--------
>>> import numpy as np
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
>>> luen = cx.LuenbergerObserver(plant, [[2.0]])
>>> T = np.linspace(0, 10, 501)
>>> resp = cx.simulate(plant, [luen], T, noise=0.3, initial_state=3.0,
...                      initial_estimate=5.0)
>>> resp.output_labels
['x[0]', 'xhat1[0]', 'e1[0]']
>>> round(float(resp.outputs[2, -1]), 4)     # steady-state error 0.24
0.24
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any
import numpy as np
import scipy.linalg as la
import control as ct

from ._checks import as_matrix, as_plant
from .exceptions import ArgumentError, DimensionError, ParameterError
from ._typing import ArrayLike, Plant

if TYPE_CHECKING:
    from .observers import Observer

__all__ = ['simulate']


#: python-control's legacy names (and this module's first ones)
_ALIASES = {'T': 'timepts', 'U': 'inputs', 'u': 'inputs', 'w': 'noise',
            'X0': 'initial_state', 'x0': 'initial_state',
            'xhat0': 'initial_estimate'}


def simulate(plant: Plant, observers: Observer | Sequence[Observer],
             timepts: ArrayLike | None = None, inputs: ArrayLike = 0.0,
             noise: ArrayLike = 0.0, initial_state: ArrayLike = 0.0,
             initial_estimate: ArrayLike | None = None,
             Bw: ArrayLike | None = None, Dw: ArrayLike | None = None,
             **legacy: Any) -> ct.TimeResponseData:
    """Simulate the plant and its observers on the time grid ``timepts``.

    python-control's names are used (``timepts``, ``inputs``,
    ``initial_state``); the legacy ``T``, ``U``/``u``, ``X0``/``x0``,
    ``w`` and ``xhat0`` are accepted too.

    Parameters
    ----------
    plant : control.StateSpace
        The plant.
    observers : Observer or sequence of Observer
        Observers of this plant (their estimators run on the plant's
        measurement).
    timepts : array_like
        Time points (evenly spaced; in steps of ``dt`` for discrete time).
    inputs, noise : array_like or float, optional
        Input and noise/disturbance signals: scalars, vectors (constant) or
        arrays ``(channels, len(timepts))``.
    initial_state : array_like or float, optional
        Initial plant state.
    initial_estimate : array_like or float, optional
        Initial estimate of every observer (every copy of a coupled
        observer; disturbance estimates start at 0).  Default 0.
    Bw, Dw : array_like, optional
        How ``w`` enters the plant; default: the first observer's noise
        model (for a GI observer, its ``Bw`` and ``Dw = I``).
    **legacy
        The legacy names ``T``, ``U``/``u``, ``X0``/``x0``, ``w`` and
        ``xhat0`` of ``timepts``, ``inputs``, ``initial_state``, ``noise``
        and ``initial_estimate``.

    Returns
    -------
    control.TimeResponseData
        Outputs the plant's state (named as the plant's states), then
        ``xhat<k>[...]`` and ``e<k>[...]`` for each observer
        ``k = 1, 2, ...`` (``xhat1[2]`` for python-control's default
        state names, ``xhat1[velocity]`` for a state named velocity).

    Examples
    --------
    >>> import numpy as np
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> pair = cx.CoupledObserver.from_pair(plant, 1.7896, 2.2278, 0.0538,
    ...                                     -1.1633)
    >>> resp = cx.simulate(plant, pair, np.linspace(0, 20, 801), w=0.3)
    >>> round(float(resp.outputs[-1, -1]), 4)
    0.2272
    """
    given = dict(timepts=timepts, inputs=inputs, noise=noise,
                 initial_state=initial_state,
                 initial_estimate=initial_estimate)
    defaults = dict(timepts=None, inputs=0.0, noise=0.0, initial_state=0.0,
                    initial_estimate=None)
    for old, value in legacy.items():
        if old not in _ALIASES:
            raise ArgumentError(f"unrecognized keyword(s): {old!r}")
        new = _ALIASES[old]
        if given[new] is not defaults[new] and not (
                isinstance(given[new], float) and given[new] == 0.0):
            raise ArgumentError(f"give {new}= or {old}=, not both")
        given[new] = value
    if given['timepts'] is None:
        raise ArgumentError("simulate needs timepts (the time grid)")
    T, u, w = given['timepts'], given['inputs'], given['noise']
    x0, xhat0 = given['initial_state'], given['initial_estimate']
    group: list[Observer] = list(observers) if isinstance(
        observers, (list, tuple)) else [observers]  # type: ignore[list-item]
    from .observers import Observer
    if not group or not all(isinstance(o, Observer) for o in group):
        raise ArgumentError("observers must be controlext observers")
    A, B, C, D, dt = as_plant(plant)
    n, m, p = A.shape[0], B.shape[1], C.shape[0]
    for obs in group:
        if obs.problem.dt != dt:
            raise ArgumentError(
                f"observer {obs.name!r} has timebase dt = {obs.problem.dt} "
                f"but the plant has dt = {dt}: an observer runs at its "
                "plant's sampling time (continuous: 0)")
    first = group[0]
    if Bw is None:
        Bw = first.problem.plant_Bw
        if Dw is None:
            Dw = first.problem.plant_Dw
    Bw = as_matrix(Bw, 'Bw', (n, None))
    q = Bw.shape[1]
    Dw = np.eye(p, q) if Dw is None else as_matrix(Dw, 'Dw', (p, q))
    T = _time_grid(T, dt)
    ests = [o.estimator() for o in group]
    for est in ests:
        if est.ninputs != m + p or est.noutputs != n:
            raise ArgumentError("an observer does not match the plant's "
                                "inputs, outputs and states")
    # block system: states [x; xi_1; ...], inputs [u; w]; an estimator's
    # inputs are [y; u]
    Ablocks, Bu, Bw_rows = [A], [B], [Bw]
    for est in ests:
        By_e, Bu_e = est.B[:, :p], est.B[:, p:]
        Ablocks.append(est.A)
        Bu.append(Bu_e + By_e @ D)
        Bw_rows.append(By_e @ Dw)
    Abig = la.block_diag(*Ablocks)
    N = Abig.shape[0]
    off = n
    for est in ests:
        ne = est.nstates
        Abig[off:off + ne, :n] += est.B[:, :p] @ C
        off += ne
    Bbig = np.hstack([np.vstack(Bu), np.vstack(Bw_rows)])
    rows = [np.hstack([np.eye(n), np.zeros((n, N - n))])]
    names = _state_names(plant, n)
    labels = list(names)
    off = n
    xh_rows = []
    for est in ests:
        ne = est.nstates
        Ck = np.zeros((n, N))
        Ck[:, off:off + ne] = est.C
        xh_rows.append(Ck)
        off += ne
    for k, Ck in enumerate(xh_rows):
        rows.append(Ck)
        labels += [f'xhat{k + 1}[{key}]' for key in _keys(names)]
    for k, Ck in enumerate(xh_rows):
        rows.append(Ck - rows[0])
        labels += [f'e{k + 1}[{key}]' for key in _keys(names)]
    Cbig = np.vstack(rows)
    sys = ct.ss(Abig, Bbig, Cbig, np.zeros((Cbig.shape[0], m + q)), dt,
                inputs=[f'u[{i}]' for i in range(m)] +
                [f'w[{i}]' for i in range(q)], outputs=labels)
    X0 = [np.broadcast_to(np.asarray(x0, dtype=float), (n,))]
    xh = np.zeros(n) if xhat0 is None else \
        np.broadcast_to(np.asarray(xhat0, dtype=float), (n,))
    for obs in group:
        # every copy starts at xhat0, disturbance estimates at 0
        init = np.zeros((obs.copies, obs.problem.n))
        init[:, :n] = xh
        X0.append(init.ravel())
    U = _signal(u, m, T, 'u')
    W = _signal(w, q, T, 'w')
    return ct.forced_response(sys, T, np.vstack([U, W]),
                              X0=np.concatenate(X0))


def _time_grid(T, dt):
    """The time points as a checked 1-D array: finite, increasing, and
    in whole steps of ``dt`` for a discrete plant."""
    try:
        T = np.asarray(T, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ArgumentError("timepts must be an array of times; found "
                            f"{type(T).__name__}") from exc
    if T.ndim != 1 or T.size < 2:
        raise DimensionError("timepts must be a 1-D array of at least two "
                             f"times; found shape {T.shape}")
    if not np.all(np.isfinite(T)):
        raise ParameterError("timepts must be finite; found NaN or inf")
    steps = np.diff(T)
    if np.any(steps <= 0):
        raise ParameterError("timepts must increase strictly; found a step "
                             f"of {steps.min():.6g}")
    if dt:
        step = 1.0 if dt is True else float(dt)
        ratio = steps / step
        if np.any(np.abs(ratio - np.round(ratio)) > 1e-6 * np.maximum(
                1.0, ratio)):
            bad = float(steps[int(np.argmax(np.abs(ratio -
                                                   np.round(ratio))))])
            raise ParameterError(
                f"timepts must be in whole steps of the plant's dt = "
                f"{step:g}; found a step of {bad:.6g} (use, e.g., "
                f"np.arange(0, tf, {step:g}))")
    return T


def _state_names(plant, n):
    """The plant's state names (python-control's ``x[i]`` by default)."""
    names = getattr(plant, 'state_labels', None)
    if names is None or len(names) != n:
        return [f'x[{i}]' for i in range(n)]
    return list(names)


def _keys(names):
    """What goes between the brackets of ``xhat1[...]``: the index for
    python-control's default names, else the state's name."""
    return [str(i) if name == f'x[{i}]' else name
            for i, name in enumerate(names)]


def _signal(sig, channels, T, name):
    try:
        arr = np.asarray(sig, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"{name} must be numbers; found "
                            f"{type(sig).__name__}") from exc
    if not np.all(np.isfinite(arr)):
        raise ParameterError(f"{name} must be finite; found NaN or inf "
                             "(every output would be NaN)")
    if arr.ndim == 0:
        return np.full((channels, len(T)), float(arr))
    if arr.ndim == 1 and arr.size == channels and arr.size != len(T):
        return np.outer(arr, np.ones(len(T)))
    arr = np.atleast_2d(arr)
    if arr.shape == (channels, len(T)):
        return arr
    if arr.shape == (1, len(T)) and channels == 1:
        return arr
    raise ArgumentError(f"{name} must be a scalar, a vector of {channels} "
                        f"constants or an array of shape ({channels}, "
                        f"{len(T)}); found shape {arr.shape}")
