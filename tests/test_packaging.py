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
    assert 'Classifier: Typing :: Typed' in text


def _declared_bounds():
    """``{name: lower bound}`` of pyproject.toml's dependencies."""
    import re
    import tomllib
    with open(ROOT / 'pyproject.toml', 'rb') as fh:
        deps = tomllib.load(fh)['project']['dependencies']
    bounds = {}
    for dep in deps:
        name, = re.findall(r'^[A-Za-z0-9_.-]+', dep)
        low = re.findall(r'>=\s*([0-9][0-9.]*)', dep)
        assert low, f"{dep}: every dependency declares its lower bound"
        bounds[name.lower()] = low[0]
    return bounds


def test_lower_bounds_file_pins_the_declared_bounds():
    """CI installs .ci/lower-bounds.txt exactly and runs the suite on it:
    the file must pin every dependency at its declared lower bound."""
    pins = {}
    for line in (ROOT / '.ci' / 'lower-bounds.txt').read_text().splitlines():
        line = line.split('#')[0].strip()
        if line:
            name, version = line.split('==')
            pins[name.strip().lower()] = version.strip()
    declared = _declared_bounds()
    assert set(pins) == set(declared)
    for name, low in declared.items():
        # 0.9 and 0.9.0 name the same release
        norm = lambda v: tuple(int(x) for x in v.split('.')) + (0,) * (
            3 - len(v.split('.')))
        assert norm(pins[name]) == norm(low), (name, pins[name], low)


def test_python_control_is_bounded_above():
    """Observer subclasses control.StateSpace and rebuilds its private
    update/output functions when unpickled: a release of python-control
    that changes them must be tested before users get it."""
    import tomllib
    with open(ROOT / 'pyproject.toml', 'rb') as fh:
        deps = tomllib.load(fh)['project']['dependencies']
    control, = [d for d in deps if d.startswith('control')]
    assert '<' in control


@pytest.mark.slow
def test_sdist_carries_what_the_tests_read(tmp_path):
    """The tests read docs/, examples/ and benchmarks/: an sdist without
    them cannot run its own tests."""
    import tarfile
    proc = subprocess.run([sys.executable, '-m', 'build', '--sdist',
                           '-o', str(tmp_path), str(ROOT)],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr
    sdist, = tmp_path.glob('controlext-*.tar.gz')
    with tarfile.open(sdist) as tf:
        names = {n.split('/', 1)[1] for n in tf.getnames() if '/' in n}
    for path in ('tests/conftest.py', 'docs/conf.py', 'examples',
                 'benchmarks/plants.py', '.ci/lower-bounds.txt'):
        assert any(n == path or n.startswith(path + '/') for n in names), \
            path
