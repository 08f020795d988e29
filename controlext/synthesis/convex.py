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
  the plant shifted by ``σ``);
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

from ..exceptions import ArgumentError
from .lmi import solve_observer_lmi
from .modal import modal_applies, modal_problem
from .regions import HalfPlane
from .riccati import hinf_filter_gain, hinf_filter_level

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
    gamma_opt : float
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
    """
    G: np.ndarray
    gamma_bound: float
    gamma_opt: float
    method: str
    stage: str
    solver: str
    status: str = 'optimal'
    stats: dict = field(default_factory=dict)
    luenberger: 'ConvexResult' = None


def riccati_applies(problem, region):
    """Can the filter Riccati equation give a certified design?"""
    return (problem.copies == 1 and not problem.dt and
            (region is None or type(region) is HalfPlane) and
            np.linalg.matrix_rank(problem.Dw @ problem.Dw.T) == problem.p)


def convex_stage(problem, region, options):
    """The certified convex design of ``problem`` in ``region``.

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

    Raises
    ------
    ArgumentError
        If the requested ``method`` does not apply to the problem (before
        any solver runs).
    """
    method = options.method
    if problem.copies > 1 and method != 'lmi':
        sub = convex_stage(problem.single(), region, options)
        return ConvexResult(
            G=problem.embed(sub.G), gamma_bound=sub.gamma_bound,
            gamma_opt=sub.gamma_opt, method=f'embedded {sub.method}',
            stage=sub.stage, solver=sub.solver, status=sub.status,
            stats={'luenberger': sub.stats}, luenberger=sub)
    riccati_ok = riccati_applies(problem, region)
    if method == 'riccati' and not riccati_ok:
        raise ArgumentError("method='riccati' needs a continuous plant, no "
                            "pole region other than a decay half-plane, and "
                            "noise on every measurement (Dw Dwᵀ nonsingular)")
    split = None
    if method in ('modal', 'auto'):
        split = modal_applies(problem, region, options.lmi_max_states,
                              options.modal_guard)
    if method == 'modal' and split is None:
        top = min(options.lmi_max_states, problem.n - 1)
        count = "one mode" if top <= 1 else f"between 1 and {top} modes"
        raise ArgumentError(
            f"method='modal' needs a pole region with {count} of A outside "
            "or near it, and noise that does not reach the other modes "
            "(Bw = 0 or in the span of the slow Schur vectors)")
    if split is not None:
        return _modal_design(problem, region, options, split)
    if method == 'riccati' or (method == 'auto' and riccati_ok and (
            region is None or problem.n > options.lmi_max_states)):
        return _riccati_design(problem, region, options.margin)
    return _lmi_design(problem, region, options)


def _lmi_design(problem, region, options):
    sol = solve_observer_lmi(problem, region, options.margin,
                             options.solver, options.solver_options)
    return ConvexResult(G=sol.G, gamma_bound=sol.gamma_bound,
                        gamma_opt=sol.gamma_opt, method='lmi', stage='lmi',
                        solver=sol.stats['solver'], status=sol.status,
                        stats={'lmi': sol.stats})


def _modal_design(problem, region, options, split):
    """The LMI on the slow modes (:mod:`~controlext.synthesis.modal`)."""
    U, k = split
    sol = solve_observer_lmi(modal_problem(problem, U, k), region,
                             options.margin, options.solver,
                             options.solver_options)
    return ConvexResult(G=U[:, :k] @ sol.G, gamma_bound=sol.gamma_bound,
                        gamma_opt=sol.gamma_opt, method='modal lmi',
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
    gopt = hinf_filter_level(As, *args)
    gbound = margin * gopt if gopt > 0 else 1e-9
    L = hinf_filter_gain(As, *args, gbound if margin > 1 else
                         gopt * (1 + 1e-6))
    return ConvexResult(G=L, gamma_bound=gbound, gamma_opt=gopt,
                        method='riccati' if region is None else
                        'shifted riccati', stage='riccati', solver='riccati')
