"""Design maps: H∞ norm and decay rate over a grid of two gain entries.

The maps of Figures 3–4 of Li & Sanfelice vary two entries of a gain
(``ℓ1``, ``ℓ2`` of the coupled pair) and show the H∞ norm and the rate of
convergence of the error system.  :func:`design_map` evaluates the whole
grid at once: the error matrices of every grid point are stacked, their
eigenvalues computed in one batched call, and the H∞ norm is

* exact in closed form for single-input single-output systems of order
  ``<= 2``: with ``x = ω²``, ``|T(jω)|² = (b₁² x + b₀²) / ((a₀ − x)² + a₁² x)``
  peaks at ``x = 0`` or at the root of ``b₁² x² + 2 b₀² x − (b₁² a₀² −
  b₀² (a₁² − 2 a₀)) = 0``;
* otherwise batched: singular values on a common logarithmic frequency
  grid for all points at once, then a vectorised golden-section search
  around each point's peak (accurate for peaks wider than the grid step).

Unstable points get ``γ = inf``.

Examples
--------
>>> import numpy as np
>>> import control as ct
>>> import controlext as cx
>>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
>>> pair = cx.CoupledObserver.from_pair(plant, 2.0, 2.0, 0.0, 0.0)
>>> m = cx.design_map(pair, (0, 1), [0.0, 1.0], (1, 0), [0.0, -1.0])
>>> round(float(m.gamma[0, 0]), 4), round(float(m.decay[0, 0]), 4)
(0.8, 2.5)
"""

from __future__ import annotations

from typing import TYPE_CHECKING
from dataclasses import dataclass

import numpy as np

from ._checks import as_array, check_choice, check_finite
from .exceptions import ArgumentError, DimensionError
from ._typing import ArrayLike, ExecutorLike

if TYPE_CHECKING:
    from .observers import Observer

__all__ = ['DesignMap', 'design_map']


@dataclass
class DesignMap:
    """Values of a design map; ``gamma[i, j]``, ``decay[i, j]`` belong to
    ``y[i]``, ``x[j]`` (image convention).

    Attributes
    ----------
    x, y : ndarray
        The values of the two gain entries.
    gamma, decay : ndarray
        γ and the decay rate over the grid.
    xentry, yentry : tuple
        The gain entries that were varied.
    """
    x: np.ndarray
    y: np.ndarray
    gamma: np.ndarray
    decay: np.ndarray
    xentry: tuple
    yentry: tuple


def design_map(obs: Observer, xentry: tuple[int, ...], xvalues: ArrayLike,
               yentry: tuple[int, ...], yvalues: ArrayLike,
               method: str = 'auto',
               executor: ExecutorLike = None) -> DesignMap:
    """H∞ norm and decay rate over a grid of two gain entries.

    Parameters
    ----------
    obs : Observer
        Base design: its gain ``obs.G`` gives the entries not varied.
    xentry, yentry : (int, int)
        Indices ``(row, column)`` of the gain entries to vary.
    xvalues, yvalues : array_like
        Values of those entries.
    method : {'auto', 'closed', 'batched'}
        ``'closed'`` needs a SISO error system of order ``<= 2``.
    executor : concurrent.futures.Executor, optional
        Splits the grid into row blocks evaluated in parallel.

    Returns
    -------
    DesignMap

    Examples
    --------
    >>> import numpy as np
    >>> import control as ct
    >>> import controlext as cx
    >>> plant = ct.ss([[-0.5]], [[1.0]], [[1.0]], 0)
    >>> pair = cx.CoupledObserver.from_pair(plant, 2.0, 2.0, 0.0, 0.0)
    >>> ell = np.linspace(-6, 6, 200)
    >>> m = cx.design_map(pair, (0, 1), ell, (1, 0), ell)
    >>> m.gamma.shape
    (200, 200)
    """
    from .observers import Observer
    if not isinstance(obs, Observer):
        raise ArgumentError("design_map needs a controlext observer; found "
                            f"{type(obs).__name__}")
    xv = as_array(xvalues, 'xvalues').ravel()
    yv = as_array(yvalues, 'yvalues').ravel()
    for values, name in ((xv, 'xvalues'), (yv, 'yvalues')):
        if values.size == 0:
            raise DimensionError(f"{name} is empty; expected at least one "
                                 "value")
        check_finite(values, name)
    for entry, name in ((xentry, 'xentry'), (yentry, 'yentry')):
        _check_entry(entry, name, obs.problem.gain_shape)
    check_choice(method, 'method', ('auto', 'closed', 'batched'))
    if executor is not None and len(yv) > 1:
        blocks = np.array_split(yv, min(len(yv), 8))
        parts = list(executor.map(_map_block, [
            (obs.problem, obs.G, xentry, xv, yentry, b, method)
            for b in blocks if b.size]))
        return DesignMap(xv, yv, np.vstack([g for g, _ in parts]),
                         np.vstack([d for _, d in parts]), tuple(xentry),
                         tuple(yentry))
    gamma, decay = _map_values(obs.problem, obs.G, xentry, xv, yentry, yv,
                               method)
    return DesignMap(xv, yv, gamma, decay, tuple(xentry), tuple(yentry))


def _check_entry(entry, name, shape):
    """A (row, column) index into the gain."""
    if not (isinstance(entry, (tuple, list)) and len(entry) == 2 and
            all(isinstance(i, (int, np.integer)) and not isinstance(i, bool)
                for i in entry)):
        raise ArgumentError(f"{name} must be a (row, column) pair of "
                            f"integers; found {entry!r}")
    for i, size, what in zip(entry, shape, ('row', 'column')):
        if not 0 <= i < size:
            raise DimensionError(f"{name} {what} {i} is outside the gain of "
                                 f"shape {shape}")


def _map_block(args):
    return _map_values(*args)


def _map_values(prob, obs_G, xentry, xv, yentry, yv, method):
    G = np.broadcast_to(obs_G, (len(yv), len(xv)) + obs_G.shape).copy()
    G[:, :, xentry[0], xentry[1]] = xv[None, :]
    G[:, :, yentry[0], yentry[1]] = yv[:, None]
    Acl = prob.Ae - G @ prob.Ce
    Bcl = G @ prob.Dwe - prob.Bwe
    Ccl = prob.Cze
    eig = _eigvals(Acl)
    if prob.dt:
        step = 1.0 if prob.dt is True else float(prob.dt)
        rho = np.max(np.abs(eig), axis=-1)
        decay = -np.log(np.maximum(rho, 1e-300)) / step
        stable = rho < 1
    else:
        decay = -np.max(eig.real, axis=-1)
        stable = decay > 0
    siso = Ccl.shape[0] == 1 and Bcl.shape[-1] == 1 and Acl.shape[-1] <= 2
    if method == 'closed' and not (siso and not prob.dt):
        raise ArgumentError("method='closed' needs a continuous SISO error "
                            "system of order <= 2")
    if siso and not prob.dt and method != 'batched':
        gamma = _closed_form(Acl, Bcl, Ccl)
    else:
        gamma = _batched(Acl, Bcl, Ccl, prob.dt)
    return np.where(stable, gamma, np.inf), decay


def _eigvals(A):
    """Eigenvalues of stacked matrices (closed form for 1 × 1, 2 × 2)."""
    n = A.shape[-1]
    if n == 1:
        return A[..., 0].astype(complex)
    if n == 2:
        half = 0.5 * (A[..., 0, 0] + A[..., 1, 1])
        det = A[..., 0, 0] * A[..., 1, 1] - A[..., 0, 1] * A[..., 1, 0]
        root = np.sqrt((half**2 - det).astype(complex))
        return np.stack([half + root, half - root], axis=-1)
    return np.linalg.eigvals(A)


def _closed_form(A, B, C):
    """Exact H∞ norm of stacked SISO systems of order 1 or 2."""
    n = A.shape[-1]
    c = np.broadcast_to(C, A.shape[:-2] + C.shape)
    if n == 1:
        a = A[..., 0, 0]
        return np.abs(c[..., 0, 0] * B[..., 0, 0] / a)
    # T(s) = (b1 s + b0) / (s^2 + a1 s + a0)
    a1 = -(A[..., 0, 0] + A[..., 1, 1])
    a0 = A[..., 0, 0] * A[..., 1, 1] - A[..., 0, 1] * A[..., 1, 0]
    cb = (c @ B)[..., 0, 0]
    cab = (c @ A @ B)[..., 0, 0]
    b1 = cb
    b0 = cab + a1 * cb          # numerator of C adj(sI - A) B
    f = lambda x: (b1**2 * x + b0**2) / ((a0 - x)**2 + a1**2 * x)
    best = f(np.zeros_like(a0))
    qa, qb = b1**2, 2 * b0**2
    qc = -(b1**2 * a0**2 - b0**2 * (a1**2 - 2 * a0))
    with np.errstate(divide='ignore', invalid='ignore'):
        disc = np.sqrt(np.maximum(qb**2 - 4 * qa * qc, 0.0))
        for root in ((-qb + disc) / (2 * qa), (-qb - disc) / (2 * qa)):
            ok = np.isfinite(root) & (root > 0)
            val = np.where(ok, f(np.where(ok, root, 0.0)), 0.0)
            best = np.maximum(best, val)
        lin = np.where(qa == 0, -qc / qb, -1.0)       # b1 = 0: linear
        ok = np.isfinite(lin) & (lin > 0)
        best = np.maximum(best, np.where(ok, f(np.where(ok, lin, 0.0)),
                                         0.0))
    return np.sqrt(best)


def _sigma_max(T):
    """Largest singular value of stacked matrices (closed form when the
    smaller dimension is 1 or 2)."""
    if T.shape[-1] == 1 or T.shape[-2] == 1:
        return np.sqrt(np.sum(np.abs(T)**2, axis=(-2, -1)))
    if min(T.shape[-2:]) == 2:
        if T.shape[-1] != 2:
            T = np.swapaxes(T, -1, -2)
        a = np.sum(np.abs(T[..., 0])**2, axis=-1)
        d = np.sum(np.abs(T[..., 1])**2, axis=-1)
        b = np.sum(T[..., 0].conj() * T[..., 1], axis=-1)
        return np.sqrt(0.5 * (a + d) + np.sqrt(0.25 * (a - d)**2 +
                                               np.abs(b)**2))
    return np.linalg.svd(T, compute_uv=False)[..., 0]


def _batched(A, B, C, dt, num=64, iters=32):
    """Batched H∞ norm of stacked stable systems.

    Each point's matrix is diagonalised once, ``A = V Λ V⁻¹``, so
    ``T(z) = Σ_k (C v_k)(w_kᵀ B) / (z − λ_k)`` costs a weighted sum per
    frequency.  The peak is bracketed on a common grid (log-spaced,
    refined around every point's resonances ``|Im λ|``) and located by a
    vectorised golden-section search.  Points whose eigenvector matrix is
    ill-conditioned (nearly defective) use linear solves instead.
    """
    lam, V = np.linalg.eig(A)
    cond = np.linalg.cond(V)
    good = np.isfinite(cond) & (cond < 1e8)
    Vi = np.zeros_like(V)
    Vi[good] = np.linalg.inv(V[good])
    CV = C @ V                                   # (..., p, n)
    VB = Vi @ B                                  # (..., n, m)
    if dt:
        step = 1.0 if dt is True else float(dt)
        zf = lambda om: np.exp(1j * om * step)
        w = np.linspace(0, np.pi / step, 4 * num)
    else:
        zf = lambda om: 1j * om
        mags = np.abs(lam[good & np.all(np.isfinite(lam), axis=-1)])
        pos = mags[mags > 0]
        lo = 1e-3 * np.min(pos) if pos.size else 1e-4
        hi = 1e2 * max(1.0, np.max(pos) if pos.size else 1.0)
        w = np.concatenate([[0.0], np.logspace(np.log10(lo), np.log10(hi),
                                                num)])

    def sigma(om):
        """σmax at frequencies om (shape (..., F)) for every point."""
        z = zf(om)
        d = 1.0 / (z[..., :, None] - lam[..., None, :])     # (..., F, n)
        T = (CV[..., None, :, :] * d[..., :, None, :]) @ VB[..., None, :, :]
        val = _sigma_max(T)
        if not np.all(good):                    # nearly defective points
            bad = ~good
            M = z[bad][..., None, None] * np.eye(A.shape[-1]) - \
                A[bad][..., None, :, :]
            Tb = C @ np.linalg.solve(M, B[bad][..., None, :, :])
            val[bad] = np.linalg.svd(Tb, compute_uv=False)[..., 0]
        return val.real

    shape = A.shape[:-2]
    grid = np.broadcast_to(w, shape + w.shape)
    if not dt:                                  # add each point's resonances
        res = np.abs(lam.imag)
        grid = np.concatenate([grid] + [f * res for f in
                                        (0.8, 0.9, 0.95, 1.0, 1.05, 1.1,
                                         1.25)] + [np.abs(lam)], axis=-1)
    grid = np.sort(grid, axis=-1)
    vals = sigma(grid)
    k = np.argmax(vals, axis=-1)
    best = np.take_along_axis(vals, k[..., None], -1)[..., 0]
    # bracket with the nearest *distinct* grid values (a conjugate pair
    # puts each resonance into the grid twice)
    wk = np.take_along_axis(grid, k[..., None], -1)
    lo = np.max(np.where(grid < wk, grid, -np.inf), axis=-1)
    hi = np.min(np.where(grid > wk, grid, np.inf), axis=-1)
    lo = np.where(np.isfinite(lo), lo, wk[..., 0])
    hi = np.where(np.isfinite(hi), hi, wk[..., 0])
    g = (np.sqrt(5) - 1) / 2
    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = sigma(x1[..., None])[..., 0], sigma(x2[..., None])[..., 0]
    for _ in range(iters):
        left = f1 > f2
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        x1n = np.where(left, hi - g * (hi - lo), x2)
        x2n = np.where(left, x1, lo + g * (hi - lo))
        new = sigma(np.where(left, x1n, x2n)[..., None])[..., 0]
        f1n = np.where(left, new, f2)
        f2n = np.where(left, f1, new)
        x1, x2, f1, f2 = x1n, x2n, f1n, f2n
    return np.maximum(best, np.maximum(f1, f2))
