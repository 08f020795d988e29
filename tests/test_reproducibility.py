"""The last bits of the plant do not move the design: relative 1e-13
perturbations of A and C (random signs, the draws of
``benchmarks/reproducibility.py``, seed 0) move γ by less than 0.2 %.

Every norm is rebuilt with ``ct.linfnorm`` from the design's gain; the
reference is the design of the plant as given."""

import control as ct
import numpy as np
import pytest

import controlext as cx

SECOND = ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]], 0)


def norm(obs):
    p = obs.problem
    return ct.linfnorm(ct.ss(p.Ae - obs.G @ p.Ce, obs.G @ p.Dwe - p.Bwe,
                             p.Cze, 0))[0]


def draws(plant, count, seed=0):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        A = plant.A * (1 + 1e-13 * rng.choice([-1.0, 1.0], plant.A.shape))
        C = plant.C * (1 + 1e-13 * rng.choice([-1.0, 1.0], plant.C.shape))
        yield ct.ss(A, plant.B, C, 0)


@pytest.mark.slow
def test_nominal_three_copy_optimum():
    """The second-order plant's nominal N = 3 optimum on three draws.
    With only the first basin's pole-cluster polish, the third draw ended
    in another basin, 4.1 % higher (0.013421 against 0.012890)."""
    base = norm(cx.coupled_observer(SECOND, decay=1.0, copies=3,
                                    gain_tolerance=0))
    for plant in draws(SECOND, 3):
        moved = cx.coupled_observer(plant, decay=1.0, copies=3,
                                    gain_tolerance=0)
        assert norm(moved) == pytest.approx(base, rel=2e-3)


@pytest.mark.slow
def test_default_three_copy_design():
    """The second-order plant's default (robust) N = 3 design on the
    first draw, which ended 0.25 % above the plant as given (0.0130885
    against 0.0130563) while ranking designs within 1e-4 of the noise
    channel's size (0.34 % of this γ) as equal."""
    base = cx.coupled_observer(SECOND, decay=1.0, copies=3)
    plant = next(draws(SECOND, 1))
    moved = cx.coupled_observer(plant, decay=1.0, copies=3)
    assert norm(moved) == pytest.approx(norm(base), rel=2e-3)
    for obs in (base, moved):
        assert np.max(np.linalg.eigvals(
            obs.problem.Ae - obs.G @ obs.problem.Ce).real) <= -1.0
