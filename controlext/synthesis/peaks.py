"""The H∞ norm of a large error system from its eigendecomposition.

Refinement evaluates the error system at thousands of gains, and each
evaluation already decomposes the error matrix ``A = V Λ V⁻¹`` (for the
region margins).  In that modal form the frequency response

    T(jω) = (C V) (jω − Λ)⁻¹ (V⁻¹ B)

costs ``O(n p m)`` per frequency instead of a factorisation, so the peak
of ``σmax(T(jω))`` can be searched directly.  The gain and its slope are
sampled at ``ω = 0``, the modal frequencies ``|Im λ|``, the peaks met
recently and a logarithmic grid spanning the poles; Newton's method (in
a trust interval) on the largest eigenvalue of ``T(jω)ᴴ T(jω)`` then
climbs from every place a maximum may hide — the local maxima of the
samples, the modal frequencies, and the maximum of the cubic through
two neighbouring samples and their slopes — where the gain is within
half the largest sampled.  The result is a gain at one frequency, so a
lower bound of the norm, and the norm itself when the global peak was
among those climbed.

:class:`~controlext.synthesis.objective.Objective` uses it on
continuous-time error systems of more than :data:`STATES` states, where
``ab13dd`` (Hamiltonian level sets: exact, but ``O(n³)`` with a large
constant) dominates an evaluation, and guards it: the gain at the peak
found is recomputed by a direct solve (a nearly defective error matrix,
whose modal form is inaccurate, goes to ``ab13dd``), and every
:data:`~controlext.synthesis.objective.CHECK_EVERY` evaluations
``ab13dd`` runs beside it; should it find a higher peak, the objective
uses ``ab13dd`` alone from then on.  The designs' reported norms are
always ``ab13dd``'s.  An H∞ optimum levels many peaks, and a search that
missed one of them would let refinement raise it unseen: the flanks of
the lightly damped resonances among the samples and the :data:`TRACKED`
recent peaks among the starts are what keep that rare.

Examples
--------
>>> import numpy as np
>>> A = np.diag([-0.1, -0.2]) + np.array([[0, 3.0], [-3.0, 0]])
>>> B, C = np.array([[0.0], [1.0]]), np.array([[1.0, 0.0]])
>>> lam, V = np.linalg.eig(A)
>>> gamma, w = peak_search(lam, V, B, C)
>>> from controlext.norms import hinfnorm_matrices
>>> exact, _ = hinfnorm_matrices(A, B, C, np.zeros((1, 1)))
>>> bool(abs(gamma - exact) <= 1e-9 * exact)
True
"""

import numpy as np

__all__ = ['peak_search', 'STATES', 'TRACKED']

#: error systems of more than this many states (continuous time) are
#: searched in modal form during refinement (a search costs about half
#: of ``ab13dd`` at 80 states, a third at 120; at 50 states, a 25-mass
#: chain, refinement took 1.7x longer with it)
STATES = 64

#: how many recent peak frequencies such a search starts from
TRACKED = 8


def _apply(Cm, X):
    """``Cm @ X[k]`` for every ``k``, as one matrix product."""
    K, n, r = X.shape
    Y = Cm @ X.transpose(1, 0, 2).reshape(n, K * r)
    return Y.reshape(-1, K, r).transpose(1, 0, 2)


def _gram(X, Y):
    """``X[k]ᴴ Y[k]`` for every ``k`` (small factors: one broadcast sum
    instead of a batch of tiny matrix products)."""
    return np.sum(np.conj(X)[..., :, None] * Y[..., None, :], axis=1)


def _slopes(Cm, Bm, lam, w, second=True):
    """``σmax(T(jω))²`` and its first two derivatives in ``ω`` (the
    second ``None`` unless ``second``)."""
    d = 1j * w[:, None] - lam[None, :]                      # (K, n)
    X0 = Bm[None] / d[:, :, None]
    X1 = X0 * (-1j / d)[:, :, None]                         # d/dω
    parts = [X0, X1]
    if second:
        parts.append(X1 * (-2j / d)[:, :, None])            # d²/dω²
    m = Bm.shape[1]
    Y = _apply(Cm, np.concatenate(parts, axis=-1))          # (K, p, 3m)
    T, T1 = Y[..., :m], Y[..., m:2 * m]
    H = _gram(T, T)
    H1 = _gram(T1, T)
    H1 = H1 + np.conj(np.swapaxes(H1, -1, -2))
    H2 = None
    if second:
        H2 = _gram(Y[..., 2 * m:], T)
        H2 = H2 + np.conj(np.swapaxes(H2, -1, -2)) + 2 * _gram(T1, T1)
    if m == 1:
        return H[:, 0, 0].real, H1[:, 0, 0].real, \
            None if H2 is None else H2[:, 0, 0].real
    vals, vecs = np.linalg.eigh(H)
    v = vecs[..., -1]                                       # (K, m)
    vc = np.conj(v)
    f1 = np.einsum('ki,kij,kj->k', vc, H1, v).real
    if not second:
        return vals[:, -1], f1, None
    f2 = np.einsum('ki,kij,kj->k', vc, H2, v).real
    # the eigenvector's own motion (second-order perturbation theory)
    c = np.einsum('kir,kij,kj->kr', np.conj(vecs[..., :-1]), H1, v)
    gap = np.maximum(vals[:, -1:] - vals[:, :-1], 1e-300)
    f2 = f2 + 2 * np.sum(np.abs(c) ** 2 / gap, axis=-1)
    return vals[:, -1], f1, f2


def _newton(Cm, Bm, lam, w, iterations=30, rtol=1e-13, least=1e-3):
    """Local maxima ``(ω, σmax(T(jω))²)`` from the frequencies ``w``.

    Newton's method in a trust interval: a step that does not raise the
    gain is refused and the interval shrinks fourfold; one that does
    doubles it, up to a tenth of the frequency or ``least``, whichever
    is larger (where the curve is not concave, the step climbs the slope
    by the interval: away from ω = 0 at a minimum there).  A start stops
    when its Newton step promises less than ``rtol`` (relative), when its
    interval has shrunk to nothing, and when it meets another start or
    climbs towards a neighbour already as high (the same hill, climbed
    once).
    """
    w = np.asarray(w, dtype=float).copy()
    radius = np.maximum(0.1 * w, least)
    f, f1, f2 = _slopes(Cm, Bm, lam, w)
    active = np.arange(w.size)
    for _ in range(iterations):
        r = radius[active]
        newton = f2[active] < 0
        step = np.where(newton, -f1[active] / np.where(newton, f2[active],
                                                       -1.0),
                        np.where((f1[active] < 0) & (w[active] > 0), -r, r))
        done = newton & (np.abs(step) <= r) & \
            (0.5 * f1[active] * step <= rtol * f[active])
        step = np.clip(step, -r, r)
        trial = np.maximum(w[active] + step, 0.0)
        step = trial - w[active]
        ft, f1t, f2t = _slopes(Cm, Bm, lam, trial)
        up = ft >= f[active]
        take = active[up]
        w[take], f[take], f1[take], f2[take] = trial[up], ft[up], f1t[up], \
            f2t[up]
        radius[active] = np.where(
            up, np.minimum(np.maximum(2 * np.abs(step), r),
                           np.maximum(0.1 * w[active], least)),
            np.abs(step) / 4)
        done |= radius[active] <= 1e-10 * (1 + np.abs(w[active]))
        going = np.zeros(w.size, dtype=bool)
        going[active[~done]] = True
        # a start climbing towards its neighbour (in frequency, among all
        # starts) that is already as high climbs the same hill: it stops
        # (a maximum between them would have had a start of its own), as
        # does one that meets another
        order = np.argsort(w, kind='stable')
        a, b = order[:-1], order[1:]
        met = w[b] - w[a] <= 1e-9 * (1 + w[b])
        going[b[going[b] & ((f1[b] < 0) & (f[a] >= f[b]) | met)]] = False
        going[a[going[a] & (f1[a] > 0) & (f[b] >= f[a]) & ~met]] = False
        active = np.flatnonzero(going)
        if not active.size:
            break
    return w, f


def peak_search(lam, V, B, C, extra=(), share=0.5, density=120):
    """``(γ, ω)``: the largest gain found of ``C (sI − A)⁻¹ B`` with
    ``A = V diag(lam) V⁻¹`` (continuous time, stable), and its frequency.

    ``extra``: frequencies to start from besides the grid (recent peaks);
    the grid holds ``0``, the modal frequencies, the points a damping
    width either side of each lightly damped resonance (damping below 10
    % of its frequency) and ``density`` points spaced logarithmically
    from a tenth of the slowest pole to ten times the fastest.  Newton's
    method starts from the maximum of the cubic
    through each pair of neighbouring samples and their slopes (where it
    has one inside), from each local maximum of the samples and from each
    modal frequency, where the gain there is within ``share`` of the
    largest sampled gain.
    """
    Bm = np.linalg.solve(V, B.astype(complex))
    Cm = C @ V
    extra = np.asarray(extra, dtype=float)
    mags = np.abs(lam)
    lo = max(float(mags.min()), 1e-8) / 10
    hi = max(float(mags.max()), 1e-8) * 10
    # the flanks of each lightly damped resonance, a width away: a peak
    # levelled with its neighbours may sit there, between samples whose
    # slopes all fall (25-mass chain: 2.023 rad/s, a pole at
    # -0.05 + 1.992j, samples at 1.992 and 2.108)
    light = lam[(lam.imag > 0) & (-lam.real < 0.1 * lam.imag)]
    flanks = (light.imag[:, None] - light.real[:, None] *
              np.array([-1.0, 1.0])).ravel()
    grid = np.unique(np.concatenate([
        [0.0], np.abs(lam.imag), extra, np.geomspace(lo, hi, density),
        flanks[flanks > 0]]))
    values, slope, _ = _slopes(Cm, Bm, lam, grid, second=False)
    # between neighbours, the cubic through the two samples and their
    # slopes: where it has a maximum, the curve has one near it (a slope
    # turning from rising to falling, or a bump between two falling or
    # two rising samples)
    h = np.diff(grid)
    fa, fb = values[:-1], values[1:]
    ga, gb = h * slope[:-1], h * slope[1:]
    a2 = 6 * (fa - fb) + 3 * (ga + gb)
    a1 = 6 * (fb - fa) - 4 * ga - 2 * gb
    a0 = ga
    # the root of the slope a2 t² + a1 t + a0 where it falls through 0
    # (there the second derivative is −√D), in the form that holds as
    # a2 -> 0
    D = a1 ** 2 - 4 * a2 * a0
    with np.errstate(invalid='ignore', divide='ignore'):
        t = 2 * a0 / (np.sqrt(np.maximum(D, 0.0)) - a1)
    cubic = (D > 0) & (t > 0) & (t < 1)
    inner = grid[:-1] + np.where(cubic, t, 0.0) * h
    # and the local maxima of the samples and the modal frequencies (a
    # resonance's sample may sit on the far flank of its peak, below a
    # neighbour's); where the gain is within ``share`` of the largest
    left = np.concatenate([[-np.inf], values[:-1]])
    right = np.concatenate([values[1:], [-np.inf]])
    pick = np.flatnonzero((values >= left) & (values >= right) |
                          np.isin(grid, np.abs(lam.imag)))
    level = share ** 2 * values.max()
    pick = pick[values[pick] >= level]
    near = cubic & (np.maximum(fa, fb) >= level)
    starts = np.concatenate([grid[pick], inner[near], extra])
    # (every step Newton takes raises the gain, and the largest sample is
    # among the starts)
    w, top = _newton(Cm, Bm, lam, starts, least=lo / 10)
    k = int(np.argmax(top))
    return float(np.sqrt(max(top[k], 0.0))), float(w[k])
