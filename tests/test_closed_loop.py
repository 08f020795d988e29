"""Estimators in python-control's closed-loop tools: for every observer
kind, continuous and discrete, ``ct.create_statefbk_iosystem(plant, K,
estimator=obs.estimator())`` builds the loop, its poles are the
regulator's and the observer's error poles (the separation principle),
and the estimate converges to the state in simulation."""

import warnings

import numpy as np
import pytest
import control as ct

import controlext as cx

A = np.array([[0.0, 1.0], [2.0, -0.5]])          # unstable: feedback needed
B = np.array([[0.0], [1.0]])
C = np.array([[1.0, 0.0], [1.0, 0.0]])           # redundant sensors
BW = np.array([[0.2, -0.1], [0.5, 0.3]])
L1 = np.array([[3.0, 3.0], [5.0, 5.0]]) / 2


def _plant(dt):
    plant = ct.ss(A, B, C, 0, name='plant', inputs=['force'],
                  outputs=['pos_a', 'pos_b'], states=['pos', 'vel'])
    return ct.c2d(plant, dt) if dt else plant


def _observer(kind, plant):
    dt = plant.dt
    L = L1 * (0.1 if dt else 1.0)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', UserWarning)
        if kind == 'luenberger':
            return cx.LuenbergerObserver(plant, L)
        if kind == 'coupled':
            return cx.CoupledObserver(plant, np.kron(np.eye(2), L) + 0.05)
        if kind == 'gi':
            return cx.GIObserver(plant, L, BW)
        return cx.gi_observer(plant, BW, decay=0.5, augmented=True,
                              refine=False)


@pytest.mark.parametrize('dt', [0, 0.05], ids=['continuous', 'discrete'])
@pytest.mark.parametrize('kind', ['luenberger', 'coupled', 'gi',
                                  'augmented-gi'])
def test_state_feedback_loop_with_estimator(kind, dt):
    plant = _plant(dt)
    obs = _observer(kind, plant)
    assert np.all(np.abs(ct.poles(obs)) < 1) if dt else \
        np.all(ct.poles(obs).real < 0)
    K = ct.dlqr(plant, np.eye(2), np.eye(1))[0] if dt else \
        ct.lqr(plant, np.eye(2), np.eye(1))[0]
    est = obs.estimator()
    assert est.output_labels == ['xhat[0]', 'xhat[1]']
    assert est.input_labels == ['pos_a', 'pos_b', 'force']
    ctrl, loop = ct.create_statefbk_iosystem(plant, K, estimator=est)
    # separation: regulator poles ∪ observer error poles (independent:
    # eigenvalues of A - B K and of the error matrix)
    expect = np.concatenate([np.linalg.eigvals(plant.A - plant.B @ K),
                             np.linalg.eigvals(obs.A)])
    got = np.linalg.eigvals(ct.ss(loop).A)
    np.testing.assert_allclose(np.sort_complex(got), np.sort_complex(expect),
                               atol=1e-8)
    # the estimate converges to the state from a wrong start
    rate = -np.log(np.max(np.abs(got))) / dt if dt else -np.max(got.real)
    horizon = 30 / rate
    T = np.arange(int(horizon / dt)) * dt if dt else \
        np.linspace(0, horizon, 3001)
    x0 = np.concatenate([[1.0, -0.5], np.zeros(loop.nstates - 2)])
    resp = ct.input_output_response(loop, T, 0 * T if loop.ninputs == 1
                                    else np.zeros((loop.ninputs, T.size)),
                                    X0=x0)
    xs = resp.states[:2]
    xhat = resp.states[2:2 + obs.problem.n][:2]
    if obs.copies > 1:
        xhat = 0.5 * (resp.states[2:4] + resp.states[4:6])
    assert np.linalg.norm(xs[:, -1] - xhat[:, -1]) < 1e-6
    assert np.linalg.norm(xs[:, -1]) < 1e-6          # and the loop is stable


@pytest.mark.parametrize('kind', ['luenberger', 'coupled', 'gi'])
def test_the_error_system_is_refused_as_an_estimator(kind):
    """The observer object is the error system (inputs the noise, outputs
    the error): python-control would take it for an estimator and build a
    loop that feeds the error to the regulator.  It is refused, and the
    message says what to pass; the right call builds the loop."""
    plant = _plant(0)
    obs = _observer(kind, plant)
    K = ct.place(plant.A, plant.B, [-1, -2])
    with pytest.raises(cx.ArgumentError, match=r'obs\.estimator\(\)'):
        ct.create_statefbk_iosystem(plant, K, estimator=obs)
    ctrl, loop = ct.create_statefbk_iosystem(plant, K,
                                             estimator=obs.estimator())
    assert loop.nstates == plant.nstates + obs.estimator().nstates
    # the property still reads as python-control's everywhere else
    assert obs.state_labels == list(obs.state_index)
