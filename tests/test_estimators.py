"""The runnable estimator equals the error system, for every kind.

N = 1, 2, 3 copies × plain / GI / augmented GI × continuous / discrete:
the estimator wired to the plant by signal name, driven by noise ``w``,
gives the estimation error ``x̂ − x`` that the observer's error system
gives for the same ``w`` and the same initial error.  The reference is a
simulation of plant and estimator (``ct.interconnect``), independent of
the error-system matrices; the gains are full coupled gains (a stable
design plus random coupling), so every off-diagonal path is exercised.
"""

import warnings

import numpy as np
import pytest
import control as ct

import controlext as cx

KINDS = ['plain', 'gi', 'augmented']


def _plant(dt):
    """3 states (one unstable), an input with feedthrough, 3 sensors of
    rank 2 (so Π has rank 1)."""
    A = np.array([[0.3, 1.0, 0.0], [-1.0, -0.4, 0.5], [0.0, 0.2, -1.5]])
    B = np.array([[0.0], [1.0], [0.5]])
    C = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 1.0], [1.0, 1.0, 1.0]])
    D = np.array([[0.0], [0.2], [0.2]])
    if dt:
        sysd = ct.c2d(ct.ss(A, B, C, D), dt)
        A, B = sysd.A, sysd.B
    return ct.ss(A, B, C, D, dt, inputs=['force'],
                 outputs=['pos', 'vel', 'sum'], name='plant')


BW = np.array([[0.5, -0.2, 0.1], [0.0, 0.3, 0.4], [0.2, 0.0, -0.3]])


def _stable(obs):
    poles = ct.poles(obs)
    return np.max(np.abs(poles)) < 0.995 if obs.dt else \
        np.max(poles.real) < -0.05


def _observer(kind, copies, dt, seed=0):
    """A stable observer of the kind with a full coupled gain."""
    plant = _plant(dt)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', UserWarning)
        if kind == 'plain':
            base = cx.hinf_observer(plant, Bw=BW, Dw=np.eye(3) + 0.1,
                                    decay=0.3, refine=False, method='lmi')
            L, Lw = base.L, None
        else:
            base = cx.gi_observer(plant, BW, augmented=kind == 'augmented',
                                  decay=0.3, refine=False)
            L, Lw = base.L, base.Lw
        rng = np.random.default_rng(seed)
        for scale in (0.1, 0.03, 0.01, 0.0):
            GL = np.kron(np.eye(copies), L) + \
                scale * rng.normal(size=(copies * L.shape[0],
                                         copies * L.shape[1]))
            GLw = None if Lw is None else np.kron(np.eye(copies), Lw) + \
                scale * rng.normal(size=(copies * Lw.shape[0],
                                         copies * Lw.shape[1]))
            if kind == 'plain':
                obs = cx.LuenbergerObserver(plant, GL, Bw=BW,
                                            Dw=np.eye(3) + 0.1) \
                    if copies == 1 else \
                    cx.CoupledObserver(plant, GL, Bw=BW, Dw=np.eye(3) + 0.1)
            else:
                obs = cx.GIObserver(plant, GL, BW, augmented=Lw is not None,
                                    Lw=GLw, copies=copies)
            if _stable(obs):
                return plant, obs
    raise AssertionError("no stable test gain")


def _closed_loop(plant, obs):
    """Plant with noise inputs, its state as outputs, and the estimator
    wired by the plant's signal names."""
    prob = obs.problem
    Bw, Dw = prob.plant_Bw, prob.plant_Dw
    q = Bw.shape[1]
    noisy = ct.ss(plant.A, np.hstack([plant.B, Bw]),
                  np.vstack([plant.C, np.eye(plant.nstates)]),
                  np.vstack([np.hstack([plant.D, Dw]),
                             np.zeros((plant.nstates, 1 + q))]),
                  plant.dt, name='plant',
                  inputs=['force'] + [f'w[{i}]' for i in range(q)],
                  outputs=list(plant.output_labels) +
                  [f'x[{i}]' for i in range(plant.nstates)])
    est = obs.estimator(name='est')
    n = plant.nstates
    return ct.interconnect(
        [noisy, est], inplist=['force'] + [f'w[{i}]' for i in range(q)],
        inputs=['force'] + [f'w[{i}]' for i in range(q)],
        outlist=[f'plant.x[{i}]' for i in range(n)] +
        [f'est.xhat[{i}]' for i in range(n)],
        outputs=[f'x[{i}]' for i in range(n)] +
        [f'xhat[{i}]' for i in range(n)]), est


@pytest.mark.parametrize('dt', [0, 0.1], ids=['continuous', 'discrete'])
@pytest.mark.parametrize('copies', [1, 2, 3])
@pytest.mark.parametrize('kind', KINDS)
def test_estimator_error_equals_error_system(kind, copies, dt):
    plant, obs = _observer(kind, copies, dt)
    closed, est = _closed_loop(plant, obs)
    n, q = plant.nstates, obs.ninputs
    rng = np.random.default_rng(1)
    steps = 400
    T = np.arange(steps) * dt if dt else np.linspace(0, 8, 4001)
    u = np.sin(1.3 * T)
    w = 0.5 * rng.normal(size=(q, 1)) * np.ones((1, T.size)) + \
        np.vstack([np.sin((k + 1) * 0.7 * T) for k in range(q)])
    x0 = rng.normal(size=n)
    xi0 = rng.normal(size=est.nstates)
    resp = ct.forced_response(closed, T, np.vstack([u, w]),
                              X0=np.concatenate([x0, xi0]))
    err = resp.outputs[n:] - resp.outputs[:n]
    # the error system from the same initial error ξ(0) − [x(0); 0]
    m = obs.problem.n
    e0 = xi0.reshape(copies, m).copy()
    e0[:, :n] -= x0
    ref = ct.forced_response(obs, T, w, X0=e0.ravel()).outputs
    scale = np.max(np.abs(ref))
    assert scale > 1e-2
    tol = 1e-8 if dt else 1e-6
    np.testing.assert_allclose(err, ref, rtol=0, atol=tol * scale)


@pytest.mark.parametrize('dt', [0, 0.1], ids=['continuous', 'discrete'])
@pytest.mark.parametrize('kind', KINDS)
def test_estimate_converges_without_noise(kind, dt):
    plant, obs = _observer(kind, 2, dt)
    closed, est = _closed_loop(plant, obs)
    n, q = plant.nstates, obs.ninputs
    # 25 time constants of the slowest error pole
    horizon = 25 / max(obs.decay, 1e-2)
    T = np.arange(int(horizon / dt)) * dt if dt else \
        np.linspace(0, horizon, 5001)
    u = np.sin(T)
    x0 = np.array([1.0, -2.0, 0.5])
    resp = ct.forced_response(closed, T, np.vstack([u, np.zeros((q, T.size))]),
                              X0=np.concatenate([x0, np.zeros(est.nstates)]))
    err = resp.outputs[n:] - resp.outputs[:n]
    assert np.linalg.norm(err[:, 0]) > 1
    assert np.linalg.norm(err[:, -1]) < 1e-6 * np.linalg.norm(err[:, 0])


@pytest.mark.parametrize('dt', [0, 0.1], ids=['continuous', 'discrete'])
@pytest.mark.parametrize('copies', [1, 2])
def test_augmented_gi_rejects_constant_disturbances(copies, dt):
    plant, obs = _observer('augmented', copies, dt)
    np.testing.assert_allclose(ct.dcgain(obs), 0, atol=1e-9)
    # and in simulation: a constant disturbance (both parts of it) leaves
    # no steady-state error
    closed, est = _closed_loop(plant, obs)
    n, q = plant.nstates, obs.ninputs
    horizon = 30 / max(obs.decay, 1e-2)
    T = np.arange(int(horizon / dt)) * dt if dt else \
        np.linspace(0, horizon, 6001)
    w = np.outer([0.4, -0.3, 0.2], np.ones(T.size))
    resp = ct.forced_response(closed, T, np.vstack([np.zeros(T.size), w]))
    err = resp.outputs[n:] - resp.outputs[:n]
    assert np.max(np.abs(err[:, -1])) < 1e-6


def test_discrete_augmented_gi_designed_rejects_bias():
    """The reproducer: a sampled first-order plant with a sensor bias."""
    plant = ct.ss([[np.exp(-0.05)]], [[0.1]], [[1.0]], 0, 0.1)
    with pytest.warns(UserWarning, match='equals the classic observer'):
        obs = cx.gi_observer(plant, [[-1.0]], decay=1.0, augmented=True)
    # α(k+1) = α(k): the disturbance state is an integrator at z = 1
    assert np.isclose(obs.problem.A[1, 1], 1.0)
    np.testing.assert_allclose(ct.dcgain(obs), 0, atol=1e-9)
    assert np.max(np.abs(ct.poles(obs))) <= np.exp(-0.1) + 1e-7


def test_coupled_gi_estimator_is_invariant():
    """The reproducer: a disturbance entirely outside range(C) does not
    reach the coupled GI estimate."""
    plant = ct.ss([[-1., 1.], [0., -2.]], [[0.], [1.]],
                  [[1., 0.], [1., 0.]], 0)
    Bw = [[.5, .2], [0., 1.]]
    obs = cx.gi_observer(plant, Bw, decay=1.0, copies=2, refine=False)
    T = np.linspace(0, 20, 2001)
    w = np.vstack([np.sin(T), -np.sin(T)])       # along [1, -1] = range(Π)
    resp = cx.simulate(plant, obs, T, w=w)
    assert np.max(np.abs(resp.outputs[-2:])) < 1e-10
    # while the plain coupled observer with the same gain sees it
    plain = cx.CoupledObserver(plant, obs.L, Bw=Bw, Dw=np.eye(2))
    resp = cx.simulate(plant, plain, T, w=w)
    assert np.max(np.abs(resp.outputs[-2:])) > 1e-3


@pytest.mark.parametrize('dt', [0, 0.1], ids=['continuous', 'discrete'])
def test_augmented_coupled_gi_is_designed(dt):
    plant = _plant(dt)
    obs = cx.gi_observer(plant, BW, decay=0.5, augmented=True, copies=2,
                         refine_options=dict(random_starts=2, polish=2))
    np.testing.assert_allclose(ct.dcgain(obs), 0, atol=1e-8)
    est = obs.estimator(disturbance=True)
    assert est.output_labels == ['xhat[0]', 'xhat[1]', 'xhat[2]',
                                 'dhat[0]', 'dhat[1]', 'dhat[2]']
    assert est.input_labels == ['pos', 'vel', 'sum', 'force']
