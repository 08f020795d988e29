"""Rates and the tolerances every stage judges them by: one definition
each, shared by verification, the trade-off report and the limits.

Examples
--------
>>> from controlext.synthesis.rates import decay_rate
>>> decay_rate([-1 + 2j, -1 - 2j, -3])
1.0
"""

import numpy as np

__all__ = ['decay_rate', 'REGION_TOL', 'STABILITY_TOL', 'SETTLING_BAND']

#: tolerance on region margins (absolute, scaled by the pole magnitude)
REGION_TOL = 1e-6
#: an error pole closer than this (relative) to the stability boundary
#: does not decay: it is a mode the gain did not move, to rounding
STABILITY_TOL = 1e-9
#: the settling band, relative to the error's start (the 2 % settling
#: time of the trade-off report and of settling_time=)
SETTLING_BAND = 0.02


def decay_rate(poles, dt=0) -> float:
    """Rate of convergence of a system with the given poles:
    ``−max Re λ``, or ``−ln max |λ| / dt`` in discrete time (``inf``
    without poles).

    Parameters
    ----------
    poles : array_like
        The poles.
    dt : float or bool, optional
        Timebase (0: continuous time; True: unit step).

    Returns
    -------
    float
    """
    poles = np.asarray(poles, dtype=complex)
    if poles.size == 0:
        return float('inf')
    if dt:
        rho = np.max(np.abs(poles))
        dt = 1.0 if dt is True else float(dt)
        return float('inf') if rho == 0 else float(-np.log(rho) / dt)
    return float(-np.max(poles.real))
