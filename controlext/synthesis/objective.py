"""The objective of refinement: the true norm under a pole region.

For a gain ``G`` of an :class:`~controlext.synthesis.problem.ObserverProblem`,
:class:`Objective` evaluates the exact penalty

    f(G) = ‖T_G‖ + τ ‖G‖² + ρ · max(0, g(G) + δ),

where ``‖T_G‖`` is the norm the criteria minimise (H∞ by default, or H2;
:class:`~controlext.synthesis.criteria.Criteria`) and ``g(G)`` the largest
constraint margin (``<= 0`` when every constraint holds): the region
margins over the eigenvalues of ``Ae − G Ce``; with a gain bound ``κ``,
``s (‖W G‖₂ / κ − 1)`` (``W`` diagonal weights giving the gain in the
user's units, ``s`` the margins' rate scale); with a bound ``b`` on the
other norm, ``s (‖T_G‖ / b − 1)``; with a limit of ratio ``r``
(:mod:`~controlext.synthesis.limits`), ``s φ(r)`` with ``φ`` the limit's
own increasing transform (``φ(1) = 0``).  Its gradient: that of the H∞ norm from
the singular vectors at the peak frequency, that of the H2 norm from the
two Gramians, that of a region margin from the right and left
eigenvectors of the critical eigenvalue, that of the gain margin from the
top singular vectors of ``W G``.

One evaluation is one eigendecomposition of the error matrix (it gives the
stability test, the region margins and the critical eigenvector) and one
call of slycot's ``ab13dd``; the gradient costs two linear solves more and
is computed only when asked for, reusing the decomposition of the same
point (a line search needs it only at the points it accepts), and a trial
point whose penalty and frequency response at recent peak frequencies
already exceed the line search's threshold is rejected on that lower
bound alone.  On continuous-time error systems of more than
:data:`~controlext.synthesis.peaks.STATES` states the search's H∞ norm
comes from the eigendecomposition instead of ``ab13dd``
(:mod:`~controlext.synthesis.peaks`); :meth:`Objective.norm` is always
``ab13dd``'s.

Examples
--------
>>> import numpy as np
>>> import controlext as cx
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.objective import Objective
>>> prob = ObserverProblem(A=[[-0.5]], C=[[1.0]])
>>> f = Objective(prob, cx.HalfPlane(2.5), rho=10.0)
>>> value, grad = f(np.array([2.0]))      # the paper's k0 = 2: γ0 = 0.8
>>> round(value, 6), grad.shape
(0.8, (1,))
"""

import math

import numpy as np

from ..norms import hinfnorm_matrices
from .criteria import Criteria, h2_parts, stable_poles
from .limits import limits_of
from . import peaks as _peaks

__all__ = ['Objective', 'WorstCase', 'objective_of']

_ONE = np.ones(1)

#: the tolerance of :meth:`Objective.norm` (that of verification)
EXACT = 1e-10

#: every how many modal peak searches ``ab13dd`` runs instead
CHECK_EVERY = 20


class Objective:
    """Penalised H∞ objective of a problem and region, with gradient.

    Parameters
    ----------
    problem : ObserverProblem
        The generalised plant.
    region : Region or None
        Pole region (``None``: stability only).
    rho : float, optional
        Weight of the exact penalty on the region margin.
    delta : float, optional
        Margin kept inside the region: the penalty starts at ``g = −δ``.
    tikhonov : float, optional
        Weight ``τ`` of ``‖G‖²``.
    peaks : int, optional
        How many recent peak frequencies the line-search bound looks at.
    gain_bound : float, optional
        ``κ``: the constraint ``‖W G‖₂ <= κ``.
    gain_weights : array_like, optional
        The diagonal of ``W`` (one weight per gain row; default ones).
    gain_units : float, optional
        ``s``, the scale of the gain and norm margins against the region
        margins.
    criteria : Criteria, optional
        The norm minimised and the norm bounded (default: minimise H∞).
    norm_tol : float, optional
        Relative tolerance of the H∞ norms of the search (``ab13dd``'s
        ``tol``); :meth:`norm` always computes to 1e-10.

    Calling the objective with a flat gain ``x`` returns ``(f, ∇f)``
    (``(f, None)`` with ``grad=False``); outside the stability region
    ``f = inf``.  With ``above=a`` (and ``grad=False``) it may instead
    return a lower bound of ``f`` that exceeds ``a`` — the penalty plus
    the frequency response at the last few distinct peak frequencies met,
    a batch of linear solves instead of ``ab13dd`` — which is all that a
    line search rejecting a trial step needs to know (when the H∞ norm is
    minimised); a point inside the region is rejected so only if the bound
    also shows it is no new ``best``.  ``count`` counts the points
    evaluated; ``best`` is the smallest norm met inside the constraints
    and its gain.
    """

    #: the pole-placement polish may run on it
    placeable = True

    def __init__(self, problem, region, rho=0.0, delta=0.0, tikhonov=0.0,
                 peaks=4, gain_bound=None, gain_weights=None, gain_units=1.0,
                 criteria=None, norm_tol=1e-10):
        self.prob, self.region = problem, region
        self.criteria = Criteria() if criteria is None else criteria
        self.primary = self.criteria.objective
        self.norm_bounds = self.criteria.bounds
        self.needed = self.criteria.norms
        self.limits = limits_of(self.criteria, problem, region)
        self.gain_bound, self.gain_units = gain_bound, gain_units
        self.gain_weights = np.ones(problem.gain_shape[0]) \
            if gain_weights is None else np.asarray(gain_weights, float)
        self.peaks = peaks
        self.norm_tol = norm_tol
        self.shape = problem.gain_shape
        self.rho, self.delta, self.tikhonov = rho, delta, tikhonov
        self.dt = problem.dt
        self.Ae, self.Ce = problem.Ae, problem.Ce
        self.Dwe, self.Bwe, self.Ccl = problem.Dwe, problem.Bwe, problem.Cze
        self.Dcl = np.zeros((problem.nz, problem.q))
        self.eye = np.eye(self.Ae.shape[0])
        self.count = 0
        self._last = None
        self._peaks = []
        # large continuous-time error systems: the norm from the modal form
        # during the search (:mod:`~controlext.synthesis.peaks`)
        self.modal = not self.dt and self.Ae.shape[0] > _peaks.STATES
        if self.modal:
            # its starts: an H∞ optimum levels many peaks, and a peak left
            # out of the search's starts may be missed
            self.peaks = max(peaks, _peaks.TRACKED) if peaks else 0
        self._searches = 0
        self.reset_best()

    def reset_best(self):
        """Forget the best point inside the region seen so far."""
        self.best = (np.inf, None)

    # -- pieces -------------------------------------------------------------

    @property
    def offset(self):
        """The least margin beyond an edge when a limit is held (its
        ``outside`` in gain units; the region's margin adds to it), 0
        without limits."""
        return max((self.gain_units * limit.outside
                    for limit in self.limits), default=0.0)

    @property
    def constrained(self):
        """Is there a constraint (a region, a gain or a norm bound)?"""
        return self.region is not None or self.gain_bound is not None or \
            bool(self.norm_bounds) or bool(self.limits)

    def _point(self, G):
        """Error matrix, its eigendecomposition and the worst margin."""
        Acl = self.Ae - G @ self.Ce
        lam, V = np.linalg.eig(Acl)
        worst, crit = -np.inf, None
        if self.region is not None:
            m = self.region.margins(lam)
            i, j = divmod(int(m.argmax()), m.shape[1])
            worst, crit = float(m[i, j]), (i, j)
        if self.gain_bound is not None:
            WG = self.gain_weights[:, None] * G
            # the Frobenius norm bounds the spectral one: where even it
            # leaves the gain margin below the region's, no SVD is needed
            # (the default bound is far from binding almost everywhere)
            frob = math.sqrt(float(np.sum(WG * WG)))
            if self.gain_units * (frob / self.gain_bound - 1.0) > worst:
                top = np.linalg.svd(WG, compute_uv=False)[0]
                gm = self.gain_units * (top / self.gain_bound - 1.0)
                if gm > worst:
                    worst, crit = float(gm), ('gain', WG)
        return Acl, lam, V, worst, crit

    def _margin_grad(self, lam, V, crit):
        """Gradient of the critical margin with respect to G (0 where no
        margin is critical: a limit beyond an edge, without a region)."""
        if crit is None:
            return np.zeros(self.shape)
        if crit[0] == 'limit':
            return self.gain_units * crit[1] * crit[2]()
        if crit[0] == 'norm':
            _, name, Acl, Bcl, norms = crit
            bound = dict(self.norm_bounds)[name]
            return self.gain_units / bound * self._gradient(
                name, Acl, Bcl, norms)
        if crit[0] == 'gain':
            U, _, Vh = np.linalg.svd(crit[1])
            return self.gain_units / self.gain_bound * np.outer(
                self.gain_weights * U[:, 0], Vh[0])
        i, j = crit
        # the left eigenvector yᴴ (row i of V⁻¹, so yᴴ x = 1) by one solve
        unit = np.zeros(V.shape[0])
        unit[i] = 1.0
        try:
            left = np.linalg.solve(V.T, unit)
        except np.linalg.LinAlgError:
            left = np.linalg.pinv(V)[i]
        dlam = -np.outer(left, self.Ce @ V[:, i])
        dre, dim = self.region.margin_gradients(lam[i:i + 1])[0, j]
        return dre * dlam.real + dim * dlam.imag

    def _hinf(self, Acl, Bcl, lam, tol=None, V=None):
        """True H∞ norm and peak frequency (``inf`` if unstable), to the
        relative tolerance ``tol`` (default the search's ``norm_tol``).

        Given the eigenvectors ``V`` of a large error system (see
        ``modal``), the search's norm comes from the modal peak search,
        checked by a direct solve at its peak and by ``ab13dd`` every
        :data:`CHECK_EVERY` searches; a check that finds a higher peak
        ends the modal searches of this objective."""
        def exact():
            return hinfnorm_matrices(
                Acl, Bcl, self.Ccl, self.Dcl, self.dt,
                tol=self.norm_tol if tol is None else tol, poles=lam)

        if V is None or not self.modal or tol is not None or \
                not stable_poles(lam, self.dt):
            return exact()
        self._searches += 1
        try:
            gamma, w = _peaks.peak_search(lam, V, Bcl, self.Ccl,
                                          extra=self._peaks)
        except np.linalg.LinAlgError:       # eigenvectors singular
            return exact()
        if self._searches % CHECK_EVERY == 0:
            # the check: a peak the search missed ends its use here
            out = exact()
            if out[0] > gamma * (1 + 1e-6):
                self.modal = False
            return out
        try:
            T = self.Ccl @ np.linalg.solve(1j * w * self.eye - Acl, Bcl)
        except np.linalg.LinAlgError:
            return exact()
        direct = float(np.linalg.norm(T, 2))
        if abs(direct - gamma) <= 1e-8 * max(direct, 1e-300):
            return direct, w
        return exact()

    def _norms(self, Acl, Bcl, lam, names, tol=None, V=None):
        """``{name: (value, detail)}`` of the norms ``names`` (``inf`` if
        unstable): the peak frequency for H∞ (its gradient needs it), None
        for H2."""
        out = {}
        if 'hinf' in names:
            out['hinf'] = self._hinf(Acl, Bcl, lam, tol, V)
        if 'h2' in names:
            out['h2'] = (np.inf, None) if not stable_poles(lam, self.dt) \
                else (h2_parts(Acl, Bcl, self.Ccl, self.dt,
                               gradient=False)[0], None)
        return out

    def _gradient(self, name, Acl, Bcl, norms):
        """Gradient with respect to G of the norm ``name`` at a point."""
        if name == 'hinf':
            return self._norm_grad(Acl, Bcl, norms['hinf'][1])
        _, dA, dB = h2_parts(Acl, Bcl, self.Ccl, self.dt)
        # Acl = Ae − G Ce, Bcl = G Dwe − Bwe
        return dB @ self.Dwe.T - dA @ self.Ce.T

    def _bounded(self, norms, worst, crit, Acl, Bcl, G):
        """The worst margin and its source, with the norm bounds and the
        limits (:mod:`~controlext.synthesis.limits`)."""
        for name, bound in self.norm_bounds:
            value = norms[name][0]
            if not np.isfinite(value):
                continue            # unstable: the norm is inf anyway
            m = self.gain_units * (value / bound - 1.0)
            if m > worst:
                worst, crit = m, ('norm', name, Acl, Bcl, norms)
        for limit in self.limits:
            ratio, gradient = limit.ratio(G, Acl, self.Ce)
            if not np.isfinite(ratio):
                # a pole off an edge: the limit's margin goes on from its
                # value at the edge, and the region's margin leads back
                worst = self.gain_units * limit.outside + max(worst, 0.0)
                continue
            g, slope = limit.margin(ratio)
            m = self.gain_units * g
            if m > worst:
                worst, crit = m, ('limit', slope, gradient)
        return worst, crit

    def _norm_grad(self, Acl, Bcl, w):
        """Gradient of ``σmax(T(z))`` at the peak: ``Re(a bᴴ)``."""
        z = np.exp(1j * w * self.dt) if self.dt else 1j * w
        M = z * self.eye - Acl
        RB = np.linalg.solve(M, Bcl)
        T = self.Ccl @ RB
        size = np.linalg.norm(T)
        if size == 0:
            # T ≡ 0 at the peak: the norm is 0, its least value, and 0 is
            # a subgradient there
            return np.zeros(self.shape)
        if T.shape[1] == 1:                 # one noise input: no SVD
            u, v = T[:, 0] / size, _ONE
        else:
            U, _, Vh = np.linalg.svd(T)
            u, v = U[:, 0], Vh[0].conj()
        a = np.linalg.solve(M.conj().T, self.Ccl.T @ u)
        b = self.Dwe @ v - self.Ce @ (RB @ v)
        return np.real(np.outer(a.conj(), b))

    def peak_bound(self, G):
        """A lower bound of the H∞ norm at ``G`` from the recent peak
        frequencies (0 when none is known or another norm is
        minimised)."""
        if not self._peaks or self.primary != 'hinf':
            return 0.0
        return self._peak_bound(self.Ae - G @ self.Ce, G @ self.Dwe - self.Bwe)

    def _peak_bound(self, Acl, Bcl):
        """``max_k σmax(T(j w_k))`` over the recent peak frequencies
        ``w_k``: a lower bound of the H∞ norm (``inf`` on a pole)."""
        w = np.array(self._peaks)
        z = np.exp(1j * w * self.dt) if self.dt else 1j * w
        M = z[:, None, None] * self.eye - Acl
        try:
            T = self.Ccl @ np.linalg.solve(M, Bcl[None])
        except np.linalg.LinAlgError:
            return np.inf
        sv = np.linalg.norm(T[..., 0], axis=-1) if T.shape[-1] == 1 else \
            np.linalg.svd(T, compute_uv=False)[..., 0]
        return float(sv.max())

    # -- public -------------------------------------------------------------

    def margin(self, G):
        """Worst constraint margin at ``G`` and its gradient."""
        if not self.constrained:
            return -np.inf, np.zeros_like(G)
        Acl, lam, V, m, crit = self._point(G)
        if self.norm_bounds or self.limits:
            Bcl = G @ self.Dwe - self.Bwe
            norms = self._norms(Acl, Bcl, lam,
                                [name for name, _ in self.norm_bounds])
            m, crit = self._bounded(norms, m, crit, Acl, Bcl, G)
        if crit is None:
            return m, np.zeros_like(G)
        return m, self._margin_grad(lam, V, crit)

    def norm(self, G):
        """The minimised norm at ``G`` (``inf`` if the error is
        unstable)."""
        G = np.asarray(G, dtype=float).reshape(self.shape)
        Acl = self.Ae - G @ self.Ce
        return self._norms(Acl, G @ self.Dwe - self.Bwe,
                           np.linalg.eigvals(Acl),
                           (self.primary,), tol=EXACT)[self.primary][0]

    def norm_gradient(self, x):
        """``(γ, ∇γ)``: the minimised norm at the flat gain ``x`` and its
        gradient (flat; ``inf`` and zeros where unstable)."""
        gamma, _, dgamma, _ = self.pieces(x)
        if not math.isfinite(gamma):
            return np.inf, np.zeros_like(x)
        return gamma, dgamma().ravel()

    def active_gradients(self, G):
        """The gradients (flat) of the constraint margins active at ``G``:
        the region's margin of every pole within ``ACTIVE`` of an edge,
        and the worst other margin (gain or norm bound, limit) if it is
        that close to its bound."""
        from .stationary import ACTIVE
        G = np.ascontiguousarray(G, dtype=float).reshape(self.shape)
        last = self._last
        if last is not None and last[0] == G.tobytes():
            # the point just evaluated (the stationarity test asks for
            # the norm's gradient first): its eigendecomposition and
            # worst margin, not a second pass (a limit's margin costs an
            # H∞ norm with one input per state)
            _, _, _, _, lam, V, worst, crit, _, _ = last
        else:
            Acl, lam, V, worst, crit = self._point(G)
            if self.norm_bounds or self.limits:
                Bcl = G @ self.Dwe - self.Bwe
                norms = self._norms(Acl, Bcl, lam, [
                    name for name, _ in self.norm_bounds])
                worst, crit = self._bounded(norms, worst, crit, Acl, Bcl,
                                            G)
        out = []
        if self.region is not None:
            tol = ACTIVE * max(1.0, float(np.max(np.abs(lam))))
            margins = self.region.margins(lam)
            for i, j in zip(*np.nonzero(margins > -tol)):
                out.append(self._margin_grad(lam, V, (int(i), int(j))).ravel())
        if self.constrained and np.isfinite(worst) and \
                worst > -ACTIVE * self.gain_units:
            out.append(self._margin_grad(lam, V, crit).ravel())
        return out

    def pieces(self, x):
        """``(γ, m, dγ, dm)`` at the flat gain ``x``: the minimised norm,
        the worst constraint margin and thunks of their gradients (the
        parts :class:`WorstCase` combines over models)."""
        G, Acl, Bcl, lam, V, m, crit, norms, sq = self._evaluate(x)
        gamma = norms[self.primary][0]

        def dgamma():
            return self._gradient(self.primary, Acl, Bcl, norms)

        def dmargin():
            return self._margin_grad(lam, V, crit)

        return gamma, m, dgamma, dmargin

    def _evaluate(self, x):
        """The cached evaluation of a flat gain: ``(G, Acl, Bcl, lam, V,
        m, crit, norms, ‖G‖²)``."""
        key = x.tobytes()
        last = self._last
        if last is not None and last[0] == key:
            return last[1:]
        self.count += 1
        G = x.reshape(self.shape)
        Bcl = G @ self.Dwe - self.Bwe
        sq = float(np.sum(G * G))
        Acl, lam, V, m, crit = self._point(G)
        return self._store(key, G, Acl, Bcl, lam, V, m, crit, sq)

    def _store(self, key, G, Acl, Bcl, lam, V, m, crit, sq):
        """Complete an evaluation with the norms and keep it."""
        norms = self._norms(Acl, Bcl, lam, self.needed, V=V)
        m, crit = self._bounded(norms, m, crit, Acl, Bcl, G)
        self._last = (key, G.copy(), Acl, Bcl, lam, V, m, crit, norms, sq)
        w = norms['hinf'][1] if 'hinf' in norms else np.nan
        if math.isfinite(w) and self.peaks and all(
                abs(w - p) > 1e-3 * (abs(w) + 1e-9) for p in self._peaks):
            self._peaks = [w] + self._peaks[:self.peaks - 1]
        gamma = norms[self.primary][0]
        if math.isfinite(gamma) and m <= 0 and gamma < self.best[0]:
            self.best = (gamma, G.copy())
        return self._last[1:]

    def __call__(self, x, grad=True, above=None):
        # the line search asks again for the point it has just accepted:
        # the points are compared by their bytes (np.array_equal costs
        # more than the rest of a rejected trial point)
        key = x.tobytes()
        last = self._last
        if last is not None and last[0] == key:
            G, Acl, Bcl, lam, V, m, crit, norms, sq = last[1:]
        else:
            self.count += 1
            G = x.reshape(self.shape)
            Bcl = G @ self.Dwe - self.Bwe
            sq = float(np.sum(G * G))
            bounded = above is not None and self._peaks and \
                self.primary == 'hinf'
            if bounded:
                # a line search only asks whether f(x) > above: the gain at
                # recent peak frequencies (a lower bound of the norm) plus
                # the penalty often says so without ab13dd (the norm bounds
                # only add to the margin, so the bound holds without them);
                # a point the peaks alone reject, and that cannot be a new
                # best, needs no eigendecomposition either
                Acl = self.Ae - G @ self.Ce
                peak = self._peak_bound(Acl, Bcl)
                bound = self.tikhonov * sq + peak
                if bound > above and peak >= self.best[0]:
                    return bound, None
            Acl, lam, V, m, crit = self._point(G)
            if bounded:
                bound += self.rho * max(0.0, m + self.delta)
                if bound > above and (m > 0 or peak >= self.best[0]):
                    return bound, None
            G, Acl, Bcl, lam, V, m, crit, norms, sq = self._store(
                key, G, Acl, Bcl, lam, V, m, crit, sq)
        return _penalty(self, x, G, sq, norms[self.primary][0], m, grad,
                        lambda: self._gradient(self.primary, Acl, Bcl,
                                               norms),
                        lambda: self._margin_grad(lam, V, crit))


class WorstCase:
    """The objective of one gain on several plant models: the worst case
    over ``problem.members`` of the minimised norm, with the worst
    constraint margin of any model in the exact penalty,

        f(G) = max_k ‖T_k,G‖ + τ ‖G‖² + ρ · max(0, max_k g_k(G) + δ),

    and a gradient of the active model's norm and margin.  It has the
    interface of :class:`Objective` (same parameters); each model is an
    :class:`Objective` without a penalty of its own.
    """

    #: the pole-placement polish needs one model's pole map
    placeable = False

    def __init__(self, problem, region, rho=0.0, delta=0.0, tikhonov=0.0,
                 peaks=4, gain_bound=None, gain_weights=None, gain_units=1.0,
                 criteria=None, norm_tol=1e-10):
        self.members = [Objective(member, region, 0.0, delta, 0.0, peaks,
                                  gain_bound, gain_weights, gain_units,
                                  criteria, norm_tol)
                        for member in problem.members]
        first = self.members[0]
        self.prob, self.region, self.shape = problem, region, first.shape
        self.rho, self.delta, self.tikhonov = rho, delta, tikhonov
        self.Ae, self.Ce = first.Ae, first.Ce
        self.constrained = first.constrained
        self.offset = first.offset
        self.count = 0
        self.reset_best()

    def reset_best(self):
        """Forget the best point inside the constraints seen so far."""
        self.best = (np.inf, None)

    def margin(self, G):
        """Worst constraint margin over the models, and its gradient."""
        return max((member.margin(G) for member in self.members),
                   key=lambda item: item[0])

    def norm(self, G):
        """The worst minimised norm over the models at ``G``."""
        return max(member.norm(G) for member in self.members)

    def norm_gradient(self, x):
        """``(γ, ∇γ)`` of the worst model at the flat gain ``x``."""
        return max((member.norm_gradient(x) for member in self.members),
                   key=lambda item: item[0])

    def active_gradients(self, G):
        """The active constraints' gradients of every model."""
        return [g for member in self.members
                for g in member.active_gradients(G)]

    def __call__(self, x, grad=True, above=None):
        self.count += 1
        G = x.reshape(self.shape)
        sq = float(np.sum(G * G))
        if above is not None:
            # a line search only asks whether f(x) > above: any model's
            # gain at its recent peak frequencies bounds f from below
            # (as for one model, :meth:`Objective.__call__`)
            peak = max(member.peak_bound(G) for member in self.members)
            bound = self.tikhonov * sq + peak
            if bound > above and peak >= self.best[0]:
                return bound, None
        parts = [member.pieces(x) for member in self.members]
        i = max(range(len(parts)), key=lambda k: parts[k][0])
        j = max(range(len(parts)), key=lambda k: parts[k][1])
        gamma, m = parts[i][0], parts[j][1]
        if math.isfinite(gamma) and m <= 0 and gamma < self.best[0]:
            self.best = (gamma, G.copy())
        return _penalty(self, x, G, sq, gamma, m, grad, parts[i][2],
                        parts[j][3])


def _penalty(obj, x, G, sq, gamma, m, grad, dgamma, dmargin):
    """``(f, ∇f)`` of the exact penalty ``γ + τ ‖G‖² + ρ max(0, m + δ)``
    from the norm ``γ``, the worst margin ``m`` and thunks of their
    gradients (``inf`` where the error is unstable)."""
    if not math.isfinite(gamma):
        return np.inf, (np.zeros_like(x) if grad else None)
    value = gamma + obj.tikhonov * sq
    penalised = m + obj.delta > 0
    if penalised:
        value += obj.rho * (m + obj.delta)
    if not grad:
        return value, None
    g = dgamma() + 2 * obj.tikhonov * G
    if penalised:
        g = g + obj.rho * dmargin()
    return value, g.ravel()


def objective_of(problem, region, *args, **kwargs):
    """The objective of ``problem``: :class:`Objective`, or
    :class:`WorstCase` for a problem of several plant models."""
    cls = WorstCase if len(problem.members) > 1 else Objective
    return cls(problem, region, *args, **kwargs)
