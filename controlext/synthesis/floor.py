"""The floor: the optimal filter level with no constraint at all.

``γ∞*`` is the least H∞ norm from noise to estimation error that *any*
causal linear estimator reaches on the plant — of any structure or order,
without a pole region (the central H∞ filter is of the plant's order, so
one Luenberger gain attains it to any precision).  No observer of this
package, coupled or not, can be below it; a design at it has no headroom.

Continuous time with noise on every measurement: bisection on the filter
Riccati equation (milliseconds).  Otherwise (discrete time, noise-free
measurements, a Riccati bisection that fails): the bounded-real LMI with
no region, which is exact for one copy (with noise on every measurement
solved again at clarabel's tolerances :data:`LOOSER` where it ends
``optimal_inaccurate`` at the defaults).

For the H2 norm the floor is the Kalman filter's (``criterion='h2'``):
the Riccati equation where every measurement is noisy, else the H2 LMI
with no region, exact for one copy as well.

Examples
--------
>>> import controlext as cx
>>> from controlext.synthesis import ObserverProblem
>>> from controlext.synthesis.floor import filter_floor
>>> prob = ObserverProblem([[-0.5]], [[1.0]], Bw=[[1.0, 0.0]],
...                        Dw=[[0.0, 1.0]])
>>> round(filter_floor(prob), 6)         # 1 / sqrt(1.25)
0.894427
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..exceptions import ParameterError, SolverError
from .riccati import hinf_filter_level, kalman_filter

if TYPE_CHECKING:
    from .problem import ObserverProblem

__all__ = ['filter_floor']


def filter_floor(problem: ObserverProblem, solver: str | None = None,
                 rtol: float = 1e-7, max_states: int = 40,
                 criterion: str = 'hinf') -> float | None:
    """``γ∞*`` (or, with ``criterion='h2'``, the Kalman filter's H2 norm)
    of ``problem``'s one-copy estimation problem, or None when neither
    route gives it (the LMI is not tried above ``max_states`` states; the
    floor only informs, it holds no design back).  For several plant
    models, the largest of the models' floors: the worst case of one
    gain on all is above each."""
    if len(problem.members) > 1:
        levels = [filter_floor(member, solver, rtol, max_states, criterion)
                  for member in problem.members]
        known = [level for level in levels if level is not None]
        return max(known) if known else None
    one = problem.single()
    noisy = np.linalg.matrix_rank(one.Dw @ one.Dw.T) == one.p
    level = np.inf
    if criterion == 'h2' and noisy:
        try:
            level = kalman_filter(one.A, one.C, one.Bw, one.Dw, one.Cz,
                                  one.dt)[1]
        except (ParameterError, np.linalg.LinAlgError):
            pass
    elif not one.dt and noisy:
        try:
            level = hinf_filter_level(one.A, one.C, one.Bw, one.Dw, one.Cz,
                                      rtol=rtol)
        except (ParameterError, np.linalg.LinAlgError):
            pass
    if np.isfinite(level):
        return float(level)
    if one.n > max_states:
        return None
    from .criteria import Criteria
    from .lmi import solve_observer_lmi
    # a second, looser solve only with noise on every sensor: without it
    # the problem is singular, its optimum often approached only as the
    # gain grows, and a looser solve's level there is checked against
    # nothing
    tries: list[dict[str, float]] = [{}]
    if noisy and (solver is None or str(solver).upper() == 'CLARABEL'):
        tries += LOOSER
    for options in tries:
        try:
            sol = solve_observer_lmi(one, None, margin=1.0, solver=solver,
                                     solver_options=options,
                                     criteria=Criteria(criterion))
        except SolverError as exc:
            if exc.status != 'optimal_inaccurate':
                return None
        except ParameterError:
            return None
        else:
            return float(sol.gamma_convex)
    return None


#: clarabel's tolerances, loosest last, for a floor whose LMI ended
#: 'optimal_inaccurate' at its defaults (1e-8), as it does on about one
#: random discrete plant with noisy sensors in ten: at 1e-7 it ends
#: 'optimal' on most of them (14 of 19), at most 1.2e-4 above the level a
#: Riccati gain reaches, well inside the 0.1 % the floor is used with;
#: clarabel 0.9 (the declared lower bound) needs 1e-6 on the discrete
#: plant of tests/test_tradeoff.py, and ends 3.6e-5 above its level
LOOSER = ({'tol_gap_abs': 1e-7, 'tol_gap_rel': 1e-7, 'tol_feas': 1e-7},
          {'tol_gap_abs': 1e-6, 'tol_gap_rel': 1e-6, 'tol_feas': 1e-6})
