"""Typed records of how a design was made: :class:`DesignStats` (a
design report's ``stats``) and :class:`RefineSummary` (its ``refine``
entry).

Each is a dataclass with one typed, documented field per fact, and reads
as a mapping of the facts that were recorded: ``'refine' in stats``,
``stats['limits']``, ``stats.get('headroom')`` and ``dict(stats)`` keep
working, and a fact that was never recorded is absent rather than None
(``floor_level=None`` records that no floor could be computed; an unset
``floor_level`` means none was asked for).  A key that is not a field is
an error, so a misspelt fact cannot be recorded silently.
"""

from __future__ import annotations

from collections.abc import MutableMapping
from dataclasses import dataclass, fields
from typing import Any

__all__ = ['DesignStats', 'RefineSummary']


class _Unset:
    """The default of a field that was not recorded."""

    def __repr__(self):
        return 'UNSET'

    def __reduce__(self):
        return (_unset, ())


def _unset():
    return UNSET


UNSET: Any = _Unset()


class _Record(MutableMapping):
    """A dataclass whose recorded fields read as a mapping."""

    _given: set[str]      # the recorded fields (not a field itself)

    def __post_init__(self):
        given = set()
        for f in fields(self):
            if getattr(self, f.name) is UNSET:
                object.__setattr__(self, f.name, None)
            else:
                given.add(f.name)
        object.__setattr__(self, '_given', given)

    @classmethod
    def of(cls, facts=None, **more):
        """The record of a mapping (a record is copied) and keywords; a
        key that is not a field raises a ``KeyError`` naming the fields."""
        facts = dict(facts or {}, **more)
        cls._check(facts)
        return cls(**facts)

    @classmethod
    def _check(cls, keys):
        names = {f.name for f in fields(cls)}
        unknown = [key for key in keys if key not in names]
        if unknown:
            raise KeyError(f"{cls.__name__} has no field {unknown[0]!r} "
                           f"(its fields: {', '.join(sorted(names))})")

    def replace(self, **changes) -> '_Record':
        """A copy with ``changes`` recorded (the others as they are)."""
        self._check(changes)
        kept = {name: getattr(self, name) for name in self._given}
        return type(self)(**dict(kept, **changes))

    def __getitem__(self, key):
        if key not in self._given:
            raise KeyError(key)
        return getattr(self, key)

    def __setitem__(self, key, value):
        self._check([key])
        setattr(self, key, value)
        self._given.add(key)

    def __delitem__(self, key):
        if key not in self._given:
            raise KeyError(key)
        setattr(self, key, None)
        self._given.discard(key)

    def __iter__(self):
        return (f.name for f in fields(self) if f.name in self._given)

    def __len__(self):
        return len(self._given)

    def __repr__(self):
        inner = ', '.join(f'{key}={self[key]!r}' for key in self)
        return f'{type(self).__name__}({inner})'

    # a mapping's == compares items; a record's, the recorded facts
    def __eq__(self, other):
        if isinstance(other, MutableMapping):
            return dict(self.items()) == dict(other.items())
        return NotImplemented

    __hash__ = None      # type: ignore[assignment]  # mutable


@dataclass(eq=False, repr=False)
class RefineSummary(_Record):
    """What a design report keeps of a refinement
    (``report.stats['refine']``).

    Attributes
    ----------
    start : str or None
        The start the refined gain came from.
    starts : list of (str, float)
        Every start and the norm its run ended at.
    evaluations : int
        Objective evaluations over all runs.
    time : float
        Seconds spent refining.
    phases : dict
        Seconds and evaluations per phase (screening, polishing, ...).
    stationary : StationarityTest or None
        The gradient-sampling test of the end point
        (:mod:`~controlext.synthesis.stationary`).
    failed : str or None
        Why refinement gave no gain (the convex design was kept).
    runners : list of (str, ndarray)
        The end points of other basins, best first
        (:attr:`~controlext.synthesis.RefineResult.runners`).
    """
    start: str | None = UNSET
    starts: list | None = UNSET
    evaluations: int | None = UNSET
    time: float | None = UNSET
    phases: dict | None = UNSET
    stationary: Any = UNSET
    failed: str | None = UNSET
    runners: list | None = UNSET


@dataclass(eq=False, repr=False)
class DesignStats(_Record):
    """How a design was made (``DesignReport.stats``).

    Attributes
    ----------
    lmi : dict or None
        The LMI solver's statistics per stage (``'stage1'``,
        ``'stage2'``, ``'certificate'``: status, iterations, times).
    modal : dict or None
        The modal route's facts (``'slow_states'``).
    riccati : dict or None
        The Riccati route's facts (``'regularisation'``).
    luenberger : dict or None
        The convex statistics of a coupled design's embedded one-copy
        design.
    fallback : list of (str, str) or None
        Convex routes that failed before the one that gave the design,
        and why.
    floor_level : float or None
        The unconstrained filter level of the minimised norm (None
        recorded: it could not be computed).
    floor : str or None
        Why the convex design was not refined (its norm is 0).
    luenberger_hinf : float or None
        The norm of a coupled design's one-copy design.
    headroom : str or None
        Why a design at the filter level was not refined.
    refine : RefineSummary or None
        The refinement (:class:`RefineSummary`).
    refused : list of (str, str) or None
        Candidate designs that failed verification, and why.
    tolerance : str or None
        How the gain tolerance was met.
    nominal : float or None
        The minimised norm of the nominal optimum (the design of
        ``gain_tolerance=0``) where it missed the gain tolerance and the
        design is another: what the tolerance cost is the design's norm
        over this one (not recorded for a norm near 0, which ranks equal
        to 0).  The road can end below it, where it found a design the
        nominal search missed (a three-copy design refined under the
        tolerance from a pair's: campaign seed 5183, 0.669 against
        0.691); the report then says the tolerance cost nothing.
    limits : dict or None
        Each bounded criterion's value over its bound.
    max_gain : dict or None
        The gain bound and the gain's norm under it.
    """
    lmi: dict | None = UNSET
    modal: dict | None = UNSET
    riccati: dict | None = UNSET
    luenberger: dict | None = UNSET
    fallback: list | None = UNSET
    floor_level: float | None = UNSET
    floor: str | None = UNSET
    luenberger_hinf: float | None = UNSET
    headroom: str | None = UNSET
    refine: RefineSummary | None = UNSET
    refused: list | None = UNSET
    tolerance: str | None = UNSET
    nominal: float | None = UNSET
    limits: dict | None = UNSET
    max_gain: dict | None = UNSET

    def __post_init__(self):
        super().__post_init__()
        if isinstance(self.refine, dict):
            self.refine = RefineSummary.of(self.refine)
