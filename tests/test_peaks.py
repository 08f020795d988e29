"""The modal peak search of large error systems against slycot's
``ab13dd`` (python-control's ``linfnorm``), a direct frequency response
and finite differences."""


import numpy as np
import pytest
import control as ct

import controlext as cx
from controlext.synthesis import ObserverProblem
from controlext.synthesis import peaks
from controlext.synthesis.objective import Objective, CHECK_EVERY

from plants import beam  # noqa: E402


def _flexible(seed, n=60, m=2, p=3):
    """Seeded stable system of ``n / 2`` lightly damped modes (damping
    1-10 %, 0.5-100 rad/s) in random coordinates: many peaks of similar
    height."""
    rng = np.random.default_rng(seed)
    blocks = []
    for w in np.sort(rng.uniform(0.5, 100.0, n // 2)):
        zeta = rng.uniform(0.01, 0.1)
        blocks.append([[-zeta * w, w], [-w, -zeta * w]])
    J = np.zeros((n, n))
    for k, block in enumerate(blocks):
        J[2 * k:2 * k + 2, 2 * k:2 * k + 2] = block
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    return Q @ J @ Q.T, rng.normal(size=(n, m)), rng.normal(size=(p, n))


def _gain(A, B, C, w):
    """``σmax(C (jw − A)⁻¹ B)`` by a direct solve."""
    T = C @ np.linalg.solve(1j * w * np.eye(A.shape[0]) - A, B)
    return np.linalg.svd(T, compute_uv=False)[0]


@pytest.mark.parametrize('m', [1, 2, 3])
def test_search_finds_the_norm(m):
    """On 30 seeded flexible systems the search returns a gain attained
    at its frequency (a lower bound of the norm), and the norm itself
    (ab13dd to 1e-9; also on seeds 0-199 for m = 1, 2, 3)."""
    missed = 0
    for seed in range(30):
        A, B, C = _flexible(seed, m=m)
        lam, V = np.linalg.eig(A)
        gamma, w = peaks.peak_search(lam, V, B, C)
        exact = ct.linfnorm(ct.ss(A, B, C, 0))[0]
        assert gamma == pytest.approx(_gain(A, B, C, w), rel=1e-9)
        assert gamma <= exact * (1 + 1e-9)
        missed += gamma < exact * (1 - 1e-9)
    assert missed == 0


def test_search_at_a_peak_of_zero_frequency():
    """A well-damped system whose largest gain is at ω = 0."""
    A = np.diag([-1.0, -2.0, -5.0])
    B = np.ones((3, 1))
    C = np.ones((1, 3))
    lam, V = np.linalg.eig(A)
    gamma, w = peaks.peak_search(lam, V, B, C)
    assert w == 0.0
    assert gamma == pytest.approx(1 + 1 / 2 + 1 / 5, rel=1e-12)


@pytest.mark.parametrize('m', [1, 3])
def test_slopes_match_finite_differences(m):
    """The first two derivatives of ``σmax(T(jω))²`` in ω, the second
    with the singular vector's own motion, against central differences
    (at a frequency where the top singular value is simple)."""
    A, B, C = _flexible(3, n=20, m=m)
    lam, V = np.linalg.eig(A)
    Bm, Cm = np.linalg.solve(V, B.astype(complex)), C @ V
    w0, h = 7.3, 1e-4
    f = lambda w: _gain(A, B, C, w) ** 2
    value, d1, d2 = peaks._slopes(Cm, Bm, lam, np.array([w0]))
    assert value[0] == pytest.approx(f(w0), rel=1e-9)
    assert d1[0] == pytest.approx((f(w0 + h) - f(w0 - h)) / (2 * h),
                                  rel=1e-5)
    assert d2[0] == pytest.approx(
        (f(w0 + h) - 2 * f(w0) + f(w0 - h)) / h ** 2, rel=1e-3)


def test_objective_of_a_large_system_is_its_norm():
    """The refinement objective of the beam pair's 80-state error system
    (modal search, ab13dd every few evaluations) equals ab13dd's norm
    at random gains near the convex design, and ``norm()`` is always
    ab13dd's value."""
    plant, Cz = beam()
    obs = cx.coupled_observer(plant, decay=0.5, Cz=Cz, refine=False)
    prob = obs.problem
    G0 = np.asarray(obs.G, dtype=float).reshape(prob.gain_shape)
    assert prob.Ae.shape[0] > peaks.STATES
    f = Objective(prob, None)
    assert f.modal
    rng = np.random.default_rng(0)
    missed = 0
    for k in range(40):
        G = G0 * (1 + 0.05 * rng.normal(size=G0.shape))
        value, _ = f(G.ravel(), grad=False)
        exact = ct.linfnorm(ct.ss(*prob.error_system(G)))[0]
        assert value <= exact * (1 + 1e-9)
        missed += value < exact * (1 - 1e-9)
        assert f.norm(G) == pytest.approx(exact, rel=1e-9)
    assert missed == 0
    assert f._searches == 40 and f.modal     # no check found a miss


def test_discrete_and_small_systems_keep_ab13dd():
    prob = ObserverProblem(A=[[0.9, 0.1], [-0.1, 0.95]], C=[[1.0, 2.0]],
                           dt=0.1)
    assert not Objective(prob, None).modal
    small = ObserverProblem(A=[[-1.0, 1.0], [-1.0, 0.0]], C=[[1.0, 2.0]],
                            copies=2)
    assert not Objective(small, None).modal


def test_a_check_that_finds_a_missed_peak_ends_the_search(monkeypatch):
    """Should the search miss a peak (here: forced to report half the
    gain), the first ab13dd check sees it and the objective uses ab13dd
    alone from then on."""
    A, _, C = _flexible(5, n=70, p=2)
    prob = ObserverProblem(A=A, C=C)
    f = Objective(prob, None)
    assert f.modal
    true = peaks.peak_search
    monkeypatch.setattr(peaks, 'peak_search', lambda *a, **k: (
        0.5 * true(*a, **k)[0], true(*a, **k)[1]))
    rng = np.random.default_rng(1)
    for _ in range(CHECK_EVERY + 5):
        G = 1e-3 * rng.normal(size=prob.gain_shape)
        value, _ = f(G.ravel(), grad=False)
    assert not f.modal
    exact = ct.linfnorm(ct.ss(*prob.error_system(G)))[0]
    assert value == pytest.approx(exact, rel=1e-9)
