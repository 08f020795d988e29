"""The validation vocabulary: every input check of the package.

One rule throughout: a value of the wrong *type* raises
:class:`~controlext.exceptions.ArgumentError`, a value of the right type
but an invalid *value* raises :class:`~controlext.exceptions.ParameterError`
(a wrong shape :class:`~controlext.exceptions.DimensionError`).  Messages
say what was expected and what was found; inputs are copied, never
modified; every check runs before any solver.
"""

from __future__ import annotations

import numbers
from typing import Any

import numpy as np
import control as ct

from ._typing import Array
from .exceptions import (ArgumentError, DimensionError, NotDetectableError,
                         ParameterError, RegionError)

__all__ = []


# -- numbers ----------------------------------------------------------------

def check_number(value, name, *, low=None, high=None, low_open=False,
                 integer=False, optional=False):
    """A real number (an ``int`` with ``integer=True``) within bounds.

    ``bool`` and strings are refused (``decay=True`` or ``decay="1"`` is a
    mistake, not a number); NaN and inf are refused.  ``low`` is inclusive
    unless ``low_open``; ``high`` is inclusive.
    """
    if value is None and optional:
        return None
    kind = numbers.Integral if integer else numbers.Real
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, kind):
        what = 'an integer' if integer else 'a real number'
        raise ArgumentError(f"{name} must be {what}; found "
                            f"{type(value).__name__} {value!r}")
    value = int(value) if integer else float(value)
    if not np.isfinite(value):
        raise ParameterError(f"{name} must be finite; found {value}")
    if low is not None and (value < low or (low_open and value == low)):
        sign = '>' if low_open else '>='
        raise ParameterError(f"{name} must be {sign} {low:g}; found "
                             f"{value:g}")
    if high is not None and value > high:
        raise ParameterError(f"{name} must be <= {high:g}; found {value:g}")
    return value


def check_copies(copies, minimum=1):
    """The number of coupled copies, an integer ``>= minimum``."""
    copies = check_number(copies, 'copies', integer=True)
    if copies < minimum:
        hint = " (use hinf_observer or gi_observer for one copy)" \
            if minimum > 1 else ""
        raise ParameterError(f"copies must be >= {minimum}; found "
                             f"{copies}{hint}")
    return copies


def check_choice(value, name, choices):
    """One of ``choices`` (strings)."""
    if not isinstance(value, str) or value not in choices:
        listed = ', '.join(repr(c) for c in choices)
        raise (ParameterError if isinstance(value, str) else ArgumentError)(
            f"{name} must be one of {listed}; found {value!r}")
    return value


def check_name(name):
    """A system name: a string or None."""
    if name is not None and not isinstance(name, str):
        raise ArgumentError(f"name must be a string; found "
                            f"{type(name).__name__} {name!r}")
    if name is not None and '.' in name:
        # python-control reserves '.' for subsystem signal names
        raise ParameterError(f"name must not contain '.' (python-control "
                             f"keeps it for subsystem signals); found "
                             f"{name!r}")
    return name


def check_system(name=None, inputs=None, outputs=None, states=None):
    """python-control's system keywords, checked: ``name`` a string;
    ``inputs``/``outputs``/``states`` None, a count (the default names),
    a base name (``'w'`` gives ``w[0]``, ``w[1]``, …) or a sequence of
    distinct names.  Returns them
    as a dictionary (their counts are checked by :func:`signal_names`)."""
    check_name(name)
    for what, spec in (('inputs', inputs), ('outputs', outputs),
                       ('states', states)):
        if spec is None or isinstance(spec, str) or (
                isinstance(spec, numbers.Integral) and
                not isinstance(spec, bool)):
            continue
        if not isinstance(spec, (list, tuple)) or not all(
                isinstance(label, str) for label in spec):
            raise ArgumentError(
                f"{what} must be a count, a base name or a list of signal "
                f"names "
                f"(strings); found {type(spec).__name__} {spec!r}")
        if len(set(spec)) != len(spec):
            raise ParameterError(f"{what} must be distinct names; found "
                                 f"{list(spec)}")
    return dict(name=name, inputs=inputs, outputs=outputs, states=states)


def signal_names(spec, default, count, what):
    """Signal names of a system keyword (see :func:`check_system`):
    ``default`` (a base name or a list) when ``spec`` is None."""
    if isinstance(spec, numbers.Integral) and spec != count:
        raise DimensionError(f"{what}: the error system has {count} "
                             f"{what}; found {what}={spec}")
    spec = default if spec is None or isinstance(spec, numbers.Integral) \
        else spec
    if isinstance(spec, str):
        return [f'{spec}[{i}]' for i in range(count)]
    if len(spec) != count:
        raise DimensionError(f"{what}: the error system has {count} "
                             f"{what}; found {len(spec)} names {list(spec)}")
    return list(spec)


def timebase(dt):
    """python-control's timebase: 0 (continuous), True (discrete,
    unspecified step) or a positive step; None counts as continuous."""
    if dt is None or (dt is not True and isinstance(dt, numbers.Real)
                      and not isinstance(dt, bool) and dt == 0):
        return 0
    if dt is True:
        return True
    return check_number(dt, 'dt', low=0, low_open=True)


def sample_step(dt):
    """The sampling period of a discrete timebase (1 if unspecified)."""
    return 1.0 if dt is True else float(dt)


# -- matrices ---------------------------------------------------------------

def as_array(M: Any, name: str) -> Array:
    """A float copy of ``M``; complex values and non-numbers are refused."""
    try:
        arr = np.array(M)
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"{name} must be a numeric matrix; found "
                            f"{type(M).__name__}") from exc
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number) or
                                   arr.dtype == bool):
        raise ArgumentError(f"{name} must be a numeric matrix; found "
                            f"{type(M).__name__} of {arr.dtype}")
    if np.iscomplexobj(arr):
        if np.any(arr.imag != 0):
            raise ParameterError(f"{name} must be real; found complex "
                                 "entries (the observers are real systems)")
        arr = arr.real
    return np.array(arr, dtype=float)


def check_finite(M, name):
    """Raise :class:`ParameterError` at the first NaN or inf of ``M``."""
    if not np.all(np.isfinite(M)):
        bad = np.argwhere(~np.isfinite(M))[0]
        raise ParameterError(
            f"{name} must be finite; found {M[tuple(bad)]} at index "
            f"{tuple(int(i) for i in bad)}")


def as_matrix(M: Any, name: str,
              shape: tuple[int | None, int | None]) -> Array:
    """Return a float copy of ``M`` with the expected ``shape``.

    ``shape`` entries may be ``None`` (any size). Scalars and vectors are
    accepted where the expected shape makes them unambiguous.
    """
    arr = as_array(M, name)
    rows, cols = shape
    if arr.ndim == 0:
        arr = arr.reshape(1, 1)
    elif arr.ndim == 1:
        if rows == 1 and cols != 1:
            arr = arr.reshape(1, -1)
        else:
            arr = arr.reshape(-1, 1)
    if arr.ndim != 2:
        raise DimensionError(f"{name} must be a 2-D matrix; found an array "
                             f"with {arr.ndim} dimensions")
    for axis, (want, what) in enumerate(((rows, 'rows'), (cols, 'columns'))):
        if want is not None and arr.shape[axis] != want:
            raise DimensionError(
                f"{name} has the wrong number of {what}; expected {want} "
                f"instead of {arr.shape[axis]} (shape {arr.shape})")
    check_finite(arr, name)
    return arr


def as_plant(plant):
    """Return ``(A, B, C, D, dt)`` copies of an LTI plant's matrices."""
    if isinstance(plant, ct.TransferFunction):
        try:
            plant = ct.ss(plant)
        except ValueError as exc:
            raise ParameterError(f"the plant's transfer function has no "
                                 f"state-space realisation: {exc}") from exc
    if not isinstance(plant, ct.StateSpace):
        raise ArgumentError(
            "plant must be a linear system (control.StateSpace or "
            f"control.TransferFunction); found {type(plant).__name__}")
    A, B, C, D = (as_array(M, f"plant.{name}") for M, name in
                  ((plant.A, 'A'), (plant.B, 'B'), (plant.C, 'C'),
                   (plant.D, 'D')))
    if A.shape[0] == 0:
        raise DimensionError("plant has no states; expected at least one")
    if C.shape[0] == 0:
        raise DimensionError("plant has no outputs; an observer needs at "
                             "least one measurement")
    for name, M in (('A', A), ('B', B), ('C', C), ('D', D)):
        check_finite(M, f"plant.{name}")
    return A, B, C, D, timebase(plant.dt)


def noise_model(n, p, Bw=None, Dw=None, Cz=None):
    """Return ``(Bw, Dw, Cz)`` with the package defaults filled in.

    The defaults are the paper's measurement-noise model: ``Bw = 0``,
    ``Dw = I_p`` and ``Cz = I_n``. The number of noise channels is taken
    from whichever of ``Bw``/``Dw`` is given.
    """
    Bw = None if Bw is None else as_matrix(Bw, 'Bw', (n, None))
    Dw = None if Dw is None else as_matrix(Dw, 'Dw', (p, None))
    q = Bw.shape[1] if Bw is not None else \
        Dw.shape[1] if Dw is not None else p
    Bw = np.zeros((n, q)) if Bw is None else Bw
    Dw = (np.eye(p) if q == p else np.zeros((p, q))) if Dw is None \
        else as_matrix(Dw, 'Dw', (p, q))
    Cz = np.eye(n) if Cz is None else as_matrix(Cz, 'Cz', (None, n))
    return Bw, Dw, Cz


def check_weights(weights, copies):
    """Output weights as an array of length ``copies`` summing to one."""
    if weights is None:
        return np.full(copies, 1.0 / copies)
    w = as_array(weights, 'weights')
    if w.ndim != 1:
        raise DimensionError(f"weights must be a 1-D sequence of {copies} "
                             f"numbers (one per copy); found shape "
                             f"{w.shape}")
    if w.size != copies:
        raise DimensionError(f"weights has the wrong length; expected "
                             f"{copies} (one per copy) instead of {w.size}")
    if not np.all(np.isfinite(w)):
        raise ParameterError(f"weights must be finite; found {w.tolist()}")
    if np.any(w < 0):
        raise ParameterError(f"weights must be >= 0 (the estimate is a "
                             f"weighted average of the copies); found "
                             f"{w.tolist()}")
    if abs(w.sum() - 1) > 1e-9:
        raise ParameterError(f"weights must sum to 1; found sum "
                             f"{w.sum():.6g} for weights {w.tolist()}")
    return w


# -- modes ------------------------------------------------------------------

def balance_pair(A, C):
    """Diagonal state scaling ``d`` that balances ``[[A, 0], [C, 0]]``:
    ``(D⁻¹ A D, C D)`` has rows and columns of comparable size, whatever
    the units of the states (LAPACK's ``gebal``, powers of 2, no
    permutation)."""
    import scipy.linalg as la
    n, p = A.shape[0], C.shape[0]
    M = np.block([[A, np.zeros((n, p))], [C, np.zeros((p, p))]])
    _, (scale, _) = la.matrix_balance(M, permute=False, separate=True)
    return scale[:n]


def unobservable_modes(A, C, rtol=1e-10):
    """Eigenvalues of ``A`` that the PBH test finds unobservable from ``C``.

    The test runs on the balanced pair of :func:`balance_pair` and compares
    the smallest singular value of ``[A − λI; C]`` with the size of the
    balanced matrices, so that a change of state units does not change
    the answer.
    """
    n = A.shape[0]
    d = balance_pair(A, C)
    Ab = A / d[:, None] * d[None, :]
    Cb = C * d[None, :]
    size = max(np.linalg.norm(Ab, 2), np.linalg.norm(Cb, 2), 1e-300)
    modes = []
    for lam in np.linalg.eigvals(Ab):
        M = np.vstack([Ab - lam * np.eye(n), Cb.astype(complex)]) / size
        smin = np.linalg.svd(M, compute_uv=False)[-1]
        if smin <= rtol * n:
            modes.append(lam)
    return np.array(modes)


def format_mode(lam, dt):
    """``s = -0.5`` or ``z = 0.9+0.1j``: a mode for a message."""
    var = 'z' if dt else 's'
    if abs(lam.imag) < 1e-12:
        return f"{var} = {lam.real:.6g}"
    return f"{var} = {lam.real:.6g}{lam.imag:+.6g}j"


def check_detectable(A, C, dt=0, what="plant"):
    """Raise :class:`NotDetectableError` naming an unstable unobservable mode."""
    # a mode on the stability boundary (to rounding) does not decay
    edge = 1e-9 * max(1.0, np.linalg.norm(A, 2))
    for lam in unobservable_modes(A, C):
        unstable = abs(lam) >= 1 - 1e-9 if dt else lam.real >= -edge
        if unstable:
            raise NotDetectableError(
                f"the {what} is not detectable: the mode at "
                f"{format_mode(lam, dt)} is unobservable from C and not "
                "asymptotically stable, so no observer gain can make the "
                "estimation error converge")


def check_region_reachable(A, C, region, dt=0):
    """Raise :class:`RegionError` if an unobservable mode lies outside
    ``region`` (no gain can move it)."""
    for lam in unobservable_modes(A, C):
        if not region.contains([lam]):
            raise RegionError(
                f"{region} cannot be reached: the mode at "
                f"{format_mode(lam, dt)} is unobservable from C, so every "
                "observer keeps it"
                + (f"; it decays at rate {-lam.real:.6g}, which limits the "
                   "decay to at most that value"
                   if not dt and lam.real < 0 else ""))
