"""The modal convex stage: the Schur split, the exactness of the reduced
noise-to-error system, and when ``method='auto'`` takes it."""

import numpy as np
import pytest
import control as ct

import controlext as cx
from controlext.synthesis.modal import modal_applies, modal_problem, modal_split
from controlext.norms import hinfnorm_matrices
from controlext.synthesis import ObserverProblem


def plant(seed=0, n=8, p=2):
    """Two unstable, two slow and n - 4 fast modes in a random basis."""
    rng = np.random.default_rng(seed)
    re = np.concatenate([[0.4, 0.1, -0.3, -0.6],
                         rng.uniform(-5.0, -2.0, n - 4)])
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    A = Q @ np.diag(re) @ Q.T
    return ct.ss(A, np.zeros((n, 1)), rng.normal(size=(p, n)),
                 np.zeros((p, 1))), re


def test_split_orders_the_slow_modes_first():
    P, re = plant()
    U, k = modal_split(P.A, cx.HalfPlane(1.0))
    np.testing.assert_allclose(U.T @ U, np.eye(8), atol=1e-12)
    assert k == 4                      # Re λ > -1 (and none near it)
    T = U.T @ P.A @ U
    np.testing.assert_allclose(T[k:, :k], 0, atol=1e-10)
    slow = np.sort(np.linalg.eigvals(T[:k, :k]).real)
    np.testing.assert_allclose(slow, np.sort(re[:4]), atol=1e-10)


@pytest.mark.filterwarnings('ignore::controlext.GainWarning')   # convex only
@pytest.mark.parametrize('seed', [0, 1, 2])
def test_reduced_error_system_is_exact_without_process_noise(seed):
    """For L = U₁ L₁ and Bw = 0 the full error system's H∞ norm (slycot,
    n states) equals the k-state one's, and its poles are those of
    T11 − L₁ C U₁ together with the untouched fast modes."""
    P, re = plant(seed)
    prob = ObserverProblem(P.A, P.C)
    U, k = modal_split(prob.A, cx.HalfPlane(1.0))
    sub = modal_problem(prob, U, k)
    L1 = cx.hinf_observer(ct.ss(sub.A, np.zeros((k, 1)), sub.C, 0),
                          Cz=sub.Cz, decay=1.0, refine=False).L
    full = hinfnorm_matrices(*prob.error_system(U[:, :k] @ L1))[0]
    reduced = hinfnorm_matrices(*sub.error_system(L1))[0]
    assert full == pytest.approx(reduced, rel=1e-8)
    poles = np.linalg.eigvals(prob.A - U[:, :k] @ L1 @ prob.C)
    expect = np.concatenate([np.linalg.eigvals(sub.A - L1 @ sub.C), re[4:]])
    np.testing.assert_allclose(np.sort_complex(poles),
                               np.sort_complex(expect), atol=1e-8)


def test_auto_takes_the_modal_stage_and_certifies_it():
    P, _ = plant()
    obs = cx.hinf_observer(P, decay=1.0, refine=False)
    assert obs.report.method == 'modal lmi'
    assert obs.report.stats['modal']['slow_states'] == 4
    assert max(ct.poles(obs).real) <= -1.0 + 1e-6
    assert cx.hinfnorm(obs)[0] <= obs.report.gamma_bound * (1 + 1e-5)
    pair = cx.coupled_observer(P, decay=1.0, refine=False)
    assert pair.report.method == 'embedded modal lmi'
    np.testing.assert_allclose(pair.K1, obs.L)
    refined = cx.hinf_observer(P, decay=1.0)
    assert refined.report.method == 'modal lmi+refine'
    assert refined.hinf <= obs.hinf * (1 + 1e-9)


def test_modal_stage_not_taken_where_it_does_not_apply():
    P, _ = plant()
    prob = ObserverProblem(P.A, P.C)
    assert modal_applies(prob, None, 40) is None            # no region
    assert modal_applies(prob, cx.HalfPlane(6.0), 40) is None   # all slow
    assert modal_applies(prob, cx.HalfPlane(1.0), 3) is None    # too many
    Bw = np.hstack([np.ones((8, 1)), np.zeros((8, 2))])
    Dw = np.hstack([np.zeros((2, 1)), np.eye(2)])
    noisy = ObserverProblem(P.A, P.C, Bw=Bw, Dw=Dw)
    assert modal_applies(noisy, cx.HalfPlane(1.0), 40) is None  # Bw leaks
    with pytest.raises(cx.ArgumentError, match="method='modal' needs"):
        cx.hinf_observer(P, decay=6.0, method='modal')
    obs = cx.hinf_observer(P, decay=1.0, Bw=Bw, Dw=Dw, refine=False)
    assert obs.report.method == 'lmi'
