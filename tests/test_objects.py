"""Observer objects: attributes, copies, pickling, python-control algebra,
and the runnable estimator wired to the plant."""

import copy
import pickle

import numpy as np
import pytest
import control as ct

import controlext as cx


@pytest.fixture
def obs(second_order_plant):
    return cx.LuenbergerObserver(second_order_plant, [[2.0], [5.0]],
                                 name='obs')


def test_realisation_is_the_error_system(obs, second_order_plant):
    A, C = second_order_plant.A, second_order_plant.C
    L = np.array([[2.0], [5.0]])
    np.testing.assert_allclose(obs.A, A - L @ C)
    np.testing.assert_allclose(obs.B, L)           # L Dw - Bw, Bw = 0
    np.testing.assert_allclose(obs.C, np.eye(2))
    np.testing.assert_allclose(obs.D, 0)
    assert isinstance(obs, ct.StateSpace) and isinstance(obs, cx.Observer)
    assert obs.input_labels == ['w[0]']
    assert obs.output_labels == ['ebar[0]', 'ebar[1]']
    np.testing.assert_allclose(obs.L, L)
    assert obs.report.method == 'given'
    np.testing.assert_allclose(obs.plant.A, A)


def test_noise_model_enters_the_realisation(second_order_plant):
    Bw = np.array([[1.0], [0.5]])
    Dw = np.array([[0.2]])
    Cz = np.array([[1.0, 0.0]])
    L = np.array([[2.0], [5.0]])
    obs = cx.LuenbergerObserver(second_order_plant, L, Bw=Bw, Dw=Dw, Cz=Cz)
    np.testing.assert_allclose(obs.B, L @ Dw - Bw)
    np.testing.assert_allclose(obs.C, Cz)


@pytest.mark.parametrize('clone', [
    copy.deepcopy, copy.copy, lambda o: o.copy(),
    lambda o: pickle.loads(pickle.dumps(o)),
], ids=['deepcopy', 'copy', 'method', 'pickle'])
def test_copies_keep_class(obs, clone):
    new = clone(obs)
    assert type(new) is cx.LuenbergerObserver
    np.testing.assert_allclose(new.L, obs.L)
    assert new.report.hinf == obs.report.hinf
    assert ct.linfnorm(new)[0] == pytest.approx(0.4859, rel=1e-3)
    np.testing.assert_allclose(new.estimator().A, obs.estimator().A)


def test_algebra_returns_plain_statespace(obs):
    for result in (obs * 2, obs + obs, obs[0, 0], obs.sample(0.1),
                   ct.minreal(obs, verbose=False)):
        assert type(result) is ct.StateSpace


def test_estimator_signals(obs):
    est = obs.estimator()
    assert est.input_labels == ['y[0]', 'u[0]']     # as ct.create_estimator_iosystem
    assert est.output_labels == ['xhat[0]', 'xhat[1]']
    assert est.name == 'obs_estimator'


def test_estimator_converges_to_plant_state(second_order_plant):
    A, B, C = second_order_plant.A, second_order_plant.B, \
        second_order_plant.C
    # the plant also outputs its state, so the test can compare
    plant = ct.ss(A, B, np.vstack([C, np.eye(2)]), np.zeros((3, 1)),
                  name='plant', inputs='u', outputs=['y', 'x[0]', 'x[1]'])
    design_plant = ct.ss(A, B, C, 0, inputs='u', outputs='y')
    obs = cx.hinf_observer(design_plant, decay=1.0)
    est = obs.estimator(name='est')
    assert est.input_labels == ['y', 'u']
    closed = ct.interconnect(
        [plant, est], inplist=[['plant.u', 'est.u']],
        outlist=['x[0]', 'x[1]', 'xhat[0]', 'xhat[1]'],
        connections=[['est.y', 'plant.y']], inputs='u')
    # horizon from the slowest error pole: 12 time constants
    T = np.linspace(0, 12 / obs.decay, 3001)
    u = np.sin(T)
    x0 = np.array([1.0, -2.0, 0.0, 0.0])         # estimate starts at 0
    resp = ct.forced_response(closed, T, u, X0=x0)
    err = resp.outputs[2:] - resp.outputs[:2]
    assert np.linalg.norm(err[:, 0]) > 1
    assert np.linalg.norm(err[:, -1]) < 1e-4 * np.linalg.norm(err[:, 0])


def test_readable_design(second_order_plant):
    obs = cx.hinf_observer(second_order_plant, decay=1.0, name='obs1')
    with _repr_format('info'):
        text = repr(obs)
    assert text.startswith("<LuenbergerObserver 'obs1': copies=1")
    assert f"γ={obs.hinf:.6g}" in text and "stage='refined'" in text
    shown = str(obs)
    assert 'H∞ norm γ, noise → error' in shown and 'G =' in shown
    # plain words for how the gain was found, aligned rows, no -0
    assert 'refined on the true norm' in shown and '-0 ' not in shown
    for line in shown.split('G =')[0].splitlines()[1:]:
        assert line[27] == ' ' and line[28] != ' ', line
    assert 'refined' in shown
    # python-control's print of the system, signal names and matrices
    plain = ct.ss(obs.A, obs.B, obs.C, obs.D, inputs=obs.input_labels,
                  outputs=obs.output_labels, states=obs.state_labels)
    for line in str(plain).splitlines()[1:]:
        assert line in shown
    html = obs._repr_html_()
    assert '<table>' in html and 'LuenbergerObserver' in html
    assert len(repr(obs.report)) < 200
    assert 'convex bound' in repr(obs.report)


class _repr_format:
    """``config.defaults['iosys.repr_format']`` set for a block."""

    def __init__(self, fmt):
        self.fmt = fmt

    def __enter__(self):
        self.old = ct.config.defaults.get('iosys.repr_format')
        ct.config.defaults['iosys.repr_format'] = self.fmt

    def __exit__(self, *exc):
        if self.old is None:
            del ct.config.defaults['iosys.repr_format']
        else:
            ct.config.defaults['iosys.repr_format'] = self.old


@pytest.mark.skipif('iosys.repr_format' not in ct.config.defaults,
                    reason="python-control without repr_format (< 0.10.2)")
def test_repr_follows_python_controls_format(second_order_plant):
    """'eval' rebuilds the system (here the error system, which the
    observer is), as python-control's own repr does; 'info' summarises."""
    obs = cx.LuenbergerObserver(second_order_plant, [[2.0], [5.0]])
    with _repr_format('eval'):
        rebuilt = eval(repr(obs), {'StateSpace': ct.StateSpace,
                                   'array': np.array})
        assert repr(obs).startswith('StateSpace(')
    np.testing.assert_array_equal(rebuilt.A, second_order_plant.A -
                                  np.array([[2.0], [5.0]]) @
                                  second_order_plant.C)
    with _repr_format('info'):
        assert repr(obs).startswith('<LuenbergerObserver')


def test_matlab_conventions(second_order_plant):
    import controlext.matlab as cm
    L = np.array([[2.0], [5.0]])
    est = cm.estim(second_order_plant, L)
    A, C = second_order_plant.A, second_order_plant.C
    np.testing.assert_allclose(est.A, A - L @ C)           # x̂' = (A-LC)x̂+..
    np.testing.assert_allclose(est.C[:1], C)               # ŷ = C x̂
    np.testing.assert_allclose(est.C[1:], np.eye(2))       # x̂
    # MATLAB's two-argument estim: every input is unmeasured noise, the
    # estimator's inputs are the measurements y only
    assert est.ninputs == 1
    np.testing.assert_allclose(est.B, L)
    known = cm.estim(second_order_plant, L, [0], [0])       # inputs [y; u]
    np.testing.assert_allclose(known.B, np.hstack([L, second_order_plant.B]))
    with pytest.raises(cx.ParameterError, match='known'):
        cm.estim(second_order_plant, L, [0], [3])
    obs = cx.LuenbergerObserver(second_order_plant, L)
    t = np.linspace(0, 5, 101)
    y, tout, x = cm.obsim(second_order_plant, obs, t, x0=[1.0, 0.0])
    resp = cx.simulate(second_order_plant, obs, t, initial_state=[1.0, 0.0])
    np.testing.assert_allclose(y, resp.outputs.T)
    assert y.shape == (101, 6) and x.shape[0] == 101
    np.testing.assert_allclose(tout, t)
    unstable = ct.ss([[1.0]], [[1.0]], [[1.0]], 0)
    assert cm.hinfnorm(unstable) == (np.inf, np.inf)        # MATLAB: Inf
