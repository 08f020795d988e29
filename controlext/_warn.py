"""Warnings attributed to the user's call.

A warning the package gives about a design (a :class:`GainWarning`, a
fallback it took) names the line of the user's code that asked for the
design, as python-control's and numpy's warnings do, rather than a line
inside the package: that is where the user looks, and Python's default
filter shows a warning once per location, so a location inside the
package would show one design's warning and hide the next plant's.

Examples
--------
>>> import warnings
>>> from controlext._warn import warn
>>> with warnings.catch_warnings(record=True) as caught:
...     warnings.simplefilter('always')
...     warn('a note', UserWarning)
>>> caught[0].filename.endswith('_warn.py')
False
"""

import os
import sys
import warnings

__all__ = ['warn']

_PACKAGE = os.path.dirname(os.path.abspath(__file__)) + os.sep


def warn(message: str, category: type[Warning]) -> None:
    """``warnings.warn(message, category)`` at the first frame outside
    the package (the innermost frame where every frame is inside it)."""
    frame = sys._getframe(1)
    level = 2               # that of warn's caller
    while frame.f_back is not None and \
            os.path.abspath(frame.f_code.co_filename).startswith(_PACKAGE):
        frame = frame.f_back
        level += 1
    warnings.warn(message, category, stacklevel=level)
