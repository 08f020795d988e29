"""The reproduction of Section IV of Li & Sanfelice (``python -m
controlext``): the paper's plants and published designs, the table of
published against computed numbers (tables.py) and the figures
(figures.py).  It uses the library; the library does not use it.

Examples
--------
>>> from controlext.paper import scalar_plant
>>> scalar_plant().A.tolist()
[[-0.5]]
"""

from .tables import (scalar_plant, second_order_plant, PaperRow, paper_rows,
                     luenberger_rows, coupled_rows, format_table, BIAS,
                     PAIR_33, PAIR_PENBMI)

__all__ = ['scalar_plant', 'second_order_plant', 'PaperRow', 'paper_rows',
           'luenberger_rows', 'coupled_rows', 'format_table', 'BIAS',
           'PAIR_33', 'PAIR_PENBMI']
