"""A battery of bad inputs: each gets an error of the package's own
classes (a subclass of ControlextError), raised before any solver runs.

The cases are every factory crossed with every kind of mistake a user
makes with its arguments (wrong types, shapes, values, NaN and inf,
python-control's and MATLAB's habits), and the mistakes of the regions,
the norms, the simulation and the MATLAB names.  The list is printed by
``python -m pytest tests/test_bad_inputs.py -v``."""

import warnings

import control as ct
import numpy as np
import pytest

import controlext as cx
import controlext.matlab as cm

PLANT = ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]], 0)
PLANT2 = ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]],
               [[1.0, 2.0], [1.0, 2.0]], 0)         # redundant sensors
DISCRETE = ct.ss([[1.0, 0.1], [0.0, 1.0]], [[0.005], [0.1]], [[1.0, 0.0]],
                 0, 0.1)
BW2 = [[0.1, 0.2], [0.3, 0.1]]

FACTORIES = {
    'hinf': lambda **kw: cx.hinf_observer(PLANT, **kw),
    'coupled': lambda **kw: cx.coupled_observer(PLANT, **kw),
    'gi': lambda **kw: cx.gi_observer(PLANT2, BW2, **kw),
}

#: (keyword, value, why) for every factory
COMMON = [
    ('decay', -1.0, 'negative decay'),
    ('decay', 0.0, 'zero decay'),
    ('decay', float('nan'), 'NaN decay'),
    ('decay', float('inf'), 'infinite decay'),
    ('decay', 'fast', 'decay as a string'),
    ('decay', [1.0, 2.0], 'decay as a list'),
    ('region', 'disk', 'region as a string'),
    ('region', 3, 'region as a number'),
    ('method', 'fast', 'unknown method'),
    ('method', None, 'method=None'),
    ('margin', 0.5, 'margin below 1'),
    ('margin', 1e12, 'margin of 1e12'),
    ('margin', float('nan'), 'NaN margin'),
    ('seed', -1, 'negative seed'),
    ('seed', 1.5, 'fractional seed'),
    ('max_gain', -1.0, 'negative max_gain'),
    ('max_gain', 'big', 'max_gain as a word'),
    ('objective', 'h3', 'unknown objective'),
    ('max_hinf', -1.0, 'negative max_hinf'),
    ('max_h2', float('nan'), 'NaN max_h2'),
    ('settling_time', -1.0, 'negative settling time'),
    ('gain_tolerance', -1e-3, 'negative gain tolerance'),
    ('solver', 'NOSUCHSOLVER', 'unknown solver'),
    ('refine_options', {'seed': 1}, 'unknown refinement option'),
    ('refine_options', 3, 'refine_options as a number'),
    ('refine', 'yes', 'refine as a string'),
    ('options', {'margin': 2}, 'options as a dict'),
    ('name', 3, 'name as a number'),
    ('inputs', ['a', 'b', 'c', 'd', 'e'], 'too many input names'),
    ('executor', 'threads', 'executor as a string'),
]
#: mistakes with the noise model (the GI observer takes Bw positionally)
NOISE = [
    ('Bw', [[1.0, 2.0, 3.0]], 'Bw with the wrong number of rows'),
    ('Bw', [[np.nan], [1.0]], 'NaN in Bw'),
    ('Dw', [[1.0], [2.0]], 'Dw with the wrong number of rows'),
    ('Cz', [[1.0, 2.0, 3.0]], 'Cz with the wrong number of columns'),
]
COUPLED = [
    ('copies', 1, 'one copy for a coupled observer'),
    ('copies', 2.5, 'fractional copies'),
    ('copies', 0, 'no copies'),
    ('weights', [1.5, -0.5], 'negative weights'),
    ('weights', [[0.5, 0.5]], '2-D weights'),
    ('weights', [0.5, 0.3], 'weights not summing to 1'),
    ('weights', [0.3, 0.3, 0.4], 'weights of the wrong length'),
    ('weights', [np.nan, 1.0], 'NaN weights'),
]

CASES = []
for kind, factory in FACTORIES.items():
    for key, value, why in COMMON:
        CASES.append((f'{kind}: {why}',
                      (lambda f, k, v: lambda: f(**{k: v}))(factory, key,
                                                             value)))
for kind in ('hinf', 'coupled'):
    for key, value, why in NOISE:
        CASES.append((f'{kind}: {why}',
                      (lambda f, k, v: lambda: f(**{k: v}))(
                          FACTORIES[kind], key, value)))
for key, value, why in COUPLED:
    CASES.append((f'coupled: {why}',
                  (lambda k, v: lambda: cx.coupled_observer(PLANT, **{k: v})
                   )(key, value)))

CASES += [
    # plants
    ('hinf: plant None', lambda: cx.hinf_observer(None)),
    ('hinf: plant a string', lambda: cx.hinf_observer('plant')),
    ('hinf: plant a matrix', lambda: cx.hinf_observer(np.eye(2))),
    ('hinf: plant with NaN', lambda: cx.hinf_observer(
        ct.ss([[np.nan]], [[1.0]], [[1.0]], 0))),
    ('hinf: plant with inf', lambda: cx.hinf_observer(
        ct.ss([[-1.0]], [[1.0]], [[np.inf]], 0))),
    ('hinf: improper transfer function', lambda: cx.hinf_observer(
        ct.tf([1, 0, 0], [1, 1]))),
    ('hinf: undetectable plant', lambda: cx.hinf_observer(
        ct.ss([[1.0, 0.0], [0.0, -1.0]], [[1.0], [1.0]], [[0.0, 1.0]], 0))),
    ('hinf: unobservable mode outside the region', lambda: cx.hinf_observer(
        ct.ss([[-0.5, 0.0], [0.0, -1.0]], [[1.0], [1.0]], [[0.0, 1.0]], 0),
        decay=1.0)),
    ("hinf: lqe's QN, RN", lambda: cx.hinf_observer(PLANT, np.eye(1),
                                                    np.eye(1))),
    ('hinf: decay and region both', lambda: cx.hinf_observer(
        PLANT, decay=1.0, region=cx.HalfPlane(1.0))),
    ('hinf: discrete region for a continuous plant', lambda: cx.hinf_observer(
        PLANT, region=cx.Disk(0.5, domain='discrete'))),
    ('hinf: sector for a discrete plant', lambda: cx.hinf_observer(
        DISCRETE, region=cx.Sector(0.5))),
    ('hinf: plant without outputs', lambda: cx.hinf_observer(
        ct.ss([[-1.0]], [[1.0]], np.zeros((0, 1)), np.zeros((0, 1))))),
    ('gi: Bw of the wrong shape', lambda: cx.gi_observer(PLANT2, [[1.0]])),
    ('gi: Bw a string', lambda: cx.gi_observer(PLANT2, 'Bw')),
    ('gi: augmented with copies 0', lambda: cx.gi_observer(
        PLANT2, BW2, augmented=True, copies=0)),
    ('gi: augmented as a string', lambda: cx.gi_observer(
        PLANT2, BW2, augmented='yes')),
    # pole placement
    ('luenberger: too few poles', lambda: cx.luenberger_observer(
        PLANT, [-1.0])),
    ('luenberger: unstable poles', lambda: cx.luenberger_observer(
        PLANT, [-1.0, 0.5])),
    ('luenberger: poles outside the unit circle', lambda:
        cx.luenberger_observer(DISCRETE, [0.5, 1.2])),
    ('luenberger: unpaired complex pole', lambda: cx.luenberger_observer(
        PLANT, [-1 + 1j, -2.0])),
    ('luenberger: NaN pole', lambda: cx.luenberger_observer(
        PLANT, [np.nan, -2.0])),
    ('luenberger: poles as a string', lambda: cx.luenberger_observer(
        PLANT, 'fast')),
    # observers from given gains
    ('LuenbergerObserver: gain of the wrong shape', lambda:
        cx.LuenbergerObserver(PLANT, [[1.0, 2.0]])),
    ('LuenbergerObserver: NaN gain', lambda: cx.LuenbergerObserver(
        PLANT, [[np.nan], [1.0]])),
    ('CoupledObserver: gain of the wrong shape', lambda:
        cx.CoupledObserver(PLANT, np.eye(3))),
    ('CoupledObserver.from_pair: a list gain', lambda:
        cx.CoupledObserver.from_pair(PLANT, [1.0], 2.0, 0.0, 0.0)),
    # regions
    ('HalfPlane: NaN', lambda: cx.HalfPlane(np.nan)),
    ('HalfPlane: a string', lambda: cx.HalfPlane('1')),
    ('Disk: negative radius', lambda: cx.Disk(-1.0)),
    ('Disk: zero radius', lambda: cx.Disk(0.0)),
    ('Disk: unknown domain', lambda: cx.Disk(0.5, domain='z')),
    ('Sector: damping above 1', lambda: cx.Sector(2.0)),
    ('Sector: negative damping', lambda: cx.Sector(-0.5)),
    ('region & a number', lambda: cx.HalfPlane(1) & 3),
    ('a number & region', lambda: 3 & cx.HalfPlane(1)),
    ('continuous & discrete region', lambda: cx.Sector(0.5) & cx.Disk(
        0.5, domain='discrete')),
    # norms and analysis
    ('hinfnorm: a string', lambda: cx.hinfnorm('abc')),
    ('hinfnorm: NaN system', lambda: cx.hinfnorm(
        ct.ss([[np.nan]], [[1.0]], [[1.0]], 0))),
    ('is_stable: a string', lambda: cx.is_stable('abc')),
    ('is_stable: a dict', lambda: cx.is_stable({'a': 1})),
    # simulation
    ('simulate: times off the sample grid', lambda: cx.simulate(
        DISCRETE, cx.luenberger_observer(DISCRETE, [0.5, 0.6]),
        np.linspace(0, 1, 7))),
    ('simulate: NaN noise', lambda: cx.simulate(
        PLANT, cx.LuenbergerObserver(PLANT, [[2.0], [5.0]]),
        np.linspace(0, 1, 11), noise=np.full(11, np.nan))),
    ('simulate: decreasing times', lambda: cx.simulate(
        PLANT, cx.LuenbergerObserver(PLANT, [[2.0], [5.0]]),
        np.linspace(1, 0, 11))),
    ('simulate: one time point', lambda: cx.simulate(
        PLANT, cx.LuenbergerObserver(PLANT, [[2.0], [5.0]]), [0.0])),
    ('simulate: times as a string', lambda: cx.simulate(
        PLANT, cx.LuenbergerObserver(PLANT, [[2.0], [5.0]]), 'now')),
    ('simulate: input of the wrong length', lambda: cx.simulate(
        PLANT, cx.LuenbergerObserver(PLANT, [[2.0], [5.0]]),
        np.linspace(0, 1, 11), inputs=np.ones(5))),
    ('simulate: an observer of another plant', lambda: cx.simulate(
        PLANT, cx.LuenbergerObserver(PLANT2, [[2.0, 0.0], [5.0, 0.0]]),
        np.linspace(0, 1, 11))),
    ('simulate: not an observer', lambda: cx.simulate(
        PLANT, PLANT, np.linspace(0, 1, 11))),
    # MATLAB names
    ('estim: a sensor out of range', lambda: cm.estim(
        PLANT, [[2.0], [5.0]], [3])),
    ('estim: a known input out of range', lambda: cm.estim(
        PLANT, [[2.0], [5.0]], [0], [4])),
    ('estim: repeated sensors', lambda: cm.estim(
        PLANT2, [[2.0, 0.0], [5.0, 0.0]], [0, 0])),
    # estimators in python-control's loop builder
    ('create_statefbk_iosystem with the error system', lambda:
        ct.create_statefbk_iosystem(PLANT, [[1.0, 1.0]],
                                    estimator=cx.LuenbergerObserver(
                                        PLANT, [[2.0], [5.0]]))),
]


@pytest.mark.parametrize('make', [make for _, make in CASES],
                         ids=[why for why, _ in CASES])
def test_bad_input_is_refused_cleanly(make, monkeypatch):
    import cvxpy as cp

    def no_solve(*args, **kwargs):
        raise AssertionError("a solver ran before the input was checked")
    monkeypatch.setattr(cp.Problem, 'solve', no_solve)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', cx.GainWarning)
        with pytest.raises(cx.ControlextError):
            make()


def test_the_battery_is_as_large_as_the_campaigns():
    assert len(CASES) >= 141
