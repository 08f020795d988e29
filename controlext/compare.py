"""Observers side by side, with the Kalman filter most users would pick.

:func:`compare` prints (and returns as data) the trade-off of each
observer — γ, the floor γ∞*, the H2 norm, the gain norm, the transient,
the decay and its sensitivity to gain errors — beside the Kalman filter
of the same plant and noise model (the filter Riccati equation, as
``control.lqe`` / ``control.dlqe`` solve it, with the noise correlation):
the unit-intensity noise ``w`` of ``x' = A x + Bw w``, ``y = C x + Dw w``
gives process noise ``I``, sensor noise ``Dw Dwᵀ`` and their correlation
``Dwᵀ``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.linalg as la

from .exceptions import ArgumentError
from .luenberger import LuenbergerObserver
from .observers import Observer
from .synthesis.tradeoff import Tradeoff

if TYPE_CHECKING:
    from ._typing import Plant

__all__ = ['Comparison', 'compare', 'kalman_observer']


@dataclass(repr=False)
class Comparison:
    """Trade-off rows of :func:`compare`; ``str()`` is the table.

    Attributes
    ----------
    rows : list of Tradeoff
        One row per design.
    notes : list of str
        What the table's reader should know (the floor, the Kalman filter).
    """
    rows: list[Tradeoff]
    notes: list[str] = field(default_factory=list)

    def as_dict(self) -> dict[str, dict[str, Any]]:
        """``{name: numbers}`` for every row."""
        return {row.name: row.as_dict() for row in self.rows}

    def __getitem__(self, name: str) -> Tradeoff:
        for row in self.rows:
            if row.name == name:
                return row
        raise KeyError(name)

    def __repr__(self) -> str:
        return f"<Comparison of {', '.join(r.name for r in self.rows)}>"

    def __str__(self) -> str:
        head = (f"{'observer':<14}{'γ (H∞)':>10}{'floor':>10}{'H2':>10}"
                f"{'‖G‖':>10}{'peak':>8}{'settle':>9}{'decay':>9}"
                f"{'lost@1e-3':>11}")

        def cell(value, width, fmt='.4g'):
            return f"{'n/a':>{width}}" if value is None else \
                f"{value:>{width}{fmt}}"
        lines = [head, '-' * len(head)]
        for r in self.rows:
            lines.append(f"{r.name[:13]:<14}{cell(r.hinf, 10)}"
                         f"{cell(r.floor, 10)}{cell(r.h2, 10)}"
                         f"{cell(r.gain_norm, 10)}{cell(r.peak, 8, '.3g')}"
                         f"{cell(r.settling_time, 9, '.3g')}"
                         f"{cell(r.decay, 9, '.3g')}"
                         f"{cell(r.sensitivity.get(1e-3), 11, '.2g')}")
        return '\n'.join(lines + self.notes)


def kalman_observer(obs: Observer, name: str = 'kalman'
                    ) -> LuenbergerObserver:
    """The Kalman filter of ``obs``'s plant and noise model, as an
    observer (the steady-state gain, as ``control.lqe`` — or
    ``control.dlqe`` in discrete time, in the predictor form the other
    observers use — gives it, with the correlation of process and sensor
    noise that a shared noise vector ``w`` brings).

    Parameters
    ----------
    obs : Observer
        Its plant and noise model (``Bw``, ``Dw``) are used.
    name : str, optional
        System name of the returned observer.

    Returns
    -------
    LuenbergerObserver

    Raises
    ------
    ArgumentError
        If the sensor noise ``Dw Dwᵀ`` is singular (no Kalman gain).

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> obs = cx.LuenbergerObserver(plant, [[2.0]], Bw=[[1.0, 0.0]],
    ...                             Dw=[[0.0, 1.0]])
    >>> kf = cx.kalman_observer(obs)
    >>> round(float(kf.L[0, 0]), 6)         # -0.5 + sqrt(1.25)
    0.618034
    """
    prob = obs.problem
    n = prob.nx
    A, C = prob.A[:n, :n], prob.C[:, :n]
    Bw, Dw = prob.plant_Bw, prob.plant_Dw
    R = Dw @ Dw.T
    if np.linalg.matrix_rank(R) < R.shape[0]:
        raise ArgumentError(
            "no Kalman filter: the sensor noise Dw Dwᵀ is singular (a "
            "measurement without noise); found Dw = "
            f"{np.array2string(Dw, precision=3)}")
    # process noise Bw Bwᵀ, correlated with the sensor noise by Bw Dwᵀ
    # (control.lqe does not take the cross-covariance)
    S = Bw @ Dw.T
    try:
        if prob.dt:
            P = la.solve_discrete_are(A.T, C.T, Bw @ Bw.T, R, s=S)
            L = (A @ P @ C.T + S) @ la.inv(C @ P @ C.T + R)
        else:
            P = la.solve_continuous_are(A.T, C.T, Bw @ Bw.T, R, s=S)
            L = (P @ C.T + S) @ la.inv(R)
    except (ValueError, np.linalg.LinAlgError) as exc:
        raise ArgumentError(f"no Kalman filter: the filter Riccati "
                            f"equation has no stabilising solution ({exc}); "
                            "is the plant detectable and every unstable "
                            "mode reached by the noise?") from exc
    return LuenbergerObserver(obs.plant, L, Bw=Bw, Dw=Dw,
                              Cz=prob.Cz[:, :n], name=name)


def compare(*observers: Observer, kalman: bool = True) -> Comparison:
    """The trade-off of each observer side by side (and the Kalman filter
    of the first one's plant and noise model).

    Parameters
    ----------
    *observers : Observer
        Designs of the same plant (their names label the rows).
    kalman : bool, optional
        Add the Kalman filter's row (skipped, with a note, where the
        sensor noise is singular).

    Returns
    -------
    Comparison
        ``print()`` it for the table; ``.rows`` and ``.as_dict()`` hold
        the numbers.

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> noise = dict(Bw=[[1.0, 0.0]], Dw=[[0.0, 1.0]])
    >>> table = cx.compare(cx.hinf_observer(plant, decay=2.5, name='hinf',
    ...                                     **noise))
    >>> [row.name for row in table.rows]
    ['hinf', 'kalman']
    >>> bool(table['kalman'].h2 <= table['hinf'].h2)
    True
    """
    if not observers or not all(isinstance(o, Observer) for o in observers):
        raise ArgumentError("compare expects controlext observers; found "
                            f"{[type(o).__name__ for o in observers]}")
    rows = [o.tradeoff for o in observers]
    for row, o in zip(rows, observers):
        row.name = o.name
    notes = []
    if kalman:
        try:
            kf = kalman_observer(observers[0])
        except ArgumentError as exc:
            notes.append(f"(no Kalman row: {exc})")
        else:
            rows.append(kf.tradeoff)
    return Comparison(rows, notes)
