"""python-control's system keywords (``name``, ``inputs``, ``outputs``,
``states``) on every factory and observer class, and the report's field
names."""

import warnings

import numpy as np
import pytest
import control as ct

import controlext as cx

PLANT = ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]], 0)
GI_PLANT = ct.ss([[1.0, 1.0], [0.0, -2.0]], [[0.0], [1.0]],
                 [[1.0, 0.0], [1.0, 0.0]], 0)
GI_BW = [[-0.5, 0.2], [0.0, 1.0]]

#: (factory, number of noise inputs, weighted-error outputs, error states)
MAKERS = {
    'luenberger': (lambda **kw: cx.luenberger_observer(PLANT, [-2, -3],
                                                       **kw), 1, 2, 2),
    'hinf': (lambda **kw: cx.hinf_observer(PLANT, decay=1.0, **kw), 1, 2, 2),
    'coupled': (lambda **kw: cx.coupled_observer(
        PLANT, decay=1.0, refine=False, **kw), 1, 2, 4),
    'gi-aug': (lambda **kw: cx.gi_observer(
        GI_PLANT, GI_BW, decay=1.0, augmented=True, refine=False, **kw),
        2, 2, 3),
    'class': (lambda **kw: cx.LuenbergerObserver(PLANT, [[2], [5]], **kw),
              1, 2, 2),
    'coupled-class': (lambda **kw: cx.CoupledObserver.from_pair(
        ct.ss([[-0.5]], [[1.0]], [[1.0]], 0), 3.5198, 0.4802, -8.0142,
        0.2883, **kw), 1, 1, 2),
}


@pytest.mark.parametrize('kind', MAKERS)
def test_names_given_as_lists_and_base_names(kind):
    make, q, nz, ns = MAKERS[kind]
    obs = make(name='est', inputs='v', outputs=[f'z{i}' for i in range(nz)],
               states='err')
    assert obs.name == 'est'
    assert obs.input_labels == [f'v[{i}]' for i in range(q)]
    assert obs.output_labels == [f'z{i}' for i in range(nz)]
    assert obs.state_labels == [f'err[{i}]' for i in range(ns)]
    # a count equal to the system's keeps the default names
    default = make(inputs=q)
    assert default.input_labels == [f'w[{i}]' for i in range(q)]


@pytest.mark.parametrize('kind', MAKERS)
def test_names_connect_by_name(kind):
    """The names are the system's: interconnect finds them."""
    make, q, nz, ns = MAKERS[kind]
    obs = make(inputs='v', outputs='z')
    noise = ct.ss([], [], [], np.eye(q), inputs=[f'n[{i}]' for i in range(q)],
                  outputs=[f'v[{i}]' for i in range(q)], name='noise')
    loop = ct.interconnect([noise, obs], inplist=noise.input_labels,
                           outlist=obs.output_labels)
    # the interconnection is the error system itself (identity in front)
    assert ct.linfnorm(loop)[0] == pytest.approx(ct.linfnorm(
        ct.ss(obs.A, obs.B, obs.C, obs.D))[0], rel=1e-9)


def test_wrong_count_names_the_counts():
    with pytest.raises(cx.DimensionError, match=r"states: the error system "
                       r"has 2 states; found 1 names"):
        cx.CoupledObserver.from_pair(ct.ss([[-0.5]], [[1.0]], [[1.0]], 0),
                                     3.5, 0.5, -8.0, 0.3, states=["a"])


def test_report_gamma_convex_and_deprecated_alias():
    """The paper's scalar pair: the convex stage's level is 0.8 (the
    Luenberger-equivalent start, Table I), the refined design 0.4953."""
    obs = cx.coupled_observer(ct.ss([[-0.5]], [[1.0]], [[1.0]], 0),
                              decay=2.5, gain_tolerance=0)
    assert obs.report.gamma_convex == pytest.approx(0.8, abs=1e-3)
    assert obs.hinf == pytest.approx(0.4953, abs=1e-4)
    with pytest.warns(DeprecationWarning, match='gamma_convex'):
        assert obs.report.gamma_opt == obs.report.gamma_convex
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        assert 'gamma_opt' not in obs.report.as_dict()
