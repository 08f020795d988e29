"""python -m controlext: the reproduction table."""

import os
import subprocess
import sys

import numpy as np
import pytest

from controlext.__main__ import main
from controlext.paper import paper_rows


def test_published_gains_rows_all_match():
    rows = paper_rows(synthesise=False)
    assert rows and all(r.ok for r in rows), [r for r in rows if not r.ok]
    published = {r.published for r in rows}
    assert {'0.4953', '0.2850', '0.0594', '0.4859', '0.8'} <= published


def test_main_prints_table(capsys):
    assert main(['--no-synthesis', '--no-figures']) == 0
    out = capsys.readouterr().out
    for value in ('0.4953', '0.2850', '0.0594', '-1.9123', '0.2272'):
        assert value in out
    assert 'MISMATCH' not in out


@pytest.mark.slow
def test_module_entry_point_with_synthesis_and_figures(tmp_path):
    out = tmp_path / 'figs'
    proc = subprocess.run([sys.executable, '-m', 'controlext', '--out',
                           str(out)], capture_output=True, text=True,
                          timeout=900, env={**os.environ,
                                            'MPLBACKEND': 'Agg'})
    assert proc.returncode == 0, proc.stderr
    assert '(refined)' in proc.stdout and 'MISMATCH' not in proc.stdout
    pngs = sorted(p.name for p in out.glob('*.png'))
    assert pngs == sorted(['figure2_estimates.png', 'figure3_maps.png',
                           'figure4_feasible_region.png',
                           'figure5_errors.png', 'tradeoff.png',
                           'gi_disturbance.png', 'poles_region.png'])
    assert all((out / p).stat().st_size > 10_000 for p in pngs)
    assert proc.stderr == ''          # no progress output off a terminal


def test_workers_must_be_positive(capsys):
    with pytest.raises(SystemExit):
        main(['--no-figures', '--workers', '0'])
    assert 'at least 1; found 0' in capsys.readouterr().err


@pytest.mark.slow
def test_designs_on_workers_are_the_serial_ones():
    """The reproduction runs its designs on a process pool by default;
    they are those of the serial run, digit for digit.  Three of its
    designs with pole clusters, the kind most sensitive to rounding:
    nominal three copies of the scalar plant, the second-order pair
    nominal and robust (the entry-point test runs them all on a pool)."""
    import concurrent.futures
    import multiprocessing
    from controlext.paper.designs import run_designs
    keys = [('scalar', 3, 2.5), ('second', 2, 1.0),
            ('second', 2, 1.0, 'robust')]
    serial = run_designs(keys)
    # (forkserver: this process has threads by now; see test_coupled)
    with concurrent.futures.ProcessPoolExecutor(
            2, mp_context=multiprocessing.get_context('forkserver')) as pool:
        parallel = run_designs(keys, executor=pool)
    for key in keys:
        assert parallel[key].hinf == serial[key].hinf, key
        np.testing.assert_array_equal(parallel[key].G, serial[key].G)


def test_figures_take_the_designs_they_are_given():
    """The trade-off figure plots the γ of the designs passed to it and
    runs none of its own (the reproduction designs each one once)."""
    import types
    import matplotlib
    matplotlib.use('Agg')
    from controlext.paper.designs import TRADEOFF_DECAYS, tradeoff_keys
    from controlext.paper.figures import figure_tradeoff
    designs = {key: types.SimpleNamespace(hinf=10.0 ** -key[1] * key[2])
               for key in tradeoff_keys()}
    fig = figure_tradeoff(designs=designs)
    lines = fig.axes[0].get_lines()
    assert len(lines) == 3
    for N, line in zip((1, 2, 3), lines):
        assert list(line.get_xdata()) == list(TRADEOFF_DECAYS)
        assert list(line.get_ydata()) == \
            [10.0 ** -N * d for d in TRADEOFF_DECAYS]


def test_designs_run_once_per_key():
    from controlext.paper.designs import TABLE, run_designs, tradeoff_keys
    calls = []

    class Recorder:
        def map(self, fn, jobs):
            jobs = list(jobs)
            calls.extend(jobs)
            return [None] * len(jobs)

    keys = TABLE + tradeoff_keys()
    out = run_designs(keys, Recorder())
    assert set(out) == set(keys)
    assert len(calls) == len(set(keys)) == len(keys) - 3
    # the slowest (most copies) are handed out first
    copies = [design['copies'] for _, design in calls]
    assert copies == sorted(copies, reverse=True)
