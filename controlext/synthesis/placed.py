"""Polishing with the error poles as variables.

The optimum of a pole-constrained design often stacks several error poles
on the region's edge as one nearly defective cluster (the scalar paper
plant's ``N``-copy optimum has all ``N`` poles at ``−σ``).  Near such a
point the eigenvalues move as the ``k``-th root of a gain change, so the
region margins that refinement penalises (:mod:`~controlext.synthesis.objective`)
are not Lipschitz there and BFGS stalls short of the optimum (scalar plant,
``N = 5``: 0.157–0.167 against 0.1380).

This stage parametrises the gain by its characteristic polynomial
instead.  Every gain is ``G = F + k hᵀ`` with ``F`` free, ``h`` a unit
mixing of the measurements and ``k`` the Ackermann gain of the pair
``(M, c) = (Ae − F Ce, hᵀ Ce)`` that gives ``M − k c`` the characteristic
polynomial ``χ``:

    k = χ(M) O⁻¹ e_m,        O = [c; c M; …; c M^{m−1}].

``χ`` is a product of quadratic factors (and one linear factor when ``m``
is odd) in the region's own variable — ``S = M + σ I`` for a half-plane
``Re s <= −σ``, ``S = (M − c₀ I)/r`` for a disk ``|z − c₀| <= r`` — whose
coefficients are mapped so that their roots are in the region whatever
the parameters: ``S² + u² S + v²`` (both roots in ``Re S <= 0``), and
``S² + (1 + tanh a) tanh b · S + tanh a`` (both in ``|S| <= 1``, the
Schur–Cohn conditions).  The region is then kept by construction, a
stacked cluster is an ordinary point (all ``u = v = 0``), and BFGS
minimises the plain norm (with the gain and norm bounds and limits of
refinement's objective as before).  The gradient is the objective's
gradient in ``G`` carried back through the map in reverse mode (one pass
of ``O(m³)`` per factor, about the cost of the map itself).

A stacked cluster's eigenvalues are computed only to about
``(ε ‖M‖)^{1/k}`` (2e-3 to 7e-3 for five poles at −2.5): where the
computed poles of the result are outside the region, as verification
sees them, the search goes on with every pole held ``δ`` inside (``δ``
growing by the computed excess), which costs little: the best
five-copy filter with its poles at ``−2.5 − 0.003`` is 0.24 % above the
one at ``−2.5``.  Moving the poles of the result without searching
again cost 1.6 % (the zeros were tuned to the old poles).

The gain realises ``χ`` only as accurately as ``O`` is conditioned, and
BFGS, which sees the norm and not the poles, drifts towards nearly
unobservable pairs ``(M, c)`` where the realised poles are off (scalar
plant, ``N = 5``, seed 1: ``cond O = 6·10⁹``, poles 0.05 outside, 8 %
lost to holding them inside).  Each search therefore starts again on a
new map built at the gain it realised (``cond O`` back to about ``10⁴``)
while that halves the excess: 1.0028–1.0030× the best filter over seeds
0–3 at ``N = 5``, against 1.004–1.081× with one map.

The search runs twice: from the given gain's poles, and from all of them
stacked next to the edge, which some problems need (scalar
plant, ``N = 6``, seed 0: 1.77× the best filter from the poles, 1.015×
stacked).  The stacked search goes on past a sixth of its budget only
when it is within ``RACE_TIE`` of the first one's result by then.

How far a cluster of six poles splits when its gain is rounded depends on
the map's ``(F, h)``, not only on the poles: at ``N = 6`` the computed
excess of one search ranged from 0.001 to 0.02, and the result lost about
as much (1.006–1.021× the best filter over seeds 0–5).  Where the best
result has ``CLUSTER`` or more poles near the edge and was held inside by
more than ``HOLD``, ``draws`` more maps (``DRAWS`` by default,
``refine_options['placed_draws']``) are drawn at its gain (a new ``h``
each, ``F`` at the best gain), and the best result is kept: 1.006–1.009×
over seeds 0–15, for about 5 s more.
"""

import functools

import numpy as np

from .bfgs import bfgs

__all__ = ['PoleMap', 'placed_polish']

#: how far behind the other start's result the stacked start may be after
#: a sixth of its budget and go on
RACE_TIE = 0.05

#: the first search of a map ends when ``CREEP[0]`` steps gained less
#: than ``CREEP[1]`` (relative): its last steps creep (the 8-state mass
#: chain's ran all 1,500 steps, the last 750 gaining 1e-4 in all)
CREEP = (300, 1e-4)

#: a result held inside the region by more than this (relative to the
#: edge's scale) and with ``CLUSTER`` or more poles within ``NEAR`` of
#: the edge (relative likewise) gets ``draws`` (default ``DRAWS``) more
#: maps drawn at its gain
HOLD = 1e-3
NEAR = 3e-2
CLUSTER = 5
DRAWS = 16


def _pairs(lam):
    """Eigenvalues grouped as conjugate pairs, then real ones in pairs of
    neighbours; ``(pairs, single)``."""
    cpx = sorted((z for z in lam if z.imag > 1e-12 * max(1, abs(z))),
                 key=lambda z: z.real)
    real = sorted(z.real for z in lam if abs(z.imag) <= 1e-12 * max(1, abs(z)))
    pairs = [(z, z.conjugate()) for z in cpx]
    pairs += [(real[k], real[k + 1]) for k in range(0, len(real) - 1, 2)]
    return pairs, real[-1:] if len(real) % 2 else []


class PoleMap:
    """The map ``θ -> G`` of the module text on a problem and a region
    edge ``('plane', a, 1)`` or ``('circle', c, r)``, started at ``G0``
    (``theta0`` maps to a gain whose poles are those of ``G0`` moved at
    least ``floor`` into the region)."""

    def __init__(self, problem, edge, G0, rng, floor=1e-3):
        self.Ae, self.Ce = problem.Ae, problem.Ce
        self.m, self.P = self.Ae.shape[0], self.Ce.shape[0]
        self._last = None
        self.kind, self.center, self.radius = edge
        G0 = np.asarray(G0, float)
        lam = (np.linalg.eigvals(self.Ae - G0 @ self.Ce) - self.center) / \
            self.radius
        pairs, single = _pairs(lam)
        q = []
        for a, b in pairs:
            s, p = (a + b).real, (a * b).real
            if self.kind == 'plane':     # S² − s S + p, roots in Re S <= 0
                q += [np.sqrt(max(-s, floor)), np.sqrt(max(p, floor ** 2))]
            else:                        # roots in |S| <= 1 (Schur–Cohn)
                g = np.clip(p, -1 + floor, 1 - floor)
                b_ = np.clip(-s / (1 + g), -1 + floor, 1 - floor)
                q += [np.arctanh(g), np.arctanh(b_)]
        for a in single:
            q += [np.sqrt(max(-a.real, floor)) if self.kind == 'plane' else
                  np.arctanh(np.clip(-a.real, -1 + floor, 1 - floor))]
        h = rng.normal(size=self.P)
        self.theta0 = np.concatenate([G0.ravel(), h / np.linalg.norm(h),
                                      np.asarray(q, float)])

    def _coefficients(self, q):
        """``[(α, β, dα/dq, dβ/dq, indices)]``: factor ``S² + α S + β``
        (``β`` None for the linear factor ``S + α``) and its derivatives
        in the parameters ``q[indices]``."""
        out = []
        for k in range(self.m // 2):
            a, b = q[2 * k], q[2 * k + 1]
            if self.kind == 'plane':
                out.append((a * a, b * b, np.array([2 * a, 0.0]),
                            np.array([0.0, 2 * b]), [2 * k, 2 * k + 1]))
            else:
                g, t = np.tanh(a), np.tanh(b)
                out.append(((1 + g) * t, g,
                            np.array([(1 - g * g) * t, (1 + g) * (1 - t * t)]),
                            np.array([1 - g * g, 0.0]), [2 * k, 2 * k + 1]))
        if self.m % 2:
            a = q[-1]
            if self.kind == 'plane':
                out.append((a * a, None, np.array([2 * a]), None, [q.size - 1]))
            else:
                t = np.tanh(a)
                out.append((t, None, np.array([1 - t * t]), None,
                            [q.size - 1]))
        return out

    def _parts(self, theta, shift):
        """Everything :meth:`gain` and :meth:`gain_vjp` share (the last
        point's kept: a search asks for the gain of a point, then for its
        gradient)."""
        key = (theta.tobytes(), shift)
        if self._last is not None and self._last[0] == key:
            return self._last[1]
        parts = self._compute_parts(theta, shift)
        self._last = (key, parts)
        return parts

    def _compute_parts(self, theta, shift):
        m, P = self.m, self.P
        F = theta[:m * P].reshape(m, P)
        h = theta[m * P:m * P + P]
        q = theta[m * P + P:]
        M = self.Ae - F @ self.Ce
        c = h @ self.Ce
        eye = np.eye(m)
        if self.kind == 'plane':
            scale = 1.0 / self.radius
            S = (M - self.center * eye) * scale + shift * eye
            lead = 1.0
        else:       # χ(S/(1 − δ)) made monic in M for Ackermann
            scale = 1.0 / (self.radius * (1 - shift))
            S = (M - self.center * eye) * scale
            lead = (self.radius * (1 - shift)) ** m
        coef = self._coefficients(q)
        factors = [S @ S + a * S + b * eye if b is not None else S + a * eye
                   for a, b, _, _, _ in coef]
        chi = eye
        for f in factors:
            chi = chi @ f
        rows = np.empty((m, m))
        rows[0] = c
        for j in range(1, m):
            rows[j] = rows[j - 1] @ M
        return dict(F=F, h=h, M=M, S=S, eye=eye, scale=scale, lead=lead,
                    coef=coef, factors=factors, chi=lead * chi, rows=rows)

    def stacked(self, theta, floor=1e-3):
        """``θ`` with every pole moved next to the region's edge (the
        shape of the optimum of the module text), ``F`` and ``h`` kept."""
        theta = theta.copy()
        q = theta[self.m * self.P + self.P:]
        q[:] = np.sqrt(floor) if self.kind == 'plane' else np.arctanh(
            1 - floor) * np.sign(q + 1e-300)
        return theta

    def gain(self, theta, shift=0.0):
        """The gain of ``θ``; ``shift > 0`` moves every pole that far
        further into the region (in the region's own variable)."""
        return self.gain_vjp(theta, None, shift)[0]

    def gain_vjp(self, theta, W, shift=0.0):
        """``(G, Jᵀ W)``: the gain of ``θ`` and the gradient in ``θ`` of
        ``⟨W, G(θ)⟩`` (reverse mode through Ackermann's formula; the
        second is None when ``W`` is)."""
        p = self._parts(theta, shift)
        m = self.m
        if 'G' not in p:
            e = np.zeros(m)
            e[-1] = 1.0
            with np.errstate(all='ignore'):
                p['w'] = np.linalg.solve(p['rows'], e)
                p['k'] = p['chi'] @ p['w']
            p['G'] = p['F'] + np.outer(p['k'], p['h'])
        w, k, G = p['w'], p['k'], p['G'].copy()
        if W is None:
            return G, None
        W = np.asarray(W, float).reshape(G.shape)
        gF = W.copy()
        gh = W.T @ k
        gk = W @ p['h']
        # k = χ w with O w = e: adjoints of χ and of the rows of O
        with np.errstate(all='ignore'):
            z = np.linalg.solve(p['rows'].T, p['chi'].T @ gk)
        gchi = np.outer(gk, w) * p['lead']
        grows = -np.outer(z, w)
        M, rows = p['M'], p['rows']
        gM = np.zeros((m, m))
        for j in range(m - 1, 0, -1):       # rows[j] = rows[j-1] @ M
            gM += np.outer(rows[j - 1], grows[j])
            grows[j - 1] += grows[j] @ M.T
        gh += self.Ce @ grows[0]            # rows[0] = h @ Ce
        # χ = f₁ f₂ ⋯ f_K: adjoint of each factor from prefix and suffix
        factors, S, eye = p['factors'], p['S'], p['eye']
        prefix = [eye]
        for f in factors[:-1]:
            prefix.append(prefix[-1] @ f)
        suffix = eye
        gS = np.zeros((m, m))
        gq = np.zeros(theta.size - m * self.P - self.P)
        for f, pre, (a, b, da, db, idx) in zip(
                factors[::-1], prefix[::-1], p['coef'][::-1]):
            gf = pre.T @ gchi @ suffix.T
            suffix = f @ suffix
            if b is None:                   # S + α
                gS += gf
                gq[idx] += np.trace(gf) * da
            else:                           # S² + α S + β
                gS += gf @ S.T + S.T @ gf + a * gf
                gq[idx] += np.sum(gf * S) * da + np.trace(gf) * db
        gM += gS * p['scale']
        gF -= gM @ self.Ce.T                # M = Ae − F Ce
        return G, np.concatenate([gF.ravel(), gh, gq])

    def jacobian(self, theta, shift=0.0, step=1e-6):
        """Central differences of :meth:`gain`: ``(G.size, θ.size)`` (a
        check on :meth:`gain_vjp`)."""
        cols = []
        for i in range(theta.size):
            d = np.zeros_like(theta)
            d[i] = step * max(1.0, abs(theta[i]))
            cols.append((self.gain(theta + d, shift) -
                         self.gain(theta - d, shift))
                        .ravel() / (2 * d[i]))
        return np.stack(cols, axis=1)


def placed_polish(obj, region, G0, seed=0, iterations=1500, rounds=4,
                  enough=None, draws=DRAWS):
    """Polish ``G0`` over the gains of :class:`PoleMap` on ``obj`` (a
    refinement :class:`~controlext.synthesis.objective.Objective`).

    Returns ``(γ, G)`` of a gain whose computed poles are in ``region``
    and that meets ``obj``'s other constraints, or None where the region
    is not one half-plane or disk, the map is singular at the start or no
    such gain was found.  It returns as soon as it finds a gain of norm
    ``enough`` or less (a floor no gain beats).  A result that is a
    cluster held inside the region gets ``draws`` more maps (module
    text).
    """
    try:
        edges = region.edges()
    except Exception:       # a sector, or an intersection with one
        return None
    if len(edges) != 1:
        return None
    # the region is built in: the inner objective keeps the other
    # constraints (gain bound, norm bounds, limits) as penalties
    inner = _without_region(obj)
    best = None
    rng = np.random.default_rng(seed)
    for stacked in (False, True):
        G, behind = G0, np.inf
        for _ in range(rounds):
            try:
                pmap = PoleMap(obj.prob, edges[0], G, rng)
            except np.linalg.LinAlgError:
                break
            first = G is G0
            theta = pmap.stacked(pmap.theta0) if stacked and first \
                else pmap.theta0
            # the stacked start races the result of the other: it goes on
            # past a sixth of its budget only within RACE_TIE of it
            race = None if not (stacked and first and best is not None) \
                else (iterations // 6, best[0] * (1 + RACE_TIE))
            # a new map starts next to its optimum
            out = _search(pmap, obj, inner, theta,
                          iterations if first else iterations // 3, race)
            if out is None:
                break
            G, excess, candidate = out
            if candidate is not None and (best is None or
                                          candidate[0] < best[0]):
                best, held = candidate, max(excess, 0.0)
                if enough is not None and best[0] <= enough:
                    return best
            # the gain realises the polynomial only as well as the
            # Ackermann solve is conditioned: where BFGS drifted to a
            # nearly unobservable (M, c), start a new map at the gain
            # it realised, poles and all, while that halves the excess
            if excess <= 0 or excess > 0.5 * behind:
                break
            behind = excess
    # a cluster of five or more poles is held inside by as much as its
    # realisation splits it, which depends on the map's (F, h): where
    # the best result is such a cluster, held in, more maps are drawn at
    # its gain and the best result kept
    scale = _scale(edges[0])
    if draws and best is not None and held > HOLD * scale and near_edge(
            region, np.linalg.eigvals(obj.Ae - best[1] @ obj.Ce),
            NEAR * scale) >= CLUSTER:
        for _ in range(draws):
            try:
                pmap = PoleMap(obj.prob, edges[0], best[1], rng)
            except np.linalg.LinAlgError:
                break
            out = _search(pmap, obj, inner, pmap.theta0, iterations // 3)
            if out is not None and out[2] is not None and \
                    out[2][0] < best[0]:
                best = out[2]
                if enough is not None and best[0] <= enough:
                    break
    return best


def _search(pmap, obj, inner, theta, iterations, race=None):
    """BFGS over ``pmap`` from ``theta``: ``(G, excess, candidate)`` with
    ``G`` the gain found with the poles on the edge, ``excess`` how far
    its computed poles are outside the region and ``candidate`` the
    ``(γ, G)`` of a gain whose computed poles are in it (found by holding
    the poles further inside by the excess, until none is left), or None
    if the map is singular or the search lost its ``race = (steps,
    level)``: above ``level`` after ``steps`` steps."""

    def f(theta, grad=True, above=None, shift=0.0):
        lost = np.inf, (np.zeros_like(theta) if grad else None)
        try:
            G = pmap.gain(theta, shift)
            if not np.all(np.isfinite(G)):
                return lost
            value, g = inner(G.ravel(), grad=grad, above=above)
            if not grad or not np.isfinite(value):
                return value, (np.zeros_like(theta) if grad else None)
            g = pmap.gain_vjp(theta, g, shift)[1]
        except np.linalg.LinAlgError:
            return lost         # (M, c) unobservable: no Ackermann gain
        return (value, g) if np.all(np.isfinite(g)) else lost

    steps = 0

    def behind(x, fx):
        nonlocal steps
        steps += 1
        return steps > race[0] and fx > race[1]

    shift, first = 0.0, None
    for _ in range(12):
        theta, value = bfgs(functools.partial(f, shift=shift), theta,
                            iterations if shift == 0 else iterations // 4,
                            stop=behind if shift == 0 and race else None,
                            stall=40, stall_tol=1e-9,
                            creep=CREEP if shift == 0 else None)
        if race and shift == 0 and steps > race[0] and value > race[1]:
            return None         # lost the race
        if not np.isfinite(value):
            return first and (*first, None)
        G = pmap.gain(theta, shift)
        excess = obj.margin(G)[0]
        if first is None:
            first = (G, excess)
        if excess <= 0:
            gamma = obj.norm(G)
            return (*first, (gamma, G) if np.isfinite(gamma) else None)
        # step by the excess: doubling overshoots (scalar plant, N = 5:
        # 1.085x against 1.051x with one map)
        shift += excess / pmap.radius + 1e-4
        if pmap.kind == 'circle' and shift >= 0.5:
            break
    return (*first, None)


def _scale(edge):
    """The scale of an edge ``(kind, centre, radius)``: a circle's radius,
    a line's distance from the origin (at least 1)."""
    kind, center, radius = edge
    return radius if kind == 'circle' else max(abs(center), radius)


def near_edge(region, lam, width):
    """How many of the poles ``lam`` lie within ``width`` of the edge of
    ``region`` (or outside it)."""
    return int(np.count_nonzero(region.margins(lam).max(axis=1) >= -width))


def _without_region(obj):
    """A copy of ``obj`` that does not look at the region (its limits,
    built with the region, stay)."""
    import copy
    inner = copy.copy(obj)
    inner.region = None
    inner._last = None
    inner.reset_best()
    return inner
