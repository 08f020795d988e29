"""Bad input: the package's own exceptions, raised before any solver runs,
with messages that say what was expected and what was found."""

import numpy as np
import pytest
import control as ct

import controlext as cx
import cvxpy as cp

import controlext.synthesis.convex as convex


@pytest.fixture(autouse=True)
def no_solver(monkeypatch, request):
    """Fail loudly if a test in this file reaches the LMI engine."""
    if 'solver_allowed' in request.keywords:
        return

    def forbidden(*args, **kwargs):
        raise AssertionError('the solver ran before the input was checked')

    monkeypatch.setattr(cp.Problem, 'solve', forbidden)
    monkeypatch.setattr(convex, 'hinf_filter_level', forbidden)


def undetectable():
    # mode at s = 1 of the second state is unobservable from C = [1 0]
    return ct.ss([[-1.0, 0.0], [0.0, 1.0]], [[1.0], [1.0]], [[1.0, 0.0]], 0)


def slow_unobservable():
    # unobservable mode at s = -0.5: decay cannot exceed 0.5
    return ct.ss([[-2.0, 0.0], [0.0, -0.5]], [[1.0], [1.0]], [[1.0, 0.0]], 0)


@pytest.mark.parametrize('factory', [
    lambda p: cx.hinf_observer(p),
    lambda p: cx.hinf_observer(p, decay=1.0),
], ids=['no-decay', 'decay'])
def test_not_detectable_names_the_mode(factory):
    with pytest.raises(cx.NotDetectableError, match=r'mode at s = 1\b'):
        factory(undetectable())
    assert issubclass(cx.NotDetectableError, ValueError)


def test_unreachable_decay_states_the_limit():
    with pytest.raises(cx.RegionError,
                       match=r's = -0\.5.*at most that value|rate 0\.5'):
        cx.hinf_observer(slow_unobservable(), decay=1.0)


def test_placement_with_unobservable_mode():
    with pytest.raises(cx.RegionError, match='unobservable'):
        cx.luenberger_observer(slow_unobservable(), [-3, -4])


@pytest.mark.parametrize('decay, exc, match', [
    (-1.0, cx.ParameterError, r'decay must be .*>= 0; found -1'),
    (np.nan, cx.ParameterError, r'found nan'),
    (np.inf, cx.ParameterError, r'found inf'),
    ('fast', cx.ArgumentError, r'decay must be a real number; found str'),
])
def test_bad_decay(second_order_plant, decay, exc, match):
    with pytest.raises(exc, match=match):
        cx.hinf_observer(second_order_plant, decay=decay)


@pytest.mark.parametrize('kwargs, match', [
    (dict(Bw=np.ones((3, 1))), r'Bw has the wrong number of rows; '
                               r'expected 2 instead of 3'),
    (dict(Dw=np.ones((2, 1))), r'Dw has the wrong number of rows; '
                               r'expected 1 instead of 2'),
    (dict(Bw=np.ones((2, 2)), Dw=np.ones((1, 3))),
     r'Dw has the wrong number of columns; expected 2 instead of 3'),
    (dict(Cz=np.ones((1, 3))), r'Cz has the wrong number of columns; '
                               r'expected 2 instead of 3'),
])
def test_noise_model_shapes(second_order_plant, kwargs, match):
    with pytest.raises(cx.DimensionError, match=match):
        cx.hinf_observer(second_order_plant, **kwargs)
    with pytest.raises(cx.DimensionError, match=match):
        cx.LuenbergerObserver(second_order_plant, [[1.0], [1.0]], **kwargs)


def test_gain_shape(second_order_plant):
    with pytest.raises(cx.DimensionError,
                       match=r'L has the wrong number of rows; expected 2 '
                             r'instead of 3'):
        cx.LuenbergerObserver(second_order_plant, np.ones((3, 1)))
    with pytest.raises(ct.ControlDimension):      # python-control's class
        cx.LuenbergerObserver(second_order_plant, np.ones((2, 2)))


@pytest.mark.parametrize('bad', [np.nan, np.inf])
def test_nan_and_inf(second_order_plant, bad):
    with pytest.raises(cx.ParameterError, match='must be finite'):
        cx.LuenbergerObserver(second_order_plant, [[bad], [1.0]])
    with pytest.raises(cx.ParameterError, match=r'Bw must be finite'):
        cx.hinf_observer(second_order_plant, Bw=[[bad], [0.0]])
    A = np.array([[-1.0, bad], [0.0, -1.0]])
    with pytest.raises(cx.ParameterError, match=r'plant\.A must be finite'):
        cx.hinf_observer(ct.ss(A, [[0.0], [1.0]], [[1.0, 0.0]], 0))


@pytest.mark.parametrize('plant', [np.eye(2), 'plant', None],
                         ids=['array', 'str', 'None'])
def test_non_system_plant(plant):
    with pytest.raises(cx.ArgumentError, match='plant must be a linear '
                                               'system'):
        cx.hinf_observer(plant)
    with pytest.raises(TypeError):
        cx.luenberger_observer(plant, [-1, -2])


def test_placement_arguments(second_order_plant):
    with pytest.raises(cx.DimensionError, match='expected 2 .* instead of 1'):
        cx.luenberger_observer(second_order_plant, [-1])
    with pytest.raises(cx.ParameterError, match='conjugate pairs'):
        cx.luenberger_observer(second_order_plant, [-1 + 1j, -2])


def test_name_with_a_dot_is_refused_by_the_package(second_order_plant):
    # python-control itself raises a bare ValueError for this name
    with pytest.raises(ValueError):
        ct.ss([[-1.0]], [[1.0]], [[1.0]], 0, name='a.b')
    with pytest.raises(cx.ParameterError, match="must not contain '.'"):
        cx.hinf_observer(second_order_plant, name='γ <= 1.1')


def test_other_arguments(second_order_plant):
    with pytest.raises(cx.ParameterError, match="method must be one of "
                                                "'auto', 'lmi'.*'newton'"):
        cx.hinf_observer(second_order_plant, method='newton')
    with pytest.raises(cx.ParameterError, match='margin must be'):
        cx.hinf_observer(second_order_plant, margin=0.5)
    with pytest.raises(cx.ArgumentError, match='either decay= or region='):
        cx.hinf_observer(second_order_plant, decay=1,
                         region=cx.HalfPlane(1))
    with pytest.raises(cx.ArgumentError, match="needs one continuous plant "
                                               "model, no pole region other"):
        cx.hinf_observer(second_order_plant, region=cx.Disk(3.0, -4.0),
                         method='riccati')
    with pytest.raises(cx.ArgumentError,
                       match="needs one continuous plant model"):
        cx.coupled_observer(second_order_plant, decay=1, Dw=[[0.0]],
                            Bw=[[1.0], [0.0]], method='riccati')
    with pytest.raises(cx.ParameterError, match="'auto', 'lmi', 'riccati', "
                                                "'modal'; found 'scs'"):
        cx.coupled_observer(second_order_plant, decay=1, method='scs')


def test_inputs_not_mutated(second_order_plant):
    plant = second_order_plant
    before = [M.copy() for M in (plant.A, plant.B, plant.C, plant.D)]
    L = np.array([[2.0], [5.0]])
    Bw = np.array([[1.0], [0.0]])
    obs = cx.LuenbergerObserver(plant, L, Bw=Bw)
    obs.G[0, 0] = 100.0                  # the object keeps its own copy
    assert L[0, 0] == 2.0 and Bw[0, 0] == 1.0
    for M, B in zip((plant.A, plant.B, plant.C, plant.D), before):
        np.testing.assert_array_equal(M, B)


@pytest.mark.solver_allowed
def test_solver_failure_is_translated(second_order_plant):
    # one iteration of clarabel cannot reach 'optimal'
    with pytest.raises(cx.SolverError, match=r"status '(?!optimal')\w+'") \
            as info:
        cx.hinf_observer(second_order_plant, decay=1.0, method='lmi',
                         solver_options={'max_iter': 1})
    assert info.value.status != 'optimal'
    assert info.value.stats['stage1']['iterations'] is not None


def test_unknown_solver_is_refused_before_solving(second_order_plant):
    with pytest.raises(cx.ParameterError, match="'NOSUCHSOLVER' is not an "
                                                "installed cvxpy solver"):
        cx.hinf_observer(second_order_plant, decay=1.0, method='lmi',
                         solver='NOSUCHSOLVER')
