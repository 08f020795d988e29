"""The last bits of the plant do not move the design: relative 1e-13
perturbations of A and C (random signs, the draws of
``benchmarks/reproducibility.py``, seed 0) move γ by less than 0.2 %.

Every norm is rebuilt with ``ct.linfnorm`` from the design's gain; the
reference is the design of the plant as given."""

import control as ct
import numpy as np
import pytest

import controlext as cx
from controlext.synthesis import ObserverProblem
from controlext.synthesis.judge import equal
from reproducibility import perturbed


def norm(obs):
    p = obs.problem
    return ct.linfnorm(ct.ss(p.Ae - obs.G @ p.Ce, obs.G @ p.Dwe - p.Bwe,
                             p.Cze, 0))[0]


@pytest.mark.slow
def test_nominal_three_copy_optimum(second_order_plant):
    """The second-order plant's nominal N = 3 optimum on three draws.
    With only the first basin's pole-cluster polish, the third draw ended
    in another basin, 4.1 % higher (0.013421 against 0.012890)."""
    base = norm(cx.coupled_observer(second_order_plant, decay=1.0,
                                    copies=3, gain_tolerance=0))
    rng = np.random.default_rng(0)
    for _ in range(3):
        plant = perturbed(second_order_plant, rng)
        moved = cx.coupled_observer(plant, decay=1.0, copies=3,
                                    gain_tolerance=0)
        assert norm(moved) == pytest.approx(base, rel=2e-3)


def test_designs_a_third_of_a_percent_apart_are_not_equal(
        second_order_plant):
    """The ranking returns the design of least gain among those it counts
    as equal.  On the second-order plant's three copies (γ = 0.013, 290
    times the floor of norms near 0) it counted designs 0.34 % apart as
    equal, and which one it returned moved with the plant's last bits
    (default design, first draw: 0.0130885 against 0.0130563).  Now only
    0.1 % of γ is a tie there; norms near 0 are still all equal."""
    prob = ObserverProblem(A=second_order_plant.A, C=second_order_plant.C,
                           copies=3,
                           Bw=[[1.0, 0.0], [0.0, 0.0]],
                           Dw=[[0.0, 1.0]])
    zero = 1e-4 * prob.noise_scale
    gamma = 290 * zero
    assert gamma * 1.0034 > gamma + equal(gamma, prob)
    assert gamma * 1.0009 <= gamma + equal(gamma, prob)
    assert 0.5 * zero + equal(0.5 * zero, prob) >= 1.4 * zero


@pytest.mark.slow
def test_pair_does_not_hang_on_identical_copies():
    """The quadruple tank pair (benchmarks/plants.py), nominal, on the
    plant and the first draw.  Refinement started from the one-copy
    design embedded, identical copies, which BFGS keeps identical (the
    norm does not change when copies swap places) until rounding tips
    it: 1.412 on the plant, 1.652 on the draw.  A search polishing six
    starts reached 1.404-1.411 on the plant and three draws; identical
    copies are 1.785."""
    from plants import PUBLIC, noise_model
    plant = PUBLIC['quadruple tank']
    Bw, Dw = noise_model(plant)
    draw = perturbed(plant, np.random.default_rng(0))
    gammas = [norm(cx.coupled_observer(p, decay=0.5, Bw=Bw, Dw=Dw,
                                       gain_tolerance=0))
              for p in (plant, draw)]
    assert max(gammas) <= 1.45
    assert max(gammas) <= 1.02 * min(gammas)
