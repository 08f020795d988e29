"""Coupled-pair synthesis at scale against the straightforward LMI.

Baseline (measured in the same run): Theorem 3.10 as written — one
common Lyapunov matrix of size 2n, cvxpy + clarabel, one stage, gain
X⁻¹Y.  Against it: controlext's convex stage (``refine=False``) and its
default refined design.  Seeded random plants with unstable modes,
p = 2 outputs, decay σ = 1.

    python benchmarks/synthesis_scaling.py [n ...]     (default 5 10 20 30)
"""

import sys
import time
import warnings

import numpy as np
import cvxpy as cp
import control as ct

import controlext as cx

SIGMA = 1.0


def plant(n, seed=0, p=2):
    """Two unstable modes (0.5, 0.2), the others with real parts in
    [-4, -1.2]; a quarter of the modes in complex pairs; a random
    orthogonal similarity."""
    rng = np.random.default_rng(seed)
    J = np.zeros((n, n))
    re = np.sort(rng.uniform(-4.0, -1.2, n))[::-1]
    re[:2] = [0.5, 0.2]
    k = 0
    while k < n:
        if k + 1 < n and k % 4 == 0:
            w = rng.uniform(0.5, 3.0)
            J[k:k + 2, k:k + 2] = [[re[k], w], [-w, re[k]]]
            k += 2
        else:
            J[k, k] = re[k]
            k += 1
    Q, _ = np.linalg.qr(rng.normal(size=(n, n)))
    A = Q @ J @ Q.T
    return ct.ss(A, rng.normal(size=(n, 1)), rng.normal(size=(p, n)),
                 np.zeros((p, 1)))


def straightforward_lmi(P):
    """Theorem 3.10 with a common Lyapunov matrix (the baseline)."""
    A, C = np.asarray(P.A), np.asarray(P.C)
    n, p = A.shape[0], C.shape[0]
    Ae, Ce = np.kron(np.eye(2), A), np.kron(np.eye(2), C)
    De = np.kron(np.ones((2, 1)), np.eye(p))
    Cinf = np.kron(np.ones((1, 2)) / 2, np.eye(n))
    X = cp.Variable((2 * n, 2 * n), symmetric=True)
    Y = cp.Variable((2 * n, 2 * p))
    g = cp.Variable()
    Z = X @ Ae - Y @ Ce
    brl = cp.bmat([[Z + Z.T, Y @ De, Cinf.T],
                   [(Y @ De).T, -g * np.eye(p), np.zeros((p, n))],
                   [Cinf, np.zeros((n, p)), -g * np.eye(n)]])
    cons = [X >> 1e-8 * np.eye(2 * n), Z + Z.T + 2 * SIGMA * X << 0,
            0.5 * (brl + brl.T) << -1e-9 * np.eye(2 * n + p + n)]
    prob = cp.Problem(cp.Minimize(g), cons)
    try:
        prob.solve(solver=cp.CLARABEL)
    except cp.error.SolverError:
        return np.inf, False, 'solver_error'
    if X.value is None:
        return np.inf, False, prob.status
    G = np.linalg.solve(X.value, Y.value)
    obs = cx.CoupledObserver(P, G)
    holds = np.max(ct.poles(obs).real) <= -SIGMA + 1e-6
    return obs.hinf, holds, prob.status


def timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def main(sizes):
    print(f"{'n':>3} | {'base s':>7} {'base γ':>9} {'ok':>3} {'status':>18} |"
          f" {'convex s':>8} {'ratio':>6} {'γ':>9} {'γ/base':>7} |"
          f" {'refined s':>9} {'γ':>9} {'γ/base':>7} {'ok':>3}")
    for n in sizes:
        P = plant(n)
        tb, (gb, okb, status) = timed(lambda: straightforward_lmi(P))
        tc, conv = timed(lambda: cx.coupled_observer(P, decay=SIGMA,
                                                     refine=False))
        tr, ref = timed(lambda: cx.coupled_observer(P, decay=SIGMA))
        okr = np.max(ct.poles(ref).real) <= -SIGMA + 1e-6
        print(f"{n:>3} | {tb:>7.2f} {gb:>9.4g} {'y' if okb else 'n':>3} "
              f"{status:>18} | {tc:>8.2f} {tb / tc:>6.1f} {conv.hinf:>9.4g} "
              f"{conv.hinf / gb:>7.3f} | {tr:>9.2f} {ref.hinf:>9.4g} "
              f"{ref.hinf / gb:>7.3f} {'y' if okr else 'n':>3}", flush=True)


if __name__ == '__main__':
    warnings.simplefilter('ignore', UserWarning)
    main([int(a) for a in sys.argv[1:]] or [5, 10, 20, 30])
