"""max_gain=: a bound on ‖G‖₂ held by refinement and verified, on every
kind; against closed forms and independent evaluation of the result."""

import warnings

import numpy as np
import pytest
import control as ct

import controlext as cx

from test_robustness import AXIS  # noqa: E402

UNSTABLE = ct.ss([[1.0]], [[1.0]], [[1.0]], 0)


@pytest.mark.parametrize('bound', [100.0, 10.0])
def test_unstable_scalar_closed_form(bound):
    """x' = x, y = x + w, decay 2: e' = (1 − L) e + L w has γ = L / (L − 1),
    decreasing in L, so the bounded optimum is L = κ exactly."""
    obs = cx.hinf_observer(UNSTABLE, decay=2.0, max_gain=bound)
    L = float(obs.L[0, 0])
    assert L == pytest.approx(bound, rel=1e-6)
    assert L <= bound * (1 + 1e-6)
    assert obs.hinf == pytest.approx(bound / (bound - 1), rel=1e-6)
    assert obs.report.stats['max_gain']['norm'] <= bound * (1 + 1e-6)


def test_unbounded_is_larger():
    free = cx.hinf_observer(UNSTABLE, decay=2.0, max_gain=None)
    bounded = cx.hinf_observer(UNSTABLE, decay=2.0, max_gain=10.0)
    assert np.linalg.norm(free.G) > 10
    assert free.hinf < bounded.hinf


def test_cart_pendulum_pays_little_for_a_bounded_gain():
    """Cart–pendulum at decay 2: the unbounded design needs ‖L‖ ≈ 1e4;
    ‖L‖ ≤ 1000 costs a few per cent of γ, and tightening the bound moves
    γ up (monotone)."""
    plant = AXIS['cart-pendulum']
    free = cx.hinf_observer(plant, decay=2.0, max_gain=None)
    gammas = []
    for bound in (3000.0, 1000.0, 300.0):
        obs = cx.hinf_observer(plant, decay=2.0, max_gain=bound)
        assert np.linalg.norm(obs.L, 2) <= bound * (1 + 1e-6)
        assert obs.decay >= 2.0 - 1e-6
        # the norm of the returned gain, rebuilt by hand on a grid
        A, C = plant.A, plant.C
        w = np.logspace(-2, 3, 3000)
        peak = max(np.linalg.svd(np.linalg.solve(
            1j * x * np.eye(4) - (A - obs.L @ C), obs.L), compute_uv=False)[0]
            for x in w)
        assert obs.hinf >= peak * (1 - 1e-6)
        gammas.append(obs.hinf)
    assert np.linalg.norm(free.L, 2) > 3000
    assert free.hinf <= gammas[0] <= gammas[1] <= gammas[2]
    assert gammas[1] <= 1.05 * free.hinf


@pytest.mark.parametrize('make', [
    lambda kw: cx.coupled_observer(ct.ss([[-0.5]], [[1.0]], [[1.0]], 0),
                                   decay=2.5, **kw),
    lambda kw: cx.gi_observer(ct.ss([[1.0, 1.0], [0.0, -2.0]], [[0.0], [1.0]],
                                    [[1.0, 0.0], [1.0, 0.0]], 0),
                              [[-0.5, 0.2], [0.0, 1.0]], decay=1.0,
                              augmented=True, **kw),
    lambda kw: cx.hinf_observer(ct.c2d(UNSTABLE, 0.1), decay=2.0, **kw),
], ids=['coupled', 'gi-augmented', 'discrete'])
def test_every_kind_holds_the_bound(make):
    """Half the free design's gain is held.  The GI plant is designed at
    decay 1, where γ itself asks for a fast pole (gain 500-700): at decay
    3 its γ is flat in the gain, and with numpy 2.5 / scipy 1.18 the free
    design came out at the least gain that meets the region (25.2 by a
    brute-force search), so half of it is rightly refused."""
    free = make(dict(max_gain=None))
    bound = 0.5 * np.linalg.norm(free.G, 2)
    obs = make(dict(max_gain=bound))
    assert np.linalg.norm(obs.G, 2) <= bound * (1 + 1e-6)
    assert obs.hinf >= free.hinf * (1 - 1e-3)


@pytest.mark.parametrize('seed', [0, 1])
def test_bound_in_the_plants_units(seed):
    """The bound is on the gain in the plant's own units, also where the
    synthesis runs on a rescaled realisation: the cart–pendulum with its
    positions in km and its angles in hundredths of a radian.  (Seed 1
    was refused while seed 0 showed a design exists: the convex design,
    2.3x over the bound, was the only start.)"""
    P = AXIS['cart-pendulum']
    T = np.diag([1e-3, 1e-3, 1e2, 1e2])
    plant = ct.ss(T @ P.A @ np.linalg.inv(T), T @ P.B,
                  P.C @ np.linalg.inv(T), 0)
    free = cx.hinf_observer(plant, decay=2.0, max_gain=None,
                            gain_tolerance=0)
    bound = 0.1 * np.linalg.norm(free.L, 2)
    obs = cx.hinf_observer(plant, decay=2.0, max_gain=bound, seed=seed,
                           gain_tolerance=0)
    # held (to 1e-6) and at the bound (the optimum presses on it; the
    # polish with the poles as variables, which holds the bound as a
    # penalty, ended 3.5e-4 inside it with numpy 2.0 and scipy 1.13)
    assert np.linalg.norm(obs.L, 2) <= bound * (1 + 1e-6)
    assert np.linalg.norm(obs.L, 2) == pytest.approx(bound, rel=1e-3)
    assert obs.decay >= 2.0 - 1e-6
    # "γ within a few per cent of the unbounded one" (the trade-off
    # issue); 5.1 % measured here (γ 500.2 against 476.1)
    assert obs.hinf <= 1.06 * free.hinf


def test_options_checked_before_any_solve():
    for bad, exc in [('big', cx.ParameterError), (-1.0, cx.ParameterError),
                     (0.0, cx.ParameterError), (True, cx.ArgumentError)]:
        with pytest.raises(exc, match='max_gain'):
            cx.SynthesisOptions(max_gain=bad)


def test_refine_false_says_the_bound_is_not_held():
    with pytest.warns(cx.GainWarning, match='refine=False'):
        cx.hinf_observer(UNSTABLE, decay=2.0, max_gain=1.5, refine=False)


def test_unbounded_discrete_design_warns_in_its_own_words():
    """A discrete mode at 0.95 seen 1e-8 as strongly as the other: moving
    it into |z| < 0.5 needs l₂ · 1e-8 > 0.45 (the error matrix is nearly
    triangular), a gain above 4.5e7.  With the bound lifted the design
    says so with GainWarnings only: scipy's notes on the ill-conditioned
    bilinear map of the norm's cross-check (some 200 LinAlgWarnings) stay
    inside, and the warning gives no pole rate for a discrete design (it
    said 'its fastest error pole 0 times')."""
    plant = ct.ss(np.diag([0.9, 0.95]), [[1.0], [1.0]], [[1.0, 1e-8]], 0,
                  0.1)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always')
        obs = cx.hinf_observer(plant, region=cx.Disk(0.5), max_gain=None)
    kinds = {w.category for w in caught}
    assert kinds == {cx.GainWarning}, kinds
    assert not any('fastest error pole' in str(w.message) for w in caught)
    L = np.asarray(obs.L)
    assert np.linalg.norm(L, 2) > 0.45e8
    poles = np.linalg.eigvals(plant.A - L @ plant.C)
    assert np.all(np.abs(poles) < 0.5 + 1e-6)
