"""Simulation, design maps, plots, MATLAB-style names and the figures."""

import numpy as np
import pytest
import control as ct

import controlext as cx
from controlext.paper import PAIR_33, PAIR_PENBMI

matplotlib = pytest.importorskip('matplotlib')
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402


@pytest.fixture(autouse=True)
def no_show(monkeypatch):
    monkeypatch.setattr(plt, 'show', lambda *a, **k: pytest.fail('show'))
    yield
    plt.close('all')


def paper_observers(plant):
    return [cx.LuenbergerObserver(plant, [[2.0]]),
            cx.CoupledObserver.from_pair(plant, *PAIR_33)]


def test_simulate_gives_state_estimates_errors(scalar_plant):
    T = np.linspace(0, 20, 2001)
    resp = cx.simulate(scalar_plant, paper_observers(scalar_plant), T,
                       w=0.3, x0=3.0, xhat0=5.0)
    assert resp.output_labels == ['x[0]', 'xhat1[0]', 'xhat2[0]', 'e1[0]',
                                  'e2[0]']
    out = resp.outputs
    # x(t) = 3 e^{-t/2}
    np.testing.assert_allclose(out[0], 3 * np.exp(-0.5 * T), rtol=1e-6)
    np.testing.assert_allclose(out[3], out[1] - out[0], atol=1e-12)
    # steady-state errors 0.24 and 0.2272 (Section IV-A)
    assert out[3, -1] == pytest.approx(0.24, abs=5e-5)
    assert out[4, -1] == pytest.approx(0.2272, abs=5e-5)
    assert out[3, 0] == pytest.approx(2.0) and out[4, 0] == pytest.approx(2.0)


def test_simulate_gi_with_its_noise_model():
    from controlext.paper.figures import GI_BW, gi_plant
    plant = gi_plant()
    gi = cx.gi_observer(plant, GI_BW, decay=1.0, augmented=True)
    T = np.linspace(0, 30, 3001)
    resp = cx.simulate(plant, gi, T, w=[0.3, -0.1], x0=[1.0, -1.0])
    assert np.max(np.abs(resp.outputs[-2:, -1])) < 1e-8


def test_simulate_rejects_bad_signals(scalar_plant):
    with pytest.raises(cx.ArgumentError, match=r'w must be .* found shape'):
        cx.simulate(scalar_plant, paper_observers(scalar_plant),
                    np.linspace(0, 1, 11), w=np.ones((2, 5)))
    with pytest.raises(cx.ArgumentError, match='controlext observers'):
        cx.simulate(scalar_plant, [scalar_plant], np.linspace(0, 1, 11))


def loop_map(obs, xe, xs, ye, ys):
    """Reference: a Python loop of control.linfnorm calls."""
    g = np.full((len(ys), len(xs)), np.inf)
    d = np.zeros_like(g)
    for i, yv in enumerate(ys):
        for j, xv in enumerate(xs):
            G = obs.G.copy()
            G[xe], G[ye] = xv, yv
            sys = ct.ss(*obs.problem.error_system(G))
            d[i, j] = -np.max(ct.poles(sys).real)
            if d[i, j] > 0:
                g[i, j] = ct.linfnorm(sys)[0]
    return g, d


@pytest.mark.parametrize('method', ['closed', 'batched'])
def test_design_map_matches_loop_scalar_pair(scalar_plant, method):
    pair = cx.CoupledObserver.from_pair(scalar_plant, 2.0, 2.0, 0.0, 0.0)
    ell = np.linspace(-6, 6, 13)
    m = cx.design_map(pair, (0, 1), ell, (1, 0), ell, method=method)
    g, d = loop_map(pair, (0, 1), ell, (1, 0), ell)
    np.testing.assert_array_equal(np.isfinite(m.gamma), np.isfinite(g))
    fin = np.isfinite(g)
    np.testing.assert_allclose(m.gamma[fin], g[fin], rtol=1e-6)
    np.testing.assert_allclose(m.decay, d, atol=1e-9)


def test_design_map_larger_error_system(second_order_plant):
    mu = np.array([[-0.2790, 0.2160, 0.1400, -0.1149],
                   [0.0367, -0.9901, 0.3470, 0.7500]]).T
    obs = cx.CoupledObserver(second_order_plant, mu)
    xs, ys = np.linspace(-1, 1, 7), np.linspace(-1.5, 0.5, 6)
    m = cx.design_map(obs, (1, 1), xs, (2, 0), ys)
    g, d = loop_map(obs, (1, 1), xs, (2, 0), ys)
    fin = np.isfinite(g)
    assert fin.sum() > 10
    np.testing.assert_allclose(m.gamma[fin], g[fin], rtol=1e-6)
    with pytest.raises(cx.ArgumentError, match="method='closed' needs"):
        cx.design_map(obs, (1, 1), xs, (2, 0), ys, method='closed')


def test_plots_return_control_plots(scalar_plant):
    T = np.linspace(0, 5, 201)
    resp = cx.simulate(scalar_plant, paper_observers(scalar_plant), T,
                       w=0.3, x0=3.0, xhat0=5.0)
    for cplt in (cx.error_plot(resp, labels=['L', 'C']),
                 cx.estimate_plot(resp),
                 cx.tradeoff_plot({'decay': np.array([1.0, 2.0]),
                                   1: np.array([0.5, 0.6]),
                                   2: np.array([0.3, 0.4])})):
        assert isinstance(cplt, ct.ControlPlot)
        ax = cplt.axes[0, 0]
        assert ax.get_xlabel() and ax.get_ylabel() and ax.get_title()
        assert cplt.legend is not None
    pair = cx.CoupledObserver.from_pair(scalar_plant, 2.0, 2.0, 0.0, 0.0)
    ell = np.linspace(-3, 3, 20)
    cplt = cx.design_map_plot(cx.design_map(pair, (0, 1), ell, (1, 0), ell),
                              required_decay=2.5, max_gamma=0.8)
    assert cplt.axes.shape == (1, 2)
    obs = cx.CoupledObserver.from_pair(scalar_plant, *PAIR_PENBMI)
    cplt = cx.pole_region_plot(obs.poles(), cx.HalfPlane(2.5))
    assert cplt.axes[0, 0].get_xlabel() == 'Re s'


def test_matlab_names_change_no_global_setting():
    import importlib
    from control.matlab import ss      # python-control's own import sets
    before = dict(ct.config.defaults)  # freqplot.dB: snapshot after it
    import controlext.matlab as cm
    importlib.reload(cm)
    assert cm.hinfobs is cx.hinf_observer and cm.hinfnorm is cx.hinfnorm
    assert cm.coupledobs is cx.coupled_observer and cm.giobs is cx.gi_observer
    sys = ss([[-0.5]], [[1.0]], [[1.0]], 0)
    assert cm.hinfnorm(cm.luenobs(sys, [-2.5]))[0] == pytest.approx(0.8)
    assert dict(ct.config.defaults) == before


@pytest.mark.parametrize('name', ['figure_2', 'figure_3', 'figure_4',
                                  'figure_5', 'figure_gi'])
def test_cheap_figures_draw(name):
    from controlext.paper import figures
    fig = getattr(figures, name)()
    assert fig.axes and all(a.get_xlabel() for a in fig.axes
                            if a.get_label() != '<colorbar>')


def test_design_map_mimo_error_system():
    """8-state error system with 2 noise inputs and 4 outputs (the 2 × 2
    closed form for the largest singular value)."""
    A = [[-0.0558, -0.9968, 0.0802, 0.0415], [0.5980, -0.1150, -0.0318, 0],
         [-3.0500, 0.3880, -0.4650, 0], [0, 0.0805, 1.0000, 0]]
    B = [[0.0073, 0], [-0.4750, 0.0077], [0.1530, 0.1430], [0, 0]]
    C = [[0, 1, 0, 0], [0, 0, 0, 1]]
    plant = ct.ss(A, B, C, np.zeros((2, 2)))
    L = cx.luenberger_observer(plant, [-1, -1.5, -2, -2.5]).L
    obs = cx.CoupledObserver(plant, np.kron(np.eye(2), L))
    xs = L[0, 0] + np.linspace(-1, 1, 5)
    ys = np.linspace(-1, 1, 4)
    m = cx.design_map(obs, (0, 2), xs, (4, 1), ys)
    g, d = loop_map(obs, (0, 2), xs, (4, 1), ys)
    fin = np.isfinite(g)
    assert fin.sum() >= 10
    np.testing.assert_allclose(m.gamma[fin], g[fin], rtol=1e-6)
    np.testing.assert_allclose(m.decay, d, atol=1e-9)


def test_control_plot_shapes_follow_python_control(second_order_plant):
    """python-control's own ControlPlot: ``lines`` has the shape of
    ``axes``, each element the list of that axes' lines.  Ours likewise,
    for every plot; label= and legend_loc= as in python-control."""
    own = ct.step_response(second_order_plant).plot()
    assert own.lines.shape == own.axes.shape
    obs = cx.LuenbergerObserver(second_order_plant, [[2.0], [5.0]])
    resp = cx.simulate(second_order_plant, obs, np.linspace(0, 5, 51),
                       initial_state=[1.0, 0.0])
    plots = [cx.error_plot(resp), cx.estimate_plot(resp),
             cx.pole_region_plot(obs, cx.HalfPlane(1.0)),
             cx.tradeoff_plot({'decay': np.array([1.0, 2.0]),
                               1: np.array([0.5, 0.7])})]
    for cplt in plots:
        assert cplt.lines.shape == cplt.axes.shape == (1, 1)
        assert isinstance(cplt.lines[0, 0], list)
        assert all(hasattr(line, 'get_xdata') for line in cplt.lines[0, 0])
    labelled = cx.error_plot(resp, label='mine', legend_loc='lower left')
    legend = labelled.axes[0, 0].get_legend()
    assert [t.get_text() for t in legend.get_texts()] == ['mine']
    assert legend._loc == 3                     # matplotlib's 'lower left'
    assert cx.error_plot(resp, legend_loc=False).axes[0, 0].get_legend() \
        is None
    with pytest.raises(cx.ArgumentError):
        cx.error_plot(resp, labels=['a'], label='b')
    plt.close('all')


def test_plots_of_a_plant_with_named_states():
    plant = ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]],
                  0, states=['pos', 'vel'])
    obs = cx.LuenbergerObserver(plant, [[2.0], [5.0]])
    resp = cx.simulate(plant, obs, np.linspace(0, 5, 51),
                       initial_state=[1.0, 0.0])
    e = resp.outputs[resp.output_labels.index('e1[vel]')]
    line = cx.error_plot(resp, norm=False).lines[0, 0][1]
    np.testing.assert_allclose(line.get_ydata(), e)
    assert cx.estimate_plot(resp, state=1).axes[0, 0].get_ylabel() == \
        'vel and estimates'
    plt.close('all')
