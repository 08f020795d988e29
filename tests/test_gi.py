"""GI observers (seeds 001/002): invariance, the augmented form's exact
rejection of constant disturbances, and synthesis through the engine."""

import warnings

import numpy as np
import pytest
import control as ct

import controlext as cx

# 2 states, 2 redundant sensors of x1: range(C) = span([1, 1]) and
# Π projects on [1, -1] (the sensors' disagreement is measured exactly)
A = np.array([[-1.0, 1.0], [0.0, -2.0]])
B = np.array([[0.0], [1.0]])
C = np.array([[1.0, 0.0], [1.0, 0.0]])
BW = np.array([[0.5, 0.2], [0.0, 1.0]])
PI = 0.5 * np.array([[1.0, -1.0], [-1.0, 1.0]])


@pytest.fixture
def plant():
    return ct.ss(A, B, C, np.zeros((2, 1)))


def three_sensor_plant():
    """2 states, 3 sensors (rank 2): Π has rank 1."""
    A3 = np.array([[0.0, 1.0], [-2.0, -0.5]])
    C3 = np.array([[1.0, 0.0], [0.0, 1.0], [1.0, 1.0]])
    Bw3 = np.array([[0.3, -0.2, 0.5], [0.1, 0.4, -0.3]])
    return ct.ss(A3, [[0.0], [1.0]], C3, np.zeros((3, 1))), Bw3


def assert_blind_to_pi(plant, obs, reach=False):
    """Simulate plant and estimator (cx.simulate wires them) under a
    disturbance in range(Π): the estimate must not move."""
    Pi = cx.projection(plant.C)
    direction = Pi[:, np.argmax(np.diag(Pi))]
    T = np.linspace(0, 10, 1001)
    w = np.outer(direction, 1.0 + np.sin(2 * T))
    resp = cx.simulate(plant, obs, T, w=w)
    n = plant.nstates
    assert np.max(np.abs(resp.outputs[-n:])) < 1e-9
    if not reach:
        return
    # a disturbance in range(C) does reach it (this gain does not cancel it)
    inside = np.outer(cx.range_basis(plant.C)[:, 0], 1.0 + np.sin(2 * T))
    assert np.max(np.abs(cx.simulate(plant, obs, T, w=inside)
                         .outputs[-n:])) > 1e-4


def placed_gain(Amat, Cmat, poles):
    # minimum-norm placement through the first sensor combination
    return ct.place(Amat.T, Cmat.T, poles).T


def test_projection_and_basis():
    np.testing.assert_allclose(cx.projection(C), PI, atol=1e-12)
    U = cx.range_basis(C)
    np.testing.assert_allclose(U @ U.T, np.eye(2) - PI, atol=1e-12)
    np.testing.assert_allclose(cx.projection(C) @ C, 0, atol=1e-12)


@pytest.mark.parametrize('augmented', [False, True], ids=['plain', 'aug'])
def test_invariance_in_simulation(plant, augmented):
    L = np.array([[1.0, 1.0], [0.5, 0.5]])
    Lw = np.array([[0.7, 0.7]]) if augmented else None
    obs = cx.GIObserver(plant, L, BW, augmented=augmented, Lw=Lw)
    np.testing.assert_allclose(obs.Pi, PI, atol=1e-12)
    assert_blind_to_pi(plant, obs, reach=True)
    if not augmented:
        np.testing.assert_allclose(obs.A, A - L @ C)
        np.testing.assert_allclose(obs.B, (L - BW) @ (np.eye(2) - PI),
                                   atol=1e-12)
        np.testing.assert_allclose(obs.C, np.eye(2))
    else:
        assert obs.nstates == 3
        np.testing.assert_allclose(ct.dcgain(obs), 0, atol=1e-10)
        np.testing.assert_allclose(obs.Lw, Lw)
    np.testing.assert_allclose(obs.L, L)


def test_same_gain_gi_never_worse_and_blind_to_pi():
    plant3, Bw3 = three_sensor_plant()
    L = placed_gain(plant3.A, plant3.C, [-2.0, -3.0])
    classic = cx.LuenbergerObserver(plant3, L, Bw=Bw3, Dw=np.eye(3))
    gi = cx.GIObserver(plant3, L, Bw3)
    # T_GI = T_classic (I - Π)  =>  ‖T_GI‖∞ ≤ ‖T_classic‖∞
    assert cx.hinfnorm(gi)[0] <= cx.hinfnorm(classic)[0] * (1 + 1e-10)
    # a disturbance in range(Π) does not reach the GI error at all ...
    Pi = gi.Pi
    direction = Pi[:, np.argmax(np.diag(Pi))]
    T = np.linspace(0, 10, 2001)
    wt = np.outer(direction, np.sin(2 * T) + 1.0)
    assert np.max(np.abs(ct.forced_response(gi, T, wt).outputs)) < 1e-12
    # ... but reaches the classic one since L Π ≠ Bw Π
    assert np.linalg.norm(L @ Pi - Bw3 @ Pi) > 1e-3
    assert np.max(np.abs(ct.forced_response(classic, T, wt).outputs)) > 1e-3


def test_synthesised_gi_not_above_classic():
    plant3, Bw3 = three_sensor_plant()
    gi = cx.gi_observer(plant3, Bw3)
    classic = cx.hinf_observer(plant3, Bw=Bw3, Dw=np.eye(3), method='lmi')
    # both optima are 0 here (L = Bw cancels the noise): equal to the
    # solver's tolerance
    assert gi.report.gamma_convex <= classic.report.gamma_convex * (1 + 1e-6) + 1e-6
    assert_blind_to_pi(plant3, gi)
    assert gi.hinf <= gi.report.gamma_bound * (1 + 1e-5) + 1e-5


@pytest.mark.parametrize('kwargs', [dict(decay=1.0),
                                    dict(decay=1.0, augmented=True),
                                    dict(decay=1.0, copies=2)],
                         ids=['plain', 'augmented', 'coupled'])
def test_gi_synthesis_respects_decay(plant, kwargs):
    obs = cx.gi_observer(plant, BW, **kwargs)
    assert np.max(ct.poles(obs).real) <= -1.0 + 1e-6
    assert_blind_to_pi(plant, obs)
    if kwargs.get('augmented'):
        np.testing.assert_allclose(ct.dcgain(obs), 0, atol=1e-8)


def test_augmented_estimate_converges_classic_keeps_bias(plant):
    aug = cx.gi_observer(plant, BW, decay=1.0, augmented=True)
    # a classic Luenberger observer (poles placed, not tuned to Bw: the
    # H∞ design with this Bw may cancel it exactly with L = Bw, which is
    # the freedom GI does not need)
    classic = cx.luenberger_observer(plant, [-2.0, -3.0])
    # plant with disturbance input w and its state as extra outputs
    sim_plant = ct.ss(A, np.hstack([B, BW]), np.vstack([C, np.eye(2)]),
                      np.hstack([np.zeros((4, 1)),
                                 np.vstack([np.eye(2), np.zeros((2, 2))])]),
                      name='plant', inputs=['u', 'w[0]', 'w[1]'],
                      outputs=['y[0]', 'y[1]', 'x[0]', 'x[1]'])
    T = np.linspace(0, 25 / min(aug.decay, classic.decay), 10001)
    # constant disturbance (both parts) + a sinusoid outside range(C)
    w = np.array([[0.3], [-0.1]]) + np.outer([1.0, -1.0],
                                             0.2 * np.sin(3 * T))
    u = np.sin(0.5 * T)
    finals = {}
    for label, obs in (('aug', aug), ('classic', classic)):
        est = obs.estimator(name='est')
        sys = ct.interconnect(
            [sim_plant, est], inplist=[['plant.u', 'est.u[0]'], 'plant.w[0]',
                                       'plant.w[1]'],
            inputs=['u', 'w[0]', 'w[1]'],
            outlist=['plant.x[0]', 'plant.x[1]', 'est.xhat[0]',
                     'est.xhat[1]'],
            connections=[['est.y[0]', 'plant.y[0]'],
                         ['est.y[1]', 'plant.y[1]']], check_unused=False)
        resp = ct.forced_response(sys, T, np.vstack([u, w]),
                                  X0=[1.0, -1.0] + [0.0] * (sys.nstates - 2))
        err = resp.outputs[2:] - resp.outputs[:2]
        finals[label] = np.max(np.abs(err[:, -500:]))
    assert finals['aug'] < 1e-6
    assert finals['classic'] > 1e-2


def test_augmented_pair_not_detectable():
    # an integrator measured by the only sensor: the state and a constant
    # sensor bias cannot be told apart
    plant = ct.ss([[0.0]], [[1.0]], [[1.0]], 0)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', UserWarning)
        with pytest.raises(cx.NotDetectableError,
                           match='augmented plant .* not detectable'):
            cx.gi_observer(plant, [[0.0]], augmented=True)


def test_full_range_warns_and_equals_classic():
    plant = ct.ss(A, B, np.eye(2), np.zeros((2, 1)))
    L = np.array([[2.0, 0.0], [0.0, 3.0]])
    with pytest.warns(UserWarning, match='equals the classic observer'):
        gi = cx.GIObserver(plant, L, BW)
    assert gi.invariant_directions == 0
    classic = cx.LuenbergerObserver(plant, L, Bw=BW, Dw=np.eye(2))
    np.testing.assert_allclose(gi.B, classic.B, atol=1e-12)
    with pytest.warns(UserWarning, match='equals the classic'):
        cx.gi_observer(plant, BW, decay=1.0)


def test_shapes_are_checked(plant):
    with pytest.raises(cx.DimensionError,
                       match='Bw has the wrong number of rows; expected 2 '
                             'instead of 3'):
        cx.GIObserver(plant, np.ones((2, 2)), np.ones((3, 2)))
    with pytest.raises(cx.DimensionError,
                       match='L has the wrong number of columns; expected 2 '
                             'instead of 1'):
        cx.GIObserver(plant, np.ones((2, 1)), BW)
    with pytest.raises(cx.DimensionError,
                       match='Lw has the wrong number of columns; expected 2'):
        cx.GIObserver(plant, np.ones((2, 2)), BW, augmented=True,
                      Lw=np.ones((1, 3)))
    with pytest.raises(cx.ArgumentError, match='needs Lw'):
        cx.GIObserver(plant, np.ones((2, 2)), BW, augmented=True)
    with pytest.raises(cx.DimensionError, match='Bw has the wrong number'):
        cx.gi_observer(plant, np.ones((2, 3)), decay=1.0)


def test_placement_with_redundant_sensors(plant):
    obs = cx.luenberger_observer(plant, [-2.0, -3.0])
    eig = np.sort(np.linalg.eigvals(A - obs.L @ C).real)
    np.testing.assert_allclose(eig, [-3.0, -2.0], atol=1e-9)
    # the gain acts only through range(C): L Π = 0
    np.testing.assert_allclose(obs.L @ PI, 0, atol=1e-12)
