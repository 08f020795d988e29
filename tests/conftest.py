"""Named plants shared by the tests."""

import os

# one BLAS thread per test process: the suite runs one process per core
# (pytest-xdist), and OpenBLAS threads waiting beside the other process
# cost more than they save on these small matrices
for _name in ('OPENBLAS_NUM_THREADS', 'OMP_NUM_THREADS', 'MKL_NUM_THREADS'):
    os.environ.setdefault(_name, '1')

import numpy as np  # noqa: E402
import pytest
import control as ct

os.environ.setdefault('MPLBACKEND', 'Agg')


@pytest.fixture
def scalar_plant():
    """Plant (4) of Li & Sanfelice with a = -0.5."""
    return ct.ss([[-0.5]], [[1.0]], [[1.0]], [[0.0]])


@pytest.fixture
def second_order_plant():
    """Second-order plant of Li & Sanfelice, Section IV-B."""
    return ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]],
                 [[0.0]])


def unstable_plant(seed=0, n=4, p=2, q=2):
    """Seeded random plant with an unstable mode (spectral abscissa 0.5)."""
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    A += (0.5 - np.max(np.linalg.eigvals(A).real)) * np.eye(n)
    B = rng.normal(size=(n, 1))
    C = rng.normal(size=(p, n))
    Bw = rng.normal(size=(n, q))
    return ct.ss(A, B, C, np.zeros((p, 1))), Bw


def error_system(plant, G, copies=1, weights=None, Bw=None, Dw=None,
                 Cz=None):
    """The coupled error system rebuilt by hand from the plant and a gain
    (the paper's (17)/(28) for two copies), independent of the package's
    problem description."""
    A, C = np.asarray(plant.A, float), np.asarray(plant.C, float)
    n, p = A.shape[0], C.shape[0]
    Bw = np.zeros((n, p)) if Bw is None else np.asarray(Bw, float)
    Dw = np.eye(p) if Dw is None else np.asarray(Dw, float)
    Cz = np.eye(n) if Cz is None else np.asarray(Cz, float)
    c = np.full(copies, 1 / copies) if weights is None else \
        np.asarray(weights, float)
    Acl = np.zeros((copies * n, copies * n))
    Bcl = np.zeros((copies * n, Bw.shape[1]))
    for i in range(copies):
        rows = slice(i * n, (i + 1) * n)
        Acl[rows, rows] = A
        Bcl[rows] = -Bw
        for j in range(copies):
            Gij = G[rows, j * p:(j + 1) * p]
            Acl[rows, j * n:(j + 1) * n] -= Gij @ C
            Bcl[rows] += Gij @ Dw
    Ccl = np.hstack([ci * Cz for ci in c])
    return Acl, Bcl, Ccl


def grid_hinf(A, B, C, dt=0, points=4000):
    """H∞ norm by a dense logarithmic frequency grid refined at the peak
    (golden section): no slycot, no Hamiltonian; ``inf`` if unstable."""
    from scipy.optimize import minimize_scalar
    lam = np.linalg.eigvals(A)
    if (np.max(np.abs(lam)) >= 1) if dt else (np.max(lam.real) >= 0):
        return np.inf
    n = A.shape[0]
    step = 1.0 if dt is True else float(dt or 1.0)

    def gain(w):
        s = np.exp(1j * w * step) if dt else 1j * w
        return np.linalg.svd(C @ np.linalg.solve(s * np.eye(n) - A, B),
                             compute_uv=False)[0]

    top = np.pi / step if dt else 1e3 * max(1.0, np.max(np.abs(lam)))
    w = np.concatenate([[0.0], np.logspace(-4, np.log10(top), points)])
    vals = np.array([gain(x) for x in w])
    k = int(np.argmax(vals))
    lo, hi = w[max(k - 1, 0)], w[min(k + 1, len(w) - 1)]
    best = minimize_scalar(lambda x: -gain(x), bounds=(lo, hi),
                           method='bounded', options={'xatol': 1e-12})
    return max(vals[k], -best.fun)


def rounded(G, digits=6):
    return np.vectorize(lambda x: float(f"{x:.{digits - 1}e}"))(G)


def worst_pole(obs, G):
    """The slowest error pole's real part (continuous time) or modulus
    (discrete time) of gain ``G``, from the problem's matrices."""
    p = obs.problem
    eigs = np.linalg.eigvals(p.Ae - G @ p.Ce)
    return float(np.max(np.abs(eigs) if p.dt else eigs.real))


def keeps(obs, edge, seed=0, draws=200):
    """6-digit rounding and ``draws`` random relative errors of 1e-6 in
    every entry keep the slowest pole inside ``edge``."""
    G = obs.G
    assert worst_pole(obs, rounded(G)) <= edge
    rng = np.random.default_rng(seed)
    worst = max(worst_pole(obs, G * (1 + 1e-6 * rng.uniform(-1, 1, G.shape)))
                for _ in range(draws))
    assert worst <= edge
