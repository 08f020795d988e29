"""Exception classes of controlext.

Every error the package raises derives from :class:`ControlextError` and,
where python-control has a matching class, from that class too, so code
that already catches python-control's errors keeps working::

    ControlextError
    ├── DimensionError      (control.ControlDimension, ValueError)
    ├── ArgumentError       (control.ControlArgument, TypeError)
    ├── ParameterError      (ValueError)
    ├── NotDetectableError  (ValueError)
    ├── RegionError         (ValueError)
    ├── SolverError         (RuntimeError)
    └── VerificationError   (RuntimeError)

    GainWarning             (UserWarning): a design whose gain or error
                            poles lie far beyond the plant's scale

Examples
--------
>>> import controlext as cx
>>> issubclass(cx.DimensionError, ValueError)
True
"""

from control.exception import ControlArgument, ControlDimension

__all__ = [
    'ControlextError', 'DimensionError', 'ArgumentError', 'ParameterError',
    'NotDetectableError', 'RegionError', 'SolverError', 'VerificationError',
    'GainWarning',
]


class ControlextError(Exception):
    """Base class of every error raised by controlext."""


class DimensionError(ControlextError, ControlDimension):
    """A matrix or system has the wrong shape (expected vs found)."""


class ArgumentError(ControlextError, ControlArgument):
    """An argument has the wrong type (for example a plant that is not a
    linear system)."""


class ParameterError(ControlextError, ValueError):
    """An argument has an invalid value (NaN, inf, a negative decay, ...)."""


class NotDetectableError(ControlextError, ValueError):
    """The plant (or the augmented plant) is not detectable."""


class RegionError(ControlextError, ValueError):
    """No gain can place the error poles in the requested region."""


class SolverError(ControlextError, RuntimeError):
    """The convex solver did not return an optimal solution.

    Attributes
    ----------
    status : str
        The solver status reported by cvxpy (for example ``'infeasible'``).
    stats : dict
        Solver statistics (solver name, iterations, solve time).
    """

    def __init__(self, message, status=None, stats=None):
        super().__init__(message)
        self.status = status
        self.stats = stats or {}


class VerificationError(ControlextError, RuntimeError):
    """A synthesised design failed its own verification."""


class GainWarning(UserWarning):
    """A returned design's gain or error poles are far beyond the plant's
    scale (the optimum is approached only as the gain grows), or its
    error grows more than 10⁶-fold before it decays, or relative gain
    errors of 1e-6 cost it more than a third of its decay rate: the design
    is verified, but it amplifies rounding and unmodelled noise."""
