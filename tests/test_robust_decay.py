"""Robust decay by default: the factories' designs keep their region under
relative gain errors of 1e-6 (certified) and when their gains are rounded
to 6 significant digits; ``gain_tolerance=0`` gives the nominal optimum.

Every check rebuilds the error matrix ``Ae − G Ce`` from the gain with
numpy, independently of the code that made it."""

import warnings

import control as ct
import numpy as np
import pytest

import controlext as cx
from controlext.exceptions import GainWarning
from conftest import keeps, rounded, worst_pole
from plants import PUBLIC, noise_model

SCALAR = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
SECOND = ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]], 0)
B747 = PUBLIC['747 lateral']         # two sensors, two inputs


@pytest.mark.parametrize('plant, decay, copies, published', [
    (SCALAR, 2.5, 2, 0.4953),
    (SCALAR, 2.5, 3, None),
    (SECOND, 1.0, 2, 0.0594),
    pytest.param(SECOND, 1.0, 3, None, marks=pytest.mark.slow),
], ids=['scalar-2', 'scalar-3', 'second-2', 'second-3'])
def test_paper_designs_keep_their_decay(plant, decay, copies, published):
    nominal = cx.coupled_observer(plant, decay=decay, copies=copies,
                                  gain_tolerance=0)
    if published is not None:
        # the nominal optimum is the published number's design
        assert nominal.hinf < published + 5e-5
    # the nominal optimum's slowest poles sit on the edge as a cluster:
    # no gain error at all is certified (its 6-digit rounding lands
    # outside or on the edge, depending on the stack's last bits)
    from controlext.synthesis.limits import GainTolerance
    assert GainTolerance(1e-6).verify(nominal.problem, nominal.G,
                                      nominal.report.region) > 1
    obs = cx.coupled_observer(plant, decay=decay, copies=copies)
    keeps(obs, -decay)
    assert obs.report.stats['limits']['gain_tolerance'] <= 1 + 1e-6
    # the cost in γ: within 1.5 % of the nominal optimum (three copies
    # of the second-order plant: +1.15 % with numpy 2.4, +1.53 % with
    # numpy 2.5, where the repair ends elsewhere; 2 % is asserted there);
    # a pair's repaired nominal optimum within 0.5 % (measured +0.06 %
    # and +0.07 %)
    within = 1.005 if copies == 2 else \
        1.02 if copies == 3 and plant is SECOND else 1.015
    assert nominal.hinf * (1 - 1e-6) <= obs.hinf <= within * nominal.hinf
    # the report keeps the nominal optimum's norm (it missed the
    # tolerance) and says what the tolerance cost
    kept = obs.report.stats['nominal']
    assert kept == pytest.approx(nominal.hinf, rel=1e-3)
    if published is not None:
        assert kept < published + 5e-5
    cost = f"{100 * (obs.hinf / kept - 1):+.3g} % in γ over the nominal"
    assert cost in str(obs.report)
    if plant is SCALAR:
        # a repair within 1 % of the nominal optimum is the design, with
        # no design of a looser tolerance after it (scalar N = 3: +0.65 %)
        assert obs.report.stats['tolerance'] == \
            'the nominal optimum, refined under the gain tolerance'
        assert obs.hinf <= 1.01 * nominal.hinf


def test_report_states_the_h2_cost_of_the_tolerance():
    """Minimising the H2 norm, the report keeps the H2 norm of the
    nominal optimum (that of the ``gain_tolerance=0`` design, whose
    clustered poles miss the tolerance) and states the cost in it."""
    obs = cx.coupled_observer(SCALAR, decay=2.5, objective='h2')
    nominal = cx.coupled_observer(SCALAR, decay=2.5, objective='h2',
                                  gain_tolerance=0)
    keeps(obs, -2.5)
    kept = obs.report.stats['nominal']
    assert kept == pytest.approx(nominal.report.h2, rel=1e-3)
    assert kept * (1 - 1e-6) <= obs.report.h2 <= 1.005 * kept
    cost = f"{100 * (obs.report.h2 / kept - 1):+.3g} % in H2 norm"
    assert cost in str(obs.report)


def test_report_says_a_road_below_the_nominal_search_cost_nothing():
    """Where the road ends below the nominal search (campaign seed 5183:
    a three-copy design refined under the tolerance from a pair's, 0.669
    against the nominal search's 0.691), the report says the tolerance
    cost nothing and by how much the design is below, not a negative
    cost; above it, the cost as before."""
    obs = cx.coupled_observer(SCALAR, decay=2.5)
    report = obs.report
    gamma = report.hinf
    report.stats = report.stats.replace(nominal=gamma / 0.95)
    text = str(report)
    assert "gain tolerance costs" in text
    assert "nothing: this design's γ is 5 % below the nominal search's " \
        f"{gamma / 0.95:.6g}" in text
    assert "-5" not in text.split("gain tolerance costs")[1].splitlines()[0]
    report.stats = report.stats.replace(nominal=gamma / 1.02)
    assert "+2 % in γ over the nominal optimum's" in str(report)


def test_mimo_747_designs_keep_their_decay():
    """Two sensors, input disturbances and sensor noise; one copy and a
    pair.  The certificate is a bound: every corner of the box of
    relative errors at the certified size keeps the decay."""
    Bw = np.hstack([B747.B, np.zeros((4, 2))])
    Dw = np.hstack([np.zeros((2, 2)), 0.1 * np.eye(2)])
    rng = np.random.default_rng(5)
    for copies in (1, 2):
        factory = cx.hinf_observer if copies == 1 else \
            lambda *a, **k: cx.coupled_observer(*a, copies=copies, **k)
        obs = factory(B747, decay=0.5, Bw=Bw, Dw=Dw,
                      refine_options=dict(random_starts=8))
        keeps(obs, -0.5)
        ratio = obs.report.stats['limits']['gain_tolerance']
        certified = 1e-6 / max(ratio, 1e-300)
        G = obs.G
        for _ in range(200):
            signs = rng.choice([-1.0, 1.0], size=G.shape)
            assert worst_pole(obs, G * (1 + certified * signs)) <= -0.5


def test_nine_state_five_sensor_design_keeps_its_decay():
    """The frame with an active mass driver (9 states, 5 sensors, four
    lightly damped modes): the default design keeps its decay, its norm
    rebuilt from the gain with ``ct.linfnorm`` is the report's, and it is
    at most 1.5 % above the unconstrained filter level found by bisection
    on scipy's Riccati solver (measured +0.89 %).  Its nominal optimum
    meets the tolerance, so its report has no cost to state."""
    from test_hinf_observer import riccati_level
    plant = PUBLIC['frame with mass driver']
    Bw, Dw = noise_model(plant)
    obs = cx.hinf_observer(plant, decay=0.5, Bw=Bw, Dw=Dw)
    keeps(obs, -0.5)
    # its nominal optimum met the tolerance: it is the design, and there
    # is no cost to report
    assert obs.report.stats['tolerance'] == \
        'the nominal optimum keeps its region under the gain tolerance'
    assert 'nominal' not in obs.report.stats
    assert 'gain tolerance costs' not in str(obs.report)
    p = obs.problem
    rebuilt = ct.linfnorm(ct.ss(p.Ae - obs.G @ p.Ce, obs.G @ p.Dwe - p.Bwe,
                                p.Cze, 0))[0]
    assert rebuilt == pytest.approx(obs.hinf, rel=1e-6)
    level = riccati_level(plant.A, plant.C, Bw, Dw, np.eye(9))
    assert level * (1 - 1e-6) <= rebuilt <= 1.015 * level


def test_certificate_of_uncoupled_copies_is_that_of_one():
    """Scalar plant a = -0.5, gain 3 (pole -3.5), edge Re s = -2.5: the
    resolvent's peak on the edge is 1, so the tolerance is certified up
    to 1/3 (ratio 3ε).  Two uncoupled copies of that gain have the same
    poles and the same certified tolerance (a bound by ‖G‖_F would lose
    √2)."""
    from controlext.synthesis import ObserverProblem
    from controlext.synthesis.limits import GainTolerance
    limit = GainTolerance(0.1)
    one = ObserverProblem(A=[[-0.5]], C=[[1.0]])
    assert limit.verify(one, np.array([[3.0]]),
                        cx.HalfPlane(2.5)) == pytest.approx(0.3)
    pair = ObserverProblem(A=[[-0.5]], C=[[1.0]], copies=2)
    G = pair.embed(np.array([[3.0]]))
    assert limit.verify(pair, G, cx.HalfPlane(2.5)) == pytest.approx(0.3)


def test_discrete_pair_keeps_its_disk():
    """c2d of the second-order plant, a pair in the disk |z| <= e^{-dt}."""
    dt = 0.1
    plant = ct.c2d(SECOND, dt)
    radius = float(np.exp(-1.0 * dt))
    obs = cx.coupled_observer(plant, region=cx.Disk(radius,
                                                    domain='discrete'))
    keeps(obs, radius)
    nominal = cx.coupled_observer(plant, region=cx.Disk(
        radius, domain='discrete'), gain_tolerance=0)
    assert obs.hinf <= 1.015 * nominal.hinf


def test_digits_are_monotone_on_the_default_design():
    """The report's ``digits``: rounding to that many digits or more keeps
    the region (every count checked here, 6 included)."""
    obs = cx.coupled_observer(SCALAR, decay=2.5, copies=3)
    d = obs.report.tradeoff.digits
    assert d <= 6
    for digits in range(d, 18):
        assert worst_pole(obs, rounded(obs.G, digits)) <= -2.5 * (1 - 1e-9)


def test_no_default_where_it_cannot_be_certified():
    """A sector's rays carry no certificate, and refine=False returns the
    convex design: neither refuses for the default tolerance."""
    sector = cx.HalfPlane(1.0) & cx.Sector(0.7)
    obs = cx.hinf_observer(SECOND, region=sector)
    assert obs.report.criteria.gain_tolerance is None
    convex = cx.hinf_observer(SECOND, decay=1.0, refine=False)
    assert convex.report.criteria.gain_tolerance is None
    # asked for, it is refused before any solver runs
    with pytest.raises(cx.exceptions.ArgumentError, match='half-planes'):
        cx.hinf_observer(SECOND, region=sector, gain_tolerance=1e-6)


def test_nominal_optimum_with_a_warning_where_no_design_is_robust():
    """A nearly unobservable discrete plant (cond(obsv) ~ 1e7) in a small
    disk: the gains that place its poles there need more than 6 digits,
    so the default falls back to the nominal optimum and says so; asked
    for explicitly, the tolerance is refused."""
    rng = np.random.default_rng(3)
    A = np.eye(4) + 0.01 * rng.normal(size=(4, 4))
    C = rng.normal(size=(1, 4))
    plant = ct.ss(A, np.zeros((4, 1)), C, 0, 0.1)
    disk = cx.Disk(0.304, center=-0.08, domain='discrete')
    small = dict(refine_options=dict(random_starts=4, polish=2))
    with pytest.warns(GainWarning, match='nominal optimum'):
        obs = cx.hinf_observer(plant, region=disk, **small)
    assert disk.contains(ct.poles(obs), tol=1e-6)
    assert not disk.contains(np.linalg.eigvals(
        obs.problem.Ae - rounded(obs.G) @ obs.problem.Ce), tol=1e-6)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore')
        with pytest.raises(cx.exceptions.VerificationError):
            cx.hinf_observer(plant, region=disk, gain_tolerance=1e-6,
                             **small)


def test_gain_tolerance_zero_is_the_nominal_optimum():
    """0 and the engine's own default (None in SynthesisOptions) agree,
    and the report says no tolerance was held."""
    a = cx.coupled_observer(SCALAR, decay=2.5, gain_tolerance=0)
    assert a.report.criteria.gain_tolerance == 0
    assert 'gain_tolerance' not in a.report.stats.get('limits', {})
    # the PENBMI pair of the paper: γ 0.4953, and the refined optimum
    # below it
    assert a.hinf < 0.4953


def test_default_design_survives_tiny_plant_perturbations():
    """Relative perturbations of 1e-13 in A and C (two seeded draws) move
    the default scalar pair's γ by less than 0.2 %."""
    base = cx.coupled_observer(SCALAR, decay=2.5).hinf
    rng = np.random.default_rng(7)
    for _ in range(2):
        A = SCALAR.A * (1 + 1e-13 * rng.uniform(-1, 1, SCALAR.A.shape))
        C = SCALAR.C * (1 + 1e-13 * rng.uniform(-1, 1, SCALAR.C.shape))
        moved = cx.coupled_observer(ct.ss(A, SCALAR.B, C, 0), decay=2.5)
        assert moved.hinf == pytest.approx(base, rel=2e-3)


def test_repaired_nominal_optimum_on_a_public_plant():
    """HE1 (4 states, 2 sensors): the nominal optimum's poles are fragile;
    the default design is its repair, within 0.5 % of it (the public
    plants' allowance), and keeps its decay; both norms recomputed with
    ``ct.linfnorm`` on error systems rebuilt from the gains."""
    plant = PUBLIC['HE1']
    Bw, Dw = noise_model(plant)
    nominal = cx.hinf_observer(plant, decay=0.5, Bw=Bw, Dw=Dw,
                               gain_tolerance=0)
    obs = cx.hinf_observer(plant, decay=0.5, Bw=Bw, Dw=Dw)
    keeps(obs, -0.5)

    def norm(o):
        p = o.problem
        return ct.linfnorm(ct.ss(p.Ae - o.G @ p.Ce, o.G @ p.Dwe - p.Bwe,
                                 p.Cze, 0))[0]
    assert norm(nominal) * (1 - 1e-6) <= norm(obs) <= \
        1.005 * norm(nominal)


def test_nominal_optimum_meeting_the_tolerance_meets_fewer_copies_too():
    """The tolerance road's first exit (the nominal optimum keeps its
    region under the tolerance) still compares it with the designs of
    fewer copies: a nominal search that stopped short, stood in for by
    both copies at four times the one-copy gain (poles at −8.5, far
    inside), loses to the one-copy design embedded.  The norms are
    rebuilt from the gains with ``ct.linfnorm``."""
    from controlext.synthesis import SynthesisOptions
    from controlext.synthesis.tolerance import tolerant
    from controlext.synthesis.verify import verify_design
    one = cx.hinf_observer(SCALAR, decay=2.5)
    problem = cx.coupled_observer(SCALAR, decay=2.5, refine=False).problem
    region = cx.HalfPlane(2.5)
    options = SynthesisOptions(gain_tolerance=1e-6)
    short = problem.embed(4 * one.G)
    embedded = problem.embed(one.G)

    def norm(G):
        p = problem
        return ct.linfnorm(ct.ss(p.Ae - G @ p.Ce, p.Bwe - G @ p.Dwe, p.Cze,
                                 0))[0]

    def synthesise(p, r, o, **facts):
        return short, verify_design(p, short, r)

    def check(G, **facts):
        return verify_design(problem, G, region, criteria=options.criteria,
                             **facts)

    done, _, _, _ = tolerant(synthesise, problem, region, options, None,
                             None, None, check, [(embedded, 'luenberger')])
    G, report = done
    assert norm(embedded) < norm(short) - 0.1       # 0.8 against 0.94
    np.testing.assert_array_equal(G, embedded)
    assert report.stage == 'luenberger'
    assert abs(report.hinf - norm(embedded)) <= 1e-6 * norm(embedded)


def test_runners_are_other_basins_best_first():
    """A refinement keeps the end points of up to two other basins within
    5 % of its result, each more than ``race_tie`` (0.1 %) behind the one
    kept before it: a basin's pole-cluster polish and its BFGS end point
    0.05 % apart are one basin."""
    from controlext.synthesis.refine import RUNNER_GAP, RUNNERS, _runners
    G = {label: np.full((2, 1), k) for k, label in enumerate('abcdef')}
    results = [(10.0, 'a', G['a']), (10.005, 'b', G['b']),
               (10.2, 'c', G['c']), (10.204, 'd', G['d']),
               (10.4, 'e', G['e']), (10.45, 'f', G['f'])]
    runners = _runners(results, 1e-3)
    assert (RUNNERS, RUNNER_GAP) == (2, 0.05)
    assert [label for label, _ in runners] == ['c', 'e']
    assert runners[0][1] is G['c']
    assert _runners(results[:2], 1e-3) == []
    # 6 % behind: not a runner
    far = [(10.0, 'a', G['a']), (10.6, 'f', G['f'])]
    assert _runners(far, 1e-3) == []


def test_tighter_tolerance_starts_from_the_looser_designs_basins(
        monkeypatch):
    """Under the default tolerance, where neither the nominal optimum nor
    its repair will do, refinement starts from the design of 1e-4, then
    the other basins its refinement ended in (which of them ends lowest
    under 1e-6 is not the one that led: HE1 pair, 18.27-19.37 over the
    plant and three 1e-13 draws from the leader alone), then the nominal
    optimum."""
    import controlext.synthesis.tolerance as tolerance
    from controlext.synthesis import SynthesisOptions
    from controlext.synthesis.records import RefineSummary
    from controlext.synthesis.verify import verify_design
    problem = cx.coupled_observer(SCALAR, decay=2.5, refine=False).problem
    region = cx.HalfPlane(2.5)
    options = SynthesisOptions(gain_tolerance=1e-6)
    # a gain of 2 puts both copies' poles on the edge -2.5, which no
    # tolerance certifies; 3 and 4 hold them inside
    nominal = problem.embed([[2.0]])
    looser = problem.embed([[3.0]])
    other = problem.embed([[4.0]])

    def synthesise(p, r, o, **facts):
        G = looser if o.criteria.gain_tolerance else nominal
        report = verify_design(p, G, r)
        if o.criteria.gain_tolerance:
            report.stats = report.stats.replace(refine=RefineSummary(
                runners=[('lmi+random3', other)]))
        return G, report

    def check(G, **facts):
        return verify_design(problem, G, region, criteria=options.criteria,
                             **facts)

    monkeypatch.setattr(tolerance, '_repaired', lambda *args: None)
    done, starts, repair, _ = tolerance.tolerant(
        synthesise, problem, region, options, None, None, None, check)
    assert done is None and repair
    assert [label for label, _ in starts] == [
        'gain_tolerance=0.0001', 'gain_tolerance=0.0001 lmi+random3',
        'nominal optimum']
    assert starts[0][1] is looser and starts[1][1] is other
    assert starts[2][1] is nominal

