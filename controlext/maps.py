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

from dataclasses import dataclass

import numpy as np

__all__ = ['DesignMap', 'design_map']


@dataclass
class DesignMap:
    """Values of a design map; ``gamma[i, j]``, ``decay[i, j]`` belong to
    ``y[i]``, ``x[j]`` (image convention)."""
    x: np.ndarray
    y: np.ndarray
    gamma: np.ndarray
    decay: np.ndarray
    xentry: tuple
    yentry: tuple


def design_map(obs, xentry, xvalues, yentry, yvalues, method='auto',
               executor=None):
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
    from .exceptions import ArgumentError
    xv = np.asarray(xvalues, dtype=float).ravel()
    yv = np.asarray(yvalues, dtype=float).ravel()
    if method not in ('auto', 'closed', 'batched'):
        raise ArgumentError(f"method must be 'auto', 'closed' or 'batched'; "
                            f"found {method!r}")
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


def _map_block(args):
    return _map_values(*args)


def _map_values(prob, obs_G, xentry, xv, yentry, yv, method):
    from .exceptions import ArgumentError
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


def _sigma(A, B, C, z):
    """Largest singular value of C (zI − A)⁻¹ B for stacked A and z."""
    n = A.shape[-1]
    M = z[..., None, None] * np.eye(n) - A
    T = C @ np.linalg.solve(M, B)
    return np.linalg.svd(T, compute_uv=False)[..., 0]


def _batched(A, B, C, dt, num=400, iters=60):
    """Batched H∞ norm: common frequency grid, then golden section."""
    eig = np.linalg.eigvals(A)
    if dt:
        step = 1.0 if dt is True else float(dt)
        w = np.linspace(0, np.pi / step, num)
        zf = lambda om: np.exp(1j * om * step)
    else:
        mags = np.abs(eig[np.isfinite(eig)])
        lo = max(1e-4, 0.01 * np.min(mags[mags > 0])) if np.any(mags > 0) \
            else 1e-4
        hi = 100 * max(1.0, np.max(mags))
        w = np.concatenate([[0.0], np.logspace(np.log10(lo), np.log10(hi),
                                               num)])
        zf = lambda om: 1j * om
    shape = A.shape[:-2]
    Ab = A[..., None, :, :]
    Bb = B[..., None, :, :]
    vals = _sigma(Ab, Bb, C, np.broadcast_to(zf(w), shape + w.shape))
    k = np.argmax(vals, axis=-1)
    lo = w[np.maximum(k - 1, 0)]
    hi = w[np.minimum(k + 1, len(w) - 1)]
    best = np.take_along_axis(vals, k[..., None], -1)[..., 0]
    g = (np.sqrt(5) - 1) / 2
    x1, x2 = hi - g * (hi - lo), lo + g * (hi - lo)
    f1, f2 = _sigma(A, B, C, zf(x1)), _sigma(A, B, C, zf(x2))
    for _ in range(iters):
        left = f1 > f2
        hi = np.where(left, x2, hi)
        lo = np.where(left, lo, x1)
        x2n = np.where(left, x1, lo + g * (hi - lo))
        x1n = np.where(left, hi - g * (hi - lo), x2)
        f1n = np.where(left, _sigma(A, B, C, zf(x1n)), f2)
        f2n = np.where(left, f1, _sigma(A, B, C, zf(x2n)))
        x1, x2, f1, f2 = x1n, x2n, f1n, f2n
    return np.maximum(best, np.maximum(f1, f2))
