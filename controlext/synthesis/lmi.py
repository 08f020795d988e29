"""The synthesis engine: the generalised observer LMI, solved by cvxpy.

For the problem of :class:`~controlext.synthesis.problem.ObserverProblem` the
variables are ``X = Xᵀ > 0``, ``Y = X G`` and ``γ``; with
``Z = X Ae − Y Ce`` and ``M = Y Dwe − X Bwe``

* continuous bounded-real lemma ``[[Z + Zᵀ, M, Czeᵀ], [*, −γI, 0], [*, *, −γI]] < 0``;
* discrete bounded-real lemma (Stein form)
  ``[[−X, Z, M, 0], [*, −X, 0, Czeᵀ], [*, *, −γI, 0], [*, *, *, −γI]] < 0``;
* a pole region with characteristic matrices ``(L, M_r)``:
  ``L ⊗ X + M_r ⊗ Zᵀ + M_rᵀ ⊗ Z ≤ 0``;
* for the H2 norm (``objective='h2'`` or ``max_h2=`` of
  :class:`~controlext.synthesis.criteria.Criteria`), with ``W = Wᵀ``:
  ``[[Z + Zᵀ, Czeᵀ], [*, −I]] < 0`` (discrete:
  ``[[X, Zᵀ, Czeᵀ], [*, X, 0], [*, *, I]] > 0``) and
  ``[[W, Mᵀ], [M, X]] >= 0``, so that ``X`` bounds the observability
  Gramian and ``‖T‖₂² <= tr(Mᵀ X⁻¹ M) <= tr W``.

The same ``X`` serves every constraint (the mixed H2/H∞ problem of
Khargonekar & Rotea, as MATLAB's ``h2hinfsyn`` solves it): the level
minimised is the objective's, and a bound on the other norm is a
constraint at that level.

The gain is ``G = X⁻¹ Y``. On plants with unstable modes the optimal γ is
usually not attained and ``X`` tends to singular, so the engine solves in
two stages: stage 1 finds ``γ*``; stage 2 fixes ``γ = margin · γ*`` and
maximises the smallest eigenvalue of ``X`` (with ``X ≤ λmax(X₁) I`` so the
problem stays bounded), which keeps ``G`` of moderate norm.  Where ``γ*``
is attained by a moderate gain (stage 1 ``optimal``, its gain at most ten
times the conditioned one's, verified at ``γ*`` and better by more than
0.1 %) the stage-1 gain is returned instead, certified at ``γ*``
(``stats['stage2']['kept'] = 'stage 1'``).  The level of
stage 2 is at least ``γ* + (margin − 1) · 10⁻³ · ‖Cze‖ (‖Bwe‖ + ‖Dwe‖)``,
so a problem whose optimum is ``γ* = 0`` still gets a moderate gain.

The returned certificate always comes from a solve that ended ``optimal``;
anything else raises :class:`~controlext.exceptions.SolverError` with the
status and statistics.  Stage 1 may end ``optimal_inaccurate`` when ``γ*``
is not attained: its value then only locates the optimum (recorded in
``stats['stage1']['status']``) and stage 2 is retried at slightly larger
margins.  A stage 2 that ends ``optimal_inaccurate`` is accepted only if
the extracted gain verifies — its true H∞ norm (slycot) is within the
level and its poles are in the region — and ``stats['stage2']['verified']``
records it: the numbers decide, not the status.

Examples
--------
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.lmi import solve_observer_lmi
>>> prob = ObserverProblem(A=[[-1.0, 1.0], [-1.0, 0.0]], C=[[1.0, 2.0]])
>>> sol = solve_observer_lmi(prob, margin=1.0)
>>> sol.status
'optimal'
"""

from dataclasses import dataclass, field
import time
import warnings

import numpy as np
import cvxpy as cp

from ..exceptions import SolverError
from .criteria import Criteria

__all__ = ['LMISolution', 'solve_observer_lmi', 'lmi_memory', 'available_memory',
           'check_lmi_memory']


@dataclass
class LMISolution:
    """Result of :func:`solve_observer_lmi`.

    Attributes
    ----------
    G : ndarray
        Gain ``X⁻¹ Y``.
    gamma_convex : float
        Optimal level ``γ*`` of stage 1 (the convex problem's optimum).
    gamma_bound : float
        Certified bound of the returned gain (``margin · γ*``).
    X, Y : ndarray
        The certificate: Lyapunov matrix and ``Y = X G``.
    status : str
        Solver status (always ``'optimal'`` for a returned solution).
    stats : dict
        Solver name, iterations and solve time of each stage.
    """
    G: np.ndarray
    gamma_convex: float
    gamma_bound: float
    X: np.ndarray
    Y: np.ndarray
    status: str
    stats: dict = field(default_factory=dict)


#: solvers whose 'optimal_inaccurate' means the iteration cap was reached
FIRST_ORDER = {'SCS'}


def _first_order(solver):
    return str(solver).upper() in FIRST_ORDER


#: peak memory of building and solving the observer LMI, in bytes, is
#: about LMI_BYTES * size ** LMI_POWER with size = N n + (noise inputs):
#: measured on random plants of 20, 30 and 40 states (57, 204, 525 MB
#: above the interpreter's own; `python benchmarks/lmi_memory.py`)
LMI_BYTES, LMI_POWER = 2.5e3, 3.3

#: the share of the memory available now that one LMI may take
LMI_MEMORY_SHARE = 0.5


def lmi_memory(problem) -> float:
    """The estimated peak memory (bytes) of the observer LMI of
    ``problem``.

    Examples
    --------
    >>> from controlext.synthesis import ObserverProblem
    >>> from controlext.synthesis.lmi import lmi_memory
    >>> prob = ObserverProblem(A=[[-1.0, 1.0], [-1.0, 0.0]], C=[[1.0, 2.0]])
    >>> lmi_memory(prob) < 1e6
    True
    """
    size = problem.copies * problem.n + problem.Bw.shape[1]
    return len(problem.members) * LMI_BYTES * float(size) ** LMI_POWER


def available_memory() -> float:
    """Bytes of memory available to this process now (``MemAvailable``
    of ``/proc/meminfo``, else the free physical pages; ``inf`` where
    neither can be read)."""
    try:
        with open('/proc/meminfo') as fh:
            for line in fh:
                if line.startswith('MemAvailable:'):
                    return float(line.split()[1]) * 1024
    except OSError:
        pass
    try:
        import os
        return float(os.sysconf('SC_AVPHYS_PAGES') *
                     os.sysconf('SC_PAGE_SIZE'))
    except (ValueError, OSError, AttributeError):
        return float('inf')


def check_lmi_memory(problem) -> None:
    """Refuse, before anything is built, an LMI that would not fit in
    memory: the interpreter would be killed, with nothing to catch."""
    need, have = lmi_memory(problem), available_memory()
    if need > LMI_MEMORY_SHARE * have:
        raise SolverError(
            f"the LMI of this problem ({problem.copies * problem.n} error "
            f"states) needs about {need / 2**30:.3g} GiB of memory and "
            f"{have / 2**30:.3g} GiB are available: it was not built.  "
            "method='auto' designs large plants by the shifted Riccati "
            "equation, and lmi_max_states= bounds the LMI's size",
            status='memory')


def solve_observer_lmi(problem, region=None, margin=1.02, solver=None,
                       solver_options=None, criteria=None):
    """Solve the observer LMI of ``problem`` in two stages.

    Parameters
    ----------
    problem : ObserverProblem
        The generalised plant.
    region : Region, optional
        Pole region for the error dynamics.
    margin : float, optional
        Stage 2 fixes ``γ = margin · γ*`` (``>= 1``); ``margin = 1`` skips
        stage 2 and returns the stage-1 gain.
    solver : str, optional
        cvxpy solver name (default ``'CLARABEL'``).
    solver_options : dict, optional
        Keyword arguments passed to the solver.
    criteria : Criteria, optional
        The norm minimised (the level ``γ`` is its bound) and the norm
        bounded (default: minimise the H∞ norm).

    Returns
    -------
    LMISolution
    """
    check_lmi_memory(problem)
    solver = solver or cp.CLARABEL
    opts = dict(solver_options or {})
    criteria = Criteria() if criteria is None else criteria
    X, Y, gamma, level, cons = _build(problem, region, criteria)
    # the H2 level enters squared (tr W <= γ²): stage 1 minimises γ² there
    squared = criteria.objective == 'h2'

    stage1 = cp.Problem(cp.Minimize(gamma), cons + level(gamma))
    stats = {'solver': solver}
    # When γ* is not attained (unstable modes) clarabel may end stage 1
    # 'optimal_inaccurate': its γ then only locates the optimum, and the
    # certificate must come from stage 2, which has to end 'optimal'.  A
    # first-order solver ends so at its iteration cap, where its γ locates
    # nothing (the fallback route's stage 2 then took three more capped
    # solves)
    accept = (cp.OPTIMAL, cp.OPTIMAL_INACCURATE) \
        if margin > 1 and not _first_order(solver) else (cp.OPTIMAL,)
    _solve(stage1, solver, opts, 'stage 1 (minimise γ)', stats, 'stage1',
           accept=accept)
    gamma_convex = float(np.sqrt(max(gamma.value, 0.0))) if squared else \
        float(gamma.value)
    Xv, Yv = X.value, Y.value
    X1, Y1 = Xv, Yv
    gbound = gamma_convex
    if margin > 1:
        n = Xv.shape[0]
        # X <= max(λmax(X₁), 1) I keeps stage 2 bounded; where γ* is not
        # attained X₁ tends to 0, and a bound at λmax(X₁) alone would keep
        # stage 2 at the same huge gain (scalar unstable plant, decay 2:
        # L = 4.9e8 for γ 1.00000000, against 154 at 1.0065 by Riccati)
        xmax = max(float(np.linalg.eigvalsh(0.5 * (Xv + Xv.T))[-1]), 1.0)
        inexact = stage1.status != cp.OPTIMAL
        tries = (margin, 1.05 * margin, 1.25 * margin) if inexact else \
            (margin,)
        # an absolute floor: when γ* is ~0 (the noise can be cancelled
        # exactly) margin·γ* would still demand γ ≈ 0 and a huge gain
        floor = (margin - 1) * 1e-3 * problem.noise_scale
        for k, factor in enumerate(tries):
            gbound = max(factor * gamma_convex, gamma_convex + floor)
            t = cp.Variable()
            stage2 = cp.Problem(cp.Maximize(t), cons + level(cp.Constant(
                gbound**2 if squared else gbound)) + [
                X >> t * np.eye(n), X << xmax * np.eye(n)])
            try:
                _solve(stage2, solver, opts, 'stage 2 (condition X)', stats,
                       'stage2', accept=(cp.OPTIMAL, cp.OPTIMAL_INACCURATE))
                if stage2.status != cp.OPTIMAL and not _verifies(
                        problem, region, X.value, Y.value, gbound,
                        criteria):
                    raise SolverError(
                        "stage 2 (condition X): solver ended with status "
                        f"'{stage2.status}' and its gain does not verify",
                        status=stage2.status, stats=stats)
                if stage2.status != cp.OPTIMAL:
                    stats.setdefault('stage2', {})['verified'] = True
                Xv, Yv = X.value, Y.value
                if stage1.status == cp.OPTIMAL and _stage1_is_better(
                        problem, region, X1, Y1, Xv, Yv, gamma_convex,
                        criteria):
                    Xv, Yv, gbound = X1, Y1, gamma_convex
                    stats.setdefault('stage2', {})['kept'] = 'stage 1'
                break
            except SolverError:
                if k + 1 < len(tries):
                    continue
                if inexact:
                    raise
                # stage 1's X is feasible for stage 2, so the failure is
                # numerical: keep the stage-1 certificate and record it
                stats.setdefault('stage2', {})['fallback'] = \
                    'stage 1 solution kept'
                gbound = gamma_convex
    Xv = 0.5 * (Xv + Xv.T)
    G = np.linalg.solve(Xv, Yv)
    return LMISolution(G=G, gamma_convex=gamma_convex, gamma_bound=gbound, X=Xv,
                       Y=Yv, status='optimal', stats=stats)


def _stage1_is_better(problem, region, X1, Y1, X2, Y2, gamma_convex,
                      criteria):
    """Is the stage-1 gain worth keeping over the conditioned one?

    Where ``γ*`` is attained the stage-1 gain is often of moderate norm
    too, and its true norm can be up to ``margin`` below the conditioned
    gain's.  It is kept when it verifies at ``γ*`` (true H∞ norm, poles
    in the region), its true norm is lower by more than 0.1 % and its
    norm is at most ten times the conditioned gain's (where ``γ*`` is not
    attained it is orders of magnitude larger, and is not kept)."""
    G1, G2 = _gain(X1, Y1), _gain(X2, Y2)
    if G1 is None or G2 is None or \
            not np.linalg.norm(G1, 2) <= 10 * np.linalg.norm(G2, 2):
        return False
    report = _verified(problem, region, G1, gamma_convex, criteria)
    other = _verified(problem, None, G2, None, criteria, check=False)
    return report is not None and criteria.value(report) < \
        (1 - 1e-3) * criteria.value(other)


def _verifies(problem, region, Xv, Yv, gbound, criteria):
    """Does the gain of an inexact solution pass the design verification
    (true norm within ``gbound``, poles in the region, norm bounds)?"""
    G = _gain(Xv, Yv)
    return G is not None and \
        _verified(problem, region, G, gbound, criteria) is not None


def _gain(Xv, Yv):
    """``G = X⁻¹ Y`` of a solution, or None."""
    if Xv is None or Yv is None:
        return None
    try:
        return np.linalg.solve(0.5 * (Xv + Xv.T), Yv)
    except np.linalg.LinAlgError:
        return None


def _verified(problem, region, G, gbound, criteria, check=True):
    """The design report of ``G`` if it verifies at ``gbound``, else None."""
    from ..exceptions import VerificationError
    from .verify import verify_design
    try:
        return verify_design(problem, G, region, gamma_bound=gbound,
                             method='lmi', criteria=criteria, check=check)
    except VerificationError:
        return None


def _build(problem, region, criteria):
    """Variables, ``level(g)`` (the constraints ``objective <= g``, with
    ``g`` squared for the H2 norm) and the other constraints: those of
    every model of ``problem.members``, with one ``X`` and one ``Y``."""
    shape = problem.gain_shape
    N = problem.Ae.shape[0]
    X = cp.Variable((N, N), symmetric=True, name='X')
    Y = cp.Variable(shape, name='Y')
    gamma = cp.Variable(nonneg=True, name='gamma')
    scale = max(1.0, max(np.linalg.norm(member.Ae, 2)
                         for member in problem.members))
    eps = 1e-9 * scale
    cons = [X >> eps * np.eye(N)]
    levels = []
    for member in problem.members:
        more, level = model_constraints(member, region, criteria, X, Y,
                                         eps)
        cons += more
        levels.append(level)
    return X, Y, gamma, lambda g: [c for level in levels
                                   for c in level(g)], cons


def model_constraints(problem, region, criteria, X, Y, eps):
    """The constraints of one model on ``(X, Y)`` and its ``level(g)``."""
    Ae, Ce, Bwe, Dwe, Cze = (problem.Ae, problem.Ce, problem.Bwe,
                             problem.Dwe, problem.Cze)
    N, q, nz = Ae.shape[0], Bwe.shape[1], Cze.shape[0]
    Z = X @ Ae - Y @ Ce
    M = Y @ Dwe - X @ Bwe
    discrete = bool(problem.dt)

    def brl(g):
        if discrete:
            blk = cp.bmat([
                [-X, Z, M, np.zeros((N, nz))],
                [Z.T, -X, np.zeros((N, q)), Cze.T],
                [M.T, np.zeros((q, N)), -g * np.eye(q), np.zeros((q, nz))],
                [np.zeros((nz, N)), Cze, np.zeros((nz, q)), -g * np.eye(nz)]])
        else:
            blk = cp.bmat([
                [Z + Z.T, M, Cze.T],
                [M.T, -g * np.eye(q), np.zeros((q, nz))],
                [Cze, np.zeros((nz, q)), -g * np.eye(nz)]])
        blk = 0.5 * (blk + blk.T)
        return blk << -eps * np.eye(blk.shape[0])

    cons = []
    if region is not None:
        for L, Mr in region.blocks():
            blk = cp.kron(L, X) + cp.kron(Mr, Z.T) + cp.kron(Mr.T, Z)
            cons.append(0.5 * (blk + blk.T) << 0)
    W = None
    if 'h2' in criteria.norms:
        W = cp.Variable((q, q), symmetric=True, name='W')
        if discrete:
            lyap = cp.bmat([
                [X, Z.T, Cze.T],
                [Z, X, np.zeros((N, nz))],
                [Cze, np.zeros((nz, N)), np.eye(nz)]])
            lyap = 0.5 * (lyap + lyap.T)
            cons.append(lyap >> eps * np.eye(lyap.shape[0]))
        else:
            lyap = cp.bmat([[Z + Z.T, Cze.T], [Cze, -np.eye(nz)]])
            lyap = 0.5 * (lyap + lyap.T)
            cons.append(lyap << -eps * np.eye(lyap.shape[0]))
        wblk = cp.bmat([[W, M.T], [M, X]])
        cons.append(0.5 * (wblk + wblk.T) >> 0)

    def bound(name, g):
        return [brl(g)] if name == 'hinf' else [cp.trace(W) <= g]

    for name, value in criteria.bounds:
        cons += bound(name, value**2 if name == 'h2' else value)
    return cons, lambda g: bound(criteria.objective, g)


def _solve(prob, solver, opts, what, stats, key, accept=(cp.OPTIMAL,)):
    start = time.perf_counter()
    try:
        with warnings.catch_warnings():
            # cvxpy warns on inaccurate solutions; the status decides here
            warnings.simplefilter('ignore', UserWarning)
            prob.solve(solver=solver, **opts)
    except cp.error.SolverError as exc:
        raise SolverError(f"{what}: the solver {solver} failed ({exc}); "
                          "the constraints may be infeasible (is the pole "
                          "region empty or unreachable?)",
                          status='solver_error', stats=stats) from exc
    info = prob.solver_stats
    stats[key] = {'status': prob.status,
                  'iterations': getattr(info, 'num_iters', None),
                  'solve_time': getattr(info, 'solve_time', None),
                  'wall_time': time.perf_counter() - start}
    if prob.status not in accept:
        hint = {'infeasible': 'no gain meets the constraints (is the pole '
                              'region reachable?)',
                'unbounded': 'the problem is unbounded',
                }.get(prob.status, 'the solution is not reliable')
        if _first_order(solver) and prob.status == cp.OPTIMAL_INACCURATE:
            hint += (" (it stopped at its iteration cap; solver_options="
                     "{'max_iters': ...} raises it)")
        raise SolverError(f"{what}: solver {solver} ended with status "
                          f"'{prob.status}': {hint}", status=prob.status,
                          stats=stats)


def decay_certificate(A, alpha, solver=None, solver_options=None):
    """Best-conditioned ``P`` with ``Aᵀ P + P A ≤ −2 α P`` (Lemma 3.3).

    Minimises ``κ`` subject to ``I ≤ P ≤ κ I``; returns ``(P, κ)``.

    Examples
    --------
    >>> from controlext.synthesis.lmi import decay_certificate
    >>> P, kappa = decay_certificate([[-2.0, 0.0], [0.0, -3.0]], 1.0)
    >>> round(kappa, 4)
    1.0
    """
    A = np.asarray(A, dtype=float)
    n = A.shape[0]
    P = cp.Variable((n, n), symmetric=True, name='P')
    kappa = cp.Variable(name='kappa')
    lyap = A.T @ P + P @ A + 2 * alpha * P
    prob = cp.Problem(cp.Minimize(kappa), [
        0.5 * (lyap + lyap.T) << 0, P >> np.eye(n), P << kappa * np.eye(n)])
    stats = {'solver': solver or cp.CLARABEL}
    _solve(prob, solver or cp.CLARABEL, dict(solver_options or {}),
           f'decay certificate (alpha = {alpha:g})', stats, 'certificate')
    Pv = 0.5 * (P.value + P.value.T)
    return Pv, float(kappa.value)


def common_certificate(problem, G, region=None, solver=None):
    """The least ``γ`` with one Lyapunov matrix ``X`` certifying the
    fixed gain ``G`` on every model of ``problem.members``: the H∞
    bounded-real LMI of each model's error system at ``γ`` and its
    region LMI, with the same ``X``.  Both are affine in the plant data,
    so the certificate holds on every plant in the models' convex hull.
    None where no such ``X`` is found (or the solution does not check
    out: every LMI is re-evaluated at the solver's ``X``).

    Examples
    --------
    >>> import controlext as cx
    >>> from controlext.synthesis import ObserverProblem
    >>> from controlext.synthesis.models import ModelSet
    >>> models = ModelSet([ObserverProblem([[-1.0]], [[1.0]]),
    ...                    ObserverProblem([[-2.0]], [[1.0]])])
    >>> # L = 1: poles -2 and -3, norms 1/2 and 1/3
    >>> round(common_certificate(models, [[1.0]], cx.HalfPlane(1.5)), 4)
    0.5
    """
    G = np.asarray(G, dtype=float)
    N = problem.Ae.shape[0]
    X = cp.Variable((N, N), symmetric=True)
    gamma = cp.Variable(nonneg=True)
    scale = max(1.0, max(np.linalg.norm(m.Ae, 2) for m in problem.members))
    eps = 1e-9 * scale
    cons = [X >> eps * np.eye(N), X << 1e6 * np.eye(N)]
    blocks = []
    for member in problem.members:
        Acl, Bcl, Ccl, _ = member.error_system(G)
        q, nz = Bcl.shape[1], Ccl.shape[0]
        Z, M = X @ Acl, X @ Bcl
        if member.dt:
            blk = cp.bmat([
                [-X, Z, M, np.zeros((N, nz))],
                [Z.T, -X, np.zeros((N, q)), Ccl.T],
                [M.T, np.zeros((q, N)), -gamma * np.eye(q),
                 np.zeros((q, nz))],
                [np.zeros((nz, N)), Ccl, np.zeros((nz, q)),
                 -gamma * np.eye(nz)]])
        else:
            blk = cp.bmat([[Z + Z.T, M, Ccl.T],
                           [M.T, -gamma * np.eye(q), np.zeros((q, nz))],
                           [Ccl, np.zeros((nz, q)), -gamma * np.eye(nz)]])
        blocks.append(0.5 * (blk + blk.T))
        if region is not None:
            for L, Mr in region.blocks():
                rb = cp.kron(L, X) + cp.kron(Mr, Z.T) + cp.kron(Mr.T, Z)
                blocks.append(0.5 * (rb + rb.T))
    cons += [blk << 0 for blk in blocks]
    prob = cp.Problem(cp.Minimize(gamma), cons)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')
            prob.solve(solver=solver or cp.CLARABEL)
    except (cp.error.SolverError, ValueError, ArithmeticError):
        return None
    if prob.status != cp.OPTIMAL or X.value is None:
        return None
    # the solver's word is checked: every LMI at its X, to a tolerance
    # relative to the blocks' size
    worst = max(float(np.linalg.eigvalsh(blk.value)[-1]) for blk in blocks)
    size = max(float(np.linalg.norm(blk.value, 2)) for blk in blocks)
    if worst > 1e-7 * max(size, 1.0) or \
            float(np.linalg.eigvalsh(X.value)[0]) <= 0:
        return None
    return float(gamma.value) * (1 + 1e-6) + 1e-9
