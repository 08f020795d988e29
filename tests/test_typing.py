"""The public API is annotated and the type checker runs clean on it."""

import inspect
import pathlib
import subprocess
import sys

import pytest

import controlext as cx
import controlext.matlab as cxm

ROOT = pathlib.Path(__file__).parent.parent


def _public_callables():
    """Every public function, and every public method defined by a public
    class of ``controlext`` and ``controlext.matlab`` (not inherited from
    python-control)."""
    seen = []
    for module in (cx, cxm):
        for name in module.__all__:
            obj = getattr(module, name)
            if inspect.isfunction(obj):
                seen.append((name, obj))
            elif inspect.isclass(obj) and not issubclass(
                    obj, (Exception, Warning)):
                for attr, value in vars(obj).items():
                    if attr.startswith('_') and attr != '__init__':
                        continue
                    if isinstance(value, (classmethod, staticmethod)):
                        value = value.__func__
                    if isinstance(value, property):
                        value = value.fget
                    if inspect.isfunction(value) and \
                            value.__qualname__.startswith(obj.__name__):
                        seen.append((f'{name}.{attr}', value))
    return seen


def test_the_walk_finds_the_api():
    names = {name for name, _ in _public_callables()}
    assert {'hinf_observer', 'Observer.estimator', 'Observer.__init__',
            'hinfnorm', 'estim', 'Disk.__init__'} <= names


@pytest.mark.parametrize('name, func', _public_callables(),
                         ids=[n for n, _ in _public_callables()])
def test_public_signature_is_annotated(name, func):
    sig = inspect.signature(func)
    missing = [p.name for p in sig.parameters.values()
               if p.name not in ('self', 'cls') and
               p.annotation is inspect.Parameter.empty]
    assert not missing, f"{name}: parameters without a type: {missing}"
    assert sig.return_annotation is not inspect.Signature.empty or \
        name.endswith('.__init__'), f"{name}: no return type"


def test_mypy_is_clean():
    pytest.importorskip('mypy')
    proc = subprocess.run([sys.executable, '-m', 'mypy'], cwd=ROOT,
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stdout + proc.stderr
