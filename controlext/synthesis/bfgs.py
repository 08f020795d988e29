"""BFGS for nonsmooth functions, with a weak-Wolfe line search.

On a locally Lipschitz function that is smooth almost everywhere — a
maximum of smooth pieces, such as an H∞ norm over a gain — BFGS with an
inexact line search that only asks for sufficient decrease and a weak
curvature condition converges to Clarke-stationary points in practice
(Lewis & Overton, *Nonsmooth optimization via quasi-Newton methods*,
Math. Program. 141, 2013); it is the engine of HIFOO and of
:mod:`controlext.synthesis.refine`.

Examples
--------
A kink at ``x0 = 1`` and a smooth valley in ``x1``:

>>> import numpy as np
>>> from controlext.synthesis.bfgs import bfgs
>>> def f(x, grad=True, above=None):
...     value = abs(x[0] - 1) + 2 * (x[1] + 0.5) ** 2
...     g = np.array([np.sign(x[0] - 1), 4 * (x[1] + 0.5)])
...     return value, (g if grad else None)
>>> x, fx = bfgs(f, np.array([3.0, 2.0]), 200)
>>> np.round(x, 4).tolist(), bool(fx < 1e-6)
([1.0, -0.5], True)
"""

import numpy as np

__all__ = ['bfgs']


def bfgs(f, x0, maxiter, stop=None, stall=10, stall_tol=1e-7, creep=None,
         size=abs):
    """BFGS with a weak-Wolfe bisection line search (Lewis & Overton).

    ``f(x, grad=True)`` returns ``(value, gradient)`` (``(value, None)``
    with ``grad=False``) and may return ``inf`` outside its domain; the
    line search asks for the gradient only at points that pass the
    sufficient-decrease test.  ``stop(x, fx)`` ends the run early when it
    returns True; the run also ends when ``stall`` iterations improved
    ``f`` by less than ``stall_tol`` (relative): on a nonsmooth objective
    BFGS otherwise keeps creeping towards the kink.  ``creep = (steps,
    rtol)`` adds a longer window: the run ends when ``steps`` iterations
    improved ``f`` by less than ``rtol`` (a slow steady creep, which the
    short window never sees stall).  Both are relative to ``size(f)``
    (default ``|f|``).
    """
    x = np.array(x0, dtype=float)
    fx, gx = f(x)
    if not np.isfinite(fx):
        return x, fx
    nvar = x.size
    H = np.eye(nvar) / max(1.0, np.linalg.norm(gx))
    history = [fx]
    for _ in range(maxiter):
        if stop is not None and stop(x, fx):
            break
        if len(history) > stall and \
                history[-stall - 1] - fx <= stall_tol * size(fx):
            break
        if creep is not None and len(history) > creep[0] and \
                history[-creep[0] - 1] - fx <= creep[1] * size(fx):
            break
        d = -H @ gx
        if gx @ d >= 0:
            H = np.eye(nvar) / max(1.0, np.linalg.norm(gx))
            d = -H @ gx
        slope = gx @ d
        lo, hi, t = 0.0, np.inf, 1.0
        found = False
        for _ in range(40):
            xn = x + t * d
            fn, gn = f(xn, grad=False, above=fx + 1e-4 * t * slope)
            if not fn <= fx + 1e-4 * t * slope:
                hi = t
            else:
                fn, gn = f(xn)
                if gn @ d >= 0.9 * slope:
                    found = True
                    break
                lo = t
            t = 0.5 * (lo + hi) if np.isfinite(hi) else 2.0 * lo
        if not found:
            fn, gn = f(xn)      # the true value, not a bound
            if not (np.isfinite(fn) and fn < fx):
                break
        s, y = xn - x, gn - gx
        x, fx, gx = xn, fn, gn
        history.append(fx)
        sy = s @ y
        if sy > 1e-16:
            rho = 1.0 / sy
            Hy = H @ y
            H = H + ((sy + y @ Hy) * rho**2) * np.outer(s, s) \
                - rho * (np.outer(Hy, s) + np.outer(s, Hy))
        if np.linalg.norm(s) <= 1e-12 * max(1.0, np.linalg.norm(x)):
            break
    return x, fx
