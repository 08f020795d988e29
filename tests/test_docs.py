"""The documentation builds with warnings as errors, and every public
function documents itself with a doctested example."""

import inspect
import pathlib
import subprocess
import sys

import pytest

import controlext as cx

DOCS = pathlib.Path(__file__).parent.parent / 'docs'


def test_every_public_function_has_examples():
    missing = [name for name in cx.__all__
               if inspect.isfunction(getattr(cx, name)) and '>>>' not in
               (inspect.getdoc(getattr(cx, name)) or '')]
    assert not missing, missing


def test_every_public_name_is_in_the_api_reference():
    api = (DOCS / 'api.rst').read_text()
    missing = [name for name in cx.__all__ if f'   {name}\n' not in api]
    assert not missing, missing


def test_sphinx_build_without_warnings(tmp_path):
    pytest.importorskip('sphinx')
    pytest.importorskip('numpydoc')
    proc = subprocess.run(
        [sys.executable, '-m', 'sphinx', '-W', '--keep-going', '-b', 'html',
         '-q', '-d', str(tmp_path / 'doctrees'), str(DOCS),
         str(tmp_path / 'html')], capture_output=True, text=True,
        timeout=600)
    assert proc.returncode == 0, proc.stderr
    html = (tmp_path / 'html' / 'generated' /
            'controlext.coupled_observer.html').read_text()
    assert 'Examples' in html and 'Theorem 3.10' in html
