"""The convex stage: one certified design for any observer problem.

:func:`convex_stage` chooses the route for any
:class:`~controlext.synthesis.problem.ObserverProblem` — Luenberger,
coupled, GI, augmented GI, coupled GI — and returns a typed
:class:`ConvexResult` (gain, certified bound, γ*, solver statistics):

* more than one copy (unless ``method='lmi'``): the one-copy design of the
  same problem embedded as ``G = I_N ⊗ L`` — every copy runs the same
  observer, so the averaged error and its certificate are the one-copy
  ones (the coupled LMI of Theorem 3.10 has the same γ in every case
  measured, at ``(N n)^3.7`` instead of ``n^3.7``);
* ``'riccati'``: the filter Riccati equation (continuous time, noise on
  every measurement, no region or a decay half-plane: for ``Re s <= -σ``
  the plant shifted by ``σ``); for ``objective='h2'`` with no region and no
  norm bound, the Kalman filter (continuous or discrete), which is the
  H2 optimum;
* ``'modal'``: the LMI on the modes outside or near the region
  (:mod:`~controlext.synthesis.modal`);
* ``'lmi'``: the two-stage LMI of :mod:`~controlext.synthesis.lmi`;
* ``'auto'``: Riccati without a region, else the modal LMI where it
  applies, else the full LMI up to ``lmi_max_states`` states and the
  shifted Riccati design above.

Examples
--------
>>> import controlext as cx
>>> from controlext.synthesis import ObserverProblem, SynthesisOptions
>>> from controlext.synthesis.convex import convex_stage
>>> prob = ObserverProblem(A=[[-1.0, 1.0], [-1.0, 0.0]], C=[[1.0, 2.0]],
...                        copies=2)
>>> res = convex_stage(prob, cx.HalfPlane(1.0), SynthesisOptions())
>>> res.method, res.G.shape, res.luenberger.G.shape
('embedded lmi', (4, 2), (2, 1))
"""

from dataclasses import dataclass, field

import numpy as np

from ..exceptions import (ArgumentError, ParameterError, SolverError,
                          VerificationError)
from .lmi import solve_observer_lmi
from .modal import modal_applies, modal_problem
from .placement import interior_poles, partial_gain, place_gain
from .regions import Disk, HalfPlane
from .riccati import (hinf_filter_gain, hinf_filter_level, kalman_filter,
                      regularisations)
from .verify import verify_design

__all__ = ['ConvexResult', 'convex_stage', 'riccati_applies']


@dataclass
class ConvexResult:
    """A certified gain from the convex stage.

    Attributes
    ----------
    G : ndarray
        The gain (``problem.gain_shape``).
    gamma_bound : float
        Certified bound on the H∞ norm of its error system.
    gamma_convex : float
        The convex problem's optimum ``γ*`` (its infimum where the
        optimum is not attained).
    method : str
        ``'lmi'``, ``'modal lmi'``, ``'riccati'``, ``'shifted riccati'``,
        or ``'embedded …'`` for a coupled problem's one-copy design.
    stage : str
        ``'lmi'`` or ``'riccati'``: what produced the gain.
    solver, status : str
        Solver and final status.
    stats : dict
        Solver statistics of each solve.
    luenberger : ConvexResult or None
        For an embedded design, the one-copy result it embeds.
    report : DesignReport or None
        Its verification; None for a placed gain whose poles missed the
        region, which is only a start for refinement.
    certificate : ndarray or None
        The LMI's Lyapunov matrix ``X`` that certifies ``gamma_bound``
        and the region for ``G`` (``X (Ae − G Ce)`` in the bounded-real
        and region LMIs); None for the Riccati, placed and embedded
        routes (an embedded design's is its ``luenberger`` result's).
    """
    G: np.ndarray
    gamma_bound: float
    gamma_convex: float
    method: str
    stage: str
    solver: str
    status: str = 'optimal'
    stats: dict = field(default_factory=dict)
    luenberger: 'ConvexResult | None' = None
    report: object = None
    certificate: np.ndarray | None = None


def riccati_applies(problem, region, criteria=None):
    """Can a Riccati equation give a certified design?  The H∞ filter's
    (continuous time, no region or a decay half-plane) for the plain H∞
    design; the Kalman filter's (no region) for the plain H2 design; noise
    on every measurement for both; one plant model (the filter of one
    model is no common design of several)."""
    if problem.copies != 1 or len(problem.members) > 1 or \
            np.linalg.matrix_rank(problem.Dw @ problem.Dw.T) != problem.p:
        return False
    if criteria is None or criteria.default:
        return not problem.dt and (region is None or
                                   type(region) is HalfPlane)
    return criteria.objective == 'h2' and not criteria.bounds and \
        region is None


def convex_stage(problem, region, options):
    """The certified, verified convex design of ``problem`` in ``region``.

    Parameters
    ----------
    problem : ObserverProblem
        The generalised plant.
    region : Region or None
        Pole region of the error dynamics.
    options : SynthesisOptions
        ``method``, ``margin``, ``solver``, ``solver_options``,
        ``lmi_max_states`` and ``modal_guard`` are used.

    Returns
    -------
    ConvexResult
        With its verified ``report``.

    Raises
    ------
    ArgumentError
        If the requested ``method`` does not apply to the problem (before
        any solver runs).
    SolverError
        If no route gave a verified design; the message names each step
        that failed and what to try.

    Notes
    -----
    With ``method='auto'`` a route that fails numerically (a solver
    status, no Riccati solution, a gain that fails verification) hands
    over to the next: the full LMI, the shifted Riccati design, the LMI
    with another installed solver, and — with a region — a gain placed
    inside the region, from which refinement starts.
    ``stats['fallback']`` records what failed on the way.
    """
    method = options.method
    criteria = options.criteria.convex     # the limits are not convex
    if problem.copies > 1 and method != 'lmi':
        sub = convex_stage(problem.single(), region, options)
        G = problem.embed(sub.G)
        result = ConvexResult(
            G=G, gamma_bound=sub.gamma_bound, gamma_convex=sub.gamma_convex,
            method=f'embedded {sub.method}', stage=sub.stage,
            solver=sub.solver, status=sub.status,
            stats={'luenberger': sub.stats}, luenberger=sub)
        if sub.report is not None:      # else only a start, as sub is
            result.report = verify_design(problem, G, region, convex=result,
                                          criteria=criteria)
        return result
    failures = []
    for name, route in _routes(problem, region, options):
        try:
            result = route()
            result.report = verify_design(problem, result.G, region,
                                          convex=result, criteria=criteria)
        except VerificationError as exc:
            failures.append((name, exc))
            if name == 'placement' and options.refine and \
                    np.all(np.isfinite(result.G)):
                # the poles missed the region (an ill-conditioned pair):
                # no design to return, but a start refinement can push
                # inside the region
                result.stats['fallback'] = [(n, str(e))
                                            for n, e in failures]
                return result
            continue
        except (SolverError, ParameterError) as exc:
            failures.append((name, exc))
            continue
        if failures:
            result.stats['fallback'] = [(name, str(exc))
                                        for name, exc in failures]
        return result
    if method != 'auto':
        _refuse_forced(problem, region, options, failures)
    steps = '; '.join(f"{name}: {exc}" for name, exc in failures)
    last = failures[-1][1]
    raise SolverError(
        f"no convex route gave a verified design ({steps}); try a looser "
        "region, a larger margin= (1.1), another solver= or "
        "solver_options={'max_iter': 500}",
        status=getattr(last, 'status', 'failed'),
        stats={'fallback': [(name, str(exc)) for name, exc in failures]})


def _refuse_forced(problem, region, options, failures):
    """Raise the refusal of a forced ``method=``: what failed, and whether
    the default route designs the problem (tried before refusing)."""
    method = options.method
    steps = '; '.join(f"{name}: {exc}" for name, exc in failures)
    last = failures[-1][1]
    try:
        other = convex_stage(problem, region, options.replace(method='auto'))
    except (SolverError, VerificationError, ParameterError):
        other = None
    if other is None:
        advice = ("the default method='auto' found no design either: try "
                  "a looser region, a larger margin= (1.1) or another "
                  "solver=")
    else:
        advice = (f"the default method='auto' designs this problem (by its "
                  f"{other.method} route): omit method=, or pass "
                  "method='auto'")
    text = f"method={method!r} failed ({steps}); {advice}"
    if isinstance(last, SolverError):
        raise SolverError(text, status=last.status, stats=dict(
            last.stats, fallback=[(n, str(e)) for n, e in failures],
            designs_with='auto' if other is not None else None))
    raise type(last)(text)


def _NotApplicable(text):
    """The refusal of a forced route that does not apply to the problem,
    told from the problem alone (no solve)."""
    return ArgumentError(f"{text}; method='auto' chooses a route that "
                         "applies")


def _routes(problem, region, options):
    """The convex routes to try, in order: ``[(name, thunk), ...]``."""
    method = options.method
    criteria = options.criteria.convex     # the limits are not convex
    riccati_ok = riccati_applies(problem, region, criteria)
    if method == 'riccati' and not riccati_ok:
        raise _NotApplicable(
            "method='riccati' needs one continuous plant model, no pole "
            "region "
            "other than a decay half-plane, and noise on every measurement "
            "(Dw Dwᵀ nonsingular); for objective='h2' (the Kalman filter, "
            "either time domain) noise on every measurement, no region and "
            "no max_hinf=" if criteria.default or
            criteria.objective == 'h2'
            else "method='riccati' designs no bound on the H2 norm "
            "(max_h2=): use method='lmi'")
    split = None
    if method == 'modal' and not criteria.default:
        raise _NotApplicable("method='modal' designs the plain H∞ observer; "
                            f"for {criteria} use method='lmi'")
    if method in ('modal', 'auto') and criteria.default and \
            len(problem.members) == 1:
        split = modal_applies(problem, region, options.lmi_max_states,
                              options.modal_guard)
    if method == 'modal' and split is None:
        top = min(options.lmi_max_states, problem.n - 1)
        count = "one mode" if top <= 1 else f"between 1 and {top} modes"
        raise _NotApplicable(
            f"method='modal' needs one plant model and a pole region with "
            f"{count} of A outside "
            "or near it, and noise that does not reach the other modes "
            "(Bw = 0 or in the span of the slow Schur vectors)")
    lmi = ('lmi', lambda: _lmi_design(problem, region, options))
    riccati = ('shifted riccati' if region is not None else 'riccati',
               lambda: _riccati_design(problem, region, options.margin))
    if not criteria.default:
        riccati = ('kalman', lambda: _kalman_design(problem))
    modal = ('modal lmi', lambda: _modal_design(problem, region, options,
                                                split))
    other = [name for name in ('SCS', 'CLARABEL')
             if name != options.solver_name and name in _installed()]
    if method == 'lmi':
        # the LMI route retries on a balanced realisation scaled to unit
        # noise (the solver's tolerances are absolute), then with the other
        # installed solver, before it gives up
        routes = [lmi, ('lmi (rescaled)',
                        lambda: _rescaled_lmi(problem, region, options))]
        if other and options.solver is None and not options.solver_options:
            # (options given for the default solver are not another's)
            again = options.replace(solver=other[0],
                                    solver_options=FALLBACK_OPTIONS[other[0]])
            routes.append((f'lmi ({other[0]})',
                           lambda: _lmi_design(problem, region, again)))
        return routes
    if method == 'riccati':
        return [riccati]
    if method == 'modal':
        return [modal]
    large = problem.n > options.lmi_max_states
    routes = [modal] if split is not None else []
    if riccati_ok and (region is None or large):
        routes += [riccati, lmi]
    else:
        routes += [lmi] + ([riccati] if riccati_ok else [])
    if other and options.solver is None:
        # a fallback, so a bounded one (SCS took 70 s a solve on a
        # 10-state discrete plant it could not solve either)
        again = options.replace(solver=other[0],
                                solver_options=FALLBACK_OPTIONS[other[0]])
        routes.append((f'lmi ({other[0]})',
                       lambda: _lmi_design(problem, region, again)))
    routes.append(('placement', lambda: _placed_design(problem, region)))
    return routes


#: the fallback solver's budget: a few seconds per stage
FALLBACK_OPTIONS = {'SCS': {'max_iters': 20000, 'time_limit_secs': 10.0},
                    'CLARABEL': {'time_limit': 10.0}}


def _installed():
    import cvxpy as cp
    return cp.installed_solvers()


def _placed_design(problem, region):
    """A gain with the error poles placed inside the region (or the
    stability region): no bound to certify, a start for refinement.  Of
    the placement of the poles outside the region only
    (:func:`~controlext.synthesis.placement.partial_gain`) and that of
    all of them, the one whose poles are deeper inside (on every plant
    model: the gains are placed on the nominal one)."""
    stable = Disk(1.0) if problem.dt else HalfPlane(0.0)
    target = region if region is not None else stable

    def worst(L):
        return max(max(target.worst_margin(lam), stable.worst_margin(lam))
                   for lam in (np.linalg.eigvals(member.A - L @ member.C)
                               for member in problem.members))

    gains, failure = [], None
    for place in (lambda: partial_gain(problem.A, problem.C, target, stable,
                                       problem.dt),
                  lambda: place_gain(problem.A, problem.C, interior_poles(
                      problem.A, target, problem.dt)),
                  lambda: riccati_placement(problem.A, problem.C, target,
                                            problem.dt)):
        try:
            L = place()
        except (ParameterError, np.linalg.LinAlgError, ValueError) as exc:
            failure = exc
            continue
        if np.all(np.isfinite(L)):
            gains.append((worst(L), len(gains), L))
    if not gains:
        raise failure if isinstance(failure, ParameterError) else \
            ParameterError(f"pole placement failed: {failure}")
    L = min(gains)[2]
    return ConvexResult(G=L, gamma_bound=None, gamma_convex=float('nan'),
                        method='placement', stage='placement',
                        solver='placement')


#: the Riccati placement aims at the region shrunk by this share of its
#: size, so that rounding keeps the poles inside
SHRINK = 0.02


def riccati_placement(A, C, region, dt=0):
    """A gain putting every pole of ``A − L C`` inside a half-plane or a
    disk region, from a Riccati equation rather than eigenvalue
    assignment: the filter Riccati gain (identity weights) of the plant
    mapped so that the region, slightly shrunk, becomes the stability
    region (``A + σ I`` for ``Re s ≤ −σ``; ``(A − c I) / ρ`` for the disk
    of centre ``c`` and radius ``ρ``).  It exists whenever the pair is
    detectable in the region, and stays accurate on defective and
    nearly unobservable plants, where pole placement does not.

    Examples
    --------
    >>> import numpy as np
    >>> import controlext as cx
    >>> from controlext.synthesis.convex import riccati_placement
    >>> A, C = np.array([[1.0, 1.0], [0.0, 1.0]]), np.array([[1.0, 0.0]])
    >>> L = riccati_placement(A, C, cx.Disk(0.5), dt=1)
    >>> bool(np.max(np.abs(np.linalg.eigvals(A - L @ C))) < 0.5)
    True
    """
    import scipy.linalg as la
    n, p = A.shape[0], C.shape[0]
    if type(region) is HalfPlane and not dt:
        sigma = region.decay + SHRINK * max(1.0, abs(region.decay))
        As = A + sigma * np.eye(n)
        try:
            P = la.solve_continuous_are(As.T, C.T, np.eye(n), np.eye(p))
        except (np.linalg.LinAlgError, ValueError) as exc:
            raise ParameterError(f"Riccati placement failed: {exc}") from exc
        return P @ C.T
    if type(region) is Disk:
        rho = region.radius * (1 - SHRINK)
        Ad = (A - region.center * np.eye(n)) / rho
        try:
            P = la.solve_discrete_are(Ad.T, C.T, np.eye(n), np.eye(p))
        except (np.linalg.LinAlgError, ValueError) as exc:
            raise ParameterError(f"Riccati placement failed: {exc}") from exc
        Ld = Ad @ P @ C.T @ np.linalg.inv(C @ P @ C.T + np.eye(p))
        return rho * Ld
    raise ParameterError(f"Riccati placement needs a half-plane (continuous "
                         f"time) or a disk region; found {region}")


def _kalman_design(problem):
    """The Kalman filter: the H2 optimum, its level certified."""
    args = (problem.C, problem.Bw, problem.Dw, problem.Cz, problem.dt)
    failure = None
    for reg in regularisations(problem.A, problem.Bw, problem.Dw):
        try:
            L, level = kalman_filter(problem.A, *args, reg=reg)
        except ParameterError as exc:
            failure = exc
            continue
        # the certificate: the (regularised) error covariance; rounding
        # of the Riccati solution is within the verification's tolerance
        return ConvexResult(G=L, gamma_bound=level, gamma_convex=level,
                            method='kalman', stage='riccati',
                            solver='riccati',
                            stats={'riccati': {'regularisation': reg}})
    raise failure


def _lmi_design(problem, region, options):
    sol = solve_observer_lmi(problem, region, options.margin,
                             options.solver, options.solver_options,
                             criteria=options.criteria.convex)
    return ConvexResult(G=sol.G, gamma_bound=sol.gamma_bound,
                        gamma_convex=sol.gamma_convex, method='lmi', stage='lmi',
                        solver=sol.stats['solver'], status=sol.status,
                        stats={'lmi': sol.stats}, certificate=sol.X)


def _rescaled_lmi(problem, region, options):
    """:func:`_lmi_design` on the problem with its noise channels scaled
    to unit size and its states balanced, the gain mapped back."""
    d = problem.state_scaling()
    scaled = problem.scaled(d)
    noise = max(scaled.noise_scale, 1e-300)
    scaled = scaled.noise_scaled(1 / noise)
    res = _lmi_design(scaled, region, options)
    res.G = problem.unscale_gain(res.G, d)
    # X of the scaled states and noise: D⁻¹ X D⁻¹ / (noise scale) certifies
    # the problem's (the bounded-real lemma of B s at γ s holds with X / s)
    inv = 1 / np.kron(np.ones(problem.copies), d)
    res.certificate = res.certificate * np.outer(inv, inv) / noise
    res.gamma_bound *= noise
    res.gamma_convex *= noise
    res.method = 'lmi'
    return res


def _modal_design(problem, region, options, split):
    """The LMI on the slow modes (:mod:`~controlext.synthesis.modal`)."""
    U, k = split
    sol = solve_observer_lmi(modal_problem(problem, U, k), region,
                             options.margin, options.solver,
                             options.solver_options)
    return ConvexResult(G=U[:, :k] @ sol.G, gamma_bound=sol.gamma_bound,
                        gamma_convex=sol.gamma_convex, method='modal lmi',
                        stage='lmi', solver=sol.stats['solver'],
                        status=sol.status,
                        stats={'lmi': sol.stats, 'modal': {'slow_states': k}})


def _riccati_design(problem, region, margin):
    """Central H∞ filter, shifted by the decay of a half-plane region.

    With ``As = A + σ I`` the error system of ``L`` is that of the shifted
    plant evaluated at ``s + σ``: its poles are those of the shifted error
    system moved by ``−σ``, and by the maximum modulus principle its H∞
    norm is at most the shifted one.  The level is therefore a certified
    bound — more conservative than the LMI's (1.2–2× measured), found in
    milliseconds.
    """
    sigma = 0.0 if region is None else region.decay
    As = problem.A + sigma * np.eye(problem.n)
    args = (problem.C, problem.Bw, problem.Dw, problem.Cz)
    failure = None
    for reg in regularisations(As, problem.Bw, problem.Dw):
        try:
            gopt = hinf_filter_level(As, *args, reg=reg)
            gbound = margin * gopt if gopt > 0 else 1e-9
            L = hinf_filter_gain(As, *args, gbound if margin > 1 else
                                 gopt * (1 + 1e-6), reg=reg)
        except ParameterError as exc:
            failure = exc
            continue
        return ConvexResult(G=L, gamma_bound=gbound, gamma_convex=gopt,
                            method='riccati' if region is None else
                            'shifted riccati', stage='riccati',
                            solver='riccati',
                            stats={'riccati': {'regularisation': reg}})
    raise failure
