"""Type aliases of the public API (for annotations only).

python-control, cvxpy and scipy carry no type information, so their
classes read as ``Any`` to a type checker; the aliases name what is meant.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, TypeAlias, Union

import numpy as np
import numpy.typing as npt

__all__ = ['ArrayLike', 'Array', 'BoolArray', 'Plant', 'Names',
           'ExecutorLike']

#: anything numpy turns into an array of numbers
ArrayLike: TypeAlias = npt.ArrayLike
#: a float array
Array: TypeAlias = npt.NDArray[np.float64]
#: a boolean array (a mask)
BoolArray: TypeAlias = npt.NDArray[np.bool_]
#: a python-control linear system (``StateSpace`` or ``TransferFunction``)
Plant: TypeAlias = Any
#: python-control's system keywords: a count, a base name or the names
Names: TypeAlias = Union[int, str, Sequence[str], None]
#: a ``concurrent.futures.Executor`` or a Dask ``Client``
ExecutorLike: TypeAlias = Any
