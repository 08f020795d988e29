"""The printed reports' layout: one aligned row per fact.

Examples
--------
>>> from controlext._text import table_row
>>> table_row('decay rate', '1')
'decay rate                  1'
"""

__all__ = ['LABEL_WIDTH', 'table_row']

#: width of the label column of the printed reports
LABEL_WIDTH = 28


def table_row(label: str, value: str) -> str:
    """One aligned row of a printed report: the label padded to
    :data:`LABEL_WIDTH`, then the value."""
    return f"{label:<{LABEL_WIDTH}}{value}"
