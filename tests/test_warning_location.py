"""Every warning the package gives names the user's line.

python-control's and numpy's warnings point at the caller's code; so do
the package's, whatever depth inside it they come from (a factory, the
pipeline, a sub-design of copies, a norm's fallback).  A location inside
the package also hid warnings: Python's default filter shows a warning
once per location and text.
"""

import warnings

import control as ct
import numpy as np
import pytest

import controlext as cx
from controlext import norms
from controlext.synthesis.conditioning import GainBound, warn_if_held

UNSTABLE = ct.ss([[1.0]], [[1.0]], [[1.0]], 0)
#: a discrete mode seen 1e-8 as strongly as the other: moving it into
#: |z| < 0.5 needs a gain above 4.5e7 (test_max_gain)
WEAK = ct.ss(np.diag([0.9, 0.95]), [[1.0], [1.0]], [[1.0, 1e-8]], 0, 0.1)


def _caught(call):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter('always')
        call()
    return caught


def _here(caught, category):
    mine = [w for w in caught if issubclass(w.category, category)]
    assert mine, [str(w.message) for w in caught]
    return {(w.filename, w.lineno) for w in mine}


def _line_of(marker):
    with open(__file__) as f:
        return next(k for k, line in enumerate(f, 1) if marker in line)


def test_gain_warnings_of_a_design_name_the_callers_line():
    disk = cx.Disk(0.5)
    caught = _caught(lambda: cx.hinf_observer(WEAK, region=disk, max_gain=None))  # design-line  # noqa: E501
    # the extreme gain and the transient peak, both at the call
    assert len({str(w.message)[:20] for w in caught}) >= 2
    assert _here(caught, cx.GainWarning) == {
        (__file__, _line_of('# design-line'))}


@pytest.mark.parametrize('factory', [cx.hinf_observer, cx.coupled_observer])
def test_refine_false_bound_warning_names_the_callers_line(factory):
    caught = _caught(lambda: factory(UNSTABLE, 2.0, max_gain=1.5, refine=False))  # bound-line  # noqa: E501
    assert _here(caught, cx.GainWarning) == {
        (__file__, _line_of('# bound-line'))}


def test_held_at_the_default_bound_is_told_at_the_call():
    class Report:
        hinf = 0.5
        stats: dict = {}

    bound = GainBound(2.0, np.ones(2))
    G = np.array([[2.0], [0.0]])                # ‖G‖₂ = 2: at the bound
    caught = _caught(lambda: warn_if_held(bound, G, Report, 'auto'))
    assert _here(caught, cx.GainWarning) == {
        (__file__, _line_of("Report, 'auto'))"))}
    assert Report.stats['max_gain'] == dict(bound=2.0, norm=2.0)
    # a bound the user chose, or a gain below it: nothing to tell
    assert not _caught(lambda: warn_if_held(bound, G, Report, 2.0))
    assert not _caught(lambda: warn_if_held(bound, G / 2, Report, 'auto'))


def test_gi_classic_warning_once_at_the_call():
    plant = ct.ss([[np.exp(-0.05)]], [[0.1]], [[1.0]], 0, 0.1)
    caught = _caught(lambda: cx.gi_observer(plant, [[-1.0]], 1.0, True))  # gi-line
    classic = [w for w in caught if 'classic' in str(w.message)]
    assert len(classic) == 1
    assert {(w.filename, w.lineno) for w in classic} == {
        (__file__, _line_of('# gi-line'))}


def test_norm_fallback_warning_at_the_call(monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError('ab13dd failed')

    monkeypatch.setattr(norms.ct, 'linfnorm', broken)
    sys = ct.ss([[-1.0]], [[1.0]], [[1.0]], 0)
    caught = _caught(lambda: cx.hinfnorm(sys))  # norm-line
    assert _here(caught, RuntimeWarning) == {
        (__file__, _line_of('# norm-line'))}


def test_deprecated_alias_warning_at_the_access():
    obs = cx.hinf_observer(UNSTABLE, decay=2.0, refine=False)
    caught = _caught(lambda: obs.report.gamma_opt)  # alias-line
    assert _here(caught, DeprecationWarning) == {
        (__file__, _line_of('# alias-line'))}
