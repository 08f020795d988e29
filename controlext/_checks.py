"""Input checks shared by the factories and the observer classes.

Every check raises one of controlext's exceptions with a message that
says what was expected and what was found, before any solver runs.
Inputs are copied, never modified.
"""

import numpy as np
import control as ct

from .exceptions import (ArgumentError, DimensionError, NotDetectableError,
                         ParameterError, RegionError)

__all__ = []


def as_plant(plant):
    """Return ``(A, B, C, D, dt)`` copies of an LTI plant's matrices."""
    if isinstance(plant, ct.TransferFunction):
        plant = ct.ss(plant)
    if not isinstance(plant, ct.StateSpace):
        raise ArgumentError(
            "plant must be a linear system (control.StateSpace or "
            f"control.TransferFunction); found {type(plant).__name__}")
    A, B, C, D = (np.array(M, dtype=float) for M in
                  (plant.A, plant.B, plant.C, plant.D))
    if A.shape[0] == 0:
        raise DimensionError("plant has no states; expected at least one")
    if C.shape[0] == 0:
        raise DimensionError("plant has no outputs; an observer needs at "
                             "least one measurement")
    for name, M in (('A', A), ('B', B), ('C', C), ('D', D)):
        check_finite(M, f"plant.{name}")
    return A, B, C, D, plant.dt


def check_finite(M, name):
    if not np.all(np.isfinite(M)):
        bad = np.argwhere(~np.isfinite(M))[0]
        raise ParameterError(
            f"{name} must be finite; found {M[tuple(bad)]} at index "
            f"{tuple(int(i) for i in bad)}")


def as_matrix(M, name, shape):
    """Return a float copy of ``M`` with the expected ``shape``.

    ``shape`` entries may be ``None`` (any size). Scalars and vectors are
    accepted where the expected shape makes them unambiguous.
    """
    try:
        arr = np.array(M, dtype=float)
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"{name} must be a numeric matrix; found "
                            f"{type(M).__name__}") from exc
    rows, cols = shape
    if arr.ndim == 0:
        arr = arr.reshape(1, 1)
    elif arr.ndim == 1:
        if cols == 1 and (rows is None or arr.size == rows):
            arr = arr.reshape(-1, 1)
        elif rows == 1:
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


def noise_model(n, p, Bw=None, Dw=None, Cz=None):
    """Return ``(Bw, Dw, Cz)`` with the package defaults filled in.

    The defaults are the paper's measurement-noise model: ``Bw = 0``,
    ``Dw = I_p`` and ``Cz = I_n``. The number of noise channels is taken
    from whichever of ``Bw``/``Dw`` is given.
    """
    q = p
    for M in (Bw, Dw):
        if M is not None:
            arr = np.asarray(M, dtype=float)
            q = arr.shape[1] if arr.ndim == 2 else 1
            break
    Bw = np.zeros((n, q)) if Bw is None else as_matrix(Bw, 'Bw', (n, q))
    Dw = (np.eye(p, q) if q == p else np.zeros((p, q))) if Dw is None \
        else as_matrix(Dw, 'Dw', (p, q))
    Cz = np.eye(n) if Cz is None else as_matrix(Cz, 'Cz', (None, n))
    return Bw, Dw, Cz


def check_decay(decay):
    if decay is None:
        return None
    try:
        decay = float(decay)
    except (TypeError, ValueError) as exc:
        raise ArgumentError(f"decay must be a real number; found "
                            f"{type(decay).__name__}") from exc
    if not np.isfinite(decay) or decay < 0:
        raise ParameterError(f"decay must be a finite number >= 0; found "
                             f"{decay}")
    return decay


def unobservable_modes(A, C, tol=1e-8):
    """Eigenvalues of ``A`` that the PBH test finds unobservable from ``C``."""
    n = A.shape[0]
    scale = max(1.0, np.linalg.norm(A, 2), np.linalg.norm(C, 2))
    modes = []
    for lam in np.linalg.eigvals(A):
        M = np.vstack([A - lam * np.eye(n), C.astype(complex)])
        smin = np.linalg.svd(M, compute_uv=False)[-1]
        if smin <= tol * scale * n:
            modes.append(lam)
    return np.array(modes)


def _fmt_mode(lam, dt):
    var = 'z' if dt else 's'
    if abs(lam.imag) < 1e-12:
        return f"{var} = {lam.real:.6g}"
    return f"{var} = {lam.real:.6g}{lam.imag:+.6g}j"


def check_detectable(A, C, dt=0, what="plant"):
    """Raise :class:`NotDetectableError` naming an unstable unobservable mode."""
    for lam in unobservable_modes(A, C):
        unstable = abs(lam) >= 1 if dt else lam.real >= 0
        if unstable:
            raise NotDetectableError(
                f"the {what} is not detectable: the mode at "
                f"{_fmt_mode(lam, dt)} is unobservable from C and not "
                "asymptotically stable, so no observer gain can make the "
                "estimation error converge")


def check_region_reachable(A, C, region, dt=0):
    """Raise :class:`RegionError` if an unobservable mode lies outside
    ``region`` (no gain can move it)."""
    for lam in unobservable_modes(A, C):
        if not region.contains([lam]):
            raise RegionError(
                f"{region} cannot be reached: the mode at "
                f"{_fmt_mode(lam, dt)} is unobservable from C, so every "
                "observer keeps it"
                + (f"; it decays at rate {-lam.real:.6g}, which limits the "
                   "decay to at most that value"
                   if not dt and lam.real < 0 else ""))
