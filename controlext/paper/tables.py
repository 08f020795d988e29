"""Section IV of Li & Sanfelice: the plants, the published designs and
the table that ``python -m controlext`` prints.

Each row holds the published number (seed 000, Section IV; DESIGN.md §5),
the value controlext computes for the published gains, and — for design
rows — the value controlext's own synthesis reaches.  The published
numbers are nominal optima: the synthesised column is designed with
``gain_tolerance=0``, and the last column gives the factories' default
design beside it, whose decay survives relative gain errors of 1e-6 and
rounding to 6 significant digits, with its cost in γ.

Examples
--------
>>> from controlext.paper import scalar_plant, second_order_plant
>>> scalar_plant().A.tolist(), second_order_plant().C.tolist()
([[-0.5]], [[1.0, 2.0]])
"""

from dataclasses import dataclass

import numpy as np
import control as ct

from ..analysis import iss_estimate, log_norm
from ..coupled import CoupledObserver
from ..luenberger import LuenbergerObserver
from .designs import ROBUST, TABLE, designs_for
from .plants import scalar_plant, second_order_plant

__all__ = ['scalar_plant', 'second_order_plant', 'PaperRow', 'paper_rows',
           'luenberger_rows', 'coupled_rows', 'format_table']

#: measurement bias of Section IV-A
BIAS = 0.3


@dataclass
class PaperRow:
    """One line of the reproduction table."""
    case: str
    quantity: str
    published: str
    computed: str
    synthesised: str = ''
    ok: bool = True
    robust: str = ''


def _fmt(x, digits=4):
    if isinstance(x, complex) or np.iscomplexobj(x):
        return f"{x.real:.{digits}f} ± {abs(x.imag):.{digits}f}i"
    return f"{x:.{digits}f}"


def _close(value, published, digits):
    return abs(value - published) <= 0.5 * 10.0 ** (-digits) + 1e-12 or \
        abs(value - published) <= 1e-3 * abs(published)


def luenberger_rows():
    """Rows for the Luenberger observers of Section IV."""
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
    rows.append(PaperRow('2nd order, K0 = [0.2852; 0.3574]', 'γ (σ = 1)',
                         '0.2850', _fmt(obs.hinf),
                         ok=_close(obs.hinf, 0.2850, 4)))
    return rows


#: coupled pair picked from (33), Section IV-A: (k1, k2, l1, l2)
PAIR_33 = (1.7896, 2.2278, 0.0538, -1.1633)
#: coupled pair found by PENBMI, Section IV-A
PAIR_PENBMI = (3.5198, 0.4802, -8.0142, 0.2883)
#: coupled gain of Section IV-B (the paper prints its transpose)
MU_SECOND_ORDER = np.array([[-0.2790, 0.2160, 0.1400, -0.1149],
                            [0.0367, -0.9901, 0.3470, 0.7500]]).T


def coupled_rows(synthesise=True, executor=None, designs=None):
    """Rows for the coupled observers of Section IV (and, with
    ``synthesise``, the designs controlext's own synthesis reaches: taken
    from ``designs``, a result of
    :func:`~controlext.paper.designs.run_designs`, those it lacks run on
    ``executor`` when given)."""
    plant = scalar_plant()
    pair = CoupledObserver.from_pair(plant, *PAIR_33)
    eig = ct.poles(pair)
    eig = eig[np.argmax(eig.imag)]
    mu = log_norm(pair.A)
    sse = float(ct.dcgain(pair)) * BIAS
    iss = iss_estimate(pair).output_gain
    case = 'scalar pair (33)'
    rows = [
        PaperRow(case, 'eigenvalues', '-2.5087 ± 0.1208i', _fmt(eig),
                 ok=_close(eig.real, -2.5087, 4) and
                 _close(abs(eig.imag), 0.1208, 4)),
        PaperRow(case, 'µ(Ã)', '-1.9123', _fmt(mu), ok=_close(mu, -1.9123, 4)),
        PaperRow(case, 'e* at m = 0.3', '0.2272', _fmt(sse),
                 ok=_close(sse, 0.2272, 4)),
        PaperRow(case, 'ISS gain (33) < 0.8', '0.787', _fmt(iss, 3),
                 ok=_close(iss, 0.787, 3)),
    ]
    penbmi = CoupledObserver.from_pair(plant, *PAIR_PENBMI)
    syn, second, robust = {}, {}, {}
    if synthesise:
        designs = designs_for(TABLE + ROBUST, designs, executor)
        syn = {N: designs['scalar', N, 2.5] for N in (2, 3)}
        second = {N: designs['second', N, 1.0] for N in (1, 2, 3)}
        robust = {key[:3]: _robust(designs[key], designs[key[:3]])
                  for key in ROBUST}
    rows.append(PaperRow('scalar pair (PENBMI), σ = 2.5', 'γ', '0.4953',
                         _fmt(penbmi.hinf), _syn(syn.get(2)),
                         ok=_close(penbmi.hinf, 0.4953, 4) and
                         _reached(syn.get(2), 0.4953),
                         robust=robust.get(('scalar', 2, 2.5), '')))
    if synthesise:
        rows.append(PaperRow('scalar, 3 copies, σ = 2.5', 'γ', '', '',
                             _syn(syn[3]), ok=syn[3].hinf < syn[2].hinf,
                             robust=robust[('scalar', 3, 2.5)]))
    plant = second_order_plant()
    coupled = CoupledObserver(plant, MU_SECOND_ORDER)
    syn = second
    rows.append(PaperRow('2nd order, Luenberger, σ = 1', 'γ (Thm 3.12)',
                         '0.2850', '', _syn(syn.get(1)),
                         ok=_reached(syn.get(1), 0.2851),
                         robust=robust.get(('second', 1, 1.0), '')))
    rows.append(PaperRow('2nd order, coupled Mu, σ = 1', 'γ', '0.0594',
                         _fmt(coupled.hinf), _syn(syn.get(2)),
                         ok=_close(coupled.hinf, 0.0594, 4) and
                         _reached(syn.get(2), 0.0594),
                         robust=robust.get(('second', 2, 1.0), '')))
    if synthesise:
        rows.append(PaperRow('2nd order, 3 copies, σ = 1', 'γ', '', '',
                             _syn(syn[3]), ok=syn[3].hinf < syn[2].hinf,
                             robust=robust[('second', 3, 1.0)]))
    return rows


def _syn(obs):
    return '' if obs is None else f"{_fmt(obs.hinf)} ({obs.report.stage})"


def _robust(obs, nominal):
    """The default (robust-decay) design's γ and its cost over the
    nominal optimum."""
    return f"{_fmt(obs.hinf)} ({obs.hinf / nominal.hinf - 1:+.2%})"


def _reached(obs, published):
    """A synthesised design reaches a published value to its digits."""
    return obs is None or obs.hinf < published + 5e-5


def paper_rows(synthesise=True, executor=None, designs=None):
    """Every row of the reproduction table (the designs from ``designs``,
    or run on ``executor`` when given)."""
    return luenberger_rows() + coupled_rows(synthesise, executor, designs)


def format_table(rows):
    """The rows as an aligned plain-text table."""
    head = ('case', 'quantity', 'published', 'computed', 'synthesised',
            'default (robust)', '')
    body = [(r.case, r.quantity, r.published, r.computed, r.synthesised,
             r.robust, 'ok' if r.ok else 'MISMATCH') for r in rows]
    widths = [max(len(str(x)) for x in col) for col in zip(head, *body)]
    line = lambda cells: '  '.join(str(c).ljust(w)
                                   for c, w in zip(cells, widths)).rstrip()
    sep = '  '.join('-' * w for w in widths)
    return '\n'.join([line(head), sep] + [line(b) for b in body])
