"""Named plants shared by the tests."""

import os

import numpy as np
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
