"""The figures of ``python -m controlext``: Section IV of Li & Sanfelice
(Figures 2–5), a trade-off figure and a GI figure.

Each ``figure_*`` function returns a matplotlib figure; :func:`write_all`
saves them as PNG files into a folder.

Examples
--------
>>> import matplotlib
>>> matplotlib.use('Agg')
>>> from controlext.paper.figures import figure_5
>>> fig = figure_5()
>>> len(fig.axes)
2
"""

import functools
import os
import sys

import numpy as np
import control as ct

from ..analysis import crossing_time
from ..coupled import CoupledObserver
from ..gi import gi_observer
from ..luenberger import LuenbergerObserver, luenberger_observer
from ..maps import design_map
from .designs import TRADEOFF_DECAYS, designs_for, tradeoff_keys
from .tables import BIAS, PAIR_33, PAIR_PENBMI, scalar_plant
from ..plot import (design_map_plot, error_plot, estimate_plot,
                   pole_region_plot, tradeoff_plot)
from ..simulate import simulate

__all__ = ['figure_2', 'figure_3', 'figure_4', 'figure_5',
           'figure_tradeoff', 'figure_gi', 'figure_poles', 'write_all']

A_SCALAR = -0.5


def _plt():
    import matplotlib.pyplot as plt
    return plt


def figure_2(seed=0):
    """Plant state, Luenberger (k0 = 2) and PENBMI-pair estimates under
    noisy measurements (x(0) = 3, estimates start at 5)."""
    plant = scalar_plant()
    luen = LuenbergerObserver(plant, [[2.0]])
    pair = CoupledObserver.from_pair(plant, *PAIR_PENBMI)
    T = np.linspace(0, 6, 1201)
    rng = np.random.default_rng(seed)
    noise = BIAS + 0.3 * np.repeat(rng.normal(size=len(T) // 10 + 1),
                                   10)[:len(T)]
    resp = simulate(plant, [luen, pair], T, w=noise, x0=3.0, xhat0=5.0)
    cplt = estimate_plot(resp, labels=['Luenberger, k0 = 2',
                                       'coupled pair (PENBMI gains)'],
                         title='Figure 2: plant state and estimates '
                               '(m = 0.3 + noise)')
    return cplt.figure


def figure_3(num=200):
    """γ and decay rate: Luenberger against k0, coupled pair over
    (ℓ1, ℓ2) with k1 = k2 = 2."""
    plt = _plt()
    fig, ax = plt.subplots(2, 2, figsize=(12, 8.5))
    k0 = np.linspace(0.05, 8, 400)
    ax[0, 0].plot(k0, k0 / (k0 - A_SCALAR), 'b')
    ax[0, 0].set(xlabel='k0', ylabel='H∞ norm γ0',
                 title='(a) Luenberger: H∞ norm against k0')
    ax[1, 0].plot(k0, k0 - A_SCALAR, 'b')
    ax[1, 0].set(xlabel='k0', ylabel='decay rate σn',
                 title='(c) Luenberger: rate of convergence against k0')
    for a in ax[:, 0]:
        a.grid(True, alpha=0.3)
    pair = CoupledObserver.from_pair(scalar_plant(), 2.0, 2.0, 0.0, 0.0)
    ell = np.linspace(-6, 6, num)
    dmap = design_map(pair, (0, 1), ell, (1, 0), ell)
    design_map_plot(dmap, ax=np.array([[ax[0, 1], ax[1, 1]]]))
    ax[0, 1].set_title('(b) coupled pair: H∞ norm, k1 = k2 = 2 '
                       '(white: unstable)')
    ax[1, 1].set_title('(d) coupled pair: decay rate σ, k1 = k2 = 2')
    fig.suptitle('Figure 3: Luenberger observer and coupled pair, a = -0.5')
    fig.tight_layout()
    return fig


def figure_4(required=2.5, num=240):
    """(a) γ0 and k0 needed for a required decay; (b) the (ℓ1, ℓ2) region
    where the coupled pair (k1 = k2 = k0) meets the decay and beats γ0."""
    plt = _plt()
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.6))
    sig = np.linspace(0.6, 6, 300)
    k0 = sig + A_SCALAR
    ax[0].plot(sig, k0 / (k0 - A_SCALAR), 'b', label='γ0 (H∞ norm)')
    ax[0].plot(sig, k0, 'g--', label='k0')
    k_req = required + A_SCALAR
    g_req = k_req / (k_req - A_SCALAR)
    ax[0].plot([required], [g_req], 'ko')
    ax[0].annotate(f'σ = {required:g}: k0 = {k_req:g}, γ0 = {g_req:.2f}',
                   (required, g_req), textcoords='offset points',
                   xytext=(10, -15))
    ax[0].set(xlabel='required decay σn,⋆', ylabel='value',
              title='(a) Luenberger: k0 and γ0 for a required decay')
    ax[0].legend()
    ax[0].grid(True, alpha=0.3)
    pair = CoupledObserver.from_pair(scalar_plant(), k_req, k_req, 0.0, 0.0)
    ell = np.linspace(-6, 6, num)
    dmap = design_map(pair, (0, 1), ell, (1, 0), ell)
    X, Y = np.meshgrid(dmap.x, dmap.y)
    fast = dmap.decay >= required - 1e-9
    better = fast & (dmap.gamma < g_req)
    ax[1].contourf(X, Y, fast.astype(float), levels=[0.5, 1.5],
                   colors=['tab:blue'], alpha=0.25)
    ax[1].contourf(X, Y, better.astype(float), levels=[0.5, 1.5],
                   colors=['tab:green'], alpha=0.6)
    ax[1].contour(X, Y, dmap.decay, levels=[required], colors='tab:blue')
    from matplotlib.patches import Patch
    ax[1].legend(handles=[
        Patch(color='tab:blue', alpha=0.25, label=f'decay ≥ {required:g}'),
        Patch(color='tab:green', alpha=0.6,
              label=f'decay ≥ {required:g} and γ < γ0 = {g_req:.2f}')],
        loc='upper right')
    ax[1].set(xlabel='ℓ1', ylabel='ℓ2',
              title=f'(b) coupled pair, k1 = k2 = {k_req:g}: feasible region')
    ax[1].grid(True, alpha=0.3)
    fig.suptitle('Figure 4: designing for a required rate of convergence')
    fig.tight_layout()
    return fig


def figure_5():
    """Errors under m = 0.3: Luenberger (k0 = 2) and the pair of (33)."""
    plt = _plt()
    plant = scalar_plant()
    luen = LuenbergerObserver(plant, [[2.0]])
    pair = CoupledObserver.from_pair(plant, *PAIR_33)
    T = np.linspace(0, 5, 1001)
    resp = simulate(plant, [luen, pair], T, w=BIAS, x0=3.0, xhat0=5.0)
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.4))
    labels = ['Luenberger, k0 = 2', 'coupled pair (33)']
    error_plot(resp, labels=labels, norm=False, ax=np.array([[ax[0]]]),
               title='(a) error trajectories, m = 0.3')
    ax[0].set_ylim(0.0, 2.1)
    i0 = resp.output_labels.index('e1[0]')
    i1 = resp.output_labels.index('e2[0]')
    out = np.atleast_2d(resp.outputs)
    ax[1].plot(T, out[i0], 'b--', label=labels[0])
    ax[1].plot(T, out[i1], 'k-', label=labels[1])
    tstar = crossing_time(luen, pair, [2.0], BIAS)
    ax[1].axvline(tstar, color='tab:red', lw=1)
    ax[1].annotate(f't⋆ = {tstar:.2f} s', (tstar, 0.26),
                   textcoords='offset points', xytext=(6, 0))
    ax[1].set(xlim=(0, 5), ylim=(0.2, 0.3), xlabel='time t [s]',
              ylabel='e(t)',
              title='(b) zoom: e* = 0.2272 (pair) < 0.2400 (Luenberger)')
    ax[1].legend()
    ax[1].grid(True, alpha=0.3)
    fig.suptitle('Figure 5: observer errors with m(t) ≡ 0.3')
    fig.tight_layout()
    return fig


def figure_tradeoff(decays=TRADEOFF_DECAYS, executor=None, designs=None):
    """Best γ against required decay, N = 1, 2, 3 (second-order plant):
    the designs taken from ``designs`` (a result of
    :func:`~controlext.paper.designs.run_designs`), those it lacks run
    on ``executor`` when given.

    Below the plant's own rate (0.5) the best gain is ``L = 0`` with
    ``γ = 0``, so the default decays start above it."""
    designs = designs_for(tradeoff_keys(decays), designs, executor)
    curve = {'decay': np.asarray(decays, dtype=float)}
    for N in (1, 2, 3):
        curve[N] = np.array([designs['second', N, float(d)].hinf
                             for d in decays])
    cplt = tradeoff_plot(curve, title='Trade-off on the second-order plant: '
                                      'γ against required decay')
    cplt.axes[0, 0].set_yscale('log')
    return cplt.figure


def gi_plant():
    """2 states, 2 redundant sensors of x1 (used by the GI figure)."""
    return ct.ss([[-1.0, 1.0], [0.0, -2.0]], [[0.0], [1.0]],
                 [[1.0, 0.0], [1.0, 0.0]], np.zeros((2, 1)))


GI_BW = np.array([[0.5, 0.2], [0.0, 1.0]])


def figure_gi():
    """Classic (placed) Luenberger against augmented GI under a constant
    disturbance on redundant sensors."""
    plant = gi_plant()
    classic = luenberger_observer(plant, [-2.0, -3.0])
    gi = gi_observer(plant, GI_BW, decay=1.0, augmented=True)
    T = np.linspace(0, 12, 1201)
    resp = simulate(plant, [classic, gi], T, u=np.sin(0.5 * T),
                    w=[0.3, -0.1], x0=[1.0, -1.0], Bw=GI_BW, Dw=np.eye(2))
    cplt = error_plot(resp, labels=['classic Luenberger (placed poles)',
                                    'augmented GI observer'],
                      title='GI: constant sensor disturbance w = [0.3, '
                            '-0.1], redundant sensors')
    cplt.axes[0, 0].set_yscale('log')
    cplt.axes[0, 0].set_ylim(1e-8, 10)
    return cplt.figure


def figure_poles(designs=None):
    """Poles of the synthesised second-order pair with its region (taken
    from ``designs`` when it holds it)."""
    key = ('second', 2, 1.0)
    obs = designs_for([key], designs)[key]
    cplt = pole_region_plot(obs, extent=(-3, 0.5, -2, 2),
                            title='Coupled pair, σ = 1: error poles in '
                                  'Re s ≤ -1')
    return cplt.figure


def write_all(folder, progress=True, executor=None, designs=None):
    """Write every figure as PNG into ``folder``; return the paths (the
    designs taken from ``designs``, those it lacks run on ``executor``
    when given)."""
    import matplotlib
    matplotlib.use('Agg')
    plt = _plt()
    os.makedirs(folder, exist_ok=True)
    show = progress and sys.stderr.isatty()
    jobs = [('figure2_estimates.png', figure_2),
            ('figure3_maps.png', figure_3),
            ('figure4_feasible_region.png', figure_4),
            ('figure5_errors.png', figure_5),
            ('tradeoff.png', functools.partial(
                figure_tradeoff, executor=executor, designs=designs)),
            ('gi_disturbance.png', figure_gi),
            ('poles_region.png', functools.partial(figure_poles,
                                                   designs=designs))]
    paths = []
    for k, (name, make) in enumerate(jobs):
        if show:
            print(f"\r[{k + 1}/{len(jobs)}] {name:<32}", end='',
                  file=sys.stderr, flush=True)
        fig = make()
        path = os.path.join(folder, name)
        fig.savefig(path, dpi=110, bbox_inches='tight')
        plt.close(fig)
        paths.append(path)
    if show:
        print(file=sys.stderr)
    return paths
