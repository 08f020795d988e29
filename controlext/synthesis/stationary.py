"""The stationarity test of a refined gain, as gradient sampling ends.

The norms refinement minimises are not differentiable at their optima
(two peaks of the H∞ norm equal, poles on a region's edge), so a small
gradient never says that a point is optimal.  Gradient sampling
(Burke, Lewis & Overton) and HANSO stop instead when the convex hull of
the gradients at points near ``x`` holds a short vector: the minimum-norm
element ``d`` of ``conv{∇f(x_i) : ‖x_i − x‖ <= ε}`` approximates the
shortest element of the Clarke ε-subdifferential, and ``‖d‖`` small means
that no direction decreases ``f`` by much within ``ε``.

:func:`stationarity` samples gradients of the minimised norm at ``x``
and at points in a ball of radius ``ε = RADIUS · max(1, ‖x‖)`` around
it, adds the gradients of the constraints active at ``x`` (the region's
margins of the poles on its edges, a bound at its limit) with any
nonnegative weight — the Clarke stationarity of a constrained problem,
as the exact penalty has it above the multipliers — finds ``d`` by a
nonnegative least-squares solve, and measures it relative to the norm:
``‖d‖ · ε / |f|`` is the relative decrease that the best direction buys
over the ball.  The point passes when that is at most ``TOL``.

Examples
--------
>>> import numpy as np
>>> from controlext.synthesis.stationary import min_norm_element
>>> # the point of the segment from (1, 0) to (-1, 1) nearest the origin
>>> d = min_norm_element(np.array([[1.0, 0.0], [-1.0, 1.0]]))
>>> np.round(d, 3).tolist()
[0.2, 0.4]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import lsq_linear

__all__ = ['Stationarity', 'stationarity', 'min_norm_element', 'ACTIVE']

#: sampling radius, relative to the gain's size
RADIUS = 1e-5
#: largest relative decrease over the ball for a stationary point: a
#: relative slope of 1e-2 (a 1 % change of the gain buys at most 0.01 %
#: of the norm)
TOL = 1e-7
#: a constraint is active when its margin is above ``−ACTIVE`` times the
#: poles' size
ACTIVE = 1e-5
#: most samples of the test (twice the gain's entries up to this)
SAMPLES = 60
#: most samples on error systems of more than ``LARGE`` states, where an
#: evaluation costs a tenth of a second or more: the first ones of the
#: full test's draws, so such a point passes only if the full test would
#: pass it (a 120-state pair under a gain tolerance: 61 samples took 40 s)
LARGE_SAMPLES, LARGE = 12, 64


@dataclass
class Stationarity:
    """The outcome of :func:`stationarity`.

    Attributes
    ----------
    passed : bool
        Is the point stationary to :data:`TOL`?
    measure : float
        ``‖d‖ ε / |f|``: the relative decrease of the objective the best
        direction buys over the sampling ball.
    samples : int
        Gradients sampled.
    """
    passed: bool
    measure: float
    samples: int


def min_norm_element(grads: np.ndarray, cone: np.ndarray | None = None
                     ) -> np.ndarray:
    """The shortest vector ``Σ λ_i g_i + Σ μ_j c_j`` with the ``g_i`` the
    rows of ``grads`` in a convex combination (``λ >= 0``, ``Σ λ = 1``)
    and the ``c_j`` the rows of ``cone`` with any weights ``μ >= 0``
    (bounded least squares, the sum held at 1 by a heavy row)."""
    grads = np.asarray(grads, dtype=float)
    cone = np.zeros((0, grads.shape[1])) if cone is None else \
        np.asarray(cone, dtype=float)
    # a cone's rows may have any length (their weights are free): unit
    # rows keep the solve's scale that of the combined gradients
    lengths = np.linalg.norm(cone, axis=1)
    cone = cone[lengths > 0] / lengths[lengths > 0, None]
    rows = np.vstack([grads, cone])
    scale = max(float(np.max(np.abs(grads))), 1e-300)
    heavy = 1e3
    ones = np.concatenate([np.ones(len(grads)), np.zeros(len(cone))])
    M = np.vstack([rows.T / scale, heavy * ones])
    rhs = np.concatenate([np.zeros(grads.shape[1]), [heavy]])
    # bounded least squares by lstsq steps (scipy's nnls of 1.12-1.13
    # raised on singular and slow problems; this one gives the same
    # answer from the lower bounds to the newest)
    weights = lsq_linear(M, rhs, bounds=(0.0, np.inf), method='bvls').x
    weights = weights / max(float(np.sum(weights[:len(grads)])), 1e-300)
    return weights @ rows


def stationarity(obj, G, seed: int = 0, samples: int | None = None
                 ) -> Stationarity:
    """Gradient-sampling test of ``G`` on refinement's objective ``obj``
    (module text): the gradients of the minimised norm at ``G`` and at
    ``samples`` points in the ball around it (default ``2 · entries``, at
    most :data:`SAMPLES`, :data:`LARGE_SAMPLES` on error systems of more
    than :data:`LARGE` states), and those of the constraints active at
    ``G``
    and at the samples (``obj.active_gradients``), which enter with any
    nonnegative weight: at a constrained optimum the norm's descent is
    blocked by them."""
    x = np.asarray(G, dtype=float).ravel()
    count = samples
    if count is None:
        count = min(2 * x.size, SAMPLES if obj.Ae.shape[0] <= LARGE
                    else LARGE_SAMPLES)
    radius = RADIUS * max(1.0, float(np.linalg.norm(x)))
    rng = np.random.default_rng(seed)
    value, grad = obj.norm_gradient(x)
    if not np.isfinite(value):
        return Stationarity(False, float('inf'), 1)
    grads = [grad]
    active = obj.active_gradients(x.reshape(obj.shape))
    for _ in range(count):
        u = rng.normal(size=x.size)
        u *= radius * rng.random() ** (1 / x.size) / np.linalg.norm(u)
        fx, gx = obj.norm_gradient(x + u)
        if np.isfinite(fx):
            grads.append(gx)
        # a cluster of poles on an edge splits at the samples, where its
        # margins have the finite gradients they lack at x
        active += obj.active_gradients((x + u).reshape(obj.shape))
    d = min_norm_element(np.array(grads), np.array(active).reshape(
        len(active), x.size))
    measure = float(np.linalg.norm(d)) * radius / max(abs(value), 1e-300)
    return Stationarity(measure <= TOL, measure, len(grads))
