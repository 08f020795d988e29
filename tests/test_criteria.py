"""The H2 objective and the mixed H2/H∞ designs (objective=, max_hinf=,
max_h2=): every number is checked against an independent source —
python-control's Kalman filters (``ct.lqe``/``ct.dlqe``), its H2 and H∞
norms (``ct.norm``), a closed-form scalar Riccati solution, finite
differences, the exact Gramian in rational arithmetic — never against the
code that produced it."""

import warnings

import numpy as np
import pytest
import control as ct

import controlext as cx
from controlext.exceptions import (ArgumentError, ControlextError,
                                   ParameterError)
from controlext.synthesis import ObserverProblem
from controlext.synthesis.criteria import Criteria, h2_norm, h2_parts
from controlext.synthesis.objective import Objective

from design_campaign import exact_gramian, exact_h2  # noqa: E402

# the README's plant with process noise on both states and sensor noise
PLANT = ct.ss([[-1, 1], [-1, 0]], [[0], [1]], [[1, 2]], 0)
BW = np.array([[1.0, 0.0], [0.5, 0.0]])
DW = np.array([[0.0, 1.0]])


def _norms(obs):
    """H2 and H∞ norms of an observer's error system, by python-control."""
    sys = ct.ss(obs.A, obs.B, obs.C, obs.D, obs.dt)
    return float(ct.norm(sys, 2)), float(ct.norm(sys, 'inf'))


def _quiet(fn, *args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', cx.GainWarning)
        return fn(*args, **kwargs)


@pytest.mark.parametrize('dt', [0, 0.2])
def test_h2_gradient_matches_finite_differences(dt):
    """The objective's H2 value is ct.norm(·, 2) of the error system and
    its gradient matches central differences of that value."""
    rng = np.random.default_rng(3)
    A = rng.normal(size=(3, 3)) - (0 if dt else 3) * np.eye(3)
    if dt:
        A *= 0.5 / max(abs(np.linalg.eigvals(A)))
    prob = ObserverProblem(A, rng.normal(size=(2, 3)),
                           Bw=rng.normal(size=(3, 2)),
                           Dw=np.hstack([np.zeros((2, 0)), np.eye(2)]),
                           dt=dt)
    obj = Objective(prob, None, criteria=Criteria('h2'))
    G = 0.05 * rng.normal(size=prob.gain_shape)
    value, grad = obj(G.ravel())
    sys = ct.ss(*prob.error_system(G), dt)
    assert value == pytest.approx(float(ct.norm(sys, 2)), rel=1e-9)
    step, fd = 1e-6, np.zeros(G.size)
    for k in range(G.size):
        e = np.zeros(G.size)
        e[k] = step
        up = ct.ss(*prob.error_system(G + e.reshape(G.shape)), dt)
        down = ct.ss(*prob.error_system(G - e.reshape(G.shape)), dt)
        fd[k] = (ct.norm(up, 2) - ct.norm(down, 2)) / (2 * step)
    np.testing.assert_allclose(grad, fd, rtol=1e-5, atol=1e-8)


def test_h2_objective_without_region_is_the_kalman_filter():
    """objective='h2' with no region returns python-control's lqe gain."""
    obs = cx.hinf_observer(PLANT, Bw=BW, Dw=DW, objective='h2')
    L, P, _ = ct.lqe(PLANT.A, BW[:, :1], PLANT.C, np.eye(1), np.eye(1))
    np.testing.assert_allclose(obs.G, L, rtol=1e-8)
    h2, _ = _norms(obs)
    assert h2 == pytest.approx(np.sqrt(np.trace(P)), rel=1e-8)
    assert obs.report.h2 == pytest.approx(h2, rel=1e-8)


def test_discrete_h2_objective_is_the_kalman_predictor():
    plant = ct.c2d(PLANT, 0.1)
    obs = cx.hinf_observer(plant, Bw=0.1 * BW, Dw=DW, objective='h2')
    L, P, _ = ct.dlqe(plant.A, 0.1 * BW[:, :1], plant.C, np.eye(1),
                      np.eye(1))
    np.testing.assert_allclose(obs.G, L, rtol=1e-7)
    assert _norms(obs)[0] == pytest.approx(np.sqrt(np.trace(P)), rel=1e-7)


def test_scalar_kalman_floor_refuses_a_smaller_max_h2():
    """x' = -x/2 + w1, y = x + w2: the Kalman covariance solves
    -P - P^2 + 1 = 0, P = (sqrt 5 - 1)/2; no estimator has a smaller H2
    norm, so a bound below sqrt(P) is refused before any solve."""
    plant = ct.ss([[-0.5]], [[0.0]], [[1.0]], 0)
    kw = dict(Bw=[[1.0, 0.0]], Dw=[[0.0, 1.0]])
    floor = np.sqrt((np.sqrt(5) - 1) / 2)
    obs = cx.hinf_observer(plant, objective='h2', **kw)
    assert _norms(obs)[0] == pytest.approx(floor, rel=1e-9)
    with pytest.raises(ParameterError, match='least H2 norm'):
        cx.hinf_observer(plant, decay=1.0, max_h2=0.99 * floor, **kw)
    # γ∞* = 1/sqrt(1.25) for this plant (floor module's example, by the
    # Riccati equation with γ: 1 - 1/γ² = 1/1.25)
    with pytest.raises(ParameterError, match='least H∞ norm'):
        cx.hinf_observer(plant, objective='h2', max_hinf=0.85, **kw)


@pytest.mark.parametrize('copies', [1, 2])
def test_h2_design_in_a_region_beats_the_hinf_design_on_white_noise(copies):
    """At decay 1 the H∞-optimal design has H2 norm > 5; the H2 design
    is within 1 % of the Kalman filter's, which no design beats (ct.lqe),
    with its poles in the region."""
    factory = cx.hinf_observer if copies == 1 else cx.coupled_observer
    obs = factory(PLANT, Bw=BW, Dw=DW, decay=1.0, objective='h2')
    h2, _ = _norms(obs)
    _, P, _ = ct.lqe(PLANT.A, BW[:, :1], PLANT.C, np.eye(1), np.eye(1))
    kalman = np.sqrt(np.trace(P))
    assert kalman * (1 - 1e-9) <= h2 <= 1.01 * kalman
    assert max(np.linalg.eigvals(obs.A).real) <= -1 + 1e-6
    hinf_design = factory(PLANT, Bw=BW, Dw=DW, decay=1.0)
    assert _norms(hinf_design)[0] > 5 * h2


def test_mixed_bounds_hold_and_move_the_objective_the_right_way():
    """objective='h2' with max_hinf: the bound holds (ct.norm), and a
    tighter bound never gives a smaller H2 norm."""
    free = cx.hinf_observer(PLANT, Bw=BW, Dw=DW, decay=1.0, objective='h2')
    h2_free, hinf_free = _norms(free)
    lowest = cx.hinf_observer(PLANT, Bw=BW, Dw=DW, decay=1.0)
    hinf_low = _norms(lowest)[1]
    previous = h2_free
    for bound in np.linspace(hinf_free, hinf_low, 5)[1:-1]:
        obs = cx.hinf_observer(PLANT, Bw=BW, Dw=DW, decay=1.0,
                               objective='h2', max_hinf=bound)
        h2, hinf = _norms(obs)
        assert hinf <= bound * (1 + 1e-6)
        assert max(np.linalg.eigvals(obs.A).real) <= -1 + 1e-6
        assert h2 >= previous * (1 - 1e-6)
        previous = h2


def test_max_h2_bounds_an_hinf_design():
    """objective='hinf' with max_h2: the H2 bound holds and costs γ
    against the unbounded design (ct.norm)."""
    free = cx.hinf_observer(PLANT, Bw=BW, Dw=DW, decay=1.0)
    h2_free, hinf_free = _norms(free)
    obs = cx.coupled_observer(PLANT, Bw=BW, Dw=DW, decay=1.0, max_h2=1.0)
    h2, hinf = _norms(obs)
    assert h2 <= 1.0 * (1 + 1e-6) < h2_free
    assert hinf >= hinf_free * (1 - 1e-3)
    assert obs.report.criteria == Criteria('hinf', max_h2=1.0,
                                           gain_tolerance=1e-6)


def test_convex_stage_certifies_both_norms():
    """refine=False returns the mixed LMI's gain: its H2 norm within the
    certified level and its H∞ norm within the bound (ct.norm)."""
    obs = cx.hinf_observer(PLANT, Bw=BW, Dw=DW, decay=1.0, objective='h2',
                           max_hinf=0.9, refine=False)
    h2, hinf = _norms(obs)
    assert obs.report.stage == 'lmi'
    assert h2 <= obs.report.gamma_bound * (1 + 1e-5)
    assert hinf <= 0.9 * (1 + 1e-6)


def test_discrete_mixed_design_in_a_disk():
    plant = ct.c2d(PLANT, 0.1)
    region = cx.Disk(0.9, domain='discrete')
    obs = cx.hinf_observer(plant, Bw=0.1 * BW, Dw=DW, region=region,
                           objective='h2', max_hinf=0.9)
    h2, hinf = _norms(obs)
    assert hinf <= 0.9 * (1 + 1e-6)
    assert max(abs(np.linalg.eigvals(obs.A))) <= 0.9 + 1e-6
    assert obs.report.h2 == pytest.approx(h2, rel=1e-8)


def test_gi_observer_h2_objective_keeps_invariance():
    """A GI design minimising H2 (noise-free part of y: the LMI route)
    reports its true H2 norm and stays blind to the part of w outside
    range(C)."""
    plant = ct.ss([[0.5, 1.0, 0.0], [0.0, -2.0, 1.0], [0.0, 0.0, -1.0]],
                  [[0.0], [1.0], [0.0]],
                  [[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]], 0)
    Bw = [[1.0, 0.3], [0.2, 1.0], [0.5, -0.4]]
    obs = _quiet(cx.gi_observer, plant, Bw, decay=3.0, objective='h2')
    resp = ct.ss(obs.A, obs.B, obs.C, obs.D)
    assert obs.report.h2 == pytest.approx(float(ct.norm(resp, 2)),
                                          rel=1e-6, abs=1e-9)
    assert max(np.linalg.eigvals(obs.A).real) <= -3 + 1e-6
    # w along the complement of range(C) = span([1, -1]) does not reach
    # the error
    away = np.array([1.0, -1.0]) / np.sqrt(2)
    for w in (0.0, 0.7, 3.0):
        assert np.linalg.norm(resp(1j * w) @ away) < 1e-8


@pytest.mark.parametrize('kw, error, text', [
    (dict(objective='H2'), ParameterError, "'hinf', 'h2'"),
    (dict(objective=2), ArgumentError, 'objective'),
    (dict(objective='h2', max_hinf=-1.0), ParameterError, 'max_hinf'),
    (dict(objective='h2', max_hinf='1'), ArgumentError, 'max_hinf'),
    (dict(max_hinf=1.0), ArgumentError, 'minimises already'),
    (dict(objective='h2', max_h2=1.0), ArgumentError, 'minimises already'),
    (dict(objective='h2', max_hinf=1.0, method='riccati'), ArgumentError,
     'Kalman'),
    (dict(max_h2=1.0, method='modal'), ArgumentError, 'modal'),
])
def test_bad_criteria_are_refused_before_any_solve(kw, error, text,
                                                   monkeypatch):
    import cvxpy as cp
    monkeypatch.setattr(cp.Problem, 'solve', lambda *a, **k: pytest.fail(
        'a solver ran'))
    with pytest.raises(error, match=text):
        cx.hinf_observer(PLANT, Bw=BW, Dw=DW, decay=1.0, **kw)
    assert issubclass(error, ControlextError)


def test_h2_norm_closed_form():
    # 1/(s+2): ‖·‖₂² = 1/4; discrete 1/(z - 1/2): Σ 4^-k = 4/3
    assert h2_norm([[-2.0]], [[1.0]], [[1.0]]) == pytest.approx(0.5)
    assert h2_norm([[0.5]], [[1.0]], [[1.0]], dt=1) == \
        pytest.approx(np.sqrt(4 / 3))
    # the rational reference of the tests below and of the campaign
    assert exact_h2(np.array([[-2.0]]), np.array([[1.0]]),
                    np.array([[1.0]])) == 0.5
    assert exact_h2(np.array([[0.5]]), np.array([[1.0]]),
                    np.array([[1.0]]), dt=1) == np.sqrt(4 / 3)
    # an unstable realisation has no Gramian: the Stein solution of
    # z = 2 is -1/3, and the reference says NaN rather than a complex root
    assert np.isnan(exact_h2(np.array([[2.0]]), np.array([[1.0]]),
                             np.array([[1.0]]), dt=1))


@pytest.mark.parametrize('solver', ['slycot', 'fallback'])
@pytest.mark.parametrize('seed', range(4))
def test_discrete_gramian_of_far_from_normal_matrices(seed, solver,
                                                      monkeypatch):
    """The discrete Gramian (Stein equation in Schur form: slycot's
    SB03MD, or the complex Schur fallback where slycot raises) against
    the sum of ``Aᵏ Aᵏᵀ`` (positive terms: no cancellation on the trace),
    on matrices of poles 0.3-0.5 and ‖A‖ 120-190, where scipy's default
    Kronecker solve is off by up to 3e-3; and against scipy on a well
    conditioned one."""
    import scipy.linalg as la
    import controlext.synthesis.criteria as criteria
    from controlext.synthesis.criteria import gramian
    if solver == 'fallback':
        def broken(*args, **kwargs):
            raise RuntimeError('SB03MD failed')
        monkeypatch.setattr(criteria, '_sb03md', broken)
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(6, 6))
    A *= 0.9 / np.max(np.abs(np.linalg.eigvals(A)))
    B = rng.normal(size=(6, 2))
    ref = la.solve_discrete_lyapunov(A, B @ B.T)
    assert np.linalg.norm(gramian(A, B @ B.T, dt=1) - ref) <= \
        1e-12 * np.linalg.norm(ref)
    U = np.linalg.qr(rng.normal(size=(4, 4)))[0]
    A = U @ (np.diag([0.3, 0.4, -0.5, 0.45]) +
             np.triu(100 * rng.normal(size=(4, 4)), 1)) @ U.T
    P = gramian(A, np.eye(4), dt=1)
    series, Ak = 0.0, np.eye(4)
    for _ in range(400):
        series += np.sum(Ak * Ak)
        Ak = Ak @ A
    assert np.trace(P) == pytest.approx(series, rel=1e-8)
    assert np.min(np.linalg.eigvalsh(P)) > 0.99        # P >= Q = I


def test_h2_of_a_design_in_mixed_units():
    """The second-order plant with its states in units 1e-3 and 1e3: the
    H∞ design's error matrix has ‖A‖ 1.3e6 and poles -1 ± 0.35j, which
    scipy's Lyapunov solver took for a pair summing to zero (the report
    said H2 = inf).  Against the energy of the impulse response, summed
    on a grid of exact steps e^{A h}."""
    import scipy.linalg as la
    T = np.diag([1e-3, 1e3])
    A = np.array([[-1.0, 1.0], [-1.0, 0.0]])
    plant = ct.ss(T @ A @ np.linalg.inv(T), T @ [[0.0], [1.0]],
                  np.array([[1.0, 2.0]]) @ np.linalg.inv(T), 0)
    obs = cx.hinf_observer(plant, decay=1.0)
    Ae, Be, Ce = (np.asarray(M) for M in (obs.A, obs.B, obs.C))
    assert np.linalg.norm(Ae, 2) > 1e5
    h, steps = 1e-3, 40000                      # 40 s: e^{-40} is nothing
    Phi, x = la.expm(Ae * h), Be.copy()
    energy = np.empty(steps + 1)
    for k in range(steps + 1):
        energy[k] = np.sum((Ce @ x) ** 2)
        x = Phi @ x
    assert obs.report.tradeoff.h2 == pytest.approx(
        np.sqrt(h * (energy.sum() - (energy[0] + energy[-1]) / 2)), rel=1e-5)


def test_h2_of_poles_on_the_axis_to_working_precision():
    """Poles at -1e-17 ± j sum to zero in floating point: the H2 norm is
    inf (with its gradient) and scipy's 'perturbed coefficients' warning
    does not reach the user; at -1e-3 ± j it is python-control's value,
    sqrt(1 / (4 · 1e-3)) to first order."""
    B, C = np.array([[0.0], [1.0]]), np.array([[1.0, 0.0]])
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        A = np.array([[-1e-17, 1.0], [-1.0, -1e-17]])
        assert h2_norm(A, B, C) == np.inf
        assert h2_parts(A, B, C)[0] == np.inf
        A = np.array([[-1e-3, 1.0], [-1.0, -1e-3]])
        near = h2_norm(A, B, C)
    assert near == pytest.approx(ct.norm(ct.ss(A, B, C, 0), 2), rel=1e-9)
    assert near == pytest.approx(np.sqrt(1 / 4e-3), rel=1e-3)


@pytest.mark.parametrize('b', [1e6, 3e6])
def test_continuous_gramian_of_a_far_from_normal_matrix(b):
    """Poles -1 ± j in a rotated block [[-1, b], [-1/b, -1]], which
    balancing does not undo: scipy's real Schur solver takes the block for
    a pair summing to zero (the Gramian was inf, as on the axis).  Against
    the exact solution of the three linear equations of the symmetric
    ``P`` in rational arithmetic, to the accuracy the conditioning
    (about b²) allows."""
    from controlext.synthesis.criteria import gramian
    c, s = np.cos(0.3), np.sin(0.3)
    R = np.array([[c, -s], [s, c]])
    A = R @ np.array([[-1.0, b], [-1.0 / b, -1.0]]) @ R.T
    # A P + P Aᵀ = -I (P = [[p, q], [q, r]])
    (p, q), (_, r) = exact_gramian(A, np.eye(2))
    ref = np.array([[float(p), float(q)], [float(q), float(r)]])
    with warnings.catch_warnings():
        warnings.simplefilter('error')
        P = gramian(A, np.eye(2))
    assert np.linalg.norm(P - ref) <= 1e-3 * np.linalg.norm(ref)
    assert h2_norm(A, np.eye(2), np.eye(2)) == pytest.approx(
        np.sqrt(float(p + r)), rel=1e-3)


@pytest.mark.parametrize('dt', [0, 1])
@pytest.mark.parametrize('size', [1e5, 4.7e5, 1e6])
def test_h2_of_a_far_from_normal_pair(size, dt):
    """Two nearly decoupled copies of a 2×2 block of entries ``size``
    and poles 0.5074 e^{±0.2j} (discrete) or -0.5 ± j (continuous): the
    error matrix of a coupled pair of gain 3e6 (campaign call 1313,
    ‖A‖ 4.7e5).  SLICOT's SB03MD returned a Gramian with eigenvalues down
    to -5e10 there, and the H2 norm read 0.  Against the exact solution
    of the Gramian's equation in rational arithmetic."""
    lam = 0.5074 * np.exp(0.2j) if dt else -0.5 + 1j
    a = -0.6 * size
    d = 2 * lam.real - a
    b = 0.36 * size
    block = np.array([[a, b], [(a * d - abs(lam) ** 2) / b, d]])
    A = np.kron(np.eye(2), block) + 1e-13 * np.array(
        [[0, 0, 1, -1], [0, 0, 1, 1], [1, 1, 0, 0], [-1, 1, 0, 0]])
    B = 1e3 * np.array([[1.0, 0.2], [0.5, -1.0], [0.3, 0.1], [-0.7, 0.4]])
    C = np.array([[0.24, -0.14, 0.24, -0.14]])
    exact = exact_h2(A, B, C, dt)
    assert h2_norm(A, B, C, dt) == pytest.approx(exact, rel=1e-4)
    assert h2_parts(A, B, C, dt, gradient=False)[0] == pytest.approx(
        exact, rel=1e-4)


@pytest.mark.parametrize('dt', [0, 1])
def test_h2_where_slycot_raises(dt, monkeypatch):
    """Without SB03OD's factor the H2 norm comes from the Gramian's
    solvers: the same value on a well-conditioned system."""
    import controlext.synthesis.criteria as criteria

    def broken(*args, **kwargs):
        raise RuntimeError('SB03OD failed')
    A = np.array([[0.5, 0.2], [-0.1, 0.3]]) if dt else \
        np.array([[-1.0, 2.0], [-0.5, -3.0]])
    B, C = np.array([[1.0], [0.5]]), np.array([[1.0, -2.0]])
    exact = exact_h2(A, B, C, dt)
    monkeypatch.setattr(criteria, '_sb03od', broken)
    assert criteria.gramian_factor(A, B, dt) is None
    assert h2_norm(A, B, C, dt) == pytest.approx(exact, rel=1e-12)
    assert h2_parts(A, B, C, dt)[0] == pytest.approx(exact, rel=1e-12)


def test_h2_gradient_from_the_factors():
    """The gradient of the H2 norm (from the Gramians' Cholesky factors)
    against central differences, continuous and discrete."""
    rng = np.random.default_rng(3)
    for dt in (0, 1):
        A = rng.normal(size=(4, 4))
        if dt:
            A *= 0.8 / np.max(np.abs(np.linalg.eigvals(A)))
        else:
            A -= (np.max(np.linalg.eigvals(A).real) + 0.5) * np.eye(4)
        B, C = rng.normal(size=(4, 2)), rng.normal(size=(3, 4))
        h, dA, dB = h2_parts(A, B, C, dt)
        E = rng.normal(size=(4, 4))
        F = rng.normal(size=(4, 2))
        step = 1e-6
        diff = (h2_norm(A + step * E, B + step * F, C, dt) -
                h2_norm(A - step * E, B - step * F, C, dt)) / (2 * step)
        assert np.sum(dA * E) + np.sum(dB * F) == pytest.approx(diff,
                                                               rel=1e-6)


def test_sweep_of_max_hinf_holds_every_bound():
    noise = dict(Bw=BW, Dw=DW, decay=1.0, objective='h2')
    s = cx.sweep(PLANT, 'max_hinf', [0.76, 0.85], **noise)
    assert np.all(s.metric('hinf') <= np.array([0.76, 0.85]) * (1 + 1e-6))
    # a looser bound never costs white-noise error
    assert s.metric('h2')[1] <= s.metric('h2')[0] * (1 + 1e-6)


def test_bound_the_mixed_lmi_cannot_certify_is_still_met():
    """A nearly unobservable mode: the mixed LMI (one Lyapunov matrix for
    both norms and the region) is infeasible at max_hinf = 1.05 γ of the
    H∞ design, yet that design meets the bound, so a design exists; the
    result keeps the bound and the region (ct.norm, poles) and has a
    smaller H2 norm than the H∞ design."""
    plant = ct.ss([[-1.0, 0.0], [0.0, 0.5]], [[1.0], [1.0]], [[1.0, 1e-4]],
                  0)
    noise = dict(Bw=[[1.0, 0.0], [1.0, 0.0]], Dw=[[0.0, 1.0]], decay=1.0)
    base = _quiet(cx.hinf_observer, plant, **noise)
    h2_base, hinf_base = _norms(base)
    obs = _quiet(cx.hinf_observer, plant, objective='h2',
                 max_hinf=1.05 * hinf_base, **noise)
    h2, hinf = _norms(obs)
    assert hinf <= 1.05 * hinf_base * (1 + 1e-6)
    assert max(np.linalg.eigvals(obs.A).real) <= -1 + 1e-6
    assert h2 < h2_base
