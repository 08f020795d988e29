"""A seeded subset of benchmarks/design_campaign.py: random plants of
every family (unstable, marginal, defective, nearly unobservable, badly
scaled, no solution) through every observer kind and region type, each
design judged without the package's verification code (the error system
rebuilt from the plant and the gain, the region's own formula, a grid
norm and control.linfnorm, the estimator run against the plant)."""

import warnings

import control as ct
import numpy as np
import pytest

from design_campaign import (campaign, design, exact_h2, judge,  # noqa: E402
                             make_case, rebuild)

#: a single call's limit before it counts as a hang: these tests are about
#: what a call returns, and on CI's two shared cores a call that takes
#: 46 s alone (1906) ran past 120 s
HANG = 600.0


@pytest.mark.slow
def test_seeded_campaign():
    counts, details = campaign(42, limit=120.0, start=0, workers=2)
    bad = [d for d in details if d[5] in ('crash', 'hang', 'silent wrong',
                                          'refused wrong',
                                          'forced refusal, unnamed')]
    assert not bad, bad
    assert counts['unwarned huge gain'] == 0
    assert counts['verified'] >= 30


@pytest.mark.parametrize('seed', [117, 159])
def test_augmented_gi_on_badly_scaled_plants(seed):
    """Wrong refusals of the full campaign: the state scaling drove the
    constant-disturbance states to 3e-30 (their rows of A are empty, so
    the balancing sweeps did not converge), and placement on the scaled
    pair could not move the disturbance mode.  An independent placement
    on the augmented pair shows a design exists; the judge must now
    accept the returned one."""
    counts, details = campaign(1, limit=HANG, start=seed, workers=1)
    assert details[0][2] == 'gi-aug' and details[0][1] == 'badly-scaled'
    assert details[0][5] == 'verified', details[0]


@pytest.mark.slow
def test_fragile_design_is_not_silent():
    """Campaign seed 297 (a defective discrete plant, a small disk): the
    design's error grows 2.6e6-fold before it decays, and the estimator
    then parts from its error system by rounding (6e-5 relative in 60
    steps).  The package must say so (a GainWarning), so the judge counts
    it as warned, not silent."""
    counts, details = campaign(1, limit=HANG, start=297, workers=1)
    assert details[0][5] in ('verified', 'warned, check failed'), details[0]


@pytest.mark.slow
@pytest.mark.parametrize('seed, why', [
    (416, 'the trade-off H2 norm crashed: scipy inverted a singular A + I'),
    (655, 'a mode seen 1e-6 as strongly as the others was called '
          'unobservable (balanced PBH σ_min 2.6e-8; obsv has full rank)'),
    (846, "the Riccati route crashed: scipy's ordered Schur form raised "
          "'leading eigenvalues do not satisfy sort condition'"),
] + [(seed, 'silent: relative gain errors of 1e-6 cost the design more '
              'than its decay (484: γ 3.7e6, decay lost 8.3) with no '
              'GainWarning') for seed in (484, 575, 870)] + [
    (819, 'silent: the estimator parted from its error system by 2x the '
          'judge\'s rounding tolerance; 1e-6 gain errors cost 1.733 of its '
          'decay 3.48, under the old warning threshold of half the decay'),
    (658, 'judged silent: estimator and error system, both run in double, '
          '1.2e-7 apart at γ 1.3e5, each 6.5e-8 off the same runs in '
          'extended precision, which the judge now compares'),
])
def test_campaign_seeds_fixed(seed, why):
    """Seeds of the full campaign that crashed or were refused wrongly;
    an independent placement (655) shows a design exists."""
    counts, details = campaign(1, limit=HANG, start=seed, workers=1)
    assert details[0][5] in ('verified', 'warned, check failed',
                             'refused right'), (why, details[0])


@pytest.mark.parametrize('seed', [1313, 1341])
def test_h2_of_far_from_normal_designs_is_verified(seed):
    """Discrete pairs of gain 3e6-3e7 whose error matrices are far from
    normal: SLICOT's SB03MD gave Gramians with negative eigenvalues, and
    the reported H2 norm was 0 against python-control's 2.45605e6 (1313)
    or 2.50e7 against 3.54e7 (1341; the exact Gramian in rational
    arithmetic gives 3.53682e7).  The design itself depends on the
    numpy/scipy stack (with numpy 2.5 and scipy 1.18, 1341's has H2
    1.17e6, and the package is 4.7e-6 from the exact value, python-control
    7.7e-6): the reported H2 norm is held against the exact one at 1e-4,
    and every other check of the judge must pass."""
    case = make_case(seed)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        obs = design(case)
    why = judge(case, obs)
    assert why == '' or why.startswith('H2 norm'), why
    exact = exact_h2(*rebuild(case, obs), case['dt'])
    assert obs.report.tradeoff.h2 == pytest.approx(exact, rel=1e-4)


@pytest.mark.parametrize('seed', [990, 1706])
def test_placement_fallback_keeps_the_poles_inside(seed):
    """Discrete 10-state GI plants of dt 0.01-0.02 whose poles cluster at
    0.97-0.995, already inside the region (990: stability only; 1706:
    |z| < 0.998): both LMI solvers failed, and placing all ten poles came
    out unstable, so the design was refused, though the zero gain meets
    the region.  The placement fallback now moves only the poles outside
    (none here), and refines a design without a certified level: on 990
    γ is far below that of the zero gain, by python-control's norm."""
    counts, details = campaign(1, limit=HANG, start=seed, workers=1)
    assert details[0][5] == 'verified', details[0]
    if seed == 990:
        case = make_case(990)
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')
            obs = design(case)
        keep = case['C'] @ np.linalg.pinv(case['C'])
        zero = ct.ss(case['A'], -case['Bw_gi'] @ keep,
                     np.eye(len(case['A'])), 0, case['dt'])
        assert obs.hinf < 1e-3 * ct.linfnorm(zero)[0]


def test_a_norm_fallback_in_verification_is_not_told():
    """Campaign call 1906 (a marginal plant, three copies): ab13dd failed
    on one candidate's error system while it was verified, and a
    RuntimeWarning about the package's fallback reached the user."""
    counts, details = campaign(1, limit=HANG, start=1906, workers=1)
    assert details[0][5] == 'verified', details[0]
    assert details[0][7] == [], details[0]


@pytest.mark.parametrize('seed', [702, 1080])
def test_undetectable_augmented_plant_is_a_right_refusal(seed):
    """A GI-augmented plant whose disturbance mode (s = 0 or z = 1) the
    measurements [C, U] do not see: the package refuses with
    NotDetectableError, and the judge now proves it right by the PBH test
    of the augmented pair at that exact mode (it counted these as refusals
    without proof: 3 of the 10 of calls 900-1199)."""
    counts, details = campaign(1, limit=HANG, start=seed, workers=1)
    assert details[0][2] == 'gi-aug'
    assert details[0][5] == 'refused right', details[0]


@pytest.mark.parametrize('seed', [8, 30, 63, 129, 140, 206])
def test_designs_for_several_models_pass_the_judge(seed):
    """Campaign calls of 2 to 4 models (every 11th seed): the gain's
    error system rebuilt on every model, its poles in the region and
    each model's stated norm against a grid and control.linfnorm."""
    case = make_case(seed)
    assert 2 <= len(case['models']) + 1 <= 4
    counts, details = campaign(1, limit=HANG, start=seed, workers=1)
    assert details[0][5] == 'verified', details[0]


def test_a_multi_model_refusal_leaks_no_solver_warning():
    """Campaign seed 85 (two models, no common gain found): the pairwise
    LMIs that name the conflicting models let cvxpy's 'solution may be
    inaccurate' reach the user."""
    counts, details = campaign(1, limit=HANG, start=85, workers=1)
    assert details[0][5] in ('refused', 'refused right'), details[0]
    assert 'models 1 and 2' in details[0][6]
    assert details[0][7] == []


def test_no_tolerance_cost_is_stated_against_a_norm_near_zero():
    """Seed 5211 (defective, four plant models, stability only): the
    nominal optimum (γ 2.0e-6) misses the default gain tolerance and the
    default design has γ 9.4e-6.  Both are below 1e-4 of the noise scale,
    where norms rank equal to 0: a cost relative to them (+369 %) would
    say nothing, and the report states none."""
    obs = design(make_case(5211))
    assert obs.hinf < 1e-4 * obs.problem.noise_scale
    assert 'nominal' not in obs.report.stats
    assert 'gain tolerance costs' not in str(obs.report)
