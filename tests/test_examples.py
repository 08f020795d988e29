"""Every script in examples/ runs headless and writes its figure."""

import os
import pathlib
import subprocess
import sys

import pytest

EXAMPLES = sorted((pathlib.Path(__file__).parent.parent / 'examples')
                  .glob('*.py'))


def test_there_are_examples():
    assert len(EXAMPLES) >= 4


#: run by the documentation build for the gallery (tests/test_docs.py
#: fails if one of them fails, prints nothing or writes no figure)
HEAVY = {'second_order_tradeoff', 'boeing747_lateral', 'flexible_beam'}
LIGHT = [p for p in EXAMPLES if p.stem not in HEAVY]


@pytest.mark.parametrize('script', LIGHT, ids=[p.stem for p in LIGHT])
def test_example_runs(script, tmp_path):
    root = str(pathlib.Path(__file__).parent.parent)
    env = {**os.environ, 'MPLBACKEND': 'Agg',
           'PYTHONPATH': root + os.pathsep + os.environ.get('PYTHONPATH',
                                                            '')}
    proc = subprocess.run([sys.executable, str(script)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=600,
                          env=env)
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.strip()
    assert (tmp_path / f'{script.stem}.png').stat().st_size > 5000
