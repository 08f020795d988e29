"""Plots of observer data (matplotlib, an optional dependency).

Each function draws into a new figure (or the given axes), returns a
:class:`control.ControlPlot` — python-control's convention, with
``.lines``, ``.axes`` and ``.figure`` — and never calls ``plt.show()``.

Examples
--------
>>> import numpy as np
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
>>> luen = cx.LuenbergerObserver(plant, [[2.0]])
>>> resp = cx.simulate(plant, [luen], np.linspace(0, 5, 101), w=0.3,
...                    x0=3.0, xhat0=5.0)
>>> cplt = cx.error_plot(resp, labels=['Luenberger'])
>>> cplt.axes.shape
(1, 1)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any
import numpy as np
import control as ct
from ._typing import Array, ArrayLike
from .exceptions import ArgumentError, DimensionError, ParameterError

if TYPE_CHECKING:
    from .maps import DesignMap
    from .observers import Observer
    from .synthesis import Region
    from .sweep import Sweep

__all__ = ['error_plot', 'estimate_plot', 'tradeoff_plot',
           'design_map_plot', 'pole_region_plot', 'sweep_plot']


def _plt():
    try:
        import matplotlib.pyplot as plt
    except ImportError as exc:          # pragma: no cover
        raise ImportError("plotting needs matplotlib: pip install "
                          "matplotlib") from exc
    return plt


def _axes(ax, ncols=1):
    plt = _plt()
    if ax is None:
        fig, ax = plt.subplots(1, ncols, figsize=(6.4 * ncols, 4.2),
                               squeeze=False)
        return fig, ax
    ax = np.atleast_2d(np.asarray(ax, dtype=object))
    return ax.flat[0].figure, ax


def _lines(lines):
    """python-control's ``ControlPlot.lines``: an array shaped like the
    axes whose element is the list of that axes' artists."""
    out = np.empty((1, 1), dtype=object)
    out[0, 0] = list(lines)
    return out


def _finish(a, lines, ax, fig, legend_loc=None, default_loc='best'):
    """Grid, legend (none for ``legend_loc=False``, python-control's
    convention) and the ``ControlPlot`` of one axes."""
    a.grid(True, alpha=0.3)
    legend = None if legend_loc is False else \
        a.legend(loc=legend_loc or default_loc)
    return ct.ControlPlot(_lines(lines), ax, fig, legend=legend)


def _labels(labels, label, count):
    """One label per observer from ``labels=`` or python-control's
    ``label=`` (a string for one observer, or a list)."""
    if label is not None:
        if labels is not None:
            raise ArgumentError("give labels= or label=, not both")
        labels = [label] if isinstance(label, str) else list(label)
    labels = list(labels) if labels is not None else \
        [f'observer {k + 1}' for k in range(count)]
    if len(labels) != count:
        raise DimensionError(f"expected {count} labels (one per observer); "
                             f"found {len(labels)}")
    return labels


def _layout(resp):
    """``(n, K)``: the plant's states and the observers of a
    :func:`controlext.simulate` response, whose outputs are the plant
    state, then each observer's estimate, then each observer's error,
    ``n`` signals each."""
    n = sum(1 for lb in resp.output_labels if lb.startswith('e1['))
    K = (len(resp.output_labels) // n - 1) // 2 if n else 0
    return n, K


def error_plot(resp: ct.TimeResponseData, labels: Sequence[str] | None = None,
               norm: bool = True, ax: Any = None,
               title: str | None = None, *,
               label: str | Sequence[str] | None = None,
               legend_loc: str | bool | None = None) -> Any:
    """Estimation errors of a :func:`controlext.simulate` response.

    Parameters
    ----------
    resp : control.TimeResponseData
        From :func:`controlext.simulate`.
    labels : list of str, optional
        One label per observer.
    norm : bool, optional
        Plot ``|e_k(t)|`` (default) instead of each error component.
    ax : matplotlib axes, optional
        Axes to draw in (default: a new figure).
    title : str, optional
        Axes title.
    label : str or list of str, optional
        python-control's name for ``labels``.
    legend_loc : str or False, optional
        Legend location (matplotlib's names); ``False`` draws none.

    Returns
    -------
    control.ControlPlot

    Examples
    --------
    >>> import numpy as np
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> obs = cx.LuenbergerObserver(plant, [[2.0]])
    >>> resp = cx.simulate(plant, obs, np.linspace(0, 5, 51), x0=1.0)
    >>> cx.error_plot(resp).axes[0, 0].get_ylabel()
    '|e(t)|'
    """
    n, K = _layout(resp)
    labels = _labels(labels, label, K)
    fig, ax = _axes(ax)
    a = ax[0, 0]
    lines = []
    out = np.atleast_2d(resp.outputs)
    for k in range(K):
        first = n * (1 + K + k)
        e = out[first:first + n]
        if norm:
            lines += a.plot(resp.time, np.linalg.norm(e, axis=0),
                            label=labels[k])
        else:
            for i in range(n):
                name = resp.output_labels[i]
                lines += a.plot(resp.time, e[i], label=f'{labels[k]}, '
                                f'e[{i if name == f"x[{i}]" else name}]')
    a.axhline(0.0, color='0.6', lw=0.8)
    a.set_xlabel('time t [s]')
    a.set_ylabel('|e(t)|' if norm else 'e(t)')
    a.set_title(title or 'Estimation error')
    return _finish(a, lines, ax, fig, legend_loc)


def estimate_plot(resp: ct.TimeResponseData,
                  labels: Sequence[str] | None = None, state: int = 0,
                  ax: Any = None, title: str | None = None, *,
                  label: str | Sequence[str] | None = None,
                  legend_loc: str | bool | None = None) -> Any:
    """True state and each observer's estimate of one state component.

    Parameters
    ----------
    resp : control.TimeResponseData
        From :func:`controlext.simulate`.
    labels : list of str, optional
        One label per observer.
    state : int, optional
        Which state component (default 0).
    ax : matplotlib axes, optional
        Axes to draw in (default: a new figure).
    title : str, optional
        Axes title.
    label : str or list of str, optional
        python-control's name for ``labels``.
    legend_loc : str or False, optional
        Legend location (matplotlib's names); ``False`` draws none.

    Returns
    -------
    control.ControlPlot

    Examples
    --------
    >>> import numpy as np
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> obs = cx.LuenbergerObserver(plant, [[2.0]])
    >>> resp = cx.simulate(plant, obs, np.linspace(0, 5, 51), x0=1.0)
    >>> len(cx.estimate_plot(resp).lines[0, 0])
    2
    """
    n, K = _layout(resp)
    labels = _labels(labels, label, K)
    if not 0 <= state < n:
        raise ParameterError(f"state must be in 0 ... {n - 1}; found {state}")
    fig, ax = _axes(ax)
    a = ax[0, 0]
    out = np.atleast_2d(resp.outputs)
    lines = a.plot(resp.time, out[state], 'r-.', label='plant state')
    styles = ['b--', 'k-', 'g:', 'm-']
    for k in range(K):
        lines += a.plot(resp.time, out[n * (1 + k) + state],
                        styles[k % len(styles)], label=labels[k])
    a.set_xlabel('time t [s]')
    a.set_ylabel(f'{resp.output_labels[state]} and estimates')
    a.set_title(title or 'Plant state and estimates')
    return _finish(a, lines, ax, fig, legend_loc)


def tradeoff_plot(curve: dict[Any, Array], ax: Any = None,
                  title: str | None = None) -> Any:
    """γ against required decay, one line per number of copies.

    ``curve`` is the dictionary of :func:`controlext.tradeoff_curve`.

    Parameters
    ----------
    curve : dict
        From :func:`controlext.tradeoff_curve`.
    ax : matplotlib axes, optional
        Axes to draw in (default: a new figure).
    title : str, optional
        Axes title.

    Returns
    -------
    control.ControlPlot

    Examples
    --------
    >>> import numpy as np
    >>> import controlext as cx
    >>> curve = {'decay': np.array([1.0, 2.0]), 1: np.array([0.5, 0.7]),
    ...          2: np.array([0.1, 0.3])}
    >>> cx.tradeoff_plot(curve).axes[0, 0].get_xlabel()
    'required decay rate σ'
    """
    fig, ax = _axes(ax)
    a = ax[0, 0]
    lines = []
    markers = {1: 'o-', 2: 's-', 3: '^-'}
    for N in sorted(k for k in curve if k != 'decay'):
        name = 'Luenberger (N = 1)' if N == 1 else f'coupled, N = {N}'
        lines += a.plot(curve['decay'], curve[N], markers.get(N, 'x-'),
                        label=name)
    a.set_xlabel('required decay rate σ')
    a.set_ylabel('H∞ norm γ (noise → error)')
    a.set_title(title or 'Trade-off: robustness against rate of convergence')
    return _finish(a, lines, ax, fig)


def design_map_plot(dmap: DesignMap, required_decay: float | None = None,
                    max_gamma: float | None = None, ax: Any = None,
                    labels: tuple[str, str] = ('ℓ1', 'ℓ2'),
                    title: str | None = None) -> Any:
    """Heat maps of γ and of the decay rate over a design map.

    Draws two panels (γ, decay); with ``required_decay`` the contour
    ``decay = required_decay`` is drawn on both, and with ``max_gamma``
    the contour ``γ = max_gamma``.

    Parameters
    ----------
    dmap : DesignMap
        From :func:`controlext.design_map`.
    required_decay : float, optional
        Draw the contour of this decay rate.
    max_gamma : float, optional
        Draw the contour of this γ.
    ax : matplotlib axes, optional
        Two axes to draw in (default: a new figure).
    labels : (str, str), optional
        Axis labels of the two gain entries.
    title : str, optional
        Figure title.

    Returns
    -------
    control.ControlPlot

    Examples
    --------
    >>> import numpy as np
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> pair = cx.CoupledObserver.from_pair(plant, 2.0, 2.0, 0.0, 0.0)
    >>> ell = np.linspace(-6, 6, 50)
    >>> m = cx.design_map(pair, (0, 1), ell, (1, 0), ell)
    >>> cx.design_map_plot(m, required_decay=2.5).axes.shape
    (1, 2)
    """
    plt = _plt()
    fig, ax = _axes(ax, ncols=2)
    X, Y = np.meshgrid(dmap.x, dmap.y)
    g = np.where(np.isfinite(dmap.gamma), dmap.gamma, np.nan)
    top = np.nanpercentile(g, 95) if np.any(np.isfinite(g)) else 1.0
    panels = [(ax[0, 0], np.clip(g, None, top), 'H∞ norm γ', 'viridis'),
              (ax[0, 1], np.clip(dmap.decay, 0, None), 'decay rate σ',
               'magma')]
    lines = []
    for a, data, name, cmap in panels:
        mesh = a.pcolormesh(X, Y, data, shading='auto', cmap=cmap)
        fig.colorbar(mesh, ax=a, label=name)
        if required_decay is not None:
            cs = a.contour(X, Y, dmap.decay, levels=[required_decay],
                           colors='w', linewidths=1.5)
            lines.append(cs)
        if max_gamma is not None:
            cs = a.contour(X, Y, g, levels=[max_gamma], colors='c',
                           linewidths=1.5, linestyles='--')
            lines.append(cs)
        a.set_xlabel(labels[0])
        a.set_ylabel(labels[1])
        a.set_title(name + (f' (white: σ = {required_decay:g})'
                            if required_decay is not None else ''))
    if title:
        fig.suptitle(title)
    return ct.ControlPlot(_lines(lines), ax, fig)


def pole_region_plot(obs_or_poles: Observer | ArrayLike,
                     region: Region | None = None, ax: Any = None,
                     extent: tuple[float, float, float, float] | None = None, title: str | None = None,
                     dt: float | bool | None = None) -> Any:
    """Error poles with the requested region shaded.

    Parameters
    ----------
    obs_or_poles : Observer or array_like
        An observer (its poles and ``report.region`` are used) or poles.
    region : Region, optional
        Region to shade (default: the observer's).
    extent : (re_min, re_max, im_min, im_max), optional
        Window (default: around the poles and the region).
    ax : matplotlib axes, optional
        Axes to draw in (default: a new figure).
    title : str, optional
        Axes title.
    dt : float or bool, optional
        Timebase of given poles (draws the unit circle when discrete);
        an observer's own is used.

    Returns
    -------
    control.ControlPlot

    Examples
    --------
    >>> import controlext as cx
    >>> cplt = cx.pole_region_plot([-2 + 1j, -2 - 1j], cx.HalfPlane(1.0))
    >>> cplt.axes[0, 0].get_xlabel()
    'Re s'
    """
    from .observers import Observer
    plt = _plt()
    fig, ax = _axes(ax)
    a = ax[0, 0]
    if isinstance(obs_or_poles, Observer):
        poles = ct.poles(obs_or_poles)
        if region is None:
            region = obs_or_poles.report.region
        dt = obs_or_poles.dt
    else:
        poles = np.atleast_1d(np.asarray(obs_or_poles, dtype=complex))
    if extent is None:
        r = max(1.0, 1.3 * np.max(np.abs(poles))) if poles.size else 1.0
        extent = (-r, 0.25 * r, -r, r) if not dt else (-1.2, 1.2, -1.2, 1.2)
    lines = []
    if region is not None:
        re = np.linspace(extent[0], extent[1], 300)
        im = np.linspace(extent[2], extent[3], 300)
        R, I = np.meshgrid(re, im)
        mask = region.inside(R + 1j * I)
        a.contourf(R, I, mask.astype(float), levels=[0.5, 1.5],
                   colors=['tab:green'], alpha=0.2)
        for curve in region.boundary(extent):
            lines += a.plot(curve.real, curve.imag, color='tab:green', lw=1)
    if dt:
        th = np.linspace(0, 2 * np.pi, 400)
        lines += a.plot(np.cos(th), np.sin(th), 'k:', lw=0.8,
                        label='unit circle')
    lines += a.plot(poles.real, poles.imag, 'x', ms=9, mew=2,
                    color='tab:red', label='error poles')
    a.axhline(0, color='0.6', lw=0.8)
    a.axvline(0, color='0.6', lw=0.8)
    a.set_xlim(extent[0], extent[1])
    a.set_ylim(extent[2], extent[3])
    a.set_xlabel('Re z' if dt else 'Re s')
    a.set_ylabel('Im z' if dt else 'Im s')
    a.set_title(title or (f'Error poles in {region}' if region is not None
                          else 'Error poles'))
    return _finish(a, lines, ax, fig, default_loc='upper left')


def sweep_plot(result: Sweep, y: str = 'hinf', x: str | None = None,
               ax: Any = None, title: str | None = None) -> Any:
    """Metric ``y`` against the swept values, or against metric ``x``
    with the Pareto front drawn (``x='settling_time'`` or ``x='h2'``).

    Parameters
    ----------
    result : Sweep
        From :func:`controlext.sweep`.
    y : str, optional
        Metric on the vertical axis (a :class:`~controlext.Tradeoff`
        field: ``'hinf'``, ``'h2'``, ``'settling_time'``, ...).
    x : str, optional
        Metric on the horizontal axis (default: the swept values).
    ax : matplotlib axes, optional
        Axes to draw in (default: a new figure).
    title : str, optional
        Axes title.

    Returns
    -------
    control.ControlPlot

    Examples
    --------
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> s = cx.sweep(plant, 'decay', [1.0, 2.5])
    >>> len(cx.sweep_plot(s).lines[0, 0])
    1
    """
    fig, axes = _axes(ax)
    a = axes[0, 0]
    ys = result.metric(y)
    if x is None:
        lines = a.plot(result.values, ys, 'o-', label=y)
        a.set_xlabel(result.parameter)
    else:
        xs = result.metric(x)
        lines = a.plot(xs, ys, 'o', label='designs')
        front = result.front(x, y)
        lines += a.plot(xs[front], ys[front], 'k--', lw=1,
                        label='Pareto front')
        for k, v in enumerate(result.values):
            a.annotate(f"{v:g}" if isinstance(v, float) else str(v),
                       (xs[k], ys[k]), fontsize=8)
        a.set_xlabel(x)
    a.set_ylabel(y)
    a.set_title(title or f"{y} over {result.parameter}")
    return _finish(a, lines, axes, fig)
