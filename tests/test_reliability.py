"""Reproducers of the independent reliability campaign: a crash, inputs
that were accepted or met a foreign exception, placements refused within
rounding, and degenerate designs returned without a word.  Each test
builds its case from the campaign's description and checks the reason
independently of the code under test."""

import warnings

import control as ct
import numpy as np
import pytest
import scipy.linalg as la

import controlext as cx
from controlext import norms

SECOND = ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]], 0)


# -- 1. the crash: a resolvent exactly singular on the unit circle ---------

def test_peak_search_survives_an_exactly_singular_resolvent():
    """The discrete peak search evaluates ``C (zI − A)⁻¹ B`` on a grid of
    the unit circle that holds z = 1.  Where ``I − A`` is singular in
    floating point (here exactly: I − A has equal rows), scipy raises
    LinAlgError; the gain there is unbounded, so the norm is inf, not a
    crash."""
    A = np.array([[0.0, -1.0], [-1.0, 0.0]])
    B, C = np.eye(2), np.eye(2)
    with pytest.raises(np.linalg.LinAlgError):
        la.solve((np.eye(2) - A) * (1 + 0j), B)   # the reason, independently
    sys = ct.ss(A, B, C, np.zeros((2, 2)), 0.1)
    gamma, _ = norms._attained(sys, 1.0, 0.0)
    assert gamma == np.inf


def test_coupled_design_on_nearly_unobservable_discrete_plant():
    """The campaign's crash: a 4-state discrete plant (dt 0.1), two
    outputs, a mode seen 1e-8 as strongly as the others, measurement noise
    only, Disk(0.615).  The call ends in a verified design or one of the
    package's errors, never in numpy's LinAlgError."""
    rng = np.random.default_rng(3)
    V = la.qr(rng.normal(size=(4, 4)))[0]
    A = V @ np.diag([0.9, 0.5, -0.3, 0.2]) @ V.T
    C = rng.normal(size=(2, 4))
    C -= 1.0 * np.outer(C @ V[:, 1], V[:, 1])    # mode 0.5 all but unseen
    C += 1e-8 * np.outer(rng.normal(size=2), V[:, 1])
    plant = ct.ss(A, np.zeros((4, 1)), C, 0, 0.1)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter('ignore', cx.GainWarning)
            obs = cx.coupled_observer(plant, region=cx.Disk(0.615))
    except cx.ControlextError:
        return
    Acl = obs.problem.error_system(
        np.asarray(obs.G).reshape(obs.problem.gain_shape))[0]
    assert np.max(np.abs(np.linalg.eigvals(Acl))) <= 0.615 + 1e-9


# -- 2. placement refused within its own rounding --------------------------

def test_placement_tolerance_follows_its_conditioning():
    """Five poles clustered in 0.1 on a 5-state chain with one sensor:
    the placed error matrix is so far from normal that rounding alone
    (eps times the eigenvector condition number, Bauer–Fike) moves the
    poles by more than 1e-6.  Such a placement is returned with a
    GainWarning that names the conditioning, not refused."""
    n = 5
    A = np.diag(np.ones(n - 1), 1)
    C = np.eye(1, n)
    plant = ct.ss(A, np.eye(n, 1), C, 0)
    poles = -1 - 0.025 * np.arange(n)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always')
        obs = cx.luenberger_observer(plant, poles)
    placed = np.sort(np.linalg.eigvals(A - np.asarray(obs.L) @ C).real)
    # the independent Bauer–Fike reach of rounding for this placement
    _, V = np.linalg.eig(A - np.asarray(obs.L) @ C)
    reach = np.finfo(float).eps * np.linalg.cond(V) * np.linalg.norm(
        np.asarray(obs.L), 2)
    miss = np.max(np.abs(placed - np.sort(poles)))
    assert miss <= 10 * n * reach
    if miss > 1e-6:
        assert any(w.category is cx.GainWarning and
                   'ill-conditioned' in str(w.message) for w in caught)


@pytest.mark.parametrize('dt, poles', [(0, [-1.0, 0.5]),
                                       (0.1, [0.5, 1.2])])
def test_placement_outside_the_stability_region_is_refused(dt, poles):
    plant = ct.ss(SECOND.A, SECOND.B, SECOND.C, 0, dt)
    with pytest.raises(cx.ParameterError, match='poles must lie'):
        cx.luenberger_observer(plant, poles)


# -- 7. bad inputs: the package's errors, before any solver ---------------

@pytest.mark.parametrize('make, error', [
    (lambda: cx.HalfPlane(1) & 3, cx.ArgumentError),
    (lambda: 3 & cx.HalfPlane(1), cx.ArgumentError),
    (lambda: cx.is_stable('abc'), cx.ArgumentError),
    (lambda: cx.coupled_observer(SECOND, weights=[1.5, -0.5]),
     cx.ParameterError),
    (lambda: cx.coupled_observer(SECOND, weights=[[0.5, 0.5]]),
     cx.DimensionError),
    (lambda: cx.hinf_observer(SECOND, method=None), cx.ArgumentError),
    (lambda: cx.hinf_observer(SECOND, decay=1, margin=1e12),
     cx.ParameterError),
    (lambda: cx.hinf_observer(SECOND, decay=0), cx.ParameterError),
    (lambda: cx.hinf_observer(SECOND, np.eye(1), np.eye(1)),
     cx.ArgumentError),
], ids=['region & int', 'int & region', 'is_stable(str)',
        'negative weights', '2-D weights', 'method=None', 'margin=1e12',
        'decay=0', 'lqe habit (QN, RN)'])
def test_bad_input_gets_the_packages_error(make, error, monkeypatch):
    import cvxpy as cp

    def no_solve(*args, **kwargs):
        raise AssertionError("a solver ran before the input was checked")
    monkeypatch.setattr(cp.Problem, 'solve', no_solve)
    with pytest.raises(error) as info:
        make()
    assert isinstance(info.value, cx.ControlextError)


def test_lqe_habit_says_where_the_noise_model_goes():
    with pytest.raises(cx.ArgumentError, match='Bw='):
        cx.hinf_observer(SECOND, np.eye(1), np.eye(1))


@pytest.fixture(scope='module')
def discrete_pair():
    plant = ct.ss([[1.0, 0.1], [0.0, 1.0]], [[0.005], [0.1]], [[1.0, 0.0]],
                  0, 0.1)
    poles = [0.5, 0.6]
    return plant, cx.luenberger_observer(plant, poles)


def test_simulate_refuses_times_off_the_sample_grid(discrete_pair):
    plant, obs = discrete_pair
    with pytest.raises(cx.ParameterError, match='whole steps'):
        cx.simulate(plant, obs, np.linspace(0, 1, 7))
    resp = cx.simulate(plant, obs, np.arange(0, 1, 0.1))
    assert np.all(np.isfinite(resp.outputs))


def test_simulate_refuses_nan_noise(discrete_pair):
    plant, obs = discrete_pair
    T = np.arange(0, 1, 0.1)
    noise = np.zeros(T.size)
    noise[3] = np.nan
    with pytest.raises(cx.ParameterError, match='finite'):
        cx.simulate(plant, obs, T, noise=noise)


def test_simulate_keeps_the_plants_state_names():
    plant = ct.ss(SECOND.A, SECOND.B, SECOND.C, 0,
                  states=['position', 'velocity'])
    obs = cx.luenberger_observer(plant, [-2, -3])
    resp = cx.simulate(plant, obs, np.linspace(0, 1, 11))
    names = list(resp.output_labels)
    assert names[:2] == ['position', 'velocity']
    assert 'xhat1[velocity]' in names and 'e1[position]' in names


def test_coupled_observer_has_no_single_gain():
    pair = cx.coupled_observer(SECOND, decay=1)
    with pytest.raises(AttributeError, match='Mu'):
        pair.L


# -- 8. degenerate designs are said to be so -------------------------------

def test_zero_gain_design_is_said_to_ignore_its_sensor():
    """A stable plant, measurement noise only: the error system is
    ``(sI − A + LC)⁻¹ L`` from the noise, so L = 0 makes it exactly 0 and
    is optimal; the observer then ignores its sensor, which is said."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always')
        obs = cx.hinf_observer(SECOND)
    assert np.linalg.norm(obs.L) <= 1e-9
    assert any('ignores its measurements' in str(w.message)
               for w in caught if w.category is cx.GainWarning)


def test_very_fast_error_poles_are_said_to_be_so():
    """Cart–pendulum (linearised, states x, x', θ, θ'; cart position
    measured) at decay 3: the H∞ optimum puts error poles hundreds of
    times beyond the decay and the plant's own modes."""
    M, m, l, g = 1.0, 0.1, 0.5, 9.81
    A = [[0, 1, 0, 0], [0, 0, -m * g / M, 0], [0, 0, 0, 1],
         [0, 0, (M + m) * g / (M * l), 0]]
    plant = ct.ss(A, [[0], [1 / M], [0], [-1 / (M * l)]], [[1, 0, 0, 0]], 0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always')
        obs = cx.hinf_observer(plant, decay=3)
    fastest = np.max(np.abs(ct.poles(obs)))
    slow = max(3.0, np.max(np.abs(np.linalg.eigvals(np.array(A, float)))))
    said = any(w.category is cx.GainWarning and 'faster' in str(w.message)
               for w in caught)
    assert said == (fastest > cx.synthesis.conditioning.FAST * slow) or \
        any('times the plant' in str(w.message) for w in caught)
