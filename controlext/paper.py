"""Section IV of Li & Sanfelice: the plants, the published designs and
the table that ``python -m controlext`` prints.

Each row holds the published number (seed 000, Section IV; DESIGN.md §5),
the value controlext computes for the published gains, and — for design
rows — the value controlext's own synthesis reaches.

Examples
--------
>>> from controlext.paper import scalar_plant, second_order_plant
>>> scalar_plant().A.tolist(), second_order_plant().C.tolist()
([[-0.5]], [[1.0, 2.0]])
"""

from dataclasses import dataclass

import numpy as np
import control as ct

__all__ = ['scalar_plant', 'second_order_plant', 'PaperRow', 'paper_rows',
           'format_table']

#: measurement bias of Section IV-A
BIAS = 0.3


def scalar_plant(a=-0.5):
    """The scalar plant (4): ``x' = a x``, ``y = x + m``, ``a = -0.5``."""
    return ct.ss([[a]], [[1.0]], [[1.0]], [[0.0]], name='scalar')


def second_order_plant():
    """The second-order plant of Section IV-B."""
    return ct.ss([[-1.0, 1.0], [-1.0, 0.0]], [[0.0], [1.0]], [[1.0, 2.0]],
                 [[0.0]], name='second_order')


@dataclass
class PaperRow:
    """One line of the reproduction table."""
    case: str
    quantity: str
    published: str
    computed: str
    synthesised: str = ''
    ok: bool = True


def _fmt(x, digits=4):
    if isinstance(x, complex) or np.iscomplexobj(x):
        return f"{x.real:.{digits}f} ± {abs(x.imag):.{digits}f}i"
    return f"{x:.{digits}f}"


def _close(value, published, digits):
    return abs(value - published) <= 0.5 * 10.0 ** (-digits) + 1e-12 or \
        abs(value - published) <= 1e-3 * abs(published)


def luenberger_rows():
    """Rows for the Luenberger observers of Section IV."""
    from .observers import LuenbergerObserver
    from .design import hinf_observer
    rows = []
    obs = LuenbergerObserver(scalar_plant(), [[2.0]])
    pole = ct.poles(obs)[0].real
    sse = float(ct.dcgain(obs)) * BIAS
    rows += [
        PaperRow('scalar, k0 = 2', 'γ0', '0.8', _fmt(obs.hinf),
                 ok=_close(obs.hinf, 0.8, 1)),
        PaperRow('scalar, k0 = 2', 'pole', '-2.5', _fmt(pole),
                 ok=_close(pole, -2.5, 1)),
        PaperRow('scalar, k0 = 2', 'e0* at m = 0.3', '0.24', _fmt(sse),
                 ok=_close(sse, 0.24, 2)),
    ]
    plant = second_order_plant()
    obs = LuenbergerObserver(plant, [[2.0], [5.0]])
    rows += [
        PaperRow('2nd order, K0 = [2; 5]', 'decay', '1', _fmt(obs.decay),
                 ok=_close(obs.decay, 1, 0)),
        PaperRow('2nd order, K0 = [2; 5]', 'γ', '0.4859', _fmt(obs.hinf),
                 ok=_close(obs.hinf, 0.4859, 4)),
    ]
    obs = LuenbergerObserver(plant, [[0.2852], [0.3574]])
    syn = hinf_observer(plant, decay=1.0)
    rows.append(PaperRow('2nd order, K0 = [0.2852; 0.3574]', 'γ (σ = 1)',
                         '0.2850', _fmt(obs.hinf),
                         f"{_fmt(syn.hinf)} ({syn.report.method})",
                         ok=_close(obs.hinf, 0.2850, 4)))
    return rows


def paper_rows():
    """Every row of the reproduction table."""
    return luenberger_rows()


def format_table(rows):
    """The rows as an aligned plain-text table."""
    head = ('case', 'quantity', 'published', 'computed', 'synthesised', '')
    body = [(r.case, r.quantity, r.published, r.computed, r.synthesised,
             'ok' if r.ok else 'MISMATCH') for r in rows]
    widths = [max(len(str(x)) for x in col) for col in zip(head, *body)]
    line = lambda cells: '  '.join(str(c).ljust(w)
                                   for c, w in zip(cells, widths)).rstrip()
    sep = '  '.join('-' * w for w in widths)
    return '\n'.join([line(head), sep] + [line(b) for b in body])
