"""python -m controlext: the reproduction table."""

import subprocess
import sys

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
def test_module_entry_point_with_synthesis():
    proc = subprocess.run([sys.executable, '-m', 'controlext'],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    assert '(refined)' in proc.stdout and 'MISMATCH' not in proc.stdout
