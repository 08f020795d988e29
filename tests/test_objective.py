"""The refinement objective against independent computations: its norm
against python-control's ``linfnorm`` (slycot), its gradient against
central differences, and the line-search bound against the true value."""

import numpy as np
import pytest
import control as ct

import controlext as cx
from controlext.synthesis.objective import Objective
from controlext.paper.tables import MU_SECOND_ORDER
from controlext.synthesis import ObserverProblem


@pytest.fixture
def pair():
    """The paper's second-order coupled pair (Section IV-B)."""
    prob = ObserverProblem(A=[[-1.0, 1.0], [-1.0, 0.0]], C=[[1.0, 2.0]],
                           copies=2)
    return prob, np.asarray(MU_SECOND_ORDER, dtype=float)


@pytest.mark.parametrize('dt', [0, 0.1], ids=['continuous', 'discrete'])
def test_norm_is_linfnorm(pair, dt):
    prob, G = pair
    if dt:
        # a stable discrete-time plant, same gain shape
        prob = ObserverProblem(A=[[0.9, 0.1], [-0.1, 0.95]],
                               C=[[1.0, 2.0]], copies=2, dt=dt)
        G = 0.1 * G
    f = Objective(prob, None)
    sys = ct.ss(*prob.error_system(G), dt)
    assert f.norm(G) == pytest.approx(ct.linfnorm(sys)[0], rel=1e-9)
    # the paper's γ of the published pair
    if not dt:
        assert f.norm(G) == pytest.approx(0.0594, rel=1e-3)


def test_gradient_matches_central_differences(pair):
    """At a point with a single peak and the penalty active, the analytic
    gradient of f equals central differences of f."""
    prob, G = pair
    region = cx.HalfPlane(1.3)          # the pair's decay is about 1.0
    f = Objective(prob, region, rho=0.5, delta=1e-7, tikhonov=1e-3)
    x = G.ravel()
    value, grad = f(x)
    assert f.margin(G)[0] > 0           # the penalty is active here
    h = 1e-6
    fd = np.array([(f(x + h * e, grad=False)[0] -
                    f(x - h * e, grad=False)[0]) / (2 * h)
                   for e in np.eye(x.size)])
    np.testing.assert_allclose(grad, fd, rtol=1e-4, atol=1e-7)


def test_line_search_bound_is_a_lower_bound(pair):
    """With ``above=a`` a returned value either is the true f or exceeds a
    and lies below the true f."""
    prob, G = pair
    region = cx.HalfPlane(1.0)
    f = Objective(prob, region, rho=0.3, delta=1e-7)
    truth = Objective(prob, region, rho=0.3, delta=1e-7)
    rng = np.random.default_rng(0)
    x0 = G.ravel()
    f(x0)                               # a peak frequency to bound with
    bounded = 0
    for _ in range(200):
        x = x0 + 0.2 * rng.normal(size=x0.size)
        true_value = truth(x, grad=False)[0]
        above = truth(x0, grad=False)[0]
        value, _ = f(x, grad=False, above=above)
        if value == true_value:
            continue
        bounded += 1
        assert above < value <= true_value
    assert bounded > 20                 # the cheap bound does reject steps
