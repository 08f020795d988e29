"""The typed records of how a design was made: DesignReport.stats and its
refinement summary."""

import pickle
import warnings

import control as ct
import numpy as np
import pytest

import controlext as cx
from controlext.synthesis import DesignStats, RefineSummary


def test_a_recorded_none_is_not_an_absent_fact():
    # floor_level=None says no floor could be computed; an unset one that
    # none was asked for: the pipeline reads them differently
    computed, unasked = DesignStats(floor_level=None), DesignStats()
    assert 'floor_level' in computed and computed['floor_level'] is None
    assert 'floor_level' not in unasked
    assert unasked.get('floor_level', 'absent') == 'absent'
    assert unasked.floor_level is None
    with pytest.raises(KeyError):
        unasked['floor_level']


def test_a_misspelt_fact_is_refused_and_named():
    stats = DesignStats()
    with pytest.raises(KeyError, match="no field 'limit'.*limits"):
        stats['limit'] = {}
    with pytest.raises(KeyError, match="no field 'headrom'"):
        DesignStats.of({'headrom': 'x'})
    with pytest.raises(KeyError, match="no field 'stationarity'"):
        RefineSummary.of(stationarity=None)
    with pytest.raises(KeyError, match="no field 'limit'"):
        stats.replace(limit={})
    assert len(stats) == 0


def test_it_reads_and_writes_as_a_mapping_of_the_recorded_facts():
    stats = DesignStats.of({'lmi': {'solver': 'CLARABEL'}},
                           refine={'evaluations': 12, 'failed': None})
    assert list(stats) == ['lmi', 'refine'] and len(stats) == 2
    # a refinement given as a mapping becomes its typed summary
    assert isinstance(stats.refine, RefineSummary)
    assert dict(stats.refine) == {'evaluations': 12, 'failed': None}
    stats.update(floor_level=0.25, headroom='at the floor')
    assert stats.floor_level == 0.25 and stats['headroom'] == 'at the floor'
    del stats['headroom']
    assert 'headroom' not in stats and stats.headroom is None
    with pytest.raises(KeyError):
        del stats['headroom']
    assert dict(stats) == {'lmi': {'solver': 'CLARABEL'},
                           'refine': stats.refine, 'floor_level': 0.25}
    assert stats == dict(stats) and stats != {'lmi': None}


def test_replace_leaves_the_record_it_copies_as_it_was():
    stats = DesignStats(floor_level=None, limits={'settling_time': 0.5})
    new = stats.replace(limits={'gain_tolerance': 0.9}, tolerance='held')
    assert stats.limits == {'settling_time': 0.5} and 'tolerance' not in stats
    assert new.limits == {'gain_tolerance': 0.9} and new.tolerance == 'held'
    assert 'floor_level' in new and new is not stats


def test_pickling_keeps_what_was_recorded():
    # designs travel between processes (executors): the record's absent
    # and recorded-as-None facts must survive the trip
    stats = DesignStats(floor_level=None, refine=RefineSummary(failed='x'))
    back = pickle.loads(pickle.dumps(stats))
    assert list(back) == ['floor_level', 'refine']
    assert 'lmi' not in back and back.refine.failed == 'x'
    assert 'start' not in back.refine


@pytest.fixture(scope='module')
def refined():
    # an unstable mode and an integrator, process noise on every state and
    # measurement noise, decay 1, nominal: refined
    plant = ct.ss([[0.5, 1, 0], [0, 0, 1], [0, 0, -2]], [[0], [0], [1]],
                  [[1, 0, 0]], 0)
    with warnings.catch_warnings():
        warnings.simplefilter('ignore', cx.GainWarning)
        return cx.hinf_observer(plant, decay=1.0, gain_tolerance=0,
                                Bw=np.c_[np.eye(3), np.zeros((3, 1))],
                                Dw=np.array([[0.0, 0, 0, 1]]))


def test_a_design_report_holds_typed_records(refined):
    stats = refined.report.stats
    assert isinstance(stats, DesignStats)
    assert isinstance(stats.refine, RefineSummary)
    assert stats.refine.evaluations > 0 and stats.refine.failed is None
    # the refinement's end point is its best start, at the norm that
    # verification recomputed from the gain (slycot, not the objective)
    names, norms = zip(*stats.refine.starts)
    assert stats.refine.start == names[int(np.argmin(norms))]
    assert min(norms) == pytest.approx(refined.report.hinf, rel=1e-6)
    # the filter floor the pipeline recorded is the Riccati level
    one = refined.problem.single()
    floor = cx.synthesis.riccati.hinf_filter_level(one.A, one.C, one.Bw,
                                                   one.Dw, one.Cz)
    assert stats.floor_level == pytest.approx(floor, rel=1e-5)
    assert stats.floor_level <= refined.report.hinf
    # the report's flag reads the typed summary
    assert refined.report.stationary is bool(stats.refine.stationary.passed)


def test_a_mapping_assigned_to_a_report_becomes_a_record(refined):
    report = pickle.loads(pickle.dumps(refined.report))
    report.stats = {'tolerance': 'given'}
    assert isinstance(report.stats, DesignStats)
    assert list(report.stats) == ['tolerance'] and report.stationary is None
    with pytest.raises(KeyError, match="no field"):
        report.stats = {'tolerances': 'given'}
