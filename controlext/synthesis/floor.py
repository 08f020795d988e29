"""The floor: the optimal H∞ filter level with no constraint at all.

``γ∞*`` is the least H∞ norm from noise to estimation error that *any*
causal linear estimator reaches on the plant — of any structure or order,
without a pole region (the central H∞ filter is of the plant's order, so
one Luenberger gain attains it to any precision).  No observer of this
package, coupled or not, can be below it; a design at it has no headroom.

Continuous time with noise on every measurement: bisection on the filter
Riccati equation (milliseconds).  Otherwise (discrete time, noise-free
measurements, a Riccati bisection that fails): the bounded-real LMI with
no region, which is exact for one copy.

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
from .riccati import hinf_filter_level

if TYPE_CHECKING:
    from .problem import ObserverProblem

__all__ = ['filter_floor']


def filter_floor(problem: ObserverProblem, solver: str | None = None,
                 rtol: float = 1e-7, max_states: int = 40) -> float | None:
    """``γ∞*`` of ``problem``'s one-copy estimation problem, or None when
    neither route gives it (the LMI is not tried above ``max_states``
    states; the floor only informs, it holds no design back)."""
    one = problem.single()
    if not one.dt and np.linalg.matrix_rank(one.Dw @ one.Dw.T) == one.p:
        try:
            level = hinf_filter_level(one.A, one.C, one.Bw, one.Dw, one.Cz,
                                      rtol=rtol)
        except (ParameterError, np.linalg.LinAlgError):
            level = np.inf
        if np.isfinite(level):
            return float(level)
    if one.n > max_states:
        return None
    from .lmi import solve_observer_lmi
    try:
        sol = solve_observer_lmi(one, None, margin=1.0, solver=solver)
    except (SolverError, ParameterError):
        return None
    return float(sol.gamma_convex)
