"""The package builds as a wheel that carries its license and metadata."""

import subprocess
import sys
import zipfile
import pathlib

import pytest

import controlext as cx

ROOT = pathlib.Path(__file__).parent.parent


@pytest.mark.slow
def test_wheel_builds_with_license_and_one_version(tmp_path):
    proc = subprocess.run([sys.executable, '-m', 'pip', 'wheel', str(ROOT),
                           '--no-deps', '-q', '-w', str(tmp_path)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    wheel, = tmp_path.glob('controlext-*.whl')
    with zipfile.ZipFile(wheel) as zf:
        names = zf.namelist()
        meta = zf.read(next(n for n in names if n.endswith('METADATA')))
    assert any(n.endswith('licenses/LICENSE') for n in names)
    assert any(n.startswith('controlext/synthesis/') for n in names)
    assert any(n.startswith('controlext/paper/') for n in names)
    assert 'controlext/py.typed' in names          # PEP 561: typed package
    text = meta.decode()
    assert 'License-Expression: BSD-3-Clause' in text
    assert f'Version: {cx.__version__}' in text        # the one source
    assert 'Classifier: Programming Language :: Python :: 3.13' in text
