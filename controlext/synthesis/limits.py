"""Limits a design keeps besides its norms: a settling time and a gain
tolerance.

Both are held the way a norm bound is (:mod:`~controlext.synthesis.criteria`):
refinement keeps the *ratio* ``r(G) <= 1`` as an exact penalty on a
margin ``φ(r) = ln r`` with its gradient, and verification measures the
ratio on the returned design.  The convex stage does not see them (neither is
convex in the gain); its design is a start.

``settling_time=T``
    The averaged error from the worst unit initial error, every copy
    starting from the same error (:func:`~controlext.synthesis.tradeoff.transient`),
    stays within 2 % of its start after ``T``: the ratio is
    ``max_{t >= T} ‖Cz̄ e^{Acl t} X0‖₂ / (0.02 ‖Cz̄ X0‖₂)`` over a time grid.
    Its gradient at the worst time ``t`` with top singular vectors
    ``u, v`` is ``t L(t Aclᵀ, Cz̄ᵀ u vᵀ X0ᵀ)`` in ``Acl`` (``L`` the
    Fréchet derivative of the exponential; in discrete time the sum
    ``Σ_j (Aclᵀ)^j W (Aclᵀ)^{k−1−j}``, the corner of a block power).

``gain_tolerance=ε``
    Every gain entry may be off by a relative error of ``ε`` (a gain
    printed to ``d`` significant digits is off by at most
    ``5·10^{−d}``) and the error poles stay in the region.  Rounding adds
    ``Δ`` with ``|Δ_ij| <= ε |G_ij|``, so ``‖Δ‖₂ <= ε ‖|G|‖₂`` (the
    spectral norm is monotone on nonnegative matrices; ``|G|`` is the
    entrywise absolute value, and ``‖|G|‖₂ <= ‖G‖_F``, with no growth
    over identical uncoupled copies); an eigenvalue of ``Acl − Δ Ce``
    reaches a boundary point ``z`` only if ``‖Δ‖₂ ‖Ce (z I − Acl)⁻¹‖₂ >=
    1``.  The certified ratio is therefore

        r(G) = ε ‖|G|‖₂ · max over the region's edges of
               sup_{z on the edge} ‖Ce (z I − Acl)⁻¹‖₂,

    and ``r < 1`` proves that no such perturbation moves a pole out.  On
    the line ``Re s = a`` the supremum is the H∞ norm of ``(Acl − a I,
    I, Ce, 0)``; on the circle ``|z − c| = r`` it is the discrete-time
    H∞ norm of ``((Acl − c I)/r, I/r, Ce, 0)`` (:meth:`Region.edges`).
    The bound depends on the state coordinates (the property does not:
    a diagonal change of units maps relative gain errors onto relative
    gain errors), so verification accepts the certificate in the given
    units or in the canonical ones of
    :meth:`~controlext.synthesis.problem.ObserverProblem.state_scaling`.
    Verification also rounds the gain to ``d = ⌈−log10 ε⌉`` significant
    digits (6 for ``ε = 1e-6``) and checks the region on that gain: a
    rounding is off by up to ``5·10^{−d}``, beyond the certificate, and
    is what a gain printed to ``d`` digits is.

Examples
--------
>>> import numpy as np
>>> import controlext as cx
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.limits import GainTolerance
>>> prob = ObserverProblem(A=[[-0.5]], C=[[1.0]])
>>> G = np.array([[3.0]])                  # pole -3.5, region Re s <= -2.5
>>> # ε · 3 · max_ω |1 / (jω − 1)| = 3 ε: certified up to ε = 1/3
>>> round(GainTolerance(0.1).verify(prob, G, cx.HalfPlane(2.5)), 6)
0.3
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as la

from ..norms import hinfnorm_matrices
from .rates import SETTLING_BAND
from .tradeoff import rounded_keeps, transient

__all__ = ['GainTolerance', 'SettlingTime', 'limits_of', 'edges_of']

#: grid points per settling time in refinement's envelope
GRID = 48
#: how far past the settling time the envelope is checked (in units of T)
REACH = 3.0


def edges_of(region, dt=0):
    """The edges of ``region`` (:meth:`Region.edges`); with no region, the
    stability boundary (the imaginary axis, or the unit circle)."""
    if region is None:
        return [('circle', 0.0, 1.0)] if dt else [('plane', 0.0, 1.0)]
    return region.edges()


def _unit(values):
    """Top singular triple ``(σ, u, v)`` of a matrix."""
    U, s, Vh = np.linalg.svd(values)
    return float(s[0]), U[:, 0], Vh[0].conj()


class GainTolerance:
    """The region survives relative gain errors ``eps`` (module text)."""

    name = 'gain_tolerance'
    #: the margin beyond an edge: above ``ln r`` anywhere inside, where
    #: rounding bounds ``r`` by about ``1e16`` (``ln r < 37``), so that
    #: the margin falls all the way from outside an edge to inside it
    outside = 40.0

    @staticmethod
    def margin(ratio):
        """``(φ(r), φ'(r))`` with ``φ(r) = ln r``: a barrier at an edge,
        where the ratio grows as a power of a pole's distance to it (a
        cluster of ``k`` poles, as the ``−k``-th power: ``1 − 1/r`` had
        no slope left there and the push stalled)."""
        ratio = max(ratio, 1e-300)
        return float(np.log(ratio)), 1.0 / ratio

    def __init__(self, eps, region=None, dt=0):
        self.eps = float(eps)
        self.edges = edges_of(region, dt)

    def _edge_peaks(self, Acl, Ce, w):
        """``(value, z)`` of the largest resolvent norm on each edge."""
        n = Acl.shape[0]
        eye = np.eye(n)
        W = np.diag(w)
        out = []
        for kind, c, r in self.edges:
            if kind == 'plane':
                h, f = hinfnorm_matrices(Acl - c * eye, W, Ce,
                                         np.zeros((Ce.shape[0], n)), 0)
                z = c + 1j * f
            else:
                h, f = hinfnorm_matrices((Acl - c * eye) / r, W / r, Ce,
                                         np.zeros((Ce.shape[0], n)), True)
                z = c + r * np.exp(1j * f) if np.isfinite(f) else \
                    complex(c + r)
            out.append((h, z))
        return out

    def ratio(self, G, Acl, Ce, w=None):
        """``(r, gradient thunk)`` of the certified ratio at ``G``
        (``inf`` when a pole is outside an edge)."""
        w = np.ones(G.shape[0]) if w is None else w
        Gw = G / w[:, None]
        F, fu, fv = _unit(np.abs(Gw)) if G.size else (0.0, None, None)
        peaks = self._edge_peaks(Acl, Ce, w)
        h, z = max(peaks, key=lambda item: item[0])
        value = self.eps * F * h
        if not np.isfinite(value):
            return float('inf'), None

        def gradient():
            a, b = _resolvent_vectors(z, Acl, Ce, w)
            dA = np.real(np.outer(a.conj(), b))
            dh = -dA @ Ce.T                 # Acl = Ae − G Ce
            dF = np.sign(G) * np.outer(fu, fv) / w[:, None] if F > 0 \
                else np.zeros_like(G)
            return self.eps * (h * dF + F * dh)

        return float(value), gradient

    @property
    def digits(self):
        """The significant digits a gain is rounded to in verification:
        ``⌈−log10 ε⌉``."""
        return int(np.ceil(-np.log10(self.eps) - 1e-9))

    def explain(self, ratio):
        """What a ratio above 1 means, for a refusal."""
        if ratio == float('inf'):
            return (f"leaves its region when its gain is rounded to "
                    f"{self.digits} significant digits "
                    f"(gain_tolerance={self.eps:.3g})")
        return (f"keeps its region certified only under relative gain "
                f"errors up to {self.eps / ratio:.3g}, less than "
                f"gain_tolerance={self.eps:.3g}")

    def verify(self, problem, G, region=None, units=None):
        """The certified ratio of ``G`` on ``problem``: the smallest of
        the given, the canonical and ``units``' (the state units a design
        was made in, if any) — each is a valid certificate, the error
        being relative to every entry in any units (``<= 1``:
        certified); ``inf`` when the gain rounded to :attr:`digits`
        digits leaves the region."""
        G = np.asarray(G, float)
        Acl = problem.error_system(G)[0]
        copies = np.ones(problem.copies)
        weights = [np.ones(G.shape[0]),
                   np.kron(copies, problem.state_scaling())]
        if units is not None:
            weights.append(np.kron(copies, np.asarray(units, float)))
        limit = GainTolerance(self.eps, region, problem.dt)
        ratio = min(limit.ratio(G, Acl, problem.Ce, w)[0] for w in weights)
        if np.isfinite(ratio) and self.digits <= 17 and \
                not rounded_keeps(problem, G, region, self.digits):
            return float('inf')
        return ratio


class SettlingTime:
    """The averaged error settles within ``T`` (module text)."""

    name = 'settling_time'
    outside = 1.0

    @staticmethod
    def margin(ratio):
        """``(φ(r), φ'(r))`` with ``φ(r) = ln r``."""
        ratio = max(ratio, 1e-300)
        return float(np.log(ratio)), 1.0 / ratio

    def __init__(self, T, problem):
        self.T = float(T)
        self.dt = problem.dt
        self.C = problem.Cze
        self.X0 = np.kron(np.ones((problem.copies, 1)), np.eye(problem.n))
        self.band = SETTLING_BAND * la.svdvals(self.C @ self.X0)[0]

    def _times(self):
        """Grid times ``t >= T`` (whole steps in discrete time)."""
        if not self.dt:
            return self.T + self.T * REACH * np.arange(
                int(GRID * REACH) + 1) / (GRID * REACH)
        step = 1.0 if self.dt is True else float(self.dt)
        first = int(np.ceil(self.T / step - 1e-9))
        last = first + max(int(np.ceil(REACH * self.T / step)), 8)
        stride = max(1, (last - first) // int(GRID * REACH))
        return step * np.arange(first, last + 1, stride)

    def ratio(self, G, Acl, Ce=None, w=None):
        """``(r, gradient thunk)``: the largest envelope over the grid
        against the band."""
        if self.band == 0:
            return 0.0, lambda: np.zeros_like(G)
        times = self._times()
        with np.errstate(over='ignore', invalid='ignore'):
            if self.dt:
                step = 1.0 if self.dt is True else float(self.dt)
                ks = np.rint(times / step).astype(int)
                X = np.linalg.matrix_power(Acl, int(ks[0])) @ self.X0
                hop = np.linalg.matrix_power(Acl, int(ks[1] - ks[0])) \
                    if ks.size > 1 else None
            else:
                X = la.expm(Acl * times[0]) @ self.X0
                hop = la.expm(Acl * (times[1] - times[0]))
            states = np.empty((times.size,) + X.shape)
            for i in range(times.size):
                states[i] = X
                if hop is not None:
                    X = hop @ X
            Y = self.C @ states
        if not np.all(np.isfinite(Y)):
            return float('inf'), None
        env = np.linalg.norm(Y[..., 0], axis=-1) if Y.shape[-1] == 1 else \
            np.linalg.svd(Y, compute_uv=False)[:, 0]
        k = int(np.argmax(env))
        value = float(env[k] / self.band)
        if not np.isfinite(value):
            return float('inf'), None
        t = float(times[k])

        def gradient():
            n = Acl.shape[0]
            if self.dt:
                step = 1.0 if self.dt is True else float(self.dt)
                power = int(round(t / step))
                Y = self.C @ np.linalg.matrix_power(Acl, power) @ self.X0
            else:
                Y = self.C @ la.expm(Acl * t) @ self.X0
            _, u, v = _unit(Y)
            W = np.real(np.outer(self.C.T @ u, self.X0 @ v))
            if self.dt:
                block = np.block([[Acl.T, W], [np.zeros((n, n)), Acl.T]])
                dA = np.linalg.matrix_power(block, power)[:n, n:]
            else:
                dA = t * la.expm_frechet(t * Acl.T, W,
                                         compute_expm=False)
            return -(dA @ Ce.T) / self.band

        return value, gradient

    def explain(self, ratio):
        """What a ratio above 1 means, for a refusal."""
        return (f"settles to 2 % in {ratio * self.T:.6g}, after "
                f"settling_time={self.T:.6g}")

    def verify(self, problem, G, region=None, units=None):
        """The settling time of ``G`` against ``T`` (``<= 1``: met), from
        the dense simulation of the trade-off (``units`` do not matter)."""
        settle = transient(problem, G)[1]
        return settle / self.T if self.T > 0 else \
            (0.0 if settle == 0 else float('inf'))


def limits_of(criteria, problem, region=None):
    """The limit objects of ``criteria`` on ``problem`` and ``region``."""
    out = []
    if criteria.settling_time is not None:
        out.append(SettlingTime(criteria.settling_time, problem))
    if criteria.gain_tolerance:
        out.append(GainTolerance(criteria.gain_tolerance, region,
                                 problem.dt))
    return out


def _resolvent_vectors(z, Acl, Ce, w):
    """``(a, b)`` with ``a = M⁻ᴴ Ceᵀ u``, ``b = M⁻¹ diag(w) v``, ``M = z I −
    Acl`` and ``(u, v)`` the top singular pair of ``Ce M⁻¹ diag(w)``: the
    derivative of that resolvent's norm is ``Re(a bᴴ)``.  A peak can sit
    on a pole that ``Ce`` does not see (its norm stays finite there) and
    ``M`` is then singular to working precision: ``z`` is moved along
    the edge by 1e-12, then 1e-9 of its size, where it is not."""
    n = Acl.shape[0]
    for shift in (0.0, 1e-12, 1e-9):
        M = (z + 1j * shift * max(1.0, abs(z))) * np.eye(n) - Acl
        try:
            T = Ce @ np.linalg.solve(M, np.diag(w))
            _, u, v = _unit(T)
            return (np.linalg.solve(M.conj().T, Ce.T @ u),
                    np.linalg.solve(M, w * v))
        except np.linalg.LinAlgError:
            continue
    raise np.linalg.LinAlgError(
        f"the resolvent at the certificate's peak z = {z:.6g} is singular "
        "even 1e-9 away from it")

