"""The designs of the reproduction, each run once.

The table (:mod:`~controlext.paper.tables`) needs five designs and the
figures (:mod:`~controlext.paper.figures`) the second-order plant's at
five decays for one, two and three copies, three of them the table's own.
:func:`run_designs` runs the ones asked for together, on ``executor``
when given (the slowest first, so that a pool ends together), and both
take them from its result.  A design is keyed ``(plant, copies, decay)``
with ``plant`` ``'scalar'`` or ``'second'``; one copy is
:func:`~controlext.hinf_observer`, more a
:func:`~controlext.coupled_observer`: the table's with default options,
the figure's others with ``FIGURE_OPTIONS`` (fewer random starts).  The
published numbers are nominal optima, so these designs are made with
``gain_tolerance=0``; the key ``(plant, copies, decay, 'robust')`` is
the design with every default, robust decay included (:data:`ROBUST`).

Examples
--------
>>> from controlext.paper.designs import TABLE, run_designs
>>> sorted(TABLE)[:2]
[('scalar', 2, 2.5), ('scalar', 3, 2.5)]
>>> obs = run_designs([('scalar', 1, 2.5)])[('scalar', 1, 2.5)]
>>> round(obs.hinf, 4)                  # k0 = 2: γ0 = k0 / (k0 + 0.5)
0.8
"""

import warnings

from ..exceptions import GainWarning
from ..sweep import observer
from ..synthesis.refine import single_threaded
from .plants import scalar_plant, second_order_plant

__all__ = ['TABLE', 'ROBUST', 'TRADEOFF_DECAYS', 'FIGURE_OPTIONS',
           'tradeoff_keys', 'run_designs', 'designs_for']

#: the designs of the table
TABLE = [('scalar', 2, 2.5), ('scalar', 3, 2.5),
         ('second', 1, 1.0), ('second', 2, 1.0), ('second', 3, 1.0)]

#: the table's designs with the factories' defaults (robust decay)
ROBUST = [key + ('robust',) for key in TABLE]

#: the decays of the trade-off figure; below the second-order plant's own
#: rate (0.5) the best gain is ``L = 0`` with ``γ = 0``
TRADEOFF_DECAYS = (0.6, 0.8, 1.0, 1.5, 2.0)

#: refinement options of the figure's designs that are not the table's
#: (fewer random starts than the default 32)
FIGURE_OPTIONS = {'random_starts': 6}

_PLANTS = {'scalar': scalar_plant, 'second': second_order_plant}


def tradeoff_keys(decays=TRADEOFF_DECAYS):
    """The designs of the trade-off figure."""
    return [('second', N, float(d)) for N in (1, 2, 3) for d in decays]


@single_threaded
def _design(job):
    """One design ``(plant data, keywords)`` (module level: picklable),
    BLAS on one thread: on a pool the other cores are busy.

    A nominal optimum's :class:`~controlext.exceptions.GainWarning` (its
    pole clusters split under gain errors, which is why the factories'
    default is robust) is not raised: the reproduction shows nominal
    optima on purpose, and its table prints the robust design beside
    each.  The warning would come from a worker, naming no design."""
    data, options = job
    with warnings.catch_warnings():
        if options.get('gain_tolerance') == 0:
            warnings.simplefilter('ignore', GainWarning)
        return observer(data, options)


def run_designs(keys, executor=None):
    """``{key: observer}`` for every key (duplicates run once), on
    ``executor`` when given; the designs do not depend on it."""
    # slowest first: more copies, the robust ones
    keys = sorted(set(keys), key=lambda k: (-k[1], -len(k), k[:3]))
    jobs = []
    for key in keys:
        name, copies, decay = key[:3]
        plant = _PLANTS[name]()
        options = dict(copies=copies, decay=float(decay),
                       refine_options=None if key[:3] in TABLE
                       else FIGURE_OPTIONS)
        if len(key) == 3:
            options['gain_tolerance'] = 0       # the nominal optimum
        jobs.append(((plant.A, plant.B, plant.C, plant.D, plant.dt),
                     options))
    run = map if executor is None else executor.map
    return dict(zip(keys, run(_design, jobs)))


def designs_for(keys, designs=None, executor=None):
    """``designs`` (a result of :func:`run_designs`, or None) with the
    designs of ``keys`` it lacks run on ``executor``."""
    designs = dict(designs or {})
    missing = [key for key in keys if key not in designs]
    if missing:
        designs.update(run_designs(missing, executor))
    return designs
